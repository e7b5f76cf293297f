// The step/dir shaper (firmware/trajectory/step_shaper.h): a step count
// made moves of eq. (70) (paper 000) that the position drive accepts. A
// stand-in for the drive's move command judges each offer as
// paper000_drive_move does (refused while a move runs; peak speed
// (35/16)|d|/T and peak acceleration 7.5132|d|/T^2 within the design's
// w_max, a_max) and plays the accepted moves out, so the tests see where
// the reference goes: a slow train is followed step by step with no excess;
// a burst faster than the design allows is followed at the limit (the
// moves peak at w_max), nothing is lost (the reference ends at the count),
// and the steps beyond the limit are counted.
#include <gtest/gtest.h>

#include <cmath>

extern "C" {
#include "math/mc_convert.h"
#include "trajectory/step_shaper.h"
}

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kFs = 10000;
constexpr double kPhi = 2.0 * kPi / 3200.0;  // 1/16 microsteps of a 200-step motor
constexpr double kWmax = 20.0, kAmax = 40.0;  // the ODrive's configuration's [bounds]
// the step angle as the shaper holds it (fixed point: to 2^-17 rad, 0.14 %
// off kPhi; the target is the count times this)
double phi_held() { return mc_to_double(mc_from_double(kPhi)); }

// The drive's move command as paper000_drive_move judges it, and eq. (70)
// played out from where the reference rests.
struct Drive {
    double rest = 0.0, from = 0.0, to = 0.0;
    int t = 0, n = 0;  // samples into the move, its length
    double peak_speed = 0.0;
    double peak_share = 0.0;  // the largest of peak speed / w_max, peak acceleration / a_max over the moves
    double longest_rad = 0.0, longest_s = 0.0;  // the longest move's distance and duration
    int refused_limits = 0;
    bool busy() const { return t < n; }
    double ref() const
    {
        if (!busy()) return rest;
        const double s = static_cast<double>(t) / n;
        const double p = 35 * std::pow(s, 4) - 84 * std::pow(s, 5) + 70 * std::pow(s, 6) - 20 * std::pow(s, 7);
        return from + (to - from) * p;
    }
    bool move(double theta_to, double duration)
    {
        if (busy()) return false;
        const double d = std::fabs(theta_to - rest);
        if (2.1875 * d / duration > kWmax * (1 + 1e-6) || 7.5132 * d / (duration * duration) > kAmax * (1 + 1e-6)) {
            refused_limits += 1;
            return false;
        }
        peak_speed = std::fmax(peak_speed, 2.1875 * d / duration);
        longest_rad = std::fmax(longest_rad, d);
        longest_s = std::fmax(longest_s, duration);
        peak_share = std::fmax(peak_share, std::fmax(2.1875 * d / duration / kWmax, 7.5132 * d / (duration * duration) / kAmax));
        from = rest;
        to = theta_to;
        rest = theta_to;
        t = 0;
        n = static_cast<int>(std::lround(duration * kFs));
        return true;
    }
    void sample()
    {
        if (busy()) t += 1;
    }
};

step_shaper_config_t config()
{
    step_shaper_config_t c;
    c.step_angle_rad = MC_C(kPhi);
    c.speed_max_rad_s = MC_C(kWmax);
    c.accel_max_rad_s2 = MC_C(kAmax);
    c.fs_hz = kFs;
    return c;
}

// One sample: the count in, the shaper's offer to the drive, its answer
// back, the drive's sample. Returns whether a move was accepted.
bool sample(step_shaper_t& s, Drive& d, int32_t count)
{
    step_shaper_move_t m;
    step_shaper_step(&s, count, mc_from_double(d.rest), &m);
    bool ok = false;
    if (m.move) ok = d.move(mc_to_double(m.theta_to_rad), mc_to_double(m.duration_s));
    step_shaper_answer(&s, ok);
    d.sample();
    return ok;
}

}  // namespace

