/*
 * mc_num_fixed.h - fixed-point backend of mc_num.h (MC_FIXED_POINT=1).
 * Included only through mc_num.h. Integer-only: no float or double is
 * evaluated at run time (MC_C folds at compile time), so the Cortex-M3
 * build links no soft-float helper (checked by tests/firmware/nofloat).
 *
 * ======================================================================
 * FORMAT: Q14.17 -- mc_t is int32_t, value = raw / 2^17, for every signal
 *   (in the strict check build, MC_STRICT_TYPES, a struct holding the int32_t).
 *   MC_FRAC_BITS = 17, LSB = 2^-17 = 7.63e-6, range [-16384, +16384)
 *   (saturated values are +-MC_MAX = +-(2^31-1)/2^17 = +-16383.99999; the
 *   raw value INT32_MIN = -16384 exactly can still come out of a product).
 *   Products use a 64-bit intermediate, rounded (half up) and saturated;
 *   add/sub/neg/abs/mul_i/from_i/div saturate instead of wrapping.
 * ======================================================================
 *
 * Why one global Q14.17 and not Q15.16 or Q12.19: the largest signal the
 * drive carries is an acceleration of 1e4 rad/s^2 (needs 14 integer bits),
 * and the finest resolution asked for is 1e-5 A on currents (needs 17
 * fractional bits). Q14.17 is the only 32-bit split that meets both; Q15.16
 * (1.5e-5) misses the current resolution, Q13.18 and narrower overflow the
 * acceleration. Per signal, in SI units (base value 1 for all: the drive
 * computes in SI, not per unit):
 *
 *   signal                         operating range   headroom  resolution (rel. at full scale)
 *   currents i_a, i_b, i_f, i_g    +-10 A            1638x     7.6e-6 A   (7.6e-7)
 *   voltages v, back-EMF L*d_f     +-60 V            273x      7.6e-6 V   (1.3e-7)
 *   mechanical angle theta         0..few 100 rad    >= 50x    7.6e-6 rad (4.3e-5 deg)
 *   electrical angle (wrapped)     [-pi, pi)         5215x     7.6e-6 rad
 *   speed omega                    +-200 rad/s       82x       7.6e-6 rad/s
 *   acceleration                   +-1e4 rad/s^2     1.64x     7.6e-6 rad/s^2
 *   load torque (mech. observer)   +-5 N m           3277x     7.6e-6 N m
 *   filtered injections            +-3000 V/s        5.5x      7.6e-6
 *   e_f^2 + e_g^2                  0..3600 V^2       4.5x      7.6e-6 V^2
 *   per-sample coefficients        1e-3..1e3         16x       rel. error of the stored
 *                                                              constant <= 3.8e-6/|c|:
 *                                                              f_v = 2.37e-3 -> 0.16 %,
 *                                                              Ts/L = 0.0111 -> 0.034 %,
 *                                                              R = 3.01 -> 1.3e-6
 *   per-sample increments          1e-3..10          -         <= 0.38 % at 1e-3
 *
 * No overflow over the operating range: every row's range is below
 * 16384 with the headroom shown; products of two in-range signals are
 * formed in 64 bits (|a*b| < 2^62) and only the rounded result is
 * saturated, so an intermediate never wraps. The tightest case is the
 * 1e4 rad/s^2 acceleration (1.64x); beyond 16384 values saturate (clip),
 * they never wrap sign. A product whose *result* exceeds 16384 (e.g. a
 * gain of 1e3 times an injection of 3000) is outside the drive's operating
 * range by construction (coefficients are folded per sample at design
 * time, see mc_num.h) and clips.
 * f_v (2.37e-3, the smallest coefficient) is stored with 0.16 % error;
 * f_v * omega <= 0.47 N m, so the torque error is <= 7.6e-4 N m, 0.015 %
 * of the 5 N m load bound: a single global format suffices and no separate
 * small-coefficient multiply is needed. Fold any constant below 1e-3 with a
 * co-factor at design time rather than storing it alone.
 * Integrators: an increment below 0.5 LSB (3.8e-6) per sample is lost
 * (rounding); e.g. theta += Ts*omega keeps omega down to 0.038 rad/s.
 * float32 is no better there: at 18 rad its ulp is 1.9e-6, at 300 rad 3e-5.
 *
 * Angles and wrapping (n_p = 50): mc_elec_angle(theta, n_p) forms the exact
 * 64-bit product n_p * theta_raw (|.| < 2^37, cannot overflow for any
 * int32 theta and |n_p| < 2^31) and converts it to a 32-bit binary angle
 * (2^32 = one electrical turn) with one 64-bit multiply taken modulo 2^64,
 * which is the wrap; the binary angle is converted back to rad in [-pi, pi).
 * So theta up to the full +-16384 rad (> 2600 mechanical turns, 130000
 * electrical turns) wraps with <= 1 LSB error; there is no accumulation of
 * a rounded 2*pi. The electrical angle's own resolution is n_p * 7.6e-6 =
 * 3.8e-4 rad (the mechanical angle's LSB, multiplied). mc_sincos and
 * mc_wrap_pi take any int32 rad value through the same binary-angle path.
 * Electrical *rates* (n_p * omega, up to 1e4 rad/s) are in range.
 *
 * Error bounds (absolute, vs. libm in double; tests/firmware/test_mc_math*
 * assert them over the whole int32 input range, strided + random + dense
 * around 0, and print the measured maxima):
 *   mc_mul           <= 0.5 LSB (exact rounding of the 64-bit product)
 *   mc_div           <= 0.5 LSB (exactly rounded), also mc_ratio_i
 *   mc_dot2, mc_cross2, mc_mac  <= 0.5 LSB (one rounding of the exact sum)
 *   mc_sqrt          <= 0.8 LSB (table + 2 Newton steps, 32-bit only)
 *   mc_rsqrt         <= 0.8 LSB + 2e-7 relative
 *   mc_sqrt_abs_sgn  <= 0.8 LSB + 2.5e-5 |result| (one Newton step: it only
 *                    scales super-twisting injections, where 1e-4 would do)
 *   mc_hypot         <= 0.8 LSB for results below 256, 2^-24 relative above
 *   mc_sincos        <= 1.0 LSB = 7.6e-6     (any int32 x)
 *   mc_atan2         <= 1.0 LSB = 7.6e-6 rad (any int32 y, x; 0 for (0,0))
 *   mc_wrap_pi       <= 1.0 LSB, exact for x already in [-pi, pi)
 *   mc_elec_angle    <= 1.0 LSB for |n_p| <= 1024 (the 2^47/(2 pi) constant's
 *                    rounding adds |n_p theta| 1.6e-12 rad), exact when |n_p theta| < pi
 * (1 LSB bounds: result rounding 0.5 LSB + polynomial / constant error.)
 * MC_PI is pi rounded to 17 bits (3.1415939, +1.2e-6): angles are returned
 * in [-MC_PI, MC_PI).
 */
