/*
 * speed_profile.h - a speed reference made of ramps and holds: corner
 * points (t_k, w_k), linear in between, held after the last. It is how
 * speed drives are commanded (a target and a ramp rate; paper 001's
 * benchmark, section 5.1, is such a profile) and gives the speed drive
 * w*, dw_ref/dt for the feed-forward and, for the open-loop start, the
 * angle it has turned since t = 0.
 *
 * Times are sample ticks, so the profile is exact in both builds: on
 * segment k, w* = w_k + (w_{k+1} - w_k) x with x = (tick - t_k)/(t_{k+1}
 * - t_k) (mc_ratio_i: one rounding), dw_ref/dt = the segment's slope (design
 * time), and the angle theta* = theta_k + T_k (w_k x + (w_{k+1} - w_k)
 * x^2/2), the exact integral of the line, T_k the segment length [s].
 * theta* is meant for the start-up: it stays inside Q14.17 for 16384 rad.
 */
#ifndef TRAJECTORY_SPEED_PROFILE_H
#define TRAJECTORY_SPEED_PROFILE_H

#include <stdbool.h>
#include <stdint.h>

#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SPEED_PROFILE_MAX_POINTS 16

typedef struct {
    uint32_t n_points;                              /* 1 .. SPEED_PROFILE_MAX_POINTS */
    int32_t fs_hz;                                  /* sample rate: ticks per second */
    uint32_t t_tick[SPEED_PROFILE_MAX_POINTS];      /* strictly increasing; t_tick[0] = 0 */
    mc_t omega_rad_s[SPEED_PROFILE_MAX_POINTS];     /* w at each corner (mechanical) */
    mc_t slope_rad_s2[SPEED_PROFILE_MAX_POINTS];    /* dw/dt after each corner (0 for the last) */
    mc_t length_s[SPEED_PROFILE_MAX_POINTS];        /* t_{k+1} - t_k [s] (0 for the last) */
    mc_t theta_rad[SPEED_PROFILE_MAX_POINTS];       /* integral of w from 0 to t_k */
} speed_profile_config_t;

typedef struct {
    mc_t omega_rad_s, accel_rad_s2, theta_rad;
} speed_point_t;

typedef struct {
    speed_profile_config_t cfg;
    uint32_t seg;                                   /* segment of the last evaluation */
} speed_profile_t;

/* Checks the configuration (count, increasing ticks); false if unusable. */
bool speed_profile_init(speed_profile_t *p, const speed_profile_config_t *cfg);

/* The reference at sample `tick` (ticks must not decrease between calls). */
void speed_profile_eval(speed_profile_t *p, uint32_t tick, speed_point_t *out);

/* A new target while running (a speed command): from sample `tick` (not
 * before the last evaluation) the reference ramps from where it is at
 * `tick` to omega_to_rad_s at ramp_rad_s2 (> 0) and holds there; the
 * corners before are dropped. w* and theta* stay continuous; dw/dt steps
 * to the ramp's. The ramp lasts round(|dw| fs / ramp) samples (at least
 * one), counted in whole and fractional seconds so that nothing
 * overflows: up to 6553.5 s. Returns false (nothing changed) for a ramp
 * <= 0 or a ramp longer than that. */
bool speed_profile_retarget(speed_profile_t *p, uint32_t tick, mc_t omega_to_rad_s, mc_t ramp_rad_s2);

#ifdef __cplusplus
}
#endif

#endif /* TRAJECTORY_SPEED_PROFILE_H */
