/*
 * paper000_drive.c - the paper-000 drive as a recipe (see paper000_drive.h).
 *
 * Order inside one sample k (currents sampled at t_k, voltages held over
 * [t_k, t_k + Ts)):
 *   0. supervisor: latched fault, phase count, over-current trip;
 *   1. reference theta_r[k], theta_r[k+1] (eq. 70) and the (f-g) frame (6)-(8);
 *      the adapter's alpha-beta currents turned into it;
 *   2. estimator correction (25) and observability;
 *   3. supervisor event: closed loop when |omega_r| >= omega_lim and the
 *      back-EMF is observable (paper 000 section 4.2), open loop otherwise;
 *   4. estimates (29)-(32), (71), (33)-(37) and the law: open loop (68) or
 *      fg_tracking (46)-(54); bumpless transfer at a switch;
 *   5. voltage back to the phases at the mid-sample angle, limited;
 *   6. estimator prediction to k+1 with the voltage actually applied, and
 *      the standstill R/L measurement while identifying.
 * With a computation delay d (drive_delay_config_t) the voltage acts over
 * [t_k + d Ts, t_k+1 + d Ts): the law of 4 acts on the currents predicted to
 * t_k + d Ts, 5 turns the output at the middle of that interval, 6 uses the
 * mean of the last and this command; d = 0 skips these paths.
 */
#include "drives/paper000_drive.h"

#include "mc_version.h"

/* Samples between exact recomputations of the (f-g) frame rotation: in
 * between it turns by composition (four products per sample instead of a
 * sincos of a large angle). Each composition rounds the sine and cosine by
 * at most about one LSB (7.6e-6 in Q14.17), so 32 of them drift by at most
 * 2.4e-4 rad electrical, 5e-6 rad of rotor angle at n_p = 50, before the
 * exact angle resets it; a power of two makes the test a mask. */
#define DRIVE_FRAME_RESYNC 32u

/* Computation delay (drive_delay_config_t): functions called only for
 * d != 0, and kept out of line, so that the step without a delay stays as
 * it was (its instruction budget on a Cortex-M3 is nearly spent, and
 * inlined they cost it 17 instructions a sample in registers, measured
 * with tools/bench/pil.py). */
#if defined(__GNUC__)
#define DRIVE_OUT_OF_LINE __attribute__((noinline))
#else
#define DRIVE_OUT_OF_LINE
#endif

/* R(x phi) for x in [0, 1] from r = R(phi), phi half a sample of the
 * reference's rotation, without a sincos: sin(x phi) ~ x sin(phi),
 * cos(x phi) ~ 1 - x^2 (1 - cos(phi)). Exact at x = 0 and x = 1; in between
 * the angle is off by at most x (1 - x^2) phi^3 / 6 <= 0.064 phi^3 and the
 * norm by x^2 (1 - x^2) phi^4 / 24: 8e-6 rad electrical (one Q14.17 LSB) at
 * phi = 0.05 rad, the paper's 20 rad/s at n_p = 50 and 10 kHz. */
static mc_rot_t drive_rot_fraction(mc_rot_t r, mc_t x, mc_t x2)
{
    mc_rot_t f;
    f.s = mc_mul(x, r.s);
    f.c = mc_sub(MC_ONE, mc_mul(x2, mc_sub(MC_ONE, r.c)));
    return f;
}

/* The measured (f-g) currents i_f, i_g of this sample predicted to
 * t_k + d Ts, where its command starts to act, in the (f-g) frame of that
 * instant, then into the estimated frame (44) for the laws (46)-(54): they
 * replace the measured i_d, i_q of the estimator. Eq. (23) (errata (9a))
 * over d Ts, L di/dt = v - R i + e, with the voltage that holds until then
 * (the last command, in its own control frame, a fraction of a sample off
 * the interval's: second order) and the observed back-EMF e = L d-hat
 * (28a)-(28b); the frame's own turn over d Ts, the A_fg term of (23), as a
 * rotation by 2d half samples of the reference's rotation. */
