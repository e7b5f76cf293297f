/*
 * emf_observer.h - super-twisting back-EMF observer in the (f-g) frame,
 * paper 000 eqs. (23)-(28), with the linear term L_fg and the plus-signed
 * output injections (errata to (25)).
 *
 * Model (23) with the errata sign of (9a):
 *   di_f/dt =  n_p w_r i_g + (v_f - R i_f)/L + d_f,   d_f =  (K/L) w sin(n_p dtheta)
 *   di_g/dt = -n_p w_r i_f + (v_g - R i_g)/L + d_g,   d_g = -(K/L) w cos(n_p dtheta)
 * The disturbances are kept as voltages e = L*d [V] so that the same code
 * runs in fixed point. Discretisation (Ts, zero-order-hold voltages): the
 * frame rotation A_fg is applied exactly as a rotation by the change of the
 * reference electrical angle over the sample (exp(Ts A_fg)); the voltage,
 * held constant in the phase frame, is carried exactly by that rotation;
 * the back-EMF and resistive drop, constant in the (f-g) frame, enter with
 * the mid-sample rotation (two half turns in all).
 *
 * Use per sample: emf_observer_correct() with the measured (f-g) currents
 * (updates e-hat, the equivalent injections and the error), read the
 * estimates, then emf_observer_predict() with the applied voltage.
 */
#ifndef OBSERVERS_EMF_OBSERVER_H
#define OBSERVERS_EMF_OBSERVER_H

#include "math/frame_fg.h"
#include "model/motor_model.h"
#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Gains; the motor's R and L come from the shared model (model/motor_model.h). */
typedef struct {
    mc_t lambda_A;           /* lambda_{f,g} * Ts: super-twisting root term per sample [A^(1/2)] */
    mc_t l_ts;               /* l_{f,g} * Ts: linear term per sample [-] */
    mc_t alpha_V;            /* L * alpha_{f,g} * Ts: e-hat step per sample [V] */
    mc_t alpha_V_s;          /* L * alpha_{f,g}: equivalent injection amplitude [V/s] */
    mc_t lpf_coeff;          /* Ts/(tau + Ts) of the equivalent-injection filter */
    /* Discrete-time design (design/paper000_design.c, gain_design): alpha
     * follows the reference speed, alpha(|w_r|) = alpha + slope |w_r|, as
     * the bound Pi_d of section 3.1.1 does; 0: a constant alpha (the
     * continuous-time design, which takes |w|max). */
    mc_t alpha_V_per_rad_s;  /* slope of alpha_V [V per sample per rad/s] */
    mc_t alpha_V_s_per_rad_s;/* slope of alpha_V_s [V/s per rad/s] */
} emf_observer_config_t;

typedef struct {
    emf_observer_config_t cfg;
    mc_t i_f_hat_A, i_g_hat_A; /* current estimates in the frame of this sample */
    mc_t e_f_hat_V, e_g_hat_V; /* L*d_f, L*d_g estimates, eq. (28a)-(28b) */
    mc_t z_f_V_s, z_g_V_s;     /* filtered equivalent injections L*alpha*sgn_eq(eps), (28c)-(28d) */
    mc_t err_f_A, err_g_A;     /* eps_f, eps_g of the last correction */
    mc_t alpha_V_now, alpha_V_s_now; /* alpha_V, alpha_V_s at the reference speed of this sample */
} emf_observer_t;

/* The injection amplitude for the reference speed |w_r| of this sample
 * (before emf_observer_correct); a no-op with the constant alpha. */
static inline void emf_observer_schedule(emf_observer_t *o, mc_t speed_abs_rad_s)
{
    if (mc_ne(o->cfg.alpha_V_per_rad_s, MC_ZERO)) {
        o->alpha_V_now = mc_mac(o->cfg.alpha_V, o->cfg.alpha_V_per_rad_s, speed_abs_rad_s);
        o->alpha_V_s_now = mc_mac(o->cfg.alpha_V_s, o->cfg.alpha_V_s_per_rad_s, speed_abs_rad_s);
    }
}

void emf_observer_init(emf_observer_t *o, const emf_observer_config_t *cfg);

/* Restarts the estimates (currents at the measured values, back-EMF at 0). */
void emf_observer_reset(emf_observer_t *o, mc_t i_f_A, mc_t i_g_A);

/* Output injection of eqs. (25)-(26): eps = i - i_hat; e_hat += alpha sgn(eps). */
void emf_observer_correct(emf_observer_t *o, mc_t i_f_A, mc_t i_g_A);

/* Propagates i_hat to the next sample's frame.
 *   v_f_V, v_g_V : the voltage applied over the sample, expressed in the
 *                  mid-sample frame (U(n_p (theta_r[k] + theta_r[k+1])/2) v_ab);
 *   i_f_A, i_g_A : measured currents of this sample (resistive drop);
 *   half         : rotation by half the change of n_p theta_r over the sample;
 *   m            : the motor model (R, Ts/L). */
void emf_observer_predict(emf_observer_t *o, const motor_model_t *m, mc_t v_f_V, mc_t v_g_V, mc_t i_f_A, mc_t i_g_A,
                          mc_rot_t half);

#ifdef __cplusplus
}
#endif

#endif /* OBSERVERS_EMF_OBSERVER_H */
