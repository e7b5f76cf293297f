// Paper 002's control blocks on the reference motor (p 4, R 0.3,
// L_d 3 mH, L_q 9 mH, psi 0.04 Wb, J 1e-3, d 5e-4): MTPA and its torque
// inversion (firmware/control/mtpa.h), the inversion-based current control
// (ibcc.h), SOSMC (sosmc.h) and HTSMC (htsmc.h).
#include <gtest/gtest.h>

#include <cmath>

#include "control/htsmc.h"
#include "control/ibcc.h"
#include "control/mtpa.h"
#include "control/sosmc.h"
#include "math/mc_convert.h"
#include "trajectory/speed_poly.h"

namespace {
mc_t M(double x) { return mc_from_double(x); }
double D(mc_t x) { return mc_to_double(x); }
constexpr double kR = 0.3, kLd = 3e-3, kLq = 9e-3, kPsi = 0.04, kJ = 1e-3, kD = 5e-4, kTs = 1e-4;
constexpr int kP = 4;
#if MC_FIXED
constexpr double kTol = 2e-3;  // Q14.17 arithmetic
#else
constexpr double kTol = 1e-4;
#endif
mtpa_config_t mtpa_cfg() { return mtpa_config_t{M(20.0)}; }
// ibcc_step with its two voltages in two variables
void ibcc_run(ibcc_t* s, const ibcc_config_t* c, const motor_model_t* m, mc_t i_dd, mc_t i_qd, mc_t i_d, mc_t i_q,
              mc_t w, mc_t u_max, mc_t* u_d, mc_t* u_q)
{
    ibcc_out_t o;
    ibcc_step(s, c, m, i_dd, i_qd, i_d, i_q, w, u_max, &o);
    *u_d = o.u_d_V;
    *u_q = o.u_q_V;
}
// The motor as the drive's one model (model/motor_model.h) holds it: the
// fields these blocks read.
motor_model_t motor(double Ld, double Lq, double ts = kTs)
{
    motor_model_t m{};
    m.n_p = kP;
    m.fs_hz = static_cast<int32_t>(std::lround(1.0 / ts));
    m.ts_s = M(ts);
    m.R_ohm = M(kR);
    m.L_H = m.Ld_H = M(Ld);
    m.Lq_H = M(Lq);
    m.psi_Wb = M(kPsi);
    m.J_kgm2 = M(kJ);
    m.fv_Nm_s = M(kD);
    return m;
}
}  // namespace

// The torque asked for, with i_d of (18), and no smaller current gives it:
// a scan of i_d at the same torque finds no smaller |i|.
TEST(Mtpa, InvertsTheTorqueOnTheMtpaCurve)
{
    const mtpa_config_t c = mtpa_cfg();
    const motor_model_t mm = motor(kLd, kLq);
    for (double Md : {0.05, 0.5, 1.0, 2.0, -0.7}) {
        mtpa_out_t o;
        mtpa_step(&c, &mm, M(Md), &o);
        const double id = D(o.i_d_A), iq = D(o.i_q_A);
        EXPECT_NEAR(1.5 * kP * (kPsi * iq + (kLd - kLq) * id * iq), Md, kTol * (1.0 + std::fabs(Md))) << Md;
        const double a = kPsi / (kLd - kLq);
        EXPECT_NEAR(id, -a / 2.0 - 0.5 * std::sqrt(a * a + 4.0 * iq * iq), 10 * kTol) << Md;
        EXPECT_LE(id, 0.0);
        double best = 1e9;
        for (double idg = -30.0; idg <= 0.0; idg += 0.001) {
            const double flux = kPsi + (kLd - kLq) * idg;
            if (flux <= 0.0) continue;
            const double iqg = Md / (1.5 * kP * flux);
            best = std::fmin(best, std::hypot(idg, iqg));
        }
        EXPECT_LE(std::hypot(id, iq), best + 20 * kTol) << Md;
        EXPECT_FALSE(o.limited);
    }
}

TEST(Mtpa, NonSalientAndLimited)
{
    const mtpa_config_t c = mtpa_cfg();
    const motor_model_t mm_ns = motor(kLd, kLd);
    mtpa_out_t o;
    mtpa_step(&c, &mm_ns, M(0.6), &o);
    EXPECT_EQ(D(o.i_d_A), 0.0);
    EXPECT_NEAR(D(o.i_q_A), 0.6 / (1.5 * kP * kPsi), kTol * 5);
    const motor_model_t mm = motor(kLd, kLq);
    mtpa_step(&c, &mm, M(50.0), &o);  // far beyond 20 A
    EXPECT_TRUE(o.limited);
    EXPECT_NEAR(std::hypot(D(o.i_d_A), D(o.i_q_A)), 20.0, 0.01);
    EXPECT_GT(D(o.i_q_A), 0.0);
}

