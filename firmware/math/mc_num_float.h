/*
 * mc_num_float.h - float32 backend of mc_num.h. Included only through
 * mc_num.h.
 *
 * Transcendental functions are fast single-precision approximations (no
 * libm call on the target: newlib's sinf/cosf/atan2f/fmodf are slow on a
 * Cortex-M4F). They use only +, -, *, /, sqrt and compares, all IEEE
 * correctly rounded, and no fused multiply-add (build with
 * -ffp-contract=off), so the host build and the Cortex-M4F build give
 * bit-identical results.
 *
 * Error bounds (absolute, vs. libm in double evaluated on the same float
 * input; asserted by tests/firmware/test_mc_math*, which print the
 * measured maxima):
 *   mc_sqrt, mc_sqrt_abs_sgn  correctly rounded (sqrtf: vsqrt.f32 on M4F)
 *   mc_hypot                  <= 2 ulp relative (2.4e-7 |r|) without
 *                             overflow for |a|, |b| < 1e19
 *   mc_sincos                 <= 2.0e-7 for |x| <= 8192; 8192 < |x| < 65536
 *                             loses up to ~1e-6 (reduction constant exact
 *                             for k < 2^13 quarter turns); beyond, x is
 *                             first reduced by fmodf(x, float(2 pi)) (cold
 *                             path; |x| > 65536 rad has an ulp >= 0.008)
 *   mc_atan2                  <= 4.0e-7 rad, any finite (y, x); (0,0) -> 0
 *   mc_wrap_pi                <= 4.0e-7 rad for |x| <= 1e5, exact
 *                             (unchanged) for x already in [-pi, pi)
 *   mc_elec_angle             <= 1.0e-6 rad for |n_p theta| <= 4e5 and
 *                             |n_p| <= 256 (theta 8000 rad at n_p = 50),
 *                             relative to the exact n_p * (float theta);
 *                             exact product for |n_p theta| < pi.
 * "Any value" is accepted everywhere; NaN propagates, +-inf gives NaN.
 */
#ifndef MC_NUM_FLOAT_H
#define MC_NUM_FLOAT_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "mc_type.h" /* typedef float mc_t, MC_FIXED 0 */

#define MC_C(x) ((mc_t)(x))
#define MC_ZERO ((mc_t)0.0f)
#define MC_ONE ((mc_t)1.0f)
#define MC_PI ((mc_t)3.14159265358979f)
#define MC_TWO_PI ((mc_t)6.28318530717959f)
#define MC_HALF_PI ((mc_t)1.57079632679490f)
#define MC_MAX ((mc_t)3.0e38f)

#ifdef __cplusplus
extern "C" {
#endif

/* ---- internal helpers (mc__ prefix: not part of the API) ---------------- */

/* round to nearest (ties to even) for |x| < 2^22, without libm: x + 1.5 2^23
 * lies in [2^23, 2^24) where the float spacing is 1. */
#define MC__MAGIC_RINT 12582912.0f
static inline float mc__rint22(float x) { return (x + MC__MAGIC_RINT) - MC__MAGIC_RINT; }

/* x with its `nb` lowest mantissa bits cleared (exact split x = hi + lo) */
static inline float mc__clear_low_bits(float x, uint32_t nb)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    u &= 0xFFFFFFFFu << nb;
    float r;
    memcpy(&r, &u, sizeof r);
    return r;
}

/* r - k * 2 pi with 2 pi = C1 + C2 + C3 (C1, C2: 8 significant bits, so
 * k C1 and k C2 are exact for |k| < 2^16) */
#define MC__2PI_C1 6.28125f
#define MC__2PI_C2 0.00193023681640625f
#define MC__2PI_C3 5.070363386039389e-06f
#define MC__INV_2PI 0.159154943091895f

static inline float mc__wrap_range(float r)
{
    if (r >= MC_PI) {
        r -= MC_TWO_PI;
    } else if (r < -MC_PI) {
        r += MC_TWO_PI;
    }
    return r;
}

/* ---- API of mc_num.h ------------------------------------------------------ */

/* comparisons: the same names as the fixed backend, where mc_t may be a
 * struct (strict check build) that has no C comparison operators */
