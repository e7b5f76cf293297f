// Paper 002's drive (firmware/drives/paper002/paper002_drive.h) in closed loop with
// a d-q model of the reference IPMSM written here (RK4, 10
// sub-steps; LuGre friction with its bristle advanced exactly; the load
// pulses of 0.5 N m with raised-cosine edges; phase currents with 5 mA of
// noise, an encoder of 2^16 counts with 1e-4 rad of noise), the reference
// 0 -> 100 rad/s on [0.2, 0.4] s: the speed RMSE over [0, 1] s for SOSMC
// and HTSMC with disturbance compensation, and that compensation lowers it.
// (The simulator's plant and the 16-case study are the next step;
// this checks the composition.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "design/paper002_design.h"
#include "drives/paper002/paper002_drive.h"
#include "math/mc_convert.h"

namespace {
constexpr double kR = 0.3, kLd = 3e-3, kLq = 9e-3, kPsi = 0.04, kJ = 1e-3, kD = 5e-4, kTs = 1e-4;
constexpr int kP = 4;
constexpr double kPi = 3.14159265358979323846;
mc_t M(double x) { return mc_from_double(x); }

struct Truth {
    double id = 0, iq = 0, th = 0, w = 0, z = 0;
    double r_scale = 1.0, l_scale = 1.0; /* the motor's R and L_d, L_q against the drive's model (1: exact) */
    double lugre(double wz, double zz) const
    {
        const double g = 0.05 + 0.03 * std::exp(-(wz / 0.5) * (wz / 0.5));
        const double zdot = wz - 10.0 * std::fabs(wz) * zz / g;
        return 10.0 * zz + 0.05 * zdot + 2e-4 * wz;
    }
    void step(double ud, double uq, double load)
    {
        const int n = 10;
        const double h = kTs / n;
        for (int s = 0; s < n; ++s) {
            const double Tf = lugre(w, z);
            const double R = kR * r_scale, Ld = kLd * l_scale, Lq = kLq * l_scale;
            auto f = [&](const double* x, double* dx) {
                const double we = kP * x[3];
                dx[0] = (ud - R * x[0] + Lq * we * x[1]) / Ld;
                dx[1] = (uq - R * x[1] - Ld * we * x[0] - kPsi * we) / Lq;
                dx[2] = x[3];
                dx[3] = (1.5 * kP * (kPsi * x[1] + (Ld - Lq) * x[0] * x[1]) - kD * x[3] - load - Tf) / kJ;
            };
            double x0[4] = {id, iq, th, w}, k1[4], k2[4], k3[4], k4[4], t[4];
            f(x0, k1);
            for (int i = 0; i < 4; ++i) t[i] = x0[i] + 0.5 * h * k1[i];
            f(t, k2);
            for (int i = 0; i < 4; ++i) t[i] = x0[i] + 0.5 * h * k2[i];
            f(t, k3);
            for (int i = 0; i < 4; ++i) t[i] = x0[i] + h * k3[i];
            f(t, k4);
            const double w0 = w;
            id += h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0]);
            iq += h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1]);
            th += h / 6 * (k1[2] + 2 * k2[2] + 2 * k3[2] + k4[2]);
            w += h / 6 * (k1[3] + 2 * k2[3] + 2 * k3[3] + k4[3]);
            const double wm = 0.5 * (w0 + w);
            const double g = 0.05 + 0.03 * std::exp(-(wm / 0.5) * (wm / 0.5));
            const double a = 10.0 * std::fabs(wm) / g;
            z = (a * h < 1e-12) ? z + wm * h : wm / a + (z - wm / a) * std::exp(-a * h);
        }
    }
};

double load_at(double t)
{
    // 0.5 N m pulses 0.1 s wide every 0.2 s from 0.1 s, 20 ms raised-cosine edges
    if (t < 0.1) return 0.0;
    const double u = std::fmod(t - 0.1, 0.2);
    if (u >= 0.1) return 0.0;
    auto rc = [](double x) { return 0.5 * (1.0 - std::cos(kPi * x)); };
    if (u < 0.02) return 0.5 * rc(u / 0.02);
    if (u > 0.08) return 0.5 * rc((0.1 - u) / 0.02);
    return 0.5;
}

paper002_config_t config(p002_controller_t ctrl, bool dc)
{
    // the design module's gains for the reference set
    p002_design_input_t in;
    p002_design_defaults(&in);
    in.controller = ctrl;
    in.compensate = dc;
    paper002_config_t c{};
    char err[200];
    EXPECT_TRUE(p002_design(&in, &c, err, sizeof err)) << err;
    return c;
}

double run(p002_controller_t ctrl, bool dc, bool noise)
{
    static paper002_drive_t d;
    const paper002_config_t cfg = config(ctrl, dc);
    EXPECT_TRUE(paper002_drive_init(&d, &cfg));
    Truth tr;
    std::mt19937_64 rng(11);
    std::normal_distribution<double> n01(0.0, 1.0);
    double ss = 0.0;
    for (int k = 0; k < 10000; ++k) {
        const double t = k * kTs;
        // phases of the true d-q currents
        const double c = std::cos(kP * tr.th), s = std::sin(kP * tr.th);
        const double ia = c * tr.id - s * tr.iq, ib = s * tr.id + c * tr.iq;
        const double ph[3] = {ia, -0.5 * ia + 0.8660254037844386 * ib, -0.5 * ia - 0.8660254037844386 * ib};
        hal_sample_t in{};
        in.n_phases = 3;
        for (int j = 0; j < 3; ++j) in.i_A[j] = M(ph[j] + (noise ? 5e-3 * n01(rng) : 0.0));
        in.v_bus_V = M(48.0);
        in.has_angle = true;
        const double step = 2 * kPi / 65536.0;
        double enc = std::floor(tr.th / step) * step + (noise ? 1e-4 * n01(rng) : 0.0);
        enc -= 2 * kPi * std::floor((enc + kPi) / (2 * kPi));
        in.angle_rad = M(enc);
        hal_command_t out{};
        EXPECT_TRUE(paper002_drive_step(&d, &in, &out)) << k;
        // leg voltages to d-q on the true angle
        const double v0 = (mc_to_double(out.v_V[0]) + mc_to_double(out.v_V[1]) + mc_to_double(out.v_V[2])) / 3.0;
        const double va = mc_to_double(out.v_V[0]) - v0;
        const double vb = (mc_to_double(out.v_V[1]) - mc_to_double(out.v_V[2])) / 1.7320508075688772;
        const double wd = mc_to_double(d.last.w_d_rad_s);
        ss += (wd - tr.w) * (wd - tr.w);
        tr.step(c * va + s * vb, c * vb - s * va, load_at(t));
    }
    return std::sqrt(ss / 10000.0);
}

