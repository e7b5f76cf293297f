/*
 * paper000_ops.c - paper 000's position drive behind the drive interface
 * (drives/drive.h): its commands, its status in the message set's terms
 * and its estimate. The control frame of the status is the (f-g) frame of
 * the reference, eq. (6): I1 = i_f, I2 = i_g measured, the references of
 * (38)-(39), the observer's currents and back-EMF (28) as voltages.
 */
#include "drives/paper000/paper000_drive.h"
#include "comm/generated/drive_can.h"

static const char *p000_config_problem(const void *cfg)
{
    return paper000_config_problem((const paper000_config_t *)cfg);
}

static bool p000_init(void *self, const void *cfg)
{
    return paper000_drive_init((paper000_drive_t *)self, (const paper000_config_t *)cfg);
}

static bool p000_step(void *self, const hal_sample_t *in, hal_command_t *out)
{
    return paper000_drive_step((paper000_drive_t *)self, in, out);
}

static drive_refusal_t p000_command(void *self, const drive_cmd_t *cmd)
{
    paper000_drive_t *d = (paper000_drive_t *)self;
    bool ok = false;
    switch (cmd->kind) {
    case DRIVE_CMD_ENABLE: ok = paper000_drive_set_enabled(d, cmd->enable); break;
    case DRIVE_CMD_MOVE: ok = paper000_drive_move(d, cmd->theta_to_rad, cmd->duration_s); break;
    case DRIVE_CMD_STOP: ok = paper000_drive_stop(d); break;
    case DRIVE_CMD_SET_OMEGA_LIM: ok = paper000_drive_set_omega_lim(d, cmd->omega_lim_rad_s); break;
    case DRIVE_CMD_CLEAR_FAULTS:
        /* only a latched fault is cleared: re-initialising a running drive
         * would restart it under the rotor */
        if (d->sup.state != SUP_STATE_FAULT) {
            return DRIVE_REFUSE_NO_FAULT;
        }
        ok = paper000_drive_clear_fault(d);
        break;
    default: return DRIVE_REFUSE_UNSUPPORTED; /* CmdSpeed: the speed drives' */
    }
    return ok ? DRIVE_REFUSE_NONE : DRIVE_REFUSE_STATE;
}

static void p000_status(const void *self, drive_status_t *s)
{
    const paper000_drive_t *d = (const paper000_drive_t *)self;
    paper000_telemetry_t x;
    paper000_drive_get_telemetry(d, &x);
    s->mode = (uint8_t)x.mode;
    s->state = (uint8_t)x.state;
    s->enabled = !d->disabled && x.state != SUP_STATE_FAULT;
    s->fault_code = (uint8_t)x.fault;
    s->fault_events = (uint8_t)(x.fault_events & 0xFFu);
    s->relocks = (uint8_t)((uint32_t)x.relocks & 0xFFu);
    s->first_fault = (uint8_t)paper000_drive_flight_recorder(d)->fault;
    s->overruns = (uint16_t)(x.overruns & 0xFFFFu);
    s->saturated = x.v_saturated;
    s->theta_ref_rad = x.theta_ref_rad;
    s->theta_est_rad = x.theta_est_rad;
    s->omega_ref_rad_s = x.omega_ref_rad_s;
    s->accel_ref_rad_s2 = x.accel_ref_rad_s2;
    s->omega_est_rad_s = x.omega_est_rad_s;
    s->estimate_valid = x.state == SUP_STATE_CLOSED_LOOP;
    s->theta_e_est_rad = mc_elec_angle(x.theta_est_rad, d->cfg.model.n_p);
    s->v_alpha_V = x.v_a_V;
    s->v_beta_V = x.v_b_V;
    s->estimate_quality = MC_ONE;
    s->accel_est_rad_s2 = x.accel_est_rad_s2;
    s->load_est_Nm = x.load_est_Nm;
    s->i1_A = x.i_f_A;
    s->i2_A = x.i_g_A;
    s->i1_ref_A = x.i_f_ref_A;
    s->i2_ref_A = x.i_g_ref_A;
    s->i1_est_A = x.i_f_hat_A;
    s->i2_est_A = x.i_g_hat_A;
    s->emf1_V = x.e_f_hat_V;
    s->emf2_V = x.e_g_hat_V;
    s->v1_V = x.v_f_V;
    s->v2_V = x.v_g_V;
}

/* The estimator's mechanical estimates; valid in closed loop only (in open
 * loop below omega_lim the back-EMF is unobservable, paper 000 sec. 4.2). */
static void p000_estimate(const void *self, mc_estimate_t *e)
{
    const paper000_drive_t *d = (const paper000_drive_t *)self;
    paper000_telemetry_t x;
    paper000_drive_get_telemetry(d, &x);
    e->theta_rad = x.theta_est_rad;
    e->omega_rad_s = x.omega_est_rad_s;
    e->accel_rad_s2 = x.accel_est_rad_s2;
    e->load_Nm = x.load_est_Nm;
    e->valid = x.state == SUP_STATE_CLOSED_LOOP;
}

