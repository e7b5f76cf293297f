/*
 * drive_design.c - gains of the paper-000 drive derived from the motor and
 * its bounds (host side, double precision).
 *
 * Super-twisting (13)-(16) with a perturbation whose derivative is bounded
 * by Pi converges in finite time when alpha > Pi and lambda^2 >=
 * 4 Pi (alpha + Pi)/(alpha - Pi) (Levant 1993; the Lyapunov conditions
 * (18)-(20) of the paper are met by the same pair). We take alpha = 2 Pi,
 * which gives lambda = sqrt(12 Pi). Twisting (21) needs (22):
 * lambda_m > C0/k_m and lambda_M > (K_M lambda_m + 2 C0)/k_m with
 * k_m = K_M = 1 here (w_t enters S'' with unit gain, eq. (55)); C0 is
 * the bound (57) plus the voltage-error term of the errata. A margin of
 * 1.2 is applied to each strict inequality.
 */
#include "design/drive_design.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "math/mc_convert.h"

/* Maximum of |p'| and |p''| of the degree-7 polynomial over D in [0, 1]. */
#define POLY7_DP_MAX 2.1875
#define POLY7_DDP_MAX 7.5132

void drive_design_defaults(drive_design_input_t *in)
{
    memset(in, 0, sizeof(*in));
    in->ts_s = 1e-4;
    in->v_max_V = 30.0;
    in->i_max_A = 3.0;
    in->i_trip_A = 6.0;
    in->omega_lim_rad_s = 3.0;
    in->bound_accel_rad_s2 = 0.0;      /* 0: from the trajectory */
    in->bound_speed_rad_s = 0.0;       /* 0: from the trajectory */
    in->bound_delta_omega_rad_s = 1.0; /* closed-loop velocity error (Fig. 8: ~1 rad/s) */
    in->bound_load_Nm = 0.0752;        /* Coulomb friction of the rig, section 5.3 */
    in->bound_load_rate_Nm_s = 2.0;    /* slow load changes */
    in->bound_model_error_V = 0.05;    /* errata on (57): volts of model error */
    in->load_feedforward = 1;            /* see drive_design.h */
    in->identify_rl = 1;
}

static bool fail(char *err, size_t n, const char *field, const char *why, double got)
{
    if (err && n > 0) {
        snprintf(err, n, "%s: %s (got %g)", field, why, got);
    }
    return false;
}

static double pick(double override_value, double derived) { return override_value > 0.0 ? override_value : derived; }

