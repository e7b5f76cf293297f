// The sensored FOC drive's blocks (control/pi_ctrl.h,
// estimators/encoder_observer.h), its design (design/sensored_foc_design.h)
// against their equations evaluated in double, and the drive's refusals.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

extern "C" {
#include "control/foc_current.h"
#include "control/pi_ctrl.h"
#include "design/sensored_foc_design.h"
#include "drives/sensored_foc/sensored_foc_drive.h"
#include "estimators/encoder_observer.h"
#include "math/mc_convert.h"
}

#include "fw_test_util.h"

using fwtest::D;
using fwtest::kPi;
using fwtest::M;

namespace {
#if MC_FIXED
constexpr double kTol = 2e-4;
#else
constexpr double kTol = 1e-5;
#endif
}  // namespace

// u = kp e + I + ff, I += ki_ts e, evaluated in double alongside.
TEST(PiCtrl, FollowsItsEquationInsideTheLimit)
{
    pi_ctrl_t c;
    const pi_ctrl_config_t cfg{M(2.0), M(0.05)};
    ASSERT_TRUE(pi_ctrl_init(&c, &cfg));
    double I = 0.0;
    for (int k = 0; k < 20; ++k) {
        const double e = 0.3 * std::sin(0.4 * k), ff = 0.1;
        const double u = pi_ctrl_step(&c, M(e), M(ff), M(10.0));
        EXPECT_NEAR(D(u), 2.0 * e + I + ff, 5 * kTol) << "k " << k;
        I += 0.05 * e;
        EXPECT_FALSE(c.saturated);
    }
    EXPECT_NEAR(D(c.integral), I, 20 * kTol);
}

// At the limit the integral stops while the error pushes further into it,
// and integrates again as soon as the error turns.
TEST(PiCtrl, ConditionalIntegrationAtTheLimit)
{
    pi_ctrl_t c;
    const pi_ctrl_config_t cfg{M(1.0), M(0.1)};
    ASSERT_TRUE(pi_ctrl_init(&c, &cfg));
    pi_ctrl_reset(&c, M(0.5));
    const mc_t u = pi_ctrl_step(&c, M(3.0), M(0.0), M(2.0));
    EXPECT_EQ(D(u), 2.0);
    EXPECT_TRUE(c.saturated);
    EXPECT_NEAR(D(c.integral), 0.5, kTol) << "no windup into the limit";
    (void)pi_ctrl_step(&c, M(-3.0), M(0.0), M(2.0));  // saturated low, but e < 0 and u_raw < 0 ...
    (void)pi_ctrl_step(&c, M(-0.5), M(0.0), M(2.0));  // inside: integrates
    EXPECT_FALSE(c.saturated);
    EXPECT_NEAR(D(c.integral), 0.5 - 0.05, 5 * kTol);
    const pi_ctrl_config_t bad{M(-1.0), M(0.1)};
    EXPECT_FALSE(pi_ctrl_init(&c, &bad));
}

// The first sample of the current loops (integrals at 0): each axis is
// kp e plus its coupling term, v_d = kp_d (i_d* - i_d) - w_e L_q i_q and
// v_q = kp_q (i_q* - i_q) + w_e (L_d i_d + psi), evaluated in double; with
// no error the output is the coupling alone.
TEST(FocCurrent, DecouplingTermsAndTheProportionalPart)
{
    const double Ld = 3e-3, Lq = 5e-3, psi = 0.17, kp = 10.0, we = 300.0;
    foc_current_config_t cfg{};
    cfg.pi_d = {M(kp), M(0.05)};
    cfg.pi_q = {M(kp), M(0.05)};
    motor_model_t m{};
    m.L_H = m.Ld_H = M(Ld);
    m.Lq_H = M(Lq);
    m.psi_Wb = M(psi);
    for (const auto& [idr, iqr, id, iq] : {std::array<double, 4>{0.0, 2.0, 0.0, 2.0},
                                            std::array<double, 4>{-0.5, 3.0, -0.2, 2.5}}) {
        foc_current_t c;
        ASSERT_TRUE(foc_current_init(&c, &cfg, &m));
        foc_current_step(&c, &m, M(idr), M(iqr), M(id), M(iq), M(we), M(100.0));
        const mc_t vd = c.v_d_V, vq = c.v_q_V;
        EXPECT_NEAR(D(vd), kp * (idr - id) - we * Lq * iq, 50 * kTol);
        EXPECT_NEAR(D(vq), kp * (iqr - iq) + we * (Ld * id + psi), 50 * kTol);
        EXPECT_FALSE(c.saturated);
    }
    motor_model_t bad = m;
    bad.Lq_H = M(0.0);
    foc_current_t c;
    EXPECT_FALSE(foc_current_init(&c, &cfg, &bad));
}

