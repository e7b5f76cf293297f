/*
 * paper002_drive.h - paper 002's cascaded speed drive on an interior PMSM
 * with an encoder, as a composition of its blocks (estimators/ekf_ipmsm.h,
 * control/sosmc.h or control/htsmc.h, control/mtpa.h, control/ibcc.h,
 * trajectory/speed_poly.h). Per sample:
 *   0. with cfg.iron saturating (issue 31, beyond the paper;
 *      model/iron_model.h), at the EKF's a priori currents, the motor
 *      model's L_d, L_q set to the iron's incremental inductances (I1) on
 *      the injection and to its secant ones (S2) at speed, blended by the
 *      handover's weight w (the encoder and flux variants: secant), its
 *      psi so that psi + L_d i_d is the secant flux; the flux observer's
 *      L_q the secant one: every block below reads them; linear,
 *      untouched;
 *   1. the phase currents to alpha-beta, then to d-q with the encoder's
 *      electrical angle (the paper measures i_d, i_q and theta_r);
 *   2. the EKF's correction with them (40)-(44);
 *   3. the reference w_d, dw_d/dt; the torque demand from SOSMC (27)-(28)
 *      or HTSMC (29)-(35) on the EKF's speed, acceleration and disturbance;
 *   4. MTPA (15)/(18) and its torque inversion: i_dd, i_qd;
 *   5. the current control (9) with (3)'s coupling on the EKF's currents
 *      and speed, limited to the bus's v_bus/sqrt(3);
 *   6. the d-q voltage back to alpha-beta at the estimated electrical angle
 *      advanced to the middle of the sample it acts over ((1/2 + d) Ts
 *      with the board's computation delay d), min/max zero sequence to
 *      the three legs;
 *   7. the EKF's prediction (38)-(39) with the voltage the motor sees
 *      over the coming sample: with d > 0 the last command for d Ts and
 *      this one after, their mean in the frame of the sample's middle.
 * Faults (docs/faults.md) run through the guard every drive runs under
 * (supervisor/guard.h): counted in the flight recorder, then the reaction
 * table's SAFE (latched in the supervisor, 0 V until cleared) or REPORT;
 * the drive has no re-lock. The supervisor is in CLOSED_LOOP from the
 * first sample (the angle is measured, or observed from a known start)
 * until a fault. The set: the generic one of supervisor/fault_monitor.h (over-current, I^2 t,
 * voltage saturated too long, non-finite values, stuck or railed samples,
 * converter and hardware trips, overruns); a sample of the wrong phase
 * count or, with the encoder, without its angle (BAD_INPUT); and the loss
 * of the estimate or of the rotor: the EKF's angle innovation beyond
 * los_theta_rad for los_ticks samples, its innovation covariance no longer
 * positive definite, or its speed off the reference by more than
 * stall_tol |w_d| + stall_floor_rad_s for stall_ticks samples (a stalled
 * or runaway rotor; LOSS_OF_SYNC); with the flux observer (below) also the
 * loss of lock of supervisor/lock_monitor.h (LOSS_OF_LOCK), by either of
 * two criteria: the flux observer's residual along the estimated rotor
 * axis beyond the tolerance bound, the active flux's radius as the target
 * (a steady drift); or the EKF's angle innovation against the observer's
 * angle beyond 6 sigma of its variance S = P^-_thth + r_th plus the stall
 * band's speed error over a sample, by a leaky count (the chattering
 * limit cycle and the 180-degree flips this variant's losses are;
 * design/lock_monitor_design.c, design/paper002_design.c). Float only: the EKF's covariances do not fit
 * Q14.17 (docs/paper002.md).
 *
 * Angle source by configuration (cfg.angle_source), as paper 001's drive
 * chooses its estimator: with P002_ANGLE_FLUX (beyond the paper) no
 * encoder is read; paper 001's gradient flux observer (12)-(14)
 * (estimators/flux_observer.h) runs on the active flux, eta = lambda -
 * L_q i, which for a salient motor lies along the rotor's d axis with the
 * magnitude psi + (L_d - L_q) i_d (so its gradient term, which pulls |eta|
 * to psi, acts only radially and leaves the angle alone). Its angle,
 * unwrapped (estimators/angle_unwrap.h) and divided by p, is the EKF's
 * angle measurement in step 2 and the frame of step 1; the EKF stays the
 * speed and disturbance observer, so the cascade is unchanged. The
 * observer starts at cfg.flux_theta0_rad: the rotor's angle is known at
 * start (an alignment before the run); a flux observer has no
 * information at standstill and cannot find it.
 *
 * With P002_ANGLE_HFI (issue 31, beyond the paper) the angle at standstill
 * and low speed comes from the square-wave HF injection
 * (estimators/hf_injection.h) and the flux observer above takes over:
 *   - the injection's voltage (+-V_h on its estimated d axis) is added to
 *     the command; the controller's limit is v_bus/sqrt(3) - V_h while it
 *     injects; the EKF, the flux observer and the current loop see the
 *     fundamental only: the currents of (H5), the command without it;
 *   - the electrical angle is theta_hfi + w wrap(theta_flux - theta_hfi),
 *     w = 0 below hfi_blend_lo_rad_s of the EKF's |speed|, 1 above
 *     hfi_blend_hi_rad_s, linear between;
 *   - the injection goes off above hfi_off_rad_s and on again below
 *     hfi_on_rad_s (hysteresis; on < off, hi <= on: the blend is complete
 *     before it stops); off, its loop follows the flux observer's angle
 *     and the EKF's speed, on again it starts from them;
 *   - with w = 0 the flux observer is set to the injection's angle every
 *     sample (it has no information of its own there), so that it starts
 *     the blend from the right angle;
 *   - the loss-of-lock check of the flux observer runs only with the
 *     injection off;
 *   - an angle hold: at low speed the EKF's speed carries the bias of the
 *     motor model's errors (its R against a warm winding: the back-EMF it
 *     infers from u - R i), which a speed loop turns into a creep under
 *     load; the speed reference gets k (1 - w) wrap(hold - theta_hat),
 *     hold the integral of w_d from the start angle (following theta_hat
 *     once the blend is complete, so the hold fades in and out with the
 *     blend without a step).
 * It starts at cfg.flux_theta0_rad as the flux variant, unless
 * cfg.hfi_find_angle: then the start angle is unknown and the drive finds
 * it before it closes the speed loop (issue 31):
 *   1. LOCK: the injection alone (no current command) for hfi_lock_ticks;
 *      its PLL settles on the d axis, at theta or theta + pi (H2 is even in
 *      the polarity); the mean of its (H1) amplitude over the last
 *      hfi_lock_window samples below hfi_lock_amp_min (the estimate more
 *      than pi/4 off the d axis: near the unstable quadrature or still
 *      moving) and the drive refuses to run, DRIVE_FAULT_LOSS_OF_LOCK
 *      latched (criterion "hfi-unlocked"); then magpol.n_rest samples at 0
 *      V (the injection's ripple current decays: it would bias the test's
 *      first pulse);
 *   2. POLARITY: the injection off, the magnet polarity test
 *      (estimators/magnet_polarity.h) along the PLL's angle: +1 keep it,
 *      -1 flip it by pi, 0 (undecided: a plant whose saturation does not
 *      show the magnet) refuse to run: DRIVE_FAULT_LOSS_OF_LOCK latched
 *      (the safe state, whatever the reaction table; criterion
 *      "polarity-undecided", docs/faults.md), never a start that may run
 *      backwards;
 *   3. RUN: the injection, the flux observer and the EKF restarted at the
 *      angle found (mechanical: e/p, the turn among the n_p unknown and of
 *      no matter to a speed drive), the cascade as above.
 * The speed reference runs on the drive's sample count from power-up: the
 * start's samples come off the start of the profile.
 */
