// Drive-level behaviour: configuration checks, safe state, limits, switching.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "design/paper000_design.h"
#include "design/paper001_design.h"
#include "math/mc_convert.h"
#include "p001_fixture.h"

namespace {
constexpr double kPi = 3.14159265358979323846;
#if MC_FIXED
constexpr double kLsb = 1.0 / 131072.0;  // Q14.17
#else
constexpr double kLsb = 0.0;
#endif
drive_design_input_t paper_input()
{
    drive_design_input_t in;
    drive_design_defaults(&in);
    // the rig of section 5.3 (sim/motors/paper000_stepper.toml) and the
    // supply and limits of sim/scenarios/paper000_*.toml
    in.motor = {9e-3, 3.01, 0.27, 3.18e-4, 2.37e-3, 50, 0.0752, 2, 9e-3};
    in.ts_s = 1e-4;
    in.v_max_V = 30.0;
    in.i_max_A = 3.0;
    in.i_trip_A = 4.5;
    in.omega_lim_rad_s = 3.0;
    in.n_segments = 2;
    in.segments[0] = {0.0, 2.0, 18.0};
    in.segments[1] = {2.0, 2.0, 0.0};
    // these tests look at the start itself from the first sample: no
    // rotor alignment before it (startup/align.h has its own tests)
    in.align_rotor = 0;
    return in;
}
double D(mc_t x) { return mc_to_double(x); }
// the paper-000 rig and trajectory, designed and initialised
bool init_paper_drive(paper000_drive_t *d)
{
    drive_design_input_t in = paper_input();
    paper000_config_t cfg;
    char err[160];
    return drive_design(&in, &cfg, err, sizeof err) && paper000_drive_init(d, &cfg);
}

// one sample of a two-phase stepper through the HAL data types
bool step2(paper000_drive_t *d, mc_t ia, mc_t ib, mc_t *va, mc_t *vb)
{
    hal_sample_t in{};
    in.n_phases = 2;
    in.i_A[0] = ia;
    in.i_A[1] = ib;
    hal_command_t out{};
    out.v_V[0] = mc_from_double(99.0);  // must be overwritten, fault or not
    out.v_V[1] = mc_from_double(99.0);
    const bool ok = paper000_drive_step(d, &in, &out);
    EXPECT_EQ(out.n_phases, 2);
    *va = out.v_V[0];
    *vb = out.v_V[1];
    return ok;
}

paper000_telemetry_t tlm_of(const paper000_drive_t &d)
{
    paper000_telemetry_t t;
    paper000_drive_get_telemetry(&d, &t);
    return t;
}
mc_t M(double x) { return mc_from_double(x); }
}  // namespace

TEST(DriveDesign, RejectsNonPhysicalInputNamingTheField)
{
    char err[160];
    paper000_config_t cfg;
    drive_design_input_t in = paper_input();
    ASSERT_TRUE(drive_design(&in, &cfg, err, sizeof err)) << err;
    in.motor.L_H = -1.0;
    EXPECT_FALSE(drive_design(&in, &cfg, err, sizeof err));
    EXPECT_NE(std::string(err).find("motor.L_H"), std::string::npos) << err;
    in = paper_input();
    in.ts_s = 0.0;
    EXPECT_FALSE(drive_design(&in, &cfg, err, sizeof err));
    EXPECT_NE(std::string(err).find("Ts_s"), std::string::npos) << err;
    in = paper_input();
    in.segments[1].duration_s = -2.0;
    EXPECT_FALSE(drive_design(&in, &cfg, err, sizeof err));
    EXPECT_NE(std::string(err).find("duration_s"), std::string::npos) << err;
}

// Peaks of |theta_r'| and |theta_r''| of the paper's move (18 rad in 2 s,
// eq. (70)), found by sampling the polynomial's derivatives on a fine grid:
// independent of the constants the design uses for them.
static void trajectory_peaks(double delta, double T, double *w_max, double *a_max)
{
    *w_max = 0.0;
    *a_max = 0.0;
    for (int n = 0; n <= 200000; ++n) {
        const double D = n / 200000.0;
        const double dp = 140 * std::pow(D, 3) - 420 * std::pow(D, 4) + 420 * std::pow(D, 5) - 140 * std::pow(D, 6);
        const double ddp = 420 * D * D - 1680 * std::pow(D, 3) + 2100 * std::pow(D, 4) - 840 * std::pow(D, 5);
        *w_max = std::fmax(*w_max, std::fabs(delta * dp / T));
        *a_max = std::fmax(*a_max, std::fabs(delta * ddp / (T * T)));
    }
}