// The circle, d first: v_d takes what it needs up to u_max, v_q the rest,
// sqrt(u_max^2 - v_d^2).
TEST(FocCurrent, VoltageCircleServesTheDAxisFirst)
{
    foc_current_config_t cfg{};
    cfg.pi_d = {M(10.0), M(0.0)};
    cfg.pi_q = {M(10.0), M(0.0)};
    motor_model_t m{};
    m.L_H = m.Ld_H = m.Lq_H = M(3e-3);
    m.psi_Wb = M(0.0);
    foc_current_t c;
    ASSERT_TRUE(foc_current_init(&c, &cfg, &m));
    foc_current_step(&c, &m, M(0.6), M(5.0), M(0.0), M(0.0), M(0.0), M(10.0));  // asks 6 V and 50 V
    const mc_t vd = c.v_d_V, vq = c.v_q_V;
    EXPECT_NEAR(D(vd), 6.0, 20 * kTol);
    EXPECT_NEAR(D(vq), 8.0, 20 * kTol);
    EXPECT_TRUE(c.saturated);
}

namespace {
encoder_observer_config_t obs_cfg(double J, double wo, double wl, double Ts)
{
    encoder_observer_config_t c{};
    c.l1_ts_scaled = M((2 * wo + wl) * Ts * 1024.0);
    c.ts_scaled = M(Ts * 1024.0);
    c.l2_ts = M((wo * wo + 2 * wo * wl) * Ts);
    c.l3_ts = M(J * wo * wo * wl * Ts);
    c.ts_over_J = M(Ts / J);
    c.inv_J = M(1 / J);
    return c;
}
}  // namespace

// A rotor accelerating against a constant load over many turns: the
// observer's angle (unwrapped across +-pi), speed and load converge to the
// truth, from a wrapped sensor angle.
TEST(EncoderObserver, TracksAngleSpeedAndLoadAcrossTurns)
{
    const double J = 0.012, Ts = 1e-4, TL = 0.8, a = 20.0;  // rad/s^2
    encoder_observer_t o;
    const encoder_observer_config_t cfg = obs_cfg(J, 2 * kPi * 50, 2 * kPi * 5, Ts);
    ASSERT_TRUE(encoder_observer_init(&o, &cfg, M(0.0)));
    double th = 0.0, w = 0.0, err_w = 0, err_l = 0, err_th = 0;
    const int n = 30000;  // 3 s: 90 rad, 14 turns
    for (int k = 0; k < n; ++k) {
        const double meas = std::remainder(th, 2 * kPi);
        encoder_observer_step(&o, M(meas), M(J * a + TL));
        th += w * Ts + 0.5 * a * Ts * Ts;
        w += a * Ts;
        if (k > n - 1000) {
            err_th = std::max(err_th, std::fabs(D(o.theta_rad) - th));
            err_w = std::max(err_w, std::fabs(D(o.omega_rad_s) - w));
            err_l = std::max(err_l, std::fabs(D(o.load_Nm) - TL));
        }
    }
    EXPECT_GT(o.turns, 10);
    EXPECT_LT(err_th, 2e-3) << "angle";
    EXPECT_LT(err_w, 0.02) << "speed";
    EXPECT_LT(err_l, 0.01) << "load";
    mc_estimate_t e;
    encoder_observer_get(&o, &e);
    EXPECT_TRUE(e.valid);
    EXPECT_NEAR(D(e.accel_rad_s2), (J * a + TL - D(o.load_Nm)) / J, 1.0);
}