static inline bool mc_lt(mc_t a, mc_t b) { return a < b; }
static inline bool mc_le(mc_t a, mc_t b) { return a <= b; }
static inline bool mc_gt(mc_t a, mc_t b) { return a > b; }
static inline bool mc_ge(mc_t a, mc_t b) { return a >= b; }
static inline bool mc_eq(mc_t a, mc_t b) { return a == b; }
static inline bool mc_ne(mc_t a, mc_t b) { return a != b; }

static inline mc_t mc_add(mc_t a, mc_t b) { return a + b; }
static inline mc_t mc_sub(mc_t a, mc_t b) { return a - b; }
static inline mc_t mc_mul(mc_t a, mc_t b) { return a * b; }
static inline mc_t mc_div(mc_t a, mc_t b)
{
    if (b == 0.0f) {
        return (a >= 0.0f) ? MC_MAX : -MC_MAX;
    }
    return a / b;
}
static inline mc_t mc_neg(mc_t a) { return -a; }
static inline mc_t mc_abs(mc_t a) { return fabsf(a); }
static inline mc_t mc_min(mc_t a, mc_t b) { return (a < b) ? a : b; }
static inline mc_t mc_max(mc_t a, mc_t b) { return (a > b) ? a : b; }
static inline mc_t mc_clamp(mc_t x, mc_t lo, mc_t hi) { return (x < lo) ? lo : ((x > hi) ? hi : x); }
/* false for NaN and +-inf (a bit test of the exponent, no libm call) */
static inline bool mc_is_finite(mc_t x) { return isfinite(x) != 0; }
static inline mc_t mc_mul_i(mc_t a, int32_t n) { return a * (float)n; }
/* a b + c d, a b - c d, acc + a b: two roundings each (no fused multiply-add,
 * so bit-identical to mc_add(mc_mul(a, b), mc_mul(c, d)) etc.) */
static inline mc_t mc_dot2(mc_t a, mc_t b, mc_t c, mc_t d) { return a * b + c * d; }
static inline mc_t mc_cross2(mc_t a, mc_t b, mc_t c, mc_t d) { return a * b - c * d; }
static inline mc_t mc_mac(mc_t acc, mc_t a, mc_t b) { return acc + a * b; }
static inline mc_t mc_div_i(mc_t a, int32_t n) { return mc_div(a, (float)n); }
static inline mc_t mc_from_i(int32_t n) { return (float)n; }
/* num / den, correctly rounded for |num|, |den| < 2^24 (both exact in
 * float, one IEEE division); 0 if den == 0. */
static inline mc_t mc_ratio_i(int32_t num, int32_t den) { return (den == 0) ? 0.0f : (float)num / (float)den; }
/* nearest integer (ties to even), saturated to +-2^31 range */
static inline int32_t mc_round_i(mc_t x)
{
    if (x > -4194304.0f && x < 4194304.0f) {
        return (int32_t)mc__rint22(x);
    }
    if (x >= 2147483520.0f) {
        return INT32_MAX;
    }
    if (x <= -2147483648.0f) {
        return INT32_MIN;
    }
    return (int32_t)x; /* |x| >= 2^22: already an integer */
}
static inline mc_t mc_sgn(mc_t x) { return (x > 0.0f) ? 1.0f : ((x < 0.0f) ? -1.0f : 0.0f); }
static inline mc_t mc_mul_sgn(mc_t m, mc_t x) { return (x > 0.0f) ? m : ((x < 0.0f) ? -m : 0.0f); }
static inline mc_t mc_sqrt(mc_t x) { return (x > 0.0f) ? sqrtf(x) : 0.0f; }
static inline mc_t mc_rsqrt(mc_t x) { return (x > 0.0f) ? 1.0f / sqrtf(x) : MC_MAX; }
static inline mc_t mc_sqrt_abs_sgn(mc_t x) { return (x >= 0.0f) ? sqrtf(x) : -sqrtf(-x); }
static inline mc_t mc_hypot(mc_t a, mc_t b) { return sqrtf(a * a + b * b); }

/* sin and cos of r in [-pi/4, pi/4] (cephes sinf/cosf kernels) */
static inline void mc__sincos_kernel(float r, float *sp, float *cp)
{
    const float z = r * r;
    *sp = ((-1.9515295891e-4f * z + 8.3321608736e-3f) * z - 1.6666654611e-1f) * z * r + r;
    *cp = ((2.443315711809948e-5f * z - 1.388731625493765e-3f) * z + 4.166664568298827e-2f) * z * z - 0.5f * z + 1.0f;
}