// The derived gains against the sliding-mode conditions, with every bound
// worked out here from the model and the trajectory rather than taken from
// paper000_design.c. Paper 000, rig of section 5.3, bounds of
// drive_design_defaults().
TEST(DriveDesign, GainsMeetTheSlidingModeConditions)
{
    drive_design_input_t in = paper_input();
    paper000_config_t cfg;
    char err[160];
    ASSERT_TRUE(drive_design(&in, &cfg, err, sizeof err)) << err;
    const double L = 9e-3, R = 3.01, K = 0.27, J = 3.18e-4, fv = 2.37e-3, Ts = 1e-4;
    const int np = 50;
    double w_max, a_max;
    trajectory_peaks(18.0, 2.0, &w_max, &a_max);
    EXPECT_NEAR(w_max, 19.6875, 1e-3);  // 35/16 * 9 rad/s at D = 1/2
    // Observer, section 3.1.1: the unknown input of (23) is d = (K/L) w
    // [sin; -cos](n_p dtheta); its rate is bounded by (K/L)(|w'| + n_p |w| |dw|).
    const double Pi_d = (K / L) * (a_max + np * w_max * in.bound_delta_omega_rad_s);
    const double alpha_e = D(cfg.est.emf.alpha_V) / (L * Ts);
    const double lambda_e = D(cfg.est.emf.lambda_A) / Ts;
    // Levant 1993: alpha > Pi and lambda^2 >= 4 Pi (alpha + Pi)/(alpha - Pi);
    // the design takes alpha = 2 Pi, so lambda^2 = 12 Pi.
    // (gains are compared in the units the firmware stores them, to one
    // LSB of the numeric type plus 1e-6 relative)
    auto near = [](double got, double want) { return std::fabs(got - want) <= kLsb + 1e-6 * std::fabs(want); };
    EXPECT_TRUE(near(D(cfg.est.emf.alpha_V), L * 2 * Pi_d * Ts)) << D(cfg.est.emf.alpha_V);
    EXPECT_TRUE(near(D(cfg.est.emf.lambda_A), std::sqrt(4 * Pi_d * (alpha_e + Pi_d) / (alpha_e - Pi_d)) * Ts))
        << D(cfg.est.emf.lambda_A);
    EXPECT_NEAR(lambda_e * lambda_e / (12 * Pi_d), 1.0, 2e-3);
    // i_f loop (46)-(51): the same bound, gains scaled by L into volts.
    EXPECT_TRUE(near(D(cfg.ctrl.cur.alpha_ts), L * 2 * Pi_d * Ts)) << D(cfg.ctrl.cur.alpha_ts);
    EXPECT_TRUE(near(D(cfg.ctrl.cur.lambda), L * std::sqrt(12 * Pi_d))) << D(cfg.ctrl.cur.lambda);
    // Mechanical observer, section 3.2: the unknown input is the load
    // torque over J; its rate is bounded by |dC_r/dt|max / J.
    const double Pi_m = in.bound_load_rate_Nm_s / J;
    EXPECT_TRUE(near(D(cfg.est.mech.alpha_Nm), J * 2 * Pi_m * Ts)) << D(cfg.est.mech.alpha_Nm);
    EXPECT_TRUE(near(D(cfg.est.mech.lambda_ts), std::sqrt(12 * Pi_m) * Ts)) << D(cfg.est.mech.lambda_ts);
    // Twisting, (52)-(57): with S = k xi_theta + xi_omega and J w' = K i_q -
    // f_v w - C_r, S'' = (K/J) i_q' - (f_v/J) w' - C_r'/J + k w' - (k w_r'
    // + w_r''), whose uncancelled part is C_r entering through w' twice,
    // (f_v/J^2 - k/J) C_r, its rate -C_r'/J, and a voltage error e in
    // L i_q' = ... + e, i.e. (K/(J L)) e. Each at its bound:
    const double k = D(cfg.ctrl.k_surface_per_s);
    EXPECT_EQ(k, 50.0);
    const double C0 = std::fabs(fv / (J * J) - k / J) * 0.0752 + in.bound_load_rate_Nm_s / J +
                      K / (J * L) * in.bound_model_error_V;
    // the controller's output is the voltage (JL/K) w_t, eq. (54)
    const double lm = D(cfg.ctrl.pos.lambda_m) * K / (J * L), lM = D(cfg.ctrl.pos.lambda_M) * K / (J * L);
    // (22) with k_m = K_M = 1: lambda_m > C0, lambda_M > lambda_m + 2 C0, each with a 1.2 margin
    EXPECT_NEAR(lm / C0, 1.2, 1e-3);
    EXPECT_NEAR(lM / (lm + 2 * C0), 1.2, 1e-3);
    // Voltage forms of the (54) terms: L (k - f_v/J) and (L/K)(k - f_v/J) f_v
    EXPECT_NEAR(D(cfg.ctrl.v_k_i_V_per_A), L * (k - fv / J), 1e-4);
    EXPECT_NEAR(D(cfg.ctrl.v_k_w_V_s), L / K * (k - fv / J) * fv, 1e-4);
    // Model terms of (23), (38)-(39), (68)
    EXPECT_NEAR(D(cfg.model.R_ohm), R, 1e-4);
    EXPECT_NEAR(D(cfg.model.npL_ohm_s), np * L, 1e-4);
    EXPECT_NEAR(D(cfg.model.J_over_K_A_s2), J / K, 1e-5);
    EXPECT_NEAR(D(cfg.model.fv_over_K_A_s), fv / K, 1e-5);
    EXPECT_NEAR(D(cfg.model.ts_over_L_A_per_V), Ts / L, 1e-5);
}

// The twisting gains as designed, on the sliding variable's own dynamics
// S'' = (K/(J L)) u + p(t), u the controller's voltage, with the worst
// perturbation the bound allows (|p| = C0, always pushing S away from 0):
// S reaches a small band in finite time and stays there.
TEST(DriveDesign, TwistingGainsBeatTheWorstPerturbation)
{
    drive_design_input_t in = paper_input();
    paper000_config_t cfg;
    char err[160];
    ASSERT_TRUE(drive_design(&in, &cfg, err, sizeof err)) << err;
    const double L = 9e-3, K = 0.27, J = 3.18e-4, fv = 2.37e-3;
    const double k = 50.0;
    const double C0 = std::fabs(fv / (J * J) - k / J) * 0.0752 + in.bound_load_rate_Nm_s / J +
                      K / (J * L) * in.bound_model_error_V;
    twisting_t tw;
    twisting_init(&tw, &cfg.ctrl.pos);
    double S = 0.5, Sd = 0.0;  // rad/s and rad/s^2
    const double h = 1e-6;
    double late_max = 0.0;
    for (int n = 0; n < 400000; ++n) {  // 0.4 s
        const double u = D(twisting_step(&tw, M(S), M(Sd)));
        const double p = (S >= 0 ? 1.0 : -1.0) * C0;
        Sd += h * (K / (J * L) * u + p);
        S += h * Sd;
        if (n > 300000) late_max = std::fmax(late_max, std::fabs(S));
    }
    EXPECT_LT(late_max, 1e-3) << "twisting with the designed gains did not hold S near 0";
}

