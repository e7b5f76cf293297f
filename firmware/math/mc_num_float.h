/*
 * mc_num_float.h - float32 backend of mc_num.h. Included only through
 * mc_num.h. Transcendental functions use libm single precision for now
 * (max error about 1 ulp); fast approximations may replace them as long as
 * the bounds documented in mc_num.h are kept.
 */
#ifndef MC_NUM_FLOAT_H
#define MC_NUM_FLOAT_H

#include <math.h>
#include <stdint.h>

typedef float mc_t;

#define MC_FIXED 0
#define MC_C(x) ((mc_t)(x))
#define MC_ZERO ((mc_t)0.0f)
#define MC_ONE ((mc_t)1.0f)
#define MC_PI ((mc_t)3.14159265358979f)
#define MC_TWO_PI ((mc_t)6.28318530717959f)
#define MC_MAX ((mc_t)3.0e38f)

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
static inline mc_t mc_mul_i(mc_t a, int32_t n) { return a * (float)n; }
static inline mc_t mc_div_i(mc_t a, int32_t n) { return a / (float)n; }
static inline mc_t mc_from_i(int32_t n) { return (float)n; }
static inline mc_t mc_ratio_i(int32_t num, int32_t den) { return (den == 0) ? 0.0f : (float)num / (float)den; }
static inline int32_t mc_round_i(mc_t x) { return (int32_t)lrintf(x); }
static inline mc_t mc_sgn(mc_t x) { return (x > 0.0f) ? 1.0f : ((x < 0.0f) ? -1.0f : 0.0f); }
static inline mc_t mc_sqrt(mc_t x) { return (x > 0.0f) ? sqrtf(x) : 0.0f; }
static inline mc_t mc_sqrt_abs_sgn(mc_t x) { return (x >= 0.0f) ? sqrtf(x) : -sqrtf(-x); }
static inline mc_t mc_hypot(mc_t a, mc_t b) { return sqrtf(a * a + b * b); }
static inline void mc_sincos(mc_t x, mc_t *s, mc_t *c)
{
    *s = sinf(x);
    *c = cosf(x);
}
static inline mc_t mc_atan2(mc_t y, mc_t x) { return atan2f(y, x); }
static inline mc_t mc_wrap_pi(mc_t x)
{
    return x - MC_TWO_PI * floorf((x + MC_PI) / MC_TWO_PI);
}
static inline mc_t mc_elec_angle(mc_t theta_mech_rad, int32_t n_p)
{
    /* fmodf keeps the full precision of theta for multi-turn positions */
    const float pitch = MC_TWO_PI / (float)n_p;
    return mc_wrap_pi((float)n_p * fmodf(theta_mech_rad, pitch));
}

#endif /* MC_NUM_FLOAT_H */