static DRIVE_OUT_OF_LINE void drive_delay_currents(drive_t *d, mc_rot_t rot_half, mc_t i_f, mc_t i_g)
{
    const drive_delay_config_t *c = &d->cfg.delay;
    const mc_rot_t turn_x = drive_rot_fraction(rot_half, c->x, c->x2);
    const mc_rot_t turn = c->from_next ? mc_rot_compose(rot_half, turn_x) : turn_x;
    const mc_t a = mc_mul(c->d, d->model.ts_over_L_A_per_V);
    const mc_t uf = mc_cross2(MC_ONE, mc_add(d->sup.v_prev_V[0], d->est.emf.e_f_hat_V), d->model.R_ohm, i_f);
    const mc_t ug = mc_cross2(MC_ONE, mc_add(d->sup.v_prev_V[1], d->est.emf.e_g_hat_V), d->model.R_ohm, i_g);
    mc_t p_f, p_g;
    mc_rot_fwd(turn, mc_mac(i_f, a, uf), mc_mac(i_g, a, ug), &p_f, &p_g);
    mc_rot_fwd(d->est.u_est, p_f, p_g, &d->est.i_d_A, &d->est.i_q_A); /* (44) */
}

/* Step 5 with a delay: the (f-g) command to the phases with the frame of
 * the reference at t_k + (1/2 + d) Ts, the middle of the interval where it
 * acts (eq. (7) inverse: the mid-sample frame for d < 1/2, the next
 * sample's for d >= 1/2, turned by x half samples), limited; and, unless
 * the caller gave it, the voltage really applied over this sample for the
 * observer (25), v[k-1] for d Ts then v[k], as drive_set_applied_voltage()
 * would. Returns the phase (alpha-beta) command. */
static DRIVE_OUT_OF_LINE mc_ab_t drive_delay_output(drive_t *d, mc_rot_t rot_mid, mc_rot_t rot_half, mc_t v_f, mc_t v_g)
{
    const drive_delay_config_t *c = &d->cfg.delay;
    const mc_rot_t out = mc_rot_compose(c->from_next ? d->rot_next : rot_mid, drive_rot_fraction(rot_half, c->x, c->x2));
    mc_ab_t v_ab;
    mc_rot_inv(out, v_f, v_g, &v_ab.alpha, &v_ab.beta);
    (void)supervisor_limit(&d->sup, (uint8_t)DRIVE_N_PHASES, d->cfg.limits.v_max_V, &v_ab, &v_f, &v_g);
    if (!d->v_ext_set) {
        d->v_ext_V.alpha = mc_mac(v_ab.alpha, c->d, mc_sub(d->last.v_a_V, v_ab.alpha));
        d->v_ext_V.beta = mc_mac(v_ab.beta, c->d, mc_sub(d->last.v_b_V, v_ab.beta));
        d->v_ext_set = true;
    }
    return v_ab;
}

static void drive_zero_output(drive_t *d, hal_command_t *out)
{
    out->n_phases = (uint8_t)DRIVE_N_PHASES;
    for (uint32_t k = 0; k < HAL_MAX_PHASES; ++k) {
        out->v_V[k] = MC_ZERO;
    }
    d->last.v_a_V = MC_ZERO;
    d->last.v_b_V = MC_ZERO;
}

static bool drive_config_ok(const drive_config_t *c)
{
    const motor_model_t *m = &c->model;
    const drive_limits_t *l = &c->limits;
    return m->n_p >= 1 && m->fs_hz > 0 && m->R_ohm >= MC_ZERO && m->L_H > MC_ZERO && m->K_V_s > MC_ZERO &&
           l->v_max_V > MC_ZERO && l->i_max_A > MC_ZERO && l->i_trip_A >= l->i_max_A &&
           l->omega_lim_rad_s > MC_ZERO && c->sup.blend_decay >= MC_ZERO && c->sup.blend_decay < MC_ONE &&
           c->ctrl.pos.lambda_M >= c->ctrl.pos.lambda_m && c->ctrl.pos.lambda_m >= MC_ZERO &&
           c->ctrl.cur.lambda >= MC_ZERO && c->ctrl.cur.alpha_ts >= MC_ZERO && c->est.emf.alpha_V >= MC_ZERO &&
           c->est.emf.lpf_coeff > MC_ZERO && c->est.emf.lpf_coeff <= MC_ONE && c->delay.d >= MC_ZERO &&
           c->delay.d <= MC_ONE && c->delay.x >= MC_ZERO && c->delay.x <= MC_ONE && c->delay.x2 >= MC_ZERO &&
           c->delay.x2 <= c->delay.x;
}

