/*
 * ibcc.h - paper 002's inversion-based current control, eq. (9), with the
 * cross-coupling terms of (3) the paper's (9) leaves out (errata):
 *   u_d = L_d (di_dd/dt + lambda (i_dd - i_d)) + R i_d - L_q p w_hat i_q
 *   u_q = L_q (di_qd/dt + lambda (i_qd - i_q)) + R i_q + L_d p w_hat i_d + psi p w_hat
 * with w_hat the EKF's speed (the back-EMF compensation of (9)), and the
 * result limited to the voltage the bus gives (|u| <= u_max, the direction
 * kept). The error dynamics are d(i_d - i)/dt = -lambda (i_d - i) (8):
 * lambda Ts must stay well below 1 for the sampled loop (ibcc_init checks
 * lambda Ts <= IBCC_LAMBDA_TS_MAX).
 * The inversion needs the references' derivatives, which a sampled torque
 * demand does not have: the references first pass a first-order filter,
 *   i_f[k] = i_f[k-1] + ref_alpha (i_ref[k] - i_f[k-1]),
 * and (9) runs on i_f with di_f/dt its change over the sample, so a noisy
 * or stepping demand moves the voltage by L ref_alpha / Ts per ampere, not
 * L / Ts (ref_alpha = 1: no filter, the raw reference's backward
 * difference; a deadbeat feed-forward that turns the speed loop's noise
 * into volts of chattering, measured in docs/paper002.md).
 * The motor (R, L_d, L_q, psi, n_p, fs) is the drive's one model
 * (model/motor_model.h), read by const pointer.
 */
#ifndef CONTROL_IBCC_H
#define CONTROL_IBCC_H

#include <stdbool.h>

#include "math/mc_num.h"
#include "model/motor_model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* lambda Ts at most 0.5: the sampled first-order loop with a sample of
 * computation delay is well damped below it (poles of z^2 - z + lambda Ts
 * inside 0.71 of the unit circle). */
#define IBCC_LAMBDA_TS_MAX MC_C(0.5)

typedef struct {
    mc_t lambda_per_s;   /* the current error's decay rate (8) */
    mc_t ref_alpha;      /* the reference filter's gain per sample, (0, 1] */
} ibcc_config_t;

typedef struct {
    mc_t i_dd_prev_A, i_qd_prev_A;   /* the filtered references i_f */
    bool first;
    bool saturated;      /* the last step was limited */
} ibcc_t;

/* The step's output: the dq voltages (one pointer, so that the state, the
 * config, the motor and the output pass in the four argument registers). */
typedef struct {
    mc_t u_d_V, u_q_V;
} ibcc_out_t;

bool ibcc_init(ibcc_t *s, const ibcc_config_t *c, const motor_model_t *m);

/* The dq voltages for the references i_dd, i_qd, the measured (or
 * estimated) currents i_d, i_q and the estimated speed, limited to
 * |u| <= u_max_V. */
void ibcc_step(ibcc_t *s, const ibcc_config_t *c, const motor_model_t *m, mc_t i_dd_A, mc_t i_qd_A, mc_t i_d_A,
               mc_t i_q_A, mc_t w_hat_rad_s, mc_t u_max_V, ibcc_out_t *out);

#ifdef __cplusplus
}
#endif

#endif /* CONTROL_IBCC_H */
