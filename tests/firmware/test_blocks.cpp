// Unit tests of the paper-000 firmware blocks against cases worked out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

extern "C" {
#include "control/delay_comp.h"
#include "control/load_angle.h"
#include "control/super_twisting.h"
#include "control/twisting.h"
#include "math/frame_fg.h"
#include "math/mc_convert.h"
#include "estimators/emf_observer.h"
#include "model/motor_model.h"
#include "estimators/mech_observer.h"
#include "estimators/position_estimator.h"
#include "startup/open_loop.h"
#include "startup/rl_identification.h"
#include "trajectory/trajectory.h"
}

#include "fw_test_util.h"

using fwtest::D;
using fwtest::kPi;
using fwtest::M;

namespace {
#if MC_FIXED
constexpr double kTol = 2e-4;  // a few LSB of the fixed format plus fast-math error
#else
constexpr double kTol = 1e-5;
#endif
// The shared motor model (model/motor_model.h) of the paper-000 rig, with
// the given R, L, K, J, f_v; only the fields a test's block reads matter.
motor_model_t rig_model(double R, double L, double K, double J, double fv, double Ts)
{
    motor_model_t m{};
    m.n_p = 50;
    m.fs_hz = static_cast<int32_t>(std::lround(1.0 / Ts));
    m.R_ohm = M(R);
    m.L_H = M(L);
    m.ts_over_L_A_per_V = M(Ts / L);
    m.npL_ohm_s = M(50 * L);
    m.K_V_s = M(K);
    m.fv_Nm_s = M(fv);
    m.inv_J = M(1 / J);
    m.ts_over_J = M(Ts / J);
    m.J_over_K_A_s2 = M(J / K);
    m.fv_over_K_A_s = M(fv / K);
    return m;
}
// One sample of (29) and (71) as paper 000's estimator runs it
// (fg_estimator.h): |e|^2 and observability, then the angle and the jump
// counter.
void position_estimator_step(position_estimator_t* p, mc_t e_f_V, mc_t e_g_V, mc_t theta_r_rad, mc_t omega_r_rad_s)
{
    position_estimator_observe(p, e_f_V, e_g_V);
    position_estimator_track(p, e_f_V, e_g_V, theta_r_rad, omega_r_rad_s);
}
}  // namespace

// ---- computation-delay compensation (control/delay_comp.h) ----

// The voltage applied over the sample: v[k-1] for d Ts, then v[k].
TEST(DelayComp, AppliedMeanIsTheTimeAverageOfTheTwoCommands)
{
    const mc_ab_t v = {M(12.0), M(-4.0)};
    const mc_ab_t v_prev = {M(-6.0), M(3.0)};
    for (double d : {0.0, 0.25, 0.5, 1.0}) {
        const mc_ab_t m = delay_applied_mean(M(d), v, v_prev);
        EXPECT_NEAR(D(m.alpha), (1 - d) * 12.0 + d * -6.0, 5 * kTol) << "d = " << d;
        EXPECT_NEAR(D(m.beta), (1 - d) * -4.0 + d * 3.0, 5 * kTol) << "d = " << d;
    }
}

// The output's lead: the middle of [t_k + d Ts, t_k+1 + d Ts) is (1/2 + d) Ts
// after the sample.
TEST(DelayComp, OutputLeadIsHalfASamplePlusTheDelay)
{
    const double tol = MC_FIXED ? 1.5 / 131072 : 1e-11;  // Ts itself rounds to a Q14.17 LSB
    for (double d : {0.0, 0.25, 1.0}) {
        EXPECT_NEAR(D(delay_output_lead_s(M(d), M(1e-4))), (0.5 + d) * 1e-4, tol) << "d = " << d;
    }
}

// R(x phi) from R(phi): exact at x = 0 and 1, within the stated bound
// 0.064 phi^3 in angle in between.
TEST(DelayComp, RotationFractionWithinItsBound)
{
    for (double phi : {0.01, 0.05, 0.2}) {
        const mc_rot_t r = mc_rot_from_angle(M(phi));
        for (double x : {0.0, 0.3, 0.5, 1.0}) {
            const mc_rot_t f = delay_rot_fraction(r, M(x), M(x * x));
            const double angle = std::atan2(D(f.s), D(f.c));
            EXPECT_NEAR(angle, x * phi, 0.064 * phi * phi * phi + 5 * kTol) << "phi " << phi << " x " << x;
            EXPECT_NEAR(std::hypot(D(f.s), D(f.c)), 1.0, std::pow(phi, 4) / 24 + 5 * kTol);
        }
    }
}

// Paper 000 eq. (23) over d Ts with a constant voltage v_prev + e: the
// exact solution i(t) = u/R + (i0 - u/R) exp(-R t / L); one Euler step is
// off by |i0 - u/R| (exp(-x) - 1 + x) <= |i0 - u/R| x^2 / 2, x = R d Ts / L.
TEST(DelayComp, CurrentPredictionFollowsTheWindingEquation)
{
    const double R = 1.1, L = 4.6e-3, Ts = 1e-4;
    const double i_f = 1.5, i_g = -0.8, v_f = 10.0, v_g = -7.0, e_f = -3.0, e_g = 2.5;
    for (double d : {0.0, 0.5, 1.0}) {
        mc_t p_f, p_g;
        delay_predict_fg(M(d), M(Ts / L), M(R), M(i_f), M(i_g), M(v_f), M(v_g), M(e_f), M(e_g), &p_f, &p_g);
        const double t = d * Ts, x = R * t / L;
        const double u_f = v_f + e_f, u_g = v_g + e_g;
        const double ex_f = u_f / R + (i_f - u_f / R) * std::exp(-x);
        const double ex_g = u_g / R + (i_g - u_g / R) * std::exp(-x);
        EXPECT_NEAR(D(p_f), ex_f, std::fabs(i_f - u_f / R) * x * x / 2 + 5 * kTol) << "d = " << d;
        EXPECT_NEAR(D(p_g), ex_g, std::fabs(i_g - u_g / R) * x * x / 2 + 5 * kTol) << "d = " << d;
        // and the step itself, evaluated independently in double
        EXPECT_NEAR(D(p_f), i_f + d * Ts / L * (u_f - R * i_f), 5 * kTol);
        EXPECT_NEAR(D(p_g), i_g + d * Ts / L * (u_g - R * i_g), 5 * kTol);
    }
}

// ---- (f-g) transforms, eqs. (6)-(8) ----
TEST(FrameFg, RoundTripAndHandValues)
{
    for (double x = -7.0; x <= 7.0; x += 0.37) {
        const mc_rot_t r = mc_rot_from_angle(M(x));
        mc_t f, g, a, b;
        mc_rot_fwd(r, M(1.25), M(-0.5), &f, &g);
        mc_rot_inv(r, f, g, &a, &b);
        EXPECT_NEAR(D(a), 1.25, 5 * kTol);
        EXPECT_NEAR(D(b), -0.5, 5 * kTol);
        // eq. (6): i_f = cos i_a + sin i_b, i_g = -sin i_a + cos i_b
        EXPECT_NEAR(D(f), std::cos(x) * 1.25 + std::sin(x) * -0.5, 5 * kTol);
        EXPECT_NEAR(D(g), -std::sin(x) * 1.25 + std::cos(x) * -0.5, 5 * kTol);
    }
    // a = 1 A on phase a, frame at 90 deg electrical: i_f = 0, i_g = -1
    mc_t f, g;
    mc_rot_fwd(mc_rot_from_angle(M(kPi / 2)), M(1.0), M(0.0), &f, &g);
    EXPECT_NEAR(D(f), 0.0, 5 * kTol);
    EXPECT_NEAR(D(g), -1.0, 5 * kTol);
    // double angle
    const mc_rot_t d = mc_rot_double(mc_rot_from_angle(M(0.3)));
    EXPECT_NEAR(D(d.s), std::sin(0.6), 5 * kTol);
    EXPECT_NEAR(D(d.c), std::cos(0.6), 5 * kTol);
}

