/*
 * paper001_drive.h - the paper-001 sensorless speed drive (Shah, Espinosa-
 * Perez, Ortega, Hilairet 2014) for a non-salient PMSM (or, by
 * configuration, a two-phase stepper): a short composition of parts.
 *
 *   phase adapter (adapter/)     2 or 3 phase currents -> alpha-beta, voltages back
 *                                with min/max zero sequence, limited by the measured bus
 *   reference (trajectory/)      speed_profile: ramps and holds, w*, dw_ref/dt
 *   estimator (estimators/)      the open-start estimator cfg.estimator names
 *                                (open_start.h): flux_speed.h, flux_observer (12)-(14)
 *                                -> unit vector of the angle, speed_load_observer
 *                                (15)-(16) with the unwrap of Appendix A -> w_hat,
 *                                tau_hat; or emf_speed.h, paper 000's chain
 *   controller (control/)        ida_pbc (11) with the J dw_ref/dt feed-forward
 *   start-up (startup/)          open-loop drive (paper 000's eq. (68)) along the
 *                                reference angle until the observer is trusted
 *   supervisor (supervisor/)     states, faults, bumpless switch, voltage limit
 *
 * Start from an unknown rotor angle (paper 001's result is local): the
 * drive first probes the rotor with a small standstill vector along alpha.
 * Once the rotor has moved (or after `probe_turn_ticks` samples), the
 * vector turns to the direction in which the flux has moved (beta if it
 * has not): whichever of the two mirror-image rotor angles the chord
 * allows, that vector is perpendicular to the rotor's flux and ahead of
 * it in its direction of motion, so the rotor goes on along the same arc
 * instead of retracing it (a rotor at 0 or pi from alpha, which alpha
 * cannot move, is moved by beta). The integrated flux describes the same
 * arc as the rotor, and the through-origin circle
 * fit (flux_circle_fit_center_origin) of points spaced along it finds the
 * observer's initial error as soon as the arc suffices. The observer is
 * corrected and the open-loop vector starts where the rotor is, so the
 * rotor is not dragged across up to half an electrical turn (up to 40 rpm
 * of speed error on paper 001's motor, against or with the reference). If
 * the arc stays too short, the vector starts at the reference angle. Then the
 * drive runs in open loop, a voltage vector of (68)'s magnitude turning
 * with the reference. The stator resistance damps the rotor into step with
 * it (the back-EMF drives a braking current: damping K_e K_t / R). Meanwhile
 * the flux observer runs as a pure integrator and the circle fit
 * (startup/flux_circle_fit.h) measures its initial error from the arc the
 * flux describes. Once the reference has turned `est.handover_sweep_rad`
 * electrical and the arc suffices, the observer is corrected, its gradient
 * term switched on, the speed observer started at the reference speed,
 * and the loop closed; the estimate is reported valid from then on.
 *
 * The probe, the fit and the hand-over are the estimator's
 * (estimators/flux_speed.h). Estimator by configuration (cfg.estimator):
 * with OPEN_START_BACK_EMF (estimators/emf_speed.h), paper 000's
 * estimator replaces the flux and I&I observers after the probe: it runs
 * in the (f-g) frame of the open-loop vector (the reference angle plus the
 * probe's offset), the loop closes as in paper 000 once |w*| >= omega_lim
 * and the back-EMF is observable (and reopens if it is lost), and IDA-PBC
 * (11) runs on its angle, speed and load. The controller is the same.
 */
#ifndef DRIVES_PAPER001_DRIVE_H
#define DRIVES_PAPER001_DRIVE_H

#include <stdbool.h>
#include <stdint.h>