// (9) with (3)'s coupling: at the references and at speed the voltages are
// the model's steady ones; in closed loop with the dq model the error
// decays as exp(-lambda t); the bus's limit holds.
TEST(Ibcc, SteadyVoltagesAndFirstOrderErrorDecay)
{
    const motor_model_t mi = motor(kLd, kLq);
    const ibcc_config_t c{M(1000.0), MC_ONE};
    ibcc_t s;
    ASSERT_TRUE(ibcc_init(&s, &c, &mi));
    mc_t ud, uq;
    const double w = 50.0, id = -1.0, iq = 3.0;
    ibcc_run(&s, &c, &mi, M(id), M(iq), M(id), M(iq), M(w), M(100.0), &ud, &uq);
    ibcc_run(&s, &c, &mi, M(id), M(iq), M(id), M(iq), M(w), M(100.0), &ud, &uq);
    EXPECT_NEAR(D(ud), kR * id - kLq * kP * w * iq, 1e-3 + 100 * kTol);
    EXPECT_NEAR(D(uq), kR * iq + kLd * kP * w * id + kPsi * kP * w, 1e-3 + 100 * kTol);
    // closed loop on the dq model (explicit Euler, 10 substeps), step of i_qd
    ibcc_t t;
    ASSERT_TRUE(ibcc_init(&t, &c, &mi));
    double x_d = 0.0, x_q = 0.0;
    ibcc_run(&t, &c, &mi, M(0.0), M(2.0), M(0.0), M(0.0), M(w), M(100.0), &ud, &uq);  // seeds the reference derivative
    ASSERT_TRUE(ibcc_init(&t, &c, &mi));
    for (int k = 0; k < 10; ++k) {  // 1 ms = 1/lambda
        ibcc_run(&t, &c, &mi, M(0.0), M(2.0), M(x_d), M(x_q), M(w), M(100.0), &ud, &uq);
        for (int n = 0; n < 10; ++n) {
            const double h = kTs / 10, we = kP * w;
            const double dxd = (D(ud) - kR * x_d + kLq * we * x_q) / kLd;
            const double dxq = (D(uq) - kR * x_q - kLd * we * x_d - kPsi * we) / kLq;
            x_d += h * dxd;
            x_q += h * dxq;
        }
    }
    // sampled first-order: (1 - lambda Ts)^10 = 0.349 of the step left (e^-1 = 0.368 continuous)
    EXPECT_NEAR((2.0 - x_q) / 2.0, std::pow(1.0 - 0.1, 10), 0.03);
    // the d axis sees the q current's change through the coupling for a
    // sample before the compensation (sampled) catches it: about Ts L_q p w
    // di_q / L_d = 0.012 A per 0.2 A step of i_q, decaying
    EXPECT_NEAR(x_d, 0.0, 0.05);
    ibcc_run(&t, &c, &mi, M(0.0), M(20.0), M(0.0), M(0.0), M(w), M(5.0), &ud, &uq);
    EXPECT_LE(std::hypot(D(ud), D(uq)), 5.0 + 1e-3);
    EXPECT_TRUE(t.saturated);
    const ibcc_config_t too_fast{M(6000.0), MC_ONE};
    EXPECT_FALSE(ibcc_init(&t, &too_fast, &mi)) << "lambda Ts 0.6 > 0.5";
}

// The references' prefilter: a 1 A step of i_qd at standstill (i = 0)
// asks u_q = L_q alpha (1/Ts + lambda) + R 0 in the first sample (the
// filtered reference moved by alpha), then the filtered reference follows
// 1 - (1 - alpha)^k; alpha outside (0, 1] is refused.
TEST(Ibcc, ReferencePrefilterLimitsTheFeedForward)
{
    const motor_model_t mi = motor(kLd, kLq);
    for (const double alpha : {1.0, 0.2}) {
        const ibcc_config_t c{M(1000.0), M(alpha)};
        ibcc_t s;
        ASSERT_TRUE(ibcc_init(&s, &c, &mi));
        mc_t ud, uq;
        ibcc_run(&s, &c, &mi, M(0.0), M(0.0), M(0.0), M(0.0), M(0.0), M(200.0), &ud, &uq);
        ibcc_run(&s, &c, &mi, M(0.0), M(1.0), M(0.0), M(0.0), M(0.0), M(200.0), &ud, &uq);
        EXPECT_NEAR(D(uq), kLq * alpha * (1.0 / kTs + 1000.0), 100.0 * kTol) << "alpha " << alpha;
        EXPECT_NEAR(D(ud), 0.0, kTol);
        for (int k = 2; k <= 5; ++k) {
            ibcc_run(&s, &c, &mi, M(0.0), M(1.0), M(0.0), M(0.0), M(0.0), M(200.0), &ud, &uq);
        }
        EXPECT_NEAR(D(s.i_qd_prev_A), 1.0 - std::pow(1.0 - alpha, 5), kTol) << "alpha " << alpha;
    }
    ibcc_t s;
    const ibcc_config_t zero{M(1000.0), M(0.0)};
    EXPECT_FALSE(ibcc_init(&s, &zero, &mi));
    const ibcc_config_t above{M(1000.0), M(1.5)};
    EXPECT_FALSE(ibcc_init(&s, &above, &mi));
}

TEST(Smc, TanhWithinAMillionthOfLibm)
{
    double worst = 0.0;
    for (double x = -10.0; x <= 10.0; x += 0.01) {
        worst = std::fmax(worst, std::fabs(D(smc_tanh(M(x))) - std::tanh(x)));
    }
#if MC_FIXED
    EXPECT_LT(worst, 1e-4);
#else
    EXPECT_LT(worst, 2e-6);
#endif
}

