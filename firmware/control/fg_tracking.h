/*
 * fg_tracking.h - paper 000's closed-loop position law in the (f-g) frame:
 * flatness references (38)-(39), super-twisting control of i_f (46)-(48)
 * and twisting control of the position (52)-(54), on the errors of (44) in
 * the estimated rotor frame. Maps the reference and the estimate to a
 * voltage in the (f-g) frame.
 *
 * At the open-to-closed switch (not specified by the paper) the current
 * references start at the measured estimated-frame currents and relax to
 * the flat ones with tau (fg_tracking_start, fg_tracking_relax), and the
 * super-twisting integral restarts at 0.
 */
#ifndef CONTROL_FG_TRACKING_H
#define CONTROL_FG_TRACKING_H

#include <stdbool.h>

#include "control/super_twisting.h"
#include "control/twisting.h"
#include "math/decay.h"
#include "estimators/estimate.h"
#include "math/frame_fg.h"
#include "model/motor_model.h"
#include "trajectory/trajectory.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    super_twisting_config_t cur;   /* i_f loop, eqs. (46)-(48), output in V */
    twisting_config_t pos;         /* position loop, eqs. (52)-(54), output in V */
    mc_t k_surface_per_s;          /* k of S = k xi_theta + xi_omega, eq. (52) */
    mc_t v_k_i_V_per_A;            /* L (k - f_v/J): voltage form of -(k/J - f_v/J^2) K xi_g in (54) */
    mc_t v_k_w_V_s;                /* (L/K)(k - f_v/J) f_v: same for the xi_omega term */
    mc_t i_f_ref_A;                /* flat output i_f,r (0: section 5.2) */
    mc_t load_ff_A_per_Nm;         /* 1/K to add the observed load C_r to i_g,r; 0 = paper (39) as printed */
    mc_t load_ff_max_Nm;           /* the feed-forward trusts the estimate only up to this */
    mc_t load_ff_L_over_KTs;       /* L/(K Ts): L di_g,r/dt of the fed-forward load's change; 0 = none */
    mc_t ref_blend_decay;          /* per-sample decay of the switch current-reference offset */
    mc_t ref_blend_L_over_tau_ohm; /* L/tau of that decay: its L di_r/dt voltage */
} fg_tracking_config_t;

typedef struct {
    fg_tracking_config_t cfg;
    super_twisting_t cur;
    twisting_t pos;
    mc_t i_f_off_A, i_g_off_A;     /* decaying current-reference offsets of the switch */
    mc_t i_f_ref_A, i_g_ref_A;     /* references of the last closed-loop step */
    mc_t load_ff_Nm;               /* the load fed forward at the last call (clamped; with load_ff_L_over_KTs only) */
} fg_tracking_t;

void fg_tracking_init(fg_tracking_t *t, const fg_tracking_config_t *cfg);

/* Entry into closed loop: integral to 0, reference offsets so that the
 * references start at the measured estimated-frame currents i_d, i_q. */
void fg_tracking_start(fg_tracking_t *t, const motor_model_t *m, mc_t i_max_A, const trajectory_point_t *ref,
                       const trajectory_point_t *ref_next, mc_t load_est_Nm, mc_t i_d_A, mc_t i_q_A);

/* Reference currents and voltages of the flat outputs, eqs. (38)-(39),
 * for the reference r at this sample and rn at the next, with the observed
 * load fed forward and the switch offsets added (and, with
 * load_ff_L_over_KTs, the fed load's L di/dt; it then remembers the load). */
void fg_tracking_references(fg_tracking_t *t, const motor_model_t *m, mc_t i_max_A, const trajectory_point_t *r,
                            const trajectory_point_t *rn, mc_t load_est_Nm, mc_t *i_fr, mc_t *i_gr, mc_t *v_fr,
                            mc_t *v_gr);

/* One closed-loop step (static inline, like CMSIS-DSP's arm_pid_f32: one
 * call site per drive, whose arguments then stay in registers). ref, ref_next: the reference at this sample and
 * the next; est: the estimate; u: U(n_p (theta_est - theta_r)) and i_d,
 * i_q the currents turned by it (44); hold_integral: the last command
 * saturated. Writes the (f-g) voltage. */
