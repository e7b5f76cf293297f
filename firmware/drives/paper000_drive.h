/*
 * paper000_drive.h - the paper-000 sensorless position drive (Delpoux &
 * Floquet 2014) for a two-phase stepper: a short composition of parts.
 *
 *   phase adapter (adapter/)       2 phase currents -> alpha-beta, voltages back
 *   reference (trajectory/)        eq. (70) and the (f-g) frame (6)-(8) it turns
 *   estimator (estimators/)        fg_estimator: back-EMF observer, arctan and
 *                                  jump counter, mechanical observer -> mc_estimate_t
 *   controller (control/)          fg_tracking: flatness references, super-twisting
 *                                  current and twisting position control
 *   start-up (startup/)            open-loop drive (68), standstill R/L measurement
 *   supervisor (supervisor/)       states, faults, bumpless switch, voltage limit
 *   model (model/)                 one motor model and one set of limits
 *
 * One call per sample (Ts = 100 us) takes the HAL sample and fills the HAL
 * command (hal/include/hal/hal_types.h). The state struct is fixed-size;
 * nothing allocates. Coefficients come from drive_design() (design/), which
 * derives them from the motor and its bounds. docs/architecture.md draws
 * the data flow of one sample.
 */
#ifndef DRIVES_PAPER000_DRIVE_H
#define DRIVES_PAPER000_DRIVE_H

#include <stdbool.h>
#include <stdint.h>

#include "adapter/phase_adapter.h"
#include "control/fg_tracking.h"
#include "estimators/fg_estimator.h"
#include "hal/hal_types.h"
#include "math/frame_fg.h"
#include "math/mc_num.h"
#include "model/motor_model.h"
#include "startup/open_loop.h"
#include "startup/rl_identification.h"
#include "supervisor/supervisor.h"
#include "trajectory/trajectory.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A two-phase stepper: windings a and b in quadrature. */
#define DRIVE_N_PHASES 2u

/* Computation delay (not in the paper: its dSpace card writes the DACs as
 * soon as the computation ends, d ~ 0; an MCU's PWM takes the new duty a
 * whole period later, d = 1). The voltage computed from the currents of
 * t_k acts over [t_k + d Ts, t_k+1 + d Ts); the previous one holds before.
 * The drive then (drive_design() derives the fields from d):
 *  - turns its output to the phases with the (f-g) frame of the middle of
 *    that interval, n_p theta_r at t_k + (1/2 + d) Ts, instead of the
 *    mid-sample one, so the (f-g) voltage the motor sees on average is the
 *    commanded one (eq. (7) inverse): the frame of the base (the
 *    mid-sample one, or the next sample's for d >= 1/2) turned by x half
 *    samples of the reference's rotation;
 *  - gives the observer (25) and the standstill R, L measurement the
 *    voltage really applied over the sample, (1 - d) v[k] + d v[k-1];
 *  - predicts the measured currents to t_k + d Ts, where the command starts
 *    to act, for the current and position laws (46)-(54), with the model
 *    (23) and the voltage v[k-1] that holds until then.
 * d = 0 skips all of it: the step is the one without the field. */
typedef struct {
    mc_t d;            /* delay [samples] in [0, 1] */
    mc_t x;            /* turn of the output frame past its base, in half-sample rotations, [0, 1] */
    mc_t x2;           /* x^2 */
    bool from_next;    /* base of the output frame: the next sample's (d >= 1/2) or the mid-sample one */
} drive_delay_config_t;

/* Everything drive_init needs, in the firmware numeric type. Per-sample
 * coefficients already contain Ts (see firmware/design/drive_design.c).
 * Pointer-free, so it can be stored, copied and sent as bytes. */
typedef struct {
    motor_model_t model;          /* the motor the drive believes in */
    drive_limits_t limits;
    fg_estimator_config_t est;
    fg_tracking_config_t ctrl;
    supervisor_config_t sup;
    open_loop_config_t open_loop;
    rl_id_config_t rl_id;         /* standstill R, L measurement at the start (window 0: off) */
    trajectory_config_t traj;
    drive_delay_config_t delay;   /* computation delay compensation (d = 0: none) */
    uint32_t close_dwell_ticks;   /* the back-EMF observable this many samples in a row before the loop closes */
} drive_config_t;