namespace {
// the mechanical plant (7) with a load torque, ideal estimates; returns the
// RMS speed error over 1 s tracking 0 -> 100 rad/s on [0.2, 0.4] s
template <class Ctrl>
double track(Ctrl ctrl, double load_Nm, bool give_load)
{
    double w = 0.0, rms = 0.0, a = 0.0;
    int n = 0;
    for (int k = 0; k < 10000; ++k) {
        const double t = k * kTs;
        double wd = 0.0, dwd = 0.0;
        if (t >= 0.4) {
            wd = 100.0;
        } else if (t > 0.2) {
            const double x = (t - 0.2) / 0.2;
            wd = 100.0 * x * x * x * (10.0 - 15.0 * x + 6.0 * x * x);
            dwd = 100.0 / 0.2 * 30.0 * x * x * (1.0 - x) * (1.0 - x);
        }
        const double Ml = t > 0.5 ? load_Nm : 0.0;
        // the last sample's acceleration: what the EKF's model gives
        const double Mm = ctrl(wd, dwd, w, a, give_load ? Ml : 0.0);
        a = (Mm - kD * w - Ml) / kJ;
        w += kTs * a;
        rms += (wd - w) * (wd - w);
        ++n;
    }
    return std::sqrt(rms / n);
}
}  // namespace

// SOSMC and HTSMC on the plant (7) with a 0.5 N m load from 0.5 s: the
// speed tracks the C^2 ramp to 100 rad/s; compensating the load (M0_hat =
// the load) lowers the error.
TEST(Smc, SosmcAndHtsmcTrackAndCompensationHelps)
{
    const motor_model_t mi = motor(kLd, kLq);
    double rs[2] = {0, 0}, rh[2] = {0, 0};
    for (bool dc : {true, false}) {
        sosmc_config_t sc{M(200.0), M(1e4), M(1e4), M(50.0), M(5.0), dc};
        sosmc_t s;
        ASSERT_TRUE(sosmc_init(&s, &sc, &mi));
        const double r_s = track(
            [&](double wd, double dwd, double w, double a_hat, double M0) {
                return D(sosmc_step(&s, &sc, &mi, M(wd), M(dwd), M(w), M(a_hat), M(M0)));
            },
            0.5, dc);
        htsmc_config_t hc{M(200.0), M(2e3), M(4e3), M(40.0), M(0.5), M(5.0), M(5000.0), M(0.5),
                          M(5.0), dc};
        htsmc_t h;
        ASSERT_TRUE(htsmc_init(&h, &hc, &mi));
        const double r_h = track(
            [&](double wd, double dwd, double w, double a, double M0) {
                (void)a;
                return D(htsmc_step(&h, &hc, &mi, M(wd), M(dwd), M(w), M(M0)));
            },
            0.5, dc);
        std::printf("dc %d: RMS speed error SOSMC %.4g rad/s, HTSMC %.4g rad/s\n", dc, r_s, r_h);
        rs[dc] = r_s;
        rh[dc] = r_h;
    }
    // measured: with compensation 0.026 / 0.027 rad/s, without 0.22 / 0.51
    EXPECT_LT(rs[1], 0.05);
    EXPECT_LT(rh[1], 0.05);
    EXPECT_LT(rs[1], rs[0]) << "compensation must lower SOSMC's error";
    EXPECT_LT(rh[1], rh[0]) << "compensation must lower HTSMC's error";
    EXPECT_LT(rs[0], 1.0);
    EXPECT_LT(rh[0], 1.0);
}

// ---------------------------------------------------------------------------
// Each block one step at a time against its equation evaluated in double
// from the block's own state (issue 26): a dropped term, a wrong sign, a
// swapped gain or a flipped comparison is then a one-step difference far
// above the rounding. The double evaluations are written from the paper's
// equations (and the headers' stated additions: the anti-windup, the
// |nu| bound in physical units, the reference prefilter, the voltage
// limit), not from the C code. They use the parameters as the block stores
// them (Q(x) = the value after mc_from_double), so the comparison sees the
// block's arithmetic alone, not the quantisation of its constants.
namespace {
double Q(double x) { return D(M(x)); }

// uniform in [-a, a], deterministic (a 32-bit LCG)
struct Lcg {
    unsigned s;
    explicit Lcg(unsigned seed) : s(seed) {}
    double operator()(double a)
    {
        s = s * 1103515245u + 12345u;
        return a * (2.0 * ((s >> 8) & 0xFFFF) / 65535.0 - 1.0);
    }
};

// MTPA in double, from (10) and (18) with L_d < L_q; the torque inverted
// and |i| = i_max solved by bisection to double resolution (200 halvings,
// no Newton: independent of the block's method).
struct MtpaRef {
    double Ld, Lq, psi, imax;
    int p;
    double id_of(double iq) const  // (18)
    {
        const double a = psi / (Ld - Lq);
        return -a / 2.0 - 0.5 * std::sqrt(a * a + 4.0 * iq * iq);
    }
    double torque(double id, double iq) const { return 1.5 * p * (iq * psi + (Ld - Lq) * id * iq); }  // (10)
    // along the curve the torque is odd and strictly increasing in i_q
    // (psi + (L_d - L_q) i_d >= psi > 0 and grows with |i_q|)
    double iq_of_torque(double Md) const
    {
        double lo = -1e3, hi = 1e3;
        for (int n = 0; n < 200; ++n) {
            const double mid = 0.5 * (lo + hi);
            (torque(id_of(mid), mid) > Md ? hi : lo) = mid;
        }
        return 0.5 * (lo + hi);
    }
    // the |i_q| on the curve with |i| = i_max (|i| grows with |i_q|)
    double iq_at_limit() const
    {
        double lo = 0.0, hi = imax;
        for (int n = 0; n < 200; ++n) {
            const double mid = 0.5 * (lo + hi);
            (std::hypot(id_of(mid), mid) > imax ? hi : lo) = mid;
        }
        return 0.5 * (lo + hi);
    }
};
}  // namespace