// The discrete-time gain design (paper000_design.c, gain_design = DISCRETE)
// against the sampled system's bounds, worked out here from the rig: the
// back-EMF observer's per-sample step turns its estimate by at most 0.05 rad
// electrical at every speed from omega_lim up while still meeting alpha >=
// 2 Pi_d(w) of the bounds as given there; the twisting's lambda_M and the
// load observer's alpha within the ripple cap 0.01 I_max K/(J 2 Ts), with
// (22)'s ratio kept; the load feed-forward's L/(K Ts). The default design
// is the continuous one.
TEST(DriveDesign, DiscreteDesignKeepsTheGainsWithinTheSampledBounds)
{
    const double L = 9e-3, K = 0.27, J = 3.18e-4, Ts = 1e-4, I_max = 3.0;
    const int np = 50;
    char err[160];
    drive_design_input_t in = paper_input();
    EXPECT_EQ(in.gain_design, DRIVE_GAIN_CONTINUOUS);
    paper000_config_t cont, disc;
    ASSERT_TRUE(drive_design(&in, &cont, err, sizeof err)) << err;
    EXPECT_EQ(D(cont.est.emf.alpha_V_per_rad_s), 0.0);
    EXPECT_EQ(D(cont.ctrl.load_ff_L_over_KTs), 0.0);
    in.gain_design = DRIVE_GAIN_DISCRETE;
    ASSERT_TRUE(drive_design(&in, &disc, err, sizeof err)) << err;
    double w_max, a_max;
    trajectory_peaks(18.0, 2.0, &w_max, &a_max);
    for (double w = 3.0; w <= w_max; w += 0.25) {
        const double step_V = D(disc.est.emf.alpha_V) + D(disc.est.emf.alpha_V_per_rad_s) * w;  // L alpha(w) Ts
        EXPECT_LE(step_V / (K * w), 0.05 + 1e-4) << w;
        const double Pi_w = (K / L) * (a_max + np * w * in.bound_delta_omega_rad_s);
        EXPECT_GE(step_V, L * 2 * Pi_w * Ts - 1e-5) << w;
    }
    EXPECT_NEAR(D(disc.ctrl.load_ff_L_over_KTs), L / (K * Ts), 1e-3);
    // default bounds: the twisting is below the cap and equals the continuous one
    const double cap = 0.01 * I_max * K / (J * 2 * Ts);
    const double JL_K = J * L / K;
    EXPECT_EQ(disc.ctrl.pos.lambda_M, cont.ctrl.pos.lambda_M);
    EXPECT_LT(D(cont.ctrl.pos.lambda_M) / JL_K, cap);
    // raised toward the motor's limits: capped, ratio kept; the continuous design is not
    in.bound_load_Nm = 0.475;
    in.bound_load_rate_Nm_s = 40.0;
    ASSERT_TRUE(drive_design(&in, &disc, err, sizeof err)) << err;
    in.gain_design = DRIVE_GAIN_CONTINUOUS;
    ASSERT_TRUE(drive_design(&in, &cont, err, sizeof err)) << err;
    EXPECT_NEAR(D(disc.ctrl.pos.lambda_M) / JL_K / cap, 1.0, 1e-3);
    EXPECT_NEAR(D(disc.ctrl.pos.lambda_m) / D(disc.ctrl.pos.lambda_M),
                D(cont.ctrl.pos.lambda_m) / D(cont.ctrl.pos.lambda_M), 1e-3);
    EXPECT_GT(D(cont.ctrl.pos.lambda_M) / JL_K, 2 * cap);
    EXPECT_LE(D(disc.est.mech.alpha_Nm) / (J * Ts), cap * (1 + 1e-3));
    EXPECT_GT(D(cont.est.mech.alpha_Nm) / (J * Ts), cap);
    in.gain_design = static_cast<drive_gain_design_t>(7);
    EXPECT_FALSE(drive_design(&in, &disc, err, sizeof err));
    EXPECT_NE(std::string(err).find("gain_design"), std::string::npos) << err;
}