bool drive_init(drive_t *d, const drive_config_t *cfg)
{
    d->cfg = *cfg;
    d->model = cfg->model;
    d->tick = 0;
    d->observable_run = 0;
    d->v_ext_set = false;
    d->v_ext_V.alpha = MC_ZERO;
    d->v_ext_V.beta = MC_ZERO;
    fg_estimator_init(&d->est, &cfg->est);
    fg_tracking_init(&d->ctrl, &cfg->ctrl);
    const bool traj_ok = trajectory_init(&d->traj, &cfg->traj);
    rl_id_init(&d->rl_id, &cfg->rl_id);
    supervisor_init(&d->sup, &cfg->sup, d->rl_id.state == RL_ID_RUNNING);
    d->last.tick = 0;
    d->last.i_f_A = MC_ZERO;
    d->last.i_g_A = MC_ZERO;
    hal_command_t unused;
    drive_zero_output(d, &unused);
    if (!drive_config_ok(cfg) || !traj_ok) {
        supervisor_fault(&d->sup, DRIVE_FAULT_BAD_INPUT);
        return false;
    }
    trajectory_eval(&d->traj, 0, &d->ref);
    trajectory_eval(&d->traj, 1, &d->ref_next);
    d->rot_k = mc_rot_from_angle(mc_elec_angle(d->ref.theta_rad, cfg->model.n_p));
    d->rot_next = d->rot_k;
    return true;
}

