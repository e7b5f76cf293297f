/*
 * profile_design.h - a speed profile's configuration (trajectory/
 * speed_profile.h) from its corners in SI: ticks, slopes, segment lengths
 * and the reference angle at each corner, computed in double and folded
 * once. Shared by the speed drives' designs.
 */
#ifndef DESIGN_PROFILE_DESIGN_H
#define DESIGN_PROFILE_DESIGN_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "trajectory/speed_profile.h"

#ifdef __cplusplus
extern "C" {
#endif

/* n corners (t_s[k] [s], omega_rad_s[k] [rad/s]) at fs_hz (Ts = ts_s).
 * False, with *bad_t the offending corner time, when the times do not
 * start at 0 and increase or a speed is not finite; n must be 1..
 * SPEED_PROFILE_MAX_POINTS (checked by the caller, who names the field). */
bool speed_profile_design(speed_profile_config_t *pc, size_t n, const double *t_s, const double *omega_rad_s,
                          int32_t fs_hz, double ts_s, double *bad_t);

#ifdef __cplusplus
}
#endif

#endif /* DESIGN_PROFILE_DESIGN_H */
