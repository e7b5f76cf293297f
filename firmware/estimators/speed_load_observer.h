/*
 * speed_load_observer.h - the I&I speed and load-torque observer of paper
 * 001, eqs. (15)-(16):
 *   xi' = A33 xi + [a2/J - n_p a1^2; n_p a1 a2] A(rho_b/rho_a)
 *                + [(n_p Phi/J) i^T Jm rho_hat; 0],                    (15)
 *   [w_hat; tau_hat] = xi + [a1; -a2] A(rho_b/rho_a),
 *   A33 = [-n_p a1, -1/J; n_p a2, 0],                                  (16)
 * with A the unwrap operator (angle_unwrap.h) and Jm the 90-degree rotation.
 *
 * Implemented in the estimates themselves rather than in xi: substituting
 * xi = [w_hat - a1 y; tau_hat + a2 y] (y = A's output) into (15), every
 * term in y cancels and, with y' = n_p w + (the part of y the estimate
 * does not explain),
 *   w_hat'   = (T_e - tau_hat)/J + a1 (y' - n_p w_hat),
 *   tau_hat' = -a2 (y' - n_p w_hat),
 * algebraically the same observer (its error dynamics are A33's, section
 * 4.3), but free of the unbounded y: in (15) as printed xi1 and a1 y both
 * grow like a1 n_p w t and cancel in w_hat, which in float32 loses a digit
 * every 10 s at 120 rpm and in Q14.17 overflows after a few minutes.
 * Per sample (explicit Euler), with dy the unwrapped change of A over the
 * sample and the innovation expressed as a speed, nu = dy fs/n_p - w_hat:
 *   w_hat   += (Ts/J)(T_e - tau_hat) + (a1 n_p Ts) nu,
 *   tau_hat -= (a2 n_p Ts) nu.
 * T_e = K_t i^T Jm rho_hat = K_t (rho_a i_b - rho_b i_a): the torque of
 * the alpha-beta model; K_t = n_p Phi for two phases (paper 001's (3)),
 * (3/2) n_p Phi for three phases in amplitude-invariant Clarke.
 *
 * Fixed point: every coefficient lies in [1e-3, 1e4] for both motors of
 * the repository (the design checks it); nu is a speed in rad/s.
 */
#ifndef ESTIMATORS_SPEED_LOAD_OBSERVER_H
#define ESTIMATORS_SPEED_LOAD_OBSERVER_H

#include "adapter/phase_adapter.h"
#include "estimators/angle_unwrap.h"
#include "math/frame_fg.h"
#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    mc_t ts_kt_over_J;   /* Ts K_t / J [rad/s per A over a sample] */
    mc_t ts_over_J;      /* Ts / J [rad/s per N m over a sample] */
    mc_t fs_over_np;     /* fs / n_p: unwrapped electrical change per sample -> rad/s */
    mc_t k_omega;        /* a1 n_p Ts of (15) */
    mc_t k_load_Nm_s;    /* a2 n_p Ts of (15) [N m per rad/s] */
} speed_load_observer_config_t;

typedef struct {
    speed_load_observer_config_t cfg;
    angle_unwrap_t unwrap;  /* A of Appendix A on rho_hat */
    mc_t omega_rad_s;       /* w_hat, mechanical */
    mc_t load_Nm;           /* tau_hat */
    mc_t i_q_A;             /* rho_a i_b - rho_b i_a of the last sample (T_e / K_t) */
} speed_load_observer_t;

/* Starts at w_hat = omega0, tau_hat = load0, A at the angle of rho0. */
void speed_load_observer_init(speed_load_observer_t *o, const speed_load_observer_config_t *cfg, mc_rot_t rho0,
                              mc_t omega0_rad_s, mc_t load0_Nm);

/* One sample of (15): rho is the unit vector of the flux observer, i the
 * alpha-beta current of this sample. */
void speed_load_observer_step(speed_load_observer_t *o, mc_rot_t rho, mc_ab_t i_A);

/* The same with i^T Jm rho = rho_a i_b - rho_b i_a already formed by the
 * caller (the q current of the dq rotation by rho, mc_rot_fwd's second
 * output: the same expression, so the same value). */
void speed_load_observer_step_iq(speed_load_observer_t *o, mc_rot_t rho, mc_t i_q_A);

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_SPEED_LOAD_OBSERVER_H */
