// The loss-of-lock thresholds' derivation (design/lock_monitor_design.c):
// paper 001's non-salient motor unchanged by the salient extension (L_radial
// 0, rho_max 1 give the same numbers bit for bit), and paper 002's
// sensorless variant on the active flux (design/paper002_design.c) against
// values computed here by hand: k_speed = n_p psi (sin 30 deg + sqrt(1.15^2
// - 1)), k_speed_cur = eps_L n_p (L_q + f'(eps_Phi) L_d), floor = 2 gamma
// psi^2 L_q 0.01 i_max rho_max with rho_max from MTPA (18) at i_max. The
// angle-innovation criterion's count (lock_monitor_design_innovation):
// glitch_s / Ts samples in a row, up = forget / glitch samples, limit =
// up x glitch; k^2 = 36; paper 002's 5 ms and 0.1 s at 10 kHz: 20, 1000.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

extern "C" {
#include "design/lock_monitor_design.h"
#include "design/paper002_design.h"
#include "math/mc_convert.h"
}

namespace {

lock_monitor_design_input_t paper001_input()
{
    lock_monitor_design_input_t in;
    lock_monitor_design_defaults(&in);
    in.R_ohm = 0.225;
    in.L_H = 3.8e-3;
    in.Phi_Wb = 0.17;
    in.n_p = 3;
    in.gPhi3_V = 5000.0 * 0.17 * 0.17 * 0.17;
    in.i_max_A = 8.0;
    in.settle_s = 0.054;
    in.ts_s = 1e-4;
    return in;
}

}  // namespace

TEST(LockMonitorDesign, NonSalientIsPaper001sDerivation)
{
    const lock_monitor_design_input_t in = paper001_input();
    EXPECT_EQ(in.L_radial_H, 0.0);
    EXPECT_EQ(in.rho_max, 1.0);
    lock_monitor_config_t c;
    char err[160] = "";
    ASSERT_TRUE(lock_monitor_design(&in, &c, err, sizeof err)) << err;
    // paper 001's formulas as they were before the salient extension, in
    // the same order: bit for bit (its metrics and logs are unchanged)
    const double pi = 3.14159265358979323846;
    const double k_speed = 3.0 * 0.17 * (std::sin(30.0 * pi / 180.0) + std::sqrt(1.15 * 1.15 - 1.0));
    EXPECT_EQ(c.k_speed_V_s, mc_from_double(k_speed));
    EXPECT_EQ(c.k_speed_cur_H, mc_from_double(0.5 * 3.8e-3 * 3.0));
    EXPECT_EQ(c.k_cur_ohm, mc_from_double(0.5 * 0.225));
    EXPECT_EQ(c.floor_V, mc_from_double(2.0 * (in.gPhi3_V / 0.17) * 3.8e-3 * 0.01 * 8.0));
    EXPECT_EQ(c.gPhi3_V, mc_from_double(in.gPhi3_V));
    EXPECT_EQ(c.ticks, 540);
    // docs/faults.md's numbers
    EXPECT_NEAR(mc_to_double(c.floor_V), 0.0879, 1e-4);
    EXPECT_NEAR(mc_to_double(c.k_speed_V_s), 0.5447, 1e-3);
}

TEST(LockMonitorDesign, SalientActiveFluxOfPaper002)
{
#if MC_FIXED
    GTEST_SKIP() << "paper 002's design is float only";
#endif
    p002_design_input_t in;
    p002_design_defaults(&in);
    in.angle_source = P002_ANGLE_FLUX;
    paper002_config_t cfg;
    char err[200] = "";
    ASSERT_TRUE(p002_design(&in, &cfg, err, sizeof err)) << err;
    const lock_monitor_config_t& c = cfg.lock;
    const double psi = 0.04, Ld = 3e-3, Lq = 9e-3, p = 4.0, i_max = 20.0;
    // gamma psi^3 with 2 gamma psi^2 = 50 1/s: 25 psi = 1 V
    EXPECT_NEAR(mc_to_double(c.gPhi3_V), 1.0, 1e-6);
    // n_p psi (0.5 + 0.56789)
    EXPECT_NEAR(mc_to_double(c.k_speed_V_s), p * psi * (0.5 + 0.5678908346), 1e-6);
    // 0.5 n_p (L_q + 1.15/0.56789 L_d): the radial L_d error's tangent at eps_Phi
    EXPECT_NEAR(mc_to_double(c.k_speed_cur_H), 0.5 * p * (Lq + 2.0250371 * Ld), 1e-7);
    EXPECT_NEAR(mc_to_double(c.k_cur_ohm), 0.15, 1e-7);
    // MTPA (18) at |i| = 20 A: i_d = -12.5733 A, rho_max = 1 + 6 mH x 12.5733 / psi = 2.8860
    const double rho_max = 1.0 + (Lq - Ld) * 12.57333 / psi;
    EXPECT_NEAR(rho_max, 2.8860, 1e-4);
    EXPECT_NEAR(mc_to_double(c.floor_V), 2.0 * 25.0 * Lq * 0.01 * i_max * rho_max, 1e-5);
    // five radial time constants of 20 ms at 10 kHz
    EXPECT_EQ(c.ticks, 1000);
    // the angle innovation: 6 sigma, 50 samples in a row (5 ms), drained in 0.1 s
    EXPECT_EQ(mc_to_double(c.innov_k2), 36.0);
    EXPECT_EQ(c.innov_up, 20);
    EXPECT_EQ(c.innov_limit, 1000);
    EXPECT_EQ(c.ts_s, mc_from_double(1e-4));
    // the encoder variant has none (its angle is measured)
    in.angle_source = P002_ANGLE_ENCODER;
    ASSERT_TRUE(p002_design(&in, &cfg, err, sizeof err)) << err;
    EXPECT_EQ(cfg.lock.ticks, 0);
    EXPECT_EQ(cfg.lock.innov_limit, 0);
}

