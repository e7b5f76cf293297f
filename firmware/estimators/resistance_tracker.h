/*
 * resistance_tracker.h - the stator resistance tracked on line from the
 * voltage balance along the estimated q axis, for the flux observer of
 * paper 001 (estimators/flux_observer.h), whose angle at low speed hangs
 * on the R i it subtracts (issue 30: parameter tracking).
 *
 * Why: in the observer's rotating frame a model error dR = R_hat - R
 * drifts the flux estimate by -dR i per second; the gradient term of
 * (12) holds only the radial part, and the rotation turns the rest into
 * an angle error of about 2 gamma Phi^2 dR i_q / (omega_e^2 Phi) (paper
 * 001's motor at 50 rpm under 1 N m: 18 times dR i_q / (omega_e Phi)).
 * A warm winding is such a dR, and so is a dead-time compensation that
 * is off by a few per cent: its error voltage has a fundamental along the
 * current, which the observer cannot tell from a resistance.
 *
 * What is observable where: the voltage equation along the q axis, in
 * the estimated frame, over one sample (paper 001 (1)-(2)),
 *     v_q = R i_q + L di_q/dt + omega_e L i_d + omega_e Phi,
 * gives with the tracked R_hat, Phi_hat the residual
 *     e_q = v_q - R_hat i_q - L di_q/dt - omega_e L i_d - omega_e Phi_hat
 *         = -dR i_q - omega_e dPhi - (voltage errors along q),
 * dR = R_hat - R, dPhi = Phi_hat - Phi. An angle error delta enters only
 * as omega_e Phi (1 - cos delta), second order; and at standstill the
 * current is along the estimated q axis whatever the angle, so e_q =
 * -dR i_q still. So R is observable where |i_q| is large (standstill
 * included), Phi where |omega_e| is large, and at one operating point
 * only their sum: the benchmark's holds at several speeds and loads
 * separate them. This block drives e_q to zero with a normalised
 * gradient (the regressors (i_q, omega_e), each parameter relative to its
 * start, time constant tau_R):
 *     dR_hat/dt   = R0^2 e_q i_q / (tau_R m^2),
 *     dPhi_hat/dt = Phi0 e_q K_e w_hat / (tau_R m^2),
 *     m^2 = max((R0 i_q)^2 + (K_e w_hat)^2, (R0 i_gate)^2),
 * i.e. each parameter corrects its share of e_q, the share of its own
 * voltage (the resistive drop, the back-EMF) in m^2. The estimates so
 * absorb the voltage errors along the current (dead time): they are the
 * resistance and the flux that make the flux model consistent, which is
 * what the observer's angle needs. Nulling e_q with the observer's radius
 * target at Phi_hat also nulls the gradient term's steady pull, which is
 * what turns into an angle error. Below R0 i_gate of voltage (no load,
 * near standstill) the steps shrink: the residual is then noise.
 *
 * The frame: q_hat of the middle of the sample, J (u[k-1] + u[k])/2 with
 * u the observer's unit vector; the current as the sample's trapezoid
 * mean and L di/dt as (L/Ts)(i[k] - i[k-1]) (in alpha-beta: its q
 * projection holds omega_e L i_d), as the observer integrates. The
 * back-EMF term is Phi_hat/Ts times the sine of the observer's own angle
 * step, u[k-1] x u[k]: the rate at which the observer's angle turns, not
 * the I&I speed, whose error after a load step (K_e (w_hat - w), half a
 * volt on paper 001's motor) would be read as a resistance. The I&I
 * speed only weighs the regressor (m^2, the Phi share), where its error
 * changes the step's size, not its sign.
 *
 * Fixed point: the increments (at most e_clamp R0^2 / (R0 i_gate) [Ohm]
 * and e_clamp / (R0 i_gate) relative) are accumulated unscaled, R_hat =
 * R0 + acc_R / n_tau and Phi_hat/Phi0 = 1 + acc_Phi / n_tau: a per-sample
 * gain Ts/tau_R (about 1e-4) would be below Q14.17's useful range.
 * |acc| <= n_tau dR_max and n_tau dPhi_rel_max (the design keeps both
 * below 16000). The angle step u[k-1] x u[k] resolves 7.6e-6 rad, 0.013 V
 * of back-EMF on paper 001's motor per sample; it telescopes over the
 * samples, so the accumulated error stays that of one sample.
 */
#ifndef ESTIMATORS_RESISTANCE_TRACKER_H
#define ESTIMATORS_RESISTANCE_TRACKER_H

#include <stdbool.h>
#include <stdint.h>

#include "adapter/phase_adapter.h"
#include "math/frame_fg.h"
#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    bool enabled;          /* false: R_hat = R0, Phi_hat = Phi0 (the block is not run) */
    mc_t R0_ohm;           /* the start: the model's (or the commissioning's) R */
    mc_t L_fs_ohm;         /* L/Ts: L di/dt over a sample as (L/Ts)(i[k] - i[k-1]) */
    mc_t Phi0_fs_V;        /* Phi0/Ts: the back-EMF of an angle step of one radian per sample */
    mc_t K_e_V_s;          /* n_p Phi0: the back-EMF per mechanical rad/s (the regressor) */
    mc_t v_gate2_V2;       /* (R0 i_gate)^2, the floor of m^2 */
    mc_t e_clamp_V;        /* a sample's residual clamped to +-e_clamp */
    mc_t dR_max_ohm;       /* |R_hat - R0| <= dR_max, and R_hat >= 0 */
    mc_t dPhi_rel_max;     /* |Phi_hat/Phi0 - 1| <= dPhi_rel_max (< 1) */
    int32_t n_tau;         /* tau_R / Ts, samples */
} resistance_tracker_config_t;

typedef struct {
    resistance_tracker_config_t cfg;
    mc_t acc_R_ohm;        /* R_hat = R0 + acc_R / n_tau */
    mc_t acc_Phi;          /* Phi_hat / Phi0 = 1 + acc_Phi / n_tau */
    mc_t R_ohm;            /* R_hat */
    mc_t Phi_rel;          /* Phi_hat / Phi0 */
    mc_t e_q_V;            /* the last residual, unclamped (telemetry, tests) */
    mc_ab_t i_prev_A;      /* the current of the last sample */
    mc_rot_t u_prev;       /* the observer's unit vector of the last sample */
    bool primed;           /* i_prev_A and u_prev hold a sample */
} resistance_tracker_t;

/* R_hat = R0, Phi_hat = Phi0, nothing held. Returns false (and the block
 * disabled) for a configuration out of range. */
bool resistance_tracker_init(resistance_tracker_t *t, const resistance_tracker_config_t *cfg);

/* Forget the held sample (after a jump of the observer's angle: a
 * correction, a hand-over); the estimates are kept. */
static inline void resistance_tracker_unprime(resistance_tracker_t *t) { t->primed = false; }

/* One sample: v_V the voltage held over the last sample (what the flux
 * observer integrated), i_A and u this sample's current and the
 * observer's unit vector, omega_mech_rad_s the estimated speed (the
 * regressor's weight). adapt false: the residual is formed, the estimates
 * held (open loop, start-up). The results: t->R_ohm and t->Phi_rel. */
void resistance_tracker_step(resistance_tracker_t *t, mc_ab_t v_V, mc_ab_t i_A, mc_rot_t u, mc_t omega_mech_rad_s,
                             bool adapt);

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_RESISTANCE_TRACKER_H */
