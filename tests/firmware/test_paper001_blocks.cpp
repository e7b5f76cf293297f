// Unit tests of the paper-001 firmware blocks (Shah, Espinosa-Perez, Ortega,
// Hilairet, IJRNC 2014 = ../shared/papers/001_f1ea247add877c0a.txt; errata
// in ../shared/papers/README.md): the gradient flux observer (12)-(14), the
// unwrap operator of Appendix A, the I&I speed and load observer (15)-(16),
// the IDA-PBC law (11) with its feed-forward, the speed profile and the two
// circle fits of the start-up.
//
// Two kinds of test per block: one sample at a time against the paper's
// equation evaluated independently in double, from the block's own state
// (a dropped term, a wrong sign or a wrong gain is then a one-step
// difference far above the rounding), and the block's behaviour on
// synthetic data (convergence, continuity, exact recovery).
//
// Tolerances hold in both builds; each states its budget. The fixed build
// is Q14.17 (LSB 2^-17 = 7.6e-6, every product rounded to 0.5 LSB), so a
// value that goes through a few roundings is good to a few LSB, and a
// constant stored alone carries up to 0.5 LSB (3.8e-6 absolute, i.e.
// 0.4 % of a 1e-3 coefficient). Where a test compares one step with
// double, its parameters are chosen so that every folded coefficient is a
// dyadic fraction, exact in Q14.17 and in float; the difference is then
// the block's arithmetic alone.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

extern "C" {
#include "control/ida_pbc.h"
#include "estimators/angle_unwrap.h"
#include "estimators/flux_observer.h"
#include "estimators/speed_load_observer.h"
#include "math/frame_fg.h"
#include "math/mc_convert.h"
#include "startup/flux_circle_fit.h"
#include "trajectory/speed_profile.h"
}

#include "fw_test_util.h"

using fwtest::D;
using fwtest::kPi;
using fwtest::M;

namespace {
// uniform in [-a, a], deterministic (a 32-bit LCG)
struct Lcg {
    unsigned s = 2024u;
    double operator()(double a)
    {
        s = s * 1103515245u + 12345u;
        return a * (2.0 * ((s >> 8) & 0xFFFF) / 65535.0 - 1.0);
    }
};

// Paper 001 section 5: L = 3.8 mH, R = 0.225 ohm, Phi = 0.17 Wb, n_p = 3,
// J = 0.012 kg m^2 (three phases: K_t = (3/2) n_p Phi); gamma = 5000,
// a1 = 20, a2 = 6 (section 5.1); Ts = 1e-4 s.
constexpr double kL = 3.8e-3, kR = 0.225, kPhi = 0.17, kJ = 0.012, kTs = 1e-4;
constexpr int kNp = 3;
constexpr double kKt = 1.5 * kNp * kPhi;
constexpr double kGamma = 5000.0, kA1 = 20.0, kA2 = 6.0;

// flux_observer_config_t as flux_observer.h defines it: w = lambda/Ts,
// rho = (w - (L/Ts) i) 2^-s (2^s Ts/Phi) with s = floor(log2(Phi/Ts)), so
// the gain 2^s Ts/Phi lies in (0.5, 1] as the header asks (0.602 here).
flux_observer_config_t flux_cfg(double R, double L, double Phi, double Ts, double gamma)
{
    flux_observer_config_t c{};
    c.R_ohm = M(R);
    c.L_fs_ohm = M(L / Ts);
    c.Phi_fs_V = M(Phi / Ts);
    const int s = static_cast<int>(std::floor(std::log2(Phi / Ts)));
    c.rho_pre = M(std::ldexp(1.0, -s));
    c.rho_gain = M(std::ldexp(Ts / Phi, s));
    c.gPhi3_V = M(gamma * Phi * Phi * Phi);
    return c;
}

mc_ab_t ab(double a, double b) { return mc_ab_t{M(a), M(b)}; }
mc_rot_t rot(double x) { return mc_rot_t{M(std::sin(x)), M(std::cos(x))}; }
// x as the build holds it: the double references start from the inputs the
// block was actually given (in fixed, cos x stored to 3.8e-6 is already
// 6.5e-3 V of w = Phi/Ts cos x for paper 001's motor)
double q(double x) { return D(M(x)); }

// The synthetic rotating machine of the flux-observer tests: electrical
// angle theta = theta0 + w_e k Ts, a current of amplitude I leading the
// rotor by phi_i, flux lambda = L i + Phi (cos theta, sin theta). The held
// voltage v[k-1] is the one that moves lambda from sample k-1 to k with the
// resistive drop R i integrated by the trapezoid rule (exact for the
// observer's discretisation: the tests measure the observer, not the
// discretisation of a plant).
struct SynthMachine {
    double theta0, w_e, I, phi_i;
    double theta(int k) const { return theta0 + w_e * k * kTs; }
    double ia(int k) const { return I * std::cos(theta(k) + phi_i); }
    double ib(int k) const { return I * std::sin(theta(k) + phi_i); }
    double lam_a(int k) const { return kL * ia(k) + kPhi * std::cos(theta(k)); }
    double lam_b(int k) const { return kL * ib(k) + kPhi * std::sin(theta(k)); }
    // voltage held over [k-1, k]
    double va(int k) const { return (lam_a(k) - lam_a(k - 1)) / kTs + kR * (ia(k - 1) + ia(k)) / 2; }
    double vb(int k) const { return (lam_b(k) - lam_b(k - 1)) / kTs + kR * (ib(k - 1) + ib(k)) / 2; }
};

// one sample of the observer on the synthetic machine: hold v[k-1], step with i[k]
void flux_step(flux_observer_t *o, const SynthMachine &m, int k)
{
    flux_observer_hold(o, ab(m.va(k), m.vb(k)));
    flux_observer_step(o, ab(m.ia(k), m.ib(k)));
}
}  // namespace

// ---- gradient flux observer, eqs. (12)-(14) ----

