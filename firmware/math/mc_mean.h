/*
 * mc_mean.h - the mean of a known number of samples, accumulated one
 * sample at a time without a sum that could leave the fixed-point range.
 *
 * mean += x/n with the rounding error of x/n carried into the next sample
 * (error feedback), so the mean of a constant input is exact to 1 LSB
 * however long the window; plain x/n would round the same way every
 * sample and bias the mean by up to n/2 LSB.
 */
#ifndef MATH_MC_MEAN_H
#define MATH_MC_MEAN_H

#include <stdint.h>

#include "math/mc_num.h"

/* *mean and *res start at 0; n is the number of samples the mean is over. */
static inline void mc_mean_add(mc_t *mean, mc_t *res, mc_t x, int32_t n)
{
    const mc_t t = mc_add(x, *res);
    const mc_t q = mc_div_i(t, n);
    *res = mc_sub(t, mc_mul_i(q, n));
    *mean = mc_add(*mean, q);
}

#endif /* MATH_MC_MEAN_H */
