// The parts every drive is assembled from: the phase adapter (Clarke and
// its inverse, 2 and 3 phases), the supervisor's state table, fault latch,
// bumpless transfer and voltage limit, and the shared motor model.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

extern "C" {
#include "adapter/phase_adapter.h"
#include "control/fg_tracking.h"
#include "math/mc_convert.h"
#include "model/motor_model.h"
#include "comm/can_tx.h"
#include "startup/align.h"
#include "startup/k_identification.h"
#include "supervisor/fault_monitor.h"
#include "supervisor/flight_recorder.h"
#include "supervisor/supervisor.h"
}

#include "fw_test_util.h"

using fwtest::D;
using fwtest::kPi;
using fwtest::M;

namespace {
#if MC_FIXED
constexpr double kTol = 1e-4;  // a few Q14.17 LSB
#else
constexpr double kTol = 1e-5;
#endif

hal_sample_t sample3(double a, double b, double c)
{
    hal_sample_t s{};
    s.n_phases = 3;
    s.i_A[0] = M(a);
    s.i_A[1] = M(b);
    s.i_A[2] = M(c);
    return s;
}
}  // namespace

// ---- phase adapter ----

// Balanced three-phase currents of amplitude I at angle x are the vector
// I (cos x, sin x) in alpha-beta (amplitude-invariant Clarke), with no
// zero sequence; evaluated here from the phase definitions, not the code.
TEST(PhaseAdapter, ThreePhaseBalancedIsTheRotatingVector)
{
    const double I = 2.5;
    for (int k = 0; k < 24; ++k) {
        const double x = 2 * kPi * k / 24;
        const hal_sample_t s = sample3(I * std::cos(x), I * std::cos(x - 2 * kPi / 3), I * std::cos(x + 2 * kPi / 3));
        mc_t z;
        const mc_ab_t i = phase_adapter_currents(&s, &z);
        EXPECT_NEAR(D(i.alpha), I * std::cos(x), kTol) << k;
        EXPECT_NEAR(D(i.beta), I * std::sin(x), kTol) << k;
        EXPECT_NEAR(D(z), 0.0, kTol) << k;
    }
}

// Unbalanced currents: alpha = (2a - b - c)/3, beta = (b - c)/sqrt(3),
// zero sequence (a + b + c)/3; a common offset added to all three phases
// changes only the zero sequence.
TEST(PhaseAdapter, ThreePhaseUnbalancedAndZeroSequence)
{
    const double a = 1.7, b = -0.4, c = -0.9, off = 0.35;
    for (double o : {0.0, off}) {
        const hal_sample_t s = sample3(a + o, b + o, c + o);
        mc_t z;
        const mc_ab_t i = phase_adapter_currents(&s, &z);
        EXPECT_NEAR(D(i.alpha), (2 * a - b - c) / 3, kTol);
        EXPECT_NEAR(D(i.beta), (b - c) / std::sqrt(3.0), kTol);
        EXPECT_NEAR(D(z), (a + b + c) / 3 + o, kTol);
    }
}

// Inverse: the three leg voltages have the commanded alpha-beta vector
// (Clarke of the legs gives it back), line-to-line voltages are those of
// the vector, and the min/max zero sequence centres the legs: max + min = 0.
TEST(PhaseAdapter, ThreePhaseInverseWithMinMaxZeroSequence)
{
    for (int k = 0; k < 36; ++k) {
        const double x = 2 * kPi * k / 36, V = 7.0;
        const mc_ab_t v = {M(V * std::cos(x)), M(V * std::sin(x))};
        hal_command_t out{};
        phase_adapter_voltages(3, v, &out);
        ASSERT_EQ(out.n_phases, 3);
        const double a = D(out.v_V[0]), b = D(out.v_V[1]), c = D(out.v_V[2]);
        EXPECT_NEAR((2 * a - b - c) / 3, V * std::cos(x), 2 * kTol) << k;
        EXPECT_NEAR((b - c) / std::sqrt(3.0), V * std::sin(x), 2 * kTol) << k;
        EXPECT_NEAR(std::fmax(a, std::fmax(b, c)) + std::fmin(a, std::fmin(b, c)), 0.0, 2 * kTol) << k;
        // the peak a leg needs: half the largest line-to-line voltage
        const double ll = std::fmax(std::fabs(a - b), std::fmax(std::fabs(b - c), std::fabs(c - a)));
        EXPECT_NEAR(D(phase_adapter_peak(3, v)), ll / 2, 2 * kTol) << k;
        // and it never exceeds the vector's magnitude (linear range V_bus/sqrt(3))
        EXPECT_LE(D(phase_adapter_peak(3, v)), V * std::sqrt(3.0) / 2 + 2 * kTol);
    }
    // round trip through the currents' Clarke
    const mc_ab_t v = {M(3.1), M(-4.2)};
    hal_command_t out{};
    phase_adapter_voltages(3, v, &out);
    const hal_sample_t s = sample3(D(out.v_V[0]), D(out.v_V[1]), D(out.v_V[2]));
    mc_t z;
    const mc_ab_t back = phase_adapter_currents(&s, &z);
    EXPECT_NEAR(D(back.alpha), 3.1, 2 * kTol);
    EXPECT_NEAR(D(back.beta), -4.2, 2 * kTol);
}

// Two phases: a and b are alpha and beta, bit for bit both ways (the
// paper-000 drive's bit-exactness rests on it); the peak is per winding.
TEST(PhaseAdapter, TwoPhasesAreAlphaBetaExactly)
{
    hal_sample_t s{};
    s.n_phases = 2;
    s.i_A[0] = M(1.234567);
    s.i_A[1] = M(-2.5);
    mc_t z = M(9);
    const mc_ab_t i = phase_adapter_currents(&s, &z);
    EXPECT_EQ(i.alpha, s.i_A[0]);
    EXPECT_EQ(i.beta, s.i_A[1]);
    EXPECT_EQ(D(z), 0.0);
    hal_command_t out{};
    phase_adapter_voltages(2, i, &out);
    EXPECT_EQ(out.n_phases, 2);
    EXPECT_EQ(out.v_V[0], i.alpha);
    EXPECT_EQ(out.v_V[1], i.beta);
    EXPECT_EQ(D(phase_adapter_peak(2, i)), D(M(2.5)));
    EXPECT_TRUE(phase_adapter_accepts(&s, 2));
    EXPECT_FALSE(phase_adapter_accepts(&s, 3));
}

// ---- supervisor ----

namespace {
supervisor_t sup(bool identify)
{
    supervisor_config_t c{};
    c.blend_decay = M(0.5);
    supervisor_t s;
    supervisor_init(&s, &c, /*align=*/false, identify);
    return s;
}
}  // namespace

