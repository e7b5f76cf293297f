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
 *   start-up (startup/)            rotor alignment, open-loop drive (68), standstill
 *                                  R/L measurement
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
#include "drives/drive.h"
#include "control/deadtime_comp.h"
#include "control/fg_tracking.h"
#include "control/load_angle.h"
#include "estimators/fg_estimator.h"
#include "hal/hal_types.h"
#include "math/frame_fg.h"
#include "math/mc_num.h"
#include "model/motor_model.h"
#include "startup/align.h"
#include "startup/k_identification.h"
#include "startup/open_loop.h"
#include "startup/rl_identification.h"
#include "supervisor/fault_monitor.h"
#include "supervisor/flight_recorder.h"
#include "supervisor/supervisor.h"
#include "trajectory/trajectory.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A two-phase stepper: windings a and b in quadrature. */
#define P000_N_PHASES 2u

/* Loss of synchronism and the reactions to faults (docs/faults.md). The
 * criteria, checked in closed loop (the estimate is only used there):
 *   tracking: |theta_est - theta_r| > los_track_rad for los_track_ticks
 *     (the estimate is consistent, the rotor lags: the controller at its
 *     limit gets that long to pull it back);
 *   persisting for los_ticks samples, any of:
 *     back-EMF magnitude inconsistent with the estimated speed,
 *       | |e_hat| - K |w_est| | > los_emf_tol K |w_est| + los_emf_floor_V;
 *     estimate jump: |d theta_est - d theta_r| between two checks > los_jump_rad;
 *     current observer error max(|i_f - i_f_hat|, |i_g - i_g_hat|) > los_obs_err_A
 *       (also in open loop after the alignment: an open phase shows here);
 *   the back-EMF unobservable while the reference is above omega_lim (the
 *   switch to open loop that was silent before);
 *   at the hand-over to open loop as the reference slows, the estimate more
 *   than los_track_rad from the reference (the open loop would pull the
 *   rotor onto another tooth): the safe state at once.
 * RELOCK: open loop for relock_hold_ticks, then closed again; confirmed
 * after relock_confirm_ticks of closed loop; if the reference slows below
 * omega_lim before that, the loss stands (safe state).
 * Derived in design/paper000_design.c. */
/* The loss-of-synchronism criteria (all but the unobservable back-EMF)
 * run on every P000_LOS_DECIMATION-th sample: they persist for 5 ms and
 * 0.2 s, so a quarter of the samples decides as well at a quarter of the
 * cost (their tick counts below count checks). A power of two. */
#define P000_LOS_DECIMATION 4u

typedef struct {
    uint8_t reaction[DRIVE_FAULT_COUNT]; /* fault_reaction_t per fault code */
    int32_t relock_max;                  /* RELOCK retries before SAFE */
    int32_t relock_hold_ticks;           /* open loop after a loss before the loop may close again */
    int32_t relock_confirm_ticks;        /* closed loop without a new loss that confirms a re-lock */
    mc_t los_track_rad;
    int32_t los_track_ticks;
    mc_t los_emf_tol;                    /* relative */
    mc_t los_emf_floor_V;
    mc_t los_jump_rad;
    mc_t los_obs_err_A;
    int32_t los_ticks;
} paper000_protection_config_t;

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
} paper000_delay_config_t;

/* The position law. TWISTING: paper 000's super-twisting current loop
 * (46)-(51) and twisting position loop (52)-(57) on the estimates, in
 * closed loop; the open-loop range below omega_lim is (68). LOAD_ANGLE:
 * current-vector control in the reference's frame (control/load_angle.h)
 * in closed loop and in the open-loop range (after the standstill R, L
 * measurement, which keeps (68)): a current of 0.97 I_max whose angle ahead of
 * the reference carries the torque the move and the observed load need,
 * damped on the observed speed; a load step is held by the magnetic
 * spring of that current before any estimate has seen it. */
typedef enum { P000_LAW_TWISTING = 0, P000_LAW_LOAD_ANGLE = 1 } paper000_law_t;

/* Everything paper000_drive_init needs, in the firmware numeric type. Per-sample
 * coefficients already contain Ts (see design/paper000_design.c).
 * Pointer-free, so it can be stored, copied and sent as bytes. */