bool drive_design(const drive_design_input_t *in, drive_config_t *cfg, char *err, size_t err_len)
{
    const drive_motor_si_t *m = &in->motor;
    if (!(m->L_H > 0.0)) return fail(err, err_len, "motor.L_H", "must be > 0", m->L_H);
    if (!(m->R_ohm >= 0.0)) return fail(err, err_len, "motor.R_ohm", "must be >= 0", m->R_ohm);
    if (!(m->K_Nm_per_A > 0.0)) return fail(err, err_len, "motor.K_Nm_per_A", "must be > 0", m->K_Nm_per_A);
    if (!(m->J_kgm2 > 0.0)) return fail(err, err_len, "motor.J_kgm2", "must be > 0", m->J_kgm2);
    if (!(m->fv_Nms_per_rad >= 0.0)) return fail(err, err_len, "motor.fv_Nms_per_rad", "must be >= 0", m->fv_Nms_per_rad);
    if (m->n_p < 1) return fail(err, err_len, "motor.n_p", "must be >= 1", (double)m->n_p);
    if (!(in->ts_s > 0.0)) return fail(err, err_len, "run.Ts_s", "must be > 0", in->ts_s);
    if (!(in->v_max_V > 0.0)) return fail(err, err_len, "supply.v_max_V", "must be > 0", in->v_max_V);
    if (!(in->i_max_A > 0.0)) return fail(err, err_len, "limits.i_max_A", "must be > 0", in->i_max_A);
    if (!(in->i_trip_A >= in->i_max_A)) return fail(err, err_len, "limits.i_trip_A", "must be >= i_max_A", in->i_trip_A);
    if (!(in->omega_lim_rad_s > 0.0)) return fail(err, err_len, "limits.omega_lim_rad_s", "must be > 0", in->omega_lim_rad_s);
    if (in->n_segments < 0 || in->n_segments > DRIVE_DESIGN_MAX_SEGMENTS)
        return fail(err, err_len, "trajectory.segments", "too many segments", (double)in->n_segments);

    const double L = m->L_H, R = m->R_ohm, K = m->K_Nm_per_A, J = m->J_kgm2, fv = m->fv_Nms_per_rad;
    const double Ts = in->ts_s;
    const int np = m->n_p;
    const double fs = 1.0 / Ts;
    if (fabs(fs - floor(fs + 0.5)) > 1e-6 * fs) return fail(err, err_len, "run.Ts_s", "1/Ts must be a whole number of Hz", Ts);

    /* trajectory: integer sample times, and the peaks the bounds need */
    memset(cfg, 0, sizeof(*cfg));
    trajectory_config_t *tc = &cfg->traj;
    tc->fs_hz = (int32_t)floor(fs + 0.5);
    tc->theta_start_rad = mc_from_double(0.0);
    tc->n_segments = in->n_segments;
    double from = 0.0, t_end = 0.0, speed_pk = 0.0, accel_pk = 0.0;
    for (int i = 0; i < in->n_segments; ++i) {
        const drive_segment_si_t *s = &in->segments[i];
        if (!(s->duration_s > 0.0)) return fail(err, err_len, "trajectory.segments.duration_s", "must be > 0", s->duration_s);
        if (!(s->t_start_s >= t_end - 1e-12))
            return fail(err, err_len, "trajectory.segments.t_start_s", "overlaps the previous segment", s->t_start_s);
        const double T = s->duration_s, d = s->theta_to_rad - from;
        tc->seg[i].start_tick = (uint32_t)floor(s->t_start_s * fs + 0.5);
        tc->seg[i].duration_ticks = (uint32_t)floor(T * fs + 0.5);
        tc->seg[i].theta_to_rad = mc_from_double(s->theta_to_rad);
        tc->seg[i].v_scale = mc_from_double(d / T);
        tc->seg[i].a_scale = mc_from_double(d / (T * T));
        tc->seg[i].j_scale = mc_from_double(d / (T * T * T));
        tc->seg[i].c0 = mc_from_double(d * 35.0 / 16.0);
        tc->seg[i].c1 = mc_from_double(d * 35.0 / 4.0);
        tc->seg[i].c2 = mc_from_double(d * 21.0);
        tc->seg[i].c3 = mc_from_double(d * 20.0);
        tc->seg[i].theta_mid_rad = mc_from_double(from + 0.5 * d);
        if (fabs(d * 21.0) > 0.9 * mc_max_double() || fabs(d / (T * T * T)) > 0.9 * mc_max_double())
            return fail(err, err_len, "trajectory.segments", "move too long or too fast for the numeric range; split it", d);
        speed_pk = fmax(speed_pk, POLY7_DP_MAX * fabs(d) / T);
        accel_pk = fmax(accel_pk, POLY7_DDP_MAX * fabs(d) / (T * T));
        from = s->theta_to_rad;
        t_end = s->t_start_s + T;
    }
    const double a_max = fmax(in->bound_accel_rad_s2, accel_pk);
    const double w_max = fmax(fmax(in->bound_speed_rad_s, speed_pk), in->omega_lim_rad_s);
    const double dw_max = in->bound_delta_omega_rad_s;
    const drive_gain_override_t *ov = &in->override;

    /* Electrical observer, section 3.1.1: Pi_d = (K/L)(|w'|max + n_p |w dw|max) */
    const double Pi_d = (K / L) * (a_max + np * w_max * dw_max);
    const double alpha_e = pick(ov->emf_alpha_A_s2, 2.0 * Pi_d);
    const double lambda_e = pick(ov->emf_lambda, sqrt(4.0 * Pi_d * (alpha_e + Pi_d) / fmax(alpha_e - Pi_d, 1e-9 * alpha_e)));
    /* linear term: the error dynamics (26) get a pole at l; one tenth of
     * the sample rate keeps the discrete loop well damped */
    const double l_e = pick(ov->emf_l_per_s, 0.1 * fs);
    const double tau_f = pick(ov->injection_filter_s, 1e-3);
    cfg->emf.ts_over_L_A_per_V = mc_from_double(Ts / L);
    cfg->emf.R_ohm = mc_from_double(R);
    cfg->emf.lambda_A = mc_from_double(lambda_e * Ts);
    cfg->emf.l_ts = mc_from_double(l_e * Ts);
    cfg->emf.alpha_V = mc_from_double(L * alpha_e * Ts);
    cfg->emf.alpha_V_s = mc_from_double(L * alpha_e);
    cfg->emf.lpf_coeff = mc_from_double(Ts / (tau_f + Ts));

    /* Position estimator: observable once |e| = K|w| exceeds a quarter of
     * its value at omega_lim */
    cfg->pos.n_p = np;
    cfg->pos.pitch_rad = mc_from_double(2.0 * 3.14159265358979323846 / np);
    cfg->pos.inv_K_rad_s_per_V = mc_from_double(1.0 / K);
    const double e_min = 0.25 * K * in->omega_lim_rad_s;
    cfg->pos.e2_min_V2 = mc_from_double(e_min * e_min);

    /* Mechanical observer, section 3.2: Pi = |dC_r/dt|max / J */
    const double Pi_m = in->bound_load_rate_Nm_s / J;
    const double alpha_m = pick(ov->mech_alpha_rad_s3, 2.0 * Pi_m);
    const double lambda_m = pick(ov->mech_lambda, sqrt(4.0 * Pi_m * (alpha_m + Pi_m) / fmax(alpha_m - Pi_m, 1e-9 * alpha_m)));
    const double l_m = pick(ov->mech_l_per_s, 0.01 * fs);
    cfg->mech.ts_over_J = mc_from_double(Ts / J);
    cfg->mech.inv_J = mc_from_double(1.0 / J);
    cfg->mech.K_Nm_per_A = mc_from_double(K);
    cfg->mech.fv_Nm_s = mc_from_double(fv);
    cfg->mech.lambda_ts = mc_from_double(lambda_m * Ts);
    cfg->mech.l_ts = mc_from_double(l_m * Ts);
    cfg->mech.alpha_Nm = mc_from_double(J * alpha_m * Ts);
    cfg->mech.tau_max_Nm = mc_from_double(2.0 * K * in->i_max_A);

    /* i_f loop (46)-(51): after the feed-forward of (48) the perturbation
     * left in dS_f/dt is the back-EMF error of the estimated frame, whose
     * rate is bounded like Pi_d; (51) only asks alpha, lambda > 0, the
     * perturbation asks alpha > Pi. Output scaled by L (volts). */
    const double alpha_c = pick(ov->cur_alpha_A_s2, 2.0 * Pi_d);
    const double lambda_c = pick(ov->cur_lambda, sqrt(4.0 * Pi_d * (alpha_c + Pi_d) / fmax(alpha_c - Pi_d, 1e-9 * alpha_c)));
    cfg->cur.lambda = mc_from_double(L * lambda_c);
    cfg->cur.alpha_ts = mc_from_double(L * alpha_c * Ts);
    cfg->cur.u1_max = mc_from_double(in->v_max_V);

    /* Position loop (52)-(57). k sets the sliding dynamics xi_theta' = -k xi_theta. */
    const double k = pick(ov->k_surface_per_s, 50.0);
    const double C0 = fabs(k / J - fv / (J * J)) * in->bound_load_Nm + in->bound_load_rate_Nm_s / J +
                      (K / (J * L)) * in->bound_model_error_V;
    const double lam_m = pick(ov->tw_lambda_m_rad_s3, 1.2 * C0);
    const double lam_M = pick(ov->tw_lambda_M_rad_s3, 1.2 * (lam_m + 2.0 * C0));
    if (!(lam_M >= lam_m)) return fail(err, err_len, "gains.tw_lambda_M_rad_s3", "must be >= tw_lambda_m_rad_s3", lam_M);
    const double JL_K = J * L / K;
    cfg->pos_ctrl.lambda_m = mc_from_double(JL_K * lam_m);
    cfg->pos_ctrl.lambda_M = mc_from_double(JL_K * lam_M);
    cfg->k_surface_per_s = mc_from_double(k);
    cfg->v_k_i_V_per_A = mc_from_double(L * (k - fv / J));
    cfg->v_k_w_V_s = mc_from_double((L / K) * (k - fv / J) * fv);

    /* drive */
    cfg->n_p = np;
    cfg->fs_hz = tc->fs_hz;
    cfg->R_ohm = mc_from_double(R);
    cfg->L_H = mc_from_double(L);
    cfg->npL_ohm_s = mc_from_double(np * L);
    cfg->K_V_s = mc_from_double(K);
    cfg->J_over_K_A_s2 = mc_from_double(J / K);
    cfg->fv_over_K_A_s = mc_from_double(fv / K);
    cfg->LJ_over_KTs_V_s2 = mc_from_double(L * J / (K * Ts));
    cfg->Lfv_over_KTs_V_s = mc_from_double(L * fv / (K * Ts));
    cfg->v_max_V = mc_from_double(in->v_max_V);
    cfg->i_max_A = mc_from_double(in->i_max_A);
    cfg->i_trip_A = mc_from_double(in->i_trip_A);
    cfg->omega_lim_rad_s = mc_from_double(in->omega_lim_rad_s);
    cfg->blend_decay = mc_from_double(exp(-Ts / pick(ov->blend_tau_s, 2e-3)));
    cfg->i_f_ref_A = mc_from_double(0.0);
    /* current-reference relaxation after the open-to-closed switch: slow
     * against the current loop (L/R = 3 ms), fast against the motion */
    const double tau_i = pick(ov->current_blend_tau_s, 10e-3);
    cfg->ref_blend_decay = mc_from_double(tau_i > 0 ? exp(-Ts / tau_i) : 0.0);
    cfg->ref_blend_L_over_tau_ohm = mc_from_double(tau_i > 0 ? L / tau_i : 0.0);
    cfg->load_ff_A_per_Nm = mc_from_double(in->load_feedforward ? 1.0 / K : 0.0);
    cfg->load_ff_max_Nm = mc_from_double(1.5 * in->bound_load_Nm);
    /* standstill R, L measurement: 25 electrical time constants of the
     * model, the last 40 % taken as steady state (from 15 tau: still
     * settled to 1e-3 if the true tau is twice the model's). The window is
     * valid while the reference stays below 10 % of omega_lim: the rotor
     * then sits on the f axis, where the back-EMF K w sin(n_p dtheta) is
     * below 0.1 % of R I_max for the rig. */
    if (in->identify_rl) {
        const int32_t n = (int32_t)ceil(25.0 * L / (R > 0.0 ? R : 1.0) / Ts);
        cfg->rl_id.window_ticks = n < 50 ? 50 : (n > 5000 ? 5000 : n);
        cfg->rl_id.steady_ticks = (cfg->rl_id.window_ticks * 2) / 5;
    }
    cfg->rl_id.R_model_ohm = mc_from_double(R);
    cfg->rl_id.L_fs_model_ohm = mc_from_double(L / Ts);
    cfg->rl_id.omega_still_rad_s = mc_from_double(0.1 * in->omega_lim_rad_s);
    cfg->open_loop.R_ohm = cfg->R_ohm;
    cfg->open_loop.npL_ohm_s = cfg->npL_ohm_s;
    cfg->open_loop.K_V_s = cfg->K_V_s;
    if (in->i_open_loop_A > in->i_max_A)
        return fail(err, err_len, "limits.i_open_loop_A", "must be <= i_max_A", in->i_open_loop_A);
    cfg->open_loop.i_max_A = mc_from_double(in->i_open_loop_A > 0.0 ? in->i_open_loop_A : in->i_max_A);
    cfg->open_loop.v_max_V = cfg->v_max_V;
    if (err && err_len > 0) err[0] = '\0';
    return true;
}
