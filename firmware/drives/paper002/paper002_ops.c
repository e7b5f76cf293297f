/*
 * paper002_ops.c - paper 002's IPMSM speed drive behind the drive interface
 * (drives/drive.h). The control frame of the status is the d-q frame of
 * the angle the drive runs on (the encoder's or the flux observer's):
 * I1 = i_d, I2 = i_q measured, the MTPA references, the EKF's currents;
 * Emf2 = p psi w_hat the back-EMF along q; V1, V2 = u_d, u_q. ThetaRef is
 * the integral of w_d and ThetaEst the EKF's angle, both wrapped into
 * [-pi, pi); LoadEst is the EKF's lumped disturbance M_0. The state is the
 * supervisor's: closed loop from the first sample (the angle is measured
 * or observed), or FAULT; the fault counts and the first fault are the
 * flight recorder's (supervisor/guard.h).
 */
#include "drives/paper002/paper002_drive.h"
#include "comm/generated/drive_can.h"

static const char *p002_config_problem(const void *cfg)
{
    return paper002_config_problem((const paper002_config_t *)cfg);
}

static bool p002_init(void *self, const void *cfg)
{
    return paper002_drive_init((paper002_drive_t *)self, (const paper002_config_t *)cfg);
}

static bool p002_step(void *self, const hal_sample_t *in, hal_command_t *out)
{
    return paper002_drive_step((paper002_drive_t *)self, in, out);
}

static drive_refusal_t p002_command(void *self, const drive_cmd_t *cmd)
{
    paper002_drive_t *d = (paper002_drive_t *)self;
    bool ok = false;
    switch (cmd->kind) {
    case DRIVE_CMD_ENABLE: ok = paper002_drive_set_enabled(d, cmd->enable); break;
    case DRIVE_CMD_SPEED: ok = paper002_drive_set_speed(d, cmd->omega_ref_rad_s, cmd->ramp_rad_s2); break;
    case DRIVE_CMD_STOP: ok = paper002_drive_stop(d); break;
    case DRIVE_CMD_CLEAR_FAULTS:
        if (d->sup.state != SUP_STATE_FAULT) {
            return DRIVE_REFUSE_NO_FAULT;
        }
        ok = paper002_drive_clear_fault(d);
        break;
    default: return DRIVE_REFUSE_UNSUPPORTED; /* CmdMove, CmdSetOmegaLim: the other drives' */
    }
    return ok ? DRIVE_REFUSE_NONE : DRIVE_REFUSE_STATE;
}

static void p002_status(const void *self, drive_status_t *s)
{
    const paper002_drive_t *d = (const paper002_drive_t *)self;
    const bool faulted = d->sup.state == SUP_STATE_FAULT;
    s->mode = (uint8_t)supervisor_mode(&d->sup);
    s->state = (uint8_t)d->sup.state;
    s->enabled = !d->disabled && !faulted;
    s->fault_code = (uint8_t)d->sup.fault;
    s->fault_events = (uint8_t)(d->rec.events & 0xFFu);
    s->relocks = 0u; /* no re-lock */
    s->first_fault = (uint8_t)d->rec.fault;
    s->overruns = (uint16_t)(d->mon.overruns & 0xFFFFu);
    s->saturated = d->last.saturated;
    s->theta_ref_rad = d->theta_ref_rad;
    s->theta_est_rad = d->last.theta_hat_rad;
    s->omega_ref_rad_s = d->last.w_d_rad_s;
    mc_t w_d, dw_d; /* the reference of the last step (the step counts its tick after it) */
    speed_poly_eval(&d->reference, d->tick > 0u ? d->tick - 1u : 0u, &w_d, &dw_d);
    s->accel_ref_rad_s2 = dw_d;
    s->omega_est_rad_s = d->last.w_hat_rad_s;
    s->estimate_valid = !faulted;
    s->theta_e_est_rad = mc_elec_angle(d->last.theta_hat_rad, d->cfg.model.n_p);
    s->v_alpha_V = d->u_ab_prev_V.alpha;
    s->v_beta_V = d->u_ab_prev_V.beta;
    s->estimate_quality = MC_ONE;
    s->accel_est_rad_s2 = ekf_ipmsm_accel(&d->ekf, &d->cfg.model);
    s->load_est_Nm = d->last.M0_hat_Nm;
    s->i1_A = d->last.i_d_A;
    s->i2_A = d->last.i_q_A;
    s->i1_ref_A = d->last.i_dd_A;
    s->i2_ref_A = d->last.i_qd_A;
    s->i1_est_A = d->last.i_d_hat_A;
    s->i2_est_A = d->last.i_q_hat_A;
    s->emf1_V = MC_ZERO;
    s->emf2_V = mc_mul(mc_mul_i(d->cfg.model.psi_Wb, d->cfg.model.n_p), d->last.w_hat_rad_s);
    s->v1_V = d->last.u_d_V;
    s->v2_V = d->last.u_q_V;
}