// Every (state, event) pair against the table of supervisor.h.
TEST(Supervisor, TransitionTable)
{
    const sup_state_t S[] = {SUP_STATE_IDENTIFY, SUP_STATE_OPEN_LOOP, SUP_STATE_CLOSED_LOOP, SUP_STATE_FAULT,
                             SUP_STATE_ALIGN};
    const sup_event_t E[] = {SUP_EV_IDENTIFIED, SUP_EV_ESTIMATE_TRUSTED, SUP_EV_ESTIMATE_LOST, SUP_EV_FAULT,
                             SUP_EV_ALIGNED};
    // expected[state][event]; ALIGN goes to the start state (IDENTIFY here)
    const sup_state_t want[5][5] = {
        {SUP_STATE_OPEN_LOOP, SUP_STATE_CLOSED_LOOP, SUP_STATE_IDENTIFY, SUP_STATE_FAULT, SUP_STATE_IDENTIFY},
        {SUP_STATE_OPEN_LOOP, SUP_STATE_CLOSED_LOOP, SUP_STATE_OPEN_LOOP, SUP_STATE_FAULT, SUP_STATE_OPEN_LOOP},
        {SUP_STATE_CLOSED_LOOP, SUP_STATE_CLOSED_LOOP, SUP_STATE_OPEN_LOOP, SUP_STATE_FAULT, SUP_STATE_CLOSED_LOOP},
        {SUP_STATE_FAULT, SUP_STATE_FAULT, SUP_STATE_FAULT, SUP_STATE_FAULT, SUP_STATE_FAULT},
        {SUP_STATE_ALIGN, SUP_STATE_ALIGN, SUP_STATE_ALIGN, SUP_STATE_FAULT, SUP_STATE_IDENTIFY},
    };
    for (int i = 0; i < 5; ++i) {
        for (int j = 0; j < 5; ++j) {
            supervisor_t s = sup(true);
            s.state = S[i];
            const bool changed = supervisor_dispatch(&s, E[j]);
            EXPECT_EQ(s.state, want[i][j]) << "state " << i << " event " << j;
            EXPECT_EQ(changed, want[i][j] != S[i]) << "state " << i << " event " << j;
        }
    }
    EXPECT_EQ(sup(true).state, SUP_STATE_IDENTIFY);
    EXPECT_EQ(sup(false).state, SUP_STATE_OPEN_LOOP);
    // with the alignment first: ALIGN, then the start state
    for (bool identify : {true, false}) {
        supervisor_config_t c{};
        supervisor_t s;
        supervisor_init(&s, &c, /*align=*/true, identify);
        EXPECT_EQ(s.state, SUP_STATE_ALIGN);
        EXPECT_TRUE(supervisor_dispatch(&s, SUP_EV_ALIGNED));
        EXPECT_EQ(s.state, identify ? SUP_STATE_IDENTIFY : SUP_STATE_OPEN_LOOP);
        EXPECT_EQ(supervisor_mode(&s), DRIVE_MODE_OPEN_LOOP);
    }
}

TEST(Supervisor, FaultLatchesTheFirstCause)
{
    supervisor_t s = sup(false);
    supervisor_fault(&s, DRIVE_FAULT_OVERCURRENT);
    supervisor_fault(&s, DRIVE_FAULT_BAD_INPUT);
    EXPECT_EQ(s.state, SUP_STATE_FAULT);
    EXPECT_EQ(s.fault, DRIVE_FAULT_OVERCURRENT);
    EXPECT_EQ(supervisor_mode(&s), DRIVE_MODE_FAULT);
    EXPECT_FALSE(supervisor_dispatch(&s, SUP_EV_ESTIMATE_TRUSTED));
}

// Bumpless: at a switch the applied voltage stays the last one, then the
// offset decays by blend_decay per sample to 0.
TEST(Supervisor, BlendRemovesTheStepAndDecays)
{
    supervisor_t s = sup(false);
    s.v_prev_V[0] = M(4.0);
    s.v_prev_V[1] = M(-2.0);
    mc_t v1 = M(1.0), v2 = M(1.0);
    supervisor_blend(&s, true, &v1, &v2);
    EXPECT_NEAR(D(v1), 4.0, kTol);
    EXPECT_NEAR(D(v2), -2.0, kTol);
    v1 = M(1.0);
    v2 = M(1.0);
    supervisor_blend(&s, false, &v1, &v2);
    EXPECT_NEAR(D(v1), 1.0 + 1.5, kTol);  // offset 3 V halved
    EXPECT_NEAR(D(v2), 1.0 - 1.5, kTol);
    for (int k = 0; k < 40; ++k) {
        v1 = M(1.0);
        v2 = M(1.0);
        supervisor_blend(&s, false, &v1, &v2);
    }
    EXPECT_EQ(D(s.blend_V[0]), 0.0);
    EXPECT_EQ(D(v1), 1.0);
}

// The limit scales the phase vector and the control-frame command by the
// same factor, onto the limit, and records it for the next step.
TEST(Supervisor, LimitKeepsTheDirection)
{
    supervisor_t s = sup(false);
    mc_ab_t v = {M(40.0), M(-10.0)};
    mc_t v1 = M(30.0), v2 = M(20.0);
    EXPECT_TRUE(supervisor_limit(&s, 2, M(30.0), &v, &v1, &v2));
    EXPECT_NEAR(D(v.alpha), 30.0, 1e-3);
    EXPECT_NEAR(D(v.beta), -7.5, 1e-3);
    EXPECT_NEAR(D(v1), 22.5, 1e-3);
    EXPECT_NEAR(D(v2), 15.0, 1e-3);
    EXPECT_TRUE(s.sat_prev);
    EXPECT_EQ(s.v_prev_V[0], v1);
    v = {M(3.0), M(-1.0)};
    v1 = M(2.0);
    EXPECT_FALSE(supervisor_limit(&s, 2, M(30.0), &v, &v1, &v2));
    EXPECT_EQ(D(v.alpha), D(M(3.0)));
    EXPECT_FALSE(s.sat_prev);
}

// ---- motor model ----

// A measured R and L replace every coefficient derived from them, as the
// design (double precision) would have rounded them.
TEST(MotorModel, SetRlUpdatesEveryDerivedCoefficient)
{
    motor_model_t m{};
    m.n_p = 50;
    m.fs_hz = 10000;
    m.J_over_K_A_s2 = M(3.18e-4 / 0.27);
    m.fv_over_K_A_s = M(2.37e-3 / 0.27);
    const double R = 3.3, L = 8e-3, Ts = 1e-4;
    motor_model_set_rl(&m, M(R), M(L / Ts));
    EXPECT_NEAR(D(m.R_ohm), R, kTol);
    EXPECT_NEAR(D(m.L_H), L, kTol);
    EXPECT_NEAR(D(m.npL_ohm_s), 50 * L, kTol);
    EXPECT_NEAR(D(m.ts_over_L_A_per_V), Ts / L, kTol);
    EXPECT_NEAR(D(m.LJ_over_KTs_V_s2), L * 3.18e-4 / (0.27 * Ts), 10 * kTol);
    EXPECT_NEAR(D(m.Lfv_over_KTs_V_s), L * 2.37e-3 / (0.27 * Ts), 10 * kTol);
}

