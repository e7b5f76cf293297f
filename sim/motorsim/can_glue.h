// can_glue.h - the HAL control callback of a drive on CAN: each period the
// drive's step, then up to CAN_NODE_RX_PER_STEP received frames through
// the drive's node (comm/can_node.h: validated, then carried out or
// refused), the telemetry due, and the queued frames out while the bus
// takes them. This is what an MCU's control interrupt does too; here the
// bus is hal_sw_plant's (a SocketCAN interface, sim/can/socketcan.h).
//
// With a bus the callback keeps running after a drive fault (the drive
// holds 0 V itself in FAULT), so that the heartbeat reports the fault and
// CmdClearFaults can clear it; without one a fault ends the callbacks
// (hal_safe_state), as before.
#ifndef MCSIM_MOTORSIM_CAN_GLUE_H
#define MCSIM_MOTORSIM_CAN_GLUE_H

#include <cstdint>
#include <cstdio>

#include "comm/can_node.h"
#include "drives/drive.h"
#include "hal/hal.h"
#include "motorsim/param_glue.h"

namespace mcsim {

struct CanDriveContext {
    drive_t drive{};                    // any registered drive (drives/registry.h)
    can_node_t node{};
    double ts_s = 1e-4;
    double t_start_s = 0.0;             // plant time of HAL tick 0 (for the log lines)
    std::FILE* log = nullptr;           // one line per command received, or nullptr
    std::uint32_t commands = 0;         // frames for our node received
    std::uint32_t tx_waits = 0;         // samples the bus did not take a frame
    // the drive's parameters (ParamRequest; nullptr: none): while they do
    // not design, CmdEnable is refused
    const ParamGlue* params = nullptr;
};

// Initialises ctx->node (node id, default rates) for the drive set in ctx.
// Throws std::invalid_argument naming the node id the firmware refuses.
void can_glue_init(CanDriveContext* ctx, unsigned node, std::uint32_t fs_hz);

// The control callback; ctx is a CanDriveContext.
void can_drive_control_callback(void* ctx, const hal_sample_t* in, hal_command_t* out);

}  // namespace mcsim

#endif  // MCSIM_MOTORSIM_CAN_GLUE_H
