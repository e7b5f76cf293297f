// Plant, load profile and reference checks: integration accuracy (step
// halving over the paper-000 trajectory), physics of eq. (1) against closed
// forms, and the in-step sin/cos shortcut against libm.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "model/load_profile.h"
#include "model/reference.h"
#include "model/pm_plant.h"

namespace {

using mcsim::PmPlant;

constexpr double kTs = 1e-4;

mcsim::MotorParams paper_motor()
{
    mcsim::MotorParams m;  // sim/motors/paper000_stepper.toml
    m.L_H = 9e-3;
    m.R_ohm = 3.01;
    m.K_Nm_per_A = 0.27;
    m.J_kgm2 = 3.18e-4;
    m.fv_Nms_per_rad = 2.37e-3;
    m.coulomb_Nm = 0.0752;
    m.coulomb_omega_s_rad_s = 0.05;
    m.n_p = 50;
    return m;
}

mcsim::Reference paper_reference()
{
    return mcsim::Reference({{0.0, 2.0, 18.0}, {2.0, 2.0, 0.0}});
}

// Open-loop voltages of eq. (68) (errata reading) along the paper
// trajectory, I_max = 3 A, V_max = 30 V: a voltage sequence that does not
// depend on the plant, so runs at different step sizes see the same input.
std::vector<std::pair<double, double>> open_loop_voltages(const mcsim::MotorParams& m, double duration_s)
{
    const mcsim::Reference ref = paper_reference();
    const auto n = static_cast<std::size_t>(std::llround(duration_s / kTs));
    std::vector<std::pair<double, double>> v(n);
    for (std::size_t k = 0; k < n; ++k) {
        const mcsim::RefPoint r = ref.eval(static_cast<double>(k) * kTs);
        const double w = r.omega_rad_s;
        const double z = m.n_p * w * m.L_H;
        const double amp = std::min(30.0, std::sqrt((m.R_ohm * m.R_ohm + z * z) * 9.0 + (m.K_Nm_per_A * w) * (m.K_Nm_per_A * w)));
        v[k] = {amp * std::cos(m.n_p * r.theta_rad), amp * std::sin(m.n_p * r.theta_rad)};
    }
    return v;
}

std::vector<double> run_theta(int substeps, const std::vector<std::pair<double, double>>& v)
{
    PmPlant p(paper_motor(), mcsim::LoadProfile(), substeps);
    p.reset(PmPlant::State::Zero());
    std::vector<double> th;
    th.reserve(v.size());
    for (const auto& u : v) {
        p.step(u.first, u.second, kTs);
        th.push_back(p.theta_rad());
    }
    return th;
}

TEST(Plant, StepHalvingOverPaperTrajectory)
{
    const auto v = open_loop_voltages(paper_motor(), 4.25);
    const int n = PmPlant::kDefaultSubsteps;
    const auto a = run_theta(n, v);
    const auto b = run_theta(2 * n, v);
    double max_diff = 0.0;
    double max_theta = 0.0;
    for (std::size_t k = 0; k < a.size(); ++k) {
        max_diff = std::max(max_diff, std::fabs(a[k] - b[k]));
        max_theta = std::max(max_theta, a[k]);
    }
    RecordProperty("max_theta_diff_rad", std::to_string(max_diff));
    std::printf("substeps %d vs %d: max |dtheta| = %.3g rad\n", n, 2 * n, max_diff);
    EXPECT_LT(max_diff, 1e-5);
    // The open-loop run must actually follow the trajectory, or the check
    // above would be about a rotor at rest.
    EXPECT_GT(max_theta, 17.0);
    EXPECT_LT(std::fabs(a.back()), 0.2);
}

TEST(Plant, FastStepMatchesLibmRk4)
{
    // The in-step rotation of sin/cos must give the same trajectory as RK4
    // on derivative() (std::sin/std::cos) to rounding level.
    const mcsim::MotorParams m = paper_motor();
    PmPlant p(m, mcsim::LoadProfile({{0.0, 0.05, 0.0}}), 3);
    PmPlant::State x;
    x << 1.2, -0.7, 15.0, 3.3;
    p.reset(x, 0.0);
    const double h = kTs / 3.0;
    double t = 0.0;
    for (int k = 0; k < 2000; ++k) {
        const double va = 20.0 * std::sin(0.01 * k);
        const double vb = -12.0;
        p.step(va, vb, kTs);
        for (int s = 0; s < 3; ++s) {
            const double ts = t + s * h;
            const auto k1 = p.derivative(x, ts, va, vb);
            const auto k2 = p.derivative(x + 0.5 * h * k1, ts + 0.5 * h, va, vb);
            const auto k3 = p.derivative(x + 0.5 * h * k2, ts + 0.5 * h, va, vb);
            const auto k4 = p.derivative(x + h * k3, ts + h, va, vb);
            x += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        }
        t += kTs;
    }
    EXPECT_NEAR(p.theta_rad(), x[3], 1e-10);
    EXPECT_NEAR(p.omega_rad_s(), x[2], 1e-8);
    EXPECT_NEAR(p.i_a_A(), x[0], 1e-9);
    EXPECT_NEAR(p.i_b_A(), x[1], 1e-9);
}

TEST(Plant, SmallSinCosMatchesLibm)
{
    for (double x = -0.5; x <= 0.5; x += 1e-4) {
        double s = 0.0;
        double c = 0.0;
        PmPlant::small_sincos(x, &s, &c);
        ASSERT_NEAR(s, std::sin(x), 4e-16) << x;
        ASSERT_NEAR(c, std::cos(x), 4e-16) << x;
    }
    double s = 0.0;
    double c = 0.0;
    PmPlant::small_sincos(2.0, &s, &c);  // libm fallback
    EXPECT_EQ(s, std::sin(2.0));
    EXPECT_EQ(c, std::cos(2.0));
}

TEST(Plant, LockedRotorCurrentStep)
{
    // At theta = 0 a current in phase a gives no torque (eq. 1: -K i_a sin 0),
    // so the rotor stays put and i_a is the RL step V/R (1 - exp(-t R/L)).
    const mcsim::MotorParams m = paper_motor();
    PmPlant p(m, mcsim::LoadProfile(), PmPlant::kDefaultSubsteps);
    p.reset(PmPlant::State::Zero());
    const double V = 10.0;
    const double tau = m.L_H / m.R_ohm;
    for (int k = 1; k <= 300; ++k) {  // 30 ms = 10 tau
        p.step(V, 0.0, kTs);
        const double t = k * kTs;
        // RK4 local error (h/tau)^5/120 of V/R is 1.2e-9 A per sample at one
        // sub-step; it accumulates to ~1.3e-8 A around t = tau.
        ASSERT_NEAR(p.i_a_A(), V / m.R_ohm * (1.0 - std::exp(-t / tau)), 5e-8) << "t = " << t;
        ASSERT_EQ(p.i_b_A(), 0.0);
        ASSERT_EQ(p.theta_rad(), 0.0);
    }
    EXPECT_NEAR(p.i_a_A(), V / m.R_ohm, 1e-4 * V / m.R_ohm);
}

TEST(Plant, BackEmfAmplitude)
{
    // Open circuit (i = 0): L di/dt is the back-EMF vector of magnitude K w.
    const mcsim::MotorParams m = paper_motor();
    PmPlant p(m, mcsim::LoadProfile(), 1);
    const double w = 7.0;
    for (double th = 0.0; th < 0.2; th += 0.0137) {
        PmPlant::State x;
        x << 0.0, 0.0, w, th;
        const auto dx = p.derivative(x, 0.0, 0.0, 0.0);
        EXPECT_NEAR(m.L_H * std::hypot(dx[0], dx[1]), m.K_Nm_per_A * w, 1e-12);
        EXPECT_NEAR(m.L_H * dx[0], m.K_Nm_per_A * w * std::sin(m.n_p * th), 1e-12);
    }
}

TEST(Plant, ShortedWindingsAtConstantSpeed)
{
    // Rotor held at constant speed (huge J, no friction), windings shorted
    // (v = 0): the steady current is the back-EMF K w over the impedance
    // R + j n_p w L, at electrical frequency n_p w.
    mcsim::MotorParams m = paper_motor();
    m.J_kgm2 = 1e12;
    m.fv_Nms_per_rad = 0.0;
    m.coulomb_Nm = 0.0;
    PmPlant p(m, mcsim::LoadProfile(), PmPlant::kDefaultSubsteps);
    const double w = 5.0;
    PmPlant::State x;
    x << 0.0, 0.0, w, 0.0;
    p.reset(x);
    for (int k = 0; k < 300; ++k) {  // 10 tau of transient
        p.step(0.0, 0.0, kTs);
    }
    const double expect = m.K_Nm_per_A * w / std::hypot(m.R_ohm, m.n_p * w * m.L_H);
    for (int k = 0; k < 300; ++k) {
        p.step(0.0, 0.0, kTs);
        ASSERT_NEAR(std::hypot(p.i_a_A(), p.i_b_A()), expect, 1e-4 * expect);
    }
    EXPECT_NEAR(p.omega_rad_s(), w, 1e-9);
}

TEST(Plant, CoulombFrictionAndLoadTorque)
{
    mcsim::MotorParams m = paper_motor();
    PmPlant p(m, mcsim::LoadProfile({{1.0, 0.2, 0.0}}), 1);
    EXPECT_DOUBLE_EQ(p.load_torque_Nm(10.0, 0.0), m.coulomb_Nm);
    EXPECT_DOUBLE_EQ(p.load_torque_Nm(-10.0, 0.0), -m.coulomb_Nm);
    EXPECT_DOUBLE_EQ(p.load_torque_Nm(0.0, 0.0), 0.0);
    EXPECT_NEAR(p.load_torque_Nm(0.05, 0.0), m.coulomb_Nm * std::tanh(1.0), 1e-15);
    EXPECT_DOUBLE_EQ(p.load_torque_Nm(10.0, 1.5), m.coulomb_Nm + 0.2);
    // Free deceleration with no current: J dw/dt = -f_v w - C - T_load.
    PmPlant::State x;
    x << 0.0, 0.0, 10.0, 0.0;
    p.reset(x, 0.0);
    EXPECT_NEAR(p.accel_rad_s2(), (-m.fv_Nms_per_rad * 10.0 - m.coulomb_Nm) / m.J_kgm2, 1e-9);
}

TEST(LoadProfile, StepsAndRamps)
{
    const mcsim::LoadProfile lp({{1.0, 0.5, 0.0}, {2.0, -0.5, 1.0}, {4.0, 0.0, 0.0}});
    EXPECT_EQ(lp.torque_Nm(0.0), 0.0);
    EXPECT_EQ(lp.torque_Nm(0.999), 0.0);
    EXPECT_EQ(lp.torque_Nm(1.0), 0.5);
    EXPECT_EQ(lp.torque_Nm(1.9), 0.5);
    EXPECT_NEAR(lp.torque_Nm(2.5), 0.0, 1e-15);
    EXPECT_NEAR(lp.torque_Nm(2.75), -0.25, 1e-15);
    EXPECT_EQ(lp.torque_Nm(3.5), -0.5);
    EXPECT_EQ(lp.torque_Nm(4.0), 0.0);
    EXPECT_EQ(lp.torque_Nm(100.0), 0.0);
    EXPECT_TRUE(mcsim::LoadProfile().empty());
}

TEST(Reference, PaperTrajectory)
{
    const mcsim::Reference ref = paper_reference();
    EXPECT_EQ(ref.eval(0.0).theta_rad, 0.0);
    EXPECT_NEAR(ref.eval(1.0).theta_rad, 9.0, 1e-12);  // p(1/2) = 1/2
    EXPECT_NEAR(ref.eval(1.0).omega_rad_s, 18.0 / 2.0 * 2.1875, 1e-12);  // peak p' = 35/16
    EXPECT_NEAR(ref.eval(2.0).theta_rad, 18.0, 1e-12);
    EXPECT_NEAR(ref.eval(2.0).omega_rad_s, 0.0, 1e-12);
    EXPECT_NEAR(ref.eval(3.0).omega_rad_s, -19.6875, 1e-12);
    EXPECT_EQ(ref.eval(4.2).theta_rad, 0.0);
    EXPECT_EQ(ref.final_theta_rad(), 0.0);
    // Derivatives agree with central differences.
    for (double t = 0.05; t < 4.0; t += 0.173) {
        const double h = 1e-6;
        const auto a = ref.eval(t - h);
        const auto b = ref.eval(t + h);
        EXPECT_NEAR((b.theta_rad - a.theta_rad) / (2 * h), ref.eval(t).omega_rad_s, 1e-6) << t;
        EXPECT_NEAR((b.omega_rad_s - a.omega_rad_s) / (2 * h), ref.eval(t).accel_rad_s2, 1e-5) << t;
    }
}

}  // namespace