TEST(StepShaper, RejectsConfigurationsItCannotRun)
{
    step_shaper_t s;
    step_shaper_config_t c = config();
    EXPECT_TRUE(step_shaper_init(&s, &c, 0));
    c.step_angle_rad = MC_ZERO;
    EXPECT_FALSE(step_shaper_init(&s, &c, 0));
    c = config();
    c.speed_max_rad_s = MC_C(-1.0);
    EXPECT_FALSE(step_shaper_init(&s, &c, 0));
    c = config();
    c.fs_hz = 0;
    EXPECT_FALSE(step_shaper_init(&s, &c, 0));
    step_shaper_move_t m;
    step_shaper_step(&s, 100, MC_ZERO, &m);
    EXPECT_FALSE(m.move) << "an unconfigured shaper offers nothing";
}

// A train of 200 steps at 500 steps/s (0.98 rad/s, a tenth of the limit's
// 9.14 rad/s mean): every step followed, no excess, no offer beyond the
// drive's limits, the reference at the count at the end.
TEST(StepShaper, SlowTrainIsFollowedWithoutExcess)
{
    step_shaper_t s;
    step_shaper_config_t c = config();
    ASSERT_TRUE(step_shaper_init(&s, &c, 0));
    Drive d;
    int32_t count = 0;
    for (int k = 0; k < 20 * kFs / 10; ++k) {  // 0.4 s of steps, then rest
        if (k % 20 == 0 && count < 200) count += 1;
        sample(s, d, count);
    }
    for (int k = 0; k < kFs; ++k) sample(s, d, count);
    EXPECT_EQ(s.excess_steps, 0u);
    EXPECT_EQ(d.refused_limits, 0);
    EXPECT_FALSE(d.busy());
    EXPECT_NEAR(d.ref(), 200 * phi_held(), 1e-4);
    EXPECT_EQ(step_shaper_backlog(&s), 0);
    EXPECT_LE(d.peak_speed, kWmax);
}

// A burst of 4000 steps in 0.1 s (40,000 steps/s: 78.5 rad/s, beyond the
// design's w_max = 20 rad/s and the 9.14 rad/s mean of moves peaking
// there), then the direction pin low and 1000 steps back: followed at the
// limit (the long move at the design's acceleration or speed limit within
// 2 %, none beyond, none refused), nothing lost (the reference ends at the count), and the excess
// counted: the steps beyond the rate of 0.4655 steps a sample and the
// bucket of 2: 4000 - 0.4655 x 1000 - 2 = 3532 in the burst, give or take
// a step of the credit's rounding.
TEST(StepShaper, BurstBeyondTheDesignIsFollowedAtTheLimitAndCounted)
{
    step_shaper_t s;
    step_shaper_config_t c = config();
    ASSERT_TRUE(step_shaper_init(&s, &c, 0));
    const double rate = kWmax / (2.1875 * kPhi * kFs);
    EXPECT_NEAR(s.rate_credit, rate * 1024, 1.0);
    Drive d;
    int32_t count = 0;
    for (int k = 0; k < kFs; ++k) sample(s, d, count);  // a second at rest: the credit stays at the bucket
    for (int k = 0; k < kFs / 10; ++k) {
        count += 4;
        sample(s, d, count);
    }
    const uint32_t burst_excess = s.excess_steps;
    EXPECT_NEAR(static_cast<double>(burst_excess), 4000 - rate * 1000 - 2, 1.5);
    EXPECT_GT(step_shaper_backlog(&s), 2000) << "the steps wait, counted, not lost";
    // the direction back, slowly: no more excess
    for (int k = 0; k < 4000; ++k) {
        if (k % 4 == 3) count -= 1;
        sample(s, d, count);
    }
    EXPECT_EQ(s.excess_steps, burst_excess + 0u) << "a step every 4 samples: under the limit's 0.4655";
    for (int k = 0; k < 10 * kFs && (d.busy() || step_shaper_backlog(&s) != 0); ++k) sample(s, d, count);
    EXPECT_FALSE(d.busy());
    EXPECT_EQ(step_shaper_backlog(&s), 0);
    EXPECT_NEAR(d.ref(), 3000 * phi_held(), 2e-4) << "the reference at the count: 4000 - 1000 steps";
    EXPECT_EQ(d.refused_limits, 0) << "every move within the design's limits";
    EXPECT_LE(d.peak_speed, kWmax * (1 + 1e-6));
    EXPECT_GT(d.peak_share, 0.98) << "the long move at a limit of the design (here a_max: 7.85 rad is under "
                                     "the 15.7 rad from which w_max binds)";
}