// One sample of the closed loop above (the same sensors and plant, noise
// on): the drive's step on the plant's phases and encoder, its voltage
// applied over the coming sample under load_at(t). Returns the step's
// result; w_d - w of the sample in *err; with v_err, the largest distance
// so far [V] between the alpha-beta voltage applied (Clarke of the legs)
// and step 6 of paper002_drive_step evaluated here in double: (u_d, u_q)
// turned by the electrical angle p (theta_hat + (1/2 + d) Ts w_hat), the
// estimate advanced to the middle of the sample the voltage acts over.
bool loop_step(paper002_drive_t* d, Truth* tr, std::mt19937_64* rng, double t, double* err, double* v_err = nullptr,
               double enc_offset_rad = 0.0)
{
    std::normal_distribution<double> n01(0.0, 1.0);
    const double c = std::cos(kP * tr->th), s = std::sin(kP * tr->th);
    const double ia = c * tr->id - s * tr->iq, ib = s * tr->id + c * tr->iq;
    const double ph[3] = {ia, -0.5 * ia + 0.8660254037844386 * ib, -0.5 * ia - 0.8660254037844386 * ib};
    hal_sample_t in{};
    in.n_phases = 3;
    for (int j = 0; j < 3; ++j) in.i_A[j] = M(ph[j] + 5e-3 * n01(*rng));
    in.v_bus_V = M(48.0);
    in.has_angle = true;
    const double step = 2 * kPi / 65536.0;
    double enc = std::floor(tr->th / step) * step + 1e-4 * n01(*rng) + enc_offset_rad;
    enc -= 2 * kPi * std::floor((enc + kPi) / (2 * kPi));
    in.angle_rad = M(enc);
    hal_command_t out{};
    const bool ok = paper002_drive_step(d, &in, &out);
    const double v0 = (mc_to_double(out.v_V[0]) + mc_to_double(out.v_V[1]) + mc_to_double(out.v_V[2])) / 3.0;
    const double va = mc_to_double(out.v_V[0]) - v0;
    const double vb = (mc_to_double(out.v_V[1]) - mc_to_double(out.v_V[2])) / 1.7320508075688772;
    *err = mc_to_double(d->last.w_d_rad_s) - tr->w;
    if (v_err != nullptr && ok) {
        const double lead = (0.5 + mc_to_double(d->cfg.compute_delay)) * kTs;
        const double e = kP * (mc_to_double(d->last.theta_hat_rad) + lead * mc_to_double(d->last.w_hat_rad_s));
        const double ud = mc_to_double(d->last.u_d_V), uq = mc_to_double(d->last.u_q_V);
        const double ea = va - (std::cos(e) * ud - std::sin(e) * uq), eb = vb - (std::sin(e) * ud + std::cos(e) * uq);
        *v_err = std::max(*v_err, std::hypot(ea, eb));
    }
    tr->step(c * va + s * vb, c * vb - s * va, load_at(t));
    return ok;
}
}  // namespace

TEST(Paper002Drive, TracksTheReferenceWithCompensation)
{
    // the design's gains (paper002_design.c) on the reference set
#if MC_FIXED
    GTEST_SKIP() << "float only";
#endif
    const double s_dc = run(P002_SOSMC, true, true), s_no = run(P002_SOSMC, false, true);
    const double h_dc = run(P002_HTSMC, true, true), h_no = run(P002_HTSMC, false, true);
    const double s_dc_nn = run(P002_SOSMC, true, false), h_dc_nn = run(P002_HTSMC, true, false);
    std::printf("speed RMSE [rad/s], w(0) = 0: SOSMC dc %.4g / no dc %.4g / dc without noise %.4g; HTSMC dc %.4g / "
                "no dc %.4g / dc without noise %.4g\n",
                s_dc, s_no, s_dc_nn, h_dc, h_no, h_dc_nn);
    // measured with the searched design (paper002_design.c): SOSMC 0.0497 /
    // 0.0638 / 0.0265, HTSMC 0.0502 / 0.0920 / 0.0263 rad/s. This model's
    // encoder has 2^16 counts (the reference scenario 2^20: its step is a
    // noise as large as the stated one, hence the noise-free 0.026 here and
    // 0.0149 in motorsim). The 0.04 with noise is not met (0.046 in
    // motorsim, docs/paper002.md); this test holds the composition, the
    // trend and the level reached, with a 20 % margin.
    EXPECT_LT(s_dc, s_no);
    EXPECT_LT(h_dc, h_no);
    EXPECT_LT(s_dc, 0.06);
    EXPECT_LT(h_dc, 0.06);
    EXPECT_LT(s_dc_nn, 0.033);
    EXPECT_LT(h_dc_nn, 0.033);
}

// Bad input is refused at design time with the key named; the fixed-point
// build refuses the design altogether (the EKF needs float).
TEST(Paper002Design, RefusesBadInputNamingTheKey)
{
    p002_design_input_t in;
    p002_design_defaults(&in);
    paper002_config_t c{};
    char err[200] = "";
#if MC_FIXED
    EXPECT_FALSE(p002_design(&in, &c, err, sizeof err));
    EXPECT_NE(std::string(err).find("needs the float build"), std::string::npos) << err;
#else
    EXPECT_TRUE(p002_design(&in, &c, err, sizeof err)) << err;
    in.motor.L_q_H = 0.0;
    EXPECT_FALSE(p002_design(&in, &c, err, sizeof err));
    EXPECT_NE(std::string(err).find("motor.L_q_H"), std::string::npos) << err;
    p002_design_defaults(&in);
    in.encoder_counts = 0;
    EXPECT_FALSE(p002_design(&in, &c, err, sizeof err));
    EXPECT_NE(std::string(err).find("encoder.counts_per_turn"), std::string::npos) << err;
    // the trip at or above the current limit: equal accepted, below refused
    p002_design_defaults(&in);
    in.i_trip_A = in.i_max_A;
    EXPECT_TRUE(p002_design(&in, &c, err, sizeof err)) << err;
    in.i_trip_A = 0.9 * in.i_max_A;
    EXPECT_FALSE(p002_design(&in, &c, err, sizeof err));
    EXPECT_NE(std::string(err).find("limits.i_trip_A"), std::string::npos) << err;
    // the torque limit of both speed laws: K_t i_max with K_t = 3/2 p psi
    // (10) at i_d = 0 (the reluctance torque's share left as margin), and
    // HTSMC's nu_max = M_max / J
    p002_design_defaults(&in);
    ASSERT_TRUE(p002_design(&in, &c, err, sizeof err)) << err;
    const double m_max = 1.5 * in.motor.n_p * motor_design_phi_Wb(&in.motor) * in.i_max_A;
    EXPECT_NEAR(mc_to_double(c.sosmc.M_max_Nm), m_max, 1e-6 * m_max);
    EXPECT_NEAR(mc_to_double(c.htsmc.M_max_Nm), m_max, 1e-6 * m_max);
    EXPECT_NEAR(mc_to_double(c.htsmc.nu_max), m_max / in.motor.J_kgm2, 1e-6 * m_max / in.motor.J_kgm2);
    // the user's Q and R: not positive definite is refused with the entry named
    p002_design_defaults(&in);
    const double q[EKF_N] = {1e-6, 2e-6, 1e-12, 1e-3, 4e-3};
    std::copy(q, q + EKF_N, in.ekf_q);
    in.ekf_q[4] = -4e-3;
    EXPECT_FALSE(p002_design(&in, &c, err, sizeof err));
    EXPECT_NE(std::string(err).find("paper002.ekf_q[4]: must be > 0"), std::string::npos) << err;
    in.ekf_q[4] = 0.0;  // a partial Q is no Q: refused, not mixed with the design's
    EXPECT_FALSE(p002_design(&in, &c, err, sizeof err));
    EXPECT_NE(std::string(err).find("paper002.ekf_q[4]"), std::string::npos) << err;
    p002_design_defaults(&in);
    in.ekf_r[2] = std::nan("");
    EXPECT_FALSE(p002_design(&in, &c, err, sizeof err));
    EXPECT_NE(std::string(err).find("paper002.ekf_r[0]"), std::string::npos) << err;
    // given, they replace the design's (and all 0 keeps the design's)
    p002_design_defaults(&in);
    paper002_config_t designed{};
    ASSERT_TRUE(p002_design(&in, &designed, err, sizeof err)) << err;
    std::copy(q, q + EKF_N, in.ekf_q);
    const double r[EKF_M] = {3e-5, 4e-5, 2e-8};
    std::copy(r, r + EKF_M, in.ekf_r);
    ASSERT_TRUE(p002_design(&in, &c, err, sizeof err)) << err;
    for (int i = 0; i < EKF_N; ++i) {
        EXPECT_EQ(c.ekf.q[i], static_cast<float>(q[i])) << i;
    }
    for (int i = 0; i < EKF_M; ++i) {
        EXPECT_EQ(c.ekf.r[i], static_cast<float>(r[i])) << i;
    }
    EXPECT_NE(designed.ekf.q[0], c.ekf.q[0]);
#endif
}