bool drive_step(drive_t *d, const hal_sample_t *in, hal_command_t *out)
{
    const drive_config_t *c = &d->cfg;
    d->last.tick = d->tick;
    /* 0. supervisor */
    if (d->sup.state == SUP_STATE_FAULT) {
        drive_zero_output(d, out);
        return false;
    }
    if (!phase_adapter_accepts(in, (uint8_t)DRIVE_N_PHASES)) {
        supervisor_fault(&d->sup, DRIVE_FAULT_BAD_INPUT);
        drive_zero_output(d, out);
        return false;
    }
    if (supervisor_overcurrent(in, (uint8_t)DRIVE_N_PHASES, c->limits.i_trip_A)) {
        supervisor_fault(&d->sup, DRIVE_FAULT_OVERCURRENT);
        drive_zero_output(d, out);
        return false;
    }
    mc_t i_zero_A;
    const mc_ab_t i_ab = phase_adapter_currents(in, &i_zero_A);
    (void)i_zero_A; /* two separate windings: no zero sequence */

    /* 1. frame of this sample and its rotation over the sample */
    if (d->tick > 0) {
        /* advance the reference: this sample's is the one computed last time */
        d->ref = d->ref_next;
        trajectory_eval(&d->traj, d->tick + 1, &d->ref_next);
        /* the frame turns by the rotation applied last sample; every
         * DRIVE_FRAME_RESYNC samples it is recomputed from theta_r, so the
         * rounding of the products cannot accumulate */
        if ((d->tick % DRIVE_FRAME_RESYNC) == 0u) {
            d->rot_k = mc_rot_from_angle(mc_elec_angle(d->ref.theta_rad, d->model.n_p));
            /* the observer's gain at the reference speed (discrete-time
             * design; a no-op otherwise): the speed moves by at most
             * |w'|max 32 Ts = 0.1 rad/s in between for the rig */
            fg_estimator_schedule(&d->est, d->ref.omega_rad_s);
        } else {
            d->rot_k = d->rot_next;
        }
    }
    /* n_p (theta_r[k+1] - theta_r[k]): exact (difference, then an integer
     * multiple), small, so no wrap */
    const mc_t dphi = mc_mul_i(mc_sub(d->ref_next.theta_rad, d->ref.theta_rad), d->model.n_p);
    const mc_rot_t rot_k = d->rot_k;
    const mc_rot_t rot_half = mc_rot_from_angle(mc_div_i(dphi, 2));
    const mc_rot_t rot_mid = mc_rot_compose(rot_k, rot_half);
    d->rot_next = mc_rot_compose(rot_mid, rot_half);
    mc_t i_f, i_g;
    mc_rot_fwd(rot_k, i_ab.alpha, i_ab.beta, &i_f, &i_g); /* eq. (6) */

    /* 2. estimator correction */
    fg_estimator_correct(&d->est, i_f, i_g);

    /* 3. supervisor event; the loop closes only on an estimate that has
     * been observable for close_dwell_ticks samples in a row, so that a
     * back-EMF hovering at the threshold cannot toggle the mode (and pile
     * up the switch offsets) sample after sample; it opens at once */
    const bool observable = fg_estimator_observable(&d->est);
    if (!observable) {
        d->observable_run = 0;
    } else if (d->observable_run < c->close_dwell_ticks) {
        d->observable_run += 1u;
    }
    const bool in_closed = d->sup.state == SUP_STATE_CLOSED_LOOP;
    const bool want_closed = !(mc_abs(d->ref.omega_rad_s) < c->limits.omega_lim_rad_s) && observable &&
                             (in_closed || !(d->observable_run < c->close_dwell_ticks));
    if (want_closed) {
        fg_estimator_track(&d->est, d->ref.theta_rad, d->ref.omega_rad_s);
    }
    bool switched = false;
    if (want_closed != in_closed) {
        switched = supervisor_dispatch(&d->sup, want_closed ? SUP_EV_ESTIMATE_TRUSTED : SUP_EV_ESTIMATE_LOST);
        if (switched && want_closed) {
            fg_estimator_lock_branch(&d->est, d->ref.theta_rad);
        }
    }
    const bool closed = d->sup.state == SUP_STATE_CLOSED_LOOP;

    /* 4. estimates and the law */
    fg_estimator_mechanics(&d->est, &d->model, closed, d->ref.omega_rad_s, i_f, i_g);
    mc_t v_f, v_g;
    if (closed) {
        mc_estimate_t est;
        fg_estimator_get(&d->est, true, d->ref.theta_rad, d->ref.omega_rad_s, d->ref.accel_rad_s2, &est);
        if (c->delay.d != MC_ZERO) {
            /* the law acts on the currents predicted to where its command
             * starts to act (they replace the measured ones of (44)) */
            drive_delay_currents(d, rot_half, i_f, i_g);
        }
        if (switched) {
            fg_tracking_start(&d->ctrl, &d->model, c->limits.i_max_A, &d->ref, &d->ref_next, est.load_Nm,
                              d->est.i_d_A, d->est.i_q_A);
        }
        fg_tracking_step(&d->ctrl, &d->model, c->limits.i_max_A, &d->ref, &d->ref_next, &est, d->est.u_est,
                         d->est.i_d_A, d->est.i_q_A, d->sup.sat_prev, &v_f, &v_g);
    } else {
        v_f = open_loop_voltage(&c->open_loop, &d->model, d->ref.omega_rad_s); /* eq. (68) */
        v_g = MC_ZERO;
    }
    supervisor_blend(&d->sup, switched, &v_f, &v_g);
    fg_tracking_relax(&d->ctrl);

    /* 5. to the phases at the mid-sample angle (the average (f-g) voltage over
     * the hold is then the commanded one; with a delay, the middle of the
     * interval where it acts), limited per phase to +-V_max with the
     * direction kept */
    mc_ab_t v_ab;
    if (c->delay.d == MC_ZERO) {
        mc_rot_inv(rot_mid, v_f, v_g, &v_ab.alpha, &v_ab.beta);
        /* the supervisor keeps the saturation (sat_prev) for the next step's
         * anti-windup and for the telemetry */
        (void)supervisor_limit(&d->sup, (uint8_t)DRIVE_N_PHASES, c->limits.v_max_V, &v_ab, &v_f, &v_g);
    } else {
        v_ab = drive_delay_output(d, rot_mid, rot_half, v_f, v_g);
        v_f = d->sup.v_prev_V[0]; /* the command as limited */
        v_g = d->sup.v_prev_V[1];
    }

    /* 6. observer prediction with the applied voltage (mid-sample frame) */
    mc_t v_f_obs = v_f, v_g_obs = v_g;
    if (d->v_ext_set) {
        mc_rot_fwd(rot_mid, d->v_ext_V.alpha, d->v_ext_V.beta, &v_f_obs, &v_g_obs);
        d->v_ext_set = false;
    }
    fg_estimator_predict(&d->est, &d->model, v_f_obs, v_g_obs, i_f, i_g, rot_half);
    /* the R, L measurement integrates the applied voltage too (at rest the
     * frames coincide) */
    if (d->sup.state == SUP_STATE_IDENTIFY &&
        rl_id_step(&d->rl_id, i_f, (c->delay.d != MC_ZERO) ? v_f_obs : v_f, d->ref.omega_rad_s)) {
        if (d->rl_id.state == RL_ID_DONE) {
            /* the measured R and L replace the model's everywhere at once:
             * observer (23), references (39), decoupling (48), (54), (68) */
            motor_model_set_rl(&d->model, d->rl_id.R_ohm, d->rl_id.L_fs_ohm);
        }
        (void)supervisor_dispatch(&d->sup, SUP_EV_IDENTIFIED);
    }

    phase_adapter_voltages((uint8_t)DRIVE_N_PHASES, v_ab, out);
    d->last.i_f_A = i_f;
    d->last.i_g_A = i_g;
    d->last.v_a_V = v_ab.alpha;
    d->last.v_b_V = v_ab.beta;
    d->tick += 1;
    return true;
}