namespace {
// paper 002's reference motor with its LuGre friction (the set)
mcsim::MotorParams ipmsm_lugre(double J)
{
    mcsim::MotorParams m;
    m.type = mcsim::MotorType::kPmsm3;
    m.L_H = 3e-3;
    m.L_q_H = 9e-3;
    m.R_ohm = 0.3;
    m.K_Nm_per_A = 4 * 0.04;
    m.n_p = 4;
    m.J_kgm2 = J;
    m.fv_Nms_per_rad = 5e-4;
    m.lugre_sigma0_Nm_per_rad = 10.0;
    m.lugre_sigma1_Nms_per_rad = 0.05;
    m.lugre_sigma2_Nms_per_rad = 2e-4;
    m.lugre_Mc_Nm = 0.05;
    m.lugre_Ms_Nm = 0.08;
    m.lugre_ws_rad_s = 0.5;
    return m;
}
}  // namespace

// LuGre (paper 002 (45)-(46)): at a held speed (a huge inertia) the
// bristles settle and the friction is the steady-state curve
// g(w) sign(w) + sigma2 w; a spin-down converges with the sub-steps (the
// splitting of the bristle's exact exponential step from RK4 is first
// order): the difference to 256 sub-steps shrinks about four times from
// 16 to 64 sub-steps, and is below 1e-3 rad/s at 64.
TEST(Plant, LugreSteadyFrictionAndSubstepConvergence)
{
    for (double w : {0.2, 1.0, 5.0, -3.0}) {
        mcsim::PmPlant p(ipmsm_lugre(1e6), mcsim::LoadProfile(), 4);
        mcsim::PmPlant::State x0 = mcsim::PmPlant::State::Zero();
        x0[mcsim::PmPlant::kOmega] = w;
        p.reset(x0);
        const double v[3] = {0.0, 0.0, 0.0};
        for (int k = 0; k < 10000; ++k) p.step_phases(v, 1e-4);  // 1 s: 26 of z's time constants at 0.2 rad/s
        const double r = w / 0.5;
        const double steady = (0.05 + 0.03 * std::exp(-r * r)) * (w > 0 ? 1.0 : -1.0) + 2e-4 * w;
        EXPECT_NEAR(p.lugre_torque_Nm(), steady, 1e-4) << w;
    }
    auto spin_down = [](int substeps) {
        mcsim::PmPlant p(ipmsm_lugre(1e-3), mcsim::LoadProfile(), substeps);
        mcsim::PmPlant::State x0 = mcsim::PmPlant::State::Zero();
        x0[mcsim::PmPlant::kOmega] = 20.0;
        p.reset(x0);
        const double v[3] = {0.0, 0.0, 0.0};
        std::vector<double> w;
        for (int k = 0; k < 2000; ++k) {
            p.step_phases(v, 1e-4);
            w.push_back(p.omega_rad_s());
        }
        return w;
    };
    const auto w16 = spin_down(16), w64 = spin_down(64), w256 = spin_down(256);
    double e16 = 0.0, e64 = 0.0;
    for (std::size_t k = 0; k < w16.size(); ++k) {
        e16 = std::fmax(e16, std::fabs(w16[k] - w256[k]));
        e64 = std::fmax(e64, std::fabs(w64[k] - w256[k]));
    }
    std::printf("spin-down against 256 sub-steps: 16: %.3g rad/s, 64: %.3g rad/s\n", e16, e64);
    EXPECT_LT(e64, e16 / 3.0);
    EXPECT_LT(e64, 1e-3);
    EXPECT_LT(std::fabs(w256.back()), 20.0) << "friction and the shorted windings brake";
}