// lambda_hat(0) = L i0 + Phi (cos, sin)(angle0): rho_hat(0) is the unit
// vector at angle0 (errata), w = lambda_hat/Ts. Budget: w = 1700 V scale,
// float ulp 1.2e-4 V; fixed a few LSB.
TEST(FluxObserver, InitPutsTheEstimateOnTheGivenAngle)
{
    const flux_observer_config_t c = flux_cfg(kR, kL, kPhi, kTs, kGamma);
    flux_observer_t o;
    const double a0 = 2.3, ia = 1.5, ib = -2.0;
    flux_observer_init(&o, &c, rot(a0), ab(ia, ib));
    EXPECT_NEAR(D(o.w_V.alpha), (kL * ia + kPhi * q(std::cos(a0))) / kTs, 1e-3);
    EXPECT_NEAR(D(o.w_V.beta), (kL * ib + kPhi * q(std::sin(a0))) / kTs, 1e-3);
    EXPECT_NEAR(D(o.rho.alpha), std::cos(a0), 3e-5);
    EXPECT_NEAR(D(o.rho.beta), std::sin(a0), 3e-5);
    EXPECT_NEAR(D(o.rho2), 1.0, 6e-5);
    EXPECT_NEAR(D(o.unit.c), std::cos(a0), 3e-5);
    EXPECT_NEAR(D(o.unit.s), std::sin(a0), 3e-5);
    EXPECT_TRUE(o.gradient_on);
    flux_observer_set_gradient(&o, false);
    EXPECT_FALSE(o.gradient_on);
    flux_observer_set_gradient(&o, true);
    EXPECT_TRUE(o.gradient_on);
}

// flux_observer_seed: lambda_hat = L i + r Phi (cos, sin)(angle), so
// |rho_hat| = r (the active flux's radius of a salient motor, paper002
// drive's handover), the angle the given one; the target, the held
// voltage and the gradient's switch are kept. Budgets as above.
TEST(FluxObserver, SeedPutsTheEstimateOnTheGivenAngleAndRadius)
{
    const flux_observer_config_t c = flux_cfg(kR, kL, kPhi, kTs, kGamma);
    flux_observer_t o;
    flux_observer_init(&o, &c, rot(0.3), ab(0.0, 0.0));
    flux_observer_set_target(&o, M(0.64));
    flux_observer_set_gradient(&o, false);
    flux_observer_hold(&o, ab(1.25, -0.5));
    const double a0 = -2.1, ia = 1.5, ib = -2.0, r = 0.8;
    flux_observer_seed(&o, rot(a0), ab(ia, ib), M(r));
    // r as the build holds it (in fixed 0.8 is stored to 3.8e-6, 5e-3 V of w)
    EXPECT_NEAR(D(o.w_V.alpha), (kL * ia + q(r) * kPhi * q(std::cos(a0))) / kTs, 1e-3);
    EXPECT_NEAR(D(o.w_V.beta), (kL * ib + q(r) * kPhi * q(std::sin(a0))) / kTs, 1e-3);
    EXPECT_NEAR(D(o.rho2), r * r, 6e-5);
    EXPECT_NEAR(D(o.unit.c), std::cos(a0), 3e-5);
    EXPECT_NEAR(D(o.unit.s), std::sin(a0), 3e-5);
    EXPECT_NEAR(D(o.rho2_target), 0.64, 1e-5);
    EXPECT_FALSE(o.gradient_on);
    EXPECT_NEAR(D(o.v_prev_V.alpha), 1.25, 1e-5);
    EXPECT_NEAR(D(o.v_prev_V.beta), -0.5, 1e-5);
}

// (12)-(14) one sample at a time against double, in flux units:
//   lambda1 = lambda + Ts (v[k-1] - R (i[k-1] + i[k])/2 + gamma eta (Phi^2 - |eta|^2)),
//   eta = Phi rho_hat (13)-(14) at the start of the sample (the block's state),
//   rho1 = (lambda1 - L i[k]) / Phi,
// on random currents (+-5 A, so the trapezoid differs from either end by up
// to a volt), random held voltages, the gradient off on some samples, and
// flux_observer_shift every 50 samples, which also spreads |rho| away
// from 1 so the gradient term is large (tens of volts).
// Budgets: w (= lambda/Ts, up to 2800 V): float ulp there 2.4e-4 V and a
// few roundings; fixed: rho2's rounding (0.5 LSB) times gamma Phi^3 |rho|
// (<= 50 V) plus R's storage error times |i|: 2e-3 V covers both (the
// smallest effect of a wrong term is R |di|/2, about 0.3 V). rho: 3e-5
// (4 LSB: three roundings and the stored 2^s Ts/Phi, relative 6e-6).
TEST(FluxObserver, EachStepFollowsEq12To14)
{
    const flux_observer_config_t c = flux_cfg(kR, kL, kPhi, kTs, kGamma);
    flux_observer_t o;
    flux_observer_init(&o, &c, rot(0.4), ab(1.0, -1.0));
    Lcg rnd;
    double i_prev_a = 1.0, i_prev_b = -1.0;
    double worst_w = 0.0, worst_rho = 0.0;
    int shifts = 0;
    for (int k = 0; k < 600; ++k) {
        if (k % 50 == 25) {
            // lambda_hat -= Phi c: rho_hat moves by -c, w by -(Phi/Ts) c
            const double ca = q(rnd(0.6)), cb = q(rnd(0.6));
            const double w0a = D(o.w_V.alpha), w0b = D(o.w_V.beta);
            const double r0a = D(o.rho.alpha), r0b = D(o.rho.beta);
            flux_observer_shift(&o, ab(ca, cb));
            ASSERT_NEAR(D(o.w_V.alpha), w0a - kPhi / kTs * ca, 2e-3) << k;
            ASSERT_NEAR(D(o.w_V.beta), w0b - kPhi / kTs * cb, 2e-3) << k;
            const double ra = r0a - ca, rb = r0b - cb, n = std::hypot(ra, rb);
            ASSERT_NEAR(D(o.rho.alpha), ra, 3e-5) << k;
            ASSERT_NEAR(D(o.rho.beta), rb, 3e-5) << k;
            ASSERT_NEAR(D(o.unit.c), ra / n, 1e-4) << k;
            ASSERT_NEAR(D(o.unit.s), rb / n, 1e-4) << k;
            ++shifts;
        }
        const bool grad_on = (k % 7) != 3;
        flux_observer_set_gradient(&o, grad_on);
        const double ia = q(rnd(5.0)), ib = q(rnd(5.0)), va = q(rnd(30.0)), vb = q(rnd(30.0));
        // the block's state at the start of the sample
        const double lam_a = kTs * D(o.w_V.alpha), lam_b = kTs * D(o.w_V.beta);
        const double eta_a = kPhi * D(o.rho.alpha), eta_b = kPhi * D(o.rho.beta);
        const double g = grad_on ? kGamma * (kPhi * kPhi - (eta_a * eta_a + eta_b * eta_b)) : 0.0;
        const double l1a = lam_a + kTs * (va - kR * (i_prev_a + ia) / 2 + g * eta_a);
        const double l1b = lam_b + kTs * (vb - kR * (i_prev_b + ib) / 2 + g * eta_b);
        const double r1a = (l1a - kL * ia) / kPhi, r1b = (l1b - kL * ib) / kPhi, n1 = std::hypot(r1a, r1b);

        flux_observer_hold(&o, ab(va, vb));
        flux_observer_step(&o, ab(ia, ib));
        worst_w = std::fmax(worst_w, std::fmax(std::fabs(D(o.w_V.alpha) - l1a / kTs), std::fabs(D(o.w_V.beta) - l1b / kTs)));
        worst_rho = std::fmax(worst_rho, std::fmax(std::fabs(D(o.rho.alpha) - r1a), std::fabs(D(o.rho.beta) - r1b)));
        ASSERT_LT(worst_w, 2e-3) << "step " << k;
        ASSERT_LT(worst_rho, 3e-5) << "step " << k;
        ASSERT_NEAR(D(o.rho2), n1 * n1, 1e-4) << k;
        ASSERT_NEAR(D(o.unit.c), r1a / n1, 1e-4) << k;
        ASSERT_NEAR(D(o.unit.s), r1b / n1, 1e-4) << k;
        i_prev_a = ia;
        i_prev_b = ib;
    }
    EXPECT_EQ(shifts, 12);
    std::printf("max one-step difference from (12)-(14): w %.3g V, rho %.3g\n", worst_w, worst_rho);
}

