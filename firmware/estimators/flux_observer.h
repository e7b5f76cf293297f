/*
 * flux_observer.h - the gradient flux (position) observer of paper 001,
 * eqs. (12)-(14) (Ortega et al. 2011, the observer VESC and ODrive ship):
 *   d lambda_hat/dt = v - R i + gamma eta (Phi^2 - |eta|^2),      (12)
 *   rho_hat = eta / Phi,                                          (13)
 *   eta = lambda_hat - L i,                                       (14)
 * in the stator (alpha-beta) frame; rho_hat estimates [cos; sin] of the
 * electrical angle. It needs only the alpha-beta model L di/dt = v - R i -
 * e, which a 2-phase stepper (a = alpha, b = beta) and a 3-phase PMSM
 * (after Clarke) share, so it runs on both.
 *
 * Discrete form, per sample, fixed-point friendly: the state is the flux
 * divided by Ts, w = lambda_hat / Ts [V] (a volt-sample), so that the
 * integration of (12) over one sample adds volts with coefficients near 1:
 *   w[k] = w[k-1] + v[k-1] - R (i[k-1] + i[k])/2 + gPhi3 rho(1 - |rho|^2),
 * where v[k-1] is the voltage held over the last sample (exact: the
 * inverter holds it), the resistive drop is integrated by the trapezoid
 * rule, and the gradient term of (12), gamma eta (Phi^2 - |eta|^2) with
 * eta = Phi rho, is gamma Phi^3 rho (1 - |rho|^2) = gPhi3 rho (1 - |rho|^2),
 * taken at the start of the sample (explicit Euler; its radial rate
 * 2 gamma Phi^2 Ts must stay below 1, which the design checks). Then
 *   rho[k] = (w[k] - (L/Ts) i[k]) / (Phi/Ts),
 * computed as a multiplication by 2^-s then by 2^s Ts/Phi in (1, 2], so
 * the fixed-point coefficient keeps 17 significant bits (Ts/Phi itself,
 * 6e-4 for paper 001's motor, would keep only 7).
 *
 * Fixed point: w is at most (Phi + L i_max)/Ts, 2100 V for paper 001's
 * motor and 360 V for paper 000's stepper, well inside Q14.17; v and R i
 * are volts. The unit vector (rho/|rho|) is what the controllers use
 * ("unit-vector position estimate"); |rho|^2 is kept for the supervisor.
 */
#ifndef ESTIMATORS_FLUX_OBSERVER_H
#define ESTIMATORS_FLUX_OBSERVER_H

#include <stdbool.h>

#include "adapter/phase_adapter.h"
#include "math/frame_fg.h"
#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    mc_t R_ohm;          /* R of (12) */
    mc_t L_fs_ohm;       /* L/Ts of (14) in w units */
    mc_t Phi_fs_V;       /* Phi/Ts: |eta| in w units (for the initial state) */
    mc_t rho_pre;        /* 2^-s, exact */
    mc_t rho_gain;       /* 2^s Ts/Phi, in (1, 2] (s = floor(log2(Phi/Ts)) + 1) */
    mc_t gPhi3_V;        /* gamma Phi^3 of (12) [V] */
} flux_observer_config_t;

typedef struct {
    flux_observer_config_t cfg;
    mc_ab_t w_V;         /* lambda_hat / Ts */
    mc_ab_t i_prev_A;    /* current of the last sample */
    mc_ab_t v_prev_V;    /* voltage held over the last sample */
    mc_ab_t rho;         /* rho_hat of (13), not normalised */
    mc_t rho2;           /* |rho_hat|^2 */
    mc_rot_t unit;       /* rho_hat/|rho_hat|: (cos, sin) of the estimated electrical angle */
    bool gradient_on;    /* false: (12) without its gradient term, a pure flux integrator */
    mc_t rho2_target;    /* |eta|^2 / Phi^2 the gradient term pulls to: 1 (12), or the
                          * active flux's of a salient motor (flux_observer_set_target) */
} flux_observer_t;

/* lambda_hat(0) = L i0 + Phi (cos, sin)(angle0) (errata: a unit rho_hat(0)). */
void flux_observer_init(flux_observer_t *o, const flux_observer_config_t *cfg, mc_rot_t angle0, mc_ab_t i0_A);

/* Sets the estimate to a rotor angle known from elsewhere (the HF
 * injection's, paper002_drive.h), at the radius |eta| = radius Phi:
 * lambda_hat = L i + radius Phi (cos, sin)(angle), (14) solved for it.
 * For the active flux of a salient motor radius is psi + (L_d - L_q)
 * i_d over psi, the target's square root: seeded at Phi instead, the
 * estimate starts (L_d - L_q) i_d off radially, an offset fixed in the
 * stator frame that the gradient removes only at half its radial rate
 * while the rotation turns it into an angle error at the electrical
 * frequency (measured: 0.2 rad electrical at the handover of
 * ipmsm_hfi_handover_hw.toml, i_d = -1.5 A). The configuration, the
 * target, the held voltage and the gradient's switch are kept.
 * Fixed point: radius is near 1 (the active flux within its bounds). */
void flux_observer_seed(flux_observer_t *o, mc_rot_t angle, mc_ab_t i_A, mc_t radius);

/* One sample: integrates (12) over the last sample with the voltage given
 * to flux_observer_hold() then, and evaluates (13)-(14) with i[k]. */
void flux_observer_step(flux_observer_t *o, mc_ab_t i_A);

/* Turns the gradient term of (12) on or off (off: lambda_hat - lambda stays
 * constant, which startup/flux_circle_fit.h measures). */
static inline void flux_observer_set_gradient(flux_observer_t *o, bool on) { o->gradient_on = on; }

/* The radius the gradient term pulls |eta| to, as (radius/Phi)^2 (1 at
 * init: (12)). For a salient motor observed on the active flux (L = L_q
 * in (14)), |eta| = psi + (L_d - L_q) i_d (Boldea's active flux): the
 * gradient of (12) with the fixed Phi would push the estimate radially
 * by (L_d - L_q) i_d, an offset that the rotation then turns into an
 * angle error (paper002_drive.h). */
static inline void flux_observer_set_target(flux_observer_t *o, mc_t rho2_target) { o->rho2_target = rho2_target; }

/* lambda_hat -= Phi c (c in units of Phi, the circle fit's centre), and
 * rho_hat re-evaluated with the current of the last step. */
void flux_observer_shift(flux_observer_t *o, mc_ab_t c);

/* The R of (12) from the next sample on (a tracked R: estimators/resistance_tracker.h). */
static inline void flux_observer_set_R(flux_observer_t *o, mc_t R_ohm) { o->cfg.R_ohm = R_ohm; }

/* The L/Ts of (14) from this sample on (L_fs_ohm in w units: L/Ts), a
 * saturating iron's secant inductance (model/iron_model.h); lambda_hat is
 * kept, eta and rho follow at the next step. */
static inline void flux_observer_set_L(flux_observer_t *o, mc_t L_fs_ohm) { o->cfg.L_fs_ohm = L_fs_ohm; }

/* The voltage that will be held over the coming sample. */
static inline void flux_observer_hold(flux_observer_t *o, mc_ab_t v_V) { o->v_prev_V = v_V; }

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_FLUX_OBSERVER_H */