// paper 002's load pulses: raised-cosine edges, 0.5 (1 - cos(pi x)) of the
// change; 0 before, the level held between the edges, 0 after.
TEST(LoadProfile, RaisedCosinePulse)
{
    const mcsim::LoadProfile p({mcsim::LoadStep{0.1, 0.5, 0.02, true}, mcsim::LoadStep{0.18, 0.0, 0.02, true}});
    EXPECT_EQ(p.torque_Nm(0.05), 0.0);
    EXPECT_NEAR(p.torque_Nm(0.105), 0.5 * 0.5 * (1.0 - std::cos(3.14159265358979 * 0.25)), 1e-12);
    EXPECT_NEAR(p.torque_Nm(0.11), 0.25, 1e-12);
    EXPECT_NEAR(p.torque_Nm(0.15), 0.5, 1e-12);
    EXPECT_NEAR(p.torque_Nm(0.19), 0.25, 1e-12);
    EXPECT_EQ(p.torque_Nm(0.25), 0.0);
    // smooth at the edge's ends: the slope over a microsecond is ~0
    EXPECT_LT(std::fabs(p.torque_Nm(0.120001) - p.torque_Nm(0.12)), 1e-8);
    const mcsim::LoadProfile lin({mcsim::LoadStep{0.1, 0.5, 0.02, false}});
    EXPECT_NEAR(lin.torque_Nm(0.105), 0.125, 1e-12);
}

#include "model/encoder.h"

// The encoder: floor to its counts, wrapped into [-pi, pi), noise of the
// asked sigma.
TEST(Encoder, QuantisesWrapsAndAddsNoise)
{
    mcsim::Encoder e(mcsim::EncoderParams{4096, 0.0}, 1);
    const double step = 2.0 * 3.14159265358979323846 / 4096.0;
    EXPECT_NEAR(e.measure(10.5 * step), 10.0 * step, 1e-12);
    EXPECT_NEAR(e.measure(-0.5 * step), -step, 1e-12);
    EXPECT_NEAR(e.measure(2.0 * 3.14159265358979323846 + 3.0 * step), 3.0 * step, 1e-9);
    const double m = e.measure(3.5);  // past pi: wrapped
    EXPECT_LT(m, 0.0);
    EXPECT_GE(m, -3.14159265358979323846);
    mcsim::Encoder n(mcsim::EncoderParams{1 << 30, 1e-4}, 3);
    double ss = 0.0;
    for (int k = 0; k < 20000; ++k) {
        const double d = n.measure(1.0) - 1.0;
        ss += d * d;
    }
    EXPECT_NEAR(std::sqrt(ss / 20000), 1e-4, 5e-6);
}
