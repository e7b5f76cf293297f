/*
 * can_paper002.h - paper 002's speed drive on CAN (tools/can/drive.dbc,
 * docs/can.md): its telemetry in the message set's terms and the commands
 * it obeys. The control frame of Currents, Observer and Voltages is the
 * d-q frame of the angle the drive runs on (the encoder's, or the flux
 * observer's): I1 = i_d, I2 = i_q measured, I1Ref, I2Ref the MTPA
 * references, I1Est, I2Est the EKF's currents; Emf1 = 0 and Emf2 = p psi
 * w_hat the back-EMF along q; V1 = u_d, V2 = u_q. ThetaRef is the integral
 * of w_d and ThetaEst the EKF's mechanical angle, both wrapped into
 * [-pi, pi); LoadEst is the EKF's lumped disturbance M_0. Mode is
 * closed loop from the first sample (the angle is measured), fault after
 * one. Commands map onto paper002_drive_set_enabled, _set_speed, _stop and
 * _clear_fault (drives/paper002_drive.h says when each is refused);
 * CmdMove and CmdSetOmegaLim are the other drives' and always refused
 * here. Nothing allocates.
 */
#ifndef COMM_CAN_PAPER002_H
#define COMM_CAN_PAPER002_H

#include "comm/can_node.h"
#include "drives/paper002_drive.h"

#ifdef __cplusplus
extern "C" {
#endif

void can_paper002_telemetry(const paper002_drive_t *d, mc_t v_bus_V, mc_t step_time_us, can_telemetry_t *t);

/* can_apply_fn for a paper002_drive_t. */
can_reject_t can_paper002_apply(void *drive, const can_cmd_t *cmd);

/* Once per control sample after paper002_drive_step. */
void can_paper002_step(can_node_t *n, const paper002_drive_t *d, uint32_t tick, mc_t v_bus_V, mc_t step_time_us);

#ifdef __cplusplus
}
#endif

#endif /* COMM_CAN_PAPER002_H */
