/*
 * encoder_observer.h - angle, speed, acceleration and load torque from a
 * position sensor's angle and the motor's torque: the Luenberger load
 * observer of the mechanical model
 *
 *   d theta / dt = omega,   J d omega / dt = T_e - T_L,   d T_L / dt = 0,
 *
 * (the mechanical model of paper 001 eq. (1) and paper 000 eq. (3) with the
 * load constant over the observer's horizon), corrected by the angle error
 * eps = wrap(theta_meas - theta_hat):
 *
 *   theta_hat' = omega_hat + l1 eps
 *   omega_hat' = (T_e - T_L_hat) / J + l2 eps
 *   T_L_hat'   = -l3 eps
 *
 * The error dynamics have the characteristic polynomial
 * s^3 + l1 s^2 + l2 s + l3 / J; the design places its poles
 * (design/sensored_foc_design.h). Forward
 * Euler at Ts; the sensor's angle is wrapped (any range), the estimate is
 * unwrapped (turns counted as the wrapped estimate crosses +-pi). Used by the sensored FOC
 * drive; the encoder is the drive's reference for the sensorless ones.
 *
 * Fixed point: Q14.17. The angle is integrated wrapped and scaled by
 * 2^ENC_OBS_SHIFT: an increment w Ts of one Q14.17 LSB (7.6e-6 rad) would
 * quantise the speed to 0.076 rad/s at 10 kHz and bias it by up to half
 * that; scaled, the increment's step is 7.4e-9 rad (7.4e-5 rad/s), and the
 * scaled wrapped angle, at most pi 2^10 = 3217, stays within the format.
 * The unwrapped output holds +-16384 rad (2600 turns);
 * l3 Ts eps is the load's increment per sample (J w_o^2 w_L Ts = 3.7 N m/rad
 * for 50 and 5 Hz and J = 0.012 kg m^2: 3.7e-4 N m for a 1e-4 rad error,
 * about 50 LSB).
 */
#ifndef ESTIMATORS_ENCODER_OBSERVER_H
#define ESTIMATORS_ENCODER_OBSERVER_H

#include <stdbool.h>

#include "estimators/estimate.h"
#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The angle's scale (a power of two: exact in both builds). */
#define ENC_OBS_SHIFT 10
#define ENC_OBS_SCALE MC_C(1024.0)
#define ENC_OBS_INV_SCALE MC_C(0.0009765625)

typedef struct {
    mc_t l1_ts_scaled;   /* l1 Ts 2^ENC_OBS_SHIFT [1] */
    mc_t ts_scaled;      /* Ts 2^ENC_OBS_SHIFT [s] */
    mc_t l2_ts;          /* l2 Ts [1/s] */
    mc_t l3_ts;          /* l3 Ts [N m / rad] */
    mc_t ts_over_J;      /* Ts / J [s / (kg m^2)] */
    mc_t inv_J;          /* 1 / J [1 / (kg m^2)] */
} encoder_observer_config_t;

typedef struct {
    encoder_observer_config_t cfg;
    mc_t theta_s;        /* the angle estimate wrapped into [-pi, pi), times 2^ENC_OBS_SHIFT */
    int32_t turns;       /* its whole turns */
    mc_t theta_rad;      /* unwrapped mechanical angle estimate, turns 2 pi + theta_s 2^-ENC_OBS_SHIFT */
    mc_t omega_rad_s;
    mc_t accel_rad_s2;   /* (T_e - T_L_hat) / J of the last step */
    mc_t load_Nm;        /* T_L_hat: load and friction */
    mc_t eps_rad;        /* the last angle error */
} encoder_observer_t;

/* Copies cfg and starts at theta0_rad at rest, no load. False for a
 * non-positive Ts 2^ENC_OBS_SHIFT, Ts/J or 1/J, or negative gains. */
bool encoder_observer_init(encoder_observer_t *o, const encoder_observer_config_t *cfg, mc_t theta0_rad);

/* Sets the angle estimate (the first measurement: no start transient). */
void encoder_observer_set_angle(encoder_observer_t *o, mc_t theta_rad);

/* One sample: the sensor's angle [rad, any 2 pi range] and the motor's
 * torque T_e [N m] over the sample. */
void encoder_observer_step(encoder_observer_t *o, mc_t theta_meas_rad, mc_t torque_Nm);

/* The estimate in the drives' common form (valid: always, a sensor). */
void encoder_observer_get(const encoder_observer_t *o, mc_estimate_t *e);

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_ENCODER_OBSERVER_H */
