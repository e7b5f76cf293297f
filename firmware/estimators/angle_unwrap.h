/*
 * angle_unwrap.h - the unwrap operator A of paper 001, Appendix A, as it is
 * meant (errata): e = atan2(y, x) in (-pi, pi]; the difference of two
 * consecutive samples d = e[k] - e[k-1] beyond +-pi is a wrap of the
 * atan2, so the turn counter n moves by one:
 *   d < -pi  ->  n += 1,     d > pi  ->  n -= 1,
 * and the output y = e + 2 pi n is continuous. Remark 6 requires atan2 (a
 * one-argument arctan cannot tell opposite directions apart).
 *
 * The output is kept as the pair (n, e) rather than the sum, so it never
 * loses resolution or overflows however many turns the rotor makes (the
 * sum e + 2 pi n would leave the fixed-point range after about 2600 turns);
 * `delta` is the unwrapped change over the last sample, d wrapped into
 * [-pi, pi], which is all the I&I observer (15) needs of A's output.
 * Correct while |n_p omega Ts| < pi, i.e. below fs/(2 n_p) turns per second.
 */
#ifndef ESTIMATORS_ANGLE_UNWRAP_H
#define ESTIMATORS_ANGLE_UNWRAP_H

#include <stdint.h>

#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    mc_t e_rad;       /* atan2 of the last sample, (-pi, pi] */
    int32_t n_turns;  /* n of Appendix A */
    mc_t delta_rad;   /* y[k] - y[k-1], in [-pi, pi] */
} angle_unwrap_t;

/* Starts at the angle e0_rad (in (-pi, pi]) with n = 0. */
static inline void angle_unwrap_init(angle_unwrap_t *u, mc_t e0_rad)
{
    u->e_rad = e0_rad;
    u->n_turns = 0;
    u->delta_rad = MC_ZERO;
}

/* One sample of A(y/x) (Appendix A, errata form). */
static inline void angle_unwrap_step(angle_unwrap_t *u, mc_t y, mc_t x)
{
    const mc_t e = mc_atan2(y, x);
    mc_t d = mc_sub(e, u->e_rad);
    if (mc_lt(d, mc_neg(MC_PI))) {
        u->n_turns += 1;
        d = mc_add(d, MC_TWO_PI);
    } else if (mc_gt(d, MC_PI)) {
        u->n_turns -= 1;
        d = mc_sub(d, MC_TWO_PI);
    }
    u->e_rad = e;
    u->delta_rad = d;
}

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_ANGLE_UNWRAP_H */
