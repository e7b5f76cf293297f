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

namespace {
// The drive of sfoc_input()'s design, initialised; sfoc_sample() is one
// sample of a rotor and currents that follow their references exactly: the
// encoder reads the last sample's theta_ref (wrapped), the phases carry the
// last sample's (i_d*, i_q*) at the encoder's electrical angle, with 1 mA
// of dither (a sensor that is not stuck).
void sfoc_ready(sensored_foc_config_t* c, sensored_foc_drive_t* d)
{
    sfoc_design_input_t in = sfoc_input();
    char err[200];
    ASSERT_TRUE(sfoc_design(&in, c, err, sizeof err)) << err;
    ASSERT_TRUE(sensored_foc_drive_init(d, c));
}

drive_status_t sfoc_status(const sensored_foc_drive_t* d)
{
    drive_status_t st;
    sensored_foc_drive_ops.status(d, &st);
    return st;
}

bool sfoc_sample(sensored_foc_drive_t* d)
{
    const uint32_t k = d->tick;
    hal_sample_t s{};
    s.tick = k;
    s.n_phases = 3;
    s.v_bus_V = M(48);
    s.has_angle = true;
    const drive_status_t st = sfoc_status(d);
    const double th = std::remainder(D(st.theta_ref_rad), 2 * kPi), th_e = 3 * th;
    s.angle_rad = M(th);
    const double id = D(st.i1_ref_A), iq = D(st.i2_ref_A);
    const double ia = std::cos(th_e) * id - std::sin(th_e) * iq + 1e-3 * std::sin(0.1 * k);
    const double ib = std::sin(th_e) * id + std::cos(th_e) * iq + 1e-3 * std::cos(0.1 * k);
    s.i_A[0] = M(ia);
    s.i_A[1] = M(-0.5 * ia + 0.8660254037844386 * ib);
    s.i_A[2] = mc_neg(mc_add(s.i_A[0], s.i_A[1]));
    hal_command_t out{};
    return sensored_foc_drive_step(d, &s, &out);
}
}  // namespace

// CmdSpeed's bound is on |w|: beyond it either way refused (nothing
// changed: the reference stays at rest), within it either way taken.
// Broken once: |w| replaced by w in the check (backwards accepted).
TEST(SensoredFocDrive, SpeedCommandBoundEitherWay)
{
    static sensored_foc_config_t c;
    static sensored_foc_drive_t d;
    sfoc_ready(&c, &d);
    ASSERT_TRUE(sfoc_sample(&d));
    const double w_max = D(c.speed_cmd_max_rad_s);
    ASSERT_GT(w_max, 10.0);
    EXPECT_FALSE(sensored_foc_set_speed(&d, M(-1.01 * w_max), M(10))) << "backwards beyond the bound";
    EXPECT_FALSE(sensored_foc_set_speed(&d, M(1.01 * w_max), M(10))) << "forwards beyond the bound";
    for (int k = 0; k < 10; ++k) ASSERT_TRUE(sfoc_sample(&d));
    EXPECT_EQ(D(sfoc_status(&d).omega_ref_rad_s), 0.0) << "refused: nothing changed";
    EXPECT_TRUE(sensored_foc_set_speed(&d, M(-0.99 * w_max), M(10))) << "backwards within the bound";
    for (int k = 0; k < 10; ++k) ASSERT_TRUE(sfoc_sample(&d));
    EXPECT_LT(D(sfoc_status(&d).omega_ref_rad_s), 0.0) << "ramping backwards";
    EXPECT_TRUE(sensored_foc_set_speed(&d, M(0.99 * w_max), M(10))) << "forwards within the bound";
}

