#include "comm/can_paper000.h"

void can_paper000_telemetry(const drive_t *d, mc_t v_bus_V, mc_t step_time_us, can_telemetry_t *t)
{
    drive_telemetry_t x;
    drive_get_telemetry(d, &x);
    t->drive_kind = (uint8_t)CAN_DRIVE_KIND_POSITION_P000;
    t->mode = (uint8_t)x.mode;
    t->state = (uint8_t)x.state;
    t->enabled = !d->disabled && x.state != SUP_STATE_FAULT;
    t->fault_code = (uint8_t)x.fault;
    t->fault_events = (uint8_t)(x.fault_events & 0xFFu);
    t->relocks = (uint8_t)((uint32_t)x.relocks & 0xFFu);
    t->first_fault = (uint8_t)drive_flight_recorder(d)->fault;
    t->overruns = (uint16_t)(x.overruns & 0xFFFFu);
    t->saturated = x.v_saturated;
    t->theta_ref_rad = x.theta_ref_rad;
    t->theta_est_rad = x.theta_est_rad;
    t->omega_ref_rad_s = x.omega_ref_rad_s;
    t->omega_est_rad_s = x.omega_est_rad_s;
    t->accel_est_rad_s2 = x.accel_est_rad_s2;
    t->load_est_Nm = x.load_est_Nm;
    t->i1_A = x.i_f_A;
    t->i2_A = x.i_g_A;
    t->i1_ref_A = x.i_f_ref_A;
    t->i2_ref_A = x.i_g_ref_A;
    t->i1_est_A = x.i_f_hat_A;
    t->i2_est_A = x.i_g_hat_A;
    t->emf1_V = x.e_f_hat_V;
    t->emf2_V = x.e_g_hat_V;
    t->v1_V = x.v_f_V;
    t->v2_V = x.v_g_V;
    t->v_bus_V = v_bus_V;
    t->step_time_us = step_time_us;
}

can_reject_t can_paper000_apply(void *drive, const can_cmd_t *cmd)
{
    drive_t *d = (drive_t *)drive;
    bool ok = false;
    switch (cmd->kind) {
    case CAN_CMD_ENABLE: ok = drive_set_enabled(d, cmd->enable); break;
    case CAN_CMD_MOVE: ok = drive_move(d, cmd->theta_to_rad, cmd->duration_s); break;
    case CAN_CMD_STOP: ok = drive_stop(d); break;
    case CAN_CMD_SET_OMEGA_LIM: ok = drive_set_omega_lim(d, cmd->omega_lim_rad_s); break;
    case CAN_CMD_CLEAR_FAULTS:
        /* only a latched fault is cleared: re-initialising a running drive
         * would restart it under the rotor */
        ok = d->sup.state == SUP_STATE_FAULT && drive_clear_fault(d);
        break;
    default: ok = false; break; /* CmdSpeed: the speed drive's */
    }
    return ok ? CAN_REJECT_NONE : CAN_REJECT_MODE;
}

void can_paper000_step(can_node_t *n, const drive_t *d, uint32_t tick, mc_t v_bus_V, mc_t step_time_us)
{
    if (!can_node_due(n, tick)) {
        return;
    }
    can_telemetry_t t;
    can_paper000_telemetry(d, v_bus_V, step_time_us, &t);
    can_node_transmit(n, tick, &t);
}