// ---- paper 000's references, eqs. (38)-(39) (control/fg_tracking) ----

// i_g,r = (J theta_r'' + f_v theta_r')/K + C_r/K (load fed forward, clamped),
// i_f,r = the flat constant; v_f,r and v_g,r from (38) with L di_g,r/dt
// taken as L/Ts times the change of i_g,r's model part over the sample
// (the jerk term of (39)). Evaluated here in double from those equations.
TEST(FgTracking, ReferencesFollowEq38And39)
{
    const double R = 3.01, L = 9e-3, K = 0.27, J = 3.18e-4, fv = 2.37e-3, Ts = 1e-4, np = 50;
    motor_model_t m{};
    m.n_p = 50;
    m.fs_hz = 10000;
    m.R_ohm = M(R);
    m.npL_ohm_s = M(np * L);
    m.K_V_s = M(K);
    m.J_over_K_A_s2 = M(J / K);
    m.fv_over_K_A_s = M(fv / K);
    m.LJ_over_KTs_V_s2 = M(L * J / (K * Ts));
    m.Lfv_over_KTs_V_s = M(L * fv / (K * Ts));
    fg_tracking_config_t c{};
    c.i_f_ref_A = M(0.0);
    c.load_ff_A_per_Nm = M(1.0 / K);
    c.load_ff_max_Nm = M(0.11);
    fg_tracking_t t;
    fg_tracking_init(&t, &c);
    const double w = 12.0, a = 35.0, w1 = 12.0035, a1 = 34.6;  // this sample and the next
    const trajectory_point_t r = {M(3.0), M(w), M(a)}, rn = {M(3.0012), M(w1), M(a1)};
    for (double load : {0.05, 0.3}) {  // within the trusted bound, and beyond it (clamped to 0.11)
        mc_t i_fr, i_gr, v_fr, v_gr;
        fg_tracking_references(&t, &m, M(3.0), &r, &rn, M(load), &i_fr, &i_gr, &v_fr, &v_gr);
        const double Cr = std::fmin(load, 0.11);
        const double igr = (J * a + fv * w + Cr) / K;
        const double Ldig = L * ((J * a1 + fv * w1) - (J * a + fv * w)) / (K * Ts);
        EXPECT_NEAR(D(i_fr), 0.0, kTol);
        EXPECT_NEAR(D(i_gr), igr, 2 * kTol) << load;
        EXPECT_NEAR(D(v_fr), R * 0.0 - np * L * w * igr, 5 * kTol) << load;
        EXPECT_NEAR(D(v_gr), Ldig + R * igr + np * L * w * 0.0 + K * w, 5 * kTol) << load;
    }
}

// ---- rotor alignment (startup/align.h) ----

// The voltage of each stage, its length, no step larger than one ramp
// increment, 0 V at the end and from then on.
TEST(Align, ProfileStagesAndNoVoltageStep)
{
    align_config_t c{};
    c.enabled = true;
    c.ramp_ticks = 10;
    c.hold_ticks = 20;
    c.turn_ticks = 15;
    c.settle_ticks = 20;
    c.off_ticks = 5;
    c.phi_turn_rad = M(1.5707963267948966);
    ASSERT_EQ(align_total_ticks(&c), 2 * 10 + 20 + 2 * 15 + 20 + 5);
    align_t a;
    align_init(&a, &c);
    const double V = 9.03;
    double vf_prev = 0.0, vg_prev = 0.0, max_step = 0.0, max_phi = 0.0;
    int n = 0;
    mc_t vf, vg;
    while (!align_step(&a, M(V), &vf, &vg)) {
        const double f = D(vf), g = D(vg);
        max_step = std::fmax(max_step, std::hypot(f - vf_prev, g - vg_prev));
        max_phi = std::fmax(max_phi, std::atan2(g, f));
        EXPECT_LE(std::hypot(f, g), V * (1 + 1e-5) + 1e-4) << n;
        if (n >= 10 && n < 30) {
            EXPECT_NEAR(f, V, 1e-4) << n;  // hold at angle 0
        }
        vf_prev = f;
        vg_prev = g;
        ++n;
        ASSERT_LT(n, 1000);
    }
    EXPECT_EQ(n, align_total_ticks(&c));
    EXPECT_NEAR(vf_prev, 0.0, 1e-6);  // off at the end
    EXPECT_NEAR(vg_prev, 0.0, 1e-6);
    // ramps of V/10 per sample; the turn moves the vector by at most
    // V * (pi/2)/15 (a chord is shorter than its arc)
    EXPECT_LE(max_step, V * std::fmax(0.1, 1.5707963267948966 / 15) * (1 + 1e-4) + 1e-4);
    EXPECT_NEAR(max_phi, 1.5707963267948966, 1e-3);
    EXPECT_TRUE(align_step(&a, M(V), &vf, &vg));
    EXPECT_EQ(D(vf), 0.0);
    c.enabled = false;
    EXPECT_EQ(align_total_ticks(&c), 0);
}

// ---- fault monitor (supervisor/fault_monitor.h) ----

namespace {
fault_monitor_config_t rig_faults()
{
    fault_monitor_config_t c{};
    c.i_trip_A = M(4.5);
    c.i2t_cont_A2 = M(9.0);                           // I_max = 3 A
    c.i2t_gain = M(FAULT_I2T_DECIMATION * 1e-4 / 1.0);  // t_overload 1 s at 10 kHz
    c.i2t_limit_A2 = M(4.5 * 4.5 - 9.0);
    c.sat_max_ticks = 1000;
    c.stuck_ticks = 50;
    c.stuck_dv_V = M(2.0);
    c.i_rail_A = M(0.0);
    c.rail_ticks = 2;
    c.overrun_weight = 1000;
    c.overrun_limit = 3000;
    return c;
}
hal_sample_t two(double a, double b)
{
    hal_sample_t s{};
    s.n_phases = 2;
    s.i_A[0] = M(a);
    s.i_A[1] = M(b);
    s.v_bus_V = M(30.0);
    return s;
}
}  // namespace