static inline void fg_tracking_step(fg_tracking_t *t, const motor_model_t *m, mc_t i_max_A, const trajectory_point_t *ref,
                      const trajectory_point_t *ref_next, const mc_estimate_t *est, mc_rot_t u, mc_t i_d_A,
                      mc_t i_q_A, bool hold_integral, mc_t *v_f_V, mc_t *v_g_V)
{
    const fg_tracking_config_t *c = &t->cfg;
    mc_t i_fr, i_gr, v_fr, v_gr;
    fg_tracking_references(t, m, i_max_A, ref, ref_next, est->load_Nm, &i_fr, &i_gr, &v_fr, &v_gr);
    t->i_f_ref_A = i_fr;
    t->i_g_ref_A = i_gr;

    const mc_t xi_theta = mc_sub(est->theta_rad, ref->theta_rad);
    const mc_t w_r = ref->omega_rad_s;
    const mc_t xi_f = mc_sub(i_d_A, i_fr);
    const mc_t xi_g = mc_sub(i_q_A, i_gr);
    /* xi_omega from the mechanical observer's speed: (32) differentiates the
     * back-EMF angle and is too noisy at low speed; (35) filters it through
     * the motor's own dynamics without lag from a separate filter */
    const mc_t xi_w = mc_sub(est->omega_rad_s, w_r);

    /* (48): v_f-bar = -L mu_1 + L u_st(xi_f), mu_1 of (45a) */
    const mc_t cross_f = mc_dot2(xi_w, mc_add(xi_g, i_gr), w_r, xi_g);
    const mc_t u_st = super_twisting_step(&t->cur, xi_f, hold_integral);
    const mc_t vb_f = mc_add(mc_cross2(m->R_ohm, xi_f, m->npL_ohm_s, cross_f), u_st);

    /* (52)-(54): S = k xi_theta + xi_omega, dS/dt from the observed acceleration */
    const mc_t S = mc_mac(xi_w, c->k_surface_per_s, xi_theta);
    const mc_t S_dot = mc_mac(mc_sub(est->accel_rad_s2, ref->accel_rad_s2), c->k_surface_per_s, xi_w);
    const mc_t w_tw = twisting_step(&t->pos, S, S_dot);
    /* (JL/K) times (54), with mu_2 of (42) after the errata:
     * v_g-bar = R xi_g + n_p L (xi_w (xi_f + i_f,r) + w_r xi_f) + K xi_w
     *           - L (k - f_v/J) xi_g + (L/K)(k - f_v/J) f_v xi_w + (JL/K) w_t */
    const mc_t cross_g = mc_dot2(xi_w, mc_add(xi_f, i_fr), w_r, xi_f);
    const mc_t vb_g = mc_add(mc_dot2(mc_sub(m->R_ohm, c->v_k_i_V_per_A), xi_g, m->npL_ohm_s, cross_g),
                             mc_mac(w_tw, mc_add(m->K_V_s, c->v_k_w_V_s), xi_w));

    /* v_dq = v_ref + v-bar, then back to (f-g): v_fg = U(xi_theta)^T v_dq */
    mc_rot_inv(u, mc_add(v_fr, vb_f), mc_add(v_gr, vb_g), v_f_V, v_g_V);
}

/* Decay of the switch offsets; every sample. */
static inline void fg_tracking_relax(fg_tracking_t *t)
{
    if (mc_ne(t->i_f_off_A, MC_ZERO) || mc_ne(t->i_g_off_A, MC_ZERO)) {
        t->i_f_off_A = mc_decay(t->i_f_off_A, t->cfg.ref_blend_decay);
        t->i_g_off_A = mc_decay(t->i_g_off_A, t->cfg.ref_blend_decay);
    }
}

#ifdef __cplusplus
}
#endif

#endif /* CONTROL_FG_TRACKING_H */
