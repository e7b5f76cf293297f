/*
 * drive.c - the paper-000 drive state machine (see drive.h).
 *
 * Order inside one sample k (currents sampled at t_k, voltages held over
 * [t_k, t_k + Ts)):
 *   1. reference theta_r[k], theta_r[k+1] (eq. 70) and the (f-g) frame (6)-(8);
 *   2. observer correction (25) and estimates (29)-(32), (71), (33)-(37);
 *   3. mode: open loop (68) below omega_lim, closed loop (46)-(54) above;
 *   4. voltage back to the phases at the mid-sample angle, limited;
 *   5. observer prediction to k+1 with the voltage actually applied.
 *
 * At the open/closed switch (not specified by the paper) the jump counter
 * takes the branch of theta_est closest to the open-loop position estimate,
 * the super-twisting integral restarts at 0, and the difference between the
 * last and the new (f-g) voltage is added as an offset that decays with
 * tau_blend, so the applied voltage has no step.
 */
#include "drive/drive.h"

#include "math/frame_fg.h"

/* samples between exact recomputations of the (f-g) frame rotation */
#define DRIVE_FRAME_RESYNC 32u

/* One step of an exponential decay, snapped to 0 below 1e-4 (V or A): it
 * then costs nothing and cannot stall on a rounding fixed point. */
static mc_t drive_decay(mc_t x, mc_t factor)
{
    const mc_t y = mc_mul(factor, x);
    return (mc_abs(y) < MC_C(1e-4)) ? MC_ZERO : y;
}

static void drive_zero_output(drive_t *d, mc_t *v_a_V, mc_t *v_b_V)
{
    *v_a_V = MC_ZERO;
    *v_b_V = MC_ZERO;
    d->last.v_a_V = MC_ZERO;
    d->last.v_b_V = MC_ZERO;
    d->last.v_f_V = MC_ZERO;
    d->last.v_g_V = MC_ZERO;
    d->last.v_saturated = false;
}

static void drive_set_fault(drive_t *d, drive_fault_t f)
{
    d->mode = DRIVE_MODE_FAULT;
    if (d->fault == DRIVE_FAULT_NONE) {
        d->fault = f;
    }
}

static bool drive_config_ok(const drive_config_t *c)
{
    return c->n_p >= 1 && c->fs_hz > 0 && c->R_ohm >= MC_ZERO && c->L_H > MC_ZERO && c->K_V_s > MC_ZERO &&
           c->v_max_V > MC_ZERO && c->i_max_A > MC_ZERO && c->i_trip_A >= c->i_max_A &&
           c->omega_lim_rad_s > MC_ZERO && c->blend_decay >= MC_ZERO && c->blend_decay < MC_ONE &&
           c->pos_ctrl.lambda_M >= c->pos_ctrl.lambda_m && c->pos_ctrl.lambda_m >= MC_ZERO &&
           c->cur.lambda >= MC_ZERO && c->cur.alpha_ts >= MC_ZERO && c->emf.alpha_V >= MC_ZERO &&
           c->emf.lpf_coeff > MC_ZERO && c->emf.lpf_coeff <= MC_ONE;
}

