// The loss-of-lock criteria (supervisor/lock_monitor.h) on hand-computed
// cases. LOCK_CRIT_FLUX_RESIDUAL: the residual gamma Phi^3 |target - |rho|^2|, the bound's four
// terms, the persistence, and the monitor off with ticks = 0. The
// thresholds are paper 001's motor's (design/lock_monitor_design.c): floor
// 0.088 V, 0.1125 ohm, 0.55 V s/rad, 5.7 mH, 540 samples.
// LOCK_CRIT_ANGLE_INNOVATION: the bound k^2 S + (w_tol Ts)^2 and the leaky
// count (+up beyond, -1 within, held in [0, limit]), on values that fit
// both number types (the criterion is unit-agnostic): S = 1e-3, k^2 = 36,
// w_tol = 10, Ts = 0.01: bound^2 = 0.036 + 0.01 = 0.046, |nu| 0.2145.
#include <gtest/gtest.h>

#include <cmath>

extern "C" {
#include "math/mc_convert.h"
#include "supervisor/lock_monitor.h"
}

namespace {

lock_monitor_config_t paper001_cfg(int32_t ticks)
{
    lock_monitor_config_t c{};  // the angle-innovation criterion off (innov_limit 0)
    c.gPhi3_V = mc_from_double(24.565);  // 5000 x 0.17^3
    c.k_speed_V_s = mc_from_double(0.5482);
    c.k_speed_cur_H = mc_from_double(5.7e-3);
    c.k_cur_ohm = mc_from_double(0.1125);
    c.floor_V = mc_from_double(0.0883);
    c.ticks = ticks;
    return c;
}

// |1 - rho2| giving the residual e [V]
mc_t rho2_for(double e_V) { return mc_from_double(1.0 - e_V / 24.565); }

}  // namespace

TEST(LockMonitor, BoundIsTheSumOfTheTolerances)
{
    lock_monitor_t m;
    const lock_monitor_config_t c = paper001_cfg(3);
    lock_monitor_init(&m, &c);
    // 2 rad/s, i = (0.6, 0.8): |i| = 1 A; 0.0883 + 0.1125 + 2 (0.5482 + 5.7e-3) = 1.3086 V
    (void)lock_monitor_step_flux(&m, rho2_for(0.5), MC_ONE, mc_from_double(-2.0), mc_from_double(0.6),
                                 mc_from_double(-0.8));
    EXPECT_NEAR(mc_to_double(m.bound_V), 1.3086, 1e-3);
    EXPECT_NEAR(mc_to_double(m.residual_V), 0.5, 2e-3);
}

TEST(LockMonitor, TripsAfterTicksBeyondTheBoundOnly)
{
    lock_monitor_t m;
    const lock_monitor_config_t c = paper001_cfg(3);
    lock_monitor_init(&m, &c);
    const mc_t w = MC_ZERO, id = MC_ZERO, iq = mc_from_double(2.0);  // bound 0.0883 + 0.225 = 0.3133 V
    // just below the bound: never
    for (int k = 0; k < 10; ++k) {
        EXPECT_EQ(lock_monitor_step_flux(&m, rho2_for(0.30), MC_ONE, w, id, iq), LOCK_CRIT_NONE);
    }
    // beyond it (either side of |rho| = 1): on the third sample in a row
    EXPECT_EQ(lock_monitor_step_flux(&m, rho2_for(0.33), MC_ONE, w, id, iq), LOCK_CRIT_NONE);
    EXPECT_EQ(lock_monitor_step_flux(&m, rho2_for(-0.33), MC_ONE, w, id, iq), LOCK_CRIT_NONE);
    EXPECT_EQ(lock_monitor_step_flux(&m, rho2_for(0.33), MC_ONE, w, id, iq), LOCK_CRIT_FLUX_RESIDUAL);
    // one sample back inside restarts the count
    lock_monitor_init(&m, &c);
    EXPECT_EQ(lock_monitor_step_flux(&m, rho2_for(0.33), MC_ONE, w, id, iq), LOCK_CRIT_NONE);
    EXPECT_EQ(lock_monitor_step_flux(&m, rho2_for(0.33), MC_ONE, w, id, iq), LOCK_CRIT_NONE);
    EXPECT_EQ(lock_monitor_step_flux(&m, rho2_for(0.0), MC_ONE, w, id, iq), LOCK_CRIT_NONE);
    EXPECT_EQ(lock_monitor_step_flux(&m, rho2_for(0.33), MC_ONE, w, id, iq), LOCK_CRIT_NONE);
    EXPECT_EQ(lock_monitor_step_flux(&m, rho2_for(0.33), MC_ONE, w, id, iq), LOCK_CRIT_NONE);
    EXPECT_EQ(lock_monitor_step_flux(&m, rho2_for(0.33), MC_ONE, w, id, iq), LOCK_CRIT_FLUX_RESIDUAL);
}