// With the gradient on, the estimate converges to the true flux of a
// rotating machine from 2.5 rad off, in both directions of rotation (w_e =
// +-200 rad/s electrical, where the gradient's rate gamma Phi^2 = 145 /s
// acts fully: converged within 1000 samples in double). After 2000
// samples: the angle of rho_hat within 1e-4 rad of the rotor's and |rho_hat|
// within 1e-4 of 1 (fixed: rho carries ~2 LSB = 1.5e-5; float: 1e-7).
TEST(FluxObserver, GradientConvergesToTheTrueFlux)
{
    const flux_observer_config_t c = flux_cfg(kR, kL, kPhi, kTs, kGamma);
    for (double w_e : {200.0, -200.0}) {
        const SynthMachine m{0.4, w_e, 3.0, 1.9};
        flux_observer_t o;
        flux_observer_init(&o, &c, rot(m.theta(0) + 2.5), ab(m.ia(0), m.ib(0)));
        double worst_angle = 0.0, worst_norm = 0.0;
        for (int k = 1; k <= 3000; ++k) {
            flux_step(&o, m, k);
            if (k > 2000) {
                const double err = std::remainder(std::atan2(D(o.unit.s), D(o.unit.c)) - m.theta(k), 2 * kPi);
                worst_angle = std::fmax(worst_angle, std::fabs(err));
                worst_norm = std::fmax(worst_norm, std::fabs(std::hypot(D(o.rho.alpha), D(o.rho.beta)) - 1.0));
            }
        }
        EXPECT_LT(worst_angle, 1e-4) << w_e;
        EXPECT_LT(worst_norm, 1e-4) << w_e;
        std::printf("w_e %g: angle within %.3g rad, |rho| within %.3g of 1\n", w_e, worst_angle, worst_norm);
    }
}

// With the gradient off, (12) is a pure integrator of v - R i: lambda_hat -
// lambda stays at its initial value, so rho_hat - rho is a constant vector
// (here 2 sin(1.25) = 1.9 long) over 3000 samples (a third of a second at
// 200 rad/s electrical); turned back on, the gradient removes it.
// Budget 2e-4: the integrator's rounding accumulates, in float 0.5 ulp of
// w (6e-5 V, 3.6e-8 in rho) per sample, 1e-4 after 3000 samples if every
// rounding went the same way; in fixed 1 LSB of w per sample, 1.4e-5.
TEST(FluxObserver, WithoutTheGradientIsAPureIntegrator)
{
    const flux_observer_config_t c = flux_cfg(kR, kL, kPhi, kTs, kGamma);
    for (double w_e : {200.0, -200.0}) {
        const SynthMachine m{-1.1, w_e, 2.0, 1.2};
        flux_observer_t o;
        flux_observer_init(&o, &c, rot(m.theta(0) - 2.5), ab(m.ia(0), m.ib(0)));
        flux_observer_set_gradient(&o, false);
        const double off_a = std::cos(m.theta(0) - 2.5) - std::cos(m.theta(0));
        const double off_b = std::sin(m.theta(0) - 2.5) - std::sin(m.theta(0));
        double worst = 0.0;
        for (int k = 1; k <= 3000; ++k) {
            flux_step(&o, m, k);
            worst = std::fmax(worst, std::fabs(D(o.rho.alpha) - std::cos(m.theta(k)) - off_a));
            worst = std::fmax(worst, std::fabs(D(o.rho.beta) - std::sin(m.theta(k)) - off_b));
        }
        EXPECT_LT(worst, 2e-4) << w_e;
        std::printf("w_e %g, no gradient: rho_hat - rho constant within %.3g\n", w_e, worst);
        flux_observer_set_gradient(&o, true);
        for (int k = 3001; k <= 6000; ++k) {
            flux_step(&o, m, k);
        }
        const double err = std::remainder(std::atan2(D(o.unit.s), D(o.unit.c)) - m.theta(6000), 2 * kPi);
        EXPECT_LT(std::fabs(err), 1e-4) << w_e;
    }
}

// The start-up's use of the observer (flux_circle_fit.h): with the gradient
// off, the points rho_hat of an arc lie on the unit circle centred at
// lambda~/Phi; the Kasa fit of half a turn finds that centre and
// flux_observer_shift by it puts the estimate on the rotor's angle at once.
// Budget: the centre to 1e-3 (the fit's budget, FluxCircleFit tests), so
// the angle after the shift to 2e-3 rad.
TEST(FluxObserver, CircleFitAndShiftRemoveTheInitialError)
{
    const flux_observer_config_t c = flux_cfg(kR, kL, kPhi, kTs, kGamma);
    const SynthMachine m{0.7, 60.0, 2.0, 1.5};
    flux_observer_t o;
    flux_observer_init(&o, &c, rot(m.theta(0) + 2.0), ab(m.ia(0), m.ib(0)));
    flux_observer_set_gradient(&o, false);
    flux_circle_fit_config_t fc{4, M(0.02)};
    flux_circle_fit_t fit;
    flux_circle_fit_init(&fit, &fc);
    const int n = static_cast<int>(kPi / (60.0 * kTs));  // half an electrical turn
    for (int k = 1; k <= n; ++k) {
        flux_step(&o, m, k);
        flux_circle_fit_add(&fit, o.rho);
    }
    mc_ab_t centre{};
    ASSERT_TRUE(flux_circle_fit_center(&fit, &centre));
    EXPECT_NEAR(D(centre.alpha), std::cos(m.theta(0) + 2.0) - std::cos(m.theta(0)), 1e-3);
    EXPECT_NEAR(D(centre.beta), std::sin(m.theta(0) + 2.0) - std::sin(m.theta(0)), 1e-3);
    std::printf("centre of the observer's arc off by %.3g\n",
                std::hypot(D(centre.alpha) - (std::cos(m.theta(0) + 2.0) - std::cos(m.theta(0))),
                           D(centre.beta) - (std::sin(m.theta(0) + 2.0) - std::sin(m.theta(0)))));
    flux_observer_shift(&o, centre);
    const double err = std::remainder(std::atan2(D(o.unit.s), D(o.unit.c)) - m.theta(n), 2 * kPi);
    EXPECT_LT(std::fabs(err), 2e-3);
    EXPECT_NEAR(D(o.rho2), 1.0, 4e-3);
}