TEST(FrameFg, ElectricalAngleOfLargeMechanicalAngle)
{
    // n_p = 50: 18 rad mechanical is 900 rad electrical
    for (double th : {0.0, 0.01, 1.0, 18.0, -18.0, 123.456}) {
        const double want = std::remainder(50.0 * th, 2 * kPi);
        const double got = D(mc_elec_angle(M(th), 50));
        EXPECT_NEAR(std::remainder(got - want, 2 * kPi), 0.0, 50 * 2e-5) << th;
    }
}

// ---- trajectory, eq. (70) ----
TEST(Trajectory, BoundaryConditionsOfThePolynomial)
{
    mc_t p, dp, ddp, dddp;
    trajectory_poly7(M(0.0), &p, &dp, &ddp, &dddp);
    EXPECT_NEAR(D(p), 0.0, kTol);
    EXPECT_NEAR(D(dp), 0.0, kTol);
    EXPECT_NEAR(D(ddp), 0.0, kTol);
    EXPECT_NEAR(D(dddp), 0.0, kTol);
    trajectory_poly7(M(1.0), &p, &dp, &ddp, &dddp);
    EXPECT_NEAR(D(p), 1.0, 10 * kTol);
    EXPECT_NEAR(D(dp), 0.0, 10 * kTol);
    EXPECT_NEAR(D(ddp), 0.0, 10 * kTol);
    EXPECT_NEAR(D(dddp), 0.0, 100 * kTol);
    // symmetry: p(1/2) = 1/2, peak speed p'(1/2) = 140/64 = 2.1875
    trajectory_poly7(M(0.5), &p, &dp, &ddp, &dddp);
    EXPECT_NEAR(D(p), 0.5, 10 * kTol);
    EXPECT_NEAR(D(dp), 2.1875, 10 * kTol);
    EXPECT_NEAR(D(ddp), 0.0, 10 * kTol);
}

static trajectory_t paper_trajectory()
{
    // Section 5.4: 0 -> 18 rad in 2 s, back to 0 in 2 s, at 10 kHz
    trajectory_config_t c{};
    c.fs_hz = 10000;
    c.theta_start_rad = M(0.0);
    c.n_segments = 2;
    c.seg[0].start_tick = 0;
    c.seg[0].duration_ticks = 20000;
    c.seg[0].theta_to_rad = M(18.0);
    c.seg[1].start_tick = 20000;
    c.seg[1].duration_ticks = 20000;
    c.seg[1].theta_to_rad = M(0.0);
    trajectory_t t;
    EXPECT_TRUE(trajectory_init(&t, &c));
    return t;
}

TEST(Trajectory, ChainedSegmentsAreContinuousAndConsistent)
{
    const trajectory_t t = paper_trajectory();
    trajectory_point_t a, b;
    trajectory_eval(&t, 0, &a);
    EXPECT_NEAR(D(a.theta_rad), 0.0, kTol);
    trajectory_eval(&t, 10000, &a);  // middle of the first move
    EXPECT_NEAR(D(a.theta_rad), 9.0, 1e-3);
    EXPECT_NEAR(D(a.omega_rad_s), 18.0 / 2.0 * 2.1875, 1e-3);
    trajectory_eval(&t, 20000, &a);  // junction
    EXPECT_NEAR(D(a.theta_rad), 18.0, 1e-3);
    EXPECT_NEAR(D(a.omega_rad_s), 0.0, 1e-3);
    trajectory_eval(&t, 30000, &a);
    EXPECT_NEAR(D(a.omega_rad_s), -9.0 * 2.1875, 1e-3);
    trajectory_eval(&t, 40000, &a);
    trajectory_eval(&t, 45000, &b);  // held after the end
    EXPECT_NEAR(D(a.theta_rad), 0.0, 1e-3);
    EXPECT_NEAR(D(b.theta_rad), 0.0, 1e-3);
    EXPECT_NEAR(D(b.omega_rad_s), 0.0, kTol);
    // derivatives agree with central differences of the samples. Float:
    // +-10 samples (truncation h^2 theta(3)/6 < 1e-4, rounding ~1e-3).
    // Fixed Q14.17: D has 2^-17 resolution (15 us of a 2 s move), so the
    // samples carry up to ~2e-4 rad of time jitter: +-100 samples, and the
    // tolerances grow with the truncation error of the wider difference.
#if MC_FIXED
    const uint32_t h = 100;
    const double tol_w = 0.02, tol_a = 0.15, tol_j = 1.5;
#else
    const uint32_t h = 10;
    const double tol_w = 5e-3, tol_a = 2e-2, tol_j = 0.1;
#endif
    const double dt2 = 2.0 * h * 1e-4;
    // theta_r^(3) of (70) in double: delta/T^3 p'''(D), p''' = 840 D - 5040 D^2 + 8400 D^3 - 4200 D^4
    const auto jerk = [](uint32_t k) {
        const double Dd = (k % 20000) / 20000.0, delta = (k < 20000) ? 18.0 : -18.0, T = 2.0;
        return delta / (T * T * T) * (840 * Dd - 5040 * Dd * Dd + 8400 * Dd * Dd * Dd - 4200 * Dd * Dd * Dd * Dd);
    };
    for (uint32_t k : {1234u, 7000u, 15000u, 26000u, 38000u}) {
        trajectory_point_t m, p, c;
        trajectory_eval(&t, k - h, &m);
        trajectory_eval(&t, k + h, &p);
        trajectory_eval(&t, k, &c);
        EXPECT_NEAR((D(p.theta_rad) - D(m.theta_rad)) / dt2, D(c.omega_rad_s), tol_w) << k;
        EXPECT_NEAR((D(p.omega_rad_s) - D(m.omega_rad_s)) / dt2, D(c.accel_rad_s2), tol_a) << k;
        EXPECT_NEAR((D(p.accel_rad_s2) - D(m.accel_rad_s2)) / dt2, jerk(k), tol_j) << k;
    }
    // the position against eq. (70) evaluated in double
    for (uint32_t k = 0; k <= 40000; k += 397) {
        trajectory_point_t c;
        trajectory_eval(&t, k, &c);
        const double Dd = (k % 20000) / 20000.0, pd = Dd * Dd * Dd * Dd * (35 - 84 * Dd + 70 * Dd * Dd - 20 * Dd * Dd * Dd);
        const double want = (k < 20000) ? 18.0 * pd : (k < 40000 ? 18.0 - 18.0 * pd : 0.0);
        EXPECT_NEAR(D(c.theta_rad), want, MC_FIXED ? 3e-4 : 2e-5) << k;
    }
}

