/*
 * estimator.h - the one shape an estimator of the rotor's angle has, so
 * that a drive holds the estimator its configuration names and never asks
 * which one it is (issue 43). As a drive is a table of operations over its
 * state (drives/drive.h), an estimator is a table of operations over its
 * own state struct: init from its configuration, one sample in (the phase
 * currents and the HAL sample) and the electrical angle the drive runs on
 * out with the currents its loops should see, the mechanical angle and the
 * figures its supervisor checks, then the voltage applied over the coming sample in
 * (its time update), and a seed for hand-overs and restarts at a known
 * angle. What an estimator does beyond that (a start of its own that
 * commands the voltage, an injection on top of the command, a correction
 * of the speed reference) is an optional operation, NULL where it has none;
 * a drive calls it when present and never tests the estimator's kind.
 * Found by its family (the configuration type it takes) and the number
 * the drive's configuration holds (estimators/estimator_registry.h); added
 * with its files and its lines there. Nothing allocates: the drive owns
 * the state (estimator_storage_t). The family above is the rotor-angle
 * one (rotor_angle.h); the open-start family (open_start.h: angle, speed
 * and load from the currents, with an open-loop start) keeps only its
 * cold operations in this table (init, config_problem, report,
 * set_omega_lim) and runs its sample in line in the drive's step.
 *
 * Units: SI, angles in rad (electrical where named _e), currents in A,
 * voltages in V in the stator's alpha-beta frame.
 */
#ifndef ESTIMATORS_ESTIMATOR_H
#define ESTIMATORS_ESTIMATOR_H

#include <stdbool.h>
#include <stdint.h>

#include "adapter/phase_adapter.h"
#include "hal/hal_types.h"
#include "math/frame_fg.h"
#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One sample in. */
typedef struct {
    const hal_sample_t *sample; /* the whole sample: an encoder's angle (has_angle, angle_rad) */
    mc_t omega_hint_rad_s;      /* the drive's a priori mechanical speed: what an estimator schedules on */
    mc_t flux_ratio;            /* model_based: the flux radius the drive's motor model gives this
                                  * sample over the estimator's nominal one (1: nominal) */
    mc_t L_ratio;               /* model_based: the inductance this sample over the configured one;
                                  * 0: keep the configured (a linear motor model) */
} estimator_in_t;

/* One sample out. */
typedef struct {
    mc_t theta_rad;         /* the mechanical angle, wrapped into [-pi, pi): what a mechanical
                                  * observer downstream is given as its measurement */
    bool lock_checkable;    /* a model-based observer's angle is in use this sample: its residual
                                  * (rho2 against rho2_target) is a loss-of-lock criterion */
    mc_t rho2, rho2_target; /* lock_checkable only: that observer's consistency figure |rho|^2
                                  * and its target */
    mc_t u_reserve_V;       /* an estimator with an injection only: the amplitude it takes of the
                                  * voltage this sample (0 when off); the controller's limit is reduced
                                  * by it */
} estimator_out_t;

/* A start of the estimator's own (the angle unknown at power-up). */
typedef enum {
    EST_START_RUNNING = 0, /* still starting: *u_ab_V is this sample's voltage */
    EST_START_DONE = 1,    /* found: *theta_e_rad, *u_ab_V this sample's voltage; the drive seeds
                                  * the estimator (and its own observers) there */
    EST_START_REFUSED = 2  /* the angle could not be found: the drive must not run */
} estimator_start_t;

/* The configuration type an estimator takes: a drive picks among the
 * estimators of one family, whose configuration it carries. */
typedef enum {
    EST_FAMILY_ROTOR_ANGLE = 1, /* rotor_angle_config_t (estimators/rotor_angle.h) */
    EST_FAMILY_OPEN_START = 2   /* open_start_config_t (estimators/open_start.h) */
} estimator_family_t;

/* The open-start family's sample in and out (estimators/open_start.h). */
struct open_start_in;
struct open_start_report;

typedef struct estimator_ops {
    const char *name;          /* as in the docs and logs: "flux" */
    estimator_family_t family; /* the configuration type init takes */
    uint8_t id;                /* the number a drive's configuration holds for it (stable, per family) */
    uint32_t state_bytes;      /* sizeof the state struct */
    bool needs_angle;          /* a sample without an encoder angle is bad input */
    bool model_based;          /* reads estimator_in_t's flux_ratio and L_ratio */
    /* NULL if cfg is consistent, else its first problem: a literal naming the field (NULL op: init
     * alone decides) */
    const char *(*config_problem)(const void *cfg);
    /* validates cfg, resets every state; false: cfg refused (the state is then undefined) */
    bool (*init)(void *self, const void *cfg);
    /* true while a start of its own is still to run (NULL: never) */
    bool (*starting)(const void *self);
    /* one sample of that start (NULL: none) */
    estimator_start_t (*start)(void *self, mc_ab_t i_ab_A, mc_ab_t *u_ab_V, mc_t *theta_e_rad);
    /* a restart at the electrical angle theta_e_rad: at rest, its turn among the pole pairs unknown */
    void (*seed)(void *self, mc_t theta_e_rad);
    /* the measurement update of one sample: *i_ab_A this sample's phase currents (alpha-beta) in,
     * the currents the drive's loops see out (an injection's ripple removed); returns the
     * electrical angle the drive runs on this sample, cos and sin */
    mc_rot_t (*update)(void *self, const estimator_in_t *in, mc_ab_t *i_ab_A, estimator_out_t *out);
    /* the weight of the model-based observer in the angle, 0 (injection) .. 1 (NULL: always 1) */
    mc_t (*model_weight)(const void *self);
    /* the speed reference corrected (an angle hold; NULL: none), theta_hat_rad the drive's angle */
    mc_t (*reference)(void *self, mc_t omega_ref_rad_s, mc_t theta_hat_rad);
    /* the voltage to add to the command this sample (NULL: none) */
    mc_ab_t (*injection)(const void *self);
    /* the time update (NULL: none): u_mean_ab_V the voltage the motor sees over the coming sample
     * (the computation delay's mean), u_cmd_ab_V this sample's command, both without any injection */
    void (*hold)(void *self, mc_ab_t u_mean_ab_V, mc_ab_t u_cmd_ab_V);

    /* The open-start family's (estimators/open_start.h; NULL in the others). Its sample's
     * operations (measure, open loop, hold) are not here: a drive runs them in line, its step
     * instantiated per member (estimator_registry.h, OPEN_START_ESTIMATORS). */
    /* the estimate and the figures the status shows (closed: the drive's loop is closed) */
    void (*report)(const void *self, const struct open_start_in *in, bool closed, struct open_start_report *r);
    /* the speed from which the estimate is trusted, raised at run time (NULL: not settable);
     * false: refused (below the configured one) */
    bool (*set_omega_lim)(void *self, mc_t omega_lim_rad_s);
} estimator_ops_t;

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_ESTIMATOR_H */
