/*
 * ekf_ipmsm.h - paper 002's extended Kalman filter, eqs. (36)-(44), for an
 * interior PMSM with a lumped disturbance torque: state x = [i_d, i_q,
 * theta_r, omega_r, M_0] (A, A, rad, rad/s, N m), input u = [u_d, u_q]
 * (V), measurement y = [i_d, i_q, theta_r] (an encoder and the currents in
 * the encoder's dq frame). What this block adds to the paper:
 *  - the Jacobian (the paper does not print it), from (37):
 *      F = [ -R/Ld      Lq p w/Ld  0  Lq p iq/Ld        0
 *            -Ld p w/Lq  -R/Lq     0  -(Ld id + psi) p/Lq 0
 *             0          0         0  1                  0
 *             k(Ld-Lq)iq k((Ld-Lq)id+psi) 0 -d/J        -1/J
 *             0          0         0  0                  0 ],  k = 3p/(2J),
 *    discretised A_d = I + Ts F at the last estimate (the paper's (38) is
 *    explicit Euler; so is its A_d);
 *  - the state prediction by Heun's method (explicit trapezoid, the input
 *    held over the sample) instead of (38)'s explicit Euler, which lags the
 *    speed by about Ts dw/dt / 2 while accelerating (0.5 mrad/s at
 *    1000 rad/s^2 and 10 kHz);
 *  - the covariance update in Joseph form, P+ = (I - KC) P- (I - KC)^T +
 *    K R K^T, then symmetrised: it stays symmetric positive definite where
 *    (42)'s short form loses it to rounding; the 3x3 innovation covariance
 *    S = C P- C^T + R is inverted through its Cholesky factor;
 *  - C = [I_3 0] (errata: printed 3x4), R = diag(r_i, r_i, r_theta);
 *  - the angle innovation wrapped into [-pi, pi) and theta_hat kept
 *    there: an encoder's angle wraps, and float32 keeps its resolution.
 * The motor (R, L_d, L_q, psi, n_p, J, f_v = d, Ts) is the drive's one
 * model (model/motor_model.h), read by const pointer at every step; the
 * config holds only the filter's own covariances and start.
 * Float: the fixed-point build compiles it but its design refuses it (the
 * covariances span more decades than Q14.17 holds: docs/paper002.md).
 */
#ifndef ESTIMATORS_EKF_IPMSM_H
#define ESTIMATORS_EKF_IPMSM_H

#include <stdbool.h>

#include "math/mc_num.h"
#include "model/motor_model.h"

#ifdef __cplusplus
extern "C" {
#endif

#define EKF_N 5 /* states */
#define EKF_M 3 /* measurements */

enum { EKF_ID = 0, EKF_IQ = 1, EKF_THETA = 2, EKF_OMEGA = 3, EKF_M0 = 4 };

typedef struct {
    mc_t q[EKF_N];                    /* Q_KF = diag(q) (39), > 0 */
    mc_t r[EKF_M];                    /* R_KF = diag(r) (41), > 0 */
    mc_t p0[EKF_N];                   /* P+(0) = diag(p0), > 0 */
    mc_t x0[EKF_N];                   /* x+(0) */
} ekf_ipmsm_config_t;

typedef struct {
    ekf_ipmsm_config_t cfg;
    mc_t x[EKF_N];                    /* the estimate (a priori after predict, a posteriori after correct) */
    mc_t P[EKF_N][EKF_N];
    mc_t innovation[EKF_M];           /* of the last correction */
    bool spd_ok;                      /* S's Cholesky factor existed at every correction (false stays false) */
} ekf_ipmsm_t;

/* Checks the configuration (every q, r, p0 > 0) and the motor m
 * (inductances, J, Ts > 0, R, psi, f_v >= 0, n_p >= 1); false leaves the
 * filter unusable. */
bool ekf_ipmsm_init(ekf_ipmsm_t *e, const ekf_ipmsm_config_t *cfg, const motor_model_t *m);

/* (40)-(44) with the measurement of this sample: the a posteriori
 * estimate. False if S lost positive definiteness: x, P and innovation
 * are then left as they were and spd_ok is cleared for good. */
bool ekf_ipmsm_correct(ekf_ipmsm_t *e, mc_t i_d_A, mc_t i_q_A, mc_t theta_rad);

/* (38)-(39): the a priori estimate of the next sample, the voltages u_d,
 * u_q held over it. */
void ekf_ipmsm_predict(ekf_ipmsm_t *e, const motor_model_t *m, mc_t u_d_V, mc_t u_q_V);

/* The model's acceleration dw/dt at the estimate, from (37)'s fourth row
 * (SOSMC needs it: the speed's derivative is not measured, errata). */
mc_t ekf_ipmsm_accel(const ekf_ipmsm_t *e, const motor_model_t *m);

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_EKF_IPMSM_H */