TEST(Trajectory, RejectsOverlappingOrEmptySegments)
{
    trajectory_config_t c{};
    c.fs_hz = 10000;
    c.n_segments = 2;
    c.seg[0].duration_ticks = 100;
    c.seg[1].start_tick = 50;
    c.seg[1].duration_ticks = 100;
    trajectory_t t;
    EXPECT_FALSE(trajectory_init(&t, &c));
    c.seg[1].start_tick = 100;
    c.seg[1].duration_ticks = 0;
    EXPECT_FALSE(trajectory_init(&t, &c));
}

// ---- super-twisting back-EMF observer, eqs. (23)-(28) ----
// Synthetic plant: the (f-g) model (23) with a constant rotation of the
// frame and a constant back-EMF, integrated finely between samples.
TEST(EmfObserver, ConvergesOnSyntheticBackEmf)
{
    const double L = 9e-3, R = 3.01, Ts = 1e-4;
    const double w_e = 50.0 * 10.0;           // n_p * omega_r [rad/s]
    const double ef = 1.3, eg = -2.4;         // L d_f, L d_g [V]
    const double alpha = 2e4, lambda = 400.0, l = 1000.0;
    const motor_model_t mm = rig_model(R, L, 0.27, 3.18e-4, 2.37e-3, Ts);
    const emf_observer_config_t c = fwtest::emf_config(L, Ts, alpha, lambda, l, 0.1);
    emf_observer_t o;
    emf_observer_init(&o, &c);
    double i_f = 0.0, i_g = 0.0;
    // As in the drive: a constant (f-g) command, put on the phases with the
    // mid-sample angle and held there over the sample; the observer gets the
    // command (the voltage in the mid-sample frame).
    const double vf_cmd = 2.0, vg_cmd = 5.0;
    const double c_h = std::cos(w_e * Ts / 2), s_h = std::sin(w_e * Ts / 2);
    const double vf = c_h * vf_cmd - s_h * vg_cmd, vg = s_h * vf_cmd + c_h * vg_cmd;
    const mc_rot_t half = mc_rot_from_angle(M(w_e * Ts / 2));
    double worst_late = 0.0, mean_f = 0.0, mean_g = 0.0;
    for (int k = 0; k < 3000; ++k) {
        emf_observer_correct(&o, M(i_f), M(i_g));
        if (k >= 2000) {
            worst_late = std::fmax(worst_late, std::fabs(D(o.e_f_hat_V) - ef));
            worst_late = std::fmax(worst_late, std::fabs(D(o.e_g_hat_V) - eg));
            mean_f += (D(o.e_f_hat_V) - ef) / 1000.0;
            mean_g += (D(o.e_g_hat_V) - eg) / 1000.0;
        }
        emf_observer_predict(&o, &mm, M(vf_cmd), M(vg_cmd), M(i_f), M(i_g), half);
        // plant (23): voltage constant in the phase frame (so it turns in
        // (f-g)), back-EMF constant in (f-g); RK2 on fine substeps
        const int sub = 200;
        const double h = Ts / sub;
        double uf = vf, ug = vg;
        for (int j = 0; j < sub; ++j) {
            const double a = w_e * h, cu = std::cos(a), su = std::sin(a);
            const double uf2 = cu * uf + su * ug, ug2 = -su * uf + cu * ug;
            const double k1f = w_e * i_g + (uf - R * i_f + ef) / L;
            const double k1g = -w_e * i_f + (ug - R * i_g + eg) / L;
            const double pf = i_f + h * k1f, pg = i_g + h * k1g;
            const double k2f = w_e * pg + (uf2 - R * pf + ef) / L;
            const double k2g = -w_e * pf + (ug2 - R * pg + eg) / L;
            i_f += h / 2 * (k1f + k2f);
            i_g += h / 2 * (k1g + k2g);
            uf = uf2;
            ug = ug2;
        }
    }
    // From e-hat = 0 to the true value (|e| = 2.7 V): the discrete
    // super-twisting reaches an O(Ts) band, a few steps of L alpha Ts =
    // 0.018 V, i.e. about 1 % of |e| (0.01 rad electrical).
    const double step = L * alpha * Ts;
    EXPECT_LT(worst_late, 4 * step);
    EXPECT_LT(std::fabs(mean_f), 2 * step);
    EXPECT_LT(std::fabs(mean_g), 2 * step);
    EXPECT_LT(std::fabs(D(o.err_f_A)), 2e-3);
}

// Eq. (25) of paper 000, one sample at a time, against an independent
// double-precision evaluation from the continuous equations:
//   di_hat/dt = A_fg i_hat + (v - R i)/L + d_hat + lambda|eps|^(1/2) sgn(eps) + l eps
//   dd_hat/dt = alpha sgn(eps),  eps = i - i_hat,  A_fg = n_p w_r [0 1; -1 0],
// with the frame rotation exp(Ts A_fg) = U(n_p w_r Ts) taken exactly, the
// held voltage given in the mid-sample frame, and the d_hat update (Euler,
// as voltages L d_hat) applied before the prediction that uses it. The
// firmware's state is re-read every step, so the sign decisions of both
// evaluations agree and any dropped term, wrong sign or wrong gain shows up
// as a one-step difference far above the rounding.
TEST(EmfObserver, EachStepFollowsEq25)
{
    const double L = 9e-3, R = 3.01, Ts = 1e-4, alpha = 3e4, lambda = 600.0, l = 1000.0, lpf = 0.0909;
    const motor_model_t mm = rig_model(R, L, 0.27, 3.18e-4, 2.37e-3, Ts);
    const emf_observer_config_t c = fwtest::emf_config(L, Ts, alpha, lambda, l, lpf);
    emf_observer_t o;
    emf_observer_init(&o, &c);
    unsigned seed = 12345u;
    auto rnd = [&seed](double a) {  // uniform in [-a, a], deterministic
        seed = seed * 1103515245u + 12345u;
        return a * (2.0 * ((seed >> 8) & 0xFFFF) / 65535.0 - 1.0);
    };
    double worst = 0.0;
    for (int k = 0; k < 400; ++k) {
        const double i_f = rnd(3.0), i_g = rnd(3.0), v_f = rnd(20.0), v_g = rnd(20.0);
        const double w_e = 50.0 * rnd(20.0);  // n_p w_r [rad/s]
        const double ih_f = D(o.i_f_hat_A), ih_g = D(o.i_g_hat_A);
        const double eh_f = D(o.e_f_hat_V), eh_g = D(o.e_g_hat_V);
        const double z_f = D(o.z_f_V_s), z_g = D(o.z_g_V_s);
        const double eps_f = D(mc_sub(M(i_f), o.i_f_hat_A)), eps_g = D(mc_sub(M(i_g), o.i_g_hat_A));
        auto sgn = [](double x) { return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0); };
        // d_hat' = alpha sgn(eps), as the voltage L d_hat
        const double ef1 = eh_f + L * alpha * Ts * sgn(eps_f), eg1 = eh_g + L * alpha * Ts * sgn(eps_g);
        // equivalent injection alpha sgn(eps) through the first-order filter
        const double zf1 = z_f + lpf * (L * alpha * sgn(eps_f) - z_f);
        const double zg1 = z_g + lpf * (L * alpha * sgn(eps_g) - z_g);
        // i_hat: injections, half a frame turn, the held input, the other half
        const double xf = ih_f + Ts * (lambda * std::sqrt(std::fabs(eps_f)) * sgn(eps_f) + l * eps_f);
        const double xg = ih_g + Ts * (lambda * std::sqrt(std::fabs(eps_g)) * sgn(eps_g) + l * eps_g);
        const double h = w_e * Ts / 2, ch = std::cos(h), sh = std::sin(h);
        const double yf = ch * xf + sh * xg + Ts / L * (v_f + ef1 - R * i_f);
        const double yg = -sh * xf + ch * xg + Ts / L * (v_g + eg1 - R * i_g);
        const double if1 = ch * yf + sh * yg, ig1 = -sh * yf + ch * yg;

        emf_observer_correct(&o, M(i_f), M(i_g));
        emf_observer_predict(&o, &mm, M(v_f), M(v_g), M(i_f), M(i_g), mc_rot_from_angle(M(h)));
        const double d[] = {D(o.e_f_hat_V) - ef1, D(o.e_g_hat_V) - eg1, D(o.z_f_V_s) - zf1,
                            D(o.z_g_V_s) - zg1,   D(o.i_f_hat_A) - if1, D(o.i_g_hat_A) - ig1};
        for (double x : d) {
            worst = std::fmax(worst, std::fabs(x));
        }
        ASSERT_LT(worst, 10 * kTol) << "step " << k;
    }
    std::printf("max one-step difference from eq. (25): %.3g\n", worst);
}

