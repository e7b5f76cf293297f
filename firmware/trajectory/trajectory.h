/*
 * trajectory.h - chained rest-to-rest moves of paper 000, eq. (70) (errata:
 * theta_r = theta_i + (theta_f - theta_i)(35D^4 - 84D^5 + 70D^6 - 20D^7),
 * D = (t - t_i)/(t_f - t_i)), which has zero velocity, acceleration and jerk
 * at both ends (69). Each segment starts where the previous one ended and
 * the reference holds between segments. The evaluation returns the
 * derivatives the flatness references (38)-(39) need. Time is an integer
 * sample count so that long runs lose no resolution.
 */
#ifndef TRAJECTORY_TRAJECTORY_H
#define TRAJECTORY_TRAJECTORY_H

#include <stdbool.h>
#include <stdint.h>

#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TRAJECTORY_MAX_SEGMENTS 8

typedef struct {
    uint32_t start_tick;
    uint32_t duration_ticks;   /* > 0 */
    mc_t theta_to_rad;
    /* Derived by trajectory_init when left at 0 (or at design time, in
     * double): with delta = theta_f - theta_i and T the duration,
     * delta/T^n for n = 1..3 [rad/s], [rad/s^2], [rad/s^3], and the
     * coefficients of theta_r = theta_mid + x (c0 - x^2 (c1 - x^2 (c2 -
     * c3 x^2))), x = D - 1/2: c0..c3 = delta (35/16, 35/4, 21, 20),
     * theta_mid = theta_i + delta/2. Multiplying delta in before x keeps
     * the position to a few LSB in fixed point (p(D) alone would not).
     * j_scale (the jerk's) is derived but read by no block: the drive takes
     * the jerk term of (39) as the change of the references over the
     * sample (fg_tracking_references). */
    mc_t v_scale, a_scale, j_scale;
    mc_t c0, c1, c2, c3, theta_mid_rad;
} trajectory_segment_t;

typedef struct {
    int32_t fs_hz;        /* sample rate */
    mc_t theta_start_rad; /* reference before the first segment */
    int32_t n_segments;
    trajectory_segment_t seg[TRAJECTORY_MAX_SEGMENTS]; /* sorted, non-overlapping */
} trajectory_config_t;

typedef struct {
    mc_t theta_rad, omega_rad_s, accel_rad_s2;
} trajectory_point_t;

typedef struct {
    trajectory_config_t cfg;
    mc_t theta_from_rad[TRAJECTORY_MAX_SEGMENTS]; /* start of each segment */
} trajectory_t;

/* Checks ordering and durations, derives the per-segment scales. Pass the
 * per-segment ratios precomputed (design time) or leave them 0 to have them
 * derived here with mc arithmetic (see trajectory_segment_t). Returns false on an invalid config. */
bool trajectory_init(trajectory_t *t, const trajectory_config_t *cfg);

/* Reference and its first two derivatives at sample `tick`. */
void trajectory_eval(const trajectory_t *t, uint32_t tick, trajectory_point_t *out);

/* The normalised polynomial and its derivatives w.r.t. D at D in [0, 1]:
 * p, p', p'', p'''. For the sensored drive's moves, tests and tools:
 * trajectory_eval folds the segment's scale in before rounding. */
void trajectory_poly7(mc_t D, mc_t *p, mc_t *dp, mc_t *ddp, mc_t *dddp);


#ifdef __cplusplus
}
#endif

#endif /* TRAJECTORY_TRAJECTORY_H */