// The ADC rail (i_rail_A = 4 A, below the 4.5 A trip; rail_ticks = 3):
// the third sample in a row at either rail, on any phase, trips
// SENSOR_RAIL; a sample off the rail restarts the count; an unknown rail
// (0) never trips.
TEST(FaultMonitor, RailOnEitherRailForRailTicks)
{
    fault_monitor_config_t c = rig_faults();
    c.i_rail_A = M(4.0);
    c.rail_ticks = 3;
    const double rails[][2] = {{4.0, 0.5}, {0.5, -4.0}, {-4.0, 0.5}, {0.5, 4.2}};
    for (const auto& r : rails) {
        fault_monitor_t m;
        fault_monitor_init(&m, &c);
        const hal_sample_t at = two(r[0], r[1]), off = two(0.5, 0.5);
        EXPECT_EQ(fault_monitor_sample(&m, &at, 2), DRIVE_FAULT_NONE);
        EXPECT_EQ(fault_monitor_sample(&m, &at, 2), DRIVE_FAULT_NONE);
        EXPECT_EQ(fault_monitor_sample(&m, &off, 2), DRIVE_FAULT_NONE);  // restarts the count
        EXPECT_EQ(fault_monitor_sample(&m, &at, 2), DRIVE_FAULT_NONE);
        EXPECT_EQ(fault_monitor_sample(&m, &at, 2), DRIVE_FAULT_NONE);
        EXPECT_EQ(fault_monitor_sample(&m, &at, 2), DRIVE_FAULT_SENSOR_RAIL) << r[0] << ", " << r[1];
    }
    c.i_rail_A = M(0.0);
    fault_monitor_t m;
    fault_monitor_init(&m, &c);
    for (int k = 0; k < 10; ++k) EXPECT_EQ(fault_monitor_sample(&m, &(const hal_sample_t&)two(-4.4, 4.4), 2), DRIVE_FAULT_NONE);
}

// The over-current trip on consecutive samples (i_trip_samples): 1, and 0
// (a zeroed configuration), trip on the first sample beyond i_trip; 2
// ignores single samples beyond it, on either phase, and trips on the
// second of two in a row even when the phase beyond it changes.
TEST(FaultMonitor, OvercurrentOnConsecutiveSamples)
{
    fault_monitor_t m;
    fault_monitor_config_t c = rig_faults();
    for (int n : {0, 1}) {
        c.i_trip_samples = n;
        fault_monitor_init(&m, &c);
        EXPECT_EQ(fault_monitor_sample(&m, &(const hal_sample_t &)two(1.0, 0.5), 2), DRIVE_FAULT_NONE);
        EXPECT_EQ(fault_monitor_sample(&m, &(const hal_sample_t &)two(1.0, -4.6), 2), DRIVE_FAULT_OVERCURRENT) << n;
    }
    c.i_trip_samples = 2;
    fault_monitor_init(&m, &c);
    for (int k = 0; k < 100; ++k) {
        const double a = (k % 4 == 0) ? 5.0 : 1.0, b = (k % 4 == 2) ? -5.0 : 1.0;
        ASSERT_EQ(fault_monitor_sample(&m, &(const hal_sample_t &)two(a, b), 2), DRIVE_FAULT_NONE) << k;
    }
    EXPECT_EQ(fault_monitor_sample(&m, &(const hal_sample_t &)two(4.6, 0.0), 2), DRIVE_FAULT_NONE);
    EXPECT_EQ(fault_monitor_sample(&m, &(const hal_sample_t &)two(0.0, -4.6), 2), DRIVE_FAULT_OVERCURRENT);
}

// I^2 t: a current vector of 4.2 A (just below the 4.5 A trip) trips after
// (4.5^2 - 9)/(4.2^2 - 9) = 1.31 s; 3 A never; the integral cools below I_max.
TEST(FaultMonitor, I2tTripsAfterTheOverloadTime)
{
    fault_monitor_t m;
    const fault_monitor_config_t c = rig_faults();
    fault_monitor_init(&m, &c);
    // a rotating 4.2 A vector: |i|^2 = 17.64 A^2 in every sample
    int k = 0;
    drive_fault_t f = DRIVE_FAULT_NONE;
    for (; k < 30000 && f == DRIVE_FAULT_NONE; ++k) {
        const double a = 0.01 * k;
        f = fault_monitor_sample(&m, &(const hal_sample_t &)two(4.2 * std::cos(a), 4.2 * std::sin(a)), 2);
    }
    EXPECT_EQ(f, DRIVE_FAULT_I2T);
    const double t = k * 1e-4, want = (4.5 * 4.5 - 9.0) / (4.2 * 4.2 - 9.0);
    EXPECT_NEAR(t, want, 0.01) << "tripped after " << t << " s";
    // at I_max for 10 s: nothing
    fault_monitor_init(&m, &c);
    for (k = 0; k < 100000; ++k) {
        const double a = 0.01 * k;
        ASSERT_EQ(fault_monitor_sample(&m, &(const hal_sample_t &)two(3.0 * std::cos(a), 3.0 * std::sin(a)), 2),
                  DRIVE_FAULT_NONE) << k;
    }
    // half the overload, a rest at 1 A cools it, the other half: no trip
    fault_monitor_init(&m, &c);
    for (k = 0; k < 6000; ++k) ASSERT_EQ(fault_monitor_sample(&m, &(const hal_sample_t &)two(4.2, 0.0), 2), DRIVE_FAULT_NONE);
    for (k = 0; k < 20000; ++k) ASSERT_EQ(fault_monitor_sample(&m, &(const hal_sample_t &)two(1.0, 0.0), 2), DRIVE_FAULT_NONE);
    EXPECT_EQ(mc_to_double(m.i2t_A2), 0.0);
    for (k = 0; k < 6000; ++k) ASSERT_EQ(fault_monitor_sample(&m, &(const hal_sample_t &)two(4.2, 0.0), 2), DRIVE_FAULT_NONE);
}

// Voltage saturation: 1000 saturated samples in a row are allowed, the
// 1001st trips; a single unsaturated sample restarts the count.
TEST(FaultMonitor, SaturationTooLong)
{
    fault_monitor_t m;
    const fault_monitor_config_t c = rig_faults();
    fault_monitor_init(&m, &c);
    hal_command_t out{};
    out.n_phases = 2;
    for (int k = 0; k < 999; ++k) ASSERT_EQ(fault_monitor_command(&m, &out, true), DRIVE_FAULT_NONE);
    ASSERT_EQ(fault_monitor_command(&m, &out, false), DRIVE_FAULT_NONE);
    for (int k = 0; k < 1000; ++k) ASSERT_EQ(fault_monitor_command(&m, &out, true), DRIVE_FAULT_NONE) << k;
    EXPECT_EQ(fault_monitor_command(&m, &out, true), DRIVE_FAULT_VOLTAGE_SATURATION);
}

// Stuck: identical samples while the command is constant are fine (a
// settled current); while it swings by 2 V, 50 of them trip.
TEST(FaultMonitor, StuckOnlyWhileTheVoltageMoves)
{
    fault_monitor_t m;
    const fault_monitor_config_t c = rig_faults();
    fault_monitor_init(&m, &c);
    hal_command_t out{};
    out.n_phases = 2;
    out.v_V[0] = M(9.0);
    ASSERT_EQ(fault_monitor_command(&m, &out, false), DRIVE_FAULT_NONE);  // 9 V already before
    for (int k = 0; k < 500; ++k) {
        ASSERT_EQ(fault_monitor_sample(&m, &(const hal_sample_t &)two(3.0, 0.0), 2), DRIVE_FAULT_NONE);
        ASSERT_EQ(fault_monitor_command(&m, &out, false), DRIVE_FAULT_NONE);
    }
    drive_fault_t f = DRIVE_FAULT_NONE;
    int k = 0;
    for (; k < 500 && f == DRIVE_FAULT_NONE; ++k) {
        f = fault_monitor_sample(&m, &(const hal_sample_t &)two(3.0, 0.1 * (k % 2)), 2);
        out.v_V[0] = M((k % 2) ? 6.0 : 9.0);
        (void)fault_monitor_command(&m, &out, false);
    }
    EXPECT_EQ(f, DRIVE_FAULT_SENSOR_STUCK);
    EXPECT_LE(k, 52);
}