TEST(LockMonitor, SpeedWidensTheBound)
{
    // 1 V of residual: lost at standstill with 1 A, kept at 2 rad/s (bound 1.31 V)
    lock_monitor_t m;
    const lock_monitor_config_t c = paper001_cfg(1);
    lock_monitor_init(&m, &c);
    EXPECT_EQ(lock_monitor_step_flux(&m, rho2_for(1.0), MC_ONE, mc_from_double(2.0), MC_ZERO, MC_ONE), LOCK_CRIT_NONE);
    EXPECT_EQ(lock_monitor_step_flux(&m, rho2_for(1.0), MC_ONE, MC_ZERO, MC_ZERO, MC_ONE), LOCK_CRIT_FLUX_RESIDUAL);
}

TEST(LockMonitor, TargetRadiusIsTheReference)
{
    // paper 002's active flux: |rho|^2 at its target is no residual
    lock_monitor_t m;
    const lock_monitor_config_t c = paper001_cfg(1);
    lock_monitor_init(&m, &c);
    const mc_t target = mc_from_double(0.8);
    EXPECT_EQ(lock_monitor_step_flux(&m, target, target, MC_ZERO, MC_ZERO, MC_ONE), LOCK_CRIT_NONE);
    EXPECT_NEAR(mc_to_double(m.residual_V), 0.0, 1e-4);
}

TEST(LockMonitor, OffWithoutTicks)
{
    lock_monitor_t m;
    const lock_monitor_config_t c = paper001_cfg(0);
    lock_monitor_init(&m, &c);
    for (int k = 0; k < 5; ++k) {
        EXPECT_EQ(lock_monitor_step_flux(&m, rho2_for(5.0), MC_ONE, MC_ZERO, MC_ZERO, MC_ZERO), LOCK_CRIT_NONE);
    }
}

namespace {

// paper 002's count (up 20, limit 1000: 50 samples in a row) on the values above
lock_monitor_config_t innov_cfg(int32_t up, int32_t limit)
{
    lock_monitor_config_t c{};  // the flux residual off (ticks 0)
    c.innov_k2 = mc_from_double(36.0);
    c.ts_s = mc_from_double(0.01);
    c.innov_up = up;
    c.innov_limit = limit;
    return c;
}

const double kS = 1e-3, kWtol = 10.0;

lock_criterion_t innov(lock_monitor_t *m, double nu) { return lock_monitor_step_innovation(m, mc_from_double(nu), mc_from_double(kS), mc_from_double(kWtol)); }

}  // namespace

TEST(LockMonitor, InnovationBoundIsNoiseAndSpeedTolerance)
{
    lock_monitor_t m;
    const lock_monitor_config_t c = innov_cfg(1, 1);
    lock_monitor_init(&m, &c);
    // bound^2 = 36 x 1e-3 + (10 x 0.01)^2 = 0.046: 0.21 (0.0441) within, 0.22 (0.0484) beyond, either sign
    EXPECT_EQ(innov(&m, 0.21), LOCK_CRIT_NONE);
    EXPECT_NEAR(mc_to_double(m.innov_ratio), 0.0441 / 0.046, 2e-3);
    EXPECT_EQ(innov(&m, -0.21), LOCK_CRIT_NONE);
    EXPECT_EQ(innov(&m, -0.22), LOCK_CRIT_ANGLE_INNOVATION);
    lock_monitor_init(&m, &c);
    EXPECT_EQ(innov(&m, 0.22), LOCK_CRIT_ANGLE_INNOVATION);
    // without the speed tolerance the bound is 6 sigma alone: 0.19 is beyond it
    lock_monitor_init(&m, &c);
    EXPECT_EQ(lock_monitor_step_innovation(&m, mc_from_double(0.19), mc_from_double(kS), MC_ZERO),
              LOCK_CRIT_ANGLE_INNOVATION);
    lock_monitor_init(&m, &c);
    EXPECT_EQ(lock_monitor_step_innovation(&m, mc_from_double(0.19), mc_from_double(kS), mc_from_double(-kWtol)),
              LOCK_CRIT_NONE)
        << "the tolerance's sign does not matter";
}