// In reverse and through zero, by the command path of the CAN node
// (drives/paper002/paper002_ops.c: CmdSpeed -> paper002_drive_set_speed, CmdStop ->
// paper002_drive_stop), on the loop above with the 0.5 N m pulses (which
// oppose positive speed, so at w < 0 they drive the rotor and the drive
// brakes on each). After the first sample (the bus measured): a speed
// whose back-EMF p psi |w| passes 0.9 x 48/sqrt(3) V (155.9 rad/s) is
// refused either way, -150 and +150 accepted; then +50 rad/s at 500
// rad/s^2 (0.1875 s), at 0.32 s a reversal to -50 rad/s (0.375 s, through
// zero at 0.5075 s on the pulse's rising edge), held (a pulse at
// 0.7-0.8 s), at 0.9 s stopped at the same ramp (to 0 at 1.0875 s, under
// a pulse), held at 0 to 1.2 s. No fault (the stall band is 10 + 0.5 |w_d|,
// rad/s), and the speed tracked.
TEST(Paper002Drive, ReversesThroughZeroOnCommand)
{
#if MC_FIXED
    GTEST_SKIP() << "float only";
#endif
    // measured: RMSE of w_d - w 0.0491 rad/s over the run, 0.0476 over the
    // reversal (0.32-0.695 s), 0.0451 in the hold at -50 (0.695-0.9 s); max
    // |w_d - w| after 50 ms 0.212 rad/s; w -50.04 at the stop, min -50.11,
    // final -0.047 rad/s. Bounds 1.5 times the run's (the windows' 1.6),
    // the speeds within 1 rad/s.
    constexpr double kRmseBound = 0.075, kErrMaxBound = 0.32;
    static paper002_drive_t d;
    const paper002_config_t cfg = config(P002_SOSMC, true);
    ASSERT_TRUE(paper002_drive_init(&d, &cfg));
    Truth tr;
    std::mt19937_64 rng(11);
    double err = 0.0;
    ASSERT_TRUE(loop_step(&d, &tr, &rng, 0.0, &err));
    // the back-EMF limit on |w|: the same either way
    EXPECT_FALSE(paper002_drive_set_speed(&d, M(160.0), M(500.0)));
    EXPECT_FALSE(paper002_drive_set_speed(&d, M(-160.0), M(500.0)));
    EXPECT_TRUE(paper002_drive_set_speed(&d, M(150.0), M(500.0)));
    EXPECT_TRUE(paper002_drive_set_speed(&d, M(-150.0), M(500.0)));
    // the duration from |dw|: -150 from where the reference is (still 0)
    // at 500 rad/s^2 takes 1.875 x 150 / 500 = 0.5625 s
    mc_t w, dw;
    speed_poly_eval(&d.reference, d.tick + 2812, &w, &dw);
    EXPECT_NEAR(mc_to_double(w), -75.0, 0.2);
    EXPECT_NEAR(mc_to_double(dw), -500.0, 2.0);
    ASSERT_TRUE(paper002_drive_set_speed(&d, M(50.0), M(500.0)));
    const int n = 12000;
    double ss = 0.0, err_max = 0.0, ss_rev = 0.0, ss_neg = 0.0, w_min = 0.0, w_at_stop = 0.0, v_err_neg = 0.0;
    int n_rev = 0, n_neg = 0, fault_k = -1;
    for (int k = 1; k < n; ++k) {
        const double t = k * kTs;
        if (k == 3200) {
            EXPECT_TRUE(paper002_drive_set_speed(&d, M(-50.0), M(500.0)));
        }
        if (k == 9000) {
            w_at_stop = tr.w;
            EXPECT_TRUE(paper002_drive_stop(&d));
        }
        if (!loop_step(&d, &tr, &rng, t, &err, t >= 0.695 && t < 0.9 ? &v_err_neg : nullptr) && fault_k < 0) {
            fault_k = k;
        }
        ss += err * err;
        if (t >= 0.05) err_max = std::max(err_max, std::fabs(err));
        if (t >= 0.32 && t < 0.695) {
            ss_rev += err * err;
            n_rev += 1;
        }
        if (t >= 0.695 && t < 0.9) {
            ss_neg += err * err;
            n_neg += 1;
        }
        w_min = std::min(w_min, tr.w);
    }
    const double rmse = std::sqrt(ss / (n - 1)), rmse_rev = std::sqrt(ss_rev / n_rev), rmse_neg = std::sqrt(ss_neg / n_neg);
    std::printf("reverse on command: RMSE %.4g rad/s (reversal %.4g, hold at -50 %.4g), max |w_d - w| after 50 ms "
                "%.4g, min w %.4g, w at the stop %.4g, final w %.4g rad/s\n",
                rmse, rmse_rev, rmse_neg, err_max, w_min, w_at_stop, tr.w);
    EXPECT_EQ(fault_k, -1) << "fault " << d.sup.fault << " at t = " << fault_k * kTs << " s";
    EXPECT_EQ(d.sup.fault, DRIVE_FAULT_NONE);
    EXPECT_NEAR(mc_to_double(d.last.w_d_rad_s), 0.0, 1e-6);
    EXPECT_LT(rmse, kRmseBound);
    EXPECT_LT(rmse_rev, kRmseBound);
    EXPECT_LT(rmse_neg, kRmseBound);
    EXPECT_LT(err_max, kErrMaxBound);
    EXPECT_NEAR(w_at_stop, -50.0, 1.0);
    EXPECT_GT(w_min, -51.0);
    EXPECT_NEAR(tr.w, 0.0, 1.0);
    // the output's angle in the hold at -50 rad/s: the estimate advanced
    // by (1/2 + d) Ts w_hat, backwards there. Float rounding of |u| <= 28 V
    // turned by a float sin/cos: 8.7e-6 V measured; a lead of the wrong
    // sign at -50 rad/s, p = 4, Ts = 1e-4 s turns the voltage by 0.02 rad
    // (mutant p002_output_lead_forward_only: 0.45 V measured).
    std::printf("output angle in the hold at -50 rad/s: largest error %.3g V\n", v_err_neg);
    EXPECT_LT(v_err_neg, 1e-3);
}