// Negative (generator) torque demands below and at the current limit, and
// the same demands positive: the references lie on the MTPA curve (18), give
// the demand (10) when not limited, have |i| = i_max when limited, i_q has
// the torque's sign, i_d <= 0 (L_d < L_q), and mtpa is odd in the torque.
// 400 demands uniform in +-1.5 times the torque at i_max (10.8 N m): about a
// third limited.
// Tolerances: float: the block's 4 Newton steps from M/(3/2 p psi) do not
// reach float32 resolution near the limit as mtpa.h says (evaluated in
// double: they leave 1.4e-4 A of i_q and 1.7e-4 N m at |i| = i_max = 20 A,
// 3 steps leave 0.07 A; below |M| = 2 N m they converge to float's ulps):
// 2e-4 A and 2.5e-4 N m, far below a wrong derivative or a wrong sign (the
// first Newton step alone moves i_q by amperes). Q14.17: every operation
// rounds to 0.5 LSB (3.8e-6) and a = psi/(L_d - L_q) = -6.7 enters
// sqrt(a^2 + 4 i_q^2) (the a^2 term carries a's rounding times 13): 2e-3
// A and N m, as the existing MTPA tests. When limited, the block's 16
// halvings leave |i_q| within |i_q,unlimited| 2^-16 below the limit
// (header), and |i| grows by (i_q + i_d di_d/di_q)/|i| = 1.39 A per A of
// i_q along the curve there: |i| in [i_max - 1.5 |i_q,u| 2^-16 - tol,
// i_max + tol], i_q within
// |i_q,u| 2^-16 + tol of the double solution.
TEST(Mtpa, NegativeTorqueOnTheCurveLimitedAndOdd)
{
#if MC_FIXED
    constexpr double tol = 2e-3, tolM = 2e-3;
#else
    constexpr double tol = 2e-4, tolM = 2.5e-4;
#endif
    const mtpa_config_t c = mtpa_cfg();
    const motor_model_t mm = motor(kLd, kLq);
    const MtpaRef ref{Q(kLd), Q(kLq), Q(kPsi), Q(20.0), kP};
    const double m_at_limit = 1.5 * kP * ref.iq_at_limit() * (ref.psi + (ref.Ld - ref.Lq) * ref.id_of(ref.iq_at_limit()));
    ASSERT_NEAR(m_at_limit, 10.77, 0.01);
    Lcg rnd(26u);
    int limited_neg = 0, free_neg = 0;
    for (int k = 0; k < 400; ++k) {
        const double Mabs = std::fabs(rnd(1.5 * m_at_limit));
        for (const double Md : {-Mabs, Mabs}) {
            mtpa_out_t o;
            mtpa_step(&c, &mm, M(Md), &o);
            const double id = D(o.i_d_A), iq = D(o.i_q_A);
            const double iq_u = ref.iq_of_torque(Md);
            const double i_u = std::hypot(ref.id_of(iq_u), iq_u);
            const double width = std::fabs(iq_u) * std::ldexp(1.0, -MTPA_LIMIT_STEPS);
            // on the curve (18), i_d <= 0, i_q with the torque's sign
            ASSERT_NEAR(id, ref.id_of(iq), tol) << Md;
            ASSERT_LE(id, 0.0) << Md;
            ASSERT_EQ(iq < 0.0, Md < 0.0) << Md;
            if (std::fabs(i_u - ref.imax) < 2.0 * tol) {
                continue;  // on the limit within rounding: either answer
            }
            ASSERT_EQ(o.limited, i_u > ref.imax) << Md;
            if (o.limited) {
                const double iq_l = std::copysign(ref.iq_at_limit(), Md);
                ASSERT_NEAR(iq, iq_l, width + tol) << Md;
                ASSERT_LE(std::hypot(id, iq), ref.imax + tol) << Md;
                ASSERT_GE(std::hypot(id, iq), ref.imax - 1.5 * width - tol) << Md;
                ASSERT_LT(std::fabs(ref.torque(id, iq)), std::fabs(Md)) << "limited: the torque falls short " << Md;
                limited_neg += Md < 0.0;
            } else {
                ASSERT_NEAR(iq, iq_u, tol) << Md;
                ASSERT_NEAR(ref.torque(id, iq), Md, tolM) << Md;
                free_neg += Md < 0.0;
            }
        }
        // odd in the torque: float negates exactly (bit-exact), Q14.17's
        // products round ties up (a few LSB)
        mtpa_out_t pos, neg;
        mtpa_step(&c, &mm, M(Mabs), &pos);
        mtpa_step(&c, &mm, M(-Mabs), &neg);
#if MC_FIXED
        ASSERT_NEAR(D(neg.i_q_A), -D(pos.i_q_A), 1e-4) << Mabs;
        ASSERT_NEAR(D(neg.i_d_A), D(pos.i_d_A), 1e-4) << Mabs;
#else
        ASSERT_EQ(D(neg.i_q_A), -D(pos.i_q_A)) << Mabs;
        ASSERT_EQ(D(neg.i_d_A), D(pos.i_d_A)) << Mabs;
#endif
        ASSERT_EQ(neg.limited, pos.limited) << Mabs;
    }
    EXPECT_GT(limited_neg, 80);
    EXPECT_GT(free_neg, 150);
}