// Section 5.4, open loop below omega_lim, eq. (68): the voltage is put on
// the phases along the reference electrical angle at mid-sample,
// n_p (theta_r[k] + theta_r[k+1])/2, so its average over the held sample
// is the commanded one.
TEST(Drive, OpenLoopVoltageAtTheMidSampleAngle)
{
    paper000_drive_t d;
    ASSERT_TRUE(init_paper_drive(&d));
    // no plant here: the currents stay 0 while the drive applies volts, an
    // open circuit to the observer-error criterion; report, do not react
    d.cfg.prot.reaction[DRIVE_FAULT_LOSS_OF_SYNC] = FAULT_REACT_REPORT;
    d.mon.cfg.stuck_ticks = 1 << 30;  // and to the stuck-sample criterion
    // the reference the drive itself follows (eq. (70) has its own tests;
    // in fixed point it is exact to about 2e-4 rad, 1e-2 rad electrical)
    trajectory_t traj;
    ASSERT_TRUE(trajectory_init(&traj, &d.cfg.traj));
    auto theta_r = [&traj](int tick) {
        trajectory_point_t p;
        trajectory_eval(&traj, static_cast<uint32_t>(tick), &p);
        return D(p.theta_rad);
    };
    // electrical angle error of the rotations: float rounding, or in fixed
    // point the 3.8e-4 rad electrical LSB of n_p theta plus the sincos error
    const double kAngleTol = MC_FIXED ? 1e-3 : 2e-5;
    double worst = 0.0, worst_start = 0.0;
    mc_t va, vb;
    for (int k = 0; k < 2300; ++k) {  // to omega_r = 2.6 rad/s, still open loop
        ASSERT_TRUE(step2(&d, M(0), M(0), &va, &vb)) << k << " fault " << d.sup.fault;
        ASSERT_EQ(tlm_of(d).mode, DRIVE_MODE_OPEN_LOOP);
        if (k < 1500) continue;  // omega_r >= 0.9 rad/s: half a sample is >= 2.3 mrad electrical
        const double mid = 50.0 * 0.5 * (theta_r(k) + theta_r(k + 1));
        const double got = std::atan2(D(vb), D(va));
        worst = std::fmax(worst, std::fabs(std::remainder(got - mid, 2 * kPi)));
        worst_start = std::fmax(worst_start, std::fabs(50.0 * (theta_r(k + 1) - theta_r(k)) / 2));
    }
    EXPECT_LT(worst, kAngleTol) << "phase voltage not at the mid-sample angle";
    EXPECT_GT(worst_start, 5 * kAngleTol);  // the test can tell start-of-sample from mid-sample
}

TEST(Drive, BadConfigGoesToSafeState)
{
    drive_design_input_t in = paper_input();
    paper000_config_t cfg;
    char err[160];
    ASSERT_TRUE(drive_design(&in, &cfg, err, sizeof err));
    EXPECT_EQ(paper000_config_problem(&cfg), nullptr);
    cfg.limits.i_trip_A = M(1.0);  // below i_max: inconsistent
    // the problem names the field
    ASSERT_NE(paper000_config_problem(&cfg), nullptr);
    EXPECT_EQ(std::string(paper000_config_problem(&cfg)).rfind("limits.i_trip_A:", 0), 0u) << paper000_config_problem(&cfg);
    paper000_drive_t d;
    EXPECT_FALSE(paper000_drive_init(&d, &cfg));
    mc_t va = M(5), vb = M(5);
    EXPECT_FALSE(step2(&d, M(0), M(0), &va, &vb));
    EXPECT_EQ(D(va), 0.0);
    EXPECT_EQ(D(vb), 0.0);
    EXPECT_EQ(tlm_of(d).mode, DRIVE_MODE_FAULT);
    EXPECT_EQ(tlm_of(d).fault, DRIVE_FAULT_BAD_INPUT);
}

TEST(Drive, SampleOfAnotherPhaseCountIsABadInputFault)
{
    paper000_drive_t d;
    ASSERT_TRUE(init_paper_drive(&d));
    hal_sample_t in{};
    in.n_phases = 3;
    hal_command_t out{};
    out.v_V[0] = M(5);
    EXPECT_FALSE(paper000_drive_step(&d, &in, &out));
    EXPECT_EQ(D(out.v_V[0]), 0.0);
    EXPECT_EQ(tlm_of(d).fault, DRIVE_FAULT_BAD_INPUT);
    EXPECT_EQ(tlm_of(d).mode, DRIVE_MODE_FAULT);
}

TEST(Drive, OvercurrentTripsAndStaysSafe)
{
    paper000_drive_t d;
    ASSERT_TRUE(init_paper_drive(&d));
    mc_t va, vb;
    EXPECT_TRUE(step2(&d, M(0.1), M(0.0), &va, &vb));
    EXPECT_GT(std::fabs(D(va)) + std::fabs(D(vb)), 1.0);  // open loop holds the rotor
    EXPECT_FALSE(step2(&d, M(7.0), M(0.0), &va, &vb));
    EXPECT_EQ(D(va), 0.0);
    EXPECT_EQ(tlm_of(d).fault, DRIVE_FAULT_OVERCURRENT);
    for (int k = 0; k < 10; ++k) {  // latched until paper000_drive_init
        EXPECT_FALSE(step2(&d, M(0.0), M(0.0), &va, &vb));
        EXPECT_EQ(D(va), 0.0);
        EXPECT_EQ(D(vb), 0.0);
    }
}

TEST(Drive, OpenLoopAtStandstillFollowsEq68AndPhaseVoltagesStayWithinVmax)
{
    paper000_drive_t d;
    ASSERT_TRUE(init_paper_drive(&d));
    mc_t va, vb;
    ASSERT_TRUE(step2(&d, M(0), M(0), &va, &vb));
    // theta_r = 0 at t = 0: v along phase a with magnitude R I (68), I the
    // design's open-loop current, 2/3 of I_max (OPEN_LOOP_OVER_IMAX)
    EXPECT_NEAR(D(va), 3.01 * 3.0 * 2.0 / 3.0, 1e-3);
    EXPECT_NEAR(D(vb), 0.0, 1e-3);
    EXPECT_EQ(tlm_of(d).mode, DRIVE_MODE_OPEN_LOOP);
    // absurd currents just below the trip: whatever the law asks, |v| <= V_max
    for (int k = 0; k < 200; ++k) {
        const double ia = 5.9 * std::sin(0.3 * k), ib = -5.9 * std::cos(0.7 * k);
        step2(&d, M(ia), M(ib), &va, &vb);
        EXPECT_LE(std::fabs(D(va)), 30.0 + 1e-4);
        EXPECT_LE(std::fabs(D(vb)), 30.0 + 1e-4);
    }
}