// An encoder whose reading turns to garbage (a broken line: any angle,
// uniform over a turn, each sample) while the rotor turns at +-50 rad/s:
// the angle's innovation is then beyond los_theta (0.02 rad) on nearly
// every sample, of either sign at random, and the drive trips with
// LOSS_OF_SYNC (drives/paper002/paper002_drive.h) within a few los_ticks (5 ms).
TEST(Paper002Drive, GarbageEncoderIsALossOfSyncEitherWay)
{
#if MC_FIXED
    GTEST_SKIP() << "float only";
#endif
    for (const double w_set : {50.0, -50.0}) {
        static paper002_drive_t d;
        const paper002_config_t cfg = config(P002_SOSMC, true);
        ASSERT_TRUE(paper002_drive_init(&d, &cfg));
        Truth tr;
        std::mt19937_64 rng(5), garbage(9);
        std::uniform_real_distribution<double> turn(-kPi, kPi);
        double err = 0.0;
        ASSERT_TRUE(loop_step(&d, &tr, &rng, 0.0, &err));
        ASSERT_TRUE(paper002_drive_set_speed(&d, M(w_set), M(500.0)));
        const int k_bad = 3000;
        int trip = -1;
        for (int k = 1; k < 6000 && trip < 0; ++k) {
            if (!loop_step(&d, &tr, &rng, k * kTs, &err, nullptr, k >= k_bad ? turn(garbage) : 0.0)) trip = k;
        }
        std::printf("w %+g rad/s: tripped %d samples after the encoder failed, fault %d\n", w_set, trip - k_bad,
                    static_cast<int>(d.sup.fault));
        // measured: 49 samples at +50 (the first los_ticks = 50 run), 97 at
        // -50; bound 4 runs (20 ms). The drive then holds 0 V.
        EXPECT_EQ(d.sup.fault, DRIVE_FAULT_LOSS_OF_SYNC) << "w " << w_set;
        EXPECT_GE(trip - k_bad, cfg.los_ticks - 1) << "w " << w_set;
        EXPECT_LE(trip - k_bad, 4 * cfg.los_ticks) << "w " << w_set;
        hal_sample_t in{};
        in.n_phases = 3;
        in.v_bus_V = M(48.0);
        in.has_angle = true;
        hal_command_t out{};
        out.v_V[0] = out.v_V[1] = out.v_V[2] = M(1.0);
        EXPECT_FALSE(paper002_drive_step(&d, &in, &out));
        for (int j = 0; j < 3; ++j) EXPECT_EQ(mc_to_double(out.v_V[j]), 0.0);
    }
}

// The drive runs under the guard every drive runs under (supervisor/
// guard.h): with the design's reactions (SAFE) the loss of the estimate of
// a garbage encoder latches the supervisor's FAULT, freezes the flight
// recorder at the trip's sample with the samples before it, and the
// interface's status and recorder show it; clear-faults restarts the
// drive and is refused without a fault. With REPORT for that fault the
// same loss is counted and frozen in the recorder while the drive goes on.
TEST(Paper002Drive, FaultsGoThroughTheGuard)
{
#if MC_FIXED
    GTEST_SKIP() << "float only";
#endif
    for (const bool report : {false, true}) {
        static paper002_drive_t d;
        paper002_config_t cfg = config(P002_SOSMC, true);
        if (report) {
            cfg.reaction[DRIVE_FAULT_LOSS_OF_SYNC] = static_cast<uint8_t>(FAULT_REACT_REPORT);
        }
        ASSERT_TRUE(paper002_drive_init(&d, &cfg));
        drive_t h{&paper002_drive_ops, &d};
        EXPECT_EQ(d.sup.state, SUP_STATE_CLOSED_LOOP);
        drive_cmd_t clear{};
        clear.kind = DRIVE_CMD_CLEAR_FAULTS;
        EXPECT_EQ(drive_command(&h, &clear), DRIVE_REFUSE_NO_FAULT);
        Truth tr;
        std::mt19937_64 rng(5), garbage(9);
        std::uniform_real_distribution<double> turn(-kPi, kPi);
        double err = 0.0;
        const flight_recorder_t* r = drive_recorder(&h);
        ASSERT_NE(r, nullptr);
        ASSERT_TRUE(loop_step(&d, &tr, &rng, 0.0, &err));
        // the drive's own refusal, under the interface's: a running drive is not restarted
        EXPECT_FALSE(paper002_drive_clear_fault(&d));
        EXPECT_EQ(d.tick, 1u);
        const int k_bad = 3000;
        int trip = -1, found = -1;
        for (int k = 1; k < 6000 && trip < 0 && found < 0; ++k) {
            const bool ok = loop_step(&d, &tr, &rng, k * kTs, &err, nullptr, k >= k_bad ? turn(garbage) : 0.0);
            if (!ok) trip = k;
            if (r->events > 0) found = k;
        }
        ASSERT_GE(found, k_bad) << (report ? "REPORT" : "SAFE");
        EXPECT_TRUE(r->frozen);
        EXPECT_EQ(r->fault, DRIVE_FAULT_LOSS_OF_SYNC);
        EXPECT_EQ(r->fault_tick, static_cast<uint32_t>(found));
        EXPECT_EQ(r->events, 1u);
        // the ring holds the samples up to the one before the fault's
        ASSERT_EQ(flight_recorder_count(r), FLIGHT_RECORDER_DEPTH);
        EXPECT_EQ(flight_recorder_get(r, FLIGHT_RECORDER_DEPTH - 1u)->tick, static_cast<uint32_t>(found - 1));
        EXPECT_EQ(flight_recorder_get(r, 0)->tick, static_cast<uint32_t>(found) - FLIGHT_RECORDER_DEPTH);
        drive_status_t s{};
        drive_status(&h, &s);
        EXPECT_EQ(s.first_fault, static_cast<uint8_t>(DRIVE_FAULT_LOSS_OF_SYNC));
        EXPECT_EQ(s.fault_events, 1u);
        if (report) {
            EXPECT_EQ(trip, -1) << "REPORT: the drive goes on";
            EXPECT_EQ(d.sup.state, SUP_STATE_CLOSED_LOOP);
            EXPECT_EQ(s.fault_code, static_cast<uint8_t>(DRIVE_FAULT_NONE));
            EXPECT_EQ(drive_command(&h, &clear), DRIVE_REFUSE_NO_FAULT);
        } else {
            EXPECT_EQ(trip, found);
            EXPECT_EQ(d.sup.state, SUP_STATE_FAULT);
            EXPECT_EQ(d.sup.fault, DRIVE_FAULT_LOSS_OF_SYNC);
            EXPECT_EQ(s.state, static_cast<uint8_t>(SUP_STATE_FAULT));
            EXPECT_EQ(s.mode, static_cast<uint8_t>(DRIVE_MODE_FAULT));
            EXPECT_FALSE(s.enabled);
            EXPECT_EQ(drive_command(&h, &clear), DRIVE_REFUSE_NONE);
            EXPECT_EQ(d.sup.state, SUP_STATE_CLOSED_LOOP);
            EXPECT_FALSE(r->frozen);
            EXPECT_EQ(r->events, 0u);
        }
    }
}

// An estimator for the test below: the encoder's
// (estimators/encoder_angle.h), which also records the applied mean the
// drive holds its estimator at (the drive runs any estimator of the
// interface, estimators/estimator.h).
static mc_ab_t g_held_mean;
static void probe_hold(void*, mc_ab_t u_mean_ab_V, mc_ab_t)
{
    g_held_mean = u_mean_ab_V;
}
static const estimator_ops_t kHoldProbe = [] {
    estimator_ops_t o = encoder_angle_ops;
    o.hold = probe_hold;
    return o;
}();