// ---- position and speed reconstruction, eqs. (29)-(32), (71) ----
static position_estimator_config_t pos_cfg()
{
    position_estimator_config_t c{};
    c.n_p = 50;
    c.pitch_rad = M(2 * kPi / 50);
    c.inv_K_rad_s_per_V = M(1 / 0.27);
    c.e2_min_V2 = M(0.01);
    return c;
}

TEST(PositionEstimator, AngleForBothSignsOfSpeed)
{
    const double K = 0.27;
    for (double w : {10.0, -10.0}) {
        for (double dth : {-0.05, -0.01, 0.0, 0.02, 0.06}) {
            position_estimator_t p;
            const position_estimator_config_t c = pos_cfg();
            position_estimator_init(&p, &c);
            // L d_f = K w sin(n_p dth), L d_g = -K w cos(n_p dth)  (23)
            const double ef = K * w * std::sin(50 * dth), eg = -K * w * std::cos(50 * dth);
            position_estimator_step(&p, M(ef), M(eg), M(3.0), M(w));
            EXPECT_NEAR(D(p.dtheta_est_rad), dth, 2e-5) << w << " " << dth;
            EXPECT_NEAR(D(p.cfg.inv_K_rad_s_per_V) * std::hypot(ef, eg), std::fabs(w), 1e-3);  // (30): |e|/K
            EXPECT_NEAR(D(p.theta_est_rad), 3.0 + dth, 2e-5);
        }
    }
}

TEST(PositionEstimator, JumpCounterKeepsThetaContinuousAcrossPiOverNp)
{
    const double K = 0.27, w = 5.0, pitch = 2 * kPi / 50;
    position_estimator_t p;
    const position_estimator_config_t c = pos_cfg();
    position_estimator_init(&p, &c);
    // rotor drifting ahead of the reference through 2.5 pitches and back
    double prev = 0.0;
    for (int k = 0; k <= 4000; ++k) {
        const double dth = 2.5 * pitch * std::sin(kPi * k / 4000.0);
        const double ef = K * w * std::sin(50 * dth), eg = -K * w * std::cos(50 * dth);
        position_estimator_step(&p, M(ef), M(eg), M(1.0), M(w));
        EXPECT_NEAR(D(p.theta_est_rad), 1.0 + dth, 1e-4) << k;
        EXPECT_LE(std::fabs(D(p.dtheta_est_rad)), pitch / 2 + kTol);
        if (k > 0) {
            EXPECT_LT(std::fabs(D(p.theta_est_rad) - prev), 0.01);
        }
        prev = D(p.theta_est_rad);
        if (k == 2000) {
            EXPECT_EQ(p.k, 2);  // 2.5 pitches = 2 wraps + half a pitch
        }
    }
    EXPECT_EQ(p.k, 0);
}

TEST(PositionEstimator, SpeedErrorFromRotatingBackEmf)
{
    // e rotating at n_p * dw in (f-g): the filtered injections are de/dt
    const double K = 0.27, w = 8.0, dw = 0.7, x = 0.3;
    const double Em = K * w;
    const double ef = Em * std::sin(x), eg = -Em * std::cos(x);
    const double zf = Em * 50 * dw * std::cos(x), zg = Em * 50 * dw * std::sin(x);
    position_estimator_t p;
    const position_estimator_config_t c = pos_cfg();
    position_estimator_init(&p, &c);
    position_estimator_step(&p, M(ef), M(eg), M(0), M(w - dw));
    position_estimator_speed(&p, M(ef), M(eg), M(zf), M(zg), M(w - dw));
    EXPECT_NEAR(D(p.omega_est_rad_s), w, 1e-3);  // (31)-(32)
}

TEST(PositionEstimator, BranchClosestToTheOpenLoopAngle)
{
    position_estimator_t p;
    const position_estimator_config_t c = pos_cfg();
    position_estimator_init(&p, &c);
    const double K = 0.27, w = 4.0, dth = 0.01, pitch = 2 * kPi / 50;
    position_estimator_step(&p, M(K * w * std::sin(0.5)), M(-K * w * std::cos(0.5)), M(2.0), M(w));
    position_estimator_set_branch(&p, M(2.0), M(2.0 + dth + 3 * pitch + 0.02));
    EXPECT_EQ(p.k, 3);
    EXPECT_NEAR(D(p.theta_est_rad), 2.0 + dth + 3 * pitch, 1e-4);
}

// ---- mechanical observer, eqs. (33)-(37) ----
TEST(MechObserver, EstimatesLoadAndAcceleration)
{
    const double J = 3.18e-4, K = 0.27, fv = 2.37e-3, Ts = 1e-4, Cr = 0.05;
    const motor_model_t mm = rig_model(3.01, 9e-3, K, J, fv, Ts);
    mech_observer_config_t c{};
    const double alpha = 2e4, lambda = 300, l = 100;
    c.lambda_ts = M(lambda * Ts);
    c.l_ts = M(l * Ts);
    c.alpha_Nm = M(J * alpha * Ts);
    c.tau_max_Nm = M(2.0);
    mech_observer_t m;
    mech_observer_init(&m, &c);
    double w = 5.0;
    mech_observer_reset(&m, M(w));
    for (int k = 0; k < 4000; ++k) {
        const double iq = 0.5 + 0.2 * std::sin(2 * kPi * 5 * k * Ts);
        const double acc = (K * iq - fv * w - Cr) / J;
        mech_observer_step(&m, &mm, M(w), M(iq));
        if (k > 2000) {
            EXPECT_NEAR(D(m.load_est_Nm), Cr, 3e-3) << k;
            EXPECT_NEAR(D(m.accel_est_rad_s2), acc, 10.0) << k;
        }
        w += Ts * acc;
    }
}