// SOSMC (27)-(28) one step at a time: s, the torque, the limit flag and the
// integrals' update against double from the block's state (int_err,
// int_torque), over random speeds, accelerations and disturbance
// estimates that put the torque beyond +-M_max on both sides with the
// integrand pushing either way. Anti-windup (header): the integrals are
// frozen exactly while |M| > M_max and the integrand J (alpha_I w~ + eta
// tanh(s/eps)) has M's sign (it would push M further out); otherwise they
// step by Ts times the integrand (explicit Euler). With and without DC.
// alpha_I = eta = 4096: the block forms alpha_I w~ + eta tanh(s/eps) in
// rad/s^3 before multiplying by J, which must stay below Q14.17's 16384.
// Tolerances: float: the torque's terms are below 3 N m (2.4e-7 per ulp)
// and s below 2000 (1.2e-4 per ulp), a few roundings each: 2e-6 N m,
// 1e-3 rad/s^2 on s; the integrals a few ulps of themselves (5e-7
// relative) plus 1e-9 rad on int_err (steps of 1e-4) and 2e-8 N m on
// int_torque (steps of 8e-4: the tanh's 2e-6 times J eta Ts = 4e-4
// besides). Q14.17: a few LSB (7.6e-6) per value: 5e-5 N m, 1e-3 on s
// (alpha_I int_err is one rounded product), 2e-5 on the integrals.
// A decision within the tolerance of its threshold (|M| - M_max, M's or
// the integrand's sign) may go either way; such steps (none expected in
// float) are counted and must stay rare.
TEST(Sosmc, EachStepFollowsEq27And28WithTheLimitOnBothSides)
{
    const motor_model_t mi = motor(kLd, kLq);
#if MC_FIXED
    constexpr double tM = 5e-5, tS = 1e-3, tIe = 2e-5, tIt = 2e-5, kRel = 0.0;
#else
    constexpr double tM = 2e-6, tS = 1e-3, tIe = 1e-9, tIt = 2e-8, kRel = 5e-7;
#endif
    Lcg rnd(2602u);
    for (const bool dc : {true, false}) {
        const sosmc_config_t c{M(200.0), M(4096.0), M(4096.0), M(500.0), M(1.0), dc};
        const double J = Q(kJ), d = Q(kD), a0 = Q(200.0), aI = Q(4096.0), eta = Q(4096.0), eps = Q(500.0), Mmax = Q(1.0),
                     ts = Q(kTs);
        sosmc_t s;
        ASSERT_TRUE(sosmc_init(&s, &c, &mi));
        int pos_frozen = 0, pos_free = 0, neg_frozen = 0, neg_free = 0, unlimited = 0, unsure = 0;
        for (int k = 0; k < 3000; ++k) {
            const double ie = D(s.int_err), it = D(s.int_torque);
            // the inputs, as the block receives them (Q): w~ within +-1; dw_d
            // and the acceleration chosen from the state so that the torque
            // (27)-(28) lands uniformly in +-2 M_max and s in +-2 eps,
            // independently (the integrand's sign is then not M's)
            const double wd = Q(rnd(200.0)), w = Q(wd - rnd(1.0)), M0 = Q(rnd(0.5));
            const double M_aim = rnd(2.0), s_aim = rnd(1000.0);
            const double dwd = Q((M_aim - it - Q(kD) * w - (dc ? M0 : 0.0)) / Q(kJ) - Q(200.0) * (wd - w));
            const double a = Q(dwd + Q(200.0) * (wd - w) + Q(4096.0) * ie - s_aim);
            // (27)-(28) in double
            const double e = wd - w, de = dwd - a;
            const double sv = de + a0 * e + aI * ie;
            const double Mc = J * (dwd + a0 * e) + d * w + (dc ? M0 : 0.0) + it;
            const double Mout = std::fmin(Mmax, std::fmax(-Mmax, Mc));
            const double rate = J * (aI * e + eta * std::tanh(sv / eps));
            const bool lim = std::fabs(Mc) > Mmax;
            const bool frozen = lim && Mc * rate > 0.0;
            const double M_blk = D(sosmc_step(&s, &c, &mi, M(wd), M(dwd), M(w), M(a), M(M0)));
            ASSERT_NEAR(D(s.s), sv, tS) << k;
            ASSERT_NEAR(M_blk, Mout, tM) << k << " M " << Mc;
            if (std::fabs(std::fabs(Mc) - Mmax) < 2.0 * tM || std::fabs(rate) < 1e-4) {
                ++unsure;
                continue;
            }
            ASSERT_EQ(s.limited, lim) << k << " M " << Mc;
            ASSERT_NEAR(D(s.int_err), frozen ? ie : ie + ts * e, tIe + kRel * std::fabs(ie))
                << k << " M " << Mc << " rate " << rate;
            ASSERT_NEAR(D(s.int_torque), frozen ? it : it + ts * rate, tIt + kRel * std::fabs(it))
                << k << " M " << Mc << " rate " << rate;
            if (!lim) {
                ++unlimited;
            } else if (Mc > 0.0) {
                ++(frozen ? pos_frozen : pos_free);
            } else {
                ++(frozen ? neg_frozen : neg_free);
                ASSERT_EQ(M_blk, -D(M(1.0))) << "clamped at -M_max exactly " << k;
            }
        }
        std::printf("dc %d: unlimited %d, M > M_max frozen %d / integrating %d, M < -M_max frozen %d / "
                    "integrating %d, unsure %d\n",
                    dc, unlimited, pos_frozen, pos_free, neg_frozen, neg_free, unsure);
        EXPECT_GT(unlimited, 300);
        EXPECT_GT(pos_frozen, 100);
        EXPECT_GT(pos_free, 100);
        EXPECT_GT(neg_frozen, 100);
        EXPECT_GT(neg_free, 100);
        EXPECT_LT(unsure, 10);
    }
}