// ---- unwrap operator A, Appendix A (errata form) ----

// A vector turning by a constant step per sample, in both directions, for
// steps from small to close to pi (2.9 rad): the unwrapped angle e + 2 pi n
// equals the true angle (so it is continuous across +-pi), delta is the
// step, n counts the turns. Budget: e within 1 LSB of atan2 (fixed; 4e-7
// float) of the rounded input vector (0.7 LSB); delta carries two of those
// and the rounding of 2 pi (MC_TWO_PI, 2.5e-6 in fixed): 3e-5 and 5e-5.
TEST(AngleUnwrap, ContinuousAcrossPiInBothDirections)
{
    for (double dir : {1.0, -1.0}) {
        for (double step : {0.01, 0.3, 2.9}) {
            const double y0 = dir * 3.0;  // starts next to the cut at +-pi
            angle_unwrap_t u;
            angle_unwrap_init(&u, M(y0));
            const int n = static_cast<int>(40.0 / step) + 5;
            for (int k = 1; k <= n; ++k) {
                const double y = y0 + dir * step * k;
                angle_unwrap_step(&u, M(std::sin(y)), M(std::cos(y)));
                const double got = D(u.e_rad) + 2 * kPi * u.n_turns;
                ASSERT_NEAR(got, y, 3e-5) << dir << " " << step << " " << k;
                ASSERT_NEAR(D(u.delta_rad), dir * step, 5e-5) << dir << " " << step << " " << k;
            }
            // y0 + 40 rad and more: at least six turns counted, with the sign of the motion
            EXPECT_GE(dir * u.n_turns, 6) << dir << " " << step;
        }
    }
}

// Random steps in (-3, 3) rad: the unwrapped angle is the sum of the steps.
TEST(AngleUnwrap, FollowsRandomStepsBelowPi)
{
    Lcg rnd;
    angle_unwrap_t u;
    angle_unwrap_init(&u, M(0.5));
    double y = 0.5;
    for (int k = 0; k < 2000; ++k) {
        const double d = rnd(3.0);
        y += d;
        angle_unwrap_step(&u, M(std::sin(y)), M(std::cos(y)));
        ASSERT_NEAR(D(u.delta_rad), d, 5e-5) << k;
        ASSERT_NEAR(D(u.e_rad) + 2 * kPi * u.n_turns, y, 3e-5) << k;
    }
}

// ---- I&I speed and load observer, eqs. (15)-(16) ----

// Dyadic parameters, so every folded coefficient is exact in both builds:
// n_p = 4, Ts = 2^-13 s (fs/n_p = 2048), J = 2^-6, K_t = 0.75 (Ts K_t/J =
// 3 2^-9), a1 = 16 (a1 n_p Ts = 2^-7), a2 = 4 (a2 n_p Ts = 2^-9).
namespace {
constexpr int kDyNp = 4;
constexpr double kDyTs = 1.0 / 8192, kDyJ = 1.0 / 64, kDyKt = 0.75, kDyA1 = 16.0, kDyA2 = 4.0;

speed_load_observer_config_t ii_cfg(double Ts, double Kt, double J, int np, double a1, double a2)
{
    speed_load_observer_config_t c{};
    c.ts_kt_over_J = M(Ts * Kt / J);
    c.ts_over_J = M(Ts / J);
    c.fs_over_np = M(1.0 / (Ts * np));
    c.k_omega = M(a1 * np * Ts);
    c.k_load_Nm_s = M(a2 * np * Ts);
    return c;
}
}  // namespace

// (15) as printed, in xi, one explicit Euler step from the block's state:
//   xi = [w_hat - a1 y; tau_hat + a2 y]  (y = A's output at the last sample),
//   xi' = A33 xi + [a2/J - n_p a1^2; n_p a1 a2] y + [(K_t/J) i^T Jm rho; 0],
//   [w_hat; tau_hat](k+1) = xi(k+1) + [a1; -a2] y(k+1),
// where y is the test's own unwrapped angle of the input (the sum of the
// steps it drew), K_t = n_p Phi of (15) for two phases, and i^T Jm rho =
// rho_a i_b - rho_b i_a. Random electrical steps in +-0.5 rad (n_p w Ts,
// crossing +-pi many times), random currents +-8 A.
// Budget: the block sees y through atan2 of the rounded vector, 3.4 LSB on
// each difference (fixed; 1e-6 rad in float), which enters w_hat times a1
// = 16 and tau_hat times a2 = 4: 1e-3 rad/s and 3e-4 N m (fixed), 1e-4 and
// 3e-5 (float). A missing torque term is Ts K_t/J |i_q|, 0.02 rad/s and up.
TEST(SpeedLoadObserver, EachStepFollowsEq15)
{
#if MC_FIXED
    const double tol_w = 1e-3, tol_t = 3e-4;
#else
    const double tol_w = 1e-4, tol_t = 3e-5;
#endif
    const double np = kDyNp, Ts = kDyTs, J = kDyJ, a1 = kDyA1, a2 = kDyA2;
    const speed_load_observer_config_t c = ii_cfg(Ts, kDyKt, J, kDyNp, a1, a2);
    speed_load_observer_t o;
    double y = 1.0;
    speed_load_observer_init(&o, &c, rot(y), M(3.0), M(0.2));
    Lcg rnd;
    double worst_w = 0.0, worst_t = 0.0;
    for (int k = 0; k < 800; ++k) {
        const double dy = rnd(0.5), ia = rnd(8.0), ib = rnd(8.0);
        const double y1 = y + dy;
        const mc_rot_t r = rot(y1);
        const double ra = D(r.c), rb = D(r.s);
        const double iq = ra * ib - rb * ia;  // i^T Jm rho
        const double xi1 = D(o.omega_rad_s) - a1 * y, xi2 = D(o.load_Nm) + a2 * y;
        const double dxi1 = -np * a1 * xi1 - xi2 / J + (a2 / J - np * a1 * a1) * y + kDyKt / J * iq;
        const double dxi2 = np * a2 * xi1 + np * a1 * a2 * y;
        const double w1 = xi1 + Ts * dxi1 + a1 * y1, t1 = xi2 + Ts * dxi2 - a2 * y1;

        speed_load_observer_step(&o, r, ab(ia, ib));
        ASSERT_NEAR(D(o.i_q_A), iq, 3e-5) << k;
        worst_w = std::fmax(worst_w, std::fabs(D(o.omega_rad_s) - w1));
        worst_t = std::fmax(worst_t, std::fabs(D(o.load_Nm) - t1));
        ASSERT_LT(worst_w, tol_w) << "step " << k;
        ASSERT_LT(worst_t, tol_t) << "step " << k;
        y = y1;
    }
    std::printf("max one-step difference from (15): w_hat %.3g rad/s, tau_hat %.3g N m\n", worst_w, worst_t);
}

