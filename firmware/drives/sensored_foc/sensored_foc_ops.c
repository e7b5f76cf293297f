/*
 * sensored_foc_ops.c - the sensored FOC drive behind the drive interface
 * (drives/drive.h). The status's control frame is the encoder's d-q frame:
 * I1 = i_d, I2 = i_q measured, I1Ref/I2Ref the loops' references, Emf2 =
 * w_e psi the back-EMF along q; the estimates are the encoder observer's
 * (estimators/encoder_observer.h). Mode is closed loop from the first
 * sample (the angle is measured), the supervisor's FAULT after a fault
 * (supervisor/guard.h).
 */
#include "drives/sensored_foc/sensored_foc_drive.h"

#include "comm/generated/drive_can.h"

static const char *sfoc_op_config_problem(const void *cfg)
{
    return sensored_foc_config_problem((const sensored_foc_config_t *)cfg);
}

static bool sfoc_op_init(void *self, const void *cfg)
{
    return sensored_foc_drive_init((sensored_foc_drive_t *)self, (const sensored_foc_config_t *)cfg);
}

static bool sfoc_op_step(void *self, const hal_sample_t *in, hal_command_t *out)
{
    return sensored_foc_drive_step((sensored_foc_drive_t *)self, in, out);
}

static drive_refusal_t sfoc_op_command(void *self, const drive_cmd_t *cmd)
{
    sensored_foc_drive_t *d = (sensored_foc_drive_t *)self;
    bool ok = false;
    switch (cmd->kind) {
    case DRIVE_CMD_ENABLE: ok = sensored_foc_set_enabled(d, cmd->enable); break;
    case DRIVE_CMD_MOVE: ok = sensored_foc_move(d, cmd->theta_to_rad, cmd->duration_s); break;
    case DRIVE_CMD_SPEED: ok = sensored_foc_set_speed(d, cmd->omega_ref_rad_s, cmd->ramp_rad_s2); break;
    case DRIVE_CMD_STOP: ok = sensored_foc_stop(d); break;
    case DRIVE_CMD_CLEAR_FAULTS:
        if (d->sup.state != SUP_STATE_FAULT) {
            return DRIVE_REFUSE_NO_FAULT;
        }
        ok = sensored_foc_drive_init(d, &d->cfg);
        break;
    default: return DRIVE_REFUSE_UNSUPPORTED; /* CmdSetOmegaLim: a sensorless drive's */
    }
    return ok ? DRIVE_REFUSE_NONE : DRIVE_REFUSE_STATE;
}

static void sfoc_op_status(const void *self, drive_status_t *s)
{
    const sensored_foc_drive_t *d = (const sensored_foc_drive_t *)self;
    const bool faulted = d->sup.state == SUP_STATE_FAULT;
    s->mode = (uint8_t)supervisor_mode(&d->sup);
    s->state = (uint8_t)d->sup.state;
    s->fault_code = (uint8_t)d->sup.fault;
    s->first_fault = (uint8_t)d->rec.fault;
    s->fault_events = (uint8_t)(d->rec.events & 0xFFu);
    s->relocks = 0u;
    s->enabled = !d->disabled && !faulted;
    s->saturated = d->last.saturated;
    s->overruns = (uint16_t)(d->mon.overruns & 0xFFFFu);
    s->estimate_valid = !faulted && d->started;
    s->theta_ref_rad = d->last.theta_ref_rad;
    s->theta_est_rad = d->obs.theta_rad;
    s->omega_ref_rad_s = d->last.omega_ref_rad_s;
    s->accel_ref_rad_s2 = d->last.accel_ref_rad_s2;
    s->omega_est_rad_s = d->obs.omega_rad_s;
    s->accel_est_rad_s2 = d->obs.accel_rad_s2;
    s->load_est_Nm = d->obs.load_Nm;
    s->theta_e_est_rad = d->last.theta_e_rad;
    s->i1_A = d->last.i_d_A;
    s->i2_A = d->last.i_q_A;
    s->i1_ref_A = d->last.i_d_ref_A;
    s->i2_ref_A = d->last.i_q_ref_A;
    s->i1_est_A = MC_ZERO; /* no current observer */
    s->i2_est_A = MC_ZERO;
    s->emf1_V = MC_ZERO;
    s->emf2_V = mc_mul(mc_mul_i(d->obs.omega_rad_s, d->cfg.model.n_p), d->cfg.model.psi_Wb);
    s->v1_V = d->last.v_d_V;
    s->v2_V = d->last.v_q_V;
    s->v_alpha_V = d->last.v_ab_V.alpha;
    s->v_beta_V = d->last.v_ab_V.beta;
    s->estimate_quality = MC_ONE;
}

static void sfoc_op_estimate(const void *self, mc_estimate_t *e)
{
    const sensored_foc_drive_t *d = (const sensored_foc_drive_t *)self;
    encoder_observer_get(&d->obs, e);
    e->valid = d->sup.state != SUP_STATE_FAULT && d->started;
}

static const flight_recorder_t *sfoc_op_recorder(const void *self)
{
    return &((const sensored_foc_drive_t *)self)->rec;
}

/* What the drive shows beyond its status: the encoder's d-q frame's
 * currents, references and voltages. */
static const drive_signal_t sfoc_signal_list[] = {
    {"i_d_meas_A", "A", "measured current along d of the encoder's angle", 0u},
    {"i_q_meas_A", "A", "measured current along q", 0u},
    {"i_d_ref_A", "A", "the d loop's reference", 0u},
    {"i_q_ref_A", "A", "the q loop's reference (the speed loop's output)", 0u},
    {"v_d_V", "V", "voltage command along d (PI + decoupling)", 0u},
    {"v_q_V", "V", "voltage command along q", 0u},
};
#define SFOC_N_SIGNALS ((uint32_t)(sizeof sfoc_signal_list / sizeof sfoc_signal_list[0]))
_Static_assert(SFOC_N_SIGNALS <= DRIVE_SIGNALS_MAX, "more signals than DRIVE_SIGNALS_MAX");

static const drive_signal_t *sfoc_op_signals(const void *self, uint32_t *count)
{
    (void)self;
    *count = SFOC_N_SIGNALS;
    return sfoc_signal_list;
}

static void sfoc_op_read_signals(const void *self, mc_t *v)
{
    const sensored_foc_drive_t *d = (const sensored_foc_drive_t *)self;
    v[0] = d->last.i_d_A;
    v[1] = d->last.i_q_A;
    v[2] = d->last.i_d_ref_A;
    v[3] = d->last.i_q_ref_A;
    v[4] = d->last.v_d_V;
    v[5] = d->last.v_q_V;
}

const drive_ops_t sensored_foc_drive_ops = {
    .name = "sensored_foc",
    .title = "sensored FOC: encoder, PI current loops with decoupling, speed and position loops (the baseline)",
    .kind = DRIVE_KIND_SPEED,
    .can_kind = (uint8_t)DRIVE_CAN_HEARTBEAT_DRIVE_KIND_SENSORED_FOC_CHOICE, /* the DBC's DriveKind */
    .state_bytes = (uint32_t)sizeof(sensored_foc_drive_t),
    .config_bytes = (uint32_t)sizeof(sensored_foc_config_t),
    .config_problem = sfoc_op_config_problem,
    .init = sfoc_op_init,
    .step = sfoc_op_step,
    .command = sfoc_op_command,
    .status = sfoc_op_status,
    .estimate = sfoc_op_estimate,
    .recorder = sfoc_op_recorder,
    .signals = sfoc_op_signals,
    .read_signals = sfoc_op_read_signals,
};