namespace {
// paper 001's PMSM (sim/motors/paper001_pmsm.toml), 48 V bus, 8 A, trip 12 A
sfoc_design_input_t sfoc_input()
{
    sfoc_design_input_t in{};
    sfoc_design_defaults(&in);
    in.motor.n_phases = 3;
    in.motor.n_p = 3;
    in.motor.R_ohm = 0.225;
    in.motor.L_H = in.motor.L_q_H = 3.8e-3;
    in.motor.K_Nm_per_A = 3 * 0.17;  // n_p Phi
    in.motor.J_kgm2 = 0.012;
    in.ts_s = 1e-4;
    in.v_bus_V = 48;
    in.i_max_A = 8;
    in.i_trip_A = 12;
    return in;
}
}  // namespace

// The design's gains are the header's formulas.
TEST(SensoredFocDesign, GainsAreTheStatedFormulas)
{
    sfoc_design_input_t in = sfoc_input();
    sensored_foc_config_t c;
    char err[200];
    ASSERT_TRUE(sfoc_design(&in, &c, err, sizeof err)) << err;
    const double wc = 2 * kPi * 500, ws = 2 * kPi * 20, wo = 2 * kPi * 50, wl = 2 * kPi * 5;
    const double kt = 1.5 * 3 * 0.17;
    EXPECT_NEAR(D(c.current.pi_q.kp), 3.8e-3 * wc, 1e-3);
    EXPECT_NEAR(D(c.current.pi_q.ki_ts), 0.225 * wc * 1e-4, kTol);
    EXPECT_NEAR(D(c.kt_Nm_per_A), kt, kTol);
    EXPECT_NEAR(D(c.inv_kt_A_per_Nm), 1 / kt, kTol);
    EXPECT_NEAR(D(c.pi_speed.kp), 0.012 * ws / kt, 1e-4);
    EXPECT_NEAR(D(c.pi_speed.ki_ts), 0.012 * ws / kt * 0.25 * ws * 1e-4, kTol);
    EXPECT_NEAR(D(c.obs.l2_ts), (wo * wo + 2 * wo * wl) * 1e-4, 1e-3);
    EXPECT_NEAR(D(c.obs.l3_ts), 0.012 * wo * wo * wl * 1e-4, 1e-3);
    EXPECT_NEAR(D(c.obs.l1_ts_scaled), (2 * wo + wl) * 1e-4 * 1024, 1e-3);
    EXPECT_NEAR(D(c.speed_cmd_max_rad_s), 0.9 * 48 / std::sqrt(3.0) / (3 * 0.17), 1e-3);
    // loops that do not nest are refused, naming the field
    in.speed_bw_hz = 60;
    EXPECT_FALSE(sfoc_design(&in, &c, err, sizeof err));
    EXPECT_NE(std::string(err).find("speed_bw_hz"), std::string::npos) << err;
}