// With a computation delay of d = 1 sample (an MCU's PWM): the output's
// angle is the estimate advanced by (1/2 + d) Ts w_hat (step 6, checked
// in double by loop_step), and the voltage the observers integrate over
// the coming sample is the mean (1 - d) u + d u_prev of this command and
// the last (step 7; the estimator is held at it, in alpha-beta), on the
// loop at -50 rad/s.
TEST(Paper002Drive, ComputationDelayLeadAndAppliedMean)
{
#if MC_FIXED
    GTEST_SKIP() << "float only";
#endif
    p002_design_input_t in;
    p002_design_defaults(&in);
    in.compute_delay_samples = 1.0;
    paper002_config_t cfg{};
    char err[200];
    ASSERT_TRUE(p002_design(&in, &cfg, err, sizeof err)) << err;
    static paper002_drive_t d;
    ASSERT_TRUE(paper002_drive_init(&d, &cfg));
    d.est = &kHoldProbe; /* the encoder, with the voltage it is held at recorded */
    Truth tr;
    std::mt19937_64 rng(3);
    double err_w = 0.0, v_err = 0.0, mean_err = 0.0;
    ASSERT_TRUE(loop_step(&d, &tr, &rng, 0.0, &err_w));
    ASSERT_TRUE(paper002_drive_set_speed(&d, M(-50.0), M(500.0)));
    mc_ab_t prev = d.u_ab_prev_V;
    for (int k = 1; k < 3000; ++k) {
        ASSERT_TRUE(loop_step(&d, &tr, &rng, k * kTs, &err_w, k > 2000 ? &v_err : nullptr)) << k;
        // step 7: held = (1 - d) u + d u_prev with d = 1: the previous command
        const mc_ab_t u = d.u_ab_prev_V;
        mean_err = std::max(mean_err, std::hypot(mc_to_double(g_held_mean.alpha) - mc_to_double(prev.alpha),
                                                 mc_to_double(g_held_mean.beta) - mc_to_double(prev.beta)));
        prev = u;
    }
    std::printf("delay 1: output angle error %.3g V, applied mean error %.3g V, final |w_d - w| %.3g rad/s\n", v_err,
                mean_err, std::fabs(err_w));
    EXPECT_LT(v_err, 1e-3);
    EXPECT_LT(mean_err, 1e-4);
    EXPECT_LT(std::fabs(err_w), 0.5);
}

// A sample without the encoder's angle (what the STM32F405 backend hands
// once its encoder erred: a step beyond the fastest motor, an index away
// from the count; hal/backends/stm32f405/encoder_tim.h) is bad input: the
// drive latches BAD_INPUT and holds 0 V from that sample on.
TEST(Paper002Drive, SampleWithoutTheEncodersAngleIsBadInput)
{
#if MC_FIXED
    GTEST_SKIP() << "float only";
#endif
    static paper002_drive_t d;
    const paper002_config_t cfg = config(P002_SOSMC, true);
    ASSERT_TRUE(paper002_drive_init(&d, &cfg));
    Truth tr;
    std::mt19937_64 rng(3);
    double err = 0.0;
    for (int k = 0; k < 100; ++k) ASSERT_TRUE(loop_step(&d, &tr, &rng, k * kTs, &err)) << k;
    hal_sample_t in{};
    in.n_phases = 3;
    in.v_bus_V = M(48.0);
    in.has_angle = false;
    hal_command_t out{};
    out.v_V[0] = M(1.0);
    EXPECT_FALSE(paper002_drive_step(&d, &in, &out));
    EXPECT_EQ(d.sup.state, SUP_STATE_FAULT);
    EXPECT_EQ(d.sup.fault, DRIVE_FAULT_BAD_INPUT);
    for (int j = 0; j < 3; ++j) EXPECT_EQ(mc_to_double(out.v_V[j]), 0.0);
    in.has_angle = true;
    EXPECT_FALSE(paper002_drive_step(&d, &in, &out)) << "latched: the angle back does not restart it";
}

// Loss of lock (supervisor/lock_monitor.h) in the sensorless variant only.
// With the design's thresholds (design/lock_monitor_design.c) the flux
// observer's residual on this plant (the exact model: a lock that holds)
// stays far below the bound through the start, the ramp and the load
// pulses. With a bound of nothing (k = 0, floor 1 uV: any residual is
// beyond it) and a persistence of 20 samples, the flux variant raises
// LOSS_OF_LOCK on the 20th sample and it goes through the guard like the
// drive's other faults (SAFE: latched, 0 V; REPORT: recorded, the drive
// goes on); the encoder variant with the same configuration never calls
// the monitor (its angle is measured).
TEST(Paper002Drive, LossOfLockOnlyWithTheFluxAngle)
{
#if MC_FIXED
    GTEST_SKIP() << "float only";
#endif
    p002_design_input_t in;
    p002_design_defaults(&in);
    in.angle_source = P002_ANGLE_FLUX;
    paper002_config_t flux_cfg{};
    char err[200];
    ASSERT_TRUE(p002_design(&in, &flux_cfg, err, sizeof err)) << err;
    ASSERT_GT(flux_cfg.lock.ticks, 0);
    static paper002_drive_t d;
    {
        // the designed thresholds: no alarm, the residual under a tenth of the bound
        ASSERT_TRUE(paper002_drive_init(&d, &flux_cfg));
        Truth tr;
        std::mt19937_64 rng(7);
        double e = 0.0, worst = 0.0;
        for (int k = 0; k < 7000; ++k) {
            ASSERT_TRUE(loop_step(&d, &tr, &rng, k * kTs, &e)) << k;
            worst = std::max(worst, mc_to_double(d.lock.residual_V) / mc_to_double(d.lock.bound_V));
        }
        std::printf("flux variant, designed lock thresholds: largest residual/bound %.3g, final |w_d - w| %.3g\n",
                    worst, std::fabs(e));
        EXPECT_GT(worst, 0.0) << "the monitor ran";
        EXPECT_LT(worst, 0.1);
        EXPECT_EQ(d.rec.events, 0u);
    }
    lock_monitor_config_t none = flux_cfg.lock;
    none.k_speed_V_s = none.k_speed_cur_H = none.k_cur_ohm = MC_ZERO;
    none.floor_V = M(1e-6);
    none.ticks = 20;
    for (const bool report : {false, true}) {
        paper002_config_t cfg = flux_cfg;
        cfg.lock = none;
        if (report) cfg.reaction[DRIVE_FAULT_LOSS_OF_LOCK] = static_cast<uint8_t>(FAULT_REACT_REPORT);
        ASSERT_TRUE(paper002_drive_init(&d, &cfg));
        Truth tr;
        std::mt19937_64 rng(7);
        double e = 0.0;
        int trip = -1;
        for (int k = 0; k < 200 && trip < 0; ++k) {
            if (!loop_step(&d, &tr, &rng, k * kTs, &e)) trip = k;
            if (report && d.rec.events > 0) break;
        }
        EXPECT_TRUE(d.rec.frozen) << (report ? "REPORT" : "SAFE");
        EXPECT_EQ(d.rec.fault, DRIVE_FAULT_LOSS_OF_LOCK);
        EXPECT_EQ(d.rec.fault_tick, 19u) << "the 20th sample beyond the bound";
        if (report) {
            EXPECT_EQ(trip, -1);
            EXPECT_EQ(d.sup.state, SUP_STATE_CLOSED_LOOP);
        } else {
            EXPECT_EQ(trip, 19);
            EXPECT_EQ(d.sup.state, SUP_STATE_FAULT);
            EXPECT_EQ(d.sup.fault, DRIVE_FAULT_LOSS_OF_LOCK);
        }
    }
    // the encoder variant: the same lock configuration is never consulted
    paper002_config_t enc = config(P002_SOSMC, true);
    enc.lock = none;
    ASSERT_TRUE(paper002_drive_init(&d, &enc));
    Truth tr;
    std::mt19937_64 rng(7);
    double e = 0.0;
    for (int k = 0; k < 2000; ++k) ASSERT_TRUE(loop_step(&d, &tr, &rng, k * kTs, &e)) << k;
    EXPECT_EQ(d.rec.events, 0u);
    EXPECT_EQ(d.lock.run.run, 0);
}