// HTSMC (29), (30), (35) one step at a time from the block's state
// (int_err, nu1, s_prev, first): s = w~ + alpha_I int w~, ds/dt = (s -
// s_prev)/Ts (0 at the first step), sign -> tanh(s/eps), nu2 = -lambda
// min(|s|, s0)^rho sign(s), nu = nu1 + nu2, M = M_eq - J nu clamped, and
// nu1's rate: -nu when |nu| > nu_max, else -alpha_m sign(s) when s ds/dt
// <= 0 and -alpha_M sign(s) when s ds/dt > 0. The inputs keep s within
// +-1.5 rad/s (both sides of s0 = 0.5 and of 0) and nu1 wanders to the
// bound +-nu_max and back; rho = 1/2 and 1/4. alpha_M = 2 alpha_m: a swap
// moves nu1 by Ts alpha_m |tanh| (up to 5 rad/s^2) in one step.
// Tolerances: float: M's terms below 2 N m, 2e-6 N m; nu1 below 80 with
// steps of Ts alpha tanh (tanh within 2e-6: 2e-5 rad/s^2), 1e-4 rad/s^2.
// Q14.17: M to 5e-5 N m (J nu and the sqrt of a small |s| a few LSB); nu1:
// the fixed tanh's 1e-4 times Ts alpha_M = 10 gives 1e-3, 2e-3 rad/s^2. A
// decision within rounding of its threshold (|nu| at nu_max; s ds/dt at 0:
// s or s - s_prev within a few LSB of 0) accepts either branch.
TEST(Htsmc, EachStepFollowsEq29Eq30AndTheTwistingRatesOf35)
{
#if MC_FIXED
    constexpr double tM = 5e-5, tN = 2e-3, tS = 2e-5;
#else
    constexpr double tM = 2e-6, tN = 1e-4, tS = 1e-6;
#endif
    Lcg rnd(3503u);
    for (const double rho : {0.5, 0.25}) {
        for (const bool dc : {true, false}) {
            const double ts_ = 1e-3;
            const htsmc_config_t c{M(100.0), M(5e3), M(1e4), M(20.0), M(rho), M(0.5), M(50.0), M(0.5), M(1.2), dc};
            const motor_model_t mi = motor(kLd, kLq, ts_);
            const double J = Q(kJ), d = Q(kD), aI = Q(100.0), am = Q(5e3), aM = Q(1e4), lam = Q(20.0), s0 = Q(0.5),
                         nu_max = Q(50.0), eps = Q(0.5), Mmax = Q(1.2), ts = Q(ts_);
            htsmc_t h;
            ASSERT_TRUE(htsmc_init(&h, &c, &mi));
            int bounded = 0, twist_m = 0, twist_M = 0, unsure = 0, clamped_neg = 0, clamped_pos = 0;
            for (int k = 0; k < 3000; ++k) {
                const double ie = D(h.int_err), nu1 = D(h.nu1), s_prev = D(h.s_prev);
                const bool first = h.first;
                // inputs: s = w~ + alpha_I int_err lands uniformly in +-1.5
                const double wd = Q(rnd(300.0)), dwd = Q(rnd(1500.0)), M0 = Q(rnd(0.3));
                const double w = Q(wd - (rnd(1.5) - aI * ie));
                const double e = wd - w;
                const double sv = e + aI * ie;
                const double ds = first ? 0.0 : (sv - s_prev) / ts;
                const double sg = std::tanh(sv / eps);
                const double nu2 = -lam * std::pow(std::fmin(std::fabs(sv), s0), rho) * sg;
                const double nu = nu1 + nu2;
                const double Meq = J * (dwd + aI * e) + d * w + (dc ? M0 : 0.0);  // (29)
                const double Mc = Meq - J * nu;                                  // (30)
                const double Mout = std::fmin(Mmax, std::fmax(-Mmax, Mc));
                // (35): the candidates for nu1's rate
                const double r_bound = -nu, r_m = -am * sg, r_M = -aM * sg;
                const double M_blk = D(htsmc_step(&h, &c, &mi, M(wd), M(dwd), M(w), M(M0)));
                ASSERT_NEAR(D(h.s), sv, tS) << k;
                ASSERT_NEAR(M_blk, Mout, tM) << k;
                clamped_neg += Mc < -Mmax - tM;
                clamped_pos += Mc > Mmax + tM;
                const double nu1_blk = D(h.nu1);
                const bool near_bound = std::fabs(std::fabs(nu) - nu_max) < 20.0 * tN;
                const bool near_zero = !first && (std::fabs(sv) < 10.0 * tS || std::fabs(sv - s_prev) < 10.0 * tS);
                double want;
                if (std::fabs(nu) > nu_max) {
                    want = nu1 + ts * r_bound;
                    ++bounded;
                } else if (sv * ds <= 0.0) {
                    want = nu1 + ts * r_m;
                    ++twist_m;
                } else {
                    want = nu1 + ts * r_M;
                    ++twist_M;
                }
                if (near_bound || near_zero) {
                    ++unsure;
                    const bool any = std::fabs(nu1_blk - (nu1 + ts * r_bound)) < tN ||
                                     std::fabs(nu1_blk - (nu1 + ts * r_m)) < tN ||
                                     std::fabs(nu1_blk - (nu1 + ts * r_M)) < tN;
                    ASSERT_TRUE(any) << k;
                } else {
                    ASSERT_NEAR(nu1_blk, want, tN)
                        << k << " nu " << nu << " s " << sv << " ds/dt " << ds << " sign " << sg;
                }
                ASSERT_NEAR(D(h.int_err), ie + ts * e, tS) << k;
                ASSERT_NEAR(D(h.s_prev), sv, tS) << k;
                ASSERT_FALSE(h.first);
            }
            std::printf("rho %.2f dc %d: |nu| > nu_max %d, alpha_m %d, alpha_M %d, unsure %d, clamped -%d +%d\n", rho,
                        dc, bounded, twist_m, twist_M, unsure, clamped_neg, clamped_pos);
            EXPECT_GT(bounded, 100);
            EXPECT_GT(twist_m, 300);
            EXPECT_GT(twist_M, 300);
            EXPECT_GT(clamped_neg, 50);
            EXPECT_GT(clamped_pos, 50);
            EXPECT_LT(unsure, 30);
        }
    }
}