#ifndef DRIVES_PAPER002_DRIVE_H
#define DRIVES_PAPER002_DRIVE_H

#include <stdbool.h>
#include <stdint.h>

#include "control/deadtime_comp.h"
#include "control/htsmc.h"
#include "control/ibcc.h"
#include "control/mtpa.h"
#include "control/sosmc.h"
#include "estimators/ekf_ipmsm.h"
#include "estimators/flux_observer.h"
#include "estimators/estimator_registry.h"
#include "estimators/hf_injection.h"
#include "estimators/magnet_polarity.h"
#include "drives/drive.h"
#include "hal/hal_types.h"
#include "math/mc_num.h"
#include "model/iron_model.h"
#include "model/motor_model.h"
#include "supervisor/fault_monitor.h"
#include "supervisor/flight_recorder.h"
#include "supervisor/lock_monitor.h"
#include "supervisor/supervisor.h"
#include "trajectory/speed_poly.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum { P002_SOSMC = 0, P002_HTSMC = 1 } p002_controller_t;

/* Where the angle comes from. */
typedef enum {
    P002_ANGLE_ENCODER = 0, /* the paper: an encoder (hal_sample_t angle_rad) */
    P002_ANGLE_FLUX = 1,    /* sensorless: paper 001's flux observer on the active flux */
    P002_ANGLE_HFI = 2      /* sensorless from standstill: HF injection, the flux observer at speed */
} p002_angle_source_t;

