/*
 * delay_comp.h - computation-delay compensation, one block for every drive.
 *
 * A drive computes its voltage from the currents sampled at t_k; the power
 * stage applies it d samples later (d in [0, 1]: a dSpace card writes its
 * DACs as soon as the computation ends, d ~ 0; an MCU's PWM takes a new
 * duty a whole period later, d = 1). The command v[k] then acts over
 * [t_k + d Ts, t_k+1 + d Ts) and v[k-1] holds before. Not in the papers
 * (their rigs have d ~ 0); the three parts below are what each drive needs
 * to keep its equations true with a delay:
 *
 *   delay_applied_mean    the voltage really applied over [t_k, t_k+1):
 *                         (1 - d) v[k] + d v[k-1], for the observers
 *                         (paper 000 eq. (25), paper 001 eq. (5), paper
 *                         002's EKF prediction);
 *   delay_rot_fraction    a rotation by a fraction x of a given one, for
 *                         the output frame at the middle of the interval
 *                         the voltage acts over (paper 000's (f-g) frame,
 *                         eq. (7) inverse);
 *   delay_output_lead_s   the time from the sample to the middle of the
 *                         interval the voltage acts over, (1/2 + d) Ts: the
 *                         output angle's lead (a rotor-frame drive turns
 *                         its voltage at the angle of that instant);
 *   delay_predict_fg      the measured currents predicted to t_k + d Ts,
 *                         where the command starts to act, with the model
 *                         L di/dt = v - R i + e (paper 000 eq. (23),
 *                         errata (9a)), one Euler step of d Ts.
 *
 * Pure functions of their arguments: no state, nothing allocates. Each
 * takes the delay as a number of samples d and works in both numeric
 * builds (mc_num.h); the fixed-point scaling and overflow of each is stated
 * where it is defined.
 */
#ifndef CONTROL_DELAY_COMP_H
#define CONTROL_DELAY_COMP_H

#include "adapter/phase_adapter.h"
#include "math/frame_fg.h"
#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The mean over the sample [t_k, t_k+1) of the voltage the motor sees:
 * v[k-1] for d Ts, then v[k] for (1 - d) Ts,
 *   v_mean = v + d (v_prev - v) = (1 - d) v + d v_prev.
 * Fixed point: Q14.17 volts; |v - v_prev| <= 2 v_max stays far inside the
 * format's +-16384 for any supply this project drives (< 100 V). */
static inline mc_ab_t delay_applied_mean(mc_t d_samples, mc_ab_t v, mc_ab_t v_prev)
{
    mc_ab_t m;
    m.alpha = mc_mac(v.alpha, d_samples, mc_sub(v_prev.alpha, v.alpha));
    m.beta = mc_mac(v.beta, d_samples, mc_sub(v_prev.beta, v.beta));
    return m;
}

/* R(x phi) for x in [0, 1] from r = R(phi) without a sincos:
 * sin(x phi) ~ x sin(phi), cos(x phi) ~ 1 - x^2 (1 - cos(phi)), x2 = x^2
 * given by the caller (a design constant). Exact at x = 0 and x = 1; in
 * between the angle is off by at most x (1 - x^2) phi^3 / 6 <= 0.064 phi^3
 * and the norm by x^2 (1 - x^2) phi^4 / 24: 8e-6 rad electrical (one
 * Q14.17 LSB) at phi = 0.05 rad, paper 000's 20 rad/s at n_p = 50 and
 * 10 kHz. Fixed point: every term is in [-1, 1]; no overflow. */
static inline mc_rot_t delay_rot_fraction(mc_rot_t r, mc_t x, mc_t x2)
{
    mc_rot_t f;
    f.s = mc_mul(x, r.s);
    f.c = mc_sub(MC_ONE, mc_mul(x2, mc_sub(MC_ONE, r.c)));
    return f;
}

/* (1/2 + d) Ts [s]: the middle of [t_k + d Ts, t_k+1 + d Ts) after t_k.
 * Fixed point: Ts and the result are far inside Q14.17 (3 LSB-level
 * rounding of 1.5e-4 s is 5e-5 relative). */
static inline mc_t delay_output_lead_s(mc_t d_samples, mc_t ts_s)
{
    return mc_mul(ts_s, mc_add(MC_C(0.5), d_samples));
}

/* The currents (i_f, i_g) of t_k predicted to t_k + d Ts in the same frame,
 * paper 000 eq. (23) (errata (9a)) by one Euler step,
 *   i(t_k + d Ts) = i + (d Ts / L) (v_prev + e - R i),
 * with the voltage v_prev that holds until then and the back-EMF e as a
 * voltage (L d-hat, eq. (28)). The caller turns the result by the frame's
 * own rotation over d Ts (the A_fg term of (23)). ts_over_L = Ts / L
 * [A/(V sample)]. Fixed point: Q14.17; d Ts / L is below 1 for any motor
 * whose L exceeds one sample's Ts (L >= 100 uH at 10 kHz), and
 * |v_prev + e - R i| stays below a few times the supply. */
static inline void delay_predict_fg(mc_t d_samples, mc_t ts_over_L, mc_t R_ohm, mc_t i_f_A, mc_t i_g_A,
                                    mc_t v_f_prev_V, mc_t v_g_prev_V, mc_t e_f_V, mc_t e_g_V,
                                    mc_t *i_f_pred_A, mc_t *i_g_pred_A)
{
    const mc_t a = mc_mul(d_samples, ts_over_L);
    const mc_t uf = mc_cross2(MC_ONE, mc_add(v_f_prev_V, e_f_V), R_ohm, i_f_A);
    const mc_t ug = mc_cross2(MC_ONE, mc_add(v_g_prev_V, e_g_V), R_ohm, i_g_A);
    *i_f_pred_A = mc_mac(i_f_A, a, uf);
    *i_g_pred_A = mc_mac(i_g_A, a, ug);
}

#ifdef __cplusplus
}
#endif

#endif /* CONTROL_DELAY_COMP_H */