TEST(LockMonitorDesign, InnovationCountFromGlitchAndForgetTimes)
{
    lock_innovation_design_input_t in;
    lock_innovation_design_defaults(&in);
    EXPECT_EQ(in.k_sigma, 6.0);
    in.glitch_s = 5e-3;
    in.forget_s = 0.1;
    in.ts_s = 1e-4;
    lock_monitor_config_t c{};
    char err[160] = "";
    ASSERT_TRUE(lock_monitor_design_innovation(&in, &c, err, sizeof err)) << err;
    EXPECT_EQ(c.innov_up, 20);
    EXPECT_EQ(c.innov_limit, 1000);
    EXPECT_EQ(c.ticks, 0) << "the flux residual's fields are not its";
    // 3 samples of glitch, 10 to forget: up = floor(10 / 3) = 3, limit 9 (3 in a row)
    in.glitch_s = 3e-4;
    in.forget_s = 1e-3;
    ASSERT_TRUE(lock_monitor_design_innovation(&in, &c, err, sizeof err)) << err;
    EXPECT_EQ(c.innov_up, 3);
    EXPECT_EQ(c.innov_limit, 9);
    // forget = glitch: up 1, a plain up/down count
    in.forget_s = 3e-4;
    ASSERT_TRUE(lock_monitor_design_innovation(&in, &c, err, sizeof err)) << err;
    EXPECT_EQ(c.innov_up, 1);
    EXPECT_EQ(c.innov_limit, 3);
}

TEST(LockMonitorDesign, RefusesTheInnovationInputsOutOfRange)
{
    lock_innovation_design_input_t in;
    lock_innovation_design_defaults(&in);
    in.glitch_s = 5e-3;
    in.forget_s = 0.1;
    in.ts_s = 1e-4;
    lock_monitor_config_t c{};
    char err[160] = "";
    lock_innovation_design_input_t bad = in;
    bad.ts_s = 0.0;
    EXPECT_FALSE(lock_monitor_design_innovation(&bad, &c, err, sizeof err));
    EXPECT_NE(std::strstr(err, "lock_monitor.ts_s"), nullptr) << err;
    bad = in;
    bad.k_sigma = 0.0;
    EXPECT_FALSE(lock_monitor_design_innovation(&bad, &c, err, sizeof err));
    EXPECT_NE(std::strstr(err, "lock_monitor.k_sigma"), nullptr) << err;
    bad = in;
    bad.glitch_s = 5e-5;
    EXPECT_FALSE(lock_monitor_design_innovation(&bad, &c, err, sizeof err));
    EXPECT_NE(std::strstr(err, "lock_monitor.glitch_s"), nullptr) << err;
    bad = in;
    bad.forget_s = 1e-3;
    EXPECT_FALSE(lock_monitor_design_innovation(&bad, &c, err, sizeof err));
    EXPECT_NE(std::strstr(err, "lock_monitor.forget_s"), nullptr) << err;
}

TEST(LockMonitorDesign, RefusesTheSalientInputsOutOfRange)
{
    char err[160] = "";
    lock_monitor_config_t c;
    lock_monitor_design_input_t in = paper001_input();
    in.rho_max = 0.9;
    EXPECT_FALSE(lock_monitor_design(&in, &c, err, sizeof err));
    EXPECT_NE(std::strstr(err, "lock_monitor.rho_max"), nullptr) << err;
    in = paper001_input();
    in.L_radial_H = -1e-3;
    EXPECT_FALSE(lock_monitor_design(&in, &c, err, sizeof err));
    EXPECT_NE(std::strstr(err, "lock_monitor.L_radial_H"), nullptr) << err;
    // the tangent of sqrt((1 + x)^2 - 1) at eps_Phi = 0 is vertical
    in = paper001_input();
    in.L_radial_H = 3e-3;
    in.eps_Phi = 0.0;
    EXPECT_FALSE(lock_monitor_design(&in, &c, err, sizeof err));
    EXPECT_NE(std::strstr(err, "lock_monitor.eps_Phi"), nullptr) << err;
    in.eps_Phi = 0.15;
    EXPECT_TRUE(lock_monitor_design(&in, &c, err, sizeof err)) << err;
}