typedef struct {
    motor_model_t model;           /* the one motor model: R, L_d, L_q, psi, n_p, J, f_v, Ts; every
                                    * block (EKF, SOSMC, HTSMC, MTPA, IBCC) reads it by const pointer
                                    * (first: its address is the drive's, no offset to add) */
    p002_controller_t controller;
    ekf_ipmsm_config_t ekf;
    sosmc_config_t sosmc;
    htsmc_config_t htsmc;
    mtpa_config_t mtpa;
    ibcc_config_t ibcc;
    speed_poly_t reference;
    mc_t i_trip_A;
    p002_angle_source_t angle_source;
    flux_observer_config_t flux;   /* angle_source = FLUX: (12)-(14) with L = L_q */
    mc_t flux_theta0_rad;          /* angle_source = FLUX: the rotor's (mechanical) angle at start */
    iron_model_config_t iron;      /* angle_source = FLUX, HFI: the iron's saturation the active flux
                                    * is taken with (model/iron_model.h); linear: L_q and psi + (L_d -
                                    * L_q) i_d, the paper's model */
    fault_monitor_config_t faults; /* the generic fault set */
    mc_t los_theta_rad;            /* loss of the estimate: |angle innovation| beyond this ... */
    int32_t los_ticks;             /* ... for this many consecutive samples */
    mc_t stall_tol, stall_floor_rad_s; /* |w_hat - w_d| > tol |w_d| + floor ... */
    int32_t stall_ticks;           /* ... for this many consecutive samples */
    lock_monitor_config_t lock;    /* angle_source = FLUX: loss of lock (supervisor/lock_monitor.h), the
                                    * flux observer's residual along the estimated rotor axis beyond the
                                    * tolerance bound (ticks 0: off), or the EKF's angle innovation by
                                    * the leaky count (innov_limit 0: off) (LOSS_OF_LOCK). The encoder
                                    * needs none */
    hf_injection_config_t hfi;     /* angle_source = HFI: the injection (estimators/hf_injection.h) */
    mc_t hfi_blend_lo_rad_s;       /* angle_source = HFI: |w_hat| (mechanical) where the blend to the */
    mc_t hfi_blend_hi_rad_s;       /* flux observer starts and where it is complete */
    mc_t hfi_off_rad_s;            /* angle_source = HFI: the injection off above this |w_hat| ... */
    mc_t hfi_on_rad_s;             /* ... and on again below this (hi <= on < off) */
    mc_t hfi_hold_gain_per_s;      /* angle_source = HFI: the angle hold's gain k (0: none) */
    bool hfi_find_angle;           /* angle_source = HFI: the start angle unknown: lock, polarity test, run */
    int32_t hfi_lock_ticks;        /* hfi_find_angle: samples of injection alone before the test (>= 1) */
    int32_t hfi_lock_window;       /* hfi_find_angle: the last samples of the lock whose (H1) amplitude is
                                    * averaged (1 .. hfi_lock_ticks) ... */
    mc_t hfi_lock_amp_min;         /* ... and the least mean that counts as locked (below: refused) */
    magnet_polarity_config_t magpol; /* hfi_find_angle: the polarity test */
    mc_t compute_delay;            /* d in [0, 1]: this step's voltage acts d Ts after the
                                    * currents were sampled (a DAC card ~0, an MCU's PWM 1) */
    deadtime_comp_config_t deadtime; /* the inverter's dead-time compensation
                                    * (control/deadtime_comp.h); disabled: none (no inverter) */
    uint8_t reaction[DRIVE_FAULT_COUNT]; /* fault_reaction_t per fault: SAFE or REPORT (RELOCK acts as SAFE) */
} paper002_config_t;