// ---- faults during the start (issue 26) ----

namespace {
// The rig's windings as an R-L circuit each (exact zero-order hold of the
// voltage the drive commanded), the rotor held: what the start sees at
// standstill. A small ripple keeps the samples changing (no stuck-sample
// fault).
struct RlRig {
    double R = 3.01, L = 9e-3, Ts = 1e-4;
    double ia = 0.0, ib = 0.0;
    int k = 0;
    void apply(const hal_command_t &out)
    {
        const double a = std::exp(-R * Ts / L);
        ia = a * ia + (1.0 - a) * D(out.v_V[0]) / R;
        ib = a * ib + (1.0 - a) * D(out.v_V[1]) / R;
        ++k;
    }
    hal_sample_t sample(uint32_t status = 0u) const
    {
        hal_sample_t s{};
        s.n_phases = 2;
        s.tick = static_cast<uint32_t>(k);
        s.i_A[0] = M(ia + 1e-3 * std::sin(0.37 * k));
        s.i_A[1] = M(ib + 1e-3 * std::cos(0.23 * k));
        s.v_bus_V = M(30.0);
        s.status = status;
        return s;
    }
};
// one sample of the drive on the rig, the sample possibly altered first
bool rig_step(paper000_drive_t *d, RlRig *rig, hal_command_t *out, double ia_A = NAN, double ib_A = NAN, uint32_t status = 0u)
{
    hal_sample_t s = rig->sample(status);
    if (!std::isnan(ia_A)) s.i_A[0] = M(ia_A);
    if (!std::isnan(ib_A)) s.i_A[1] = M(ib_A);
    out->v_V[0] = M(99.0);  // must be overwritten, fault or not
    out->v_V[1] = M(99.0);
    const bool ok = paper000_drive_step(d, &s, out);
    rig->apply(*out);
    return ok;
}
bool init_drive(paper000_drive_t *d, bool align)
{
    drive_design_input_t in = paper_input();
    in.align_rotor = align ? 1 : 0;
    paper000_config_t cfg;
    char err[160];
    return drive_design(&in, &cfg, err, sizeof err) && paper000_drive_init(d, &cfg);
}
}  // namespace

// An over-current sample in the middle of the standstill R/L measurement
// (startup/rl_identification.h, state IDENTIFY): a sample at the trip
// itself (-4.5 A on phase b) is not beyond it; -4.52 A is: FAULT at once
// with code OVERCURRENT, 0 V on both phases on that very sample, the
// snapshot frozen at it; the measurement never completes (no measured R
// replaces the model's) and the fault latches: 200 more samples of
// ordinary currents give 0 V, no new event, nothing measured.
TEST(Drive, OvercurrentDuringTheRlMeasurementTripsAndLatches)
{
    static paper000_drive_t d;
    ASSERT_TRUE(init_drive(&d, false));
    const double R_model = D(d.model.R_ohm);
    RlRig rig;
    hal_command_t out;
    const int n_half = d.cfg.rl_id.window_ticks / 4;
    ASSERT_GT(n_half, 10);
    for (int k = 0; k < n_half; ++k) ASSERT_TRUE(rig_step(&d, &rig, &out)) << k;
    ASSERT_EQ(d.sup.state, SUP_STATE_IDENTIFY);
    ASSERT_EQ(d.rl_id.state, RL_ID_RUNNING);
    EXPECT_GT(D(out.v_V[0]), 5.0);  // the step's R I along phase a
    ASSERT_TRUE(rig_step(&d, &rig, &out, NAN, -4.5)) << "a sample at the trip is not beyond it";
    const uint32_t t_trip = d.tick;
    const int32_t rl_k = d.rl_id.k;
    EXPECT_FALSE(rig_step(&d, &rig, &out, NAN, -4.52));
    EXPECT_EQ(D(out.v_V[0]), 0.0);
    EXPECT_EQ(D(out.v_V[1]), 0.0);
    EXPECT_EQ(d.sup.state, SUP_STATE_FAULT);
    EXPECT_EQ(d.sup.fault, DRIVE_FAULT_OVERCURRENT);
    EXPECT_EQ(tlm_of(d).mode, DRIVE_MODE_FAULT);
    const flight_recorder_t *fr = paper000_drive_flight_recorder(&d);
    EXPECT_TRUE(fr->frozen);
    EXPECT_EQ(fr->fault, DRIVE_FAULT_OVERCURRENT);
    EXPECT_EQ(fr->fault_tick, t_trip);
    EXPECT_EQ(fr->events, 1u);
    ASSERT_GT(flight_recorder_count(fr), 0u);
    EXPECT_EQ(flight_recorder_get(fr, flight_recorder_count(fr) - 1)->tick + 1, t_trip);
    for (int k = 0; k < 200; ++k) {
        EXPECT_FALSE(rig_step(&d, &rig, &out)) << k;
        EXPECT_EQ(D(out.v_V[0]), 0.0);
        EXPECT_EQ(D(out.v_V[1]), 0.0);
    }
    EXPECT_EQ(d.sup.state, SUP_STATE_FAULT);
    EXPECT_EQ(fr->events, 1u);
    EXPECT_EQ(d.rl_id.state, RL_ID_RUNNING) << "the measurement went on after the trip";
    EXPECT_EQ(d.rl_id.k, rl_k);
    EXPECT_EQ(D(d.model.R_ohm), R_model);
    EXPECT_EQ(tlm_of(d).fault, DRIVE_FAULT_OVERCURRENT);
}