/* What one step computed, for telemetry, logs and tests. */
typedef struct {
    drive_mode_t mode;
    drive_fault_t fault;
    sup_state_t state;
    uint32_t tick;
    /* references, eqs. (38)-(39), (70) */
    mc_t theta_ref_rad, omega_ref_rad_s, accel_ref_rad_s2;
    mc_t i_f_ref_A, i_g_ref_A;
    /* measured currents in the (f-g) frame, eq. (6), and the observer's */
    mc_t i_f_A, i_g_A, i_f_hat_A, i_g_hat_A;
    /* back-EMF estimates as voltages, L*d_f_hat and L*d_g_hat [V] (eq. 28) */
    mc_t e_f_hat_V, e_g_hat_V;
    /* estimates */
    mc_t theta_est_rad, omega_est_rad_s, accel_est_rad_s2, load_est_Nm;
    mc_t delta_theta_est_rad; /* eq. (29), in (-pi/n_p, pi/n_p] */
    int32_t jump_count;        /* k of eq. (71) */
    /* commands */
    mc_t v_f_V, v_g_V, v_a_V, v_b_V;
    bool v_saturated;
    /* model in use: the configured one, or the standstill measurement */
    rl_id_state_t rl_id_state;
    mc_t R_model_ohm, L_model_H;
    uint32_t fw_version;           /* MC_VERSION_U32: major << 16 | minor << 8 | patch */
} drive_telemetry_t;

typedef struct {
    drive_config_t cfg;          /* as designed; constant after drive_init */
    motor_model_t model;         /* in use: cfg.model, with R and L once measured */
    supervisor_t sup;
    fg_estimator_t est;
    fg_tracking_t ctrl;
    rl_id_t rl_id;
    trajectory_t traj;
    uint32_t tick;
    uint32_t observable_run;     /* samples in a row the back-EMF has been observable (saturates) */
    bool v_ext_set;              /* drive_set_applied_voltage() for the next step */
    mc_ab_t v_ext_V;
    trajectory_point_t ref;      /* reference of this sample */
    trajectory_point_t ref_next; /* reference of the next sample */
    mc_rot_t rot_k;              /* U(n_p theta_r) of this sample, eq. (8) */
    mc_rot_t rot_next;           /* the same for the next sample */
    /* what the last step computed that is not kept in a block's state */
    struct {
        uint32_t tick;
        mc_t i_f_A, i_g_A, v_a_V, v_b_V;
    } last;
} drive_t;

/* Validates cfg, copies it and resets every state. Returns false (drive in
 * FAULT, outputs 0 V) if cfg is inconsistent. */
bool drive_init(drive_t *d, const drive_config_t *cfg);

/* One sample: the HAL sample in (DRIVE_N_PHASES phase currents [A]), the
 * phase voltages [V] out. Always fills *out (0 V in FAULT). Returns false
 * when in FAULT; a sample of another phase count is a BAD_INPUT fault. */
bool drive_step(drive_t *d, const hal_sample_t *in, hal_command_t *out);

/* The phase voltages that will really be applied over the coming sample,
 * when they differ from what drive_step commands: the observer of that
 * step then uses them. For replays of recorded runs (sim/replay), or a
 * power stage whose output is known better than the command. With a
 * computation delay it is the mean over the sample (the drive then does not
 * form it from its commands). One-shot: applies to the next drive_step only. */
void drive_set_applied_voltage(drive_t *d, mc_t v_a_V, mc_t v_b_V);

/* Telemetry of the last step, assembled from the state on request (the
 * step itself stores only what no block keeps). */
void drive_get_telemetry(const drive_t *d, drive_telemetry_t *t);

#ifdef __cplusplus
}
#endif

#endif /* DRIVES_PAPER000_DRIVE_H */
