/*
 * sensored_foc_drive.h - the sensored field-oriented drive: the baseline
 * every peer ships (ODrive, VESC with an encoder, SimpleFOC, ST's MCSDK),
 * here the reference to compare the sensorless drives with on the same
 * scenarios. A short composition of blocks:
 *
 *   phase adapter (adapter/)        3 phase currents -> alpha-beta, voltages back
 *   encoder observer (estimators/)  angle, speed, acceleration, load torque
 *                                   from the encoder's angle and K_t i_q
 *   reference (trajectory/)         the speed profile (CmdSpeed), or a
 *                                   rest-to-rest move (CmdMove, paper 000
 *                                   eq. (70))
 *   position loop                   P on the angle error, added to the speed
 *                                   reference (moves only)
 *   speed loop (control/pi_ctrl)    PI on the speed error -> i_q*, with the
 *                                   load and J a_ref fed forward, |i_q*| <= i_max
 *   current loops (control/           PI on i_d, i_q with the cross-coupling
 *     foc_current)                  and back-EMF fed forward (decoupling),
 *                                   the voltage limited to the bus's circle
 *                                   (d first), conditional integration
 *   fault set (supervisor/)         the generic monitor, latch, flight recorder
 *
 * i_d* = 0 (the surface PMSM; a salient motor would take MTPA, paper 002's
 * control/mtpa.h). One call per sample takes the HAL sample (with the
 * encoder's angle) and fills the command. Nothing allocates. The gains come
 * from sensored_foc_design() (design/sensored_foc_design.h), derived from
 * the motor and the chosen bandwidths.
 */
#ifndef DRIVES_SENSORED_FOC_DRIVE_H
#define DRIVES_SENSORED_FOC_DRIVE_H

#include <stdbool.h>
#include <stdint.h>

#include "adapter/phase_adapter.h"
#include "control/deadtime_comp.h"
#include "control/foc_current.h"
#include "control/pi_ctrl.h"
#include "drives/drive.h"
#include "estimators/encoder_observer.h"
#include "hal/hal_types.h"
#include "math/frame_fg.h"
#include "math/mc_num.h"
#include "model/motor_model.h"
#include "supervisor/fault_monitor.h"
#include "supervisor/flight_recorder.h"
#include "supervisor/supervisor.h"
#include "trajectory/speed_profile.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Three phases in star on three inverter legs. */
#define SFOC_N_PHASES 3u
/* The polynomial of a move (trajectory_poly7, paper 000 eq. (70)) peaks at
 * 2.1875 |d| / T in speed and 7.5132 |d| / T^2 in acceleration (its
 * derivatives' maxima on [0, 1], trajectory/trajectory.h). */
#define SFOC_MOVE_PEAK_SPEED MC_C(2.1875)
#define SFOC_MOVE_PEAK_ACCEL MC_C(7.5132)

typedef struct {
    motor_model_t model;           /* the one motor model: n_p, fs, Ts, R, L_d, L_q, psi, J (the
                                    * acceleration feedforward J a_ref); the blocks read it by const pointer */
    mc_t kt_Nm_per_A;              /* 3/2 n_p psi: torque per i_q (amplitude-invariant Clarke) */
    mc_t inv_kt_A_per_Nm;          /* 1 / kt: i_q per torque of the feedforward (no division per sample) */
    foc_current_config_t current;  /* current loops with decoupling (control/foc_current.h) */
    pi_ctrl_config_t pi_speed;     /* speed loop [A s/rad], [A/rad per sample] */
    mc_t pos_kp_per_s;             /* position loop: rad/s of speed per rad of error */
    encoder_observer_config_t obs;
    mc_t i_max_A;                  /* |i_q*| limit */
    mc_t v_bus_min_V;              /* a bus below it is bad input */
    mc_t compute_delay;            /* d in [0, 1]: the voltage acts d Ts after the sample */
    deadtime_comp_config_t deadtime; /* the inverter's dead-time compensation
                                    * (control/deadtime_comp.h); disabled: none (no inverter) */
    speed_profile_config_t profile;/* the configured speed reference */
    fault_monitor_config_t faults;
    mc_t speed_cmd_max_rad_s;      /* CmdSpeed: |w| above it refused */
    mc_t accel_cmd_max_rad_s2;     /* CmdSpeed ramp and CmdMove peak acceleration above it refused */
    uint8_t reaction[DRIVE_FAULT_COUNT]; /* fault_reaction_t per fault: SAFE or REPORT (no re-lock: RELOCK acts as SAFE) */
} sensored_foc_config_t;

