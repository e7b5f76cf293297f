/*
 * encoder_angle.h - the rotor's angle from an encoder, as a rotor-angle
 * estimator (estimators/estimator.h): the sample's mechanical angle is the
 * measurement, its electrical angle the drive's frame (paper 002's
 * measured theta_r, Sec. 2). A sample without the encoder's angle is bad
 * input (needs_angle).
 */
#ifndef ESTIMATORS_ENCODER_ANGLE_H
#define ESTIMATORS_ENCODER_ANGLE_H

#include "estimators/estimator.h"
#include "estimators/rotor_angle.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    int32_t n_p; /* pole pairs */
} encoder_angle_t;

extern const estimator_ops_t encoder_angle_ops;

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_ENCODER_ANGLE_H */