void drive_get_telemetry(const drive_t *d, drive_telemetry_t *t)
{
    t->fw_version = MC_VERSION_U32;
    const bool closed = d->sup.state == SUP_STATE_CLOSED_LOOP;
    const fg_estimator_t *e = &d->est;
    t->mode = supervisor_mode(&d->sup);
    t->fault = d->sup.fault;
    t->state = d->sup.state;
    t->tick = d->last.tick;
    t->theta_ref_rad = d->ref.theta_rad;
    t->omega_ref_rad_s = d->ref.omega_rad_s;
    t->accel_ref_rad_s2 = d->ref.accel_rad_s2;
    /* references: the law's in closed loop; the open-loop start (68)
     * drives i_max along f; none in FAULT */
    const bool fault = d->sup.state == SUP_STATE_FAULT;
    t->i_f_ref_A = closed ? d->ctrl.i_f_ref_A : (fault ? MC_ZERO : d->cfg.open_loop.i_max_A);
    t->i_g_ref_A = closed ? d->ctrl.i_g_ref_A : MC_ZERO;
    t->i_f_A = d->last.i_f_A;
    t->i_g_A = d->last.i_g_A;
    /* the estimate the last sample was corrected with */
    t->i_f_hat_A = mc_sub(d->last.i_f_A, e->emf.err_f_A);
    t->i_g_hat_A = mc_sub(d->last.i_g_A, e->emf.err_g_A);
    t->e_f_hat_V = e->emf.e_f_hat_V;
    t->e_g_hat_V = e->emf.e_g_hat_V;
    t->delta_theta_est_rad = closed ? e->pos.dtheta_est_rad
                                    : (e->pos.valid ? position_estimator_angle(&e->pos, e->emf.e_f_hat_V,
                                                                               e->emf.e_g_hat_V, d->ref.omega_rad_s)
                                                    : MC_ZERO);
    t->jump_count = e->pos.k;
    mc_estimate_t est;
    fg_estimator_get(e, closed, d->ref.theta_rad, d->ref.omega_rad_s, d->ref.accel_rad_s2, &est);
    t->theta_est_rad = est.theta_rad;
    t->omega_est_rad_s = est.omega_rad_s;
    t->accel_est_rad_s2 = est.accel_rad_s2;
    t->load_est_Nm = est.load_Nm;
    /* the command of the last step, after the limit, is the supervisor's
     * (0 V in FAULT) */
    t->v_f_V = fault ? MC_ZERO : d->sup.v_prev_V[0];
    t->v_g_V = fault ? MC_ZERO : d->sup.v_prev_V[1];
    t->v_a_V = d->last.v_a_V;
    t->v_b_V = d->last.v_b_V;
    t->v_saturated = !fault && d->sup.sat_prev;
    t->rl_id_state = d->rl_id.state;
    t->R_model_ohm = d->model.R_ohm;
    t->L_model_H = d->model.L_H;
}

void drive_set_applied_voltage(drive_t *d, mc_t v_a_V, mc_t v_b_V)
{
    d->v_ext_V.alpha = v_a_V;
    d->v_ext_V.beta = v_b_V;
    d->v_ext_set = true;
}