// IBCC (9) with (3)'s coupling one step at a time from the block's
// prefilter state, over random references (a random walk with jumps),
// currents of both signs, speeds of both signs and random bus limits:
//   i_f = i_f,prev + alpha (i_ref - i_f,prev) (i_f,prev = i_ref at the first step)
//   u_d = L_d ((i_df - i_df,prev)/Ts + lambda (i_df - i_d)) + R i_d - L_q p w i_q
//   u_q = L_q ((i_qf - i_qf,prev)/Ts + lambda (i_qf - i_q)) + R i_q + L_d p w i_d + psi p w
// and when |u| > u_max, u u_max/|u|: the same direction, on the circle.
// lambda = 500/s and currents within +-6 A: the block forms di_f/dt +
// lambda (i_f - i) in A/s before multiplying by L, which must stay below
// Q14.17's 16384 (asserted on the inputs).
// Tolerances: float: the terms reach 100 V (1e-5 per ulp), 1e-4 V; the
// filtered references (below 6 A, 4.8e-7 per ulp) 3e-6 A. Q14.17: the prefilter's step rounds to 0.5
// LSB and is multiplied by f_s = 1e4 (0.04 A/s, 3.4e-4 V through L_q), the
// flux psi + L_d i_d rounds to 0.5 LSB and is multiplied by p w (up to
// 1200 rad/s: 4.6e-3 V), L_q p w to 0.5 LSB times i_q (6 A): 8e-3 V;
// 2e-5 A. Limited, the scale u_max/|u| (below 1) carries 0.5 LSB absolute
// (float: 0.5 ulp relative) and multiplies the unlimited voltage (up to
// 200 V): plus 4e-6 |u| (float 1e-7 |u|).
TEST(Ibcc, EachStepFollowsEq9WithTheCouplingAndTheLimit)
{
    const motor_model_t mi = motor(kLd, kLq);
#if MC_FIXED
    constexpr double tU = 8e-3, tI = 2e-5, kScale = 4e-6;
#else
    constexpr double tU = 1e-4, tI = 3e-6, kScale = 1e-7;
#endif
    const ibcc_config_t c{M(500.0), M(0.25)};
    const double R = Q(kR), Ld = Q(kLd), Lq = Q(kLq), psi = Q(kPsi), lam = Q(500.0), al = Q(0.25), fs = 10000.0;
    ibcc_t s;
    ASSERT_TRUE(ibcc_init(&s, &c, &mi));
    Lcg rnd(909u);
    double rd = 0.0, rq = 0.0;
    int sat = 0, unlim = 0, neg_w = 0, unsure = 0;
    for (int k = 0; k < 3000; ++k) {
        if (k % 1000 == 0) {
            ASSERT_TRUE(ibcc_init(&s, &c, &mi));  // the first step again
        }
        rd = std::fmax(-6.0, std::fmin(6.0, rd + (k % 50 == 0 ? rnd(2.0) : rnd(0.3))));
        rq = std::fmax(-6.0, std::fmin(6.0, rq + (k % 50 == 25 ? rnd(2.0) : rnd(0.3))));
        rd = Q(rd);
        rq = Q(rq);
        const double id = Q(rnd(6.0)), iq = Q(rnd(6.0)), w = Q(rnd(300.0)), umax = Q(10.0 + std::fabs(rnd(100.0)));
        const double pd = s.first ? rd : D(s.i_dd_prev_A), pq = s.first ? rq : D(s.i_qd_prev_A);
        const double fd = pd + al * (rd - pd), fq = pq + al * (rq - pq);
        const double we = kP * w;
        const double rate_d = (fd - pd) * fs + lam * (fd - id), rate_q = (fq - pq) * fs + lam * (fq - iq);
        ASSERT_LT(std::fmax(std::fabs(rate_d), std::fabs(rate_q)), 16000.0) << k;
        double ud = Ld * rate_d + R * id - Lq * we * iq;
        double uq = Lq * rate_q + R * iq + Ld * we * id + psi * we;
        const double mag = std::hypot(ud, uq);
        const bool lim = mag > umax;
        const double tol = tU + (lim ? kScale * mag : 0.0);
        if (lim) {
            ud *= umax / mag;
            uq *= umax / mag;
        }
        mc_t u_d, u_q;
        ibcc_run(&s, &c, &mi, M(rd), M(rq), M(id), M(iq), M(w), M(umax), &u_d, &u_q);
        ASSERT_NEAR(D(s.i_dd_prev_A), fd, tI) << k;
        ASSERT_NEAR(D(s.i_qd_prev_A), fq, tI) << k;
        ASSERT_NEAR(D(u_d), ud, tol) << k << " w " << w << " i " << id << " " << iq << " |u| " << mag;
        ASSERT_NEAR(D(u_q), uq, tol) << k << " w " << w << " i " << id << " " << iq << " |u| " << mag;
        if (std::fabs(mag - umax) < 2.0 * tU) {
            ++unsure;
            continue;
        }
        ASSERT_EQ(s.saturated, lim) << k;
        if (lim) {
            // on the circle, the direction of the unlimited voltage
            ASSERT_NEAR(std::hypot(D(u_d), D(u_q)), umax, tol) << k;
            ASSERT_NEAR((D(u_d) * uq - D(u_q) * ud) / umax, 0.0, tol) << k;
            ++sat;
        } else {
            ++unlim;
        }
        neg_w += w < 0.0;
    }
    std::printf("saturated %d, not %d, negative speed %d, unsure %d\n", sat, unlim, neg_w, unsure);
    EXPECT_GT(sat, 500);
    EXPECT_GT(unlim, 500);
    EXPECT_GT(neg_w, 1000);
    EXPECT_LT(unsure, 5);
}

