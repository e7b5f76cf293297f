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
};
