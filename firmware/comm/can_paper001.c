#include "comm/can_paper001.h"

void can_paper001_telemetry(const paper001_drive_t *d, mc_t v_bus_V, mc_t step_time_us, can_telemetry_t *t)
{
    paper001_telemetry_t x;
    paper001_drive_get_telemetry(d, &x);
    mc_estimate_t e;
    paper001_drive_estimate(d, &e);
    t->drive_kind = (uint8_t)CAN_DRIVE_KIND_SPEED_P001;
    t->mode = (uint8_t)x.mode;
    t->state = (uint8_t)x.state;
    t->enabled = !d->disabled && x.state != SUP_STATE_FAULT;
    t->fault_code = (uint8_t)x.fault;
    t->fault_events = (uint8_t)(x.fault_events & 0xFFu);
    t->relocks = 0u; /* the speed drive has no re-lock */
    t->first_fault = (uint8_t)paper001_flight_recorder(d)->fault;
    t->overruns = (uint16_t)(x.overruns & 0xFFFFu);
    t->saturated = x.v_saturated;
    t->theta_ref_rad = x.theta_ref_rad;
    t->theta_est_rad = e.theta_rad;
    t->omega_ref_rad_s = x.omega_ref_rad_s;
    t->omega_est_rad_s = x.omega_est_rad_s;
    t->accel_est_rad_s2 = e.accel_rad_s2;
    t->load_est_Nm = x.load_est_Nm;
    t->i1_A = x.i_d_A;
    t->i2_A = x.i_q_A;
    t->i1_ref_A = MC_ZERO; /* i_d* = 0 (non-salient) */
    t->i2_ref_A = x.i_q_ref_A;
    t->i1_est_A = MC_ZERO;
    t->i2_est_A = MC_ZERO;
    t->emf1_V = MC_ZERO;
    t->emf2_V = mc_mul(mc_mul(d->cfg.model.K_V_s, x.omega_est_rad_s), mc_sqrt(x.rho2));
    t->v1_V = x.v_d_V;
    t->v2_V = x.v_q_V;
    t->v_bus_V = v_bus_V;
    t->step_time_us = step_time_us;
}

can_reject_t can_paper001_apply(void *drive, const can_cmd_t *cmd)
{
    paper001_drive_t *d = (paper001_drive_t *)drive;
    bool ok = false;
    switch (cmd->kind) {
    case CAN_CMD_ENABLE: ok = paper001_drive_set_enabled(d, cmd->enable); break;
    case CAN_CMD_SPEED: ok = paper001_drive_set_speed(d, cmd->omega_ref_rad_s, cmd->ramp_rad_s2); break;
    case CAN_CMD_STOP: ok = paper001_drive_stop(d); break;
    case CAN_CMD_SET_OMEGA_LIM: ok = paper001_drive_set_omega_lim(d, cmd->omega_lim_rad_s); break;
    case CAN_CMD_CLEAR_FAULTS: ok = d->sup.state == SUP_STATE_FAULT && paper001_drive_clear_fault(d); break;
    default: ok = false; break; /* CmdMove: the position drive's */
    }
    return ok ? CAN_REJECT_NONE : CAN_REJECT_MODE;
}

void can_paper001_step(can_node_t *n, const paper001_drive_t *d, uint32_t tick, mc_t v_bus_V, mc_t step_time_us)
{
    if (!can_node_due(n, tick)) {
        return;
    }
    can_telemetry_t t;
    can_paper001_telemetry(d, v_bus_V, step_time_us, &t);
    can_node_transmit(n, tick, &t);
}
