// test_mc_math.cpp - the numeric backends of firmware/math/mc_num.h against
// libm in double, over each function's whole input range. Compiled twice,
// with MC_FIXED_POINT=1 (test_mc_math_fixed) and MC_FIXED_POINT=0
// (test_mc_math_float), whatever the build's own numeric type, so both
// backends are checked in every build. The error bounds asserted here are
// the ones stated in mc_num_fixed.h / mc_num_float.h; the measured maxima
// are printed ("[ max-err ] ...").
#include <gtest/gtest.h>

#include <cinttypes>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>

#include "math/mc_convert.h"
#include "math/mc_mean.h"
#include "math/mc_num.h"

namespace {

#if MC_FIXED
#define BACKEND "fixed"
const double LSB = 1.0 / 131072.0;
#else
#define BACKEND "float"
#endif

const long double PI_L = 3.141592653589793238462643383279502884L;

struct MaxErr {
    const char *name;
    double max = 0.0;
    double at = 0.0;
    double at2 = 0.0;
    uint64_t n = 0;
    explicit MaxErr(const char *nm) : name(nm) {}
    void add(double err, double x, double x2 = 0.0)
    {
        ++n;
        err = std::fabs(err);
        if (err > max || std::isnan(err)) {
            max = std::isnan(err) ? INFINITY : err;
            at = x;
            at2 = x2;
        }
    }
    void report(double bound) const
    {
        std::printf("[ max-err ] %s %-16s %.3e (bound %.3e) over %" PRIu64 " inputs, worst at %.9g, %.9g\n", BACKEND,
                    name, max, bound, n, at, at2);
        EXPECT_LE(max, bound) << name;
    }
};

// angular distance in (-pi, pi]
double ang_diff(long double a, long double b)
{
    long double d = std::fmod(a - b, 2.0L * PI_L);
    if (d > PI_L) d -= 2.0L * PI_L;
    if (d <= -PI_L) d += 2.0L * PI_L;
    return (double)d;
}

[[maybe_unused]] double D(mc_t x) { return mc_to_double(x); }

// mc_lt ... mc_ne (the firmware's only comparisons on mc_t) agree with the
// C operators on every pair of a few values around 0 and at the ends
[[maybe_unused]] void expect_comparisons_match_operators()
{
    const mc_t v[] = {mc_neg(MC_MAX), MC_C(-2.0), MC_C(-1e-4), MC_ZERO, MC_C(1e-4), MC_ONE, MC_PI, MC_MAX};
    for (mc_t a : v) {
        for (mc_t b : v) {
            EXPECT_EQ(mc_lt(a, b), a < b);
            EXPECT_EQ(mc_le(a, b), a <= b);
            EXPECT_EQ(mc_gt(a, b), a > b);
            EXPECT_EQ(mc_ge(a, b), a >= b);
            EXPECT_EQ(mc_eq(a, b), a == b);
            EXPECT_EQ(mc_ne(a, b), a != b);
        }
    }
}

#if MC_FIXED
// ----------------------------------------------------------------------------
// fixed point: inputs are every int32 raw value (strided), dense near 0, random
// ----------------------------------------------------------------------------
template <typename F>
void for_raw_inputs(uint32_t stride, int32_t dense, uint32_t n_random, F f)
{
    for (int64_t r = INT32_MIN; r <= INT32_MAX; r += stride) f((int32_t)r);
    f(INT32_MAX);
    for (int32_t r = -dense; r <= dense; ++r) f(r);
    std::mt19937_64 rng(12345);
    for (uint32_t i = 0; i < n_random; ++i) f((int32_t)(uint32_t)rng());
}

TEST(McMathFixed, FormatConstants)
{
    EXPECT_EQ(MC_FRAC_BITS, 17);
    EXPECT_EQ(MC_ONE, 131072);
    EXPECT_EQ(MC_C(1.0), 131072);
    EXPECT_EQ(MC_C(-1.0), -131072);
    EXPECT_EQ(MC_C(2.37e-3), 311);           // f_v: 0.16 % quantisation
    EXPECT_EQ(MC_C(1e6), INT32_MAX);          // saturates
    EXPECT_EQ(MC_C(-1e6), -INT32_MAX);
    EXPECT_NEAR(D(MC_PI), 3.14159265358979, 0.5 * LSB);
    EXPECT_NEAR(D(MC_TWO_PI), 6.28318530717959, 0.5 * LSB);
    EXPECT_NEAR(D(MC_HALF_PI), 1.5707963267949, 0.5 * LSB);
    EXPECT_EQ(mc_from_double(1e9), INT32_MAX);
    EXPECT_EQ(mc_from_double(-1e9), -INT32_MAX);
    EXPECT_EQ(mc_from_double(NAN), 0);
    EXPECT_EQ(mc_to_double(MC_C(-2.5)), -2.5);
}

TEST(McMathFixed, ComparisonsAndRawAccess)
{
    expect_comparisons_match_operators();
    EXPECT_EQ(mc_raw(MC_C(-1.0)), -131072);
    EXPECT_EQ(mc_raw(MC_PI), 411775);
    EXPECT_EQ(mc_from_raw(1), MC_C(7.62939453125e-06));
    EXPECT_EQ(mc_from_raw(INT32_MIN), INT32_MIN);
}

TEST(McMathFixed, SaturatingAddSubNegAbs)
{
    const mc_t big = MC_C(16000.0);
    EXPECT_EQ(mc_add(big, big), INT32_MAX);
    EXPECT_EQ(mc_add(-big, -big), -INT32_MAX);
    EXPECT_EQ(mc_sub(big, -big), INT32_MAX);
    EXPECT_EQ(mc_sub(-big, big), -INT32_MAX);
    EXPECT_EQ(mc_add(MC_C(1.5), MC_C(-0.25)), MC_C(1.25));
    EXPECT_EQ(mc_neg(INT32_MIN), INT32_MAX);
    EXPECT_EQ(mc_abs(INT32_MIN), INT32_MAX);
    EXPECT_EQ(mc_abs(MC_C(-3.0)), MC_C(3.0));
    EXPECT_EQ(mc_clamp(MC_C(5.0), MC_C(-1.0), MC_C(1.0)), MC_C(1.0));
    EXPECT_EQ(mc_clamp(MC_C(-5.0), MC_C(-1.0), MC_C(1.0)), MC_C(-1.0));
    EXPECT_EQ(mc_min(MC_C(2.0), MC_C(-2.0)), MC_C(-2.0));
    EXPECT_EQ(mc_max(MC_C(2.0), MC_C(-2.0)), MC_C(2.0));
    EXPECT_EQ(mc_sgn(MC_C(-0.001)), -MC_ONE);
    EXPECT_EQ(mc_sgn(0), 0);
    EXPECT_EQ(mc_sgn(1), MC_ONE);
}

TEST(McMathFixed, MulIsExactlyRoundedAndSaturates)
{
    std::mt19937_64 rng(1);
    MaxErr e("mc_mul");
    for (int i = 0; i < 2000000; ++i) {
        // magnitudes spread over the whole range
        const int sa = (int)(rng() % 32), sb = (int)(rng() % 32);
        const int32_t a = (int32_t)((int64_t)(rng() & 0x7FFFFFFF) >> sa) * ((rng() & 1) ? 1 : -1);
        const int32_t b = (int32_t)((int64_t)(rng() & 0x7FFFFFFF) >> sb) * ((rng() & 1) ? 1 : -1);
        const long double ex = (long double)a * b / 131072.0L / 131072.0L;
        const mc_t r = mc_mul(a, b);
        if (std::fabs((double)ex) >= 16383.99999) {
            ASSERT_TRUE(ex > 0 ? r == INT32_MAX : r <= -INT32_MAX) << a << " * " << b;
        } else {
            e.add((double)(ex - (long double)D(r)), D(a), D(b));
        }
    }
    e.report(0.5 * LSB);
    EXPECT_EQ(mc_mul(MC_C(2.37e-3), MC_C(200.0)), MC_C(311 * 200.0 / 131072.0));
    EXPECT_EQ(mc_mul_i(MC_C(3.0), 50), MC_C(150.0));
    EXPECT_EQ(mc_mul_i(MC_C(1000.0), 50), INT32_MAX);
    EXPECT_EQ(mc_mul_i(MC_C(-1000.0), 50), -INT32_MAX);
}

TEST(McMathFixed, Dot2Cross2MacExactlyRounded)
{
    std::mt19937_64 rng(21);
    MaxErr e("mc_dot2/cross2/mac");
    auto rnd = [&]() { return (int32_t)((int64_t)(rng() & 0x7FFFFFFF) >> (rng() % 32)) * ((rng() & 1) ? 1 : -1); };
    for (int i = 0; i < 1000000; ++i) {
        const int32_t a = rnd(), b = rnd(), c = rnd(), d = rnd();
        const long double s = 131072.0L * 131072.0L;
        const long double ex[3] = {((long double)a * b + (long double)c * d) / s,
                                   ((long double)a * b - (long double)c * d) / s,
                                   (long double)a / 131072.0L + (long double)b * c / s};
        const mc_t r[3] = {mc_dot2(a, b, c, d), mc_cross2(a, b, c, d), mc_mac(a, b, c)};
        for (int k = 0; k < 3; ++k) {
            if (std::fabs((double)ex[k]) >= 16383.99999) {
                ASSERT_TRUE(ex[k] > 0 ? r[k] == INT32_MAX : r[k] <= -INT32_MAX);
            } else {
                e.add((double)(ex[k] - (long double)D(r[k])), D(a), D(b));
            }
        }
    }
    e.report(0.5 * LSB);
}

TEST(McMathFixed, DivWithinBound)
{
    std::mt19937_64 rng(2);
    MaxErr e("mc_div");
    for (int i = 0; i < 2000000; ++i) {
        const int sa = (int)(rng() % 32), sb = (int)(rng() % 32);
        const int32_t a = (int32_t)((int64_t)(rng() & 0x7FFFFFFF) >> sa) * ((rng() & 1) ? 1 : -1);
        int32_t b = (int32_t)((int64_t)(rng() & 0x7FFFFFFF) >> sb) * ((rng() & 1) ? 1 : -1);
        if (b == 0) b = 1;
        const double ex = (double)a / (double)b;
        const mc_t r = mc_div(a, b);
        if (std::fabs(ex) >= 16383.99999) {
            ASSERT_EQ(r, ex > 0 ? INT32_MAX : -INT32_MAX) << a << " / " << b;
        } else {
            e.add(ex - D(r), D(a), D(b));
        }
    }
    e.report(0.5 * LSB + 1e-12);
    EXPECT_EQ(mc_div(MC_C(1.0), 0), INT32_MAX);
    EXPECT_EQ(mc_div(MC_C(-1.0), 0), -INT32_MAX);
    EXPECT_EQ(mc_div(MC_C(6.0), MC_C(-2.0)), MC_C(-3.0));
    EXPECT_EQ(mc_div(INT32_MIN, INT32_MIN), MC_ONE);
    EXPECT_EQ(mc_div(INT32_MIN, 1), -INT32_MAX);
    MaxErr er("mc_ratio_i");
    for (int i = 0; i < 1000000; ++i) {
        const int32_t num = (int32_t)(uint32_t)rng() >> (rng() % 32);
        int32_t den = (int32_t)(uint32_t)rng() >> (rng() % 32);
        if (den == 0) den = -3;
        const double ex = (double)num / den;
        const mc_t r = mc_ratio_i(num, den);
        if (std::fabs(ex) >= 16383.99999) {
            ASSERT_EQ(r, ex > 0 ? INT32_MAX : -INT32_MAX);
        } else {
            er.add(ex - D(r), num, den);
        }
    }
    er.report(0.5 * LSB + 1e-12);
    EXPECT_EQ(mc_ratio_i(1, 3), 43691);
    EXPECT_EQ(mc_ratio_i(5, 0), 0);
    EXPECT_EQ(mc_ratio_i(-7, 2), MC_C(-3.5));
}

TEST(McMathFixed, IntegerHelpers)
{
    EXPECT_EQ(mc_from_i(3), MC_C(3.0));
    EXPECT_EQ(mc_from_i(-16383), MC_C(-16383.0));
    EXPECT_EQ(mc_from_i(16384), INT32_MAX);
    EXPECT_EQ(mc_from_i(-100000), -INT32_MAX);
    EXPECT_EQ(mc_round_i(MC_C(2.4999)), 2);
    EXPECT_EQ(mc_round_i(MC_C(2.5)), 3);
    EXPECT_EQ(mc_round_i(MC_C(-2.5)), -2);
    EXPECT_EQ(mc_round_i(MC_C(-2.5001)), -3);
    EXPECT_EQ(mc_round_i(INT32_MAX), 16384);
    EXPECT_EQ(mc_div_i(MC_C(1.0), 3), 43691);  // 131072/3 = 43690.67
    EXPECT_EQ(mc_div_i(MC_C(-1.0), 3), -43691);
    EXPECT_EQ(mc_div_i(MC_C(1.0), -3), -43691);
    EXPECT_EQ(mc_div_i(INT32_MIN, -1), INT32_MAX);
    EXPECT_EQ(mc_div_i(MC_C(1.0), 0), INT32_MAX);
    std::mt19937_64 rng(3);
    for (int i = 0; i < 200000; ++i) {
        const int32_t a = (int32_t)(uint32_t)rng();
        int32_t n = (int32_t)(rng() % 2001) - 1000;
        if (n == 0) n = 7;
        const double ex = (double)a / n;
        EXPECT_LE(std::fabs(ex - mc_div_i(a, n)), 0.5) << a << " / " << n;
    }
}

TEST(McMathFixed, SqrtExactlyRoundedOverWholeRange)
{
    MaxErr e("mc_sqrt");
    for_raw_inputs(61, 1 << 20, 1000000, [&](int32_t x) {
        const mc_t r = mc_sqrt(x);
        if (x <= 0) {
            ASSERT_EQ(r, 0);
            return;
        }
        e.add(std::sqrt((long double)x / 131072.0L) - D(r), D(x));
    });
    e.report(0.8 * LSB);
    // mc_sqrt_abs_sgn (the super-twisting root term) uses one Newton step:
    // bound 0.8 LSB + 2.5e-5 |sqrt|, checked as the worst ratio to it
    double worst_ratio = 0.0, worst_at = 0.0;
    for_raw_inputs(97, 1 << 16, 1000000, [&](int32_t x) {
        const long double ax = std::fabs((long double)x) / 131072.0L;
        const long double ex = (x < 0 ? -1 : 1) * std::sqrt(ax);
        const double err = std::fabs((double)(ex - (long double)D(mc_sqrt_abs_sgn(x))));
        const double ratio = err / (0.8 * LSB + 2.5e-5 * std::sqrt((double)ax));
        if (ratio > worst_ratio) {
            worst_ratio = ratio;
            worst_at = D(x);
        }
    });
    std::printf("[ max-err ] fixed mc_sqrt_abs_sgn  %.3f of (0.8 LSB + 2.5e-5 |sqrt|), worst at %.6f\n", worst_ratio,
                worst_at);
    EXPECT_LE(worst_ratio, 1.0);
}

TEST(McMathFixed, RsqrtOverWholeRange)
{
    MaxErr e("mc_rsqrt");
    for_raw_inputs(61, 1 << 20, 1000000, [&](int32_t x) {
        if (x <= 0) return;
        const long double ex = 1.0L / std::sqrt((long double)x / 131072.0L);
        // bound 0.8 LSB + 2e-7 relative: report the error scaled to the LSB part
        const long double err = std::fabs(ex - (long double)D(mc_rsqrt(x)));
        e.add((double)(err - 2e-7L * ex > 0 ? err - 2e-7L * ex : 0.0L), D(x));
    });
    e.report(0.8 * LSB);
    EXPECT_EQ(mc_rsqrt(0), INT32_MAX);
    EXPECT_EQ(mc_rsqrt(-5), INT32_MAX);
}

TEST(McMathFixed, HypotExactlyRounded)
{
    std::mt19937_64 rng(4);
    MaxErr e("mc_hypot(<256)"), eb("mc_hypot(rel,>=256)");
    for (int i = 0; i < 3000000; ++i) {
        const int s = (int)(rng() % 32);
        const int32_t a = (int32_t)((uint32_t)rng() >> 1 >> s) * ((rng() & 1) ? 1 : -1);
        const int32_t b = (int32_t)((uint32_t)rng() >> 1 >> (s + (int)(rng() % 4)) % 32) * ((rng() & 1) ? 1 : -1);
        const long double ex = std::sqrt((long double)a * a + (long double)b * b) / 131072.0L;
        const mc_t r = mc_hypot(a, b);
        if (ex >= 16383.99999L) {
            ASSERT_EQ(r, INT32_MAX);
        } else if (ex < 256.0L) {
            e.add((double)(ex - (long double)D(r)), D(a), D(b));
        } else {
            eb.add((double)((ex - (long double)D(r)) / ex), D(a), D(b));
        }
    }
    EXPECT_EQ(mc_hypot(INT32_MIN, INT32_MIN), INT32_MAX);
    EXPECT_EQ(mc_hypot(0, 0), 0);
    EXPECT_EQ(mc_hypot(MC_C(3.0), MC_C(-4.0)), MC_C(5.0));
    e.report(0.8 * LSB);
    eb.report(std::ldexp(1.0, -24));
}

TEST(McMathFixed, SinCosOverWholeRange)
{
    MaxErr es("mc_sincos.sin"), ec("mc_sincos.cos");
    for_raw_inputs(251, 1 << 22, 2000000, [&](int32_t x) {
        mc_t s, c;
        mc_sincos(x, &s, &c);
        const long double xr = (long double)x / 131072.0L;
        es.add((double)(std::sin(xr) - (long double)D(s)), D(x));
        ec.add((double)(std::cos(xr) - (long double)D(c)), D(x));
    });
    es.report(LSB);
    ec.report(LSB);
}

TEST(McMathFixed, Atan2OverWholeRange)
{
    MaxErr e("mc_atan2");
    auto check = [&](int32_t y, int32_t x) {
        const mc_t r = mc_atan2(y, x);
        if (x == 0 && y == 0) {
            ASSERT_EQ(r, 0);
            return;
        }
        ASSERT_GT(r, -MC_PI);
        ASSERT_LE(r, MC_PI);
        e.add((double)(std::atan2((long double)y, (long double)x) - (long double)D(r)), D(y), D(x));
    };
    for (int32_t y = -80; y <= 80; ++y)
        for (int32_t x = -80; x <= 80; ++x) check(y, x);
    std::mt19937_64 rng(5);
    for (int i = 0; i < 4000000; ++i) {
        const int sy = (int)(rng() % 32), sx = (int)(rng() % 32);
        const int32_t y = (int32_t)((uint32_t)rng() >> sy);
        const int32_t x = (int32_t)((uint32_t)rng() >> sx);
        check(y, x);
    }
    // along the circle, angles dense (the drive's use: back-EMF vectors)
    for (int k = 0; k < 2000000; ++k) {
        const double a = -M_PI + 2.0 * M_PI * k / 2000000.0;
        const double m = 60.0 * 131072.0 * std::pow(10.0, -(k % 7));
        check((int32_t)std::lround(m * std::sin(a)), (int32_t)std::lround(m * std::cos(a)));
    }
    const int32_t ext[] = {INT32_MIN, INT32_MIN + 1, -1, 0, 1, INT32_MAX};
    for (int32_t y : ext)
        for (int32_t x : ext) check(y, x);
    EXPECT_EQ(mc_atan2(0, MC_C(-1.0)), MC_PI);
    e.report(LSB);
}

TEST(McMathFixed, WrapPiOverWholeRange)
{
    MaxErr e("mc_wrap_pi");
    for_raw_inputs(127, 1 << 21, 1000000, [&](int32_t x) {
        const mc_t r = mc_wrap_pi(x);
        ASSERT_GE(r, -MC_PI);
        ASSERT_LT(r, MC_PI);
        if (x >= -MC_PI && x < MC_PI) {
            ASSERT_EQ(r, x);
        }
        e.add(ang_diff((long double)x / 131072.0L, (long double)D(r)), D(x));
    });
    e.report(LSB);
}

TEST(McMathFixed, ElecAngleWrapsWithoutOverflow)
{
    MaxErr e("mc_elec_angle");
    const int32_t nps[] = {1, 2, 3, 7, 50, 200, 1024, -50};
    for (int32_t np : nps) {
        for_raw_inputs(1021, 1 << 18, 200000, [&](int32_t th) {
            const mc_t r = mc_elec_angle(th, np);
            ASSERT_GE(r, -MC_PI);
            ASSERT_LT(r, MC_PI);
            e.add(ang_diff((long double)th * np / 131072.0L, (long double)D(r)), D(th), np);
        });
    }
    // multi-turn positions of the drive: 0..18 rad and a few hundred rad at n_p = 50
    for (int32_t th = 0; th <= MC_C(400.0); th += 3) {
        e.add(ang_diff((long double)th * 50 / 131072.0L, (long double)D(mc_elec_angle(th, 50))), D(th), 50);
    }
    e.report(LSB);
}

#else
// ----------------------------------------------------------------------------
// float32
// ----------------------------------------------------------------------------
float rand_float(std::mt19937_64 &rng, int emin, int emax)
{
    const int ex = emin + (int)(rng() % (uint64_t)(emax - emin + 1));
    const double m = 1.0 + (double)(rng() >> 11) * 0x1.0p-53;
    return (float)std::ldexp((rng() & 1) ? m : -m, ex);
}

TEST(McMathFloat, Basics)
{
    EXPECT_EQ(mc_round_i(2.5f), 2);  // ties to even, like lrintf
    EXPECT_EQ(mc_round_i(3.5f), 4);
    EXPECT_EQ(mc_round_i(-2.6f), -3);
    EXPECT_EQ(mc_round_i(1e10f), INT32_MAX);
    EXPECT_EQ(mc_round_i(-1e10f), INT32_MIN);
    EXPECT_EQ(mc_round_i(16777216.0f), 16777216);
    EXPECT_EQ(mc_div(1.0f, 0.0f), MC_MAX);
    EXPECT_EQ(mc_div(-1.0f, 0.0f), -MC_MAX);
    EXPECT_EQ(mc_sqrt(-1.0f), 0.0f);
    EXPECT_EQ(mc_ratio_i(1, 3), 1.0f / 3.0f);
    EXPECT_EQ(mc_ratio_i(5, 0), 0.0f);
    EXPECT_EQ(mc_sqrt_abs_sgn(-4.0f), -2.0f);
    EXPECT_EQ(mc_hypot(3.0f, -4.0f), 5.0f);
    std::mt19937_64 rng(6);
    for (int i = 0; i < 1000000; ++i) {
        const float x = rand_float(rng, -20, 21);
        ASSERT_EQ(mc_round_i(x), (int32_t)std::lrint(x)) << x;
    }
}

TEST(McMathFloat, Comparisons)
{
    expect_comparisons_match_operators();
    EXPECT_FALSE(mc_lt(NAN, 0.0f));  // as the operators: NaN is unordered
    EXPECT_FALSE(mc_ge(NAN, 0.0f));
    EXPECT_TRUE(mc_ne(NAN, NAN));
}

TEST(McMathFloat, Dot2IsMulAdd)
{
    std::mt19937_64 rng(22);
    for (int i = 0; i < 100000; ++i) {
        const float a = rand_float(rng, -10, 10), b = rand_float(rng, -10, 10);
        const float c = rand_float(rng, -10, 10), d = rand_float(rng, -10, 10);
        ASSERT_EQ(mc_dot2(a, b, c, d), mc_add(mc_mul(a, b), mc_mul(c, d)));
        ASSERT_EQ(mc_cross2(a, b, c, d), mc_sub(mc_mul(a, b), mc_mul(c, d)));
        ASSERT_EQ(mc_mac(a, b, c), mc_add(a, mc_mul(b, c)));
    }
}

TEST(McMathFloat, HypotRelative)
{
    std::mt19937_64 rng(7);
    MaxErr e("mc_hypot(rel)");
    for (int i = 0; i < 2000000; ++i) {
        const float a = rand_float(rng, -30, 20), b = rand_float(rng, -30, 20);
        const double ex = std::hypot((double)a, (double)b);
        e.add((ex - mc_hypot(a, b)) / ex, a, b);
    }
    e.report(2.4e-7);
}

TEST(McMathFloat, SinCos)
{
    MaxErr es("mc_sincos.sin"), ec("mc_sincos.cos");
    auto check = [&](float x, MaxErr &s_err, MaxErr &c_err) {
        float s, c;
        mc_sincos(x, &s, &c);
        s_err.add(std::sin((long double)x) - (long double)s, x);
        c_err.add(std::cos((long double)x) - (long double)c, x);
    };
    for (int k = -8192000 * 2; k <= 8192000 * 2; ++k) check((float)k * 0.0005f, es, ec);
    std::mt19937_64 rng(8);
    for (int i = 0; i < 4000000; ++i) {
        const float x = rand_float(rng, -40, 12);
        if (std::fabs(x) <= 8192.0f) check(x, es, ec);
    }
    es.report(2.0e-7);
    ec.report(2.0e-7);
    MaxErr fs("sin 8192..65536"), fc("cos 8192..65536");
    for (int i = 0; i < 2000000; ++i) {
        const float x = rand_float(rng, 13, 15);
        check(x, fs, fc);
    }
    fs.report(2.0e-6);
    fc.report(2.0e-6);
    // far outside: still a unit vector, finite
    for (int i = 0; i < 100000; ++i) {
        const float x = rand_float(rng, 16, 127);
        float s, c;
        mc_sincos(x, &s, &c);
        ASSERT_TRUE(std::fabs(s) <= 1.0f && std::fabs(c) <= 1.0f) << x;
        ASSERT_NEAR((double)s * s + (double)c * c, 1.0, 1e-6) << x;
    }
}

TEST(McMathFloat, Atan2)
{
    MaxErr e("mc_atan2");
    auto check = [&](float y, float x) {
        const float r = mc_atan2(y, x);
        if (x == 0.0f && y == 0.0f) {
            ASSERT_EQ(r, 0.0f);
            return;
        }
        ASSERT_GE(r, -MC_PI);
        ASSERT_LE(r, MC_PI);
        e.add(std::atan2((long double)y, (long double)x) - (long double)r, y, x);
    };
    std::mt19937_64 rng(9);
    for (int i = 0; i < 4000000; ++i) check(rand_float(rng, -30, 30), rand_float(rng, -30, 30));
    for (int i = 0; i < 4000000; ++i) {
        const float x = rand_float(rng, -10, 10);
        check(x * (float)(1.0 + 0.02 * ((double)(rng() % 1000) / 1000.0 - 0.5)), x);
    }
    for (int k = 0; k < 4000000; ++k) {
        const double a = -M_PI + 2.0 * M_PI * k / 4000000.0;
        const double m = 60.0 * std::pow(10.0, -(k % 9));
        check((float)(m * std::sin(a)), (float)(m * std::cos(a)));
    }
    const float ext[] = {-3e38f, -1.0f, -1e-38f, 0.0f, 1e-38f, 1.0f, 3e38f};
    for (float y : ext)
        for (float x : ext) check(y, x);
    e.report(4.0e-7);
}

TEST(McMathFloat, WrapPi)
{
    MaxErr e("mc_wrap_pi");
    auto check = [&](float x) {
        const float r = mc_wrap_pi(x);
        ASSERT_GE(r, -MC_PI) << x;
        ASSERT_LT(r, MC_PI) << x;
        if (x >= -MC_PI && x < MC_PI) {
            ASSERT_EQ(r, x);
        }
        if (std::fabs(x) <= 1e5f) e.add(ang_diff((long double)x, (long double)r), x);
    };
    std::mt19937_64 rng(10);
    for (int i = 0; i < 4000000; ++i) check(rand_float(rng, -30, 16));
    for (int k = -2000000; k <= 2000000; ++k) check((float)k * 0.001f);
    for (int i = 0; i < 100000; ++i) check(rand_float(rng, 17, 127));
    // the ends of [-pi, pi) exactly, and their float neighbours: +pi
    // itself is outside (random floats never hit it)
    for (const float x : {MC_PI, -MC_PI, std::nextafter(MC_PI, 0.0f), std::nextafter(MC_PI, 4.0f),
                          std::nextafter(-MC_PI, -4.0f), 3.0f * MC_PI, -3.0f * MC_PI}) {
        check(x);
    }
    EXPECT_EQ(mc_wrap_pi(MC_PI), -MC_PI);
    e.report(4.0e-7);
}

TEST(McMathFloat, ElecAngle)
{
    MaxErr e("mc_elec_angle");
    std::mt19937_64 rng(11);
    const int32_t nps[] = {1, 2, 3, 7, 50, 200, 256, -50};
    for (int32_t np : nps) {
        for (int i = 0; i < 1000000; ++i) {
            const float th = rand_float(rng, -20, 19);
            if (std::fabs((double)th * np) > 4.0e5) continue;
            const float r = mc_elec_angle(th, np);
            ASSERT_GE(r, -MC_PI);
            ASSERT_LT(r, MC_PI);
            e.add(ang_diff((long double)th * np, (long double)r), th, np);
        }
    }
    for (int k = 0; k <= 4000000; ++k) {
        const float th = (float)k * 1e-4f;  // 0..400 rad, n_p = 50
        e.add(ang_diff((long double)th * 50, (long double)mc_elec_angle(th, 50)), th, 50);
    }
    e.report(1.0e-6);
}
#endif

// mc_mean_add (math/mc_mean.h): the mean of N samples added as x/N each,
// the division's remainder carried to the next (the identifications' R,
// L and Phi means). With the remainder carried, mean + res/N is the exact
// sum over N: the mean is within 1 LSB of the exact mean in Q14.17 (the
// last remainder, below N LSB, over N), however large N; each quotient
// rounded alone would lose up to half an LSB a sample, N/2 LSB in all
// (500 LSB, 3.8e-3, at N = 1000). In float the same to a few ulp.
TEST(McMean, RemainderCarriedMeanWithinOneLsb)
{
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-2.0, 3.0);
    for (const int32_t n : {7, 1000, 4096}) {
        mc_t mean = mc_from_double(0.0), res = mc_from_double(0.0);
        double exact = 0.0;
        for (int32_t k = 0; k < n; ++k) {
            const mc_t x = mc_from_double(u(rng));
            exact += mc_to_double(x);
            mc_mean_add(&mean, &res, x, n);
        }
        exact /= n;
#if MC_FIXED
        const double tol = LSB;
#else
        const double tol = 1e-6;  // float: n roundings of 6e-8 of |x| <= 3, on average
#endif
        EXPECT_NEAR(mc_to_double(mean), exact, tol) << "N = " << n << " (" BACKEND ")";
    }
}

}  // namespace
