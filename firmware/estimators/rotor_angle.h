/*
 * rotor_angle.h - the configuration the rotor-angle estimators of a PM
 * motor share (estimators/estimator.h): an encoder (encoder_angle.h),
 * paper 001's flux observer on the active flux (flux_angle.h), and the HF
 * injection handing over to that observer (hfi_angle.h). One type for the
 * three, so that a drive carries one configuration whichever its
 * configuration names; each reads the part it needs.
 */
#ifndef ESTIMATORS_ROTOR_ANGLE_H
#define ESTIMATORS_ROTOR_ANGLE_H

#include <stdbool.h>
#include <stdint.h>

#include "estimators/flux_observer.h"
#include "estimators/hf_injection.h"
#include "estimators/magnet_polarity.h"
#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The estimators' numbers (estimator_ops_t.id): a drive's configuration
 * holds one (paper 002's angle_source). */
enum { ROTOR_ANGLE_ENCODER = 0, ROTOR_ANGLE_FLUX = 1, ROTOR_ANGLE_HFI = 2 };

typedef struct {
    int32_t n_p;                     /* pole pairs */
    mc_t ts_s;                       /* the sample period Ts */
    mc_t theta0_rad;                 /* flux, HFI: the rotor's (mechanical) angle at start */
    flux_observer_config_t flux;     /* flux, HFI: (12)-(14) of paper 001 with L = L_q */
    hf_injection_config_t hfi;       /* HFI: the injection (estimators/hf_injection.h) */
    mc_t hfi_blend_lo_rad_s;         /* HFI: |w_hat| (mechanical) where the blend to the flux observer */
    mc_t hfi_blend_hi_rad_s;         /* starts and where it is complete */
    mc_t hfi_off_rad_s;              /* HFI: the injection off above this |w_hat| ... */
    mc_t hfi_on_rad_s;               /* ... and on again below this (lo < hi <= on < off) */
    mc_t hfi_hold_gain_per_s;        /* HFI: the angle hold's gain k (0: none) */
    bool hfi_find_angle;             /* HFI: the start angle unknown: lock, polarity test, run */
    int32_t hfi_lock_ticks;          /* hfi_find_angle: samples of injection alone before the test (>= 1) */
    int32_t hfi_lock_window;         /* hfi_find_angle: the last samples of the lock averaged (1 .. hfi_lock_ticks) */
    mc_t hfi_lock_amp_min;           /* hfi_find_angle: the least mean (H1) amplitude that counts as locked */
    magnet_polarity_config_t magpol; /* hfi_find_angle: the polarity test */
} rotor_angle_config_t;

/* The problem every estimator of the family checks (estimator.h's
 * config_problem): NULL, or the literal naming the field. */
const char *rotor_angle_problem(const void *cfg);

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_ROTOR_ANGLE_H */