bool drive_init(drive_t *d, const drive_config_t *cfg)
{
    d->cfg = *cfg;
    d->mode = DRIVE_MODE_OPEN_LOOP;
    d->fault = DRIVE_FAULT_NONE;
    d->tick = 0;
    d->blend_f_V = MC_ZERO;
    d->blend_g_V = MC_ZERO;
    d->i_f_off_A = MC_ZERO;
    d->i_g_off_A = MC_ZERO;
    d->v_f_prev_V = MC_ZERO;
    d->v_g_prev_V = MC_ZERO;
    d->sat_prev = false;
    d->v_ext_set = false;
    d->v_a_ext_V = MC_ZERO;
    d->v_b_ext_V = MC_ZERO;
    emf_observer_init(&d->emf, &cfg->emf);
    position_estimator_init(&d->pos, &cfg->pos);
    mech_observer_init(&d->mech, &cfg->mech);
    super_twisting_init(&d->cur, &cfg->cur);
    twisting_init(&d->pos_ctrl, &cfg->pos_ctrl);
    const bool traj_ok = trajectory_init(&d->traj, &cfg->traj);
    rl_id_init(&d->rl_id, &cfg->rl_id);
    d->last.tick = 0;
    d->last.i_f_A = MC_ZERO;
    d->last.i_g_A = MC_ZERO;
    d->last.i_f_ref_A = MC_ZERO;
    d->last.i_g_ref_A = MC_ZERO;
    drive_zero_output(d, &d->last.v_a_V, &d->last.v_b_V);
    if (!drive_config_ok(cfg) || !traj_ok) {
        drive_set_fault(d, DRIVE_FAULT_BAD_INPUT);
        return false;
    }
    trajectory_eval(&d->traj, 0, &d->ref);
    trajectory_eval(&d->traj, 1, &d->ref_next);
    d->rot_k = mc_rot_from_angle(mc_elec_angle(d->ref.theta_rad, cfg->n_p));
    d->rot_next = d->rot_k;
    return true;
}

/* Puts the measured R and L (L_fs = L/Ts) into every model term that uses
 * them: the observer (23), the references (39), the decoupling of (48) and
 * (54), and the open-loop voltage (68). Gains stay as designed. */
static void drive_use_measured_rl(drive_t *d, mc_t R_ohm, mc_t L_fs_ohm)
{
    drive_config_t *c = &d->cfg;
    c->R_ohm = R_ohm;
    c->L_H = mc_div_i(L_fs_ohm, c->fs_hz);
    c->npL_ohm_s = mc_div_i(mc_mul_i(L_fs_ohm, c->n_p), c->fs_hz);
    c->open_loop.R_ohm = R_ohm;
    c->open_loop.npL_ohm_s = c->npL_ohm_s;
    c->LJ_over_KTs_V_s2 = mc_mul(L_fs_ohm, c->J_over_K_A_s2);
    c->Lfv_over_KTs_V_s = mc_mul(L_fs_ohm, c->fv_over_K_A_s);
    c->emf.R_ohm = R_ohm;
    c->emf.ts_over_L_A_per_V = mc_div(MC_ONE, L_fs_ohm);
    d->emf.cfg.R_ohm = c->emf.R_ohm;
    d->emf.cfg.ts_over_L_A_per_V = c->emf.ts_over_L_A_per_V;
}

/* Reference currents and voltages of the flat outputs, eqs. (38)-(39):
 * i_g,r = (J theta_r'' + f_v theta_r')/K, and the voltages from the
 * reference model (38) with i_f,r constant. */
static void drive_references(const drive_t *d, mc_t *i_fr, mc_t *i_gr, mc_t *v_fr, mc_t *v_gr)
{
    const drive_config_t *c = &d->cfg;
    const trajectory_point_t *r = &d->ref;
    /* i_f,r: constant plus the decaying switch offset (a free flat output) */
    *i_fr = mc_add(c->i_f_ref_A, d->i_f_off_A);
    /* (39) with the load of (9c): J w_r' = K i_g,r - f_v w_r - C_r, C_r from (35) */
    mc_t i_g = mc_dot2(c->J_over_K_A_s2, r->accel_rad_s2, c->fv_over_K_A_s, r->omega_rad_s);
    i_g = mc_mac(i_g, c->load_ff_A_per_Nm, mc_clamp(d->mech.load_est_Nm, mc_neg(c->load_ff_max_Nm), c->load_ff_max_Nm));
    *i_gr = mc_clamp(mc_add(i_g, d->i_g_off_A), mc_neg(c->i_max_A), c->i_max_A);
    /* L di_g,r/dt of (39), (JL/K) theta_r''' + (L f_v/K) theta_r'', taken as
     * the change of i_g,r over the sample (L/Ts times the difference of the
     * references at k+1 and k): the voltage is held over that sample, so its
     * average is what moves the current there */
    const trajectory_point_t *rn = &d->ref_next;
    mc_t Ldi_gr = mc_dot2(c->LJ_over_KTs_V_s2, mc_sub(rn->accel_rad_s2, r->accel_rad_s2), c->Lfv_over_KTs_V_s,
                          mc_sub(rn->omega_rad_s, r->omega_rad_s));
    mc_t Ldi_fr = MC_ZERO;
    if (d->i_f_off_A != MC_ZERO || d->i_g_off_A != MC_ZERO) {
        Ldi_fr = mc_neg(mc_mul(c->ref_blend_L_over_tau_ohm, d->i_f_off_A));
        Ldi_gr = mc_sub(Ldi_gr, mc_mul(c->ref_blend_L_over_tau_ohm, d->i_g_off_A));
    }
    const mc_t npLw = mc_mul(c->npL_ohm_s, r->omega_rad_s);
    /* L di_f,r/dt = v_f,r - R i_f,r + n_p L w_r i_g,r   (38) */
    *v_fr = mc_add(mc_cross2(c->R_ohm, *i_fr, npLw, *i_gr), Ldi_fr);
    /* L di_g,r/dt = v_g,r - R i_g,r - n_p L w_r i_f,r - K w_r   (38) */
    *v_gr = mc_mac(mc_add(Ldi_gr, mc_dot2(c->R_ohm, *i_gr, npLw, *i_fr)), c->K_V_s, r->omega_rad_s);
}

