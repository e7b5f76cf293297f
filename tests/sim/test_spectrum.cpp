// hf_rms (sim/model/spectrum.h), the chattering measure of paper 002's
// study: a sine above the cut reads its RMS, one below reads ~0, and a sum
// reads only its part above the cut.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "model/spectrum.h"

namespace {

constexpr double kTs = 1e-4;  // 10 kHz, the drives' rate
constexpr double kPi = 3.14159265358979323846;

std::vector<double> sines(int n, double a1, double f1, double a2, double f2)
{
    std::vector<double> x(n);
    for (int k = 0; k < n; ++k) {
        const double t = k * kTs;
        x[k] = 3.0 + a1 * std::sin(2 * kPi * f1 * t) + a2 * std::sin(2 * kPi * f2 * t + 0.3);
    }
    return x;
}

}  // namespace

TEST(Spectrum, HfRmsReadsOnlyWhatLiesAboveTheCut)
{
    const int n = 5000;  // half a second: the second half of paper 002's runs
    // 2 kHz of amplitude 1.5 over 1 kHz: 1.5/sqrt(2); the offset 3 removed
    EXPECT_NEAR(mcsim::hf_rms(sines(n, 1.5, 2000.0, 0.0, 1.0), kTs, 1000.0), 1.5 / std::sqrt(2.0), 0.01);
    // 100 Hz (of 20 V) alone: nothing above 1 kHz beyond the window's leakage
    EXPECT_LT(mcsim::hf_rms(sines(n, 20.0, 100.0, 0.0, 1.0), kTs, 1000.0), 1e-3);
    // both: the 3.7 kHz part of amplitude 0.5 only
    EXPECT_NEAR(mcsim::hf_rms(sines(n, 20.0, 100.0, 0.5, 3700.0), kTs, 1000.0), 0.5 / std::sqrt(2.0), 0.01);
    // too short to say
    EXPECT_EQ(mcsim::hf_rms(std::vector<double>(7, 1.0), kTs, 1000.0), 0.0);
}
