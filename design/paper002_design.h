/*
 * paper002_design.h - paper 002's drive designed from the motor, the
 * sample time, the limits and the sensors' noise (host side, double
 * precision; drives/paper002/paper002_drive.h). Every gain is derived and named in
 * paper002_design.c; the fixed-point build refuses the design (the EKF's
 * covariances do not fit Q14.17: the angle's measurement variance 1e-8
 * rad^2 is below its 7.6e-6 step).
 */
#ifndef DESIGN_PAPER002_DESIGN_H
#define DESIGN_PAPER002_DESIGN_H

#include <stdbool.h>
#include <stddef.h>

#include "design/motor_design.h"
#include "drives/paper002/paper002_drive.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    /* the motor of (2), (6), (7), the one design input
     * (design/motor_design.h): R, L_d = L_H, L_q = L_q_H, psi = K / n_p,
     * p = n_p, J, d = fv_Nms_per_rad */
    motor_design_input_t motor;
    double ts_s;
    double i_max_A, i_trip_A;
    double i_rail_A;
    int i_trip_samples;      /* consecutive samples beyond i_trip_A that trip (0 or 1: instantaneous; up to 8) */         /* the ADC's full scale (0: none; the rail check is off) */
    /* the sensors: current noise (sigma) per phase, encoder counts and
     * angle noise (sigma) */
    double sigma_i_A, sigma_theta_rad;
    long encoder_counts;
    int controller;          /* p002_controller_t */
    bool compensate;         /* disturbance compensation (DC) */
    /* the reference of speed_poly.h: w0 until t0, w1 from t1 */
    double t0_s, t1_s, w0_rad_s, w1_rad_s;
    /* the angle's source (p002_angle_source_t); with FLUX the encoder's
     * fields are unused and theta0_rad (mechanical) is the rotor's angle at
     * start, known from an alignment (paper002_drive.h) */
    int angle_source;
    double theta0_rad;
    /* HFI only: the start angle unknown (theta0_rad not told to the
     * drive): it locks the injection, runs the magnet polarity test and
     * refuses to run when undecided (paper002_drive.h) */
    bool hfi_find_angle;
    /* FLUX, HFI: the iron's saturation the active flux is taken with
     * (model/iron_model.h: i_sat and the magnet's bias, as the plant's
     * [motor] i_sat_A, i_sat_bias_A), what a commissioning's inductance
     * map would give; 0, 0 (the default): linear, the paper's model */
    double iron_i_sat_A, iron_i_bias_A;
    /* the board's computation delay in samples, [0, 1] (paper002_drive.h) */
    double compute_delay_samples;
    /* the EKF's noise covariances given by the user instead of the
     * design's, per sample: Q = diag(ekf_q) over [i_d A^2, i_q A^2,
     * theta rad^2, omega (rad/s)^2, M_0 (N m)^2] (39) and R = diag(ekf_r)
     * over [i_d A^2, i_q A^2, theta rad^2] (41). All 0 (the default): the
     * design's (paper002_design.c); otherwise every entry must be > 0 (a
     * positive definite diagonal) and finite. */
    double ekf_q[EKF_N];
    double ekf_r[EKF_M];
} p002_design_input_t;

/* The reference set (p 4, R 0.3, L_d 3 mH, L_q 9 mH, psi 0.04,
 * J 1e-3, d 5e-4; 10 kHz; 5 mA and 1e-4 rad of noise; 0 -> 100 rad/s on
 * [0.2, 0.4] s), SOSMC with compensation, 20 A. */
void p002_design_defaults(p002_design_input_t *in);

/* Validates *in (a key named in err on failure), derives, folds. */
bool p002_design(const p002_design_input_t *in, paper002_config_t *cfg, char *err, size_t err_len);

#ifdef __cplusplus
}
#endif

#endif /* DESIGN_PAPER002_DESIGN_H */