/* Closed-loop law: eq. (44) errors, (48) super-twisting on xi_f, (52)-(54)
 * twisting on S_theta; returns v in the (f-g) frame. u is U(n_p (theta_est -
 * theta_r)) and (i_d, i_q) the measured currents turned by it, eq. (44). */
static void drive_closed_loop(drive_t *d, mc_rot_t u, mc_t i_d, mc_t i_q, mc_t *v_f, mc_t *v_g)
{
    const drive_config_t *c = &d->cfg;
    mc_t i_fr, i_gr, v_fr, v_gr;
    drive_references(d, &i_fr, &i_gr, &v_fr, &v_gr);
    d->last.i_f_ref_A = i_fr;
    d->last.i_g_ref_A = i_gr;

    const mc_t xi_theta = mc_sub(d->pos.theta_est_rad, d->ref.theta_rad);
    const mc_t w_r = d->ref.omega_rad_s;
    const mc_t xi_f = mc_sub(i_d, i_fr);
    const mc_t xi_g = mc_sub(i_q, i_gr);
    /* xi_omega from the mechanical observer's speed: (32) differentiates the
     * back-EMF angle and is too noisy at low speed; (35) filters it through
     * the motor's own dynamics without lag from a separate filter */
    const mc_t xi_w = mc_sub(d->mech.omega_est_rad_s, w_r);

    /* (48): v_f-bar = -L mu_1 + L u_st(xi_f), mu_1 of (45a) */
    const mc_t cross_f = mc_dot2(xi_w, mc_add(xi_g, i_gr), w_r, xi_g);
    const mc_t u_st = super_twisting_step(&d->cur, xi_f, d->sat_prev);
    const mc_t vb_f = mc_add(mc_cross2(c->R_ohm, xi_f, c->npL_ohm_s, cross_f), u_st);

    /* (52)-(54): S = k xi_theta + xi_omega, dS/dt from the observed acceleration */
    const mc_t S = mc_mac(xi_w, c->k_surface_per_s, xi_theta);
    const mc_t S_dot = mc_mac(mc_sub(d->mech.accel_est_rad_s2, d->ref.accel_rad_s2), c->k_surface_per_s, xi_w);
    const mc_t w_tw = twisting_step(&d->pos_ctrl, S, S_dot);
    /* (JL/K) times (54), with mu_2 of (42) after the errata:
     * v_g-bar = R xi_g + n_p L (xi_w (xi_f + i_f,r) + w_r xi_f) + K xi_w
     *           - L (k - f_v/J) xi_g + (L/K)(k - f_v/J) f_v xi_w + (JL/K) w_t */
    const mc_t cross_g = mc_dot2(xi_w, mc_add(xi_f, i_fr), w_r, xi_f);
    const mc_t vb_g = mc_add(mc_dot2(mc_sub(c->R_ohm, c->v_k_i_V_per_A), xi_g, c->npL_ohm_s, cross_g),
                             mc_mac(w_tw, mc_add(c->K_V_s, c->v_k_w_V_s), xi_w));

    /* v_dq = v_ref + v-bar, then back to (f-g): v_fg = U(xi_theta)^T v_dq */
    mc_rot_inv(u, mc_add(v_fr, vb_f), mc_add(v_gr, vb_g), v_f, v_g);
}

