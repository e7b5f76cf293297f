// The resistance and flux tracker (estimators/resistance_tracker.h) on the
// steady-state voltage of a non-salient PMSM in alpha-beta, v = R i +
// L di/dt + omega_e Phi J rho (paper 001 (1)), sampled as the drive feeds
// it (the voltage held over the last sample, this sample's current and
// unit vector), in this build's numeric type: R observable at standstill
// under load, Phi at speed without load, both from the two together.
#include <gtest/gtest.h>

#include <cmath>

extern "C" {
#include "estimators/resistance_tracker.h"
#include "math/mc_convert.h"
}

#include "fw_test_util.h"

using fwtest::D;
using fwtest::M;

namespace {
// paper 001's motor (sim/motors/paper001_pmsm.toml), 10 kHz
constexpr double kR = 0.225, kL = 3.8e-3, kPhi = 0.17, kTs = 1e-4;
constexpr int kNp = 3;
constexpr double kTau = 0.5;  // tau_R of design/paper001_design.c on this motor

resistance_tracker_config_t config(double R0, double Phi0)
{
    resistance_tracker_config_t c{};
    c.enabled = true;
    c.R0_ohm = M(R0);
    c.L_fs_ohm = M(kL / kTs);
    c.Phi0_fs_V = M(Phi0 / kTs);
    c.K_e_V_s = M(kNp * Phi0);
    const double i_gate = 0.8;
    c.v_gate2_V2 = M(R0 * i_gate * R0 * i_gate);
    c.e_clamp_V = M(R0 * 8.0 / 2.0);
    c.dR_max_ohm = M(R0);
    c.dPhi_rel_max = M(0.2);
    c.n_tau = static_cast<int32_t>(std::lround(kTau / kTs));
    return c;
}

bool init(resistance_tracker_t* t, const resistance_tracker_config_t& c) { return resistance_tracker_init(t, &c); }

// Runs the tracker for t_s on the motor turning at w_mech (rad/s) with the
// current i_q along the rotor's q axis (i_d = 0), the rotor angle known to
// the tracker (the observer locked). The voltage held over [k-1, k] is the
// motor's mean over that sample: R i + omega_e Phi (q axis) + omega_e L J i
// (the rotation of L i), evaluated at the sample's middle.
// R: the motor's resistance (an apparent one below 0: a voltage below R i,
// as a dead-time compensation that gives too much).
void run(resistance_tracker_t* t, double w_mech, double i_q, double t_s, double* theta_e, double R = kR)
{
    const double we = kNp * w_mech;
    const int n = static_cast<int>(std::lround(t_s / kTs));
    for (int k = 0; k < n; ++k) {
        const double th0 = *theta_e;
        const double th1 = th0 + we * kTs;
        const double thm = 0.5 * (th0 + th1);
        // i = i_q (-sin, cos)(theta); v at the middle of the sample
        const double vq = R * i_q + we * kPhi;
        const double vd = -we * kL * i_q;
        mc_ab_t v{M(vd * std::cos(thm) - vq * std::sin(thm)), M(vd * std::sin(thm) + vq * std::cos(thm))};
        mc_ab_t i{M(-i_q * std::sin(th1)), M(i_q * std::cos(th1))};
        mc_rot_t u;
        u.c = M(std::cos(th1));
        u.s = M(std::sin(th1));
        resistance_tracker_step(t, v, i, u, M(w_mech), true);
        *theta_e = th1;
    }
}

TEST(ResistanceTracker, ResistanceAtStandstillUnderLoad)
{
    resistance_tracker_t t;
    ASSERT_TRUE(init(&t, config(1.3 * kR, kPhi)));
    double th = 0.4;
    run(&t, 0.0, 2.0, 5.0 * kTau, &th);  // 5 tau_R: e^-5 of the error left
    EXPECT_NEAR(D(t.R_ohm), kR, 0.01 * 0.3 * kR + 2e-4);
    EXPECT_NEAR(D(t.Phi_rel), 1.0, 1e-4);  // no back-EMF: Phi untouched
}

TEST(ResistanceTracker, FluxAtSpeedWithoutLoad)
{
    resistance_tracker_t t;
    ASSERT_TRUE(init(&t, config(kR, 0.9 * kPhi)));
    double th = -1.0;
    run(&t, 12.0, 0.0, 5.0 * kTau, &th);
    EXPECT_NEAR(D(t.Phi_rel) * 0.9, 1.0, 0.01 * 0.1 + 3e-4);
    EXPECT_NEAR(D(t.R_ohm), kR, 1e-4);  // no current: R untouched
}

TEST(ResistanceTracker, BothFromAlternatingOperatingPoints)
{
    // at one operating point only e_q's sum is observable; a load at
    // standstill and a speed without load separate R and Phi
    resistance_tracker_t t;
    ASSERT_TRUE(init(&t, config(0.8 * kR, 1.1 * kPhi)));
    double th = 2.0;
    for (int k = 0; k < 4; ++k) {
        run(&t, 0.0, 3.0, 2.0 * kTau, &th);
        run(&t, 10.0, 0.0, 2.0 * kTau, &th);
    }
    EXPECT_NEAR(D(t.R_ohm), kR, 0.01 * kR);
    EXPECT_NEAR(D(t.Phi_rel) * 1.1, 1.0, 0.002);
}

TEST(ResistanceTracker, AtOneOperatingPointTheResidualIsNulled)
{
    // under load at speed: R and Phi both off; the tracker nulls e_q
    // (the split between them is not observable there)
    resistance_tracker_t t;
    ASSERT_TRUE(init(&t, config(1.2 * kR, 1.05 * kPhi)));
    double th = 0.0;
    run(&t, 5.0, 1.5, 10.0 * kTau, &th);
    // one sample's residual: in Q14.17 the angle step resolves 7.6e-6 rad,
    // 0.0136 V of back-EMF at Phi0/Ts = 1785 V (the header)
#if MC_FIXED
    EXPECT_LT(std::fabs(D(t.e_q_V)), 0.0136);
#else
    EXPECT_LT(std::fabs(D(t.e_q_V)), 2e-3);
#endif
    const double dR = D(t.R_ohm) - kR, dPhi = (D(t.Phi_rel) * 1.05 - 1.0) * kPhi;
    EXPECT_NEAR(dR * 1.5 + kNp * 5.0 * dPhi, 0.0, 2e-3);  // -e_q of the header
}

TEST(ResistanceTracker, HeldWithoutAdaptAndBounded)
{
    resistance_tracker_t t;
    ASSERT_TRUE(init(&t, config(kR, kPhi)));
    // adapt = false: the residual is formed, the estimates stay
    mc_ab_t v{M(0.0), M(1.0)}, i{M(0.0), M(1.0)};  // along q_hat = J (1, 0)
    mc_rot_t u;
    u.c = M(1.0);
    u.s = M(0.0);
    for (int k = 0; k < 100; ++k) {
        resistance_tracker_step(&t, v, i, u, M(0.0), false);
    }
    EXPECT_EQ(D(t.R_ohm), D(M(kR)));
    EXPECT_NEAR(D(t.e_q_V), 1.0 - kR, 1e-4);
    // a winding of 10 R: R_hat stops at R0 + dR_max = 2 R0
    double th = 0.0;
    resistance_tracker_t t2;
    ASSERT_TRUE(init(&t2, config(0.1 * kR, kPhi)));
    run(&t2, 0.0, 2.0, 20.0 * kTau, &th);
    EXPECT_NEAR(D(t2.R_ohm), 0.2 * kR, 1e-4);
}

// R_hat's lower bounds (the header: |R_hat - R0| <= dR_max, and R_hat >=
// 0), at standstill under load where R is observable: a winding at a
// quarter of R0 with dR_max = R0/2 takes R_hat down to R0 - dR_max and no
// further; with dR_max = 2 R0, an apparent resistance of -R0/2 takes it
// down to 0 and no further. Each bound is reached after about tau_R ln 3
// (the unbounded R_hat would pass it at 1/3 of its way); 10 tau_R run.
// Broken once each: the R_hat >= 0 part of the lower bound dropped, its
// R0 - dR_max part dropped, the lower clamp dropped.
TEST(ResistanceTracker, ResistanceStopsAtItsLowerBounds)
{
    {
        resistance_tracker_config_t c = config(4.0 * kR, kPhi);
        c.dR_max_ohm = M(2.0 * kR);
        resistance_tracker_t t;
        ASSERT_TRUE(init(&t, c));
        double th = 0.3;
        run(&t, 0.0, 2.0, 10.0 * kTau, &th);
        EXPECT_NEAR(D(t.R_ohm), 2.0 * kR, 2e-5) << "R0 - dR_max, not the winding's " << kR;
        run(&t, 0.0, -2.0, 2.0 * kTau, &th);
        EXPECT_NEAR(D(t.R_ohm), 2.0 * kR, 2e-5) << "held there, the current either way";
    }
    {
        resistance_tracker_config_t c = config(kR, kPhi);
        c.dR_max_ohm = M(2.0 * kR);
        resistance_tracker_t t;
        ASSERT_TRUE(init(&t, c));
        double th = -2.5;
        run(&t, 0.0, 2.0, 10.0 * kTau, &th, -0.5 * kR);
        EXPECT_NEAR(D(t.R_ohm), 0.0, 2e-5) << "R_hat >= 0, not the apparent " << -0.5 * kR;
    }
}

TEST(ResistanceTracker, RefusesBadConfig)
{
    resistance_tracker_t t;
    resistance_tracker_config_t c = config(kR, kPhi);
    c.n_tau = 0;
    EXPECT_FALSE(resistance_tracker_init(&t, &c));
    EXPECT_FALSE(t.cfg.enabled);
    c = config(kR, kPhi);
    c.dPhi_rel_max = M(1.0);
    EXPECT_FALSE(resistance_tracker_init(&t, &c));
    c.enabled = false;  // disabled: nothing checked, nothing run
    EXPECT_TRUE(resistance_tracker_init(&t, &c));
}
}  // namespace
