// socketcan.h - a Linux SocketCAN raw socket on a named interface (can0,
// vcan0), non-blocking, as the simulator's CAN bus (hal_sw_plant_set_can).
// Receives only the command identifiers of one node (a kernel filter), so
// the bus's telemetry and other nodes' traffic never reach the drive's
// queue; does not receive its own frames. Opening names what is wrong (no
// such interface, not a CAN interface, no CAN support in the kernel).
#ifndef MCSIM_CAN_SOCKETCAN_H
#define MCSIM_CAN_SOCKETCAN_H

#include <cstdint>
#include <string>

#include "hal/hal_types.h"
#include "hal_sw_plant.h"

namespace mcsim {

class SocketCan {
public:
    // Opens and binds; throws std::invalid_argument for an interface that
    // does not exist or is not CAN, std::runtime_error for anything else.
    SocketCan(const std::string& iface, unsigned node);
    ~SocketCan();
    SocketCan(const SocketCan&) = delete;
    SocketCan& operator=(const SocketCan&) = delete;

    bool send(const hal_can_frame_t& f);  // false: the socket would block (frame not taken)
    bool receive(hal_can_frame_t* f);     // false: nothing pending

    // The backend's view (hal_sw_plant_set_can(&bus())).
    const hal_sw_plant_can_t* bus() const { return &bus_; }

    std::uint64_t sent() const { return sent_; }
    std::uint64_t send_failures() const { return send_failures_; }
    std::uint64_t received() const { return received_; }
    const std::string& iface() const { return iface_; }

private:
    int fd_ = -1;
    std::string iface_;
    hal_sw_plant_can_t bus_{};
    std::uint64_t sent_ = 0, send_failures_ = 0, received_ = 0;
};

}  // namespace mcsim

#endif  // MCSIM_CAN_SOCKETCAN_H