#ifndef MC_NUM_FIXED_H
#define MC_NUM_FIXED_H

#include <stdbool.h>
#include <stdint.h>

#include "mc_type.h" /* mc_t: int32_t (a struct of it in the strict build), MC_FIXED 1 */

#if defined(MC_STRICT_TYPES) && MC_STRICT_TYPES
#ifdef __cplusplus
#error "MC_STRICT_TYPES is a C-only check build (compound literals): the C++ simulator and tests use the plain int32_t mc_t"
#endif
/* Strict check build (CMake MC_STRICT_TYPES, preset host-strict): mc_t is a
 * one-member struct, so a C operator (*, +, <, ==, !, unary -) on mc_t, an
 * implicit conversion between mc_t and an integer, or a literal not written
 * through MC_C does not compile. It is a compile check only: nothing built
 * with it ships or runs (the values and the operations are the same). */
/* mc_t is that struct (mc_type.h) */
/* the mc_t of raw value r: a compound literal, so MC_C and the constants
 * below stay constant expressions (GCC and Clang accept a compound literal
 * with constant members as a static initializer) */
#define MC__MK(r) ((mc_t){.raw = (int32_t)(r)})
#define MC__RAW(x) ((x).raw)
#else
#define MC__MK(r) ((mc_t)(r))
#define MC__RAW(x) (x)
#endif
#define MC_FRAC_BITS 17
#define MC_ONE_RAW ((int32_t)1 << MC_FRAC_BITS)
#define MC_MAX MC__MK(INT32_MAX)
#define MC_LSB_F 7.62939453125e-06 /* 2^-17, for host-side documentation and tests */

/* Compile-time conversion of a literal (double arithmetic folds away; do
 * not use MC_C on run-time values: that would bring in soft-float code,
 * which the no-float test rejects). Saturates outside +-16384. */
#define MC_C(x)                                                                          \
    MC__MK(((double)(x)) >= 16383.99999237060546875                                      \
               ? (double)INT32_MAX                                                       \
               : (((double)(x)) <= -16383.99999237060546875                              \
                      ? -(double)INT32_MAX                                               \
                      : ((double)(x)) * 131072.0 + ((((double)(x)) >= 0.0) ? 0.5 : -0.5)))

#define MC__PI_RAW ((int32_t)411775)      /* round(pi 2^17) */
#define MC__TWO_PI_RAW ((int32_t)823550)  /* round(2 pi 2^17) */
#define MC__HALF_PI_RAW ((int32_t)205887) /* round(pi/2 2^17) */
#define MC_ZERO MC__MK(0)
#define MC_ONE MC__MK(MC_ONE_RAW)
#define MC_PI MC__MK(MC__PI_RAW)
#define MC_TWO_PI MC__MK(MC__TWO_PI_RAW)
#define MC_HALF_PI MC__MK(MC__HALF_PI_RAW)

