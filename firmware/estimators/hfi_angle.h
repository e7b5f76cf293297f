/*
 * hfi_angle.h - the rotor's angle from standstill: the square-wave HF
 * injection (estimators/hf_injection.h) at and near zero speed, handing
 * over to the flux observer on the active flux (flux_angle.h) at speed,
 * as a rotor-angle estimator (estimators/estimator.h; issue 31, beyond
 * paper 002). Per sample (update):
 *   - the injection goes off above cfg.hfi_off_rad_s of the drive's |speed|
 *     and on again below cfg.hfi_on_rad_s (hysteresis); off, its loop follows
 *     the flux observer's angle and the drive's speed, on again it starts
 *     from them;
 *   - the loops see the fundamental current (H5), the flux observer too;
 *   - the electrical angle is theta_hfi + w wrap(theta_flux - theta_hfi),
 *     w = 0 below cfg.hfi_blend_lo_rad_s of |speed|, 1 above hfi_blend_hi_rad_s,
 *     linear between; with w = 0 the flux observer is set to the
 *     injection's angle (it has no information of its own there) at the
 *     active flux's radius, so that it starts the blend from it;
 *   - the flux observer's loss-of-lock check applies with the injection
 *     off (lock_checkable);
 *   - the injection's voltage goes on top of the command (injection), and
 *     its amplitude is kept free of the controller's (u_reserve_V).
 * The angle hold (reference): at low speed a mechanical observer's speed
 * carries the bias of the motor model's errors, which a speed loop turns
 * into a creep under load; the speed reference gets k (1 - w)
 * wrap(hold - theta_hat), hold the integral of the reference from the
 * start angle (following theta_hat once the blend is complete).
 * With cfg.hfi_find_angle the start angle is unknown and the start (start)
 * finds it: LOCK, the injection alone for hfi_lock_ticks (its PLL settles on
 * the d axis, at theta or theta + pi); the mean (H1) amplitude over the
 * last hfi_lock_window samples below hfi_lock_amp_min refuses (the estimate more
 * than pi/4 off the d axis); then magpol.n_rest samples at 0 V; POLARITY,
 * the magnet polarity test (estimators/magnet_polarity.h) along the PLL's
 * angle: +1 keep, -1 flip by pi, 0 refuse (never a start that may run
 * backwards); then the drive seeds everything at the angle found.
 */
#ifndef ESTIMATORS_HFI_ANGLE_H
#define ESTIMATORS_HFI_ANGLE_H

#include "estimators/estimator.h"
#include "estimators/flux_angle.h"
#include "estimators/hf_injection.h"
#include "estimators/magnet_polarity.h"
#include "estimators/rotor_angle.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum { HFI_ANGLE_LOCK = 0, HFI_ANGLE_POLARITY = 1, HFI_ANGLE_RUN = 2 } hfi_angle_phase_t;

typedef struct {
    flux_angle_t fa;          /* the observer it hands over to */
    hf_injection_t hfi;       /* the injection */
    magnet_polarity_t magpol; /* hfi_find_angle: the test */
    rotor_angle_config_t cfg; /* the speeds, the hold, the lock (the configuration as given) */
    mc_t weight;              /* the blend's w, 0 injection .. 1 flux observer */
    mc_t hold_rad;            /* the held (mechanical) angle */
    hfi_angle_phase_t phase;  /* hfi_find_angle: LOCK, POLARITY, then RUN (else RUN from init) */
    int32_t start_k;          /* samples within the LOCK phase */
    int32_t polarity;         /* the test's result once done: +1 kept, -1 flipped, 0 undecided/not run */
    mc_t lock_amp;            /* the lock's mean (H1) amplitude over its window (the running sum
                                    * until the lock ends) */
} hfi_angle_t;

extern const estimator_ops_t hfi_angle_ops;

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_HFI_ANGLE_H */