bool drive_step(drive_t *d, mc_t i_a_A, mc_t i_b_A, mc_t *v_a_V, mc_t *v_b_V)
{
    const drive_config_t *c = &d->cfg;
    d->last.tick = d->tick;
    if (d->mode == DRIVE_MODE_FAULT) {
        drive_zero_output(d, v_a_V, v_b_V);
        return false;
    }
    const mc_t trip_neg = mc_neg(c->i_trip_A);
    if (i_a_A > c->i_trip_A || i_a_A < trip_neg || i_b_A > c->i_trip_A || i_b_A < trip_neg) {
        drive_set_fault(d, DRIVE_FAULT_OVERCURRENT);
        drive_zero_output(d, v_a_V, v_b_V);
        return false;
    }

    /* 1. frame of this sample and its rotation over the sample */
    if (d->tick > 0) {
        /* advance the reference: this sample's is the one computed last time */
        d->ref = d->ref_next;
        trajectory_eval(&d->traj, d->tick + 1, &d->ref_next);
        /* the frame turns by the rotation applied last sample; every
         * DRIVE_FRAME_RESYNC samples it is recomputed from theta_r, so the
         * rounding of the products cannot accumulate */
        d->rot_k = ((d->tick % DRIVE_FRAME_RESYNC) == 0u)
                       ? mc_rot_from_angle(mc_elec_angle(d->ref.theta_rad, c->n_p))
                       : d->rot_next;
    }
    /* n_p (theta_r[k+1] - theta_r[k]): exact (difference, then an integer
     * multiple), small, so no wrap */
    const mc_t dphi = mc_mul_i(mc_sub(d->ref_next.theta_rad, d->ref.theta_rad), c->n_p);
    const mc_rot_t rot_k = d->rot_k;
    const mc_rot_t rot_half = mc_rot_from_angle(mc_div_i(dphi, 2));
    const mc_rot_t rot_mid = mc_rot_compose(rot_k, rot_half);
    d->rot_next = mc_rot_compose(rot_mid, rot_half);
    mc_t i_f, i_g;
    mc_rot_fwd(rot_k, i_a_A, i_b_A, &i_f, &i_g); /* eq. (6) */

    /* 2. estimates */
    emf_observer_correct(&d->emf, i_f, i_g);
    /* (29) and (71) only where they are used: in closed loop and at the
     * switch (the branch is chosen there); in open loop only observability */
    position_estimator_observe(&d->pos, d->emf.e_f_hat_V, d->emf.e_g_hat_V);

    /* 3. mode */
    const bool want_closed = !(mc_abs(d->ref.omega_rad_s) < c->omega_lim_rad_s) && d->pos.valid;
    if (want_closed) {
        position_estimator_step(&d->pos, d->emf.e_f_hat_V, d->emf.e_g_hat_V, d->ref.theta_rad, d->ref.omega_rad_s);
    }
    bool switched = false;
    if (d->mode == DRIVE_MODE_OPEN_LOOP && want_closed) {
        /* in open loop the rotor sits on the reference: take the branch of
         * theta_est closest to theta_r */
        position_estimator_set_branch(&d->pos, d->ref.theta_rad, d->ref.theta_rad);
        super_twisting_reset(&d->cur, MC_ZERO);
        d->mode = DRIVE_MODE_CLOSED_LOOP;
        switched = true;
    } else if (d->mode == DRIVE_MODE_CLOSED_LOOP && !want_closed) {
        d->mode = DRIVE_MODE_OPEN_LOOP;
        switched = true;
    }

    /* Mechanical observer (33)-(37): in closed loop on the (32) estimate;
     * in open loop the rotor follows the reference, so theta_r' serves as
     * the measurement and the angle is the observer's once observable. */
    const bool closed = d->mode == DRIVE_MODE_CLOSED_LOOP;
    if (closed) {
        position_estimator_speed(&d->pos, d->emf.e_f_hat_V, d->emf.e_g_hat_V, d->emf.z_f_V_s, d->emf.z_g_V_s,
                                 d->ref.omega_rad_s);
    }
    /* U(n_p (theta_est - theta_r)) of (44): n_p dtheta_est is the arctan of
     * (29) and the jump count adds whole turns, so its sine and cosine are
     * the normalised arguments of that arctan (no sincos needed). Open
     * loop before the back-EMF is observable: the reference frame. */
    mc_rot_t u_est = {MC_ZERO, MC_ONE};
    if (d->pos.valid) {
        const mc_t inv_e = mc_rsqrt(d->pos.e2_V2);
        const bool neg = d->ref.omega_rad_s < MC_ZERO;
        u_est.s = mc_mul(neg ? mc_neg(d->emf.e_f_hat_V) : d->emf.e_f_hat_V, inv_e);
        u_est.c = mc_mul(neg ? d->emf.e_g_hat_V : mc_neg(d->emf.e_g_hat_V), inv_e);
    }
    mc_t i_d_est, i_q_est; /* (44): currents in the estimated rotor frame */
    mc_rot_fwd(u_est, i_f, i_g, &i_d_est, &i_q_est);
    mech_observer_step(&d->mech, closed ? d->pos.omega_est_rad_s : d->ref.omega_rad_s, i_q_est);
    if (switched && closed) {
        /* bumpless in current: the references start at the measured
         * estimated-frame currents and relax to the flat ones */
        d->i_f_off_A = MC_ZERO;
        d->i_g_off_A = MC_ZERO;
        mc_t i_fr0, i_gr0, v_fr0, v_gr0;
        drive_references(d, &i_fr0, &i_gr0, &v_fr0, &v_gr0);
        d->i_f_off_A = mc_sub(i_d_est, i_fr0);
        d->i_g_off_A = mc_sub(i_q_est, i_gr0);
    }

    mc_t v_f, v_g;
    if (closed) {
        drive_closed_loop(d, u_est, i_d_est, i_q_est, &v_f, &v_g);
    } else {
        v_f = open_loop_voltage(&c->open_loop, d->ref.omega_rad_s); /* eq. (68) */
        v_g = MC_ZERO;
        d->last.i_f_ref_A = c->open_loop.i_max_A;
        d->last.i_g_ref_A = MC_ZERO;
    }
    if (switched) {
        d->blend_f_V = mc_add(d->blend_f_V, mc_sub(d->v_f_prev_V, v_f));
        d->blend_g_V = mc_add(d->blend_g_V, mc_sub(d->v_g_prev_V, v_g));
    }
    if (d->blend_f_V != MC_ZERO || d->blend_g_V != MC_ZERO) {
        v_f = mc_add(v_f, d->blend_f_V);
        v_g = mc_add(v_g, d->blend_g_V);
        d->blend_f_V = drive_decay(d->blend_f_V, c->blend_decay);
        d->blend_g_V = drive_decay(d->blend_g_V, c->blend_decay);
    }
    if (d->i_f_off_A != MC_ZERO || d->i_g_off_A != MC_ZERO) {
        d->i_f_off_A = drive_decay(d->i_f_off_A, c->ref_blend_decay);
        d->i_g_off_A = drive_decay(d->i_g_off_A, c->ref_blend_decay);
    }

    /* 4. to the phases at the mid-sample angle (the average (f-g) voltage over
     * the hold is then the commanded one), limited per phase to +-V_max with
     * the direction kept */
    mc_t v_a, v_b;
    mc_rot_inv(rot_mid, v_f, v_g, &v_a, &v_b);
    const mc_t v_peak = mc_max(mc_abs(v_a), mc_abs(v_b));
    const bool sat = v_peak > c->v_max_V;
    if (sat) {
        const mc_t scale = mc_div(c->v_max_V, v_peak);
        v_a = mc_mul(v_a, scale);
        v_b = mc_mul(v_b, scale);
        v_f = mc_mul(v_f, scale);
        v_g = mc_mul(v_g, scale);
    }
    d->sat_prev = sat;
    d->v_f_prev_V = v_f;
    d->v_g_prev_V = v_g;

    /* 5. observer prediction with the applied voltage (mid-sample frame) */
    mc_t v_f_obs = v_f, v_g_obs = v_g;
    if (d->v_ext_set) {
        mc_rot_fwd(rot_mid, d->v_a_ext_V, d->v_b_ext_V, &v_f_obs, &v_g_obs);
        d->v_ext_set = false;
    }
    emf_observer_predict(&d->emf, v_f_obs, v_g_obs, i_f, i_g, rot_half);
    if (!closed && rl_id_step(&d->rl_id, i_f, v_f, d->ref.omega_rad_s) && d->rl_id.state == RL_ID_DONE) {
        drive_use_measured_rl(d, d->rl_id.R_ohm, d->rl_id.L_fs_ohm);
    }

    d->last.i_f_A = i_f;
    d->last.i_g_A = i_g;
    d->last.v_f_V = v_f;
    d->last.v_g_V = v_g;
    d->last.v_a_V = v_a;
    d->last.v_b_V = v_b;
    d->last.v_saturated = sat;
    d->tick += 1;
    *v_a_V = v_a;
    *v_b_V = v_b;
    return true;
}