// ---- K in closed loop (startup/k_identification.h) ----

namespace {
k_id_config_t k_cfg(double K_model)
{
    k_id_config_t c{};
    c.enabled = true;
    c.w_min_rad_s = M(6.0);
    c.inv_w_scale_s = M(1.0 / 20.0);
    c.n_window = 500;
    c.K_model_V_s = M(K_model);
    c.deadband = M(0.03);
    return c;
}
// |e| = K |w| along a speed ramp, with +-5 % of deterministic ripple on |e|
double k_run(k_id_t* k, double K_true)
{
    int n = 0;
    for (int i = 0; i < 5000 && k->state == K_ID_RUNNING; ++i) {
        const double w = -20.0 * std::sin(0.001 * i);  // both signs, below w_min at times
        const double e = K_true * std::fabs(w) * (1.0 + 0.05 * std::sin(0.37 * i));
        k_id_step(k, M(e * e), M(w));
        ++n;
    }
    return D(k->K_V_s);
}
}  // namespace

// A plant K 15 % above or below the model's is measured within 1 %; within
// the 3 % deadband the model is kept; beyond [1/2, 2] it is rejected;
// nothing before n_window samples above w_min.
TEST(KIdentification, MeasuresKeepsAndRejects)
{
    for (double f : {0.85, 1.15}) {
        k_id_t k;
        const k_id_config_t c = k_cfg(0.27);
        k_id_init(&k, &c);
        const double K = k_run(&k, 0.27 * f);
        EXPECT_EQ(k.state, K_ID_DONE) << f;
        EXPECT_NEAR(K / (0.27 * f), 1.0, 0.01) << f;
        EXPECT_EQ(k.n, 500);
    }
    k_id_t k;
    const k_id_config_t c = k_cfg(0.27);
    k_id_init(&k, &c);
    k_run(&k, 0.27 * 1.02);
    EXPECT_EQ(k.state, K_ID_KEPT);
    k_id_init(&k, &c);
    k_run(&k, 0.27 * 2.5);
    EXPECT_EQ(k.state, K_ID_REJECTED);
    EXPECT_EQ(D(k.K_V_s), D(M(0.27)));
    k_id_init(&k, &c);
    for (int i = 0; i < 2000; ++i) EXPECT_FALSE(k_id_step(&k, M(1.0), M(5.9)));  // below w_min
    EXPECT_EQ(k.state, K_ID_RUNNING);
    EXPECT_EQ(k.n, 0);
}

// motor_model_set_K rescales every K-folded field by K_old/K_new.
TEST(KIdentification, ModelSetK)
{
    motor_model_t m{};
    m.K_V_s = M(0.27);
    m.J_over_K_A_s2 = M(3.18e-4 / 0.27 * 1000.0);  // scaled up to be resolvable in Q14.17
    m.fv_over_K_A_s = M(2.37e-3 / 0.27 * 100.0);
    m.LJ_over_KTs_V_s2 = M(0.106);
    m.Lfv_over_KTs_V_s = M(0.79);
    const double r = 0.27 / 0.31;
    const double j = D(m.J_over_K_A_s2), fv = D(m.fv_over_K_A_s);
    motor_model_set_K(&m, M(0.31));
    const double tol = MC_FIXED ? 1e-4 : 1e-6;
    EXPECT_NEAR(D(m.K_V_s), 0.31, tol);
    EXPECT_NEAR(D(m.J_over_K_A_s2), j * r, tol * 10);
    EXPECT_NEAR(D(m.fv_over_K_A_s), fv * r, tol * 10);
    EXPECT_NEAR(D(m.LJ_over_KTs_V_s2), 0.106 * r, tol);
    EXPECT_NEAR(D(m.Lfv_over_KTs_V_s), 0.79 * r, tol);
}

// ---- CAN telemetry schedule (comm/can_tx.h) ----

// Default rates over 1 s at 10 kHz: heartbeat 10, the six others 100 each,
// at most one frame queued per sample, ids of node 5; CmdSetRate changes a
// rate and turns one off; a queue nobody empties keeps its newest frames
// and counts the oldest it pushed out.
TEST(CanTx, RatesQueueAndDrops)
{
    can_tx_config_t c;
    can_tx_defaults(&c, 5, 10000);
    can_tx_t t;
    ASSERT_TRUE(can_tx_init(&t, &c));
    can_telemetry_t tlm{};
    int per_id[0x800] = {0};
    for (uint32_t k = 0; k < 10000; ++k) {
        const uint32_t before = t.sent;
        can_tx_step(&t, k, &tlm);
        EXPECT_LE(t.sent - before, 1u);
        can_frame_t f;
        while (can_tx_pop(&t, &f)) {
            ASSERT_LT(f.id, 0x800u);
            EXPECT_EQ(f.id & 0xFu, 5u);
            ++per_id[f.id];
        }
    }
    EXPECT_EQ(per_id[0x105], 10);
    EXPECT_EQ(per_id[0x175], 1);  // the version, every 1 s
    for (uint32_t id : {0x115u, 0x125u, 0x135u, 0x145u, 0x155u, 0x165u}) EXPECT_EQ(per_id[id], 100) << std::hex << id;
    EXPECT_EQ(t.dropped, 0u);
    // Position every 1 ms, Timing off
    ASSERT_TRUE(can_tx_set_period(&t, 10000, CAN_TLM_POSITION, 1));
    ASSERT_TRUE(can_tx_set_period(&t, 10000, CAN_TLM_TIMING, 0));
    EXPECT_FALSE(can_tx_set_period(&t, 10000, CAN_TLM_COUNT, 10));
    EXPECT_FALSE(can_tx_set_period(&t, 10000, CAN_TLM_POSITION, 60001));
    std::memset(per_id, 0, sizeof per_id);
    for (uint32_t k = 10000; k < 20000; ++k) {
        can_tx_step(&t, k, &tlm);
        can_frame_t f;
        while (can_tx_pop(&t, &f)) ++per_id[f.id];
    }
    EXPECT_GE(per_id[0x115], 990);
    EXPECT_EQ(per_id[0x165], 0);
    // all eight due at the same sample: one a sample, the others follow
    ASSERT_TRUE(can_tx_init(&t, &c));
    for (uint8_t m = 0; m < CAN_TLM_COUNT; ++m) ASSERT_TRUE(can_tx_set_period(&t, 0, m, 10));
    for (uint32_t k = 0; k < CAN_TLM_COUNT; ++k) {
        can_tx_step(&t, k, &tlm);
        EXPECT_EQ(t.sent, k + 1) << k;
    }
    // nobody transmits: every due message queued, the queue keeps the
    // newest 16 and counts the ones pushed out (1 heartbeat, 1 version and
    // 10 of each other message were due in 1000 samples)
    ASSERT_TRUE(can_tx_init(&t, &c));
    for (uint32_t k = 0; k < 1000; ++k) can_tx_step(&t, k, &tlm);
    EXPECT_EQ(t.count, CAN_TX_QUEUE);
    EXPECT_EQ(t.sent, 1u + 1u + 10u * 6u);
    EXPECT_EQ(t.dropped, t.sent - CAN_TX_QUEUE);
}

