/*
 * htsmc.h - paper 002's hybrid twisting sliding mode speed control
 * (HTSMC), eqs. (29)-(35): the sliding variable s = w~ + alpha_I int w~,
 * the equivalent control (29) M_eq = J (dw_d/dt + alpha_I w~) + d w +
 * M0_hat (M0_hat only with disturbance compensation), the torque (30)
 * M = M_eq - J nu, nu = nu_1 + nu_2 with the super-twisting part
 *   nu_2 = -lambda |s|^rho sign(s)   (|s| <= s0; |s0|^rho beyond)
 * and the twisting part
 *   dnu_1/dt = -nu            if |nu| > nu_max
 *            = -alpha_m sign(s) if s ds/dt <= 0
 *            = -alpha_M sign(s) if s ds/dt > 0
 * (35). In physical units: nu is an acceleration [rad/s^2], so the
 * normalised bound |nu| <= 1 of Levant's form becomes |nu| <= nu_max,
 * the acceleration the torque limit gives (errata: with 1 rad/s^2 it leaves
 * almost no authority). sign is replaced by tanh(s/eps) (the paper's
 * suggestion against chattering); ds/dt is the change of s over the last
 * sample; nu_1 is integrated by explicit Euler. J, d (f_v) and Ts are the
 * drive's one motor model (model/motor_model.h), read by const pointer.
 */
#ifndef CONTROL_HTSMC_H
#define CONTROL_HTSMC_H

#include <stdbool.h>

#include "math/mc_num.h"
#include "model/motor_model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    mc_t alpha_I;            /* [1/s] */
    mc_t alpha_m, alpha_M;   /* twisting gains [rad/s^3], alpha_M > alpha_m */
    mc_t lambda, rho, s0;    /* super-twisting: [rad/s^(2-rho)...], 0 < rho <= 1/2, s0 [rad/s] */
    mc_t nu_max;             /* |nu| bound [rad/s^2] */
    mc_t eps;                /* boundary layer [rad/s] */
    mc_t M_max_Nm;
    bool compensate;         /* add M0_hat (DC) */
} htsmc_config_t;

typedef struct {
    mc_t int_err, nu1, s, s_prev;
    bool first;
} htsmc_t;

bool htsmc_init(htsmc_t *c, const htsmc_config_t *cfg, const motor_model_t *m);

mc_t htsmc_step(htsmc_t *c, const htsmc_config_t *cfg, const motor_model_t *m, mc_t w_d, mc_t dw_d, mc_t w_hat,
                mc_t M0_hat);

#ifdef __cplusplus
}
#endif

#endif /* CONTROL_HTSMC_H */
