/*
 * open_start.h - the family of estimators (estimators/estimator.h) that
 * give a PM motor's (or a stepper's) angle, speed and load from its phase
 * currents alone and need an open-loop start to become observable: paper
 * 001's gradient flux observer with its I&I speed and load observer
 * (flux_speed.h), and paper 000's back-EMF chain in the (f-g) frame of the
 * open-loop vector (emf_speed.h). Such an estimator decides when its
 * estimate is trusted and raises the supervisor's events itself
 * (ESTIMATE_TRUSTED, ESTIMATE_LOST on open_start_in_t.sup): the hand-over
 * is the estimator's, as its start (paper 001's probe and circle fit) is.
 * The drive gives it one sample (open_start_in_t), runs its law in the
 * estimator's frame on what it returns (open_start_out_t), asks it for the
 * open-loop vector in that frame while the loop is open, and tells it the
 * voltage the motor saw. Every member shares open_start_config_t.
 *
 * The sample's operations are in line in each member's header, with these
 * signatures (prefix the member's, estimator_registry.h lists them):
 *   void prefix_measure_op(void *self, const open_start_in_t *in, open_start_out_t *out);
 *       one sample: the measurement, the start, the hand-over (the
 *       supervisor's events raised on in->sup), the currents, speed and
 *       load the law runs on and the frame it runs in;
 *   void prefix_open_loop_op(const void *self, const open_start_in_t *in, mc_t v_V, mc_t *v_d_V, mc_t *v_q_V);
 *       while the loop is open: the open-loop vector of magnitude v_V
 *       along the angle the start found turned by the reference (or, with
 *       out->own_vector, the start's own), in the estimator's frame;
 *   void prefix_hold_op(void *self, const open_start_in_t *in, mc_ab_t u_mean_ab_V, mc_t u_d_V, mc_t u_q_V);
 *       the time update: u_mean_ab_V the voltage the motor sees over the
 *       coming sample, u_d_V, u_q_V this sample's command in the
 *       estimator's frame as the limiter left it (what the motor sees if
 *       in->frame_voltage_applied); empty for an estimator whose next
 *       measure integrates in->u_held_ab_V.
 * The drive instantiates its step once per member with them (a call
 * through a table costs the control step what the inlining of its
 * blocks saved: issue 43 measured +60 instructions on the M4F).
 *
 * Units: SI, angles in rad (electrical where named _e), currents in A,
 * voltages in V.
 */
#ifndef ESTIMATORS_OPEN_START_H
#define ESTIMATORS_OPEN_START_H

#include <stdbool.h>
#include <stdint.h>

#include "estimators/estimate.h"
#include "estimators/estimator.h"
#include "estimators/fg_estimator.h"
#include "estimators/flux_observer.h"
#include "estimators/resistance_tracker.h"
#include "estimators/speed_load_observer.h"
#include "math/mc_num.h"
#include "model/motor_model.h"
#include "startup/flux_circle_fit.h"
#include "supervisor/supervisor.h"
#include "trajectory/speed_profile.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The estimators' numbers (estimator_ops_t.id): a drive's configuration
 * holds one (paper 001's estimator). */
enum { OPEN_START_FLUX = 0, OPEN_START_BACK_EMF = 1 };

typedef struct {
    motor_model_t model; /* R, L, K_e = n_p Phi, n_p, fs: the drive's motor */
    /* flux (and the probe of either) */
    flux_observer_config_t flux;        /* paper 001 (12)-(14) */
    resistance_tracker_config_t rtrack; /* R of (12) tracked on line in closed loop; disabled: the model's */
    speed_load_observer_config_t speed; /* paper 001 (15)-(16) */
    flux_circle_fit_config_t fit;       /* the observer's initial error from the open-loop motion */
    mc_t handover_sweep_rad;            /* electrical angle the open loop turns before the hand-over */
    uint32_t probe_ticks;               /* longest start-up probe (0: none) */
    uint32_t probe_turn_ticks;          /* longest time along alpha */
    mc_t probe_v_V;                     /* the probe's standstill vector */
    mc_t probe_step2;                   /* squared spacing of the probe's fit points (scaled units) */
    mc_t probe_turn2;                   /* squared chord at which the probe's vector turns (scaled units) */
    flux_circle_fit_config_t probe_fit; /* the through-origin fit of the probe's short arc */
    mc_t advance_np;                    /* n_p (1/2 + d): the output angle's lead per unit of w_hat Ts
                                         * (the voltage acts on average that late, d the drive's delay) */
    /* back-EMF only */
    fg_estimator_config_t emf;      /* paper 000's estimator gains (design/paper000_design.h) */
    motor_model_t emf_torque_model; /* the model with K = K_t: the torque of (33)-(37) */
    mc_t omega_lim_rad_s;           /* |w*| from which the back-EMF angle is trusted (paper 000 4.2) */
} open_start_config_t;

/* One sample in. The drive keeps it in its state: report reads it too. */
typedef struct open_start_in {
    supervisor_t *sup;          /* the drive's: the estimator raises ESTIMATE_TRUSTED / _LOST on it */
    uint32_t tick;              /* samples since init */
    mc_ab_t i_ab_A;             /* this sample's currents */
    mc_ab_t u_held_ab_V;        /* the voltage the motor saw on average over the last sample */
    speed_point_t ref;          /* this sample's reference: w_ref, its slope, theta_ref */
    speed_profile_t *profile;   /* the reference itself: an estimator that needs the next sample's
                                 * theta* evaluates it (speed_profile_eval at tick + 1) */
    bool frame_voltage_applied; /* the command in the estimator's frame is what the motor sees: no
                                 * dead-time compensation, no computation delay */
} open_start_in_t;

/* One sample out. */
typedef struct open_start_out {
    bool switched;             /* the estimator moved the supervisor between open and closed loop */
    bool own_vector;           /* open loop: the estimator's start commands its own vector (a probe);
                                * the drive's open-loop magnitude is not asked */
    mc_t i_d_A, i_q_A;         /* the currents in the estimator's frame: the law's */
    mc_t omega_rad_s, load_Nm; /* closed loop: the law's speed and load estimates */
    bool law_turned;           /* closed loop: the law's voltage is turned by law_rot into the */
    mc_rot_t law_rot;          /* estimator's frame (paper 000's estimated frame (44) into (f-g)) */
    mc_rot_t out_rot;          /* the estimator's frame to alpha-beta, for this sample's voltage */
    mc_t omega_own_rad_s;      /* the estimator's own speed and electrical angle (a lost */
    mc_t theta_e_own_rad;      /* estimate's criteria, the flight recorder) */
    bool lock_checkable;       /* rho2 against rho2_target is a loss-of-lock criterion */
    mc_t rho2, rho2_target;
} open_start_out_t;

/* What the status and telemetry show. */
typedef struct open_start_report {
    mc_estimate_t est; /* the estimate (valid in closed loop) */
    int32_t theta_e_turns;
    mc_t theta_e_rad; /* the electrical angle as (turns, angle in (-pi, pi]) */
    mc_t omega_rad_s; /* the estimator's own speed and load */
    mc_t load_Nm;
    mc_t rho2;      /* |rho_hat|^2 of the flux observer (1 when consistent) */
    mc_t R_obs_ohm; /* the R the flux observer subtracts */
} open_start_report_t;

/* The problem every estimator of the family checks (estimator.h's
 * config_problem): NULL, or the literal naming the field as paper 001's
 * configuration holds it (under est). */
const char *open_start_problem(const void *cfg);

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_OPEN_START_H */