// Over-current on any of the drive's phases, either sign; the third phase
// of a sample is not looked at by a two-phase drive.
TEST(FaultMonitor, OvercurrentOnAnyPhase)
{
    const fault_monitor_config_t c = rig_faults();
    fault_monitor_t m;
    for (int k = 0; k < 3; ++k) {
        for (double i : {4.6, -4.6}) {
            hal_sample_t s = sample3(0.0, 0.0, 0.0);
            s.i_A[k] = M(i);
            fault_monitor_init(&m, &c);
            EXPECT_EQ(fault_monitor_sample(&m, &s, 3), DRIVE_FAULT_OVERCURRENT) << k << " " << i;
        }
    }
    hal_sample_t s = sample3(4.4, -4.4, 4.5);
    fault_monitor_init(&m, &c);
    EXPECT_EQ(fault_monitor_sample(&m, &s, 3), DRIVE_FAULT_NONE);
    s = sample3(0.0, 0.0, 9.0);
    fault_monitor_init(&m, &c);
    EXPECT_EQ(fault_monitor_sample(&m, &s, 2), DRIVE_FAULT_NONE);
}

// ---- overruns (supervisor/fault_monitor.h), issue 26 ----
//
// The criterion: each overrun adds overrun_weight (1000) to a level, every
// sample without a status bit takes 1 off it (not below 0), and the level
// reaching overrun_limit (3000) trips. With g clean samples between
// overruns the level after the n-th is 1000 + (n - 1)(1000 - g) while it
// stays above 0, so the trip comes at the n-th exactly where that reaches
// 3000; with g >= 1000 the level is back at 0 before each overrun and
// nothing ever trips.
namespace {
hal_sample_t overrun_sample()
{
    hal_sample_t s = two(0.0, 0.0);
    s.status = HAL_STATUS_OVERRUN;
    return s;
}
// Overruns every (gap + 1)-th sample (the first at once); returns the
// number of the overrun that tripped, 0 if none did within n_max overruns.
int overruns_until_trip(fault_monitor_t* m, int gap, int n_max, uint32_t quiet_status = 0u)
{
    hal_sample_t clean = two(0.0, 0.0);
    const hal_sample_t over = overrun_sample();
    clean.status = quiet_status;
    for (int n = 1; n <= n_max; ++n) {
        const drive_fault_t f = fault_monitor_sample(m, &over, 2);
        if (f == DRIVE_FAULT_OVERRUN) return n;
        EXPECT_EQ(f, DRIVE_FAULT_NONE) << "overrun " << n;
        for (int k = 0; k < gap; ++k) {
            if (fault_monitor_sample(m, &clean, 2) != DRIVE_FAULT_NONE) {
                ADD_FAILURE() << "a clean sample faulted";
                return -1;
            }
        }
    }
    return 0;
}
}  // namespace

// Isolated overruns are tolerated however many: 1000 clean samples between
// them leak the level back to 0 (200 overruns, 0.2 M samples); 990 leave
// 10 of each, and the 201st then trips, the level exactly at the limit.
// Every overrun is counted for the telemetry either way.
TEST(FaultMonitor, IsolatedOverrunsAreTolerated)
{
    const fault_monitor_config_t c = rig_faults();
    fault_monitor_t m;
    fault_monitor_init(&m, &c);
    EXPECT_EQ(overruns_until_trip(&m, 1000, 200), 0);
    EXPECT_EQ(m.overruns, 200u);
    EXPECT_EQ(m.overrun_level, 0);
    fault_monitor_init(&m, &c);
    EXPECT_EQ(overruns_until_trip(&m, 990, 300), 201);
    EXPECT_EQ(m.overruns, 201u);
    // the samples between them carry another status bit (no bus
    // measurement: a backend without one sets it on every sample): still
    // no overrun, so the level leaks the same (it did not before: the
    // third isolated overrun then tripped)
    fault_monitor_init(&m, &c);
    EXPECT_EQ(overruns_until_trip(&m, 1000, 200, HAL_STATUS_BUS_INVALID), 0);
    EXPECT_EQ(m.overrun_level, 0);
}

// The trip at exactly the stated count: back to back the 3rd; one clean
// sample between them the 4th (1000 + 2 x 999 = 2998 after the 3rd); 500
// between them the 5th, whose level is exactly 3000 (the limit trips);
// 501 between them the 6th (2996 after the 5th); 666 the 7th (3004),
// 667 the 8th (2998 after the 7th).
TEST(FaultMonitor, OverrunsTripAtTheStatedCount)
{
    const fault_monitor_config_t c = rig_faults();
    const int cases[][2] = {{0, 3}, {1, 4}, {500, 5}, {501, 6}, {666, 7}, {667, 8}};
    for (const auto& gc : cases) {
        fault_monitor_t m;
        fault_monitor_init(&m, &c);
        EXPECT_EQ(overruns_until_trip(&m, gc[0], 20), gc[1]) << "gap " << gc[0];
    }
}

// The level leaks 1 per clean sample and never goes below 0: two overruns
// back to back (2000), then 1000 clean samples, then two more: the 4th
// trips (1000 + 2000 = 3000); after 1001 clean samples it does not (2999),
// and a 5th then does. One overrun followed by 5000 clean samples leaves
// 0, not -4000: three back to back then trip on the third.
TEST(FaultMonitor, OverrunLevelLeaksOnePerSampleDownToZero)
{
    const fault_monitor_config_t c = rig_faults();
    const hal_sample_t clean = two(0.0, 0.0), over = overrun_sample();
    for (const int quiet : {1000, 1001}) {
        fault_monitor_t m;
        fault_monitor_init(&m, &c);
        EXPECT_EQ(fault_monitor_sample(&m, &over, 2), DRIVE_FAULT_NONE);
        EXPECT_EQ(fault_monitor_sample(&m, &over, 2), DRIVE_FAULT_NONE);
        EXPECT_EQ(m.overrun_level, 2000);
        for (int k = 0; k < quiet; ++k) ASSERT_EQ(fault_monitor_sample(&m, &clean, 2), DRIVE_FAULT_NONE);
        EXPECT_EQ(m.overrun_level, 2000 - quiet);
        EXPECT_EQ(fault_monitor_sample(&m, &over, 2), DRIVE_FAULT_NONE) << quiet;
        EXPECT_EQ(fault_monitor_sample(&m, &over, 2), quiet == 1000 ? DRIVE_FAULT_OVERRUN : DRIVE_FAULT_NONE) << quiet;
        if (quiet == 1001) {
            EXPECT_EQ(fault_monitor_sample(&m, &over, 2), DRIVE_FAULT_OVERRUN);
        }
    }
    fault_monitor_t m;
    fault_monitor_init(&m, &c);
    EXPECT_EQ(fault_monitor_sample(&m, &over, 2), DRIVE_FAULT_NONE);
    for (int k = 0; k < 5000; ++k) ASSERT_EQ(fault_monitor_sample(&m, &clean, 2), DRIVE_FAULT_NONE);
    EXPECT_EQ(m.overrun_level, 0);
    EXPECT_EQ(fault_monitor_sample(&m, &over, 2), DRIVE_FAULT_NONE);
    EXPECT_EQ(fault_monitor_sample(&m, &over, 2), DRIVE_FAULT_NONE);
    EXPECT_EQ(fault_monitor_sample(&m, &over, 2), DRIVE_FAULT_OVERRUN);
}

