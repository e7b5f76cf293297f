/*
 * lock_monitor.h - loss of lock of a sensorless speed drive's estimate, by
 * named criteria, each computed from what its estimator can observe (the
 * thresholds are derived in the drive's design, design/lock_monitor_design.h;
 * docs/faults.md, "Loss of lock"). It only reports: the drive raises
 * DRIVE_FAULT_LOSS_OF_LOCK and its reaction table decides (supervisor.h).
 *
 * LOCK_CRIT_FLUX_RESIDUAL (gradient flux observer, paper 001 (12)-(14),
 * estimators/flux_observer.h; paper 001's drive and paper 002's sensorless
 * variant). The current model's residual along the estimated rotor axis:
 * with eta = lambda_hat - L i, the observer integrates v - R i and adds the
 * radial correction gamma eta (Phi^2 - |eta|^2) of (12), so in the
 * estimated d-q frame
 *   e_d = (v - R i - L di/dt) . rho_hat = Phi d|rho_hat|/dt - gamma Phi^3 |rho_hat| (target - |rho_hat|^2),
 * and in any steady state (|rho_hat| constant) the residual e_d, the
 * back-EMF component along the estimated d axis that the model does not
 * explain, is the observer's radial correction:
 *   e_d = gPhi3 |target - |rho_hat|^2|      (|rho_hat| = 1 within 1 % here).
 * A rotor at electrical speed w_e whose angle is off by delta shows
 * e_d = Phi w_e sin(delta); a rotor that turns while the estimate stands
 * still (the drift at standstill under load with a wrong R, ODrive's
 * "sensorless speed too low") shows Phi |w_e| along an axis that has
 * turned away. What a lock that holds may show is bounded by the
 * tolerances the design accepts:
 *   bound = k_speed |w_hat| + k_speed_cur |w_hat| |i| + k_cur |i| + floor
 * (k_speed: the tolerated angle error and flux error at the estimated
 * speed; k_speed_cur: the inductance error in the L di/dt of the turning
 * current; k_cur: the resistance error's R i; floor: the current sensing's
 * error in L i of (14)). e_d beyond the bound for `ticks` consecutive
 * samples is a loss of lock. At standstill the bound shrinks to k_cur |i|
 * + floor: the criterion is the "speed too low for the load, with the
 * estimate drifting" of the issue, observable as soon as the rotor's
 * motion moves the flux off the estimated circle.
 *
 * Not criteria here, and why: the flux magnitude far from Phi (|rho_hat|
 * outside [0.5, 1.5]) and the speed far from the reference stay the
 * drive's LOSS_OF_SYNC (they were there before and keep their codes);
 * a current-model residual in the tangential direction is not observable
 * (the observer integrates it into its angle: a wrong R turns the
 * estimate, which is why the drift at standstill is invisible to the
 * speed estimate).
 *
 * LOCK_CRIT_ANGLE_INNOVATION (a Kalman-type estimator that corrects its
 * angle with a measured or observed one: paper 002's EKF fed by the flux
 * observer's angle). The angle innovation nu = theta_meas - theta_hat^-
 * (the measurement minus the one-sample prediction) of a lock that holds
 * is the measurement noise, of variance S = P^-_thth + r_th (the
 * estimator's own), plus what the estimator's tolerated speed error
 * w_tol puts into the one-sample prediction, w_tol Ts (the drive passes
 * w_tol: the speed error it accepts from a lock, e.g. its stall band):
 *   nu^2 > innov_k2 S + (w_tol Ts)^2
 * is a sample beyond the bound (innov_k2 = k^2: k standard deviations of
 * the noise). A lost estimate does not drift: it chatters (the cascade's
 * limit cycle swings the estimated speed by hundreds of rad/s) and flips,
 * so its innovations leave the bound on a share of the samples, in bursts
 * of a few to a few hundred, not on every sample. The persistence is a
 * leaky count that survives that oscillation: +innov_up per sample
 * beyond, -1 per sample within, floored at 0 and held at innov_limit;
 * reaching innov_limit is the loss. It fires after innov_limit /
 * innov_up consecutive samples beyond the bound (the glitch a lock rides
 * out: one wild current sample turns the observed angle for a few
 * samples), and on intermittent losses as soon as more than 1 sample in
 * (innov_up + 1) is beyond for long enough; a full count drains in
 * innov_limit samples. The derivation: design/lock_monitor_design.c.
 * Not this criterion's: a drift slow enough for the estimator to follow
 * (its innovation stays at the noise; the flux residual above sees it).
 *
 * Fixed point: gPhi3 |target - rho2| <= 24.6 V x 3 for paper 001's motor,
 * the bound's terms are volts; every product is inside Q14.17. Paper
 * 002's sensorless variant (gPhi3 = 1 V, rho2 up to 2.89^2 at i_max) is
 * float only, as its drive.
 */
