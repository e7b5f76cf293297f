/*
 * paper000_design.h - derives every drive coefficient from the motor, the
 * sample time and the design bounds, in double precision on the host (or at
 * build time for an MCU image). The firmware blocks themselves never see a
 * physical constant that was not folded here, which is what lets the same
 * blocks run in fixed point. Each gain's derivation (conditions (22), (51),
 * (57) of paper 000) is documented in paper000_design.c.
 */
#ifndef DESIGN_PAPER000_DESIGN_H
#define DESIGN_PAPER000_DESIGN_H

#include <stdbool.h>
#include <stddef.h>

#include "design/motor_design.h"
#include "drives/paper000/paper000_drive.h"

#ifdef __cplusplus
extern "C" {
#endif

#define DRIVE_DESIGN_MAX_SEGMENTS TRAJECTORY_MAX_SEGMENTS


/* One rest-to-rest move of eq. (70): from wherever the previous segment
 * ended (0 for the first) to theta_to_rad, starting at t_start_s. */
typedef struct {
    double t_start_s, duration_s, theta_to_rad;
} drive_segment_si_t;

/* Which conditions the gains are derived from (paper000_design.c):
 *  CONTINUOUS: paper 000's continuous-time conditions (22), (51), (57) and
 *    Levant's super-twisting condition with the bounds as given, constant
 *    gains (the reference derivation);
 *  DISCRETE: the same conditions, with the gains also bounded by what the
 *    sampled system (Ts, one sample of computation delay) resolves without
 *    chattering, the back-EMF observer's gain following the reference speed,
 *    and the load feed-forward's L di/dt (docs/paper000.md compares them). */
typedef enum { DRIVE_GAIN_CONTINUOUS = 0, DRIVE_GAIN_DISCRETE = 1 } drive_gain_design_t;

/* Optional gain overrides: a value <= 0 means "derive it". */
typedef struct {
    double emf_alpha_A_s2, emf_lambda, emf_l_per_s;
    double mech_alpha_rad_s3, mech_lambda, mech_l_per_s;
    double cur_alpha_A_s2, cur_lambda;
    double k_surface_per_s, tw_lambda_m_rad_s3, tw_lambda_M_rad_s3;
    double injection_filter_s, blend_tau_s, current_blend_tau_s;
} drive_gain_override_t;

typedef struct {
    /* the motor the drive believes in (paper 000 section 5.3 for the rig),
     * the one design input (design/motor_design.h): L, R, K, J, f_v, n_p
     * and the Coulomb friction (the load bound when bound_load_Nm is 0) */
    motor_design_input_t motor;
    double ts_s;               /* sample period (1e-4 in the paper) */
    double v_max_V, i_max_A, i_trip_A, omega_lim_rad_s;
    /* current amplitude of the open-loop drive (68) and of the alignment;
     * <= 0 means 2/3 of i_max_A (OPEN_LOOP_OVER_IMAX, paper000_design.c: it
     * makes the switch to closed loop far less sensitive to R, L, K
     * errors); the paper uses i_max_A. */
    double i_open_loop_A;
    /* Bounds the gains are derived from (Section 3.1.1, 3.2, 4.1.2): */
    double bound_accel_rad_s2;       /* |omega_dot|max */
    double bound_speed_rad_s;        /* |omega|max */
    double bound_delta_omega_rad_s;  /* |omega - omega_r|max in closed loop */
    double bound_load_Nm;            /* |C_r|max incl. Coulomb friction; 0: motor.coulomb_Nm */
    double bound_load_rate_Nm_s;     /* |dC_r/dt|max */
    double bound_model_error_V;      /* voltage-equivalent model error, errata (57) */
    /* 1 (default): add the load torque C_r observed by (35) to i_g,r of (39).
     * The paper leaves C_r to the twisting loop ((56)-(57)); feeding the
     * estimate forward shrinks the perturbation the twisting must beat
     * and the torque dip at the open-to-closed switch. 0 = paper as printed. */
    int load_feedforward;
    /* 1 (default): measure R and L during the first open-loop samples at
     * standstill (startup/rl_identification.h); 0: trust the motor model. */
    int identify_rl;
    /* 1 (default): align the rotor before the start (startup/align.h), so
     * the drive starts from any rotor angle; 0: assume it rests at 0. */
    int align_rotor;
    /* 1 (default): measure K in closed loop and use it from then on
     * (startup/k_identification.h); 0: trust the motor model. */
    int identify_k;
    /* current at which a sample is at the ADC's rail [A]; 0: unknown (the
     * rail check is off). The board's, or the scenario's ADC full scale. */
    double i_rail_A;
    /* consecutive samples beyond i_trip_A that trip the drive; 0 or 1: the
     * first (instantaneous), up to 8 (fault_monitor_design) */
    int i_trip_samples;
    /* 1: a loss of synchronism falls back to the open loop and closes again
     * (FAULT_REACT_RELOCK, bounded retries, then the safe state); 0 (the
     * default): the safe state at once (paper000_design.c says why). */
    int los_relock;
    /* The board's computation delay d in [0, 1] samples (0, the default:
     * none, the paper's sampled model): the voltage computed from the
     * currents of t_k acts from t_k + d Ts (drives/paper000/paper000_drive.h,
     * paper000_delay_config_t, says what the drive does with it). */
    double compute_delay_samples;
    drive_gain_design_t gain_design;  /* see drive_gain_design_t; default CONTINUOUS */
    paper000_law_t control_law;          /* see paper000_law_t (drives/paper000/paper000_drive.h); default TWISTING */
    drive_segment_si_t segments[DRIVE_DESIGN_MAX_SEGMENTS];
    int n_segments;
    drive_gain_override_t override;
} drive_design_input_t;

/* Fills the bounds and overrides with the documented defaults. The motor,
 * the sample time, the supply and the limits (v_max_V, i_max_A, i_trip_A,
 * omega_lim_rad_s) and the segments are the caller's: they come from the
 * motor file and the scenario, not from here. */
void drive_design_defaults(drive_design_input_t *in);

/* Derives cfg from in. Returns false and writes a one-line reason naming
 * the offending field into err (if err_len > 0) when in is non-physical. */
bool drive_design(const drive_design_input_t *in, paper000_config_t *cfg, char *err, size_t err_len);

/* The gains of paper 000's estimator (back-EMF observer (23)-(28), position
 * estimator (29)-(32), mechanical observer (33)-(37)) from the motor and
 * the bounds of sections 3.1.1 and 3.2; shared by the position drive and
 * by any drive that uses that estimator (paper001_drive's estimator
 * option). K_torque differs from K_emf on a three-phase motor. */
typedef struct {
    double K_emf_V_s, K_torque_Nm_A, L_H, J_kgm2, ts_s;
    int n_p;
    double accel_max_rad_s2, speed_max_rad_s, delta_omega_max_rad_s, load_rate_max_Nm_s;
    double omega_lim_rad_s, i_max_A;
    drive_gain_override_t override;
    drive_gain_design_t gain_design;  /* DISCRETE: speed-following back-EMF gain, capped load gain */
    double ripple_cap_rad_s3;         /* DISCRETE: the cap of the load observer's alpha (paper000_design.c) */
} fg_estimator_design_t;

/* The generic fault criteria (supervisor/fault_monitor.h) for a drive of
 * n_phases phases with current limit i_max_A, trip i_trip_A and ADC rail
 * i_rail_A (0: unknown), sampled every ts_s; every threshold is a named,
 * justified constant of paper000_design.c (docs/faults.md). Shared by every
 * drive's design. */
void fault_monitor_design(fault_monitor_config_t *fc, int n_phases, double i_max_A, double i_trip_A,
                          int i_trip_samples, double i_rail_A, double ts_s);
/* i_trip_samples (consecutive samples beyond i_trip_A that trip; 0 means
 * 1, instantaneous) is within what a current protection allows. */
bool fault_trip_samples_ok(int i_trip_samples);

/* *Pi_d_out (if not NULL): the back-EMF rate bound Pi_d of section 3.1.1. */
void fg_estimator_design(const fg_estimator_design_t *in, fg_estimator_config_t *ec, double *Pi_d_out);

#ifdef __cplusplus
}
#endif

#endif /* DESIGN_PAPER000_DESIGN_H */