typedef struct {
    motor_model_t model;          /* the motor the drive believes in */
    drive_limits_t limits;
    fg_estimator_config_t est;
    fg_tracking_config_t ctrl;
    paper000_law_t law;
    load_angle_config_t load_angle; /* with law LOAD_ANGLE */
    supervisor_config_t sup;
    fault_monitor_config_t faults;
    paper000_protection_config_t prot;
    open_loop_config_t open_loop;
    align_config_t align;         /* rotor alignment before the start (disabled: none) */
    rl_id_config_t rl_id;         /* standstill R, L measurement at the start (window 0: off) */
    k_id_config_t k_id;           /* K measured in closed loop (disabled: off) */
    trajectory_config_t traj;
    paper000_delay_config_t delay;   /* computation delay compensation (d = 0: none) */
    deadtime_comp_config_t deadtime; /* an MCU board's inverter: dead-time compensation
                                      * (control/deadtime_comp.h); disabled: none (the
                                      * rig's linear amplifiers) */
    uint32_t close_dwell_ticks;   /* the back-EMF observable this many samples in a row before the loop closes */
    /* moves by command (paper000_drive_move): the peak speed and acceleration of
     * eq. (70) must stay within what the gains were designed for (the
     * design's w_max and a_max); 0: moves by command refused */
    mc_t move_speed_max_rad_s;
    mc_t move_accel_max_rad_s2;
} paper000_config_t;

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
    k_id_state_t k_id_state;
    mc_t K_model_V_s;
    uint32_t fw_version;           /* MC_VERSION_U32: major << 16 | minor << 8 | patch */
    uint32_t fault_events;         /* faults seen since init, recovered ones included */
    int32_t relocks;               /* RELOCK reactions taken */
    uint32_t overruns;             /* HAL-reported overruns */
} paper000_telemetry_t;

typedef struct {
    paper000_config_t cfg;          /* as designed; constant after paper000_drive_init */
    motor_model_t model;         /* in use: cfg.model, with R and L once measured */
    supervisor_t sup;
    fault_monitor_t mon;
    flight_recorder_t rec;
    int32_t relocks;             /* RELOCK reactions taken */
    int32_t relock_hold;         /* samples left before the loop may close again */
    bool branch_kept;            /* the jump count stayed valid through the recovery */
    int32_t recovering;          /* samples of closed loop still needed to confirm a re-lock */
    fault_persist_t los_persist;
    fault_persist_t obs_persist; /* current observer error */
    fault_persist_t track_persist; /* estimate far from the reference */
    mc_t theta_est_prev_rad;     /* estimate and reference at the last check, for the jump criterion */
    mc_t theta_ref_prev_rad;
    fg_estimator_t est;
    deadtime_comp_t dtc;             /* cfg.deadtime */
    fg_tracking_t ctrl;
    load_angle_t la;
    bool la_from_other;          /* the last step drove another law than the load-angle one */
    align_t align;
    rl_id_t rl_id;
    k_id_t k_id;
    trajectory_t traj;
    uint32_t tick;
    uint32_t align_ticks;        /* the alignment's length: the trajectory's sample 0 follows it */
    uint32_t observable_run;     /* samples in a row the back-EMF has been observable (saturates) */
    bool disabled;               /* paper000_drive_set_enabled(false): 0 V until enabled again */
    mc_t omega_lim_rad_s;        /* in use: cfg.limits' or paper000_drive_set_omega_lim's */
    bool v_ext_set;              /* paper000_drive_set_applied_voltage() for the next step */
    mc_ab_t v_ext_V;
    trajectory_point_t ref;      /* reference of this sample */
    trajectory_point_t ref_next; /* reference of the next sample */
    mc_rot_t rot_k;              /* U(n_p theta_r) of this sample, eq. (8) */
    mc_rot_t rot_next;           /* the same for the next sample */
    mc_rot_t rot_resync;         /* U(n_p theta_r) of the next resync sample, exactly, formed
                                  * one sample ahead from ref_next (paper000_drive.c) */
    /* what the last step computed that is not kept in a block's state */
    struct {
        uint32_t tick;
        mc_t i_f_A, i_g_A, v_a_V, v_b_V;
    } last;
} paper000_drive_t;

/* The drive's operations (drives/drive.h), paper000_ops.c. */
extern const drive_ops_t paper000_drive_ops;