// Paper 001's motor (three phases, K_t = 1.5 n_p Phi) turning at a constant
// speed against a constant load, the current along q balancing it (J w' =
// K_t i_q - tau_L = 0): from w_hat = tau_hat = 0 the observer converges
// with the poles of A33 (s^2 + n_p a1 s + n_p a2/J: -30 +- 24.5j /s), so
// after 1 s the initial error is down by e^-30. Budget at the end, for
// the fixed build: the coefficients a1 n_p Ts = 6e-3, a2 n_p Ts = 1.8e-3,
// Ts/J and Ts K_t/J are stored to 0.5 LSB (the ratio K_t of the last two
// moves tau_hat's equilibrium by 1e-3 relative), and increments below
// 0.5 LSB are lost (tau_hat stops moving once a2 n_p Ts |nu| < 3.8e-6,
// nu < 2e-3 rad/s): 2e-2 rad/s and 5e-3 N m; float is far inside.
TEST(SpeedLoadObserver, ConvergesToConstantSpeedAndLoad)
{
    const speed_load_observer_config_t c = ii_cfg(kTs, kKt, kJ, kNp, kA1, kA2);
    for (double w : {8.0, -12.0}) {
        for (double tau : {0.6, -0.4}) {
            const double iq = tau / kKt, th0 = -2.0;
            speed_load_observer_t o;
            speed_load_observer_init(&o, &c, rot(th0), MC_ZERO, MC_ZERO);
            double worst_w = 0.0, worst_t = 0.0;
            for (int k = 1; k <= 15000; ++k) {
                const double th = th0 + kNp * w * k * kTs;
                // i along q: i = i_q (-sin, cos), so rho_a i_b - rho_b i_a = i_q
                speed_load_observer_step(&o, rot(th), ab(-iq * std::sin(th), iq * std::cos(th)));
                if (k > 10000) {
                    worst_w = std::fmax(worst_w, std::fabs(D(o.omega_rad_s) - w));
                    worst_t = std::fmax(worst_t, std::fabs(D(o.load_Nm) - tau));
                }
            }
            EXPECT_LT(worst_w, 2e-2) << w << " " << tau;
            EXPECT_LT(worst_t, 5e-3) << w << " " << tau;
            std::printf("w %g tau %g: last 0.5 s within %.3g rad/s, %.3g N m\n", w, tau, worst_w, worst_t);
        }
    }
}

// ---- IDA-PBC, eq. (11) with the feed-forward ----
namespace {
// Dyadic parameters (exact in both builds): R = 0.25, r = 0.75, n_p = 4,
// L = 2^-8 (n_p L = 2^-6), Phi = 0.125 (K_e = n_p Phi = 0.5), J = K_t/64
// (J/K_t = 2^-6; 1/K_t is exact for K_t = K_e = 0.5, and 4/3 stored to
// 0.5 LSB for three phases, K_t = 0.75).
constexpr double kPbR = 0.25, kPbr = 0.75, kPbL = 1.0 / 256, kPbPhi = 0.125, kPbImax = 8.0;
constexpr int kPbNp = 4;
double pbc_J(double Kt) { return Kt / 64; }

ida_pbc_config_t pbc_cfg(double Kt)
{
    ida_pbc_config_t c{};
    c.R_minus_r_ohm = M(kPbR - kPbr);
    c.r_ohm = M(kPbr);
    c.npL_ohm_s = M(kPbNp * kPbL);
    c.Ke_V_s = M(kPbNp * kPbPhi);
    c.inv_Kt_A_Nm = M(1.0 / Kt);
    c.J_over_Kt_A_s2 = M(pbc_J(Kt) / Kt);
    c.i_max_A = M(kPbImax);
    return c;
}
}  // namespace

// Two phases (K_t = n_p Phi, as (11) is derived): (11) as printed,
//   v = (R - r) i + [-(L/Phi) tau w_hat; n_p Phi w* + r tau/(n_p Phi)],
// with tau = tau_hat + J dw_ref/dt (the errata's feed-forward; tau = tau_hat
// when dw_ref/dt = 0) limited to K_t i_max (Remark 2's current reference);
// then three phases (K_t = 1.5 K_e) in the current form of ida_pbc.h. Random inputs: currents +-8 A, speeds +-100
// rad/s, load +-2 N m, dw_ref/dt +-800 rad/s^2 (the reference current
// saturates on about a quarter of the samples). Budget 2e-4 V: a few
// roundings of terms up to 50 V and i_q* (error <= 3 LSB plus 1/K_t's
// storage times |tau|) times n_p L w_hat (1.6 ohm) and r.
TEST(IdaPbc, OutputIsEq11WithTheFeedForward)
{
    Lcg rnd;
    for (int phases : {2, 3}) {
        const double Ke = kPbNp * kPbPhi, Kt = (phases == 2) ? Ke : 1.5 * Ke;
        const ida_pbc_config_t c = pbc_cfg(Kt);
        ida_pbc_t s;
        ida_pbc_init(&s);
        EXPECT_EQ(D(s.i_q_ref_A), 0.0);
        int saturated = 0;
        for (int k = 0; k < 400; ++k) {
            const double id = rnd(8.0), iq = rnd(8.0), wh = rnd(100.0), th = rnd(2.0), wr = rnd(100.0);
            const double acc = (k % 4 == 0) ? 0.0 : rnd(800.0);
            double iq_ref = (th + pbc_J(Kt) * acc) / Kt;
            if (std::fabs(iq_ref) > kPbImax) {
                iq_ref = std::copysign(kPbImax, iq_ref);
                ++saturated;
            }
            double vd, vq;
            if (phases == 2) {
                const double tau = Kt * iq_ref;  // the torque the limited reference asks for
                vd = (kPbR - kPbr) * id - kPbL / kPbPhi * tau * wh;
                vq = (kPbR - kPbr) * iq + kPbNp * kPbPhi * wr + kPbr / (kPbNp * kPbPhi) * tau;
            } else {
                vd = (kPbR - kPbr) * id - kPbNp * kPbL * wh * iq_ref;
                vq = (kPbR - kPbr) * iq + Ke * wr + kPbr * iq_ref;
            }
            mc_t v_d, v_q;
            ida_pbc_step(&s, &c, M(id), M(iq), M(wh), M(th), M(wr), M(acc), &v_d, &v_q);
            ASSERT_NEAR(D(s.i_q_ref_A), iq_ref, 3e-5) << phases << " " << k;
            ASSERT_NEAR(D(v_d), vd, 2e-4) << phases << " " << k;
            ASSERT_NEAR(D(v_q), vq, 2e-4) << phases << " " << k;
        }
        EXPECT_GT(saturated, 40) << phases;
        EXPECT_LT(saturated, 200) << phases;
    }
}