namespace {
// uniform in [-a, a], deterministic (a 32-bit LCG), for the step-by-step tests
struct Lcg {
    unsigned s = 12345u;
    double operator()(double a)
    {
        s = s * 1103515245u + 12345u;
        return a * (2.0 * ((s >> 8) & 0xFFFF) / 65535.0 - 1.0);
    }
};
double sgn(double x) { return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0); }
}  // namespace

// Eqs. (33)-(35) of paper 000, one sample at a time against a double
// evaluation from the continuous observer
//   w_hat' = (K i_q - f_v w_hat + tau_hat)/J + lambda |e|^(1/2) sgn(e) + l e,
//   tau_hat' = J alpha sgn(e),  e = y - w_hat,  C_r = -tau_hat,
// discretised as documented in mech_observer.h (injections at the sample,
// model term over it, load clamped to +-tau_max), from the firmware's state.
TEST(MechObserver, EachStepFollowsEq35)
{
    const double J = 3.18e-4, K = 0.27, fv = 2.37e-3, Ts = 1e-4, alpha = 2e4, lambda = 300, l = 100, tau_max = 0.5;
    const motor_model_t mm = rig_model(3.01, 9e-3, K, J, fv, Ts);
    mech_observer_config_t c{};
    c.lambda_ts = M(lambda * Ts);
    c.l_ts = M(l * Ts);
    c.alpha_Nm = M(J * alpha * Ts);
    c.tau_max_Nm = M(tau_max);
    mech_observer_t m;
    mech_observer_init(&m, &c);
    mech_observer_reset(&m, M(3.0));
    Lcg rnd;
    double worst = 0.0;
    for (int k = 0; k < 600; ++k) {
        const double y = 3.0 + rnd(2.0), iq = rnd(3.0);
        const double wh = D(m.omega_hat_rad_s), th = D(m.tau_hat_Nm);
        const double e = D(mc_sub(M(y), m.omega_hat_rad_s));
        const double tau_net = K * iq - fv * wh + th;
        const double w_est = wh + Ts * (lambda * std::sqrt(std::fabs(e)) * sgn(e) + l * e);
        const double wh1 = w_est + Ts / J * tau_net;
        const double th1 = std::fmin(tau_max, std::fmax(-tau_max, th + J * alpha * Ts * sgn(e)));
        mech_observer_step(&m, &mm, M(y), M(iq));
        const double d[] = {D(m.accel_est_rad_s2) - tau_net / J, D(m.load_est_Nm) + th, D(m.omega_est_rad_s) - w_est,
                            D(m.omega_hat_rad_s) - wh1, D(m.tau_hat_Nm) - th1};
        const double scale[] = {1.0 / J, 1.0, 1.0, 1.0, 1.0};  // acceleration: rounding of tau_net times 1/J
        for (int j = 0; j < 5; ++j) worst = std::fmax(worst, std::fabs(d[j]) / scale[j]);
        ASSERT_LT(worst, 10 * kTol) << "step " << k;
    }
}

// Super-twisting (13)-(14): u = u_1 - lambda |S|^(1/2) sgn(S), u_1' =
// -alpha sgn(S) (forward Euler), u_1 clamped to +-u1_max and held while
// the output saturates; one step at a time against double.
TEST(SuperTwisting, EachStepFollowsEq13And14)
{
    const double lambda = 5.4, alpha_ts = 0.05, u1_max = 2.0;
    super_twisting_config_t c{M(lambda), M(alpha_ts), M(u1_max)};
    super_twisting_t st;
    super_twisting_init(&st, &c);
    Lcg rnd;
    for (int k = 0; k < 400; ++k) {
        const double S = rnd(1.0);
        const bool hold = (k % 7) == 3;
        const double u1 = D(st.u1);
        const double want_u = u1 - lambda * std::sqrt(std::fabs(S)) * sgn(S);
        const double want_u1 = hold ? u1 : std::fmin(u1_max, std::fmax(-u1_max, u1 - alpha_ts * sgn(S)));
        const double u = D(super_twisting_step(&st, M(S), hold));
        ASSERT_NEAR(u, want_u, 10 * kTol) << k;
        ASSERT_NEAR(D(st.u1), want_u1, kTol) << k;
    }
}

// (29), (71), (31)-(32) for a back-EMF vector turning at random steps
// smaller than half a pitch: the angle is atan2(s e_f, -s e_g)/n_p, the jump
// counter follows every crossing of +-pi/n_p, and the speed error is the
// cross product of (31).
TEST(PositionEstimator, EachStepFollowsEq29And71And31)
{
    const double K = 0.27, np = 50.0, pitch = 2 * kPi / np;
    position_estimator_config_t c = pos_cfg();
    position_estimator_t p;
    position_estimator_init(&p, &c);
    Lcg rnd;
    double phi = 0.3, theta_r = 1.0;  // electrical angle n_p dtheta of the back-EMF
    int k_expected = 0;
    double prev = 0.0;
    for (int k = 0; k < 500; ++k) {
        const double w_r = (k < 250) ? 8.0 : -8.0, s = w_r < 0 ? -1.0 : 1.0;
        phi += rnd(1.2);
        theta_r += w_r * 1e-4;
        const double e = K * std::fabs(w_r);
        // (29) errata: n_p dtheta = atan2(s e_f, -s e_g) => e_f = s e sin, e_g = -s e cos
        const double ef = s * e * std::sin(phi), eg = -s * e * std::cos(phi);
        const double zf = rnd(3.0), zg = rnd(3.0);
        position_estimator_step(&p, M(ef), M(eg), M(theta_r), M(w_r));
        position_estimator_speed(&p, M(ef), M(eg), M(zf), M(zg), M(w_r));
        const double dth = std::atan2(std::sin(phi), std::cos(phi)) / np;
        if (k > 0 && dth - prev < -pitch / 2) ++k_expected;
        if (k > 0 && dth - prev > pitch / 2) --k_expected;
        prev = dth;
        ASSERT_TRUE(p.valid);
        ASSERT_NEAR(D(p.dtheta_est_rad), dth, kTol) << k;
        ASSERT_EQ(p.k, k_expected) << k;
        ASSERT_NEAR(D(p.theta_est_rad), theta_r + dth + pitch * k_expected, 3 * kTol) << k;
        const double dw = (zg * ef - zf * eg) / (np * (ef * ef + eg * eg));
        ASSERT_NEAR(D(p.omega_est_rad_s), w_r + dw, 20 * kTol) << k;
    }
}

// ---- super-twisting (13)-(14) and twisting (21) on integrators ----
TEST(SuperTwisting, DrivesARelativeDegreeOneSystemToZero)
{
    // S' = u + Pi(t), |Pi'| <= 2: alpha = 4, lambda = sqrt(12*2)
    super_twisting_config_t c{};
    const double Ts = 1e-3;
    c.lambda = M(std::sqrt(24.0));
    c.alpha_ts = M(4.0 * Ts);
    c.u1_max = M(100.0);
    super_twisting_t st;
    super_twisting_init(&st, &c);
    double S = 1.0, t = 0.0, late = 0.0;
    for (int k = 0; k < 10000; ++k, t += Ts) {
        const double u = D(super_twisting_step(&st, M(S), false));
        S += Ts * (u + 1.0 + std::sin(2 * t));
        if (t > 5.0) late = std::fmax(late, std::fabs(S));
    }
    EXPECT_LT(late, 5e-3);  // O(Ts) accuracy of the discrete algorithm
    // the integral term compensates the perturbation: u1 ~ -(1 + sin 2t)
    EXPECT_NEAR(D(st.u1), -(1.0 + std::sin(2 * t)), 0.1);
}

