/*
 * ida_pbc.h - the IDA-PBC speed controller of paper 001, eq. (11), with the
 * errata: the current it feeds back is the measured alpha-beta current
 * rotated by the estimated angle (the dq current is not measured), and a
 * feed-forward J dw_ref/dt (without it a ramp leaves an error of about
 * r J (dw_ref/dt)/(n_p Phi)^2).
 *
 * In the estimated dq frame, with the current reference of Remark 2
 *   i_q* = (tau_hat + J dw_ref/dt) / K_t,          i_d* = 0,
 * the law is
 *   v_d = (R - r) i_d - n_p L w_hat i_q*,                           (11a)
 *   v_q = (R - r) i_q + K_e w* + r i_q*,                            (11b)
 * which is (11) with tau_hat/(n_p Phi) = i_q*: (11a)'s -(L/Phi) tau_hat
 * w_hat = -n_p L w_hat i_q*, (11b)'s (r/(n_p Phi)) tau_hat = r i_q*.
 * K_e = n_p Phi is the back-EMF constant, K_t the torque constant (equal
 * for a two-phase machine, K_t = (3/2) K_e for three phases in
 * amplitude-invariant Clarke; (11) is derived for K_t = K_e, and with
 * K_t != K_e the same law assigns H_d = (K_t L |i~|^2 + K_e J w~^2)/2,
 * dH_d/dt = -K_t r |i~|^2, so the proof of section 4.1 carries over).
 * The voltage is then turned to alpha-beta by the estimated angle,
 * v_ab = (rho_a I + rho_b Jm) v (11).
 *
 * The damping r is a design choice (paper 001 gives none); the design
 * (design/paper001_design.c) derives it from the closed loop of (40):
 * L J s^2 + r J s + K_e K_t = 0.
 */
#ifndef CONTROL_IDA_PBC_H
#define CONTROL_IDA_PBC_H

#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    mc_t R_minus_r_ohm;  /* R - r */
    mc_t r_ohm;          /* damping injection r > 0 */
    mc_t npL_ohm_s;      /* n_p L [V per A rad/s] */
    mc_t Ke_V_s;         /* n_p Phi [V s/rad] */
    mc_t inv_Kt_A_Nm;    /* 1/K_t */
    mc_t J_over_Kt_A_s2; /* J/K_t: the feed-forward current per unit dw_ref/dt (J alone is
                          * below the fixed-point coefficient range on small motors) */
    mc_t i_max_A;        /* |i_q*| limit */
} ida_pbc_config_t;

typedef struct {
    mc_t i_q_ref_A;      /* i_q* of the last step */
} ida_pbc_t;

static inline void ida_pbc_init(ida_pbc_t *c) { c->i_q_ref_A = MC_ZERO; }

/* One sample of (11): i_d, i_q the measured current in the estimated frame,
 * w_hat, tau_hat the estimates, w_ref and its derivative the reference. */
static inline void ida_pbc_step(ida_pbc_t *s, const ida_pbc_config_t *c, mc_t i_d_A, mc_t i_q_A, mc_t omega_hat_rad_s,
                                mc_t load_hat_Nm, mc_t omega_ref_rad_s, mc_t accel_ref_rad_s2, mc_t *v_d_V,
                                mc_t *v_q_V)
{
    /* i_q* = tau_hat/K_t + (J/K_t) dw_ref/dt */
    const mc_t i_q_ff = mc_dot2(load_hat_Nm, c->inv_Kt_A_Nm, c->J_over_Kt_A_s2, accel_ref_rad_s2);
    const mc_t i_q_ref = mc_clamp(i_q_ff, mc_neg(c->i_max_A), c->i_max_A);
    /* (11a) */
    *v_d_V = mc_sub(mc_mul(c->R_minus_r_ohm, i_d_A), mc_mul(mc_mul(c->npL_ohm_s, omega_hat_rad_s), i_q_ref));
    /* (11b) */
    *v_q_V = mc_add(mc_dot2(c->R_minus_r_ohm, i_q_A, c->Ke_V_s, omega_ref_rad_s), mc_mul(c->r_ohm, i_q_ref));
    s->i_q_ref_A = i_q_ref;
}

#ifdef __cplusplus
}
#endif

#endif /* CONTROL_IDA_PBC_H */