// Hand case: at the equilibrium of (11) (i = i*, w_hat = w*, no load, no
// ramp) the voltage is the back-EMF K_e w* on q and nothing on d; a load
// estimate adds r i_q* on q and -n_p L w_hat i_q* on d.
TEST(IdaPbc, HandCases)
{
    const ida_pbc_config_t c = pbc_cfg(0.5);
    ida_pbc_t s;
    ida_pbc_init(&s);
    mc_t v_d, v_q;
    ida_pbc_step(&s, &c, MC_ZERO, MC_ZERO, M(10.0), MC_ZERO, M(10.0), MC_ZERO, &v_d, &v_q);
    EXPECT_NEAR(D(v_d), 0.0, 1e-5);
    EXPECT_NEAR(D(v_q), 5.0, 1e-5);  // K_e w* = 0.5 * 10
    // tau_hat = 1 N m: i_q* = 2 A; the current is there (i_q = 2): v_q =
    // (R - r) 2 + 5 + r 2 = R 2 + 5, v_d = -n_p L w_hat i_q* = -(1/64) 10 2
    ida_pbc_step(&s, &c, MC_ZERO, M(2.0), M(10.0), M(1.0), M(10.0), MC_ZERO, &v_d, &v_q);
    EXPECT_NEAR(D(s.i_q_ref_A), 2.0, 1e-5);
    EXPECT_NEAR(D(v_d), -10.0 * 2.0 / 64, 1e-5);
    EXPECT_NEAR(D(v_q), 0.25 * 2 + 5.0, 1e-5);
    // the same torque asked by a ramp instead: J dw_ref/dt = 1 N m at 128 rad/s^2 (J = 1/128)
    ida_pbc_step(&s, &c, MC_ZERO, M(2.0), M(10.0), MC_ZERO, M(10.0), M(128.0), &v_d, &v_q);
    EXPECT_NEAR(D(s.i_q_ref_A), 2.0, 1e-5);
    EXPECT_NEAR(D(v_q), 0.25 * 2 + 5.0, 1e-5);
}

// ---- speed profile ----
namespace {
// speed_profile_config_t from corners (t [s], w [rad/s]) as the header
// defines it: ticks, the slope after each corner, the segment lengths, and
// theta at each corner (the integral of the piecewise-linear w).
speed_profile_config_t profile_cfg(const double *t, const double *w, int n, int fs)
{
    speed_profile_config_t c{};
    c.n_points = static_cast<uint32_t>(n);
    c.fs_hz = fs;
    double theta = 0.0;
    for (int k = 0; k < n; ++k) {
        c.t_tick[k] = static_cast<uint32_t>(std::lround(t[k] * fs));
        c.omega_rad_s[k] = M(w[k]);
        c.theta_rad[k] = M(theta);
        if (k + 1 < n) {
            const double T = t[k + 1] - t[k];
            c.length_s[k] = M(T);
            c.slope_rad_s2[k] = M((w[k + 1] - w[k]) / T);
            theta += 0.5 * (w[k] + w[k + 1]) * T;
        }
    }
    return c;
}

// the reference in double: w*, dw_ref/dt (of the segment starting at or
// before t) and the integral of w* from 0
void profile_ref(const double *t, const double *w, int n, double tt, double *wr, double *ar, double *th)
{
    double theta = 0.0;
    for (int k = 0; k < n; ++k) {
        if (k == n - 1 || tt < t[k + 1]) {
            const double a = (k == n - 1) ? 0.0 : (w[k + 1] - w[k]) / (t[k + 1] - t[k]);
            const double d = tt - t[k];
            *wr = w[k] + a * d;
            *ar = a;
            *th = theta + w[k] * d + a * d * d / 2;
            return;
        }
        theta += 0.5 * (w[k] + w[k + 1]) * (t[k + 1] - t[k]);
    }
}

// Paper 001 section 5.1's benchmark: 0 -> 50 rpm at 1 s, held to 3 s, 120
// rpm at 5 s, held to 7 s, 0 at 9 s; here ending at -3 rad/s at 10 s so
// that the hold after the last corner moves.
const double kProfT[] = {0.0, 1.0, 3.0, 5.0, 7.0, 9.0, 10.0};
const double kProfW[] = {0.0, 50 * 2 * kPi / 60, 50 * 2 * kPi / 60, 120 * 2 * kPi / 60, 120 * 2 * kPi / 60, 0.0, -3.0};
constexpr int kProfN = 7;
}  // namespace