// ---- flight recorder (supervisor/flight_recorder.h), issue 26 ----

namespace {
void record(flight_recorder_t* r, uint32_t tick)
{
    flight_record_t* s = flight_recorder_slot(r);
    if (s == nullptr) return;  // frozen: the drive writes nothing
    *s = flight_record_t{};
    s->tick = tick;
    s->i_A[0] = M(0.001 * tick);
    flight_recorder_commit(r);
}
}  // namespace

// Past 2^32 samples (5 days at 10 kHz) the record count wraps: the ring
// stays full (64 records, oldest first, in order across the wrap), so a
// fault just after it still freezes the whole 6.4 ms.
TEST(FlightRecorder, FullAcrossTheCountersWrap)
{
    flight_recorder_t r;
    flight_recorder_init(&r);
    // as if 2^32 - 10 samples had been written (the ring's contents are
    // those of the last 64, written here)
    r.n = UINT32_MAX - 73u;
    for (uint32_t k = 0; k < 64; ++k) record(&r, 1000u + k);
    ASSERT_EQ(flight_recorder_count(&r), 64u);
    for (uint32_t k = 0; k < 20; ++k) record(&r, 1064u + k);  // across the wrap
    EXPECT_EQ(flight_recorder_count(&r), 64u);
    flight_recorder_fault(&r, DRIVE_FAULT_OVERCURRENT, 1083u);
    for (uint32_t k = 0; k < 64; ++k) {
        const flight_record_t* s = flight_recorder_get(&r, k);
        ASSERT_NE(s, nullptr) << k;
        EXPECT_EQ(s->tick, 1020u + k) << k;
    }
}

// The ring: the k-th oldest of the last min(n, 64) records, oldest first,
// before and after it wraps (100 written: ticks 36..99 of 0..99), NULL
// beyond; frozen by the first fault with its code and tick, after which
// nothing is written (slot NULL, commit a no-op) and the snapshot stays.
// Every later fault is counted (events) but the first cause and tick are
// kept; init empties it.
TEST(FlightRecorder, RingWrapsFreezesAtTheFirstFaultAndCountsEveryEvent)
{
    flight_recorder_t r;
    flight_recorder_init(&r);
    EXPECT_EQ(flight_recorder_count(&r), 0u);
    EXPECT_EQ(flight_recorder_get(&r, 0), nullptr);
    for (uint32_t t = 0; t < 10; ++t) record(&r, t);
    ASSERT_EQ(flight_recorder_count(&r), 10u);
    for (uint32_t k = 0; k < 10; ++k) EXPECT_EQ(flight_recorder_get(&r, k)->tick, k);
    EXPECT_EQ(flight_recorder_get(&r, 10), nullptr);
    for (uint32_t t = 10; t < 100; ++t) record(&r, t);
    ASSERT_EQ(flight_recorder_count(&r), FLIGHT_RECORDER_DEPTH);
    for (uint32_t k = 0; k < FLIGHT_RECORDER_DEPTH; ++k) {
        ASSERT_NE(flight_recorder_get(&r, k), nullptr);
        EXPECT_EQ(flight_recorder_get(&r, k)->tick, 36u + k) << k;
        EXPECT_EQ(D(flight_recorder_get(&r, k)->i_A[0]), D(M(0.001 * (36 + k)))) << k;
    }
    EXPECT_EQ(flight_recorder_get(&r, FLIGHT_RECORDER_DEPTH), nullptr);
    EXPECT_EQ(r.events, 0u);
    EXPECT_FALSE(r.frozen);

    flight_recorder_fault(&r, DRIVE_FAULT_LOSS_OF_SYNC, 100);
    EXPECT_TRUE(r.frozen);
    EXPECT_EQ(r.fault, DRIVE_FAULT_LOSS_OF_SYNC);
    EXPECT_EQ(r.fault_tick, 100u);
    EXPECT_EQ(r.events, 1u);
    // the drive goes on (a re-lock, a reported fault): nothing is written
    for (uint32_t t = 100; t < 300; ++t) {
        record(&r, t);
        flight_recorder_commit(&r);  // a commit without a slot changes nothing either
        if (t == 150) flight_recorder_fault(&r, DRIVE_FAULT_LOSS_OF_SYNC, t);
        if (t == 200) flight_recorder_fault(&r, DRIVE_FAULT_OVERCURRENT, t);
    }
    EXPECT_EQ(flight_recorder_slot(&r), nullptr);
    EXPECT_EQ(r.events, 3u);
    EXPECT_EQ(r.fault, DRIVE_FAULT_LOSS_OF_SYNC) << "the first cause is kept";
    EXPECT_EQ(r.fault_tick, 100u);
    ASSERT_EQ(flight_recorder_count(&r), FLIGHT_RECORDER_DEPTH);
    for (uint32_t k = 0; k < FLIGHT_RECORDER_DEPTH; ++k) {
        EXPECT_EQ(flight_recorder_get(&r, k)->tick, 36u + k) << "snapshot changed at " << k;
    }
    // a fault before the ring is full: the snapshot is what there was
    flight_recorder_init(&r);
    EXPECT_FALSE(r.frozen);
    EXPECT_EQ(r.events, 0u);
    EXPECT_EQ(r.fault, DRIVE_FAULT_NONE);
    EXPECT_EQ(flight_recorder_count(&r), 0u);
    for (uint32_t t = 0; t < 5; ++t) record(&r, t);
    flight_recorder_fault(&r, DRIVE_FAULT_I2T, 5);
    for (uint32_t t = 5; t < 100; ++t) record(&r, t);
    EXPECT_EQ(flight_recorder_count(&r), 5u);
    EXPECT_EQ(flight_recorder_get(&r, 0)->tick, 0u);
    EXPECT_EQ(flight_recorder_get(&r, 4)->tick, 4u);
    EXPECT_EQ(flight_recorder_get(&r, 5), nullptr);
    EXPECT_EQ(r.events, 1u);
}