TEST(Twisting, DrivesADoubleIntegratorToZero)
{
    // S'' = w + Pi, |Pi| <= C0 = 1: (22) lambda_m > C0, lambda_M > lambda_m + 2 C0
    twisting_config_t c{};
    c.lambda_m = M(2.0);
    c.lambda_M = M(5.0);
    twisting_t tw;
    twisting_init(&tw, &c);
    EXPECT_NEAR(D(twisting_step(&tw, M(1), M(1))), -5.0, kTol);   // moving away: lambda_M
    EXPECT_NEAR(D(twisting_step(&tw, M(1), M(-1))), -2.0, kTol);  // moving back: lambda_m
    EXPECT_NEAR(D(twisting_step(&tw, M(-1), M(-1))), 5.0, kTol);
    const double Ts = 1e-4;
    double S = 0.5, Sd = 0.0, t = 0.0, late = 0.0;
    for (int k = 0; k < 100000; ++k, t += Ts) {
        const double w = D(twisting_step(&tw, M(S), M(Sd)));
        const double Pi = std::sin(3 * t);
        Sd += Ts * (w + Pi);
        S += Ts * Sd;
        if (t > 6.0) late = std::fmax(late, std::fabs(S));
    }
    EXPECT_LT(late, 1e-4);
}

// ---- open-loop voltage, eq. (68) ----
TEST(OpenLoop, VoltageOfEq68)
{
    const motor_model_t mm = rig_model(3.01, 9e-3, 0.27, 3.18e-4, 2.37e-3, 1e-4);
    open_loop_config_t c{};
    c.i_max_A = M(3.0);
    c.v_max_V = M(30.0);
    EXPECT_NEAR(D(open_loop_voltage(&c, &mm, M(0.0))), 9.03, 1e-3);  // R I_max at standstill
    const double w = 2.0;
    const double want = std::sqrt((3.01 * 3.01 + std::pow(50 * w * 9e-3, 2)) * 9.0 + std::pow(0.27 * w, 2));
    EXPECT_NEAR(D(open_loop_voltage(&c, &mm, M(-w))), want, 1e-3);
    EXPECT_NEAR(D(open_loop_voltage(&c, &mm, M(100.0))), 30.0, 1e-4);  // V_max
}

// ---- standstill R, L measurement (startup/rl_identification.h) ----
static rl_id_config_t rl_cfg(int n)
{
    rl_id_config_t c{};
    c.window_ticks = n;
    c.steady_ticks = (n * 2) / 5;
    c.R_model_ohm = M(3.01);
    c.L_fs_model_ohm = M(9e-3 / 1e-4);
    c.omega_still_rad_s = M(0.06);
    return c;
}

// exact zero-order-hold response of L di/dt = v - R i, sampled, plus noise
static bool run_rl(rl_id_t *id, double R, double L, double v, double noise, unsigned seed)
{
    const double Ts = 1e-4, a = std::exp(-R * Ts / L);
    double i = 0.0;
    unsigned x = seed;
    for (int k = 0; k < 100000; ++k) {
        x = x * 1664525u + 1013904223u;
        const double n = noise * (2.0 * (x >> 8) / 16777216.0 - 1.0);
        if (rl_id_step(id, M(i + n), M(v), M(0.0))) return true;
        i = a * i + (1.0 - a) * v / R;
    }
    return false;
}

TEST(RlIdentification, MeasuresRAndLOfAnRlCircuit)
{
    for (double scale : {0.7, 1.0, 1.3}) {
        rl_id_t id;
        const rl_id_config_t c = rl_cfg(750);
        rl_id_init(&id, &c);
        ASSERT_TRUE(run_rl(&id, 3.01 * scale, 9e-3 / scale, 9.03, 0.0, 1));
        ASSERT_EQ(id.state, RL_ID_DONE);
        EXPECT_NEAR(D(id.R_ohm), 3.01 * scale, 2e-3 * 3.01 * scale);
        EXPECT_NEAR(D(id.L_fs_ohm) * 1e-4, 9e-3 / scale, 5e-3 * 9e-3 / scale);
    }
    // with the rig's current noise (uniform +-0.03 A): R to 0.2 %, L to 3 %
    for (unsigned seed = 1; seed <= 5; ++seed) {
        rl_id_t id;
        const rl_id_config_t c = rl_cfg(750);
        rl_id_init(&id, &c);
        ASSERT_TRUE(run_rl(&id, 3.3, 8e-3, 9.03, 0.03, seed));
        ASSERT_EQ(id.state, RL_ID_DONE);
        EXPECT_NEAR(D(id.R_ohm), 3.3, 0.002 * 3.3);
        EXPECT_NEAR(D(id.L_fs_ohm) * 1e-4, 8e-3, 0.03 * 8e-3);
    }
}

TEST(RlIdentification, RejectsMotionAndImplausibleResults)
{
    rl_id_t id;
    const rl_id_config_t c = rl_cfg(750);
    rl_id_init(&id, &c);
    EXPECT_TRUE(rl_id_step(&id, M(0.1), M(9.0), M(0.5)));  // reference already moving
    EXPECT_EQ(id.state, RL_ID_REJECTED);
    EXPECT_NEAR(D(id.R_ohm), 3.01, kTol * 10);  // model kept
    rl_id_init(&id, &c);
    ASSERT_TRUE(run_rl(&id, 3.01 * 3.0, 9e-3, 9.03, 0.0, 1));  // R three times the model
    EXPECT_EQ(id.state, RL_ID_REJECTED);
    rl_id_config_t off = rl_cfg(0);
    rl_id_init(&id, &off);
    EXPECT_EQ(id.state, RL_ID_OFF);
    EXPECT_FALSE(rl_id_step(&id, M(1.0), M(9.0), M(0.0)));
}

// ---- load-angle (current-vector) law, control/load_angle.h ----
namespace {
load_angle_config_t la_config(double Is, double K, double L, double Ts)
{
    load_angle_config_t c{};
    c.i_s_A = M(Is);
    c.i_g_max_A = M(0.95 * Is);
    c.damp_A_s_per_rad = M(0.5);
    c.load_ff_max_Nm = M(0.8 * K * Is);
    c.load_slew_Nm = M(0.002);
    c.L_over_KTs_V_per_Nm = M(L / (K * Ts));
    c.kp_ohm = M(22.5);
    c.ki_ohm = M(1.125);
    return c;
}
}  // namespace