TEST(LockMonitor, InnovationCountIsLeaky)
{
    lock_monitor_t m;
    const lock_monitor_config_t c = innov_cfg(20, 1000);
    lock_monitor_init(&m, &c);
    // 49 samples in a row beyond: not yet; the 50th: lost
    for (int k = 0; k < 49; ++k) ASSERT_EQ(innov(&m, 0.5), LOCK_CRIT_NONE) << k;
    EXPECT_EQ(m.innov_count, 980);
    EXPECT_EQ(innov(&m, 0.5), LOCK_CRIT_ANGLE_INNOVATION);
    EXPECT_EQ(m.innov_count, 1000);
    EXPECT_EQ(innov(&m, 0.5), LOCK_CRIT_ANGLE_INNOVATION) << "held at the limit";
    EXPECT_EQ(m.innov_count, 1000);
    // a sample within leaks one: below the limit again
    EXPECT_EQ(innov(&m, 0.0), LOCK_CRIT_NONE);
    EXPECT_EQ(m.innov_count, 999);
    // 1 sample beyond in 21 (the share the leak answers): never, whatever the time
    lock_monitor_init(&m, &c);
    for (int k = 0; k < 21 * 500; ++k) ASSERT_EQ(innov(&m, (k % 21 == 0) ? 0.5 : 0.0), LOCK_CRIT_NONE) << k;
    EXPECT_LE(m.innov_count, 20);
    // 1 in 20: + 20 - 19 a cycle, lost in the 981st cycle (count 980 + 20 at its start)
    lock_monitor_init(&m, &c);
    int lost = -1;
    for (int k = 0; k < 20 * 1000 && lost < 0; ++k) {
        if (innov(&m, (k % 20 == 0) ? 0.5 : 0.0) != LOCK_CRIT_NONE) lost = k;
    }
    EXPECT_EQ(lost, 980 * 20);
    // a chattering loss, bursts of 10 beyond every 40 samples (+200 - 30): in the 6th burst
    lock_monitor_init(&m, &c);
    lost = -1;
    for (int k = 0; k < 4000 && lost < 0; ++k) {
        if (innov(&m, (k % 40 < 10) ? 0.5 : 0.0) != LOCK_CRIT_NONE) lost = k;
    }
    EXPECT_EQ(lost, 5 * 40 + 7) << "850 after five cycles, +20 a sample: the 8th sample of the 6th burst";
    // floored at 0: a long lock does not bank credit
    lock_monitor_init(&m, &c);
    for (int k = 0; k < 100; ++k) (void)innov(&m, 0.0);
    EXPECT_EQ(m.innov_count, 0);
}

TEST(LockMonitor, InnovationOffWithoutLimit)
{
    lock_monitor_t m;
    const lock_monitor_config_t c = innov_cfg(20, 0);
    lock_monitor_init(&m, &c);
    for (int k = 0; k < 100; ++k) EXPECT_EQ(innov(&m, 3.0), LOCK_CRIT_NONE);
    EXPECT_EQ(m.innov_count, 0);
    // and the flux residual's criterion does not step it
    const lock_monitor_config_t f = paper001_cfg(1);
    lock_monitor_init(&m, &f);
    EXPECT_EQ(innov(&m, 3.0), LOCK_CRIT_NONE) << "paper 001's configuration: the innovation criterion off";
}