// ---- K identification's decisions (startup/k_identification.h), issue 26 ----
//
// With w_scale = 16 rad/s (1/16 exact in Q14.17), |w_r| = 8 (x = 1/2) and
// |e| = K_true |w_r|, every mean is exact in both builds, so the bounds can
// be met exactly: K = K_model/2 and 2 K_model are accepted (the header's
// [1/2, 2]), a K exactly at the deadband is kept (the model's K stays in
// use), a speed exactly at w_min counts, a speed beyond w_scale counts with
// x = 1, the result comes on the n_window-th counted sample, once.
namespace {
k_id_config_t k_exact_cfg(double K_model, int n_window)
{
    k_id_config_t c{};
    c.enabled = true;
    c.w_min_rad_s = M(8.0);
    c.inv_w_scale_s = M(1.0 / 16.0);
    c.n_window = n_window;
    c.K_model_V_s = M(K_model);
    c.deadband = M(0.25);
    return c;
}
// n samples at speed w with |e| = e_V; returns the sample (1-based) on
// which k_id_step returned true, 0 if none
int k_feed(k_id_t* k, double w, double e_V, int n)
{
    int at = 0;
    for (int i = 1; i <= n; ++i) {
        if (k_id_step(k, M(e_V * e_V), M(w))) {
            EXPECT_EQ(at, 0) << "a second result at sample " << i;
            at = i;
        }
    }
    return at;
}
}  // namespace

TEST(KIdentification, ExactBoundsDeadbandAndOneResult)
{
    struct Case {
        double K_true;
        k_id_state_t want;
    };
    // K_model 0.25: [0.125, 0.5] accepted; deadband 0.25 x 0.25 = 0.0625
    const Case cases[] = {{0.125, K_ID_DONE},  {0.5, K_ID_DONE},   {0.1171875, K_ID_REJECTED},
                          {0.515625, K_ID_REJECTED}, {0.3125, K_ID_KEPT}, {0.1875, K_ID_KEPT},
                          {0.3203125, K_ID_DONE}, {0.1796875, K_ID_DONE}, {0.25, K_ID_KEPT}};
    for (const Case& cs : cases) {
        k_id_t k;
        const k_id_config_t c = k_exact_cfg(0.25, 40);
        k_id_init(&k, &c);
        // both signs of the speed; 8 rad/s is w_min itself, which counts
        const int at = k_feed(&k, (cs.K_true > 0.3 ? -8.0 : 8.0), cs.K_true * 8.0, 100);
        EXPECT_EQ(at, 40) << cs.K_true;
        EXPECT_EQ(k.state, cs.want) << cs.K_true;
        EXPECT_EQ(k.n, 40) << "counting stops with the result";
        if (cs.want == K_ID_REJECTED) {
            EXPECT_EQ(D(k.K_V_s), D(M(0.25))) << cs.K_true;
        } else {
            EXPECT_NEAR(D(k.K_V_s), cs.K_true, 1e-9 + (MC_FIXED ? 2.0 / 131072 : 0.0)) << cs.K_true;
        }
    }
    // beyond w_scale x is 1, not 2: |e| = 2 V at 32 rad/s gives 2/16
    k_id_t k;
    k_id_config_t c = k_exact_cfg(0.125, 10);
    k_id_init(&k, &c);
    EXPECT_EQ(k_feed(&k, 32.0, 2.0, 10), 10);
    EXPECT_EQ(k.state, K_ID_KEPT);
    EXPECT_EQ(D(k.K_V_s), 0.125);
    // just below w_min nothing counts; disabled: OFF, nothing counts, the model's K
    k_id_init(&k, &c);
    EXPECT_EQ(k_feed(&k, 8.0 - 1e-3, 1.0, 100), 0);
    EXPECT_EQ(k.n, 0);
    c.enabled = false;
    k_id_init(&k, &c);
    EXPECT_EQ(k.state, K_ID_OFF);
    EXPECT_EQ(k_feed(&k, 10.0, 1.0, 100), 0);
    EXPECT_EQ(k.n, 0);
    EXPECT_EQ(D(k.K_V_s), 0.125);
}

// ---- alignment (startup/align.h): every sample against the stages, issue 26 ----
//
// The stages of the header evaluated in double: ramp up V (k+1)/ramp,
// hold V, out to phi_turn and back at phi_turn/turn a sample (the vector
// at n phi_turn/turn, n = k+1 out and 2 turn - (k+1) back), settle V,
// ramp down V (ramp - (k+1))/ramp, then 0 V; true only after the last
// sample, and from then on with 0 V. Disabled: true at once.
TEST(Align, EverySampleOfTheStages)
{
    align_config_t c{};
    c.enabled = true;
    c.ramp_ticks = 8;
    c.hold_ticks = 5;
    c.turn_ticks = 6;
    c.settle_ticks = 4;
    c.off_ticks = 3;
    c.phi_turn_rad = M(1.5707963267948966);
    const double V = 6.02, phi = D(c.phi_turn_rad);
    std::vector<std::pair<double, double>> want;
    for (int k = 0; k < 8; ++k) want.push_back({V * (k + 1) / 8.0, 0.0});
    for (int k = 0; k < 5; ++k) want.push_back({V, 0.0});
    for (int k = 0; k < 12; ++k) {
        const int n = k < 6 ? k + 1 : 12 - (k + 1);
        want.push_back({V * std::cos(phi * n / 6.0), V * std::sin(phi * n / 6.0)});
    }
    for (int k = 0; k < 4; ++k) want.push_back({V, 0.0});
    for (int k = 0; k < 8; ++k) want.push_back({V * (8 - (k + 1)) / 8.0, 0.0});
    for (int k = 0; k < 3; ++k) want.push_back({0.0, 0.0});
    ASSERT_EQ(static_cast<int>(want.size()), align_total_ticks(&c));
    align_t a;
    align_init(&a, &c);
    mc_t vf, vg;
    const double tol = MC_FIXED ? 2e-4 : 1e-6;
    for (size_t k = 0; k < want.size(); ++k) {
        ASSERT_FALSE(align_step(&a, M(V), &vf, &vg)) << k;
        EXPECT_NEAR(D(vf), want[k].first, tol) << k;
        EXPECT_NEAR(D(vg), want[k].second, tol) << k;
    }
    for (int k = 0; k < 3; ++k) {
        vf = vg = M(1.0);
        EXPECT_TRUE(align_step(&a, M(V), &vf, &vg));
        EXPECT_EQ(D(vf), 0.0);
        EXPECT_EQ(D(vg), 0.0);
    }
    c.enabled = false;
    align_init(&a, &c);
    vf = vg = M(1.0);
    EXPECT_TRUE(align_step(&a, M(V), &vf, &vg));
    EXPECT_EQ(D(vf), 0.0);
    EXPECT_EQ(D(vg), 0.0);
}