// The angle-innovation criterion of the sensorless variant's loss of lock
// (supervisor/lock_monitor.h, LOCK_CRIT_ANGLE_INNOVATION; thresholds in
// design/paper002_design.c): on the exact model (a lock that holds) the
// EKF's angle innovation stays within its bound (the count never moves);
// on a motor whose R is 30 % above and L 15 % below the drive's model (the
// issue's case (a)) the cascade chatters from the start and the drive
// latches LOSS_OF_LOCK by this criterion within 20 ms, with the count at
// its limit and the flux residual's run short of its persistence; with the
// criterion off (innov_limit 0) the same run goes on without a fault (the
// flux residual alone does not see this loss).
TEST(Paper002Drive, LossOfLockByTheAngleInnovation)
{
#if MC_FIXED
    GTEST_SKIP() << "float only";
#endif
    p002_design_input_t in;
    p002_design_defaults(&in);
    in.angle_source = P002_ANGLE_FLUX;
    paper002_config_t cfg{};
    char err[200];
    ASSERT_TRUE(p002_design(&in, &cfg, err, sizeof err)) << err;
    ASSERT_EQ(cfg.lock.innov_limit, 1000);
    static paper002_drive_t d;
    {
        ASSERT_TRUE(paper002_drive_init(&d, &cfg));
        Truth tr;
        std::mt19937_64 rng(7);
        double e = 0.0, worst = 0.0;
        int32_t count = 0;
        for (int k = 0; k < 7000; ++k) {
            ASSERT_TRUE(loop_step(&d, &tr, &rng, k * kTs, &e)) << k;
            if (k >= 10) worst = std::max(worst, mc_to_double(d.lock.innov_ratio));
            count = std::max(count, d.lock.innov_count);
        }
        std::printf("exact model: largest nu^2/bound^2 after the first ms %.3g, largest count %d\n", worst, count);
        EXPECT_GT(worst, 0.0) << "the criterion ran";
        EXPECT_LT(worst, 1.0);
        EXPECT_LT(count, 100) << "a tenth of the limit";
        EXPECT_EQ(d.rec.events, 0u);
    }
    for (const bool on : {true, false}) {
        paper002_config_t c = cfg;
        if (!on) c.lock.innov_limit = 0;
        ASSERT_TRUE(paper002_drive_init(&d, &c));
        Truth tr;
        tr.r_scale = 1.3;
        tr.l_scale = 0.85;
        std::mt19937_64 rng(7);
        double e = 0.0;
        int trip = -1;
        for (int k = 0; k < 2000 && trip < 0; ++k) {
            if (!loop_step(&d, &tr, &rng, k * kTs, &e)) trip = k;
        }
        std::printf("R +30 %%, L -15 %%, angle-innovation criterion %s: fault at sample %d (%s)\n", on ? "on" : "off",
                    trip, trip >= 0 ? "loss of lock" : "none");
        if (on) {
            ASSERT_GE(trip, 49) << "not before 50 samples beyond the bound";
            EXPECT_LT(trip, 200) << "within 20 ms";
            EXPECT_EQ(d.sup.fault, DRIVE_FAULT_LOSS_OF_LOCK);
            EXPECT_EQ(d.lock.innov_count, cfg.lock.innov_limit);
            EXPECT_LT(d.lock.run.run, cfg.lock.ticks) << "the flux residual did not fire";
        } else {
            EXPECT_EQ(trip, -1);
            EXPECT_EQ(d.rec.events, 0u);
        }
    }
}

// The reference set's design with the injection and the start from an
// unknown angle (theta0_rad told, and unused by it).
static bool find_angle_design(p002_design_input_t* in, paper002_config_t* c, char* err, size_t n, double theta0_rad)
{
    p002_design_defaults(in);
    in->angle_source = P002_ANGLE_HFI;
    in->hfi_find_angle = true;
    in->theta0_rad = theta0_rad;
    return p002_design(in, c, err, n);
}

// The start from an unknown angle (paper002_drive.h, hfi_find_angle): the
// design fills the lock time and the polarity test (0.1 s: 1000 samples;
// 20 V pulses), the drive starts in LOCK with the injection on; a
// configuration without a lock time or a test is bad input, refused at
// init with DRIVE_FAULT_BAD_INPUT latched.
TEST(Paper002Drive, FindAngleStartIsDesignedAndBadConfigurationRefused)
{
#if MC_FIXED
    GTEST_SKIP() << "float only";
#endif
    p002_design_input_t in;
    paper002_config_t c{};
    char err[200];
    ASSERT_TRUE(find_angle_design(&in, &c, err, sizeof err, 0.7)) << err;
    EXPECT_TRUE(c.hfi_find_angle);
    EXPECT_EQ(c.hfi_lock_ticks, 1000);
    EXPECT_NEAR(mc_to_double(c.magpol.v_p_V), 20.0, 1e-6);
    EXPECT_GE(c.magpol.n_pulse, 1);
    EXPECT_EQ(mc_to_double(c.flux_theta0_rad), 0.0) << "the start angle is not told";
    static paper002_drive_t d;
    ASSERT_TRUE(paper002_drive_init(&d, &c));
    EXPECT_TRUE(d.starting);
    EXPECT_EQ(d.est_state.hfi.phase, HFI_ANGLE_LOCK);
    EXPECT_TRUE(d.est_state.hfi.hfi.on);
    paper002_config_t bad = c;
    bad.hfi_lock_ticks = 0;
    EXPECT_FALSE(paper002_drive_init(&d, &bad));
    EXPECT_EQ(d.sup.fault, DRIVE_FAULT_BAD_INPUT);
    bad = c;
    bad.magpol.n_pulse = 0;
    EXPECT_FALSE(paper002_drive_init(&d, &bad));
    EXPECT_EQ(d.sup.fault, DRIVE_FAULT_BAD_INPUT);
    // the encoder's variant ignores the flag: it starts in RUN
    in.angle_source = P002_ANGLE_ENCODER;
    ASSERT_TRUE(p002_design(&in, &c, err, sizeof err)) << err;
    EXPECT_FALSE(c.hfi_find_angle);
    ASSERT_TRUE(paper002_drive_init(&d, &c));
    EXPECT_FALSE(d.starting);
}

