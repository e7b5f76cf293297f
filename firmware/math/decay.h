/*
 * decay.h - one step of an exponential decay toward 0, for the offsets
 * that make a switch bumpless (supervisor, controllers).
 */
#ifndef MATH_DECAY_H
#define MATH_DECAY_H

#include "math/mc_num.h"

/* Below this magnitude [V or A] a decaying offset is snapped to 0: it then
 * costs nothing and cannot stall on a rounding fixed point of the product
 * (in Q14.17 x * factor rounds back to x for |x| below about half an LSB
 * over (1 - factor)). 1e-4 V is 3 parts per million of the paper's 30 V
 * and 1e-4 A is 30 ppm of its 3 A: far below the sensor noise. */
#define MC_DECAY_SNAP MC_C(1e-4)

/* x * factor, or 0 when that is below MC_DECAY_SNAP. factor = exp(-Ts/tau). */
static inline mc_t mc_decay(mc_t x, mc_t factor)
{
    const mc_t y = mc_mul(factor, x);
    return (mc_lt(mc_abs(y), MC_DECAY_SNAP)) ? MC_ZERO : y;
}

#endif /* MATH_DECAY_H */