// The output's angle: with a computation delay d the voltage is turned to
// the phases at the electrical angle the rotor has in the middle of the
// interval it acts over, n_p (theta + w (1/2 + d) Ts); read back from the
// status as the angle between the stator-frame and the d-q command.
TEST(SensoredFocDrive, OutputAngleLeadsByHalfASamplePlusTheDelay)
{
    sfoc_design_input_t in = sfoc_input();
    in.compute_delay_samples = 1.0;
    in.omega_rad_s[0] = 50.0;  // the reference at the encoder's speed: the loops stay small without a plant
    static sensored_foc_config_t c;
    char err[200];
    ASSERT_TRUE(sfoc_design(&in, &c, err, sizeof err)) << err;
    static sensored_foc_drive_t d;
    ASSERT_TRUE(sensored_foc_drive_init(&d, &c));
    const double w = 50.0, Ts = 1e-4;  // rad/s: 0.005 rad per sample
    hal_sample_t s{};
    s.n_phases = 3;
    s.v_bus_V = M(48);
    s.has_angle = true;
    hal_command_t out{};
    double th = 0.0;
    for (int k = 0; k < 3000; ++k) {  // the observer settles on w
        th = std::remainder(w * Ts * k, 2 * kPi);
        s.tick = static_cast<uint32_t>(k);
        s.angle_rad = M(th);
        s.i_A[0] = M(1e-3 * std::sin(0.1 * k));  // not stuck
        s.i_A[1] = M(1e-3 * std::cos(0.1 * k));
        s.i_A[2] = mc_neg(mc_add(s.i_A[0], s.i_A[1]));
        ASSERT_TRUE(sensored_foc_drive_step(&d, &s, &out)) << "sample " << k << " fault " << int(d.sup.fault);
    }
    ASSERT_NEAR(D(d.obs.omega_rad_s), w, 0.05);
    drive_status_t st;
    sensored_foc_drive_ops.status(&d, &st);
    const double out_angle = std::atan2(D(st.v_beta_V), D(st.v_alpha_V)) - std::atan2(D(st.v2_V), D(st.v1_V));
    const double expect = 3 * (th + w * 1.5 * Ts);
    EXPECT_NEAR(std::remainder(out_angle - expect, 2 * kPi), 0.0, 2e-3)
        << "the lead is 3 x 50 rad/s x 1.5e-4 s = 0.0225 rad electrical";
}

// The drive: a sample without the encoder is bad input (latched, 0 V); a
// move is refused while the speed reference runs and beyond the design's
// speed; CmdSpeed beyond its bound is refused.
TEST(SensoredFocDrive, RefusesWhatItCannotDo)
{
    sfoc_design_input_t in = sfoc_input();
    static sensored_foc_config_t c;
    char err[200];
    ASSERT_TRUE(sfoc_design(&in, &c, err, sizeof err)) << err;
    static sensored_foc_drive_t d;
    ASSERT_TRUE(sensored_foc_drive_init(&d, &c));
    hal_sample_t s{};
    s.n_phases = 3;
    s.v_bus_V = M(48);
    s.has_angle = true;
    s.angle_rad = M(0.1);
    s.i_A[0] = M(0.001);
    hal_command_t out{};
    ASSERT_TRUE(sensored_foc_drive_step(&d, &s, &out));
    const double w_max = D(c.speed_cmd_max_rad_s);
    EXPECT_FALSE(sensored_foc_set_speed(&d, M(1.1 * w_max), M(10)));
    EXPECT_FALSE(sensored_foc_move(&d, M(1000.0), M(0.1))) << "peak speed beyond the bound";
    ASSERT_TRUE(sensored_foc_move(&d, M(1.0), M(1.0)));
    EXPECT_FALSE(sensored_foc_move(&d, M(2.0), M(1.0))) << "a move during a move";
    EXPECT_FALSE(sensored_foc_set_speed(&d, M(5.0), M(10))) << "CmdSpeed during a move";
    s.has_angle = false;
    out.v_V[0] = M(1.0);
    EXPECT_FALSE(sensored_foc_drive_step(&d, &s, &out));
    EXPECT_EQ(d.sup.fault, DRIVE_FAULT_BAD_INPUT);
    EXPECT_EQ(D(out.v_V[0]), 0.0);
    s.has_angle = true;
    EXPECT_FALSE(sensored_foc_drive_step(&d, &s, &out)) << "latched";
    EXPECT_EQ(d.rec.fault, DRIVE_FAULT_BAD_INPUT);
}