static inline void mc_sincos(mc_t x, mc_t *s, mc_t *c)
{
    if (fabsf(x) <= 0.785398163f) {
        mc__sincos_kernel(x, s, c); /* small angles (increments, errors): no reduction */
        return;
    }
    /* quarter turns: pi/2 = P1 + P2 + P3 (Cody-Waite, cephes constants) */
    float xr = x;
    if (!(fabsf(xr) < 65536.0f)) {
        /* far outside any drive angle (cold path): exact fmodf by float(2 pi) */
        xr = fmodf(xr, MC_TWO_PI);
    }
    const float kb = xr * 0.636619772367581f + MC__MAGIC_RINT; /* k + 1.5 2^23 */
    uint32_t kbits;
    memcpy(&kbits, &kb, sizeof kbits); /* low bits: k mod 2^22 */
    const float k = kb - MC__MAGIC_RINT;
    const float r = ((xr - k * 1.5703125f) - k * 4.837512969970703125e-4f) - k * 7.54978995489188216e-8f;
    float sp;
    float cp;
    mc__sincos_kernel(r, &sp, &cp);
    switch (kbits & 3u) {
    case 0u: *s = sp; *c = cp; break;
    case 1u: *s = cp; *c = -sp; break;
    case 2u: *s = -sp; *c = -cp; break;
    default: *s = -cp; *c = sp; break;
    }
}

/* atan2 in [-pi, pi] ((0, 0) -> 0); cephes atanf kernel on |z| <= tan(pi/8). */
static inline mc_t mc_atan2(mc_t y, mc_t x)
{
    const float ax = fabsf(x);
    const float ay = fabsf(y);
    const float mx = (ax > ay) ? ax : ay;
    const float mn = (ax > ay) ? ay : ax;
    if (mx == 0.0f) {
        return 0.0f;
    }
    float z;
    float base;
    if (mn > 0.414213562373095f * mx) {
        z = (mn - mx) / (mn + mx);
        base = 0.785398163397448f;
    } else {
        z = mn / mx;
        base = 0.0f;
    }
    const float zz = z * z;
    float a =
        base +
        ((((8.05374449538e-2f * zz - 1.38776856032e-1f) * zz + 1.99777106478e-1f) * zz - 3.33329491539e-1f) * zz * z +
         z);
    if (ay > ax) {
        a = MC_HALF_PI - a;
    }
    if (x < 0.0f) {
        a = MC_PI - a;
    }
    return (y < 0.0f) ? -a : a;
}

/* x wrapped into [-pi, pi); returned unchanged when already there. */
static inline mc_t mc_wrap_pi(mc_t x)
{
    if (x >= -MC_PI && x < MC_PI) {
        return x;
    }
    if (!(x > -1.0e5f && x < 1.0e5f)) {
        /* far outside the drive's range (cold path): exact fmodf by float(2 pi) */
        return mc__wrap_range(fmodf(x, MC_TWO_PI));
    }
    const float k = mc__rint22(x * MC__INV_2PI);
    return mc__wrap_range(((x - k * MC__2PI_C1) - k * MC__2PI_C2) - k * MC__2PI_C3);
}

/* wrap(n_p theta) computed as if n_p theta were exact: theta = hi + lo
 * with hi holding 24 - bits(n_p) significant bits, so n_p hi and n_p lo are
 * exact products; then Cody-Waite with 2 pi = C1 + C2 + C3. */
static inline mc_t mc_elec_angle(mc_t theta_mech_rad, int32_t n_p)
{
    const float np = (float)n_p;
    const float e = np * theta_mech_rad;
    if (e >= -MC_PI && e < MC_PI) {
        return e;
    }
    if (!(e > -4.0e5f && e < 4.0e5f)) {
        return mc_wrap_pi(e);
    }
    const uint32_t anp = (n_p < 0) ? (0u - (uint32_t)n_p) : (uint32_t)n_p;
    const uint32_t nb = 32u - (uint32_t)__builtin_clz(anp | 1u);
    const float th_hi = mc__clear_low_bits(theta_mech_rad, nb);
    const float th_lo = theta_mech_rad - th_hi;
    const float k = mc__rint22(e * MC__INV_2PI);
    const float r = ((np * th_hi - k * MC__2PI_C1) - k * MC__2PI_C2) + (np * th_lo - k * MC__2PI_C3);
    return mc__wrap_range(r);
}

#ifdef __cplusplus
}
#endif

#endif /* MC_NUM_FLOAT_H */