// At the corners (the segment that starts there gives dw_ref/dt), mid-ramp and
// on a sweep, against the double reference. Budgets (fixed): x = n/N is
// rounded to 2^-17 of a segment (15 us of 2 s), times w* up to 12.6 rad/s
// gives 1e-4 rad of theta, plus the roundings of theta_k and T_k x times
// the mean: 3e-4 rad; w* 1e-4 rad/s (dw x); dw_ref/dt is a stored constant,
// 1e-5. Float is far inside all three.
TEST(SpeedProfile, CornersMidRampAndAngle)
{
    const speed_profile_config_t c = profile_cfg(kProfT, kProfW, kProfN, 10000);
    speed_profile_t p;
    ASSERT_TRUE(speed_profile_init(&p, &c));
    auto check = [&](uint32_t tick) {
        speed_point_t s;
        speed_profile_eval(&p, tick, &s);
        double wr, ar, th;
        profile_ref(kProfT, kProfW, kProfN, tick / 10000.0, &wr, &ar, &th);
        EXPECT_NEAR(D(s.omega_rad_s), wr, 1e-4) << tick;
        EXPECT_NEAR(D(s.accel_rad_s2), ar, 1e-5) << tick;
        EXPECT_NEAR(D(s.theta_rad), th, 3e-4) << tick;
    };
    // corners, mid-ramps, mid-holds, the hold after the end (ticks must not decrease)
    for (uint32_t tick : {0u, 5000u, 9999u, 10000u, 20000u, 30000u, 40000u, 50000u, 60000u, 70000u, 80000u, 89999u,
                          90000u, 95000u, 100000u, 110000u, 130000u}) {
        check(tick);
    }
    // hand values: mid first ramp w* = 25 rpm, theta = (1/2) 0.5 s 25 rpm;
    // at 4 s (mid second ramp) w* = 85 rpm, dw_ref/dt = 35 rpm/s
    speed_profile_t q;
    ASSERT_TRUE(speed_profile_init(&q, &c));
    speed_point_t s;
    speed_profile_eval(&q, 5000, &s);
    EXPECT_NEAR(D(s.omega_rad_s), 25 * 2 * kPi / 60, 1e-4);
    EXPECT_NEAR(D(s.accel_rad_s2), 50 * 2 * kPi / 60, 1e-5);
    EXPECT_NEAR(D(s.theta_rad), 0.5 * 0.5 * 25 * 2 * kPi / 60, 3e-4);
    speed_profile_eval(&q, 40000, &s);
    EXPECT_NEAR(D(s.omega_rad_s), 85 * 2 * kPi / 60, 1e-4);
    EXPECT_NEAR(D(s.accel_rad_s2), 35 * 2 * kPi / 60, 1e-5);
    // theta(4 s) = 2.5 s at 50 rpm (first ramp's mean over 1 s + 2 s hold) + 1 s at 67.5 rpm
    EXPECT_NEAR(D(s.theta_rad), (0.5 * 50 + 2 * 50 + 67.5) * 2 * kPi / 60, 3e-4);
    // the last corner: w* = 0 reached, the ramp down to -3 rad/s begins
    speed_profile_eval(&q, 90000, &s);
    EXPECT_NEAR(D(s.omega_rad_s), 0.0, 1e-4);
    EXPECT_NEAR(D(s.accel_rad_s2), -3.0, 1e-5);
    // sweep from the start again (ticks must not decrease)
    ASSERT_TRUE(speed_profile_init(&p, &c));
    for (uint32_t tick = 0; tick <= 120000u; tick += 1237u) {
        check(tick);
    }
}

// Held after the last corner: w* constant, dw_ref/dt = 0, theta growing at w*
// (here -3 rad/s from 10 s); a single point is a constant speed from 0.
TEST(SpeedProfile, HeldAfterTheLastCorner)
{
    const speed_profile_config_t c = profile_cfg(kProfT, kProfW, kProfN, 10000);
    speed_profile_t p;
    ASSERT_TRUE(speed_profile_init(&p, &c));
    speed_point_t a, b;
    speed_profile_eval(&p, 100000, &a);
    speed_profile_eval(&p, 125000, &b);
    EXPECT_NEAR(D(a.omega_rad_s), -3.0, 1e-5);
    EXPECT_NEAR(D(b.omega_rad_s), -3.0, 1e-5);
    EXPECT_EQ(D(b.accel_rad_s2), 0.0);
    EXPECT_NEAR(D(b.theta_rad) - D(a.theta_rad), -3.0 * 2.5, 1e-4);
    const double t1[] = {0.0};
    const double w1[] = {7.5};
    const speed_profile_config_t one = profile_cfg(t1, w1, 1, 8000);
    ASSERT_TRUE(speed_profile_init(&p, &one));
    speed_profile_eval(&p, 4000, &a);
    EXPECT_NEAR(D(a.omega_rad_s), 7.5, 1e-5);
    EXPECT_EQ(D(a.accel_rad_s2), 0.0);
    EXPECT_NEAR(D(a.theta_rad), 7.5 * 0.5, 1e-4);
}

TEST(SpeedProfile, RejectsBadConfigurations)
{
    speed_profile_t p;
    speed_profile_config_t c = profile_cfg(kProfT, kProfW, kProfN, 10000);
    ASSERT_TRUE(speed_profile_init(&p, &c));
    c.t_tick[3] = c.t_tick[2];  // not increasing
    EXPECT_FALSE(speed_profile_init(&p, &c));
    c = profile_cfg(kProfT, kProfW, kProfN, 10000);
    c.t_tick[0] = 1;  // must start at 0
    EXPECT_FALSE(speed_profile_init(&p, &c));
    c = profile_cfg(kProfT, kProfW, kProfN, 10000);
    c.n_points = 0;
    EXPECT_FALSE(speed_profile_init(&p, &c));
    c.n_points = SPEED_PROFILE_MAX_POINTS + 1;
    EXPECT_FALSE(speed_profile_init(&p, &c));
    c = profile_cfg(kProfT, kProfW, kProfN, 10000);
    c.fs_hz = 0;
    EXPECT_FALSE(speed_profile_init(&p, &c));
}

// ---- circle fits of the start-up (startup/flux_circle_fit.h) ----
namespace {
// offers n points c + rad (cos, sin)(a0 + k da), k = 0..n-1, one sample each
void offer_arc(flux_circle_fit_t *f, double ca, double cb, double rad, double a0, double da, int n)
{
    for (int k = 0; k < n; ++k) {
        const double a = a0 + k * da;
        flux_circle_fit_add(f, ab(ca + rad * std::cos(a), cb + rad * std::sin(a)));
    }
}
}  // namespace

// Kasa's fit, c = (1/2) Cov(q)^-1 Cov(|q|^2, q), on 80 points of an arc of
// 150 degrees of a unit circle centred at (0.62, -0.45) (neither symmetric
// about an axis nor centred at 0, so no swapped index or dropped mean goes
// unseen): the centre exactly, up to rounding. Budget (fixed): each
// running mean is updated with one rounding per point, so it carries a
// few LSB; the fit multiplies those by 1/lambda_min(Cov), about 12 for
// this arc: 1e-3. Float: 1e-4.
TEST(FluxCircleFit, KasaRecoversTheCentreOfAnArc)
{
#if MC_FIXED
    const double tol = 1e-3;
#else
    const double tol = 1e-4;
#endif
    const double ca = 0.62, cb = -0.45;
    flux_circle_fit_config_t fc{1, M(0.02)};
    flux_circle_fit_t f;
    flux_circle_fit_init(&f, &fc);
    const int n = 80;
    const double arc = 150.0 * kPi / 180;
    offer_arc(&f, ca, cb, 1.0, 0.9, arc / (n - 1), n);
    EXPECT_EQ(f.n, n);
    mc_ab_t c{};
    ASSERT_TRUE(flux_circle_fit_center(&f, &c));
    EXPECT_NEAR(D(c.alpha), ca, tol);
    EXPECT_NEAR(D(c.beta), cb, tol);
    std::printf("Kasa fit, 150 degrees: centre off by %.3g\n", std::hypot(D(c.alpha) - ca, D(c.beta) - cb));
    // and a full turn (det Cov = 1/4)
    flux_circle_fit_init(&f, &fc);
    offer_arc(&f, -1.3, 0.8, 1.0, -2.0, 2 * kPi / n, n);
    ASSERT_TRUE(flux_circle_fit_center(&f, &c));
    EXPECT_NEAR(D(c.alpha), -1.3, tol);
    EXPECT_NEAR(D(c.beta), 0.8, tol);
}