/* The EKF's a posteriori estimate of the last step, its angle unwrapped
 * (estimators/estimate.h: mechanical, continuous over turns; from its
 * start angle before the first step, and again from the angle the
 * hfi_find_angle start found). */
static void p002_estimate(const void *self, mc_estimate_t *e)
{
    const paper002_drive_t *d = (const paper002_drive_t *)self;
    e->theta_rad = mc_add(d->theta_prev_rad, mc_mul_i(MC_TWO_PI, d->theta_turns));
    e->omega_rad_s = d->last.w_hat_rad_s;
    e->accel_rad_s2 = ekf_ipmsm_accel(&d->ekf, &d->cfg.model);
    e->load_Nm = d->last.M0_hat_Nm;
    e->valid = d->sup.state != SUP_STATE_FAULT;
}

static const flight_recorder_t *p002_recorder(const void *self)
{
    return &((const paper002_drive_t *)self)->rec;
}

/* What the drive shows beyond its status: the d-q frame of the angle it
 * runs on, the EKF's covariance (its lower triangle: P is symmetric by
 * construction, estimators/ekf_ipmsm.c) and its settings; with the HF
 * injection (estimators/hfi_angle.h) the injection's state, and with its
 * own start (hfi_find_angle) the start's figures. The list is that prefix
 * of p002_signal_list. */
