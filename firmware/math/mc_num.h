/*
 * mc_num.h - the one numeric type of the firmware.
 *
 * Every firmware block computes in `mc_t` and only through the operations
 * declared here, so the same block source builds either in float32
 * (default) or in fixed point (MC_FIXED_POINT=1, see mc_num_fixed.h).
 * Values are SI quantities (A, V, rad, rad/s, ...) in both builds; the
 * fixed-point build documents its Q format, range and resolution there.
 *
 * Rules for block authors (they are what makes the fixed build possible):
 *  - no C operators on mc_t values: use mc_add/mc_sub/mc_mul/... and the
 *    comparisons mc_lt/mc_le/mc_gt/mc_ge/mc_eq/mc_ne (a raw `a * b` is
 *    silently wrong in Q14.17); the strict check build (preset host-strict,
 *    mc_t a struct, see mc_num_fixed.h) does not compile code that breaks
 *    this rule;
 *  - literals through MC_C(x), which folds at compile time in both builds;
 *  - no coefficient smaller than about 1e-3 or larger than about 1e4 at run
 *    time: fold sample time and physical constants into per-sample gains
 *    at design time (design/), where double is allowed.
 */
#ifndef MC_NUM_H
#define MC_NUM_H

#include <stdint.h>

#if defined(MC_FIXED_POINT) && MC_FIXED_POINT
#include "mc_num_fixed.h"
#else
#include "mc_num_float.h"
#endif

/* Operations every backend provides (static inline):
 *   bool mc_lt(mc_t a, mc_t b), mc_le, mc_gt, mc_ge, mc_eq, mc_ne   a < b, ...
 *   mc_t mc_add(mc_t a, mc_t b), mc_sub, mc_mul, mc_div (b == 0 saturates)
 *   mc_t mc_dot2(a,b,c,d) = a b + c d, mc_cross2(a,b,c,d) = a b - c d,
 *   mc_t mc_mac(acc,a,b) = acc + a b   (fixed: one rounding, cheaper than
 *                                    mul + add; float: same as mul + add)
 *   mc_t mc_neg(mc_t a), mc_abs(a), mc_min(a,b), mc_max(a,b)
 *   mc_t mc_clamp(mc_t x, mc_t lo, mc_t hi)
 *   bool mc_is_finite(mc_t x)        false for NaN, +-inf (fixed point: always true)
 *   mc_t mc_mul_i(mc_t a, int32_t n), mc_div_i(mc_t a, int32_t n)
 *   mc_t mc_from_i(int32_t n), int32_t mc_round_i(mc_t x)
 *   mc_t mc_ratio_i(int32_t num, int32_t den)   num/den exactly rounded, 0 if den == 0
 *   mc_t mc_sgn(mc_t x)              -1, 0 or +1
 *   mc_t mc_mul_sgn(mc_t m, mc_t x)  m sgn(x) for m >= 0, exact (a select)
 *   mc_t mc_sqrt(mc_t x)             x >= 0
 *   mc_t mc_sqrt_abs_sgn(mc_t x)     |x|^(1/2) sgn(x), the super-twisting term
 *   mc_t mc_rsqrt(mc_t x)            1/sqrt(x) for x > 0 (largest value for x <= 0)
 *   mc_t mc_hypot(mc_t a, mc_t b)
 *   void mc_sincos(mc_t x, mc_t *s, mc_t *c)   x in rad, any value
 *   mc_t mc_atan2(mc_t y, mc_t x)    result in (-pi, pi]
 *   mc_t mc_wrap_pi(mc_t x)          x wrapped into [-pi, pi)
 *   mc_t mc_elec_angle(mc_t theta_mech_rad, int32_t n_p)
 *                                    wrap(n_p * theta) without loss for large theta
 *   MC_C(x), MC_PI, MC_TWO_PI, MC_ZERO, MC_ONE   (constant expressions, also
 *                                    in static initializers)
 * Fixed point only (host-side conversions, bit-exact dumps; never arithmetic):
 *   int32_t mc_raw(mc_t x), mc_t mc_from_raw(int32_t r)   the Q14.17 bits
 * Error bounds of the approximated functions are stated in the backend
 * header and checked by tests/firmware/test_mc_math.
 */

#endif /* MC_NUM_H */
