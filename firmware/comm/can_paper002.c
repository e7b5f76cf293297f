#include "comm/can_paper002.h"

void can_paper002_telemetry(const paper002_drive_t *d, mc_t v_bus_V, mc_t step_time_us, can_telemetry_t *t)
{
    const bool faulted = d->fault != DRIVE_FAULT_NONE;
    t->drive_kind = (uint8_t)CAN_DRIVE_KIND_SPEED_P002;
    t->mode = faulted ? 2u : 1u; /* the DBC's Mode: closed loop, or fault */
    t->state = (uint8_t)(faulted ? SUP_STATE_FAULT : SUP_STATE_CLOSED_LOOP);
    t->enabled = !d->disabled && !faulted;
    t->fault_code = (uint8_t)d->fault;
    t->fault_events = faulted ? 1u : 0u; /* latched: one until cleared */
    t->relocks = 0u;                     /* no re-lock */
    t->first_fault = (uint8_t)d->fault;
    t->overruns = (uint16_t)(d->mon.overruns & 0xFFFFu);
    t->saturated = d->last.saturated;
    t->theta_ref_rad = d->theta_ref_rad;
    t->theta_est_rad = d->last.theta_hat_rad;
    t->omega_ref_rad_s = d->last.w_d_rad_s;
    t->omega_est_rad_s = d->last.w_hat_rad_s;
    t->accel_est_rad_s2 = ekf_ipmsm_accel(&d->ekf);
    t->load_est_Nm = d->last.M0_hat_Nm;
    t->i1_A = d->last.i_d_A;
    t->i2_A = d->last.i_q_A;
    t->i1_ref_A = d->last.i_dd_A;
    t->i2_ref_A = d->last.i_qd_A;
    t->i1_est_A = d->last.i_d_hat_A;
    t->i2_est_A = d->last.i_q_hat_A;
    t->emf1_V = MC_ZERO;
    t->emf2_V = mc_mul(mc_mul_i(d->cfg.ekf.psi_Wb, d->cfg.ekf.p), d->last.w_hat_rad_s);
    t->v1_V = d->last.u_d_V;
    t->v2_V = d->last.u_q_V;
    t->v_bus_V = v_bus_V;
    t->step_time_us = step_time_us;
}

can_reject_t can_paper002_apply(void *drive, const can_cmd_t *cmd)
{
    paper002_drive_t *d = (paper002_drive_t *)drive;
    bool ok = false;
    switch (cmd->kind) {
    case CAN_CMD_ENABLE: ok = paper002_drive_set_enabled(d, cmd->enable); break;
    case CAN_CMD_SPEED: ok = paper002_drive_set_speed(d, cmd->omega_ref_rad_s, cmd->ramp_rad_s2); break;
    case CAN_CMD_STOP: ok = paper002_drive_stop(d); break;
    case CAN_CMD_CLEAR_FAULTS: ok = paper002_drive_clear_fault(d); break;
    default: ok = false; break; /* CmdMove, CmdSetOmegaLim: the other drives' */
    }
    return ok ? CAN_REJECT_NONE : CAN_REJECT_MODE;
}

void can_paper002_step(can_node_t *n, const paper002_drive_t *d, uint32_t tick, mc_t v_bus_V, mc_t step_time_us)
{
    if (!can_node_due(n, tick)) {
        return;
    }
    can_telemetry_t t;
    can_paper002_telemetry(d, v_bus_V, step_time_us, &t);
    can_node_transmit(n, tick, &t);
}
