// The averaged inverter leg of sim/model/inverter.h (issue 30): the dead
// time against a hand-computed case, its transition near zero current
// against a switching-period simulation of the leg's node capacitance, the
// device drops, the minimum pulse, the star point, and the software plant's
// backend holding an optional inverter. ctest: sim.inverter.*
#include <cmath>
#include <cstdint>

#include <gtest/gtest.h>

#include "hal/hal.h"
#include "hal_sw_plant.h"
#include "mc_convert.h"
#include "model/amplifier.h"
#include "model/current_sensor.h"
#include "model/inverter.h"
#include "model/load_profile.h"
#include "model/pm_plant.h"
#include "test_motors.h"

namespace {

using mcsim_test::paper001_motor;

using mcsim::Inverter;
using mcsim::InverterParams;

// The hand-computed case: a 48 V bus, 20 kHz, 500 ns of dead time (the
// dead time of this project's VESC 6 image, hal/backends/stm32f405/boards/
// vesc6.c). Per period the leg loses (i > 0) or gains (i < 0)
// V_dc t_dead = 48 V * 500 ns = 24 uVs, i.e. 24 uVs * 20 kHz = 0.48 V of
// average voltage.
constexpr double kVdc = 48.0;
constexpr double kFpwm = 20e3;
constexpr double kTdead = 500e-9;
constexpr double kVoltSecondsPerPeriod = 24e-6;  // 48 * 500e-9, by hand
constexpr double kAvgError = 0.48;               // 24e-6 * 20e3, by hand

InverterParams dead_time_only(double i_transition_A = 0.0)
{
    InverterParams p;
    p.f_pwm_Hz = kFpwm;
    p.dead_time_s = kTdead;
    p.i_transition_A = i_transition_A;
    return p;
}

TEST(Leg, DeadTimeVoltSecondsHandComputed)
{
    const Inverter inv(dead_time_only());
    for (double v_cmd : {-15.0, -3.0, 0.0, 2.5, 10.0}) {
        // current out of the leg: the pulse is short by t_dead
        const double v_pos = inv.leg_voltage(v_cmd, 5.0, kVdc);
        const double v_neg = inv.leg_voltage(v_cmd, -5.0, kVdc);
        EXPECT_NEAR((v_cmd - v_pos) / kFpwm, kVoltSecondsPerPeriod, 1e-15) << v_cmd;
        EXPECT_NEAR((v_neg - v_cmd) / kFpwm, kVoltSecondsPerPeriod, 1e-15) << v_cmd;
        EXPECT_NEAR(v_pos, v_cmd - kAvgError, 1e-12);
        EXPECT_NEAR(v_neg, v_cmd + kAvgError, 1e-12);
        // no current, no error (sgn(0) = 0)
        EXPECT_EQ(inv.leg_voltage(v_cmd, 0.0, kVdc), v_cmd);
    }
}

TEST(Leg, SwitchingDelaysAddToTheDeadTime)
{
    InverterParams p = dead_time_only();
    p.t_on_s = 120e-9;   // the incoming switch turns on later: more error
    p.t_off_s = 200e-9;  // the outgoing one turns off later: less
    const Inverter inv(p);
    // (500 + 120 - 200) ns * 48 V * 20 kHz = 0.4032 V
    EXPECT_NEAR(inv.leg_voltage(1.0, 3.0, kVdc), 1.0 - 0.4032, 1e-12);
    EXPECT_NEAR(inv.leg_voltage(1.0, -3.0, kVdc), 1.0 + 0.4032, 1e-12);
}

TEST(Leg, SmoothTransitionAtZeroCurrent)
{
    // g(x) = x/2 up to |x| = 1, then sgn(x)(1 - 1/(2|x|)), x = i / i_tr
    const double i_tr = 2.0;
    const Inverter inv(dead_time_only(i_tr));
    const struct {
        double i, g;
    } cases[] = {{0.0, 0.0}, {0.5, 0.125}, {1.0, 0.25}, {2.0, 0.5}, {4.0, 0.75}, {20.0, 0.95}, {-1.0, -0.25}, {-4.0, -0.75}};
    for (const auto& c : cases) {
        EXPECT_NEAR(inv.transition(c.i), c.g, 1e-15) << c.i;
        EXPECT_NEAR(inv.leg_voltage(3.0, c.i, kVdc), 3.0 - c.g * kAvgError, 1e-12) << c.i;
    }
    // continuous with a continuous slope at |x| = 1, odd, monotonic
    const double h = 1e-7;
    EXPECT_NEAR(inv.transition(i_tr - h), inv.transition(i_tr + h), 1e-7);
    const double slope_left = (inv.transition(i_tr) - inv.transition(i_tr - h)) / h;
    const double slope_right = (inv.transition(i_tr + h) - inv.transition(i_tr)) / h;
    EXPECT_NEAR(slope_left, 0.25, 1e-6);  // d/di (i / (2 i_tr)) = 1/(2 i_tr)
    EXPECT_NEAR(slope_right, 0.25, 1e-6);
    double prev = -1.0;
    for (double i = -30.0; i <= 30.0; i += 0.01) {
        const double g = inv.transition(i);
        EXPECT_GE(g, prev);
        EXPECT_DOUBLE_EQ(g, -inv.transition(-i));
        prev = g;
    }
}

// One switching period of a leg, simulated at 0.1 ns: centre-aligned,
// the high interval of the command [T(1-d)/2, T(1+d)/2]; at each edge the
// outgoing switch turns off at the command's edge and the incoming one
// t_dead later; while both are off the constant current i (out of the
// node) moves the node's capacitance C, clamped to the rails by the
// diodes (drops neglected). Returns the average node voltage about the
// midpoint.
double simulate_period(double d, double i_A, double C_F, double v_dc, double t_dead, double f_pwm)
{
    const double T = 1.0 / f_pwm;
    const double t_up = 0.5 * T * (1.0 - d);
    const double t_dn = 0.5 * T * (1.0 + d);
    const int n = 500000;
    const double h = T / n;
    double v = 0.0;  // the lower switch is on at t = 0
    double sum = 0.0;
    for (int k = 0; k < n; ++k) {
        const double t = (k + 0.5) * h;
        const bool upper = t >= t_up + t_dead && t < t_dn;
        const bool lower = t < t_up || t >= t_dn + t_dead;
        if (upper) {
            v = v_dc;
        } else if (lower) {
            v = 0.0;
        } else {
            v -= i_A / C_F * h;
            v = v < 0.0 ? 0.0 : (v > v_dc ? v_dc : v);
        }
        sum += v;
    }
    return sum / n - 0.5 * v_dc;
}

TEST(Leg, TransitionIsTheNodeCapacitanceCommutation)
{
    // i_tr = C_node V_dc / t_dead: C_node = 2 nF (two devices' 1 nF output
    // capacitance) on 48 V in 500 ns: 0.192 A
    const double C = 2e-9;
    const double i_tr = C * kVdc / kTdead;
    const Inverter inv(dead_time_only(i_tr));
    const double d = 0.6;
    const double v_cmd = (d - 0.5) * kVdc;
    for (double i : {0.02, 0.1, 0.192, 0.3, 1.0, 5.0, -0.05, -0.5}) {
        const double v_sim = simulate_period(d, i, C, kVdc, kTdead, kFpwm);
        // 0.1 ns of time step on 48 V at 20 kHz: 1e-4 V of resolution
        EXPECT_NEAR(inv.leg_voltage(v_cmd, i, kVdc), v_sim, 2e-4) << "i = " << i;
    }
}

TEST(Leg, ConductionDropsMosfetAndIgbt)
{
    InverterParams p = dead_time_only();
    p.r_switch_Ohm = 1.1e-3;
    p.v_diode_V = 0.8;
    p.r_diode_Ohm = 2e-3;
    const double i = 40.0;
    const double v_cmd = 4.8;  // d = 0.6
    // MOSFETs (synchronous): the body diodes carry i in the two dead times,
    // 2 * 500 ns * 20 kHz = 2 % of the period; the channels the rest:
    //   0.98 * 1.1 mOhm * 40 A + 0.02 * (0.8 V + 2 mOhm * 40 A) = 0.04312 + 0.0176
    {
        const Inverter inv(p);
        EXPECT_NEAR(inv.leg_voltage(v_cmd, i, kVdc), v_cmd - kAvgError - (0.04312 + 0.0176), 1e-12);
        EXPECT_NEAR(inv.leg_voltage(v_cmd, -i, kVdc), v_cmd + kAvgError + (0.04312 + 0.0176), 1e-12);
    }
    // IGBTs (one-way switches, V_CE0 1 V): i > 0 in the upper switch for
    // d_eff = 0.6 - 0.01 = 0.59 and in the lower diode for 0.41:
    //   0.59 * (1 V + 1.1 mOhm * 40 A) + 0.41 * (0.8 V + 2 mOhm * 40 A)
    p.synchronous = false;
    p.v_switch_V = 1.0;
    {
        const Inverter inv(p);
        const double drop = 0.59 * (1.0 + 0.044) + 0.41 * (0.8 + 0.08);
        EXPECT_NEAR(inv.leg_voltage(v_cmd, i, kVdc), v_cmd - kAvgError - drop, 1e-12);
        // i < 0: d_eff = 0.61, the upper diode carries it for 0.61
        const double drop_neg = 0.39 * (1.0 + 0.044) + 0.61 * (0.8 + 0.08);
        EXPECT_NEAR(inv.leg_voltage(v_cmd, -i, kVdc), v_cmd + kAvgError + drop_neg, 1e-12);
    }
}

TEST(Leg, MinimumPulseAndRailsHaveNoDeadTime)
{
    InverterParams p = dead_time_only();
    p.min_pulse_s = 1e-6;  // 2 % of the 50 us period
    const Inverter inv(p);
    // d = 0.5 + v/48: 1 % high pulse -> dropped, the leg held low
    EXPECT_EQ(inv.duty(-0.49 * kVdc, kVdc), 0.0);
    EXPECT_EQ(inv.duty(0.49 * kVdc, kVdc), 1.0);
    EXPECT_NEAR(inv.duty(-0.47 * kVdc, kVdc), 0.03, 1e-12);
    // a leg at a rail does not switch: no dead-time error, whatever the current
    EXPECT_EQ(inv.leg_voltage(-0.49 * kVdc, 5.0, kVdc), -0.5 * kVdc);
    EXPECT_EQ(inv.leg_voltage(0.49 * kVdc, -5.0, kVdc), 0.5 * kVdc);
    EXPECT_EQ(inv.leg_voltage(100.0, 5.0, kVdc), 0.5 * kVdc);
    // just above the minimum: switching, the error back
    EXPECT_NEAR(inv.leg_voltage(-0.47 * kVdc, 5.0, kVdc), -0.47 * kVdc - kAvgError, 1e-12);
}

TEST(Leg, IdealInverterIsTheAmplifierBitForBit)
{
    InverterParams p;
    p.f_pwm_Hz = kFpwm;
    const Inverter inv(p);
    mcsim::Amplifier amp;
    amp.v_max_V = 0.5 * kVdc;
    for (double v = -40.0; v <= 40.0; v += 0.37) {
        for (double i : {-3.0, 0.0, 2.0}) {
            EXPECT_EQ(inv.leg_voltage(v, i, kVdc), amp.apply(v));
        }
    }
    EXPECT_EQ(inv.leg_voltage(std::nan(""), 1.0, kVdc), 0.0);
    EXPECT_EQ(p.problem(), nullptr);
    InverterParams bad = dead_time_only();
    bad.dead_time_s = 30e-6;  // more than half of 50 us
    EXPECT_NE(bad.problem(), nullptr);
}

TEST(Leg, HBridgeWindingLosesTwoDeadTimes)
{
    const Inverter inv(dead_time_only());
    // both legs commutate the winding current: 2 * 0.48 V against it
    EXPECT_NEAR(inv.winding_voltage(6.0, 1.5, kVdc), 6.0 - 2.0 * kAvgError, 1e-12);
    EXPECT_NEAR(inv.winding_voltage(6.0, -1.5, kVdc), 6.0 + 2.0 * kAvgError, 1e-12);
}

TEST(Star, PhaseVoltagesLoseTheCommonMode)
{
    const double v_leg[3] = {10.0, -2.0, 4.0};
    double v_ph[3];
    Inverter::phase_voltages(v_leg, v_ph);
    EXPECT_NEAR(v_ph[0] + v_ph[1] + v_ph[2], 0.0, 1e-14);
    EXPECT_NEAR(v_ph[0], 6.0, 1e-14);  // 10 - (10 - 2 + 4)/3
    EXPECT_NEAR(v_ph[1], -6.0, 1e-14);
    EXPECT_NEAR(v_ph[2], 0.0, 1e-14);
    // a common-mode shift of the legs does not reach the phases
    const double shifted[3] = {13.0, 1.0, 7.0};
    double v_ph2[3];
    Inverter::phase_voltages(shifted, v_ph2);
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(v_ph2[k], v_ph[k], 1e-14);
    }
}

