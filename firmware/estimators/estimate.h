/*
 * estimate.h - what every estimator produces, whatever its method: the
 * mechanical state a controller and the supervisor need. Paper 000's
 * back-EMF chain (fg_estimator.h), paper 001's flux and I&I observers and
 * paper 002's EKF each fill one of these per sample.
 */
#ifndef ESTIMATORS_ESTIMATE_H
#define ESTIMATORS_ESTIMATE_H

#include <stdbool.h>

#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    mc_t theta_rad;      /* mechanical angle [rad], unwrapped */
    mc_t omega_rad_s;    /* mechanical speed [rad/s] */
    mc_t accel_rad_s2;   /* mechanical acceleration [rad/s^2] */
    mc_t load_Nm;        /* load torque, including friction the model lacks [N m] */
    bool valid;          /* observable: usable for closed-loop control */
} mc_estimate_t;

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_ESTIMATE_H */