// A move on the way (a CAN move) is waited for, and the distance of the
// next is measured from where the reference rests: the shaper's moves are
// admitted after a CAN move elsewhere too.
TEST(StepShaper, WaitsForTheDrivesMoveAndMeasuresFromItsRest)
{
    step_shaper_t s;
    step_shaper_config_t c = config();
    ASSERT_TRUE(step_shaper_init(&s, &c, 0));
    Drive d;
    ASSERT_TRUE(d.move(5.0, 2.0));  // a CAN move to 5 rad over 2 s
    int accepted = 0;
    for (int k = 0; k < 3 * kFs; ++k) accepted += sample(s, d, 10) ? 1 : 0;
    EXPECT_EQ(accepted, 1) << "offered each sample, taken once the CAN move ended";
    EXPECT_EQ(d.refused_limits, 0);
    EXPECT_NEAR(d.ref(), 10 * phi_held(), 1e-4) << "back from 5 rad to the step target";
    EXPECT_EQ(s.moves, 1u);
}

// A burst backwards of one and a half of the longest move (its 30 s,
// STEP_SHAPER_MOVE_MAX_S, at w_max: about 139,690 steps here; in fixed point
// 16384, mc_t's range), 0.1 s long: the first sample's steps are a move at
// once, the rest waits and is taken by the longest move and then one more,
// none longer than the longest (30 s and two samples), none refused, the
// reference at the count at the end; the steps beyond the limit counted as
// forwards (the burst less the rate's 0.4655 a sample and the bucket's 2).
// Broken once: the clamp's negative side dropped (one move of 45 s); and
// |delta| as delta in the bucket (no excess backwards).
TEST(StepShaper, ReverseBurstLongerThanOneMoveIsSplit)
{
    step_shaper_t s;
    step_shaper_config_t c = config();
    ASSERT_TRUE(step_shaper_init(&s, &c, 0));
    const int32_t longest = s.max_move_steps;
#if MC_FIXED
    EXPECT_EQ(longest, 16384);
#else
    EXPECT_NEAR(longest, 30.0 * kWmax / (2.1875 * kPhi), 1.0);
#endif
    const int32_t burst = longest + longest / 2;
    Drive d;
    int32_t count = 0;
    for (int k = 0; k < kFs / 10; ++k) {
        count = -static_cast<int32_t>(static_cast<int64_t>(burst) * (k + 1) / (kFs / 10));
        sample(s, d, count);
    }
    ASSERT_EQ(count, -burst);
    const double rate = kWmax / (2.1875 * kPhi * kFs);
    EXPECT_NEAR(static_cast<double>(s.excess_steps), burst - rate * (kFs / 10) - 2, 1.5)
        << "the steps beyond the limit, counted backwards too";
    for (int k = 0; k < 100 * kFs && (d.busy() || step_shaper_backlog(&s) != 0); ++k) sample(s, d, count);
    EXPECT_FALSE(d.busy());
    EXPECT_EQ(step_shaper_backlog(&s), 0);
    EXPECT_EQ(s.moves, 3u) << "the first sample's steps, the longest move, the rest";
    EXPECT_EQ(d.refused_limits, 0);
    EXPECT_NEAR(d.longest_rad, longest * phi_held(), 1e-6 * longest * phi_held()) << "the longest move, no longer";
    EXPECT_LE(d.longest_s, 30.0 + 2.0 / kFs + 2.1875 * kPhi / kWmax)
        << "no move beyond STEP_SHAPER_MOVE_MAX_S (and two samples, and a step of the rounding)";
    EXPECT_NEAR(d.ref(), -burst * phi_held(), 1e-6 * burst * phi_held() + 1e-4) << "the reference at the count";
}