#include "adapter/phase_adapter.h"
#include "drives/drive.h"
#include "control/deadtime_comp.h"
#include "control/delay_comp.h"
#include "control/ida_pbc.h"
#include "estimators/estimate.h"
#include "estimators/estimator_registry.h"
#include "estimators/open_start.h"
#include "hal/hal_types.h"
#include "math/frame_fg.h"
#include "math/mc_num.h"
#include "model/motor_model.h"
#include "startup/open_loop.h"
#include "supervisor/fault_monitor.h"
#include "supervisor/flight_recorder.h"
#include "supervisor/lock_monitor.h"
#include "supervisor/supervisor.h"
#include "trajectory/speed_profile.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    uint8_t n_phases;              /* 3: PMSM (star, three legs); 2: stepper (two H-bridges) */
    uint8_t estimator;             /* its number in the open-start family (estimators/open_start.h):
                                    * OPEN_START_FLUX (paper 001: flux observer (12)-(14), unwrap
                                    * (App. A), I&I (15)-(16)) or OPEN_START_BACK_EMF (paper 000:
                                    * back-EMF observer (23)-(28) in the (f-g) frame of the open-loop
                                    * vector, arctan and jump counter (29)-(32), (71), mechanical
                                    * observer (33)-(37)) */
    motor_model_t model;           /* R, L, K_e = n_p Phi (K_V_s), n_p, fs */
    drive_limits_t limits;         /* i_trip_A on every phase; v_max_V unused (the bus is measured) */
    open_start_config_t est;       /* the estimator's (its model: this model) */
    ida_pbc_config_t ctrl;
    open_loop_config_t open_loop;  /* v_max_V: a cap below the bus, if any */
    supervisor_config_t sup;
    speed_profile_config_t profile;
    mc_t v_bus_min_V;              /* below this measured bus the sample is refused */
    mc_t compute_delay;            /* d in [0, 1]: this step's voltage acts d Ts after the
                                    * currents were sampled, the last one before (the board's
                                    * property: a DAC card ~0, an MCU PWM 1); the observers
                                    * integrate (1 - d) v[k] + d v[k-1] over the sample */
    deadtime_comp_config_t deadtime; /* the inverter's dead-time compensation
                                    * (control/deadtime_comp.h); disabled: none (no inverter) */
    /* faults (docs/faults.md): the generic set, and the loss of the
     * estimate in closed loop: the flux observer's |rho_hat|^2 outside
     * [los_rho2_lo, los_rho2_hi] (1 when it agrees with Phi; estimator FLUX)
     * for los_ticks samples, or the estimated speed off the reference by
     * more than los_speed_tol |w*| + los_speed_floor_rad_s for
     * los_speed_ticks (a stalled rotor or a lost estimate; any estimator).
     * The speed drive has no re-lock: every fault goes to the safe state
     * unless reaction[] says REPORT. */
    fault_monitor_config_t faults;
    uint8_t reaction[DRIVE_FAULT_COUNT];
    mc_t los_rho2_lo, los_rho2_hi;
    int32_t los_ticks;
    mc_t los_speed_tol, los_speed_floor_rad_s;
    int32_t los_speed_ticks;
    /* loss of lock (supervisor/lock_monitor.h, estimator FLUX, closed
     * loop): the flux observer's residual along the estimated rotor axis
     * beyond the tolerance bound (LOSS_OF_LOCK; ticks 0: off) */
    lock_monitor_config_t lock;
} paper001_config_t;

/* The voltage the plant really sees over the coming sample with a
 * computation delay d: v_prev for d Ts, then v for (1 - d) Ts; its mean
 * (1 - d) v + d v_prev is what the observers integrate. d = 0: v itself. */
static inline mc_ab_t paper001_applied_mean(const paper001_config_t *c, mc_ab_t v, mc_ab_t v_prev)
{
    if (mc_eq(c->compute_delay, MC_ZERO)) {
        return v;
    }
    return delay_applied_mean(c->compute_delay, v, v_prev);
}

/* Share of the largest phase voltage a commanded speed's back-EMF may
 * take: the rest (10 %) is left for the R i and L di/dt drops and the
 * controller's margin. */
#define P001_CMD_VOLTAGE_SHARE MC_C(0.9)

typedef struct {
    drive_mode_t mode;
    drive_fault_t fault;
    sup_state_t state;
    uint32_t tick;
    mc_t omega_ref_rad_s, accel_ref_rad_s2, theta_ref_rad;
    /* estimates: electrical angle as (turns, angle in (-pi, pi]) */
    int32_t theta_e_turns;
    mc_t theta_e_rad;
    mc_t omega_est_rad_s, load_est_Nm;
    mc_t rho2;                     /* |rho_hat|^2 of the flux observer (1 when consistent) */
    mc_t R_obs_ohm;                /* the R the flux observer subtracts: the model's, or tracked */
    bool estimate_valid;
    /* currents in the estimated dq frame, the reference, the command */
    mc_t i_d_A, i_q_A, i_q_ref_A;
    mc_t v_d_V, v_q_V, v_alpha_V, v_beta_V;
    bool v_saturated;
    uint32_t fw_version;           /* MC_VERSION_U32: major << 16 | minor << 8 | patch */
    uint32_t fault_events;         /* faults seen since init */
    uint32_t overruns;             /* HAL-reported overruns */
} paper001_telemetry_t;