// The through-origin fit, c = (1/2) M^-1 E(|p|^2 p): points p = q - q(0)
// of a circle of radius 1 through the origin, first on an arc of 2 rad,
// then scaled by 8 on an arc of 0.3 rad (the drive's probe: det M = 3.1e-3),
// turning either way. Centre c = (cos, sin)(b) for a start at angle b + pi.
// Budget: the error of the means times 1/lambda_min(M). Long arc:
// lambda_min = 0.042, so a few LSB of the means (fixed) give 1e-3; float
// 1e-4. Short arc: lambda_min = 1.6e-3 (the sagitta, 8 x 0.3^2/8 = 0.09,
// is all the fit sees across the chord), the moments E(|p|^2 p) reach 14,
// and 1/lambda_min = 610 turns the means' few LSB (fixed) into 2e-2 and
// float's 1e-6 into 1e-3 (measured 1.7e-2 and 1e-3): 5e-2 and 5e-3 of the
// scaled radius 8, i.e. the centre's direction to 6e-3 rad at worst.
TEST(FluxCircleFit, ThroughOriginRecoversTheCentreOfAnArc)
{
#if MC_FIXED
    const double tol_long = 1e-3, tol_short = 5e-2;
#else
    const double tol_long = 1e-4, tol_short = 5e-3;
#endif
    for (double dir : {1.0, -1.0}) {
        const double b = 0.8;  // centre direction
        const double ca = std::cos(b), cb = std::sin(b);
        flux_circle_fit_config_t fc{1, M(3e-3)};
        flux_circle_fit_t f;
        flux_circle_fit_init(&f, &fc);
        const int n = 100;
        offer_arc(&f, ca, cb, 1.0, b + kPi, dir * 2.0 / (n - 1), n);
        mc_ab_t c{};
        ASSERT_TRUE(flux_circle_fit_center_origin(&f, &c)) << dir;
        EXPECT_NEAR(D(c.alpha), ca, tol_long) << dir;
        EXPECT_NEAR(D(c.beta), cb, tol_long) << dir;
        // scaled by 8, an arc of 0.3 rad
        flux_circle_fit_init(&f, &fc);
        offer_arc(&f, 8 * ca, 8 * cb, 8.0, b + kPi, dir * 0.3 / (n - 1), n);
        ASSERT_TRUE(flux_circle_fit_center_origin(&f, &c)) << dir;
        EXPECT_NEAR(D(c.alpha), 8 * ca, tol_short) << dir;
        EXPECT_NEAR(D(c.beta), 8 * cb, tol_short) << dir;
        std::printf("through-origin fit, 0.3 rad scaled by 8: centre off by %.3g\n",
                    std::hypot(D(c.alpha) - 8 * ca, D(c.beta) - 8 * cb));
    }
}

// Too short an arc (det below det_min) or fewer than 3 points: both fits
// refuse and leave c as it was. The Kasa fit of a 30-degree arc (det Cov
// = 2.6e-6) against det_min = 0.02, while 150 degrees of the same circle
// (det 0.022) passes; the through-origin fit of a 0.1 rad arc scaled by 8
// (det M = 4.4e-6) against 3e-3.
TEST(FluxCircleFit, RefusesAnArcTooShort)
{
    flux_circle_fit_config_t fc{1, M(0.02)};
    flux_circle_fit_t f;
    flux_circle_fit_init(&f, &fc);
    const mc_ab_t untouched = ab(9.0, -9.0);
    mc_ab_t c = untouched;
    offer_arc(&f, 0.3, 0.2, 1.0, 0.5, 0.01, 2);
    EXPECT_FALSE(flux_circle_fit_center(&f, &c));
    EXPECT_FALSE(flux_circle_fit_center_origin(&f, &c));
    EXPECT_EQ(c.alpha, untouched.alpha);
    EXPECT_EQ(c.beta, untouched.beta);
    flux_circle_fit_init(&f, &fc);
    offer_arc(&f, 0.3, 0.2, 1.0, 0.5, (30.0 * kPi / 180) / 59, 60);
    EXPECT_FALSE(flux_circle_fit_center(&f, &c));
    EXPECT_EQ(c.alpha, untouched.alpha);
    EXPECT_EQ(c.beta, untouched.beta);
    // a longer arc of the same circle passes the same det_min
    flux_circle_fit_init(&f, &fc);
    offer_arc(&f, 0.3, 0.2, 1.0, 0.5, (150.0 * kPi / 180) / 59, 60);
    EXPECT_TRUE(flux_circle_fit_center(&f, &c));
    // through the origin
    flux_circle_fit_config_t fo{1, M(3e-3)};
    flux_circle_fit_init(&f, &fo);
    c = untouched;
    offer_arc(&f, 8 * std::cos(0.8), 8 * std::sin(0.8), 8.0, 0.8 + kPi, 0.1 / 59, 60);
    EXPECT_FALSE(flux_circle_fit_center_origin(&f, &c));
    EXPECT_EQ(c.alpha, untouched.alpha);
    EXPECT_EQ(c.beta, untouched.beta);
}

// decim = 3: only every third sample is a point (f.n counts them); the
// samples in between are far off the circle and must not enter the fit.
TEST(FluxCircleFit, TakesEveryDecimthSample)
{
    flux_circle_fit_config_t fc{3, M(0.02)};
    flux_circle_fit_t f;
    flux_circle_fit_init(&f, &fc);
    const double ca = 0.62, cb = -0.45;
    const int n = 60;
    for (int k = 0; k < n; ++k) {
        const double a = 0.9 + k * 0.05;
        flux_circle_fit_add(&f, ab(2.5, 2.5));
        flux_circle_fit_add(&f, ab(-2.0, 1.0));
        flux_circle_fit_add(&f, ab(ca + std::cos(a), cb + std::sin(a)));
    }
    EXPECT_EQ(f.n, n);
    mc_ab_t c{};
    ASSERT_TRUE(flux_circle_fit_center(&f, &c));
    EXPECT_NEAR(D(c.alpha), ca, 1e-3);
    EXPECT_NEAR(D(c.beta), cb, 1e-3);
}
