/*
 * mc_convert.h - HOST-SIDE conversions between double and mc_t, for the
 * simulator, the gain design, tests and tools. Uses double at run time, so
 * it must NOT be included by firmware blocks (firmware/observers, control,
 * trajectory, startup, drive): the fixed-point MCU build must contain no
 * floating-point code, and tests/firmware's no-float check would fail.
 *
 *   mc_t   mc_from_double(double x)   float: (float)x; fixed: round(x 2^17),
 *                                     saturated to +-MC_MAX, NaN -> 0
 *   double mc_to_double(mc_t x)       exact in both builds
 *   double mc_lsb(void)               2^-17 in fixed, 0 in float
 *   double mc_max_double(void)        largest representable magnitude
 */
#ifndef MATH_MC_CONVERT_H
#define MATH_MC_CONVERT_H

#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

#if MC_FIXED
static inline mc_t mc_from_double(double x)
{
    const double s = x * (double)MC_ONE_RAW;
    if (s >= (double)INT32_MAX) {
        return MC_MAX;
    }
    if (s <= -(double)INT32_MAX) {
        return mc_neg(MC_MAX);
    }
    if (!(s == s)) {
        return MC_ZERO;
    }
    return mc_from_raw((int32_t)((s >= 0.0) ? (s + 0.5) : (s - 0.5)));
}
static inline double mc_to_double(mc_t x) { return (double)mc_raw(x) / (double)MC_ONE_RAW; }
static inline double mc_lsb(void) { return 1.0 / (double)MC_ONE_RAW; }
static inline double mc_max_double(void) { return (double)INT32_MAX / (double)MC_ONE_RAW; }
#else
static inline mc_t mc_from_double(double x) { return (mc_t)x; }
static inline double mc_to_double(mc_t x) { return (double)x; }
static inline double mc_lsb(void) { return 0.0; }
static inline double mc_max_double(void) { return (double)MC_MAX; }
#endif

#ifdef __cplusplus
}
#endif

#endif /* MATH_MC_CONVERT_H */