// The rotor alignment (startup/align.h) inside the drive: for its
// align_total_ticks samples the state is ALIGN and the phase voltages are
// the stages' (f-g) vector at theta_r(0) = 0 (phase a = v_f, b = v_g) for
// the hold voltage R I of (68) at rest; on the next sample the drive
// starts the R/L measurement (IDENTIFY) with R I along phase a.
TEST(Drive, AlignmentStagesThenTheMeasurement)
{
    static paper000_drive_t d;
    ASSERT_TRUE(init_drive(&d, true));
    const align_config_t &c = d.cfg.align;
    const int n = align_total_ticks(&c);
    ASSERT_GT(n, 1000);
    const double V = D(d.model.R_ohm) * D(d.cfg.open_loop.i_max_A), phi = D(c.phi_turn_rad);
    const int ramp = c.ramp_ticks, hold = c.hold_ticks, turn = c.turn_ticks, settle = c.settle_ticks;
    RlRig rig;
    hal_command_t out;
    for (int k = 0; k < n; ++k) {
        ASSERT_EQ(d.sup.state, SUP_STATE_ALIGN) << k;
        ASSERT_TRUE(rig_step(&d, &rig, &out)) << k;
        double vf = 0.0, vg = 0.0;
        int j = k;
        if (j < ramp) {
            vf = V * (j + 1) / ramp;
        } else if ((j -= ramp) < hold) {
            vf = V;
        } else if ((j -= hold) < 2 * turn) {
            const int m = j < turn ? j + 1 : 2 * turn - (j + 1);
            vf = V * std::cos(phi * m / turn);
            vg = V * std::sin(phi * m / turn);
        } else if ((j -= 2 * turn) < settle) {
            vf = V;
        } else if ((j -= settle) < ramp) {
            vf = V * (ramp - (j + 1)) / ramp;
        }
        ASSERT_NEAR(D(out.v_V[0]), vf, 2e-3) << k;
        ASSERT_NEAR(D(out.v_V[1]), vg, 2e-3) << k;
    }
    ASSERT_TRUE(rig_step(&d, &rig, &out));
    EXPECT_EQ(d.sup.state, SUP_STATE_IDENTIFY);
    EXPECT_NEAR(D(out.v_V[0]), V, 2e-3);
    EXPECT_NEAR(D(out.v_V[1]), 0.0, 2e-3);
}

// Over-current during the alignment with the re-lock reaction configured
// for it: the alignment is no place for a re-lock (the drive has no
// estimate to re-lock on): FAULT at once, no re-lock counted, 0 V.
TEST(Drive, OvercurrentDuringTheAlignmentIsNeverReLocked)
{
    static paper000_drive_t d;
    ASSERT_TRUE(init_drive(&d, true));
    d.cfg.prot.reaction[DRIVE_FAULT_OVERCURRENT] = static_cast<uint8_t>(FAULT_REACT_RELOCK);
    RlRig rig;
    hal_command_t out;
    for (int k = 0; k < 300; ++k) ASSERT_TRUE(rig_step(&d, &rig, &out)) << k;
    ASSERT_EQ(d.sup.state, SUP_STATE_ALIGN);
    EXPECT_FALSE(rig_step(&d, &rig, &out, 4.6));
    EXPECT_EQ(d.sup.state, SUP_STATE_FAULT);
    EXPECT_EQ(d.sup.fault, DRIVE_FAULT_OVERCURRENT);
    EXPECT_EQ(d.relocks, 0);
    EXPECT_EQ(D(out.v_V[0]), 0.0);
    EXPECT_EQ(D(out.v_V[1]), 0.0);
    EXPECT_EQ(paper000_drive_flight_recorder(&d)->events, 1u);
}

// Faults with the REPORT reaction (commissioning): the drive goes on, and
// the flight recorder counts every event (telemetry fault_events) while
// its snapshot, code and tick stay those of the first: three over-current
// samples at 10, 20 and 30 ms, a hardware trip at 40 ms; then an ADC
// fault, whose reaction is the safe state: FAULT with that code, the
// recorder still naming the first over-current (its snapshot ends on the
// sample before it).
TEST(Drive, ReportedFaultsAreEachCountedAndTheFirstIsKept)
{
    static paper000_drive_t d;
    ASSERT_TRUE(init_drive(&d, false));
    d.cfg.prot.reaction[DRIVE_FAULT_OVERCURRENT] = static_cast<uint8_t>(FAULT_REACT_REPORT);
    d.cfg.prot.reaction[DRIVE_FAULT_HW_TRIP] = static_cast<uint8_t>(FAULT_REACT_REPORT);
    RlRig rig;
    hal_command_t out;
    const flight_recorder_t *fr = paper000_drive_flight_recorder(&d);
    for (int k = 0; k < 450; ++k) {
        const bool oc = k == 100 || k == 200 || k == 300;
        const uint32_t status = k == 400 ? HAL_STATUS_PWM_TRIP : 0u;
        ASSERT_TRUE(rig_step(&d, &rig, &out, oc ? -5.0 : NAN, NAN, status)) << k;
        const uint32_t want = (k >= 100) + (k >= 200) + (k >= 300) + (k >= 400);
        ASSERT_EQ(fr->events, want) << k;
        ASSERT_EQ(tlm_of(d).fault_events, want) << k;
    }
    EXPECT_NE(d.sup.state, SUP_STATE_FAULT);
    EXPECT_EQ(fr->fault, DRIVE_FAULT_OVERCURRENT);
    EXPECT_EQ(fr->fault_tick, 100u);
    ASSERT_EQ(flight_recorder_count(fr), FLIGHT_RECORDER_DEPTH);
    EXPECT_EQ(flight_recorder_get(fr, 0)->tick, 100u - FLIGHT_RECORDER_DEPTH);
    EXPECT_EQ(flight_recorder_get(fr, FLIGHT_RECORDER_DEPTH - 1)->tick, 99u);
    EXPECT_FALSE(rig_step(&d, &rig, &out, NAN, NAN, HAL_STATUS_ADC_FAULT));
    EXPECT_EQ(d.sup.fault, DRIVE_FAULT_ADC);
    EXPECT_EQ(fr->events, 5u);
    EXPECT_EQ(fr->fault, DRIVE_FAULT_OVERCURRENT);
    EXPECT_EQ(fr->fault_tick, 100u);
    EXPECT_EQ(flight_recorder_get(fr, FLIGHT_RECORDER_DEPTH - 1)->tick, 99u);
    EXPECT_EQ(D(out.v_V[0]), 0.0);
}

