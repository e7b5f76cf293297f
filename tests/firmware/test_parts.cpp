// The parts every drive is assembled from: the phase adapter (Clarke and
// its inverse, 2 and 3 phases), the supervisor's state table, fault latch,
// bumpless transfer and voltage limit, and the shared motor model.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

extern "C" {
#include "adapter/phase_adapter.h"
#include "control/fg_tracking.h"
#include "math/mc_convert.h"
#include "model/motor_model.h"
#include "comm/can_tx.h"
#include "startup/align.h"
#include "startup/k_identification.h"
#include "supervisor/fault_monitor.h"
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
// rate and turns one off; a queue nobody empties drops and counts.
TEST(CanTx, RatesQueueAndDrops)
{
    can_tx_config_t c;
    can_tx_defaults(&c, 5, 10000);
    can_tx_t t;
    can_tx_init(&t, &c);
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
    can_tx_init(&t, &c);
    for (uint8_t m = 0; m < CAN_TLM_COUNT; ++m) ASSERT_TRUE(can_tx_set_period(&t, 0, m, 10));
    for (uint32_t k = 0; k < CAN_TLM_COUNT; ++k) {
        can_tx_step(&t, k, &tlm);
        EXPECT_EQ(t.sent, k + 1) << k;
    }
    // nobody transmits: 16 frames queued, the rest counted as dropped
    can_tx_init(&t, &c);
    for (uint32_t k = 0; k < 1000; ++k) can_tx_step(&t, k, &tlm);
    EXPECT_EQ(t.count, CAN_TX_QUEUE);
    EXPECT_EQ(t.sent, CAN_TX_QUEUE);
    EXPECT_GT(t.dropped, 0u);
    // 1 heartbeat, 1 version and 10 of each other message were due in 1000 samples
    EXPECT_EQ(t.sent + t.dropped, 1u + 1u + 10u * 6u);
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
