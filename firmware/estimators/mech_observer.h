/*
 * mech_observer.h - super-twisting observer on the mechanical equation,
 * paper 000 eqs. (33)-(37): acceleration and load torque.
 *
 *   J dw/dt = K i_q_est - f_v w + tau,   tau = -C_r (unknown, slowly varying)
 * with i_q_est = -i_f sin(n_p dtheta_est) + i_g cos(n_p dtheta_est) (errata
 * sign of (9c)/(33)), the measurement y = w_est of eq. (32), and the
 * observer (35): w-hat' = (K i_q - f_v w-hat + tau-hat)/J + lambda|e|^(1/2)sgn(e) + l e,
 * tau-hat' = J alpha sgn(e), e = y - w-hat. The load state is kept as a
 * torque [N m] (J d_w of the paper) so that it stays in range in fixed point.
 * Outputs: acceleration (model of (33) at the estimates) and load torque C_r.
 */
#ifndef OBSERVERS_MECH_OBSERVER_H
#define OBSERVERS_MECH_OBSERVER_H

#include "math/mc_num.h"
#include "model/motor_model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Gains; K, f_v and J come from the shared model (model/motor_model.h). */
typedef struct {
    mc_t lambda_ts;        /* lambda_w Ts [(rad/s)^(1/2)] */
    mc_t l_ts;             /* l_w Ts [-] */
    mc_t alpha_Nm;         /* J alpha_w Ts: load step per sample [N m] */
    mc_t tau_max_Nm;       /* clamp of the load estimate */
} mech_observer_config_t;

typedef struct {
    mech_observer_config_t cfg;
    mc_t omega_hat_rad_s;  /* state, propagated to the next sample */
    mc_t tau_hat_Nm;       /* -C_r estimate */
    mc_t omega_est_rad_s;  /* filtered speed at this sample (w-hat after the correction) */
    mc_t accel_est_rad_s2;
    mc_t load_est_Nm;      /* C_r estimate (load plus Coulomb friction) */
} mech_observer_t;

void mech_observer_init(mech_observer_t *m, const mech_observer_config_t *cfg);
void mech_observer_reset(mech_observer_t *m, mc_t omega_rad_s);

/* One sample: y = velocity estimate [rad/s], i_q = torque-producing current [A]. */
void mech_observer_step(mech_observer_t *m, const motor_model_t *model, mc_t omega_meas_rad_s, mc_t i_q_A);

#ifdef __cplusplus
}
#endif

#endif /* OBSERVERS_MECH_OBSERVER_H */