// ---- the PMSM commissioning run (startup/pmsm_identification.h) ----

namespace {
using fwtest::p001_input;
// Its windings as R-L circuits in alpha-beta (R 10 % above the model's,
// L 10 % below, so a measurement differs from the model), the rotor held.
struct PmsmRig {
    double R = 0.225 * 1.1, L = 3.8e-3 * 0.9, Ts = 1e-4;
    mc_ab_t i{M(0.0), M(0.0)};
    mc_t ph[3] = {M(0.0), M(0.0), M(0.0)};
    void apply(mc_ab_t v)
    {
        const double a = std::exp(-R * Ts / L);
        const double ia = a * D(i.alpha) + (1.0 - a) * D(v.alpha) / R;
        const double ib = a * D(i.beta) + (1.0 - a) * D(v.beta) / R;
        i.alpha = M(ia);
        i.beta = M(ib);
        ph[0] = M(ia);
        ph[1] = M(-0.5 * ia + 0.8660254037844386 * ib);
        ph[2] = M(-0.5 * ia - 0.8660254037844386 * ib);
    }
};
}  // namespace

// An over-current sample in each phase of the commissioning run (the two
// alignments, the rest, the R/L step, the spin), on each of the three
// phase currents in turn and of either sign: a sample exactly at the trip
// passes, one 0.05 A beyond it ends the run: REJECTED for "over-current",
// 0 V on that sample, the model's R, L and Phi (not the measured R and L
// the spin already used), and it stays so whatever comes next.
TEST(PmsmIdentification, OvercurrentInAnyPhaseRejectsAndLatches)
{
    const p001_design_input_t in = p001_input();
    pmsm_id_config_t cfg;
    double dur = 0.0;
    char err[160];
    ASSERT_TRUE(p001_identification_design(&in, &cfg, &dur, err, sizeof err)) << err;
    const double trip = D(cfg.i_trip_A);
    const double R0 = D(cfg.model.R_ohm), L0 = D(cfg.model.L_H) * cfg.model.fs_hz, Phi0 = D(cfg.Phi_model_Wb);
    const pmsm_id_phase_t phases[] = {PMSM_ID_ALIGN_BETA, PMSM_ID_ALIGN_ALPHA, PMSM_ID_REST, PMSM_ID_RL, PMSM_ID_SPIN};
    for (const pmsm_id_phase_t target : phases) {
        SCOPED_TRACE("phase " + std::to_string(static_cast<int>(target)));
        static pmsm_id_t id;
        ASSERT_TRUE(pmsm_id_init(&id, &cfg));
        PmsmRig rig;
        mc_ab_t v;
        // into the phase, and some way through it
        int into = 0;
        for (int k = 0; k < 200000 && into < 300; ++k) {
            ASSERT_TRUE(pmsm_id_step(&id, rig.i, rig.ph, 3, M(27.0), &v)) << k << " " << id.why;
            rig.apply(v);
            into = id.phase == target ? into + 1 : 0;
            ASSERT_LE(static_cast<int>(id.phase), static_cast<int>(target));
        }
        ASSERT_EQ(id.phase, target);
        if (target == PMSM_ID_SPIN) {
            ASSERT_NE(D(id.R_ohm), R0) << "the measured R is in use";
        }
        const int j = static_cast<int>(target) % 3;
        const double sign = (static_cast<int>(target) % 2 == 0) ? 1.0 : -1.0;
        mc_t ph[3] = {rig.ph[0], rig.ph[1], rig.ph[2]};
        ph[j] = M(sign * trip);
        ASSERT_TRUE(pmsm_id_step(&id, rig.i, ph, 3, M(27.0), &v)) << "a sample at the trip is not beyond it";
        rig.apply(v);
        ph[0] = rig.ph[0];
        ph[1] = rig.ph[1];
        ph[2] = rig.ph[2];
        ph[j] = M(sign * (trip + 0.05));
        v.alpha = v.beta = M(5.0);
        EXPECT_FALSE(pmsm_id_step(&id, rig.i, ph, 3, M(27.0), &v));
        EXPECT_EQ(id.phase, PMSM_ID_REJECTED);
        EXPECT_STREQ(id.why, "over-current");
        EXPECT_EQ(D(v.alpha), 0.0);
        EXPECT_EQ(D(v.beta), 0.0);
        EXPECT_EQ(D(id.R_ohm), R0);
        EXPECT_NEAR(D(id.L_fs_ohm), L0, 1e-5 * L0);
        EXPECT_EQ(D(id.Phi_Wb), Phi0);
        for (int k = 0; k < 100; ++k) {
            rig.apply(mc_ab_t{M(0.0), M(0.0)});
            v.alpha = v.beta = M(5.0);
            EXPECT_FALSE(pmsm_id_step(&id, rig.i, rig.ph, 3, M(27.0), &v));
            EXPECT_EQ(D(v.alpha), 0.0);
            EXPECT_EQ(D(v.beta), 0.0);
        }
        EXPECT_EQ(id.phase, PMSM_ID_REJECTED);
        EXPECT_STREQ(id.why, "over-current");
    }
}

