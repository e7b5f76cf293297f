/*
 * frame_fg.h - the rotating reference frame (f-g) of paper 000, eqs. (6)-(8),
 * and the rotations the observer and controller need.
 *
 * U(x) = [cos x, sin x; -sin x, cos x] maps phase (a-b) quantities into a
 * frame at electrical angle x. With x = n_p*theta_r it is the (f-g) frame of
 * eqs. (6)-(8); with x = n_p*(theta_est - theta_r) it maps (f-g) into the
 * estimated (d-q) frame of eq. (44). Callers pass sin/cos of x so that one
 * mc_sincos serves several transforms. Pure functions, no state.
 */
#ifndef MATH_FRAME_FG_H
#define MATH_FRAME_FG_H

#include "math/mc_num.h"

typedef struct {
    mc_t s; /* sin x */
    mc_t c; /* cos x */
} mc_rot_t;

static inline mc_rot_t mc_rot_from_angle(mc_t x_rad)
{
    mc_rot_t r;
    mc_sincos(x_rad, &r.s, &r.c);
    return r;
}

/* [y1; y2] = U(x) [x1; x2]   (eqs. (6)-(8), (44)) */
static inline void mc_rot_fwd(mc_rot_t r, mc_t x1, mc_t x2, mc_t *y1, mc_t *y2)
{
    *y1 = mc_dot2(r.c, x1, r.s, x2);
    *y2 = mc_cross2(r.c, x2, r.s, x1);
}

/* [y1; y2] = U(x)^T [x1; x2] = U(-x) [x1; x2], the inverse of mc_rot_fwd. */
static inline void mc_rot_inv(mc_rot_t r, mc_t x1, mc_t x2, mc_t *y1, mc_t *y2)
{
    *y1 = mc_cross2(r.c, x1, r.s, x2);
    *y2 = mc_dot2(r.s, x1, r.c, x2);
}

/* Rotation by x + y from the rotations by x and y (angle-sum formulas). */
static inline mc_rot_t mc_rot_compose(mc_rot_t x, mc_rot_t y)
{
    mc_rot_t r;
    r.s = mc_dot2(x.s, y.c, x.c, y.s);
    r.c = mc_cross2(x.c, y.c, x.s, y.s);
    return r;
}

/* Rotation by 2x from the rotation by x (double-angle formulas). */
static inline mc_rot_t mc_rot_double(mc_rot_t r)
{
    mc_rot_t d;
    d.s = mc_mul(MC_C(2.0), mc_mul(r.s, r.c));
    d.c = mc_cross2(r.c, r.c, r.s, r.s);
    return d;
}

#endif /* MATH_FRAME_FG_H */