void drive_get_telemetry(const drive_t *d, drive_telemetry_t *t)
{
    const bool closed = d->mode == DRIVE_MODE_CLOSED_LOOP;
    t->mode = d->mode;
    t->fault = d->fault;
    t->tick = d->last.tick;
    t->theta_ref_rad = d->ref.theta_rad;
    t->omega_ref_rad_s = d->ref.omega_rad_s;
    t->accel_ref_rad_s2 = d->ref.accel_rad_s2;
    t->i_f_ref_A = d->last.i_f_ref_A;
    t->i_g_ref_A = d->last.i_g_ref_A;
    t->i_f_A = d->last.i_f_A;
    t->i_g_A = d->last.i_g_A;
    /* the estimate the last sample was corrected with */
    t->i_f_hat_A = mc_sub(d->last.i_f_A, d->emf.err_f_A);
    t->i_g_hat_A = mc_sub(d->last.i_g_A, d->emf.err_g_A);
    t->e_f_hat_V = d->emf.e_f_hat_V;
    t->e_g_hat_V = d->emf.e_g_hat_V;
    t->delta_theta_est_rad = closed ? d->pos.dtheta_est_rad
                                    : (d->pos.valid ? position_estimator_angle(&d->pos, d->emf.e_f_hat_V,
                                                                               d->emf.e_g_hat_V, d->ref.omega_rad_s)
                                                    : MC_ZERO);
    t->jump_count = d->pos.k;
    /* in open loop the rotor follows the reference (Fig. 7 of the paper) */
    t->theta_est_rad = closed ? d->pos.theta_est_rad : d->ref.theta_rad;
    t->omega_est_rad_s = closed ? d->mech.omega_est_rad_s : d->ref.omega_rad_s;
    t->accel_est_rad_s2 = closed ? d->mech.accel_est_rad_s2 : d->ref.accel_rad_s2;
    t->load_est_Nm = d->mech.load_est_Nm;
    t->v_f_V = d->last.v_f_V;
    t->v_g_V = d->last.v_g_V;
    t->v_a_V = d->last.v_a_V;
    t->v_b_V = d->last.v_b_V;
    t->v_saturated = d->last.v_saturated;
    t->rl_id_state = d->rl_id.state;
    t->R_model_ohm = d->cfg.R_ohm;
    t->L_model_H = d->cfg.L_H;
}

void drive_set_applied_voltage(drive_t *d, mc_t v_a_V, mc_t v_b_V)
{
    d->v_a_ext_V = v_a_V;
    d->v_b_ext_V = v_b_V;
    d->v_ext_set = true;
}