// The references: i_g,r the torque of (39) with the observed load over K,
// minus the damping; i_f,r the rest of I_s; the observed load reaches the
// references at the slew rate, and without an estimate the last one holds.
TEST(LoadAngle, CurrentVectorCarriesTheTorqueAndTheRestIsSpring)
{
    const double R = 3.01, L = 9e-3, K = 0.27, J = 3.18e-4, fv = 2.37e-3, Ts = 1e-4, Is = 3.0;
    const motor_model_t mm = rig_model(R, L, K, J, fv, Ts);
    load_angle_t la;
    const load_angle_config_t cfg = la_config(Is, K, L, Ts);
    load_angle_init(&la, &cfg);
    trajectory_point_t r{};
    r.omega_rad_s = M(10.0);
    r.accel_rad_s2 = M(100.0);
    mc_t vf, vg;
    // a load of 0.3 N m observed: 150 samples of 0.002 N m to get there
    for (int k = 0; k < 149; ++k) {
        load_angle_step(&la, &mm, &r, M(0), M(0), true, r.omega_rad_s, M(0.3), true, &vf, &vg);
    }
    EXPECT_NEAR(D(la.load_Nm), 0.298, 1e-3);
    load_angle_step(&la, &mm, &r, M(0), M(0), true, r.omega_rad_s, M(0.3), true, &vf, &vg);
    EXPECT_NEAR(D(la.load_Nm), 0.3, 1e-3);
    const double ig = (J * 100.0 + fv * 10.0 + 0.3) / K;
    EXPECT_NEAR(D(la.i_g_ref_A), ig, 2e-3);
    EXPECT_NEAR(D(la.i_f_ref_A), std::sqrt(Is * Is - ig * ig), 2e-3);
    // an observed speed 1 rad/s too high takes damp_A_s_per_rad off i_g,r
    load_angle_step(&la, &mm, &r, M(0), M(0), true, M(11.0), M(0.3), true, &vf, &vg);
    EXPECT_NEAR(D(la.i_g_ref_A), ig - 0.5, 2e-3);
    // no estimate: the load holds, the speed is not read (no damping)
    load_angle_step(&la, &mm, &r, M(0), M(0), false, M(50.0), M(-0.7), true, &vf, &vg);
    EXPECT_NEAR(D(la.load_Nm), 0.3, 1e-3);
    EXPECT_NEAR(D(la.i_g_ref_A), ig, 2e-3);
    // a torque beyond I_s: i_g,r capped at 0.95 I_s, 31 % of I_s left on f
    load_angle_step(&la, &mm, &r, M(0), M(0), true, M(-20.0), M(0.3), true, &vf, &vg);
    EXPECT_NEAR(D(la.i_g_ref_A), 0.95 * Is, 2e-3);
    EXPECT_NEAR(D(la.i_f_ref_A), Is * std::sqrt(1 - 0.95 * 0.95), 5e-3);
}

// The voltage: the reference model (38) at the references, plus the PI,
// with an estimate or without.
TEST(LoadAngle, VoltageIsTheReferenceModelPlusThePi)
{
    const double R = 3.01, L = 9e-3, K = 0.27, J = 3.18e-4, fv = 2.37e-3, Ts = 1e-4, Is = 3.0;
    const motor_model_t mm = rig_model(R, L, K, J, fv, Ts);
    const load_angle_config_t cfg = la_config(Is, K, L, Ts);
    trajectory_point_t r{};
    r.omega_rad_s = M(10.0);
    const double npLw = 50 * L * 10.0;
    for (const bool est : {true, false}) {
        load_angle_t la;
        load_angle_init(&la, &cfg);
        mc_t vf, vg;
        // currents on their references: no PI term, no integral
        load_angle_step(&la, &mm, &r, M(0), M(0), est, r.omega_rad_s, M(0), true, &vf, &vg);
        const double f = D(la.i_f_ref_A), g = D(la.i_g_ref_A);
        load_angle_step(&la, &mm, &r, M(f), M(g), est, r.omega_rad_s, M(0), false, &vf, &vg);
        EXPECT_NEAR(D(vf), R * f - npLw * g, 1e-3) << est;
        EXPECT_NEAR(D(vg), R * g + npLw * f + K * 10.0, 1e-3) << est;
        // 0.1 A short on g: kp 0.1 + the integral's first step ki 0.1
        const double gain = 1.0;
        load_angle_step(&la, &mm, &r, M(f), M(g - 0.1), est, r.omega_rad_s, M(0), false, &vf, &vg);
        EXPECT_NEAR(D(vg), R * g + npLw * f + K * 10.0 + gain * (22.5 + 1.125) * 0.1, 2e-3) << est;
        EXPECT_NEAR(D(la.int_g_V), gain * 1.125 * 0.1, 1e-4) << est;
        // saturated: the integral holds
        load_angle_step(&la, &mm, &r, M(f), M(g - 0.1), est, r.omega_rad_s, M(0), true, &vf, &vg);
        EXPECT_NEAR(D(la.int_g_V), gain * 1.125 * 0.1, 1e-4) << est;
    }
}

// The spring current is cut to what v_limit_V drives in steady state at
// the reference speed: the reference model's voltage at (i_f,r, i_g,r)
// then has that magnitude; at low speed nothing is cut.
TEST(LoadAngle, SpringCutToTheSupplyAtSpeed)
{
    const double R = 3.01, L = 9e-3, K = 0.27, J = 3.18e-4, fv = 2.37e-3, Ts = 1e-4, Is = 3.0, V = 28.5;
    const motor_model_t mm = rig_model(R, L, K, J, fv, Ts);
    load_angle_config_t cfg = la_config(Is, K, L, Ts);
    cfg.v_limit_V = M(V);
    for (const double w : {2.0, 19.7, -19.7}) {
        load_angle_t la;
        load_angle_init(&la, &cfg);
        trajectory_point_t r{};
        r.omega_rad_s = M(w);
        mc_t vf, vg;
        load_angle_step(&la, &mm, &r, M(0), M(0), true, r.omega_rad_s, M(0), true, &vf, &vg);
        const double f = D(la.i_f_ref_A), g = D(la.i_g_ref_A);
        const double ww = 50 * L * w;
        const double v = std::hypot(R * f - ww * g, R * g + ww * f + K * w);
        if (w == 2.0) {
            EXPECT_NEAR(f, std::sqrt(Is * Is - g * g), 2e-3);
            EXPECT_LT(v, V);
        } else {
            EXPECT_LT(f, 2.6) << w;   // cut from 3 A
            EXPECT_GT(f, 2.2) << w;
            EXPECT_NEAR(v, V, 0.05) << w;
        }
    }
}

// A motor model without resistance at rest asks no voltage: the cut is
// skipped (its Z^2 = R^2 + (n_p L w)^2 is 0). Without that check the fixed
// build's saturating 0/0 cut the spring to 0 A.
TEST(LoadAngle, NoResistanceAtRestStaysFinite)
{
    const double L = 9e-3, K = 0.27, J = 3.18e-4, fv = 2.37e-3, Ts = 1e-4, Is = 3.0;
    const motor_model_t mm = rig_model(0.0, L, K, J, fv, Ts);
    load_angle_config_t cfg = la_config(Is, K, L, Ts);
    cfg.v_limit_V = M(28.5);
    load_angle_t la;
    load_angle_init(&la, &cfg);
    trajectory_point_t r{};
    mc_t vf, vg;
    load_angle_step(&la, &mm, &r, M(0), M(0), true, M(0), M(0), true, &vf, &vg);
    EXPECT_TRUE(std::isfinite(D(la.i_f_ref_A)));
    EXPECT_NEAR(D(la.i_f_ref_A), Is, 2e-3);
    EXPECT_TRUE(std::isfinite(D(vf)));
    EXPECT_TRUE(std::isfinite(D(vg)));
}