/* Validates cfg, copies it and resets every state. Returns false (drive in
 * FAULT, outputs 0 V) if cfg is inconsistent; paper000_config_problem says why. */
bool paper000_drive_init(paper000_drive_t *d, const paper000_config_t *cfg);

/* NULL when cfg is consistent, else its first inconsistency, naming the
 * field (a string literal: nothing to free, nothing kept). The trajectory
 * is checked by trajectory_init (trajectory/trajectory.h). */
const char *paper000_config_problem(const paper000_config_t *cfg);

/* One sample: the HAL sample in (P000_N_PHASES phase currents [A]), the
 * phase voltages [V] out. With the alignment enabled, the first
 * align_ticks samples align the rotor (the reference holds at its start)
 * and the trajectory's time 0 is the sample after them. Always fills *out (0 V in FAULT). Returns false
 * when in FAULT; a sample of another phase count is a BAD_INPUT fault. */
bool paper000_drive_step(paper000_drive_t *d, const hal_sample_t *in, hal_command_t *out);

/* The phase voltages that will really be applied over the coming sample,
 * when they differ from what paper000_drive_step commands: the observer of that
 * step then uses them. For replays of recorded runs (sim/replay), or a
 * power stage whose output is known better than the command. With a
 * computation delay it is the mean over the sample (the drive then does not
 * form it from its commands). One-shot: applies to the next paper000_drive_step only. */
void paper000_drive_set_applied_voltage(paper000_drive_t *d, mc_t v_a_V, mc_t v_b_V);

/* Clears a latched fault by command: the drive starts again from its
 * initial state (alignment first). Returns what paper000_drive_init returns. The
 * flight recorder's snapshot is discarded with it. */
bool paper000_drive_clear_fault(paper000_drive_t *d);

/* Commands (through the drive interface: paper000_ops.c). Each returns
 * false and changes nothing when it is refused in the drive's present
 * state; none is refused for an argument the DBC's ranges allow unless
 * said so.
 *
 * paper000_drive_set_enabled: false puts the drive in its safe state (0 V on every
 * phase) until enabled again; true after a disable starts the drive again
 * as at power-up (alignment, identification, the configured moves): the
 * rotor may have been moved meanwhile. Refused in FAULT (clear it first);
 * enabling an enabled drive is accepted and changes nothing. */
bool paper000_drive_set_enabled(paper000_drive_t *d, bool on);

/* Move to theta_to_rad over duration_s from where the reference rests,
 * with the rest-to-rest polynomial of eq. (70), starting two samples on.
 * Refused while disabled, outside OPEN_LOOP/CLOSED_LOOP (alignment,
 * identification, FAULT), while a move is in progress or queued, and when
 * its peak speed 2.1875 |d|/T or acceleration 7.5132 |d|/T^2 exceeds
 * cfg.move_speed_max_rad_s / move_accel_max_rad_s2. */
bool paper000_drive_move(paper000_drive_t *d, mc_t theta_to_rad, mc_t duration_s);

/* Stop: the moves not yet started are dropped; the one in progress ends
 * at its end point (eq. (70) is rest-to-rest: stopping sooner would need
 * a jerk the gains were not designed for; disable is the emergency stop).
 * Refused in FAULT. */
bool paper000_drive_stop(paper000_drive_t *d);

/* The speed from which the loop closes (paper 000 section 5.1). Refused
 * in closed loop, below cfg.limits.omega_lim_rad_s (the observer's gains
 * and the observability threshold hold from there up) and above
 * cfg.move_speed_max_rad_s. paper000_drive_init restores the configured one. */
bool paper000_drive_set_omega_lim(paper000_drive_t *d, mc_t omega_lim_rad_s);

/* The flight recorder: the first fault's code, tick and the samples before
 * it (flight_recorder_get). Valid until paper000_drive_clear_fault. */
static inline const flight_recorder_t *paper000_drive_flight_recorder(const paper000_drive_t *d) { return &d->rec; }

/* Telemetry of the last step, assembled from the state on request (the
 * step itself stores only what no block keeps). */
void paper000_drive_get_telemetry(const paper000_drive_t *d, paper000_telemetry_t *t);

#ifdef __cplusplus
}
#endif

#endif /* DRIVES_PAPER000_DRIVE_H */