#define P002_P(i, j, unit) \
    {"ekf_P_" #i #j, unit, "the EKF's covariance P(" #i ", " #j "); states 0 i_d, 1 i_q, 2 theta, 3 omega, 4 M0", 0u}
static const drive_signal_t p002_signal_list[] = {
    {"i_d_meas_A", "A", "measured current along d of the angle the drive runs on", 0u},
    {"i_q_meas_A", "A", "measured current along q", 0u},
    {"i_d_est_A", "A", "the EKF's current along d (a posteriori)", 0u},
    {"i_q_est_A", "A", "the EKF's current along q", 0u},
    {"i_d_ref_A", "A", "current reference along d (MTPA)", 0u},
    {"i_q_ref_A", "A", "current reference along q", 0u},
    {"u_d_V", "V", "voltage command along d (inversion-based current control)", 0u},
    {"u_q_V", "V", "voltage command along q", 0u},
    {"M_d_Nm", "N m", "torque demand of the speed law (SOSMC or HTSMC)", 0u},
    {"theta_meas_rad", "rad", "the angle the EKF was given (the encoder's or the estimator's), mechanical", 0u},
    P002_P(0, 0, "A^2"),
    P002_P(1, 0, "A^2"),
    P002_P(1, 1, "A^2"),
    P002_P(2, 0, "A rad"),
    P002_P(2, 1, "A rad"),
    P002_P(2, 2, "rad^2"),
    P002_P(3, 0, "A rad/s"),
    P002_P(3, 1, "A rad/s"),
    P002_P(3, 2, "rad^2/s"),
    P002_P(3, 3, "rad^2/s^2"),
    P002_P(4, 0, "A N m"),
    P002_P(4, 1, "A N m"),
    P002_P(4, 2, "rad N m"),
    P002_P(4, 3, "N m rad/s"),
    P002_P(4, 4, "N^2 m^2"),
    {"ekf_P_asym", "1", "the largest |P_ij - P_ji|, each in its entry's unit (0: P is symmetric)", 0u},
    {"ekf_spd_ok", "1", "1 while every correction found S positive definite (false stays false)", DRIVE_SIGNAL_INTEGER},
    {"angle_source", "1", "the angle's estimator (p002_angle_source_t: 0 encoder, 1 flux, 2 hfi)",
     DRIVE_SIGNAL_INTEGER | DRIVE_SIGNAL_SETTING},
    {"ekf_q_id", "A^2", "the EKF's Q_KF diagonal (39), per sample: i_d", DRIVE_SIGNAL_SETTING},
    {"ekf_q_iq", "A^2", "Q_KF: i_q", DRIVE_SIGNAL_SETTING},
    {"ekf_q_theta", "rad^2", "Q_KF: theta", DRIVE_SIGNAL_SETTING},
    {"ekf_q_omega", "rad^2/s^2", "Q_KF: omega", DRIVE_SIGNAL_SETTING},
    {"ekf_q_M0", "N^2 m^2", "Q_KF: M0", DRIVE_SIGNAL_SETTING},
    {"ekf_r_id", "A^2", "the EKF's R_KF diagonal (41): i_d", DRIVE_SIGNAL_SETTING},
    {"ekf_r_iq", "A^2", "R_KF: i_q", DRIVE_SIGNAL_SETTING},
    {"ekf_r_theta", "rad^2", "R_KF: theta", DRIVE_SIGNAL_SETTING},
    /* with the HF injection */
    {"hfi_on", "1", "the injection is on (injecting and demodulating)", DRIVE_SIGNAL_INTEGER},
    {"hfi_u_alpha_V", "V", "the injection's voltage for the coming sample, alpha", 0u},
    {"hfi_u_beta_V", "V", "the injection's voltage, beta", 0u},
    {"hfi_weight", "1", "the blend's weight of the flux observer, 0 injection .. 1 flux observer", 0u},
    /* with its own start (hfi_find_angle) */
    {"hfi_start_polarity", "1", "the start's polarity test: +1 kept, -1 flipped by pi, 0 undecided or not run",
     DRIVE_SIGNAL_INTEGER},
    {"hfi_start_polarity_diff_A", "A", "the polarity test's i_pos - i_neg (0 until it is done)", 0u},
    {"hfi_start_lock_amp", "1", "the lock's mean (H1) amplitude over its window (the running sum until the "
                                "lock ends): 1 on the d axis, L_d/L_q across it", 0u},
};
#undef P002_P
#define P002_N_BASE 36u /* up to ekf_r_theta */
#define P002_N_HFI 40u  /* up to hfi_weight */
#define P002_N_SIGNALS ((uint32_t)(sizeof p002_signal_list / sizeof p002_signal_list[0]))
_Static_assert(P002_N_SIGNALS <= DRIVE_SIGNALS_MAX, "more signals than DRIVE_SIGNALS_MAX");
_Static_assert(P002_N_SIGNALS == P002_N_HFI + 3u, "the prefixes: base, injection, its start");

static uint32_t p002_signal_count(const paper002_drive_t *d)
{
    if (d->est != &hfi_angle_ops) {
        return P002_N_BASE;
    }
    return d->cfg.hfi_find_angle ? P002_N_SIGNALS : P002_N_HFI;
}

static const drive_signal_t *p002_signals(const void *self, uint32_t *count)
{
    *count = p002_signal_count((const paper002_drive_t *)self);
    return p002_signal_list;
}

static void p002_read_signals(const void *self, mc_t *v)
{
    const paper002_drive_t *d = (const paper002_drive_t *)self;
    uint32_t k = 0u;
    v[k++] = d->last.i_d_A;
    v[k++] = d->last.i_q_A;
    v[k++] = d->last.i_d_hat_A;
    v[k++] = d->last.i_q_hat_A;
    v[k++] = d->last.i_dd_A;
    v[k++] = d->last.i_qd_A;
    v[k++] = d->last.u_d_V;
    v[k++] = d->last.u_q_V;
    v[k++] = d->last.M_d_Nm;
    v[k++] = d->last.theta_meas_rad;
    mc_t asym = MC_ZERO;
    for (int i = 0; i < EKF_N; ++i) {
        for (int j = 0; j <= i; ++j) {
            v[k++] = d->ekf.P[i][j];
            asym = mc_max(asym, mc_abs(mc_sub(d->ekf.P[i][j], d->ekf.P[j][i])));
        }
    }
    v[k++] = asym;
    v[k++] = d->ekf.spd_ok ? MC_ONE : MC_ZERO;
    v[k++] = mc_from_i((int32_t)d->cfg.angle_source);
    for (int i = 0; i < EKF_N; ++i) {
        v[k++] = d->cfg.ekf.q[i];
    }
    for (int i = 0; i < EKF_M; ++i) {
        v[k++] = d->cfg.ekf.r[i];
    }
    const uint32_t n = p002_signal_count(d);
    if (n > P002_N_BASE) {
        const hfi_angle_t *h = &d->est_state.hfi;
        v[k++] = h->hfi.on ? MC_ONE : MC_ZERO;
        v[k++] = h->hfi.u_h_V.alpha;
        v[k++] = h->hfi.u_h_V.beta;
        v[k++] = h->weight;
        if (n > P002_N_HFI) {
            v[k++] = mc_from_i(h->polarity);
            v[k++] = h->magpol.diff_A;
            v[k++] = h->lock_amp;
        }
    }
}

const drive_ops_t paper002_drive_ops = {
    .name = "paper002",
    .title = "paper 002: IPMSM speed drive (EKF with lumped disturbance, MTPA, SOSMC/HTSMC, encoder or flux observer)",
    .kind = DRIVE_KIND_SPEED,
    .can_kind = (uint8_t)DRIVE_CAN_HEARTBEAT_DRIVE_KIND_PAPER002_SPEED_CHOICE, /* the DBC's DriveKind */
    .state_bytes = (uint32_t)sizeof(paper002_drive_t),
    .config_bytes = (uint32_t)sizeof(paper002_config_t),
    .config_problem = p002_config_problem,
    .init = p002_init,
    .step = p002_step,
    .command = p002_command,
    .status = p002_status,
    .estimate = p002_estimate,
    .recorder = p002_recorder,
    .signals = p002_signals,
    .read_signals = p002_read_signals,
};