// Paper 001's drive with a computation delay of d samples (issue 26: no
// test ran it with one): the design's output advance n_p (1/2 + d), the
// voltage the observers integrate (1 - d) v + d v_prev, and the output's
// rotation: the estimate advanced by n_p w_hat (1/2 + d) Ts, each against
// its formula in double (drives/paper001/paper001_drive.h, estimators/flux_speed.h); K_t = 3/2 n_p Phi for
// three phases in IDA-PBC's 1/K_t and J/K_t.
TEST(Paper001Delay, AdvanceAppliedMeanAndOutputRotation)
{
    const double np = 3.0, phi = 0.17, J = 0.012, fs = 10000.0;
    for (const double d : {0.0, 0.5, 1.0}) {
        p001_design_input_t in = p001_input();  // phi = 0.17 Wb, J = 0.012, n_p = 3, 10 kHz
        in.compute_delay_samples = d;
        paper001_config_t cfg;
        p001_design_report_t rep;
        char err[160];
        ASSERT_TRUE(p001_design(&in, &cfg, &rep, err, sizeof err)) << err;
        const double tol = MC_FIXED ? 3e-5 : 1e-6;
        EXPECT_NEAR(mc_to_double(cfg.est.advance_np), np * (0.5 + d), tol * np) << d;
        EXPECT_NEAR(mc_to_double(cfg.compute_delay), d, tol) << d;
        const double kt = 1.5 * np * phi;
        EXPECT_NEAR(mc_to_double(cfg.ctrl.inv_Kt_A_Nm), 1.0 / kt, 1e-3 / kt) << d;
        EXPECT_NEAR(mc_to_double(cfg.ctrl.J_over_Kt_A_s2), J / kt, 1e-3 * J / kt) << d;
        // the applied mean, on a few vectors of both signs
        const double vs[][4] = {{3.0, -2.0, 1.0, 4.0}, {-5.5, 0.25, 2.0, -3.0}, {0.0, 7.0, -7.0, 0.0}};
        for (const auto& v : vs) {
            const mc_ab_t now = {mc_from_double(v[0]), mc_from_double(v[1])}, prev = {mc_from_double(v[2]), mc_from_double(v[3])};
            const mc_ab_t m = paper001_applied_mean(&cfg, now, prev);
            EXPECT_NEAR(mc_to_double(m.alpha), (1.0 - d) * v[0] + d * v[2], 10 * tol) << d;
            EXPECT_NEAR(mc_to_double(m.beta), (1.0 - d) * v[1] + d * v[3], 10 * tol) << d;
        }
        // the output rotation at +-12 rad/s from an angle near +-pi
        for (const double w : {12.0, -12.0}) {
            const double a = (w > 0 ? 3.1 : -3.1);
            mc_rot_t rho;
            rho.s = mc_from_double(std::sin(a));
            rho.c = mc_from_double(std::cos(a));
            const mc_rot_t out = flux_speed_output_rot(&cfg.est, rho, mc_from_double(w));
            const double e = a + w * np * (0.5 + d) / fs;
            EXPECT_NEAR(mc_to_double(out.s), std::sin(e), 20 * tol) << d << " " << w;
            EXPECT_NEAR(mc_to_double(out.c), std::cos(e), 20 * tol) << d << " " << w;
        }
    }
}

// The identification's voltage is limited to the bus with its direction
// kept: through the alignment and into the spin with v_max a tenth of what
// it asks, every output has |v| <= v_max and, where limited, the direction
// the unlimited run has at the same sample (the run is the same: both
// start from rest and the rig only integrates).
TEST(PmsmIdentification, BusLimitKeepsTheDirection)
{
    const p001_design_input_t in = p001_input();
    pmsm_id_config_t cfg;
    double dur = 0.0;
    char err[160];
    ASSERT_TRUE(p001_identification_design(&in, &cfg, &dur, err, sizeof err)) << err;
    const double v_max = 0.1 * D(cfg.v_align_V);
    static pmsm_id_t id;
    ASSERT_TRUE(pmsm_id_init(&id, &cfg));
    PmsmRig rig;
    int limited = 0;
    for (int k = 0; k < 3000; ++k) {
        // what it asks without a limit, from the same state
        static pmsm_id_t probe;
        probe = id;
        mc_ab_t want, v;
        (void)pmsm_id_step(&probe, rig.i, rig.ph, 3, M(1000.0), &want);
        ASSERT_TRUE(pmsm_id_step(&id, rig.i, rig.ph, 3, M(v_max), &v)) << k << " " << id.why;
        const double m = std::hypot(D(v.alpha), D(v.beta)), mw = std::hypot(D(want.alpha), D(want.beta));
        ASSERT_LE(m, v_max * (1 + 1e-4) + 1e-4) << k;
        if (mw > v_max) {
            ++limited;
            // the same direction: the cross product of the unit vectors ~ 0, the dot ~ 1
            EXPECT_NEAR((D(v.alpha) * D(want.beta) - D(v.beta) * D(want.alpha)) / (m * mw), 0.0, 1e-3) << k;
            EXPECT_NEAR((D(v.alpha) * D(want.alpha) + D(v.beta) * D(want.beta)) / (m * mw), 1.0, 1e-3) << k;
        }
        rig.apply(v);
    }
    EXPECT_GT(limited, 100);
}
