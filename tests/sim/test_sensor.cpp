// Current sensor model: noise bounds and statistics, independence, seeding
// reproducibility (also across platforms: a golden value), ADC quantization.
#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "model/amplifier.h"
#include "model/current_sensor.h"

namespace {

using mcsim::CurrentSensor;
using mcsim::NoiseKind;
using mcsim::SensorParams;

SensorParams noise(NoiseKind k, double a)
{
    SensorParams p;
    p.noise = k;
    p.noise_A = a;
    return p;
}

struct Stats {
    double mean_a = 0, mean_b = 0, var_a = 0, var_b = 0, corr_ab = 0, lag1_a = 0, min_a = 1e9, max_a = -1e9;
    double frac_within_sigma_a = 0;
};

Stats collect(CurrentSensor& s, int n, double offset_a, double offset_b, double sigma)
{
    std::vector<double> a(n), b(n);
    for (int k = 0; k < n; ++k) {
        double ma = 0;
        double mb = 0;
        s.measure(offset_a, offset_b, &ma, &mb);
        a[k] = ma - offset_a;
        b[k] = mb - offset_b;
    }
    Stats st;
    for (int k = 0; k < n; ++k) {
        st.mean_a += a[k] / n;
        st.mean_b += b[k] / n;
        st.min_a = std::min(st.min_a, a[k]);
        st.max_a = std::max(st.max_a, a[k]);
        st.frac_within_sigma_a += (std::fabs(a[k]) <= sigma) ? 1.0 / n : 0.0;
    }
    double cab = 0;
    double l1 = 0;
    for (int k = 0; k < n; ++k) {
        st.var_a += (a[k] - st.mean_a) * (a[k] - st.mean_a) / n;
        st.var_b += (b[k] - st.mean_b) * (b[k] - st.mean_b) / n;
        cab += (a[k] - st.mean_a) * (b[k] - st.mean_b) / n;
        if (k > 0) {
            l1 += (a[k] - st.mean_a) * (a[k - 1] - st.mean_a) / (n - 1);
        }
    }
    st.corr_ab = cab / std::sqrt(st.var_a * st.var_b);
    st.lag1_a = l1 / st.var_a;
    return st;
}

constexpr int kN = 400000;
// |correlation| of independent samples is ~1/sqrt(n) = 1.6e-3; 5 sigma.
constexpr double kCorrTol = 5.0 / 632.0;

TEST(CurrentSensor, UniformBoundsAndStatistics)
{
    const double a = 0.03;
    CurrentSensor s(noise(NoiseKind::kUniform, a), 1);
    const Stats st = collect(s, kN, 1.5, -2.0, a);
    EXPECT_GE(st.min_a, -a);
    EXPECT_LE(st.max_a, a);
    EXPECT_LT(st.min_a, -0.999 * a);  // the whole interval is used
    EXPECT_GT(st.max_a, 0.999 * a);
    const double var = a * a / 3.0;
    EXPECT_NEAR(st.mean_a, 0.0, 5.0 * std::sqrt(var / kN));
    EXPECT_NEAR(st.mean_b, 0.0, 5.0 * std::sqrt(var / kN));
    EXPECT_NEAR(st.var_a / var, 1.0, 0.01);
    EXPECT_NEAR(st.var_b / var, 1.0, 0.01);
    EXPECT_NEAR(st.corr_ab, 0.0, kCorrTol);
    EXPECT_NEAR(st.lag1_a, 0.0, kCorrTol);
}

TEST(CurrentSensor, GaussianStatistics)
{
    const double sigma = 0.02;
    CurrentSensor s(noise(NoiseKind::kGaussian, sigma), 7);
    const Stats st = collect(s, kN, 0.0, 0.0, sigma);
    EXPECT_NEAR(st.mean_a, 0.0, 5.0 * sigma / std::sqrt(kN));
    EXPECT_NEAR(std::sqrt(st.var_a) / sigma, 1.0, 0.01);
    EXPECT_NEAR(std::sqrt(st.var_b) / sigma, 1.0, 0.01);
    EXPECT_NEAR(st.frac_within_sigma_a, 0.682689, 0.005);
    EXPECT_NEAR(st.corr_ab, 0.0, kCorrTol);
    EXPECT_NEAR(st.lag1_a, 0.0, kCorrTol);
    EXPECT_GT(st.max_a, 3.5 * sigma);  // tails exist
}

TEST(CurrentSensor, NoNoiseIsExact)
{
    CurrentSensor s(SensorParams{}, 1);
    double a = 0;
    double b = 0;
    s.measure(1.234567891, -2.5, &a, &b);
    EXPECT_EQ(a, 1.234567891);
    EXPECT_EQ(b, -2.5);
}

TEST(CurrentSensor, SeedReproducibility)
{
    for (NoiseKind k : {NoiseKind::kUniform, NoiseKind::kGaussian}) {
        CurrentSensor s1(noise(k, 0.03), 42);
        CurrentSensor s2(noise(k, 0.03), 42);
        CurrentSensor s3(noise(k, 0.03), 43);
        int differ = 0;
        for (int i = 0; i < 1000; ++i) {
            double a1 = 0, b1 = 0, a2 = 0, b2 = 0, a3 = 0, b3 = 0;
            s1.measure(0.5, 0.5, &a1, &b1);
            s2.measure(0.5, 0.5, &a2, &b2);
            s3.measure(0.5, 0.5, &a3, &b3);
            ASSERT_EQ(a1, a2);
            ASSERT_EQ(b1, b2);
            differ += (a1 != a3) ? 1 : 0;
        }
        EXPECT_GT(differ, 990);
    }
}

TEST(CurrentSensor, GoldenSequence)
{
    // std::mt19937_64 is fixed by the standard and the transforms are our
    // own, so these values must be the same on every platform and compiler.
    std::mt19937_64 rng(1);
    EXPECT_EQ(rng(), 2469588189546311528ULL);
    std::mt19937_64 rng2(1);
    EXPECT_EQ(mcsim::uniform01(rng2), static_cast<double>(2469588189546311528ULL >> 11) * 0x1.0p-53);
    CurrentSensor s(noise(NoiseKind::kUniform, 0.03), 1);
    double a = 0;
    double b = 0;
    s.measure(0.0, 0.0, &a, &b);
    EXPECT_DOUBLE_EQ(a, 0.03 * (2.0 * static_cast<double>(2469588189546311528ULL >> 11) * 0x1.0p-53 - 1.0));
}

TEST(CurrentSensor, AdcQuantization)
{
    SensorParams p;
    p.adc_bits = 12;
    p.adc_full_scale_A = 10.0;
    CurrentSensor s(p, 1);
    const double lsb = 20.0 / 4096.0;
    EXPECT_EQ(s.quantize(0.0), 0.0);
    EXPECT_EQ(s.quantize(0.4 * lsb), 0.0);
    EXPECT_EQ(s.quantize(0.6 * lsb), lsb);
    EXPECT_EQ(s.quantize(-0.6 * lsb), -lsb);
    EXPECT_EQ(s.quantize(1.0), std::floor(1.0 / lsb + 0.5) * lsb);
    EXPECT_EQ(s.quantize(50.0), 2047 * lsb);   // saturates at the top code
    EXPECT_EQ(s.quantize(-50.0), -2048 * lsb);
    for (double x = -9.9; x < 9.9; x += 0.0137) {
        ASSERT_LE(std::fabs(s.quantize(x) - x), 0.5 * lsb + 1e-15);
    }
    // Noise then quantization: every output is on the grid.
    p.noise = NoiseKind::kUniform;
    p.noise_A = 0.03;
    CurrentSensor sn(p, 3);
    for (int i = 0; i < 1000; ++i) {
        double a = 0;
        double b = 0;
        sn.measure(1.0, -1.0, &a, &b);
        ASSERT_NEAR(a / lsb, std::round(a / lsb), 1e-9);
        ASSERT_LE(std::fabs(a - 1.0), 0.03 + 0.5 * lsb);
    }
}

TEST(Amplifier, ClampsToSupply)
{
    mcsim::Amplifier amp;
    amp.v_max_V = 30.0;
    EXPECT_EQ(amp.apply(12.0), 12.0);
    EXPECT_EQ(amp.apply(31.0), 30.0);
    EXPECT_EQ(amp.apply(-100.0), -30.0);
    EXPECT_EQ(amp.apply(NAN), 0.0);
}

}  // namespace
