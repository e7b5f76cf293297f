/*
 * mc_convert.h - host-side conversions between double and mc_t, for the
 * gain design, the simulator and tests. Never included by firmware blocks
 * (it uses double).
 */
#ifndef MATH_MC_CONVERT_H
#define MATH_MC_CONVERT_H

#include "math/mc_num.h"

#if defined(MC_FIXED_POINT) && MC_FIXED_POINT
#include <math.h>
static inline mc_t mc_from_double(double x)
{
    const double s = ldexp(x, MC_FRAC_BITS);
    if (s >= 2147483647.0) return (mc_t)2147483647;
    if (s <= -2147483648.0) return (mc_t)(-2147483647 - 1);
    return (mc_t)llround(s);
}
static inline double mc_to_double(mc_t x) { return ldexp((double)x, -MC_FRAC_BITS); }
#else
static inline mc_t mc_from_double(double x) { return (mc_t)x; }
static inline double mc_to_double(mc_t x) { return (double)x; }
#endif

#endif /* MATH_MC_CONVERT_H */
