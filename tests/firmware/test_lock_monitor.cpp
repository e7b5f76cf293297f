// The loss-of-lock criterion (supervisor/lock_monitor.h) on hand-computed
// cases: the residual gamma Phi^3 |target - |rho|^2|, the bound's four
// terms, the persistence, and the monitor off with ticks = 0. The
// thresholds are paper 001's motor's (design/lock_monitor_design.c): floor
// 0.088 V, 0.1125 ohm, 0.55 V s/rad, 5.7 mH, 540 samples.
#include <gtest/gtest.h>

#include <cmath>

extern "C" {
#include "math/mc_convert.h"
#include "supervisor/lock_monitor.h"
}

namespace {

lock_monitor_config_t paper001_cfg(int32_t ticks)
{
    lock_monitor_config_t c;
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
    EXPECT_STREQ(lock_criterion_name(LOCK_CRIT_FLUX_RESIDUAL), "flux-residual");
}