// The lock's check before the polarity test (paper002_drive.h, LOCK): on
// the salient R-L plant above (L_q = 3 L_d, no magnet bias, 5 mA of
// noise) with the rotor 1.5 rad (electrical) off the drive's guess, near
// the loop's unstable quadrature (pi/2), the full 0.1 s lock reaches the d
// axis (mean (H1) amplitude 1.00) and the drive goes on to the test; 3 ms
// of lock leave the PLL near where it started (the amplitude cos^2 e +
// sin^2 e / 3: 0.37 over the last 8 samples) and the drive refuses: fault
// 12 latched at the lock's last sample, 0 V out, no test run.
// Broken once: the comparison inverted (both cases fail).
TEST(Paper002Drive, FindAngleRefusesAnUnlockedStart)
{
#if MC_FIXED
    GTEST_SKIP() << "float only";
#endif
    p002_design_input_t in;
    paper002_config_t c{};
    char err[200];
    ASSERT_TRUE(find_angle_design(&in, &c, err, sizeof err, 0.0)) << err;
    EXPECT_EQ(c.hfi_lock_window, 250);
    EXPECT_NEAR(mc_to_double(c.hfi_lock_amp_min), (1.0 + kLd / kLq) / 2.0, 1e-6);
    for (const int ticks : {1000, 30}) {
        paper002_config_t cc = c;
        cc.hfi_lock_ticks = ticks;
        cc.hfi_lock_window = (ticks + 3) / 4;
        static paper002_drive_t d;
        ASSERT_TRUE(paper002_drive_init(&d, &cc));
        Truth tr;
        tr.th = 1.5 / kP; /* the drive guesses 0 */
        std::mt19937_64 rng(5);
        double e = 0.0;
        int trip = -1;
        for (int k = 0; k < ticks + 5 && trip < 0; ++k) {
            if (!loop_step(&d, &tr, &rng, 0.0, &e)) trip = k;
        }
        const double amp = mc_to_double(d.est_state.hfi.lock_amp);
        std::printf("lock of %d samples: mean (H1) amplitude %.3f, %s\n", ticks, amp,
                    trip >= 0 ? "refused" : "on to the test");
        if (ticks == 1000) {
            EXPECT_EQ(trip, -1);
            EXPECT_GT(amp, 0.9);
            EXPECT_EQ(d.est_state.hfi.phase, HFI_ANGLE_LOCK) << "in the rest before the test";
            EXPECT_EQ(d.sup.state, SUP_STATE_CLOSED_LOOP);
        } else {
            EXPECT_EQ(trip, ticks - 1);
            EXPECT_LT(amp, mc_to_double(cc.hfi_lock_amp_min));
            EXPECT_EQ(d.sup.fault, DRIVE_FAULT_LOSS_OF_LOCK);
            EXPECT_EQ(d.est_state.hfi.magpol.state, MAGPOL_IDLE) << "no test run";
        }
    }
}

// The injection's hand-over to the flux observer (paper002_drive.h, HFI):
// the angle the EKF is given is theta_hfi + w wrap(theta_flux -
// theta_hfi), the blend across the short arc between the two. On the
// plant above (no load, the start angle known), the reference 0 -> 22
// rad/s on [0.05, 0.25] s holds the EKF's speed inside the blend's band
// (15 .. 30 rad/s: w about 0.47) for 1.75 s, the electrical angle turning
// through +-pi 14 times a second; at a crossing some samples have the two
// angles on either side of +-pi (the raw difference beyond pi, the wrapped
// one small: 16 to 23 samples in 2 s with seeds 1, 2, 3, 5, 8). In each such sample
// the blended angle (read back from the measurement the EKF was given:
// p theta_meas wrapped, theta_offset being a multiple of 2 pi/p) lies on
// the short arc between them, where its formula puts it; the long way
// round is a jump of about pi in one sample. Through the drive: the blend
// runs in estimators/hfi_angle.c; the two angles and w are read from its
// state after the step (the estimator's hfi.theta_e_rad, fa.flux.unit, weight), which
// nothing changes after the blend within the step.
// Broken once: the wrap of theta_flux - theta_hfi dropped (3.1 rad off).
TEST(Paper002Drive, HfiBlendAcrossPlusMinusPiTakesTheShortArc)
{
#if MC_FIXED
    GTEST_SKIP() << "float only";
#endif
    p002_design_input_t in;
    p002_design_defaults(&in);
    in.angle_source = P002_ANGLE_HFI;
    in.t0_s = 0.05;
    in.t1_s = 0.25;
    in.w1_rad_s = 22.0;
    paper002_config_t c{};
    char err[200];
    ASSERT_TRUE(p002_design(&in, &c, err, sizeof err)) << err;
    ASSERT_LT(mc_to_double(c.hfi_blend_lo_rad_s), 22.0);
    ASSERT_GT(mc_to_double(c.hfi_blend_hi_rad_s), 22.0);
    static paper002_drive_t d;
    ASSERT_TRUE(paper002_drive_init(&d, &c));
    Truth tr;
    std::mt19937_64 rng(3);
    double e = 0.0, worst_formula = 0.0, worst_arc = -1.0, w_min = 1.0, w_max = 0.0;
    int straddles = 0, blended = 0;
    for (int k = 0; k < 20000; ++k) {
        ASSERT_TRUE(loop_step(&d, &tr, &rng, 0.0, &e)) << k << " fault " << int(d.sup.fault);
        const double w = mc_to_double(d.est_state.hfi.weight);
        if (!(w > 0.0 && w < 1.0)) continue;
        blended += 1;
        w_min = std::min(w_min, w);
        w_max = std::max(w_max, w);
        const double th_h = mc_to_double(d.est_state.hfi.hfi.theta_e_rad);
        const double th_f = std::atan2(mc_to_double(d.est_state.hfi.fa.flux.unit.s), mc_to_double(d.est_state.hfi.fa.flux.unit.c));
        const double th = std::remainder(kP * mc_to_double(d.last.theta_meas_rad), 2 * kPi);
        const double gap = std::remainder(th_f - th_h, 2 * kPi);  // the short arc from th_h to th_f
        worst_formula = std::max(worst_formula, std::fabs(std::remainder(th - (th_h + w * gap), 2 * kPi)));
        if (std::fabs(th_f - th_h) > kPi) {
            straddles += 1;
            // on the short arc: no farther from either end than the ends are apart
            const double arc = std::max(std::fabs(std::remainder(th - th_h, 2 * kPi)),
                                        std::fabs(std::remainder(th - th_f, 2 * kPi))) - std::fabs(gap);
            worst_arc = std::max(worst_arc, arc);
        }
    }
    std::printf("blend: %d samples with 0 < w < 1 (w %.3f .. %.3f), %d with the angles on either side of +-pi; "
                "largest distance from the formula %.3g rad, beyond the short arc %.3g rad; final |w_d - w| %.3g\n",
                blended, w_min, w_max, straddles, worst_formula, worst_arc, std::fabs(e));
    EXPECT_GT(blended, 5000);
    EXPECT_GE(straddles, 10) << "the case this test is for";
    EXPECT_LT(worst_formula, 1e-4);
    EXPECT_LT(worst_arc, 1e-4);
}

