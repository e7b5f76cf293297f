/*
 * paper001_ops.c - paper 001's speed drive behind the drive interface
 * (drives/drive.h). The control frame of the status is the estimated d-q
 * frame: I1 = i_d, I2 = i_q measured, I2Ref the speed law's i_q* (i_d* = 0,
 * non-salient), Emf2 = K w_hat |rho_hat| the back-EMF along q of the flux
 * observer (paper 001 eq. (12)), V1, V2 = v_d, v_q of (11).
 */
#include "drives/paper001/paper001_drive.h"
#include "comm/generated/drive_can.h"

static const char *p001_config_problem(const void *cfg)
{
    return paper001_config_problem((const paper001_config_t *)cfg);
}

static bool p001_init(void *self, const void *cfg)
{
    return paper001_drive_init((paper001_drive_t *)self, (const paper001_config_t *)cfg);
}

static bool p001_step(void *self, const hal_sample_t *in, hal_command_t *out)
{
    return paper001_drive_step((paper001_drive_t *)self, in, out);
}

static drive_refusal_t p001_command(void *self, const drive_cmd_t *cmd)
{
    paper001_drive_t *d = (paper001_drive_t *)self;
    bool ok = false;
    switch (cmd->kind) {
    case DRIVE_CMD_ENABLE: ok = paper001_drive_set_enabled(d, cmd->enable); break;
    case DRIVE_CMD_SPEED: ok = paper001_drive_set_speed(d, cmd->omega_ref_rad_s, cmd->ramp_rad_s2); break;
    case DRIVE_CMD_STOP: ok = paper001_drive_stop(d); break;
    case DRIVE_CMD_SET_OMEGA_LIM: ok = paper001_drive_set_omega_lim(d, cmd->omega_lim_rad_s); break;
    case DRIVE_CMD_CLEAR_FAULTS:
        if (d->sup.state != SUP_STATE_FAULT) {
            return DRIVE_REFUSE_NO_FAULT;
        }
        ok = paper001_drive_clear_fault(d);
        break;
    default: return DRIVE_REFUSE_UNSUPPORTED; /* CmdMove: the position drive's */
    }
    return ok ? DRIVE_REFUSE_NONE : DRIVE_REFUSE_STATE;
}

static void p001_status(const void *self, drive_status_t *s)
{
    const paper001_drive_t *d = (const paper001_drive_t *)self;
    paper001_telemetry_t x;
    paper001_drive_get_telemetry(d, &x);
    mc_estimate_t e;
    paper001_drive_estimate(d, &e);
    s->mode = (uint8_t)x.mode;
    s->state = (uint8_t)x.state;
    s->enabled = !d->disabled && x.state != SUP_STATE_FAULT;
    s->fault_code = (uint8_t)x.fault;
    s->fault_events = (uint8_t)(x.fault_events & 0xFFu);
    s->relocks = 0u; /* the speed drive has no re-lock */
    s->first_fault = (uint8_t)paper001_flight_recorder(d)->fault;
    s->overruns = (uint16_t)(x.overruns & 0xFFFFu);
    s->saturated = x.v_saturated;
    s->theta_ref_rad = x.theta_ref_rad;
    s->theta_est_rad = e.theta_rad;
    s->omega_ref_rad_s = x.omega_ref_rad_s;
    s->accel_ref_rad_s2 = x.accel_ref_rad_s2;
    s->omega_est_rad_s = x.omega_est_rad_s;
    s->estimate_valid = x.estimate_valid;
    s->theta_e_est_rad = x.theta_e_rad;
    s->v_alpha_V = x.v_alpha_V;
    s->v_beta_V = x.v_beta_V;
    s->estimate_quality = x.rho2;
    s->accel_est_rad_s2 = e.accel_rad_s2;
    s->load_est_Nm = x.load_est_Nm;
    s->i1_A = x.i_d_A;
    s->i2_A = x.i_q_A;
    s->i1_ref_A = MC_ZERO; /* i_d* = 0 (non-salient) */
    s->i2_ref_A = x.i_q_ref_A;
    s->i1_est_A = MC_ZERO;
    s->i2_est_A = MC_ZERO;
    s->emf1_V = MC_ZERO;
    s->emf2_V = mc_mul(mc_mul(d->cfg.model.K_V_s, x.omega_est_rad_s), mc_sqrt(x.rho2));
    s->v1_V = x.v_d_V;
    s->v2_V = x.v_q_V;
}

static void p001_estimate(const void *self, mc_estimate_t *e)
{
    paper001_drive_estimate((const paper001_drive_t *)self, e);
}

static const flight_recorder_t *p001_recorder(const void *self)
{
    return paper001_flight_recorder((const paper001_drive_t *)self);
}

/* What the drive shows beyond its status: the estimated d-q frame's
 * currents and voltages (paper001_telemetry_t), the R its flux observer
 * subtracts. */
static const drive_signal_t p001_signal_list[] = {
    {"i_d_meas_A", "A", "measured current along d of the estimated angle", 0u},
    {"i_q_meas_A", "A", "measured current along q", 0u},
    {"i_q_ref_A", "A", "the speed law's i_q* (i_d* = 0, non-salient)", 0u},
    {"v_d_V", "V", "voltage command along d, eq. (11)", 0u},
    {"v_q_V", "V", "voltage command along q", 0u},
    {"R_obs_ohm", "ohm", "the resistance the flux observer subtracts: the model's, or tracked", 0u},
};
#define P001_N_SIGNALS ((uint32_t)(sizeof p001_signal_list / sizeof p001_signal_list[0]))
_Static_assert(P001_N_SIGNALS <= DRIVE_SIGNALS_MAX, "more signals than DRIVE_SIGNALS_MAX");

static const drive_signal_t *p001_signals(const void *self, uint32_t *count)
{
    (void)self;
    *count = P001_N_SIGNALS;
    return p001_signal_list;
}

static void p001_read_signals(const void *self, mc_t *v)
{
    paper001_telemetry_t x;
    paper001_drive_get_telemetry((const paper001_drive_t *)self, &x);
    v[0] = x.i_d_A;
    v[1] = x.i_q_A;
    v[2] = x.i_q_ref_A;
    v[3] = x.v_d_V;
    v[4] = x.v_q_V;
    v[5] = x.R_obs_ohm;
}

const drive_ops_t paper001_drive_ops = {
    .name = "paper001",
    .title = "paper 001: sensorless speed drive of a PMSM or a stepper (gradient flux and I&I observers, IDA-PBC)",
    .kind = DRIVE_KIND_SPEED,
    .can_kind = (uint8_t)DRIVE_CAN_HEARTBEAT_DRIVE_KIND_PAPER001_SPEED_CHOICE, /* the DBC's DriveKind */
    .state_bytes = (uint32_t)sizeof(paper001_drive_t),
    .config_bytes = (uint32_t)sizeof(paper001_config_t),
    .config_problem = p001_config_problem,
    .init = p001_init,
    .step = p001_step,
    .command = p001_command,
    .status = p001_status,
    .estimate = p001_estimate,
    .recorder = p001_recorder,
    .signals = p001_signals,
    .read_signals = p001_read_signals,
};