// Paper 002's speed reference (trajectory/speed_poly.h): the C^2 quintic
// w(x) = w0 + (w1 - w0)(10 x^3 - 15 x^4 + 6 x^5), x = (k - k0)/(k1 - k0),
// and its derivative (w1 - w0) 30 x^2 (1 - x)^2 fs / (k1 - k0), evaluated
// here in double at every tick of a rise and of a reversal (both signs),
// w0 held before k0 and w1 after k1 with dw/dt = 0; a refused interval.
TEST(SpeedPoly, EveryTickFollowsTheQuinticAndItsDerivative)
{
#if MC_FIXED
    // dw/dt saturates in Q14.17 for any ramp steeper than 16384 / (1.875
    // fs) (trajectory/speed_poly.h); paper 002's drive is float only
    GTEST_SKIP() << "float only: speed_poly's dw/dt saturates in Q14.17 (trajectory/speed_poly.h)";
#endif
    const int fs = 10000;
    struct Case {
        uint32_t k0, k1;
        double w0, w1;
    };
    for (const Case cs : {Case{2000u, 4000u, 0.0, 100.0}, Case{1000u, 3500u, 80.0, -120.0}, Case{10u, 11u, -5.0, 5.0}}) {
        speed_poly_t p;
        ASSERT_TRUE(speed_poly_init(&p, cs.k0, cs.k1, M(cs.w0), M(cs.w1), fs));
        const double n = static_cast<double>(cs.k1 - cs.k0), dw = cs.w1 - cs.w0;
        // float: about ten roundings of 6e-8 of the 200 rad/s swing, 1.2e-4,
        // and x = k/n's own (measured 1.9e-4 rad/s): 5e-4; dw/dt (peak 1.875
        // dw fs / n) to 1e-5 of its peak
        const double tol_w = 5e-4, tol_a = 1e-5;
        double worst_w = 0.0, worst_a = 0.0;
        for (uint32_t k = 0; k < cs.k1 + 500u; ++k) {
            mc_t w, a;
            speed_poly_eval(&p, k, &w, &a);
            double we = cs.w0, ae = 0.0;
            if (k >= cs.k1) {
                we = cs.w1;
            } else if (k > cs.k0) {
                const double x = (k - cs.k0) / n;
                we = cs.w0 + dw * x * x * x * (10.0 - 15.0 * x + 6.0 * x * x);
                ae = dw * 30.0 * x * x * (1.0 - x) * (1.0 - x) * fs / n;
            }
            worst_w = std::max(worst_w, std::fabs(D(w) - we));
            worst_a = std::max(worst_a, std::fabs(D(a) - ae) / (1.875 * std::fabs(dw) * fs / n));
        }
        EXPECT_LT(worst_w, tol_w) << cs.w0 << " -> " << cs.w1;
        EXPECT_LT(worst_a, tol_a) << cs.w0 << " -> " << cs.w1;
    }
    speed_poly_t p;
    EXPECT_FALSE(speed_poly_init(&p, 100u, 100u, M(0.0), M(1.0), fs));
    EXPECT_FALSE(speed_poly_init(&p, 100u, 200u, M(0.0), M(1.0), 0));
}
