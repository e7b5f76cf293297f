/*
 * sosmc.h - paper 002's asymptotic second-order sliding mode speed control
 * (SOSMC), eqs. (19)-(28): the motion equation (7) extended by an
 * integrator at the input, the integral sliding surface
 *   s = dw~/dt + alpha_0 w~ + alpha_I int w~,   w~ = w_d - w,
 * and the torque demand in the implemented form (27)-(28),
 *   M = J (dw_d/dt + alpha_0 w~) + d w + M0_hat
 *       + int [ J alpha_I w~ + J eta tanh(s/eps) ] dt,
 * with the switching gain scaled by J in (28) as in (25)-(26) (errata:
 * (28) drops the J; eta is then in rad/s^3 everywhere). dw~/dt needs the
 * speed's derivative, which is not measured: the EKF's model acceleration
 * serves (errata). M0_hat is added only with disturbance compensation on.
 * The integrals (of (28) and of w~ in s) are explicit Euler; both stop
 * while the torque is at its limit and (28)'s integrand pushes it further
 * (anti-windup by clamping, on either side). J, d (f_v) and Ts are the
 * drive's one motor model (model/motor_model.h), read by const pointer.
 */
#ifndef CONTROL_SOSMC_H
#define CONTROL_SOSMC_H

#include <stdbool.h>

#include "math/mc_num.h"
#include "model/motor_model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    mc_t alpha_0, alpha_I;   /* [1/s], [1/s^2] */
    mc_t eta;                /* switching gain [rad/s^3] */
    mc_t eps;                /* boundary layer of tanh [rad/s^2] */
    mc_t M_max_Nm;           /* torque limit (the anti-windup's) */
    bool compensate;         /* add M0_hat (DC) */
} sosmc_config_t;

typedef struct {
    mc_t int_err;            /* int w~ dt [rad] */
    mc_t int_torque;         /* the integral of (28) [N m] */
    mc_t s;                  /* the sliding variable of the last step */
    bool limited;
} sosmc_t;

bool sosmc_init(sosmc_t *c, const sosmc_config_t *cfg, const motor_model_t *m);

/* The torque demand; w_hat, a_hat the estimated speed and acceleration,
 * M0_hat the disturbance estimate. */
mc_t sosmc_step(sosmc_t *c, const sosmc_config_t *cfg, const motor_model_t *m, mc_t w_d, mc_t dw_d, mc_t w_hat,
                mc_t a_hat, mc_t M0_hat);

/* tanh, odd, saturating to +-1 (shared with htsmc.h). */
mc_t smc_tanh(mc_t x);

#ifdef __cplusplus
}
#endif

#endif /* CONTROL_SOSMC_H */
