/*
 * can_paper000.h - the paper-000 position drive on CAN (tools/can/drive.dbc,
 * docs/can.md): its telemetry in the message set's terms and the commands
 * it obeys. The control frame of Currents, Observer and Voltages is the
 * (f-g) frame of eq. (6): I1 = i_f, I2 = i_g; Emf1, Emf2 are the back-EMF
 * estimates L d_hat of eq. (28). Commands map onto drive_set_enabled,
 * drive_move, drive_stop, drive_set_omega_lim and drive_clear_fault
 * (drives/paper000_drive.h says when each is refused); CmdSpeed is the
 * speed drive's and always refused here. Nothing allocates.
 */
#ifndef COMM_CAN_PAPER000_H
#define COMM_CAN_PAPER000_H

#include "comm/can_node.h"
#include "drives/paper000_drive.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Fills *t from the drive's last step; v_bus_V and step_time_us are the
 * backend's (the drive neither measures its own time nor needs the bus). */
void can_paper000_telemetry(const drive_t *d, mc_t v_bus_V, mc_t step_time_us, can_telemetry_t *t);

/* can_apply_fn for a drive_t. */
can_reject_t can_paper000_apply(void *drive, const can_cmd_t *cmd);

/* Once per control sample after drive_step: queues the telemetry due at
 * tick (filled only when one is due). */
void can_paper000_step(can_node_t *n, const drive_t *d, uint32_t tick, mc_t v_bus_V, mc_t step_time_us);

#ifdef __cplusplus
}
#endif

#endif /* COMM_CAN_PAPER000_H */