typedef enum { SFOC_MODE_SPEED = 0, SFOC_MODE_POSITION = 1 } sfoc_mode_t;

typedef struct {
    sensored_foc_config_t cfg;
    foc_current_t current;
    pi_ctrl_t pi_speed;
    encoder_observer_t obs;
    deadtime_comp_t dtc;           /* cfg.deadtime */
    speed_profile_t profile;
    fault_monitor_t mon;
    supervisor_t sup;              /* CLOSED_LOOP, or FAULT latched until cleared (supervisor/guard.h) */
    bool disabled;
    bool started;                  /* the observer took the first angle */
    sfoc_mode_t mode;
    struct {                       /* the move in progress (POSITION) */
        mc_t theta0_rad, delta_rad, inv_ticks, inv_T_s;
        uint32_t t0_tick, n_ticks;
    } move;
    mc_t stop_ramp_rad_s2;         /* the last commanded ramp, the stop's */
    uint32_t tick;
    struct {                       /* the last step, for telemetry and logs */
        mc_t theta_ref_rad, omega_ref_rad_s, accel_ref_rad_s2;
        mc_t i_d_A, i_q_A, i_d_ref_A, i_q_ref_A, v_d_V, v_q_V;
        mc_ab_t v_ab_V;
        mc_t theta_e_rad;          /* the encoder's electrical angle, (-pi, pi] */
        bool saturated;
    } last;
    flight_recorder_t rec;         /* last: its samples are the struct's bulk, the fields read every
                                    * sample stay within the loads' immediate offsets */
} sensored_foc_drive_t;

extern const drive_ops_t sensored_foc_drive_ops;

/* NULL when cfg is consistent, else its first problem (a literal). */
const char *sensored_foc_config_problem(const sensored_foc_config_t *cfg);

/* Validates cfg, copies it and resets every state. False: FAULT (bad
 * input), 0 V out. */
bool sensored_foc_drive_init(sensored_foc_drive_t *d, const sensored_foc_config_t *cfg);

/* One sample; always fills *out (0 V in FAULT or disabled); false in FAULT.
 * A sample without the encoder's angle, of another phase count or with the
 * bus below v_bus_min_V is a BAD_INPUT fault. */
bool sensored_foc_drive_step(sensored_foc_drive_t *d, const hal_sample_t *in, hal_command_t *out);

/* Commands (drive_ops_t.command, sensored_foc_ops.c): false = refused,
 * nothing changed. Enable: false is the safe state; true after it starts
 * again as at power-up. Refused in FAULT. */
bool sensored_foc_set_enabled(sensored_foc_drive_t *d, bool on);
/* Speed mode at omega_rad_s with ramp_rad_s2 (the ramp becomes the stop's).
 * Refused disabled, in FAULT, during a move, beyond the config's bounds. */
bool sensored_foc_set_speed(sensored_foc_drive_t *d, mc_t omega_rad_s, mc_t ramp_rad_s2);
/* Position mode: from the present angle estimate to theta_to_rad over
 * duration_s (eq. (70)). Refused disabled, in FAULT, while the speed
 * reference is not at rest or a move is in progress, and when its peak
 * speed or acceleration exceeds the config's bounds. */
bool sensored_foc_move(sensored_foc_drive_t *d, mc_t theta_to_rad, mc_t duration_s);
/* Speed mode: to 0 at the stop ramp; position mode: the move ends where
 * it is going (rest-to-rest). Refused in FAULT. */
bool sensored_foc_stop(sensored_foc_drive_t *d);

#ifdef __cplusplus
}
#endif

#endif /* DRIVES_SENSORED_FOC_DRIVE_H */
