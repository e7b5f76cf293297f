/*
 * step_shaper.h - a step/dir input made a position target a position
 * drive can follow: the count of steps times the step angle is the target
 * (absolute, from the count's zero), reached by rest-to-rest moves of the
 * drive's move command (drives/drive.h DRIVE_CMD_MOVE: eq. (70) of paper
 * 000, the 7th-order polynomial p(s) = 35 s^4 - 84 s^5 + 70 s^6 - 20 s^7
 * over the move's duration T), each as short as the drive's design allows
 * and no shorter: for a distance d its peak speed (35/16) |d|/T (p'(1/2)
 * = 35/16) at most the design's w_max and its peak acceleration 7.5132
 * |d|/T^2 (max |p''|) at most a_max (paper000_drive.h, paper000_drive_move:
 * the limits it checks; design/paper000_design.c derives them from the
 * [bounds] of the drive's scenario), so
 *     T = max((35/16) |d|/w_max, sqrt(7.5132 |d|/a_max)) + 2 Ts
 * (two samples of margin against the rounding of the drive's check).
 * Why moves of eq. (70) rather than a trapezoid: paper 000's references are
 * flat outputs whose derivatives the tracking law (38)-(57) uses; its gains
 * are designed for eq. (70)'s smooth references within w_max and a_max,
 * and the drive takes no other (a jerk step is what paper000_drive_stop
 * refuses to make). While a move runs, new steps wait; the next move takes
 * all of them (at most max_move_steps). A step train faster than the
 * moves can follow is followed at the limit (each move peaking at w_max)
 * and nothing is lost: the target is the count.
 *
 * The limit as a rate: moves chained back to back, each peaking at w_max,
 * advance on average by w_max / (35/16) (the mean of eq. (70)'s speed is
 * 16/35 of its peak); a faster train grows the backlog without bound. The
 * steps beyond that rate are counted, excess_steps, as a token bucket
 * does: every sample adds rate = w_max / ((35/16) phi f_s) steps of credit
 * (phi the step angle, f_s the sample rate), up to a bucket of
 * STEP_SHAPER_BUCKET_STEPS steps; each step takes one; a step without
 * credit is an excess step. In 1/1024-step integers: exact in both
 * numeric builds.
 *
 * Inputs each sample: the step count (signed, from step/dir hardware),
 * the drive's answer to the last offered move. Output: a move to offer
 * (theta_to_rad, duration_s) or none. Fixed point: the target count times
 * phi must stay within mc_t's range (Q14.17: 16384 rad, 2,600 turns), and
 * phi is held to 2^-17 rad: 1/16 microsteps of a 200-step motor (phi =
 * 1.96e-3 rad, 257 units) round by 0.2 %; finer microsteps want the float
 * build (the STM32F405 images are float).
 */
#ifndef TRAJECTORY_STEP_SHAPER_H
#define TRAJECTORY_STEP_SHAPER_H

#include <stdbool.h>
#include <stdint.h>

#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

/* eq. (70)'s peak speed and peak acceleration factors (paper000_drive.h) */
#define STEP_SHAPER_PEAK_SPEED MC_C(2.1875)
#define STEP_SHAPER_PEAK_ACCEL MC_C(7.5132)
/* the token bucket: one step plus one of jitter of the sender's timing */
#define STEP_SHAPER_BUCKET_STEPS 2
/* credit in 1/STEP_SHAPER_CREDIT_UNIT of a step */
#define STEP_SHAPER_CREDIT_UNIT 1024
/* the longest move: CmdMove's duration field ends at 65.535 s
 * (tools/can/drive.dbc); 30 s leaves room */
#define STEP_SHAPER_MOVE_MAX_S MC_C(30.0)

typedef struct {
    mc_t step_angle_rad;      /* phi: the target moves this much a step (> 0) */
    mc_t speed_max_rad_s;     /* w_max: the drive's move_speed_max_rad_s */
    mc_t accel_max_rad_s2;    /* a_max: the drive's move_accel_max_rad_s2 */
    int32_t fs_hz;            /* samples per second (> 0) */
} step_shaper_config_t;

typedef struct {
    step_shaper_config_t cfg;
    mc_t ts_s;                 /* 1 / fs */
    int32_t rate_credit;       /* credit a sample, 1/1024 step */
    int32_t max_move_steps;    /* the longest move, in steps */
    int32_t count_last;        /* the count at the last step */
    int32_t count_moved;       /* where the last accepted move ends, in steps */
    int32_t count_offered;     /* where the offered move ends */
    bool offered;              /* a move was offered this sample */
    int32_t credit;            /* 1/1024 step, 0 .. bucket */
    uint32_t excess_steps;     /* steps beyond the limit since init (wraps) */
    uint32_t moves;            /* moves accepted */
} step_shaper_t;

typedef struct {
    bool move;                 /* offer this move to the drive */
    mc_t theta_to_rad, duration_s;
} step_shaper_move_t;

/* Checks cfg (all > 0, the rate and the longest move representable);
 * false (and the shaper offers nothing) if not. The count starts at
 * count0 (the hardware's at start), the drive resting at count0 phi. */
bool step_shaper_init(step_shaper_t *s, const step_shaper_config_t *cfg, int32_t count0);

/* One sample: the step count now, and theta_rest_rad, where the drive's
 * reference rests or goes (its status' theta_ref_rad: the move's distance
 * is measured from there, CAN moves included). *out a move to offer when
 * steps arrived since the last accepted move, else none. */
void step_shaper_step(step_shaper_t *s, int32_t count, mc_t theta_rest_rad, step_shaper_move_t *out);

/* The drive's answer to the move offered this sample: accepted, the
 * count it ends at is where the reference goes; refused (a move still
 * running, the drive aligning or disabled), offered again next sample. */
void step_shaper_answer(step_shaper_t *s, bool accepted);

/* Steps received but not yet in an accepted move. */
static inline int32_t step_shaper_backlog(const step_shaper_t *s) { return s->count_last - s->count_moved; }

#ifdef __cplusplus
}
#endif

#endif /* TRAJECTORY_STEP_SHAPER_H */