#ifndef SUPERVISOR_LOCK_MONITOR_H
#define SUPERVISOR_LOCK_MONITOR_H

#include <stdbool.h>
#include <stdint.h>

#include "math/mc_num.h"
#include "supervisor/fault_monitor.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    LOCK_CRIT_NONE = 0,
    LOCK_CRIT_FLUX_RESIDUAL = 1,   /* "flux-residual" (docs/faults.md): the flux observer's d-axis residual
                                    * beyond the tolerance bound */
    LOCK_CRIT_ANGLE_INNOVATION = 2 /* "angle-innovation": the estimator's angle innovation beyond its noise and
                                    * tolerance bound on more samples than a lock shows (leaky count) */
} lock_criterion_t;

typedef struct {
    mc_t gPhi3_V;          /* the flux observer's gamma Phi^3 [V]: e_d per unit of |target - |rho|^2| */
    mc_t k_speed_V_s;      /* bound per |w_hat| (mechanical rad/s) [V s/rad] */
    mc_t k_speed_cur_H;    /* bound per |w_hat| |i| [V s/(rad A)] */
    mc_t k_cur_ohm;        /* bound per |i| (d-q current magnitude) [V/A] */
    mc_t floor_V;          /* bound at rest without current [V] */
    int32_t ticks;         /* consecutive samples beyond the bound; 0: the monitor is off */
    /* LOCK_CRIT_ANGLE_INNOVATION (innov_limit 0: off) */
    mc_t innov_k2;         /* k^2: the bound's noise part in units of the innovation's variance S [-] */
    mc_t ts_s;             /* the sample time: the tolerated speed error's angle over one prediction [s] */
    int32_t innov_up;      /* added per sample beyond the bound (1 removed per sample within) */
    int32_t innov_limit;   /* the count that is a loss; 0: the criterion is off */
} lock_monitor_config_t;

typedef struct {
    lock_monitor_config_t cfg;
    fault_persist_t run;
    mc_t residual_V;       /* the last sample's e_d */
    mc_t bound_V;          /* and its bound */
    int32_t innov_count;   /* LOCK_CRIT_ANGLE_INNOVATION's leaky count, in [0, innov_limit] */
    mc_t innov_ratio;      /* the last sample's nu^2 over its bound^2 (> 1: beyond) */
} lock_monitor_t;

void lock_monitor_init(lock_monitor_t *m, const lock_monitor_config_t *cfg);

/* One sample of LOCK_CRIT_FLUX_RESIDUAL, while the drive uses the estimate
 * (closed loop): rho2 = |rho_hat|^2 and rho2_target (1, or the active
 * flux's, flux_observer_t), the estimated mechanical speed, the current in
 * the estimated d-q frame. Returns the criterion that holds for
 * cfg.ticks samples, else LOCK_CRIT_NONE. Reads and changes nothing else. */
lock_criterion_t lock_monitor_step_flux(lock_monitor_t *m, mc_t rho2, mc_t rho2_target, mc_t omega_hat_rad_s,
                                        mc_t i_d_A, mc_t i_q_A);

/* One sample of LOCK_CRIT_ANGLE_INNOVATION, after the estimator's
 * correction: its angle innovation nu_rad, the innovation's variance
 * s_rad2 (C P^- C^T + R for the angle, >= 0), the speed error the drive
 * accepts from a lock now, omega_tol_rad_s (>= 0; the angle's unit per
 * second). Returns LOCK_CRIT_ANGLE_INNOVATION while the leaky count is at
 * innov_limit, else LOCK_CRIT_NONE (always NONE with innov_limit 0).
 * Float in practice: S of a 1e-4 rad sensor (1e-8 rad^2) is below
 * Q14.17's resolution, so a fixed-point build would need nu and S scaled
 * by the drive first (no fixed-point drive uses it). */
lock_criterion_t lock_monitor_step_innovation(lock_monitor_t *m, mc_t nu_rad, mc_t s_rad2, mc_t omega_tol_rad_s);

#ifdef __cplusplus
}
#endif

#endif /* SUPERVISOR_LOCK_MONITOR_H */