/* The step instantiated for one estimator (paper001_drive.c); self is the drive. */
typedef bool (*paper001_run_fn)(void *self, const hal_sample_t *in, hal_command_t *out);

typedef struct {
    paper001_config_t cfg;
    paper001_run_fn run;           /* the step for the estimator cfg.estimator names */
    supervisor_t sup;
    fault_monitor_t mon;
    flight_recorder_t rec;
    fault_persist_t rho_persist, speed_persist;
    lock_monitor_t lock;
    const estimator_ops_t *est;    /* the estimator cfg.estimator names */
    estimator_storage_t est_state; /* its state */
    open_start_in_t x;             /* the sample the estimator is given: the reference w*, theta* in it */
    deadtime_comp_t dtc;           /* cfg.deadtime */
    ida_pbc_t ctrl;
    speed_profile_t profile;
    bool disabled;                 /* paper001_drive_set_enabled(false): 0 V until enabled again */
    mc_t stop_ramp_rad_s2;         /* the ramp of a stop: the last commanded, else the profile's steepest */
    mc_t v_bus_V;                  /* the last accepted bus measurement */
    uint32_t tick;
    struct {
        uint32_t tick;
        mc_t i_d_A, i_q_A;
        mc_ab_t v_ab_V;
    } last;
} paper001_drive_t;

/* The drive's operations (drives/drive.h), paper001_ops.c. */
extern const drive_ops_t paper001_drive_ops;

/* Validates cfg, copies it and resets every state. Returns false (drive in
 * FAULT, outputs 0 V) if cfg is inconsistent; paper001_config_problem says why. */
bool paper001_drive_init(paper001_drive_t *d, const paper001_config_t *cfg);

/* NULL if cfg is consistent, else its first problem: a literal naming the
 * field ("limits.i_trip_A: must be > 0"). */
const char *paper001_config_problem(const paper001_config_t *cfg);

/* One sample: phase currents and bus voltage in, phase voltages out.
 * Always fills *out (0 V in FAULT). Returns false in FAULT. */
bool paper001_drive_step(paper001_drive_t *d, const hal_sample_t *in, hal_command_t *out);

/* The estimate of the last step (valid once the loop is closed). */
void paper001_drive_estimate(const paper001_drive_t *d, mc_estimate_t *e);

void paper001_drive_get_telemetry(const paper001_drive_t *d, paper001_telemetry_t *t);

/* Clears a latched fault by command: the drive starts again from its
 * initial state (the probe first). Returns what paper001_drive_init returns. */
bool paper001_drive_clear_fault(paper001_drive_t *d);

/* Commands (through the drive interface: paper001_ops.c). Each returns
 * false and changes nothing when refused.
 *
 * paper001_drive_set_enabled: false puts the drive in its safe state (0 V)
 * until enabled again; true after a disable starts it again as at
 * power-up (probe, open-loop start, the configured profile). Refused in
 * FAULT; enabling an enabled drive changes nothing. */
bool paper001_drive_set_enabled(paper001_drive_t *d, bool on);

/* Go to omega_rad_s at ramp_rad_s2 from where the reference is
 * (speed_profile_retarget); the ramp becomes the stop ramp. Refused while
 * disabled or faulted, when K_e |w| exceeds P001_CMD_VOLTAGE_SHARE of the
 * largest phase voltage the last measured bus gives (v_bus/sqrt(3) with
 * three legs, v_bus with H-bridges), and when the ramp exceeds the
 * acceleration i_max gives the model's inertia unloaded (K_t i_max/J). */
bool paper001_drive_set_speed(paper001_drive_t *d, mc_t omega_rad_s, mc_t ramp_rad_s2);

/* Stop: ramp to 0 at the stop ramp. Refused while faulted. */
bool paper001_drive_stop(paper001_drive_t *d);

/* The speed from which the back-EMF estimator's loop closes (estimator
 * BACK_EMF only). Refused with the flux estimator, in closed loop, and
 * below cfg.omega_lim_rad_s (the gains hold from there up). */
bool paper001_drive_set_omega_lim(paper001_drive_t *d, mc_t omega_lim_rad_s);

/* The flight recorder (supervisor/flight_recorder.h): ref = w*, est = the
 * estimator's angle (flux: the electrical angle in (-pi, pi]; back-EMF:
 * the mechanical angle estimate), speed = w_hat. */
static inline const flight_recorder_t *paper001_flight_recorder(const paper001_drive_t *d) { return &d->rec; }

#ifdef __cplusplus
}
#endif

#endif /* DRIVES_PAPER001_DRIVE_H */