// The backend holding the inverter: each period's applied leg voltages are
// the inverter's for the command and the plant's currents at the sample.
struct Ctx {
    double v[3];
};
void hold_voltages(void* ctx, const hal_sample_t*, hal_command_t* out)
{
    const Ctx* c = static_cast<const Ctx*>(ctx);
    out->n_phases = 3;
    for (int k = 0; k < 3; ++k) {
        out->v_V[k] = mcsim::to_mc(c->v[k]);
    }
}


TEST(Backend, AppliesTheInverterAndWithoutItTheAmplifier)
{
    mcsim::PmPlant plant(paper001_motor(), mcsim::LoadProfile(), 1);
    plant.reset(mcsim::PmPlant::State::Zero());
    mcsim::CurrentSensor sensor(mcsim::SensorParams{}, 1);
    mcsim::Amplifier amp;
    amp.v_max_V = 0.5 * kVdc;  // a 48 V bus for three legs
    hal_sw_plant_attach(&plant, &sensor, amp, 1e-4);
    const Inverter inv(dead_time_only());
    hal_sw_plant_set_inverter(&inv);
    Ctx ctx{{3.0, -1.0, -2.0}};
    ASSERT_TRUE(hal_start(hold_voltages, &ctx));
    for (int n = 0; n < 50; ++n) {
        double i[3];
        plant.phase_currents(i);
        ASSERT_EQ(hal_sw_plant_run(1), 1u);
        const hal_sw_plant_period_t* p = hal_sw_plant_last_period();
        const double cmd[3] = {mcsim::to_double(mcsim::to_mc(3.0)), mcsim::to_double(mcsim::to_mc(-1.0)),
                               mcsim::to_double(mcsim::to_mc(-2.0))};
        EXPECT_EQ(p->v_a_V, inv.leg_voltage(cmd[0], i[0], kVdc));
        EXPECT_EQ(p->v_b_V, inv.leg_voltage(cmd[1], i[1], kVdc));
        EXPECT_EQ(p->v_c_V, inv.leg_voltage(cmd[2], i[2], kVdc));
        if (n > 5) {  // currents established: the error is there, against them
            EXPECT_NEAR(p->v_a_V, cmd[0] - kAvgError * (i[0] > 0 ? 1.0 : -1.0), 1e-12);
        }
    }
    hal_sw_plant_set_inverter(nullptr);
    ASSERT_EQ(hal_sw_plant_run(1), 1u);
    EXPECT_EQ(hal_sw_plant_last_period()->v_a_V, amp.apply(hal_sw_plant_last_period()->v_a_cmd_V));
    hal_sw_plant_detach();
}

}  // namespace