#ifdef __cplusplus
extern "C" {
#endif

/* ---- internal helpers (mc__ prefix: not part of the API) ---------------- */

/* 32x32 -> 64-bit multiplies. On ARMv7-M they are spelled as one smull /
 * umull / smlal each: GCC otherwise sometimes expands a widening multiply
 * whose operands went through a conditional negate into mul+mla+umull.
 * Same results on every target (exact integer arithmetic). */
#if defined(__arm__) && (defined(__ARM_ARCH_7M__) || defined(__ARM_ARCH_7EM__))
#define MC__ARMV7M_ASM 1
#endif

static inline int64_t mc__join64(uint32_t lo, uint32_t hi) { return (int64_t)(((uint64_t)hi << 32) | lo); }

static inline int64_t mc__smul64(int32_t a, int32_t b)
{
#ifdef MC__ARMV7M_ASM
    uint32_t lo;
    uint32_t hi;
    __asm__("smull %0, %1, %2, %3" : "=r"(lo), "=r"(hi) : "r"(a), "r"(b));
    return mc__join64(lo, hi);
#else
    return (int64_t)a * b;
#endif
}

static inline uint64_t mc__umul64(uint32_t a, uint32_t b)
{
#ifdef MC__ARMV7M_ASM
    uint32_t lo;
    uint32_t hi;
    __asm__("umull %0, %1, %2, %3" : "=r"(lo), "=r"(hi) : "r"(a), "r"(b));
    return ((uint64_t)hi << 32) | lo;
#else
    return (uint64_t)a * b;
#endif
}

/* acc + a b (wrapping modulo 2^64, never reached by the callers' ranges) */
static inline int64_t mc__smlal64(int64_t acc, int32_t a, int32_t b)
{
#ifdef MC__ARMV7M_ASM
    uint32_t lo = (uint32_t)(uint64_t)acc;
    uint32_t hi = (uint32_t)((uint64_t)acc >> 32);
    __asm__("smlal %0, %1, %2, %3" : "+r"(lo), "+r"(hi) : "r"(a), "r"(b));
    return mc__join64(lo, hi);
#else
    return acc + (int64_t)a * b;
#endif
}

static inline int32_t mc__sat64(int64_t v)
{
    if (v > (int64_t)INT32_MAX) {
        return INT32_MAX;
    }
    if (v < -(int64_t)INT32_MAX) {
        return -INT32_MAX;
    }
    return (int32_t)v;
}

static inline uint32_t mc__uabs(int32_t a) { return (a < 0) ? (0u - (uint32_t)a) : (uint32_t)a; }


/* ~2^63 / d for d in [2^31, 2^32): one hardware 32-bit divide for 15 bits,
 * one Newton step for ~30 bits. Never overestimates, never overflows. */
static inline uint32_t mc__recip(uint32_t d)
{
    uint32_t r = (0xFFFFFFFFu / ((d >> 16) + 1u)) << 15;
    uint64_t e = ((uint64_t)1 << 63) - mc__umul64(d, r);
    return r + (uint32_t)(mc__umul64(r, (uint32_t)(e >> 32)) >> 31);
}

/* 1/sqrt(x) for x in [1/4, 1), at cell midpoints of 192 cells, Q15. One
 * weak definition per translation unit; the linker keeps a single copy. */
#ifdef __cplusplus
extern "C" const uint16_t mc__rsqrt_tab[192] __attribute__((weak));
extern "C" const uint16_t mc__rsqrt_tab[192] __attribute__((weak)) =
#else
const uint16_t mc__rsqrt_tab[192] __attribute__((weak));
const uint16_t mc__rsqrt_tab[192] __attribute__((weak)) =
#endif
    {65283, 64783, 64294, 63816, 63348, 62891, 62443, 62005, 61576, 61155, 60743, 60340, 59944, 59556,
     59175, 58802, 58436, 58076, 57723, 57376, 57036, 56701, 56373, 56049, 55732, 55420, 55113, 54811,
     54513, 54221, 53933, 53650, 53372, 53097, 52827, 52561, 52299, 52040, 51786, 51535, 51288, 51044,
     50804, 50567, 50334, 50103, 49876, 49652, 49431, 49212, 48997, 48785, 48575, 48368, 48163, 47961,
     47762, 47565, 47370, 47178, 46988, 46801, 46615, 46432, 46251, 46072, 45895, 45720, 45547, 45377,
     45208, 45040, 44875, 44712, 44550, 44390, 44232, 44075, 43920, 43767, 43615, 43465, 43316, 43169,
     43024, 42880, 42737, 42596, 42456, 42317, 42180, 42044, 41910, 41776, 41644, 41514, 41384, 41256,
     41129, 41003, 40878, 40754, 40632, 40510, 40390, 40270, 40152, 40035, 39919, 39804, 39689, 39576,
     39464, 39352, 39242, 39133, 39024, 38916, 38810, 38704, 38599, 38495, 38391, 38289, 38187, 38086,
     37986, 37887, 37788, 37690, 37593, 37497, 37402, 37307, 37213, 37119, 37027, 36935, 36843, 36753,
     36663, 36573, 36485, 36397, 36309, 36223, 36136, 36051, 35966, 35882, 35798, 35715, 35632, 35550,
     35469, 35388, 35307, 35228, 35148, 35070, 34991, 34914, 34837, 34760, 34684, 34608, 34533, 34458,
     34384, 34311, 34237, 34165, 34092, 34020, 33949, 33878, 33808, 33737, 33668, 33599, 33530, 33461,
     33394, 33326, 33259, 33192, 33126, 33060, 32994, 32929, 32864, 32800};

/* sqrt(m / 2^32) 2^32 for m in [2^30, 2^32): table, two Newton steps on
 * 1/sqrt (relative error < 2^-25), one multiply. Every product keeps only
 * its high word (one umull each on Cortex-M3). */
static inline uint32_t mc__sqrt_norm_n(uint32_t m, int iterations)
{
    uint32_t r = (uint32_t)mc__rsqrt_tab[(m >> 24) - 64u] << 15; /* Q30 of 1/sqrt(m/2^32) */
    for (int it = 0; it < iterations; ++it) {
        const uint32_t t = (uint32_t)(mc__umul64(m, r) >> 32);  /* Q30: x r            */
        const uint32_t u = (uint32_t)(mc__umul64(t, r) >> 32);  /* Q28: x r^2 (~1)     */
        const uint32_t h = 0x30000000u - u;                      /* Q28: 3 - x r^2 (~2) */
        r = (uint32_t)(mc__umul64(r, h) >> 32) << 3;             /* Q30: r (3 - x r^2)/2 */
    }
    const uint64_t S = mc__umul64(m, r) >> 30;
    return (S > 0xFFFFFFFFull) ? 0xFFFFFFFFu : (uint32_t)S;
}
static inline uint32_t mc__sqrt_norm(uint32_t m) { return mc__sqrt_norm_n(m, 2); }

/* round(2^17 / sqrt(x / 2^17)) for 0 < x < 2^31: Q17 of 1/sqrt of a Q17
 * value (at most 362.04 for x = 1 LSB, so it never saturates). The same
 * table and two Newton steps as the square root. */
static inline uint32_t mc__rsqrt_q17(uint32_t x)
{
    /* clz >= 1, made odd by (clz - 1) | 1 (an even one less by 1): m = x 2^s in [2^30, 2^32) */
    const int s = (__builtin_clz(x) - 1) | 1;
    const uint32_t m = x << s;
    uint32_t r = (uint32_t)mc__rsqrt_tab[(m >> 24) - 64u] << 15; /* Q30 of 1/sqrt(m/2^32) */
    for (int it = 0; it < 2; ++it) {
        const uint32_t t = (uint32_t)(mc__umul64(m, r) >> 32);
        const uint32_t u = (uint32_t)(mc__umul64(t, r) >> 32);
        r = (uint32_t)(mc__umul64(r, 0x30000000u - u) >> 32) << 3;
    }
    /* 1/sqrt(x/2^17) 2^17 = r 2^((s - 41)/2), s odd, shift sh = (41 - s)/2 in 5..20,
     * rounded: ((r >> (sh - 1)) + 1) >> 1 with sh - 1 = (39 - s)/2 */
    return ((r >> ((39 - s) >> 1)) + 1u) >> 1;
}

/* round(sqrt(x 2^17)) for 0 < x < 2^31: the Q17 square root of a Q17 value;
 * `iterations` Newton steps after the table (2: within 0.8 LSB; 1: within
 * 2.5e-5 relative, a few instructions less) */
static inline uint32_t mc__sqrt_q17_n(uint32_t x, int iterations)
{
    /* clz >= 1, made odd by (clz - 1) | 1: 17 - s even, m = x 2^s in [2^30, 2^32) */
    const int s = (__builtin_clz(x) - 1) | 1;
    /* sqrt(x 2^17) = S / 2^sh, sh = (s + 15)/2 in 8..23, rounded:
     * ((S >> (sh - 1)) + 1) >> 1 with sh - 1 = (s + 13)/2 */
    return ((mc__sqrt_norm_n(x << s, iterations) >> ((s + 13) >> 1)) + 1u) >> 1;
}
static inline uint32_t mc__sqrt_q17(uint32_t x) { return mc__sqrt_q17_n(x, 2); }

/* round(sqrt(n)) for n < 2^63 (|error| < 1 + 2^-25 sqrt(n)) */
static inline uint32_t mc__isqrt64(uint64_t n)
{
    const uint32_t hi = (uint32_t)(n >> 32);
    if (hi == 0u) {
        const uint32_t lo = (uint32_t)n;
        if (lo == 0u) {
            return 0u;
        }
        const int s = __builtin_clz(lo) & ~1;
        const int sh = 16 + (s >> 1);
        return (uint32_t)((((uint64_t)mc__sqrt_norm(lo << s) >> (sh - 1)) + 1u) >> 1);
    }
    const int s = __builtin_clz(hi) & ~1; /* 0..30 */
    const uint32_t m = (uint32_t)(n >> (32 - s));
    const uint32_t S = mc__sqrt_norm(m);
    const int sh = s >> 1;
    return (sh == 0) ? S : (((S >> (sh - 1)) + 1u) >> 1);
}

/* rad (Q17, any int32) -> binary angle (2^32 per turn), via x * 2^47/(2 pi) mod 2^64. */
#define MC__RAD2BAM_K64 ((uint64_t)22399066950089ull) /* round(2^47 / (2 pi)) */
static inline uint32_t mc__bam_of_q17_64(int64_t x_raw)
{
    return (uint32_t)(((uint64_t)x_raw * MC__RAD2BAM_K64) >> 32);
}

/* binary angle -> rad Q17 in [-MC_PI, MC_PI) */
static inline int32_t mc__rad_of_bam(uint32_t u)
{
    const int64_t p = mc__smul64((int32_t)u, 1686629713); /* round(2 pi 2^28) */
    int32_t r = (int32_t)((p + ((int64_t)1 << 42)) >> 43);
    if (r >= MC__PI_RAW) {
        r -= MC__TWO_PI_RAW;
    }
    return r;
}

/* high word of a signed 32x32 product: one smull on Cortex-M3 */
static inline int32_t mc__mulhi(int32_t a, int32_t b) { return (int32_t)(mc__smul64(a, b) >> 32); }

/* sin and cos of a binary angle, in Q30. Horner steps are "c + mulhi(z, p) * 4"
 * (smull + add with shift); truncation errors stay below 2^-28. */
static inline void mc__sincos_bam_q30(uint32_t u, int32_t *s30, int32_t *c30)
{
    const uint32_t q = (u + 0x20000000u) >> 30;          /* nearest quadrant */
    const int32_t t = (int32_t)((u - (q << 30)) << 2);   /* Q31 of r/(pi/4), in [-1, 1) */
    const int32_t z = mc__mulhi(t, t);                   /* Q30 of t^2 */
    /* minimax, |err| < 5.6e-7 (sin, degree 5) and 2.8e-8 (cos, degree 6) */
    int32_t ps = 5212170;                                /* Q31 coefficients */
    ps = -173331992 + mc__mulhi(z, ps) * 4;
    ps = 1686621276 + mc__mulhi(z, ps) * 4;
    ps = mc__mulhi(t, ps);                               /* Q30 */
    int32_t pc = -342396;                                /* Q30 coefficients */
    pc = 17018717 + mc__mulhi(z, pc) * 4;
    pc = -331168021 + mc__mulhi(z, pc) * 4;
    pc = 1073741794 + mc__mulhi(z, pc) * 4;
    switch (q & 3u) {
    case 0u: *s30 = ps; *c30 = pc; break;
    case 1u: *s30 = pc; *c30 = -ps; break;
    case 2u: *s30 = -ps; *c30 = -pc; break;
    default: *s30 = -pc; *c30 = ps; break;
    }
}

static inline int32_t mc__q30_to_q17(int32_t v) { return (v + (1 << 12)) >> 13; }

/* ---- API of mc_num.h ------------------------------------------------------ */

/* The raw Q14.17 bits, for code that truly works on them (conversions,
 * bit-exact dumps); never for arithmetic, which the mc_* operations do. */
static inline int32_t mc_raw(mc_t x) { return MC__RAW(x); }
static inline mc_t mc_from_raw(int32_t r) { return MC__MK(r); }

/* comparisons (raw order is value order) */
static inline bool mc_lt(mc_t a, mc_t b) { return MC__RAW(a) < MC__RAW(b); }
static inline bool mc_le(mc_t a, mc_t b) { return MC__RAW(a) <= MC__RAW(b); }
static inline bool mc_gt(mc_t a, mc_t b) { return MC__RAW(a) > MC__RAW(b); }
static inline bool mc_ge(mc_t a, mc_t b) { return MC__RAW(a) >= MC__RAW(b); }
static inline bool mc_eq(mc_t a, mc_t b) { return MC__RAW(a) == MC__RAW(b); }
static inline bool mc_ne(mc_t a, mc_t b) { return MC__RAW(a) != MC__RAW(b); }

static inline mc_t mc_add(mc_t a, mc_t b)
{
    int32_t r;
    if (__builtin_add_overflow(MC__RAW(a), MC__RAW(b), &r)) {
        r = (MC__RAW(a) < 0) ? -INT32_MAX : INT32_MAX;
    }
    return MC__MK(r);
}

static inline mc_t mc_sub(mc_t a, mc_t b)
{
    int32_t r;
    if (__builtin_sub_overflow(MC__RAW(a), MC__RAW(b), &r)) {
        r = (MC__RAW(a) < 0) ? -INT32_MAX : INT32_MAX;
    }
    return MC__MK(r);
}

/* Round (half up) and saturate a Q34 64-bit product sum to Q17: the result
 * fits iff the high word hi of p + 2^16 is in [-2^16, 2^16). The candidate
 * r = p >> 17 (low 32 bits) holds hi's low 17 bits in its top 17, so
 * r >> 15 (arithmetic) is hi sign-extended from its bit 16, which equals hi
 * exactly when hi is in that range: the test is one compare against r with
 * a shifted operand (adds/adc/lsl/orr/cmp + branch on Cortex-M3, one
 * instruction less than testing hi + 2^16 < 2^17, the same value for every p). */
static inline int32_t mc__round_sat_q34(int64_t p)
{
    p += (int64_t)1 << (MC_FRAC_BITS - 1);
    const uint32_t hi = (uint32_t)((uint64_t)p >> 32);
    const int32_t r = (int32_t)(((uint32_t)p >> MC_FRAC_BITS) | (hi << (32 - MC_FRAC_BITS)));
    if ((int32_t)hi != (r >> (32 - MC_FRAC_BITS))) {
        /* cppcheck-suppress knownConditionTrueFalse ; false positive: hi is the high word of a
         * signed 64-bit sum, >= 2^31 (negative as int32_t) whenever p < 0 */
        return ((int32_t)hi < 0) ? -INT32_MAX : INT32_MAX;
    }
    return r;
}

static inline mc_t mc_mul(mc_t a, mc_t b) { return MC__MK(mc__round_sat_q34(mc__smul64(MC__RAW(a), MC__RAW(b)))); }

/* round(ua 2^17 / ub) (ties up) for ub > 0, saturated to INT32_MAX: the
 * Newton reciprocal gives the quotient within a few units, one 64-bit
 * multiply-back fixes it to exact rounding. */
static inline int32_t mc__udiv_q17(uint32_t ua, uint32_t ub)
{
    if (ua < (1u << 14)) {
        /* ua 2^17 < 2^31: one hardware divide, exactly rounded */
        return (int32_t)(((ua << MC_FRAC_BITS) + (ub >> 1)) / ub);
    }
    if (ua < (1u << 19) && ub < (1u << 27)) {
        /* two-digit long division: ua 2^17 = (q1 ub + r1) 2^4 */
        const uint32_t q1 = (ua << 13) / ub;
        if (q1 >= (1u << 27)) {
            return INT32_MAX;
        }
        const uint32_t r1 = (ua << 13) - q1 * ub;
        return (int32_t)((q1 << 4) + ((r1 << 4) + (ub >> 1)) / ub);
    }
    if (ub < (1u << 27)) {
        /* long division in 32-bit hardware divides: the integer digit, then
         * 17 fraction bits in chunks of 5, 5, 5 and 2 (r < ub < 2^27, so
         * r << 5 fits); exact, and far cheaper than the 64-bit path */
        uint32_t q = ua / ub;
        if (q >= (1u << 14)) {
            return INT32_MAX;
        }
        uint32_t r = ua - q * ub;
        static const uint8_t chunk[4] = {5u, 5u, 5u, 2u};
        for (int i = 0; i < 4; ++i) {
            r <<= chunk[i];
            const uint32_t d = r / ub;
            r -= d * ub;
            q = (q << chunk[i]) | d;
        }
        return (int32_t)(q + ((2u * r >= ub) ? 1u : 0u));
    }
    const int sh = __builtin_clz(ub);
    const uint32_t R = mc__recip(ub << sh); /* ~2^63 / (ub 2^sh) */
    /* q ~ ua 2^17 / ub = ua R / 2^(46 - sh); ua <= 2^31 so ua R < 2^63 */
    uint64_t q = mc__umul64(ua, R) >> (46 - sh);
    if (q > (uint64_t)INT32_MAX + 1u) {
        return INT32_MAX;
    }
    int64_t rem = (int64_t)((uint64_t)ua << MC_FRAC_BITS) - (int64_t)(q * ub);
    while (2 * rem >= (int64_t)ub) {
        ++q;
        rem -= ub;
    }
    while (2 * rem < -(int64_t)ub) {
        --q;
        rem += ub;
    }
    return (q > (uint64_t)INT32_MAX) ? INT32_MAX : (int32_t)q;
}

/* a / b, exactly rounded (ties away from zero); b == 0 saturates with the
 * sign of a; results beyond the range saturate. */
static inline mc_t mc_div(mc_t a, mc_t b)
{
    const int32_t ra = MC__RAW(a);
    const int32_t rb = MC__RAW(b);
    if (rb == 0) {
        return MC__MK((ra >= 0) ? INT32_MAX : -INT32_MAX);
    }
    const int32_t q = mc__udiv_q17(mc__uabs(ra), mc__uabs(rb));
    return MC__MK(((ra < 0) != (rb < 0)) ? -q : q);
}

/* num / den as a value (not raw), exactly rounded; 0 if den == 0. */
static inline mc_t mc_ratio_i(int32_t num, int32_t den)
{
    if (den == 0) {
        return MC_ZERO;
    }
    const int32_t q = mc__udiv_q17(mc__uabs(num), mc__uabs(den));
    return MC__MK(((num < 0) != (den < 0)) ? -q : q);
}

static inline mc_t mc_neg(mc_t a) { return MC__MK((MC__RAW(a) == INT32_MIN) ? INT32_MAX : -MC__RAW(a)); }
static inline mc_t mc_abs(mc_t a) { return (MC__RAW(a) < 0) ? mc_neg(a) : a; }
static inline mc_t mc_min(mc_t a, mc_t b) { return (MC__RAW(a) < MC__RAW(b)) ? a : b; }
static inline mc_t mc_max(mc_t a, mc_t b) { return (MC__RAW(a) > MC__RAW(b)) ? a : b; }
static inline mc_t mc_clamp(mc_t x, mc_t lo, mc_t hi)
{
    return (MC__RAW(x) < MC__RAW(lo)) ? lo : ((MC__RAW(x) > MC__RAW(hi)) ? hi : x);
}
/* every fixed-point value is finite (saturating arithmetic, no NaN) */
static inline bool mc_is_finite(mc_t x) { (void)x; return true; }
static inline mc_t mc_mul_i(mc_t a, int32_t n) { return MC__MK(mc__sat64(mc__smul64(MC__RAW(a), n))); }

/* a b + c d, a b - c d and acc + a b with ONE rounding and saturation of the
 * exact 64-bit sum (cheaper and more accurate than mc_mul + mc_add). */
static inline mc_t mc_dot2(mc_t a, mc_t b, mc_t c, mc_t d)
{
    return MC__MK(mc__round_sat_q34(mc__smlal64(mc__smul64(MC__RAW(a), MC__RAW(b)), MC__RAW(c), MC__RAW(d))));
}
static inline mc_t mc_cross2(mc_t a, mc_t b, mc_t c, mc_t d)
{
    return MC__MK(mc__round_sat_q34(mc__smul64(MC__RAW(a), MC__RAW(b)) - mc__smul64(MC__RAW(c), MC__RAW(d))));
}
static inline mc_t mc_mac(mc_t acc, mc_t a, mc_t b)
{
    return MC__MK(mc__round_sat_q34(mc__smlal64((int64_t)MC__RAW(acc) * MC_ONE_RAW, MC__RAW(a), MC__RAW(b))));
}

/* a / n rounded to nearest (ties away from zero); n == 0 saturates. */
static inline mc_t mc_div_i(mc_t a, int32_t n)
{
    const int32_t ra = MC__RAW(a);
    if (n == 0) {
        return MC__MK((ra >= 0) ? INT32_MAX : -INT32_MAX);
    }
    const uint32_t un = mc__uabs(n);
    uint32_t q = (mc__uabs(ra) + (un >> 1)) / un; /* <= 2^31 + 2^30: no wrap */
    if (q > (uint32_t)INT32_MAX) {
        q = (uint32_t)INT32_MAX;
    }
    return MC__MK(((ra < 0) != (n < 0)) ? -(int32_t)q : (int32_t)q);
}

static inline mc_t mc_from_i(int32_t n) { return MC__MK(mc__sat64((int64_t)n * MC_ONE_RAW)); }

/* nearest integer, ties upward (x.5 -> x+1) */
static inline int32_t mc_round_i(mc_t x)
{
    return (MC__RAW(x) >> MC_FRAC_BITS) + ((MC__RAW(x) >> (MC_FRAC_BITS - 1)) & 1);
}

static inline mc_t mc_sgn(mc_t x)
{
    return MC__MK((MC__RAW(x) > 0) ? MC_ONE_RAW : ((MC__RAW(x) < 0) ? -MC_ONE_RAW : 0));
}
/* m sgn(x) for m >= 0, exact (a select, no multiply) */
static inline mc_t mc_mul_sgn(mc_t m, mc_t x)
{
    return MC__MK((MC__RAW(x) > 0) ? MC__RAW(m) : ((MC__RAW(x) < 0) ? -MC__RAW(m) : 0));
}

static inline mc_t mc_sqrt(mc_t x)
{
    return MC__MK((MC__RAW(x) > 0) ? (int32_t)mc__sqrt_q17((uint32_t)MC__RAW(x)) : 0);
}

static inline mc_t mc_rsqrt(mc_t x)
{
    return MC__MK((MC__RAW(x) > 0) ? (int32_t)mc__rsqrt_q17((uint32_t)MC__RAW(x)) : INT32_MAX);
}

static inline mc_t mc_sqrt_abs_sgn(mc_t x)
{
    const int32_t rx = MC__RAW(x);
    if (rx == 0) {
        return MC_ZERO;
    }
    const int32_t r = (int32_t)mc__sqrt_q17_n((rx == INT32_MIN) ? (uint32_t)INT32_MAX : mc__uabs(rx), 1);
    return MC__MK((rx < 0) ? -r : r);
}

static inline mc_t mc_hypot(mc_t a, mc_t b)
{
    const uint64_t ua = mc__uabs(MC__RAW(a));
    const uint64_t ub = mc__uabs(MC__RAW(b));
    const uint32_t r = mc__isqrt64(ua * ua + ub * ub); /* < 2^63 */
    return MC__MK((r > (uint32_t)INT32_MAX) ? INT32_MAX : (int32_t)r);
}

static inline void mc_sincos(mc_t x, mc_t *s, mc_t *c)
{
    int32_t s30;
    int32_t c30;
    mc__sincos_bam_q30(mc__bam_of_q17_64(MC__RAW(x)), &s30, &c30);
    *s = MC__MK(mc__q30_to_q17(s30));
    *c = MC__MK(mc__q30_to_q17(c30));
}

/* atan2 in (-pi, pi] (0 for (0, 0)), any int32 scale of (y, x). */
static inline mc_t mc_atan2(mc_t y, mc_t x)
{
    const uint32_t ax = mc__uabs(MC__RAW(x));
    const uint32_t ay = mc__uabs(MC__RAW(y));
    const uint32_t mx = (ax > ay) ? ax : ay;
    uint32_t mn = (ax > ay) ? ay : ax;
    if (mx == 0u) {
        return MC_ZERO;
    }
    const int sh = __builtin_clz(mx);
    const uint32_t R = mc__recip(mx << sh);
    mn <<= sh;
    uint32_t z31 = (uint32_t)(mc__umul64(mn, R) >> 32); /* Q31 of mn/mx in [0, 1] */
    if (z31 > 0x7FFFFFFFu) {
        z31 = 0x7FFFFFFFu;
    }
    const int32_t z = (int32_t)z31;
    const int32_t z2 = mc__mulhi(z, z); /* Q30 */
    /* minimax odd polynomial of degree 13 on [0, 1], |err| < 2.5e-7, Q31 coefficients */
    int32_t p = 14628191;
    p = -72164444 + mc__mulhi(z2, p) * 4;
    p = 170990456 + mc__mulhi(z2, p) * 4;
    p = -284183817 + mc__mulhi(z2, p) * 4;
    p = 425369590 + mc__mulhi(z2, p) * 4;
    p = -715485030 + mc__mulhi(z2, p) * 4;
    p = 2147475298 + mc__mulhi(z2, p) * 4;
    int32_t a = (mc__mulhi(z, p) + 1) >> 1; /* Q30 -> Q29, [0, pi/4] */
    if (ay > ax) {
        a = 843314857 - a; /* pi/2 in Q29 */
    }
    if (MC__RAW(x) < 0) {
        a = 1686629713 - a; /* pi in Q29 */
    }
    if (MC__RAW(y) < 0) {
        a = -a;
    }
    int32_t r = (a + (1 << 11)) >> 12;
    if (r < -(MC__PI_RAW - 1)) {
        r = -(MC__PI_RAW - 1); /* keep (-pi, pi]: -411775 would be below -pi */
    }
    return MC__MK(r);
}

/* x wrapped into [-MC_PI, MC_PI); exact (unchanged) when already there. */
static inline mc_t mc_wrap_pi(mc_t x)
{
    if (MC__RAW(x) >= -MC__PI_RAW && MC__RAW(x) < MC__PI_RAW) {
        return x;
    }
    return MC__MK(mc__rad_of_bam(mc__bam_of_q17_64(MC__RAW(x))));
}

/* wrap(n_p theta): exact 64-bit product, then the binary-angle wrap. */
static inline mc_t mc_elec_angle(mc_t theta_mech_rad, int32_t n_p)
{
    const int64_t m = (int64_t)MC__RAW(theta_mech_rad) * n_p;
    if (m >= -(int64_t)MC__PI_RAW && m < (int64_t)MC__PI_RAW) {
        return MC__MK(m);
    }
    return MC__MK(mc__rad_of_bam(mc__bam_of_q17_64(m)));
}

#ifdef __cplusplus
}
#endif

#endif /* MC_NUM_FIXED_H */