// A changing load (issue 26): every step of a 1900-sample sequence against
// the law evaluated in double from the block's state before the step and
// the model's stored coefficients. The observed load ramps faster than the
// slew (0.006 N m a sample), steps beyond +-load_ff_max (+-1 N m against
// 0.648), ramps slower than the slew (followed exactly), steps by 0.2,
// goes missing (no estimate: held), then swings as a sine after a
// hand-over (load_angle_start: the amplitude ramps back to I_s). The load
// fed forward moves towards the clamped estimate by at most load_slew_Nm
// a sample and reaches both clamps; the voltage is (38) at the
// references, with L di_g,r/dt = L/(K Ts) times the fed-forward load's
// change over the sample (up to 0.67 V here), plus the PI. A dropped term,
// a wrong sign, a missing clamp or slew is a step far above the rounding.
TEST(LoadAngle, ChangingLoadEachStepFollowsEq38)
{
    const double R = 3.01, L = 9e-3, K = 0.27, J = 3.18e-4, fv = 2.37e-3, Ts = 1e-4, Is = 3.0;
    const motor_model_t mm = rig_model(R, L, K, J, fv, Ts);
    load_angle_config_t cfg = la_config(Is, K, L, Ts);
    cfg.i_amp_slew_A = M(0.01);
    load_angle_t la;
    load_angle_init(&la, &cfg);
    const double slew = D(cfg.load_slew_Nm), lmax = D(cfg.load_ff_max_Nm), LKT = D(cfg.L_over_KTs_V_per_Nm);
    const double kp = D(cfg.kp_ohm), ki = D(cfg.ki_ohm), damp = D(cfg.damp_A_s_per_rad), ig_cap = D(cfg.i_g_max_A);
    const double amp_slew = D(cfg.i_amp_slew_A), Is_m = D(cfg.i_s_A);
    const double JK = D(mm.J_over_K_A_s2), fvK = D(mm.fv_over_K_A_s), Rm = D(mm.R_ohm), npL = D(mm.npL_ohm_s),
                 Km = D(mm.K_V_s);
    // float: single-precision rounding of each operation; fixed: a few LSB
    // of Q14.17, times the gains (kp 22.5 V/A, L/(K Ts) 333 V/(N m))
    const double tol_load = MC_FIXED ? 3.0 / 131072 : 2e-7;
    const double tol_i = MC_FIXED ? 2e-4 : 5e-6;
    const double tol_v = MC_FIXED ? 4e-3 : 1e-4;
    bool hit_max = false, hit_min = false;
    double max_ldi = 0.0;
    for (int k = 0; k < 1900; ++k) {
        double est_load;
        bool est = true;
        if (k < 400) {
            est_load = 0.006 * k;                  // to 2.4 N m, beyond the clamp
        } else if (k < 1100) {
            est_load = -1.0;                       // a step beyond -load_ff_max
        } else if (k < 1300) {
            est_load = -0.6 + 0.0005 * (k - 1100); // slower than the slew
        } else if (k < 1400) {
            est_load = -0.3;                       // a step of 0.2
        } else if (k < 1500) {
            est_load = -5.0;                       // no estimate: ignored
            est = false;
        } else {
            est_load = 0.5 * std::sin(0.05 * k);
        }
        if (k == 1500) load_angle_start(&la, M(1.0));
        trajectory_point_t r{};
        r.omega_rad_s = M(5.0 * std::sin(0.004 * k));
        r.accel_rad_s2 = M(50.0 * std::cos(0.004 * k));
        const double w = D(r.omega_rad_s), a = D(r.accel_rad_s2);
        const mc_t w_est = M(w + 0.3 * std::sin(0.13 * k));
        // currents about the last references (the PI's integral stays small)
        const mc_t i_f_meas = M(D(la.i_f_ref_A) + 0.1 * std::sin(0.7 * k));
        const mc_t i_g_meas = M(D(la.i_g_ref_A) + 0.1 * std::cos(0.3 * k));
        const bool hold = k % 7 == 0;
        // the block's state before the step
        const double load0 = D(la.load_Nm), int_f0 = D(la.int_f_V), int_g0 = D(la.int_g_V), amp0 = D(la.i_amp_A);
        mc_t vf, vg;
        load_angle_step(&la, &mm, &r, i_f_meas, i_g_meas, est, w_est, M(est_load), hold, &vf, &vg);
        // the fed-forward load: towards the clamped estimate, at most the slew
        double load1 = load0;
        if (est) {
            const double target = std::fmin(std::fmax(D(M(est_load)), -lmax), lmax);
            load1 = load0 + std::fmin(std::fmax(target - load0, -slew), slew);
        }
        const double load_blk = D(la.load_Nm);
        ASSERT_NEAR(load_blk, load1, tol_load) << k;
        ASSERT_LE(std::fabs(load_blk - load0), slew + tol_load) << k;
        ASSERT_LE(std::fabs(load_blk), lmax + tol_load) << k;
        hit_max = hit_max || load_blk >= lmax - tol_load;
        hit_min = hit_min || load_blk <= -lmax + tol_load;
        // the references from it
        const double amp1 = amp0 < Is_m ? std::fmin(Is_m, amp0 + amp_slew) : amp0;
        ASSERT_NEAR(D(la.i_amp_A), amp1, tol_load) << k;
        double ig = JK * a + fvK * w + load_blk / Km;
        if (est) ig -= damp * (D(w_est) - w);
        const double cap = std::fmin(ig_cap, amp1);
        ig = std::fmin(std::fmax(ig, -cap), cap);
        const double i_f = std::sqrt(std::fmax(0.0, amp1 * amp1 - ig * ig));
        ASSERT_NEAR(D(la.i_g_ref_A), ig, tol_i) << k;
        ASSERT_NEAR(D(la.i_f_ref_A), i_f, tol_i) << k;
        // (38) at the references, L di_g,r/dt of the load's change, the PI
        const double e_f = i_f - D(i_f_meas), e_g = ig - D(i_g_meas);
        const double int_f1 = hold ? int_f0 : int_f0 + ki * e_f, int_g1 = hold ? int_g0 : int_g0 + ki * e_g;
        const double ldi = LKT * (load_blk - load0);
        max_ldi = std::fmax(max_ldi, std::fabs(ldi));
        const double want_f = Rm * i_f - npL * w * ig + int_f1 + kp * e_f;
        const double want_g = Rm * ig + npL * w * i_f + Km * w + ldi + int_g1 + kp * e_g;
        ASSERT_NEAR(D(vf), want_f, tol_v) << k;
        ASSERT_NEAR(D(vg), want_g, tol_v) << k;
    }
    EXPECT_TRUE(hit_max) << "the load never reached +load_ff_max";
    EXPECT_TRUE(hit_min) << "the load never reached -load_ff_max";
    EXPECT_GT(max_ldi, 0.6);  // L/(K Ts) x the slew: 0.67 V
}