typedef struct {
    paper002_config_t cfg;
    ekf_ipmsm_t ekf;
    sosmc_t sosmc;
    htsmc_t htsmc;
    ibcc_t ibcc;
    deadtime_comp_t dtc;           /* cfg.deadtime */
    mc_t theta_prev_rad;           /* the EKF's angle (in [-pi, pi)) of the last step, or its start ... */
    int32_t theta_turns;           /* ... and its whole turns since: the estimate's unwrapped angle
                                    * theta_prev_rad + 2 pi theta_turns (estimators/estimate.h) */
    fault_monitor_t mon;
    fault_persist_t los, stall;
    lock_monitor_t lock;           /* a model-based angle (FLUX; HFI with the injection off) */
    mc_t iron_Lqs_H;               /* cfg.iron saturating: the secant L_qs of step 0 (the active flux's) */
    const estimator_ops_t *est;    /* the angle's estimator, cfg.angle_source's (estimators/estimator.h) */
    bool starting;                 /* its own start (hfi_find_angle) still runs */
    estimator_storage_t est_state; /* its state */
    mc_ab_t u_ab_prev_V;           /* the last command (acts for d Ts of the coming sample) */
    speed_poly_t reference;        /* the reference now: cfg.reference, or a commanded change */
    bool disabled;                 /* CmdEnable 0: 0 V until enabled */
    mc_t v_bus_V;                  /* the last measured bus (the speed command's check) */
    mc_t stop_ramp_rad_s2;         /* the last commanded ramp */
    mc_t theta_ref_rad;            /* the integral of w_d, wrapped (telemetry) */
    supervisor_t sup;              /* CLOSED_LOOP, or FAULT latched (sup.fault) */
    flight_recorder_t rec;         /* the last samples, frozen at the first fault (its tick) */
    uint32_t tick;
    /* the last step, for telemetry and logs */
    struct {
        mc_t w_d_rad_s, M_d_Nm, i_dd_A, i_qd_A, i_d_A, i_q_A, u_d_V, u_q_V;
        /* the EKF's a posteriori estimate of this sample */
        mc_t i_d_hat_A, i_q_hat_A, theta_hat_rad, w_hat_rad_s, M0_hat_Nm;
        mc_t theta_meas_rad;       /* the angle the EKF was given: the encoder's or the observer's */
        bool saturated;
    } last;
} paper002_drive_t;

/* The drive's operations (drives/drive.h), paper002_ops.c. */
extern const drive_ops_t paper002_drive_ops;

/* Validates cfg, copies it and resets every state. Returns false (drive in
 * FAULT, outputs 0 V) if cfg is inconsistent; paper002_config_problem says why. */
bool paper002_drive_init(paper002_drive_t *d, const paper002_config_t *cfg);

/* NULL if cfg is consistent, else its first problem: a literal naming the
 * field ("i_trip_A: must be > 0"). */
const char *paper002_config_problem(const paper002_config_t *cfg);

/* One sample: always fills *out (0 V in FAULT or disabled, the sample
 * counted); false in FAULT only. */
bool paper002_drive_step(paper002_drive_t *d, const hal_sample_t *in, hal_command_t *out);

/* Commands (through the drive interface: paper002_ops.c), between steps; false: refused, nothing
 * changed. */

/* The share of the phase voltage the back-EMF of a commanded speed may
 * take (as paper 001's drive: the rest is for the currents' dynamics). */
#define P002_CMD_VOLTAGE_SHARE MC_C(0.9)
/* The C^2 quintic's peak slope over its mean: a change dw over T peaks at
 * 1.875 dw / T (speed_poly.h: d/dx (10 x^3 - 15 x^4 + 6 x^5) at x = 1/2). */
#define P002_POLY_PEAK_OVER_MEAN MC_C(1.875)

/* Off: 0 V from the next step. On (after off): the drive starts again as
 * at power-up, its configured reference from the start. Refused in FAULT
 * (clear it first) and when nothing would change. */
bool paper002_drive_set_enabled(paper002_drive_t *d, bool on);

/* From the reference's present speed to omega_rad_s by the C^2 quintic,
 * its peak acceleration ramp_rad_s2 (the duration 1.875 |dw| / ramp).
 * Refused disabled or in FAULT, for ramp <= 0 or above K_t i_max / J (K_t
 * = 3/2 p psi), and when p psi |w| exceeds P002_CMD_VOLTAGE_SHARE of the
 * phase voltage the last measured bus gives. The ramp becomes the stop
 * ramp. */
bool paper002_drive_set_speed(paper002_drive_t *d, mc_t omega_rad_s, mc_t ramp_rad_s2);

/* To 0 at the last commanded ramp (at first K_t i_max / (4 J)). */
bool paper002_drive_stop(paper002_drive_t *d);

/* Clears a latched fault: the drive starts again as at power-up. Refused
 * without a fault. */
bool paper002_drive_clear_fault(paper002_drive_t *d);

#ifdef __cplusplus
}
#endif

#endif /* DRIVES_PAPER002_DRIVE_H */