// CmdMove's acceleration bound (the header: refused when the peak
// acceleration exceeds accel_cmd_max_rad_s2), the peak taken here from
// eq. (70) itself, p(D) = 35 D^4 - 84 D^5 + 70 D^6 - 20 D^7: p''(D) =
// 420 D^2 - 1680 D^3 + 2100 D^4 - 840 D^5, whose largest |.| on [0, 1]
// (7.5132) times |d| / T^2 is the move's peak. A move over 0.2 s whose
// peak is 0.2 % above the bound is refused, 0.2 % below taken, in both
// directions (its peak speed, (35/16) |d| / T, well within its own bound).
// Broken once each: 1/T for 1/T^2, the speed's 2.1875 for 7.5132, |d| for
// d, 7.44 for 7.5132 (above the bound accepted).
TEST(SensoredFocDrive, MoveAccelerationBoundEitherWay)
{
    double peak_ddp = 0.0;
    for (int i = 0; i <= 1000000; ++i) {
        const double x = i * 1e-6;
        const double ddp = 420 * x * x - 1680 * x * x * x + 2100 * x * x * x * x - 840 * x * x * x * x * x;
        peak_ddp = std::max(peak_ddp, std::fabs(ddp));
    }
    ASSERT_NEAR(peak_ddp, 7.5132, 1e-4);
    static sensored_foc_config_t c;
    static sensored_foc_drive_t d;
    for (const double dir : {1.0, -1.0}) {
        for (const double share : {1.002, 0.998}) {  // a drive of its own each: one answer never hides the other
            sfoc_ready(&c, &d);
            ASSERT_TRUE(sfoc_sample(&d));
            const double T = 0.2, a_max = D(c.accel_cmd_max_rad_s2);
            const double dist = a_max * T * T / peak_ddp;  // the distance whose peak is a_max
            ASSERT_LT(2.1875 * dist / T, 0.5 * D(c.speed_cmd_max_rad_s)) << "the speed bound is not the one hit";
            const double from = D(sfoc_status(&d).theta_est_rad);
            EXPECT_EQ(sensored_foc_move(&d, M(from + dir * share * dist), M(T)), share < 1.0)
                << "peak " << share << " a_max (a_max " << a_max << " rad/s^2), direction " << dir;
        }
    }
}

// CmdMove is refused while the speed reference is not at rest (ramping up,
// at speed, ramping down after the stop) and taken once it rests again.
// Broken once: the check dropped (the move taken while ramping up).
TEST(SensoredFocDrive, MoveWaitsForTheSpeedReferenceAtRest)
{
    static sensored_foc_config_t c;
    static sensored_foc_drive_t d;
    sfoc_ready(&c, &d);
    ASSERT_TRUE(sfoc_sample(&d));
    ASSERT_TRUE(sensored_foc_set_speed(&d, M(5.0), M(50.0)));  // 0.1 s of ramp: 1000 samples
    auto move_by = [&](double by) {
        return sensored_foc_move(&d, M(D(sfoc_status(&d).theta_est_rad) + by), M(1.0));
    };
    for (int k = 0; k < 300; ++k) ASSERT_TRUE(sfoc_sample(&d)) << k << " fault " << int(d.sup.fault);
    ASSERT_GT(D(sfoc_status(&d).omega_ref_rad_s), 0.0);
    EXPECT_FALSE(move_by(0.1)) << "ramping up";
    for (int k = 0; k < 1000; ++k) ASSERT_TRUE(sfoc_sample(&d)) << k << " fault " << int(d.sup.fault);
    EXPECT_NEAR(D(sfoc_status(&d).omega_ref_rad_s), 5.0, 1e-3);
    EXPECT_FALSE(move_by(0.1)) << "at speed";
    ASSERT_TRUE(sensored_foc_stop(&d));
    for (int k = 0; k < 990; ++k) ASSERT_TRUE(sfoc_sample(&d)) << k << " fault " << int(d.sup.fault);
    ASSERT_GT(D(sfoc_status(&d).omega_ref_rad_s), 0.0);
    EXPECT_FALSE(move_by(0.1)) << "ramping down, " << D(sfoc_status(&d).omega_ref_rad_s) << " rad/s";
    for (int k = 0; k < 20; ++k) ASSERT_TRUE(sfoc_sample(&d)) << k << " fault " << int(d.sup.fault);
    ASSERT_EQ(D(sfoc_status(&d).omega_ref_rad_s), 0.0);
    EXPECT_TRUE(move_by(0.1)) << "at rest";
    EXPECT_EQ(d.rec.events, 0u) << "no fault on the way";
}
