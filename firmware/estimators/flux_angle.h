/*
 * flux_angle.h - the rotor's angle from paper 001's gradient flux observer
 * (12)-(14) (estimators/flux_observer.h) run on the active flux, as a
 * rotor-angle estimator (estimators/estimator.h). For a salient motor the
 * active flux eta = lambda - L_q i lies along the rotor's d axis with the
 * magnitude psi + (L_d - L_q) i_d, so with L = L_q in (14) and that
 * magnitude as the gradient term's target (estimator_in_t.flux_ratio, from
 * the drive's motor model) the term acts only radially and leaves the
 * angle alone. Its angle is unwrapped (Appendix A of paper 001,
 * estimators/angle_unwrap.h) and divided by n_p, plus the start's turn
 * among the pole pairs (theta0 - e0/n_p), for the mechanical angle. The
 * observer starts at cfg.theta0_rad: a flux observer has no information at
 * standstill and cannot find the angle (hfi_angle.h can).
 */
#ifndef ESTIMATORS_FLUX_ANGLE_H
#define ESTIMATORS_FLUX_ANGLE_H

#include "estimators/angle_unwrap.h"
#include "estimators/estimator.h"
#include "estimators/flux_observer.h"
#include "estimators/rotor_angle.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    flux_observer_t flux;         /* (12)-(14) on the active flux */
    flux_observer_config_t flux0; /* its configuration as given (L = L_q of the linear model) */
    angle_unwrap_t unwrap;        /* the observer's angle, unwrapped */
    mc_t theta_offset_rad;        /* theta0 - e0/n_p: a multiple of 2 pi/n_p */
    int32_t n_p;
} flux_angle_t;

extern const estimator_ops_t flux_angle_ops;

/* The parts hfi_angle.h shares. Init at the mechanical angle theta0_rad. */
void flux_angle_reset(flux_angle_t *o, const rotor_angle_config_t *cfg);
/* At rest at the electrical angle e (the turn among the n_p: 0). */
void flux_angle_seed(flux_angle_t *o, mc_t theta_e_rad);
/* The observer's L and target from the drive's motor model (in->L_ratio,
 * in->flux_ratio), before its step. */
void flux_angle_model(flux_angle_t *o, const estimator_in_t *in);
/* The electrical angle r unwrapped: the mechanical angle, wrapped into [-pi, pi). */
mc_t flux_angle_mechanical(flux_angle_t *o, mc_rot_t r);

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_FLUX_ANGLE_H */
