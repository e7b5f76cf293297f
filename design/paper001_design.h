/*
 * paper001_design.h - derives the paper-001 drive's coefficients (flux
 * observer gain, I&I observer gains, IDA-PBC damping, start-up, speed
 * profile) from the motor and the sample time, in double precision on the
 * host, and folds them into per-sample firmware coefficients. Every
 * choice is justified in paper001_design.c.
 */
#ifndef DESIGN_PAPER001_DESIGN_H
#define DESIGN_PAPER001_DESIGN_H

#include <stdbool.h>
#include <stddef.h>

#include "design/paper000_design.h"
#include "design/motor_design.h"
#include "drives/paper001/paper001_drive.h"
#include "startup/pmsm_identification.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    /* the motor the drive believes in (paper 001 section 5 for the
     * benchmark), the one design input (design/motor_design.h): n_phases
     * 3 (PMSM) or 2 (stepper), R and L per phase (alpha-beta model),
     * Phi = K / n_p (K_e = n_p Phi), n_p, J; friction is not designed for */
    motor_design_input_t motor;
    double ts_s;
    double i_max_A;          /* |i_q*| and the start-up current bound */
    double i_trip_A;
    double i_open_loop_A;    /* current of the open-loop start; <= 0: the default */
    /* gains; <= 0: derived */
    double gamma;            /* flux observer (12) [1/(Wb^2 s)] */
    double a1, a2;           /* I&I observer (15) */
    double r_ohm;            /* IDA-PBC damping (11) */
    double blend_tau_s;      /* decay of the voltage offset at the switch */
    double handover_sweep_rad; /* electrical; <= 0: derived */
    double fit_det_min;      /* smallest arc measure of the circle fit; <= 0: derived */
    double probe_s;          /* longest start-up probe [s]; 0: no probe (defaults: 0.3) */
    int estimator;           /* OPEN_START_FLUX (default) or OPEN_START_BACK_EMF (estimators/open_start.h) */
    double compute_delay_samples; /* the board's computation delay, [0, 1] samples */
    double i_rail_A;
    int i_trip_samples;      /* consecutive samples beyond i_trip_A that trip (0 or 1: instantaneous; up to 8) */         /* current at the ADC's rail; 0: unknown (no rail check) */
    double omega_lim_rad_s;  /* BACK_EMF: closed loop from |w*| >= this; <= 0: derived */
    bool track_resistance;   /* FLUX: R tracked on line (estimators/resistance_tracker.h) */
    /* speed profile: corners (t [s], w [rad/s mechanical]) */
    size_t n_points;
    double t_s[SPEED_PROFILE_MAX_POINTS];
    double omega_rad_s[SPEED_PROFILE_MAX_POINTS];
} p001_design_input_t;

/* What the design derived, in SI, for reports and tests. */
typedef struct {
    double gamma, a1, a2, r_ohm;
    double Ke, Kt;
    double radial_rate_per_sample;   /* 2 gamma Phi^2 Ts: < 1 for a stable explicit step */
    double observer_poles_re;        /* real part of A33's poles (16) */
    double loop_wn_rad_s, loop_zeta; /* L J s^2 + r J s + K_e K_t */
    double i_open_loop_A;
    double probe_s, i_probe_A;
    double lock_settle_s;    /* the loss-of-lock persistence (supervisor/lock_monitor.h) */
    double rtrack_tau_s, rtrack_i_gate_A, rtrack_e_clamp_V, rtrack_dR_max_ohm; /* track_resistance */
} p001_design_report_t;

/* Fills the defaults of section 5 into *in (motor and profile left as given). */
void p001_design_defaults(p001_design_input_t *in);

/* Validates *in, derives, folds. False with a reason (naming the field) in
 * err if an input is unusable. */
bool p001_design(const p001_design_input_t *in, paper001_config_t *cfg, p001_design_report_t *rep, char *err,
                 size_t err_len);

/* The commissioning run (startup/pmsm_identification.h) for the motor of
 * *in: alignment, standstill R/L step, spin for Phi; *duration_s (if not
 * NULL) is its nominal length. False with a reason if *in is unusable. */
bool p001_identification_design(const p001_design_input_t *in, pmsm_id_config_t *cfg, double *duration_s,
                                char *err, size_t err_len);

#ifdef __cplusplus
}
#endif

#endif /* DESIGN_PAPER001_DESIGN_H */
