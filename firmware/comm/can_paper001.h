/*
 * can_paper001.h - the paper-001 speed drive on CAN (tools/can/drive.dbc,
 * docs/can.md): its telemetry in the message set's terms and the commands
 * it obeys. The control frame of Currents and Voltages is the estimated
 * d-q frame: I1 = i_d, I2 = i_q, V1 = v_d, V2 = v_q. The flux observer
 * estimates no current: I1Est = I2Est = 0; Emf1 = 0 and Emf2 = K_e w_hat
 * |rho_hat| are its back-EMF in that frame (rho_hat of eqs. (12)-(14), 1
 * when it agrees with Phi). ThetaRef is the integral of w*, ThetaEst the
 * estimated mechanical angle. Commands map onto paper001_drive_set_enabled,
 * _set_speed, _stop, _set_omega_lim and _clear_fault (drives/
 * paper001_drive.h says when each is refused); CmdMove is the position
 * drive's and always refused here. Nothing allocates.
 */
#ifndef COMM_CAN_PAPER001_H
#define COMM_CAN_PAPER001_H

#include "comm/can_node.h"
#include "drives/paper001_drive.h"

#ifdef __cplusplus
extern "C" {
#endif

void can_paper001_telemetry(const paper001_drive_t *d, mc_t v_bus_V, mc_t step_time_us, can_telemetry_t *t);

/* can_apply_fn for a paper001_drive_t. */
can_reject_t can_paper001_apply(void *drive, const can_cmd_t *cmd);

/* Once per control sample after paper001_drive_step. */
void can_paper001_step(can_node_t *n, const paper001_drive_t *d, uint32_t tick, mc_t v_bus_V, mc_t step_time_us);

#ifdef __cplusplus
}
#endif

#endif /* COMM_CAN_PAPER001_H */