static const flight_recorder_t *p000_recorder(const void *self)
{
    return paper000_drive_flight_recorder((const paper000_drive_t *)self);
}

/* What the drive shows beyond its status: the (f-g) frame at the
 * reference's electrical angle n_p theta_r (eq. (6)), its observers and the
 * model it runs on (paper000_telemetry_t). */
static const drive_signal_t p000_signal_list[] = {
    {"i_f_meas_A", "A", "measured current along f, (f-g) frame at n_p theta_r, eq. (6)", 0u},
    {"i_g_meas_A", "A", "measured current along g", 0u},
    {"i_f_ref_A", "A", "current reference along f, eqs. (38)-(39) (the open-loop start's i_max)", 0u},
    {"i_g_ref_A", "A", "current reference along g", 0u},
    {"i_f_est_A", "A", "the back-EMF observer's current along f, eq. (25)", 0u},
    {"i_g_est_A", "A", "the back-EMF observer's current along g", 0u},
    {"e_f_est_V", "V", "the observer's back-EMF along f, L d_f, eq. (28)", 0u},
    {"e_g_est_V", "V", "the observer's back-EMF along g, L d_g", 0u},
    {"v_f_V", "V", "voltage command along f after the limit (0 in FAULT)", 0u},
    {"v_g_V", "V", "voltage command along g after the limit", 0u},
    {"delta_theta_est_rad", "rad", "load angle estimate theta - theta_r, eq. (29), in (-pi/n_p, pi/n_p]", 0u},
    {"jump_count", "1", "the position estimator's branch k, eq. (71)", DRIVE_SIGNAL_INTEGER},
    {"model_R_ohm", "ohm", "resistance in use: the configured one or the standstill measurement", 0u},
    {"model_L_H", "H", "inductance in use", 0u},
    {"model_K_V_s", "V s", "back-EMF constant in use (configured or identified)", 0u},
    {"rl_id_state", "1", "R, L identification's state (rl_id_state_t)", DRIVE_SIGNAL_INTEGER},
    {"k_id_state", "1", "K identification's state (k_id_state_t)", DRIVE_SIGNAL_INTEGER},
    {"relocks", "1", "RELOCK reactions taken since init", DRIVE_SIGNAL_INTEGER},
};
#define P000_N_SIGNALS ((uint32_t)(sizeof p000_signal_list / sizeof p000_signal_list[0]))
_Static_assert(P000_N_SIGNALS <= DRIVE_SIGNALS_MAX, "more signals than DRIVE_SIGNALS_MAX");

static const drive_signal_t *p000_signals(const void *self, uint32_t *count)
{
    (void)self;
    *count = P000_N_SIGNALS;
    return p000_signal_list;
}

static void p000_read_signals(const void *self, mc_t *v)
{
    paper000_telemetry_t x;
    paper000_drive_get_telemetry((const paper000_drive_t *)self, &x);
    const mc_t list[] = {x.i_f_A,
                         x.i_g_A,
                         x.i_f_ref_A,
                         x.i_g_ref_A,
                         x.i_f_hat_A,
                         x.i_g_hat_A,
                         x.e_f_hat_V,
                         x.e_g_hat_V,
                         x.v_f_V,
                         x.v_g_V,
                         x.delta_theta_est_rad,
                         mc_from_i(x.jump_count),
                         x.R_model_ohm,
                         x.L_model_H,
                         x.K_model_V_s,
                         mc_from_i((int32_t)x.rl_id_state),
                         mc_from_i((int32_t)x.k_id_state),
                         mc_from_i(x.relocks)};
    _Static_assert(sizeof list / sizeof list[0] == P000_N_SIGNALS, "one value per signal");
    for (uint32_t k = 0; k < P000_N_SIGNALS; ++k) {
        v[k] = list[k];
    }
}

const drive_ops_t paper000_drive_ops = {
    .name = "paper000",
    .title = "paper 000: sensorless position drive of a two-phase stepper (super-twisting observer, twisting control)",
    .kind = DRIVE_KIND_POSITION,
    .can_kind = (uint8_t)DRIVE_CAN_HEARTBEAT_DRIVE_KIND_PAPER000_POSITION_CHOICE, /* the DBC's DriveKind */
    .state_bytes = (uint32_t)sizeof(paper000_drive_t),
    .config_bytes = (uint32_t)sizeof(paper000_config_t),
    .config_problem = p000_config_problem,
    .init = p000_init,
    .step = p000_step,
    .command = p000_command,
    .status = p000_status,
    .estimate = p000_estimate,
    .recorder = p000_recorder,
    .signals = p000_signals,
    .read_signals = p000_read_signals,
};