// A refused configuration names its first offending field (the drive
// interface's config_problem, drives/drive.h), through the interface's
// operation too, and init refuses exactly that: FAULT, BAD_INPUT latched.
// The blocks with their own check (the EKF, the speed laws, the current
// control, the dead-time compensation) are named by their part of the
// configuration. Broken once: the check of hfi_lock_window against
// hfi_lock_ticks left out of paper002_config_problem (its case failed: no
// problem named).
TEST(Paper002Drive, ConfigProblemNamesTheFirstOffendingField)
{
#if MC_FIXED
    GTEST_SKIP() << "float only";
#endif
    ASSERT_NE(paper002_drive_ops.config_problem, nullptr);
    const paper002_config_t enc = config(P002_SOSMC, true);
    p002_design_input_t in;
    paper002_config_t find{};
    char err[200];
    ASSERT_TRUE(find_angle_design(&in, &find, err, sizeof err, 0.0)) << err;
    const paper002_config_t* goods[] = {&enc, &find};
    for (const paper002_config_t* good : goods) {
        EXPECT_EQ(paper002_config_problem(good), nullptr) << paper002_config_problem(good);
        EXPECT_EQ(paper002_drive_ops.config_problem(good), nullptr);
    }
    static paper002_drive_t d;
    struct Case {
        const char* field;
        bool find_angle;
        void (*breaks)(paper002_config_t*);
    };
    const Case cases[] = {
        {"ekf.q", false, [](paper002_config_t* c) { c->ekf.q[3] = MC_ZERO; }},
        {"sosmc", false, [](paper002_config_t* c) { c->sosmc.alpha_0 = MC_ZERO; }},
        {"htsmc", false, [](paper002_config_t* c) { c->htsmc.rho = M(0.75); }},
        {"ibcc", false, [](paper002_config_t* c) { c->ibcc.ref_alpha = M(1.5); }},
        {"i_trip_A", false, [](paper002_config_t* c) { c->i_trip_A = MC_ZERO; }},
        {"los_ticks", false, [](paper002_config_t* c) { c->los_ticks = 0; }},
        {"stall_floor_rad_s", false, [](paper002_config_t* c) { c->stall_floor_rad_s = MC_ZERO; }},
        {"compute_delay", false, [](paper002_config_t* c) { c->compute_delay = M(-0.5); }},
        {"deadtime", false, [](paper002_config_t* c) { c->deadtime.r_drop_ohm = M(-1.0); }},
        {"hfi_blend_lo_rad_s", true, [](paper002_config_t* c) { c->hfi_blend_hi_rad_s = c->hfi_blend_lo_rad_s; }},
        {"hfi_hold_gain_per_s", true, [](paper002_config_t* c) { c->hfi_hold_gain_per_s = M(-1.0); }},
        {"hfi_lock_ticks", true, [](paper002_config_t* c) { c->hfi_lock_ticks = 0; }},
        {"hfi_lock_window", true, [](paper002_config_t* c) { c->hfi_lock_window = c->hfi_lock_ticks + 1; }},
        {"magpol.n_pulse", true, [](paper002_config_t* c) { c->magpol.n_pulse = 0; }},
    };
    for (const Case& k : cases) {
        paper002_config_t bad = k.find_angle ? find : enc;
        k.breaks(&bad);
        const char* why = paper002_config_problem(&bad);
        ASSERT_NE(why, nullptr) << k.field;
        EXPECT_EQ(std::string(why).rfind(k.field, 0), 0u) << k.field << ": " << why;
        EXPECT_EQ(paper002_drive_ops.config_problem(&bad), why) << k.field;
        EXPECT_FALSE(paper002_drive_init(&d, &bad)) << k.field;
        EXPECT_EQ(d.sup.state, SUP_STATE_FAULT) << k.field;
        EXPECT_EQ(d.sup.fault, DRIVE_FAULT_BAD_INPUT) << k.field;
    }
    // the start's checks only when it finds the angle
    paper002_config_t no_find = enc;
    no_find.hfi_lock_ticks = 0;
    EXPECT_EQ(paper002_config_problem(&no_find), nullptr);
}

// Disabled is not a fault (drives/drive.h: false only in FAULT, which the
// programs answer with hal_safe_state()): the step returns true with 0 V
// on every leg and counts the sample; in FAULT it returns false. Through
// the interface as the programs hold it. Broken once: the step's disabled
// branch returning false again (the disabled steps failed).
TEST(Paper002Drive, DisabledStepsAreZeroVoltsButNotAFault)
{
#if MC_FIXED
    GTEST_SKIP() << "float only";
#endif
    static paper002_drive_t d;
    const paper002_config_t cfg = config(P002_SOSMC, true);
    ASSERT_TRUE(paper002_drive_init(&d, &cfg));
    drive_t h{&paper002_drive_ops, &d};
    Truth tr;
    std::mt19937_64 rng(3);
    double err = 0.0;
    for (int k = 0; k < 100; ++k) {
        ASSERT_TRUE(loop_step(&d, &tr, &rng, k * kTs, &err)) << k;
    }
    drive_cmd_t off{};
    off.kind = DRIVE_CMD_ENABLE;
    off.enable = false;
    ASSERT_EQ(drive_command(&h, &off), DRIVE_REFUSE_NONE);
    hal_sample_t in{};
    in.n_phases = 3;
    in.v_bus_V = M(48.0);
    in.has_angle = true;
    for (int k = 0; k < 5; ++k) {
        hal_command_t out{};
        for (int j = 0; j < 3; ++j) out.v_V[j] = M(99.0);  // must be overwritten
        EXPECT_TRUE(drive_step(&h, &in, &out)) << "disabled, sample " << k;
        EXPECT_EQ(out.n_phases, 3);
        for (int j = 0; j < 3; ++j) EXPECT_EQ(mc_to_double(out.v_V[j]), 0.0) << "leg " << j;
        EXPECT_EQ(d.tick, static_cast<uint32_t>(101 + k));
    }
    drive_status_t s{};
    drive_status(&h, &s);
    EXPECT_FALSE(s.enabled);
    EXPECT_EQ(s.state, static_cast<uint8_t>(SUP_STATE_CLOSED_LOOP));
    EXPECT_EQ(d.rec.events, 0u);
    // enabled again it runs as at power-up; a sample without the encoder's
    // angle is then a fault: false, and false again while in FAULT
    off.enable = true;
    ASSERT_EQ(drive_command(&h, &off), DRIVE_REFUSE_NONE);
    in.has_angle = false;
    hal_command_t out{};
    EXPECT_FALSE(drive_step(&h, &in, &out));
    EXPECT_EQ(d.sup.state, SUP_STATE_FAULT);
    EXPECT_FALSE(drive_step(&h, &in, &out));
    for (int j = 0; j < 3; ++j) EXPECT_EQ(mc_to_double(out.v_V[j]), 0.0) << "leg " << j;
}

// The estimate's angle is unwrapped (estimators/estimate.h): mechanical,
// continuous over turns, where the EKF keeps its own in [-pi, pi). On the
// closed loop above, the reference to 100 rad/s (the rotor turns about
// 3.3 times in 0.5 s): the estimate never steps by more than a sample's
// travel, follows the plant's unwrapped angle (as sampled) within 5 mrad, and equals
// the EKF's angle plus whole turns. Broken once: the estimate's angle
// without the turns (the EKF's, wrapped): the steps of 2 pi and the
// distance to the plant's angle failed.
TEST(Paper002Drive, EstimateAngleIsUnwrapped)
{
#if MC_FIXED
    GTEST_SKIP() << "float only";
#endif
    static paper002_drive_t d;
    const paper002_config_t cfg = config(P002_SOSMC, true);
    ASSERT_TRUE(paper002_drive_init(&d, &cfg));
    drive_t h{&paper002_drive_ops, &d};
    Truth tr;
    std::mt19937_64 rng(7);
    double err = 0.0, prev = 0.0, step_max = 0.0, dist_max = 0.0, turn_err_max = 0.0;
    for (int k = 0; k < 5000; ++k) {
        ASSERT_TRUE(loop_step(&d, &tr, &rng, k * kTs, &err)) << k;
        mc_estimate_t e{};
        drive_estimate(&h, &e);
        const double th = mc_to_double(e.theta_rad);
        if (k > 0) step_max = std::max(step_max, std::fabs(th - prev));
        prev = th;
        // loop_step has advanced the plant by the sample: back to the sampled angle
        dist_max = std::max(dist_max, std::fabs(th - (tr.th - tr.w * kTs)));
        const double turns = (th - mc_to_double(d.last.theta_hat_rad)) / (2 * kPi);
        turn_err_max = std::max(turn_err_max, std::fabs(turns - std::round(turns)));
    }
    std::printf("estimate: %.3f rad at the end (plant %.3f), largest step %.4f rad, largest distance %.4f rad\n",
                prev, tr.th, step_max, dist_max);
    EXPECT_GT(tr.th, 3 * 2 * kPi) << "over three turns";
    EXPECT_LT(step_max, 0.02);  // 100 rad/s x 1e-4 s = 0.01 rad
    EXPECT_LT(dist_max, 0.005);
    EXPECT_LT(turn_err_max, 1e-5);
}
