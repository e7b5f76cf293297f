// The inverter's legs switched at the carrier (sim/model/switched_pwm.h,
// [inverter] pwm = "switched"): a carrier period's mean leg voltage against
// the averaged model, the current ripple of a locked-rotor winding against
// its closed form, the compute delay and the sampling instant in the
// backend, the ratio check. ctest: sim.switched_pwm.*
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hal/hal.h"
#include "hal_sw_plant.h"
#include "mc_convert.h"
#include "model/amplifier.h"
#include "model/current_sensor.h"
#include "model/inverter.h"
#include "model/load_profile.h"
#include "model/pm_plant.h"
#include "model/switched_pwm.h"
#include "test_motors.h"

namespace {

using mcsim_test::paper000_stepper;
using mcsim_test::paper001_motor;

using mcsim::Inverter;
using mcsim::InverterParams;
using mcsim::PwmModel;
using mcsim::SwitchedPwm;

// The VESC 6's carrier and this project's control period: 48 V, 20 kHz,
// two carrier periods per 100 us (sim/inverters/vesc6.toml).
constexpr double kVdc = 48.0;
constexpr double kFpwm = 20e3;
constexpr double kTs = 1e-4;

// Legs that drive a fixed current (an infinite inductance): the mean leg
// voltages are the volt-seconds of the segments over the time.
class ConstantCurrentLoad final : public mcsim::PwmLoad {
public:
    ConstantCurrentLoad(int n, const double* i_A) : n_(n)
    {
        for (int k = 0; k < n; ++k) {
            i_[k] = i_A[k];
        }
    }
    void leg_currents(double* i_A) const override
    {
        for (int k = 0; k < n_; ++k) {
            i_A[k] = i_[k];
        }
    }
    void step(const double* v_leg_V, double dt_s) override
    {
        for (int k = 0; k < n_; ++k) {
            vs_[k] += v_leg_V[k] * dt_s;
        }
        t_ += dt_s;
    }
    double mean(int k) const { return vs_[k] / t_; }
    void reset()
    {
        for (double& v : vs_) {
            v = 0.0;
        }
        t_ = 0.0;
    }

private:
    int n_;
    double i_[SwitchedPwm::kMaxLegs] = {};
    double vs_[SwitchedPwm::kMaxLegs] = {};
    double t_ = 0.0;
};

// One leg's mean voltage over a control period (Ts = 1/f_pwm: one carrier
// period) in the steady state: the same command over three periods (a
// falling edge's dead time may run into the next period), the last one
// measured.
double switched_mean(const InverterParams& p, double v_cmd, double i_A)
{
    const double ts = 1.0 / p.f_pwm_Hz;
    SwitchedPwm pwm(p, 1, ts);
    const Inverter inv(p);
    const double d = inv.duty(v_cmd, kVdc);
    ConstantCurrentLoad load(1, &i_A);
    for (int k = 0; k < 3; ++k) {
        load.reset();
        pwm.run_period(load, &d, &d, 0.0, kVdc);
    }
    return load.mean(0);
}

InverterParams with_hard_sign(InverterParams p)
{
    p.f_pwm_Hz = kFpwm;
    p.i_transition_A = 0.0;  // the switched model's dead time: the current's sign
    return p;
}

// (a) Over a carrier period at a constant current the switched leg's mean
// voltage is the averaged model's leg_voltage with the hard sign (equations
// (1)-(3) of inverter.h), to 1e-9 of the voltage: the dead time and the
// delays (both signs of t_dead + t_on - t_off), the drops of MOSFETs and of
// IGBTs, the minimum pulse, the rails, pulses shorter than the dead time
// (with the drops, those are left out: there the switched leg's diode
// conducts one merged free interval, the averaged model's f_d assumes two
// whole dead times; switched_pwm.h).
// Broken once: the free leg's diode taken against the current's sign (the
// high diode for i > 0): every case with a dead time and a current fails.
TEST(Leg, CarrierPeriodMeanIsTheAveragedLegWithTheHardSign)
{
    struct Config {
        const char* name;
        InverterParams p;
    };
    std::vector<Config> configs;
    {
        InverterParams p;
        p.dead_time_s = 500e-9;  // the VESC 6 image's
        configs.push_back({"dead time", p});
        p.t_on_s = 120e-9;
        p.t_off_s = 200e-9;
        configs.push_back({"dead time and delays", p});
        InverterParams o;
        o.dead_time_s = 100e-9;
        o.t_off_s = 400e-9;  // the outgoing switch turns off after the incoming one's on: overlap
        configs.push_back({"overlap", o});
        InverterParams m;  // VESC 6's drops (sim/inverters/vesc6.toml)
        m.dead_time_s = 500e-9;
        m.r_switch_Ohm = 1.6e-3;
        m.v_diode_V = 0.8;
        m.r_diode_Ohm = 0.5e-3;
        configs.push_back({"MOSFET drops", m});
        InverterParams g;  // an IGBT leg with delays
        g.dead_time_s = 1e-6;
        g.t_on_s = 150e-9;
        g.t_off_s = 300e-9;
        g.v_switch_V = 1.1;
        g.r_switch_Ohm = 20e-3;
        g.v_diode_V = 0.9;
        g.r_diode_Ohm = 15e-3;
        g.synchronous = false;
        configs.push_back({"IGBT drops", g});
        InverterParams t;
        t.dead_time_s = 500e-9;
        t.min_pulse_s = 1e-6;  // d < 0.02 or > 0.98 not produced
        configs.push_back({"minimum pulse", t});
    }
    // commands across the range: the rails (clamped, +-24 V and beyond), a
    // pulse shorter than the dead time (-23.99 V: d T = 10 ns), inside the
    // minimum pulse (+-23.5 V: d = 0.99 / 0.01), ordinary duties
    constexpr double kShortPulse = 23.99;
    const double cmds[] = {-30.0, -24.0, -kShortPulse, -23.5, -17.3, -3.0, 0.0, 0.7, 9.6, 23.5, kShortPulse, 24.0, 31.0};
    const double currents[] = {7.5, -7.5, 0.2, -0.2, 0.0};
    for (const Config& c : configs) {
        const InverterParams p = with_hard_sign(c.p);
        ASSERT_EQ(p.problem(), nullptr) << c.name;
        const Inverter inv(p);
        const bool drops = p.v_switch_V != 0.0 || p.r_switch_Ohm != 0.0 || p.v_diode_V != 0.0 || p.r_diode_Ohm != 0.0;
        for (double v : cmds) {
            if (drops && std::fabs(v) == kShortPulse) {
                continue;
            }
            for (double i : currents) {
                const double avg = inv.leg_voltage(v, i, kVdc);
                const double sw = switched_mean(p, v, i);
                EXPECT_NEAR(sw, avg, 1e-9 * std::max(std::fabs(avg), 1.0))
                    << c.name << ": v_cmd " << v << " V, i " << i << " A";
            }
        }
    }
}

// (a') With the node capacitance (i_transition_A > 0; switched_pwm.h): the
// carrier period's mean at a constant current is the averaged model's
// leg_voltage with its transition g(x), to 1e-9 of the voltage, for
// currents on both sides of i_transition_A and both signs. Without drops:
// the averaged model weighs its drops with the smooth g(x) too, the
// switched leg with the conducting device's (hard) sign, and during a slew
// nothing conducts. Pulses shorter than the free interval are left out as
// in (a).
// Broken once: the slew time of x >= 1 taken as t_f/x (the whole ramp, not
// its half): every case with |i| >= i_transition_A fails.
TEST(Leg, CarrierPeriodMeanIsTheAveragedLegWithTheTransition)
{
    struct Config {
        const char* name;
        InverterParams p;
    };
    std::vector<Config> configs;
    {
        InverterParams p;
        p.dead_time_s = 500e-9;
        p.i_transition_A = 0.4;  // sim/inverters/vesc6.toml
        configs.push_back({"dead time", p});
        p.t_on_s = 120e-9;
        p.t_off_s = 200e-9;
        configs.push_back({"dead time and delays", p});
        InverterParams t;
        t.dead_time_s = 500e-9;
        t.i_transition_A = 1.5;
        t.min_pulse_s = 1e-6;
        configs.push_back({"minimum pulse", t});
    }
    const double cmds[] = {-30.0, -24.0, -17.3, -3.0, 0.0, 0.7, 9.6, 24.0, 31.0};
    const double currents[] = {7.5, -7.5, 1.0, -1.0, 0.4, -0.4, 0.2, -0.2, 0.03, -0.03, 0.0};
    for (const Config& c0 : configs) {
        InverterParams p = c0.p;
        p.f_pwm_Hz = kFpwm;
        ASSERT_EQ(p.problem(), nullptr) << c0.name;
        const Inverter inv(p);
        for (double v : cmds) {
            for (double i : currents) {
                const double avg = inv.leg_voltage(v, i, kVdc);
                const double sw = switched_mean(p, v, i);
                EXPECT_NEAR(sw, avg, 1e-9 * std::max(std::fabs(avg), 1.0))
                    << c0.name << ": v_cmd " << v << " V, i " << i << " A";
            }
        }
        // and it is not the hard sign's: within the transition the error is
        // below the full dead-time error
        const double hard = with_hard_sign(p).i_transition_A;
        EXPECT_EQ(hard, 0.0);
        InverterParams ph = with_hard_sign(p);
        ph.min_pulse_s = p.min_pulse_s;
        EXPECT_GT(std::fabs(switched_mean(p, 0.7, 0.2) - switched_mean(ph, 0.7, 0.2)), 0.1) << c0.name;
    }
}

// The stepper's H-bridge: two legs on one carrier at +v/2 and -v/2, the
// winding current out of the first; the winding's mean is
// Inverter::winding_voltage with the hard sign. Broken once as above.
TEST(Leg, HBridgeMeanIsTheAveragedWinding)
{
    InverterParams p;
    p.dead_time_s = 119e-9;  // the ODrive v3.6's (sim/inverters/odrive_v36.toml)
    p.r_switch_Ohm = 3.0e-3;
    p.v_diode_V = 0.8;
    p.r_diode_Ohm = 0.5e-3;
    p = with_hard_sign(p);
    const Inverter inv(p);
    const double ts = 2.0 / kFpwm;  // two carrier periods
    for (double v : {-40.0, -12.0, 0.0, 3.3, 25.0}) {
        for (double i : {2.0, -2.0, 0.0}) {
            SwitchedPwm pwm(p, 4, ts);
            const double cmd[2] = {v, 0.0};
            double d[SwitchedPwm::kMaxLegs];
            ASSERT_EQ(SwitchedPwm::leg_duties(inv, 2, cmd, kVdc, d), 4);
            const double i_leg[4] = {i, -i, 0.0, 0.0};
            ConstantCurrentLoad load(4, i_leg);
            for (int k = 0; k < 3; ++k) {
                load.reset();
                pwm.run_period(load, d, d, 0.0, kVdc);
            }
            const double avg = inv.winding_voltage(v, i, kVdc);
            EXPECT_NEAR(load.mean(0) - load.mean(1), avg, 1e-9 * std::max(std::fabs(avg), 1.0))
                << "v " << v << " i " << i;
        }
    }
}

// The plant behind the legs, with the winding current after every segment
// (an R-L current is monotonic within a segment: its extremes are there).
class RecordingLoad final : public mcsim::PwmLoad {
public:
    RecordingLoad(mcsim::PmPlant& plant) : load_(plant), plant_(plant) {}
    void leg_currents(double* i_A) const override { load_.leg_currents(i_A); }
    void step(const double* v_leg_V, double dt_s) override
    {
        load_.step(v_leg_V, dt_s);
        if (record) {
            lo = std::min(lo, plant_.i_a_A());
            hi = std::max(hi, plant_.i_a_A());
        }
    }
    bool record = false;
    double lo = 1e300, hi = -1e300;

private:
    mcsim::PlantLoad load_;
    mcsim::PmPlant& plant_;
};

// Steady-state peak-to-peak ripple of a locked-rotor R-L winding driven by
// V1 for t_h and 0 for t_l, periodically: during t_h the current relaxes
// towards I = V1/R with tau = L/R, during t_l towards 0, so with
// a = exp(-t_h/tau), b = exp(-t_l/tau) the periodic orbit is
// i_max = I (1 - a)/(1 - a b), i_min = b i_max, and
//   di_pp = I (1 - a)(1 - b) / (1 - a b)  ~  V1 t_h t_l / (L (t_h + t_l))
// for t_h, t_l << tau.
double ripple_closed_form(double v1, double t_h, double t_l, double R, double L)
{
    const double tau = L / R;
    const double a = std::exp(-t_h / tau);
    const double b = std::exp(-t_l / tau);
    return v1 / R * (1.0 - a) * (1.0 - b) / (1.0 - a * b);
}

// Runs the locked plant with the legs at duties d until the ripple is
// periodic (30 time constants), then returns the peak-to-peak of i_a over
// the last ten control periods.
double locked_ripple(mcsim::PmPlant& plant, const InverterParams& p, const double* d, double v_dc)
{
    const int legs = mcsim::PlantLoad(plant).legs();
    SwitchedPwm pwm(p, legs, kTs);
    RecordingLoad load(plant);
    const double tau = plant.motor().L_H / plant.motor().R_ohm;
    const int periods = static_cast<int>(30.0 * tau / kTs);
    for (int k = 0; k < periods; ++k) {
        load.record = k >= periods - 10;
        pwm.run_period(load, d, d, 0.0, v_dc);
    }
    return load.hi - load.lo;
}

// (b) The ripple of a locked-rotor winding under a constant duty, ideal
// legs (no dead time, no drops).
// PMSM (paper 001's motor, 48 V, 20 kHz): leg a at duty d, legs b and c
// held at the low rail. The star point floats at the legs' mean, so phase
// a sees v_a - (v_a + v_b + v_c)/3 = (2/3) V_dc while leg a is high, 0 while
// it is low: V1 = 2 V_dc/3, t_h = d T, t_l = (1 - d) T, the centred pulse
// repeating every carrier period T:
//   di_pp ~ (2/3) V_dc d (1 - d) T / L.
// Stepper (paper 000's, 30 V bus, 20 kHz): the winding's legs at duties
// d1 = 1/2 + D/2 and d2 = 1/2 - D/2 (D = v/V_dc), both centred: the winding
// sees V_dc where leg 1 is high and leg 2 low, two pulses of D T/2 per
// carrier period T/2 apart, 0 between (both high or both low): V1 = V_dc,
// t_h = D T/2, t_l = (1 - D) T/2, the ripple at twice the carrier:
//   di_pp ~ V_dc D (1 - D) T / (2 L).
// Both to 1e-8 of the exact closed form (RK4 over segments of at most
// T = 50 us against tau = 17 ms and 3 ms: h/tau <= 0.017, a local error of
// (h/tau)^5/120 = 1e-11 of the current at worst), and the small-T/tau form
// within its own first-order error (1 %).
// Broken once: each control period's segments replaced by one step of
// their mean voltages (the averaged legs): no ripple, both cases fail.
TEST(Ripple, LockedRotorPeakToPeakIsTheClosedForm)
{
    InverterParams p;
    p.f_pwm_Hz = kFpwm;  // ideal legs: dead time and drops 0
    const double T = 1.0 / kFpwm;
    {
        const mcsim::MotorParams m = paper001_motor();
        mcsim::PmPlant plant(m, mcsim::LoadProfile(), 1);
        const double d_a = 0.3;
        const double v1 = 2.0 / 3.0 * kVdc;
        mcsim::PmPlant::State x0 = mcsim::PmPlant::State::Zero();
        x0[mcsim::PmPlant::kIa] = v1 * d_a / m.R_ohm;  // start at the mean: a short transient
        plant.reset(x0);
        plant.set_locked(true);
        const double d[3] = {d_a, 0.0, 0.0};
        const double pp = locked_ripple(plant, p, d, kVdc);
        const double exact = ripple_closed_form(v1, d_a * T, (1.0 - d_a) * T, m.R_ohm, m.L_H);
        const double first_order = v1 * d_a * (1.0 - d_a) * T / m.L_H;
        std::printf("PMSM, leg a at d = %.2f: ripple %.9g A pp, closed form %.9g A, (2/3) V d (1-d) T / L = %.6g A\n",
                    d_a, pp, exact, first_order);
        EXPECT_NEAR(pp, exact, 1e-8 * exact);
        EXPECT_NEAR(pp, first_order, 0.01 * first_order);
    }
    {
        const mcsim::MotorParams m = paper000_stepper();
        mcsim::PmPlant plant(m, mcsim::LoadProfile(), 1);
        const double v_bus = 30.0;
        const double D = 0.4;  // the winding commanded 12 V
        mcsim::PmPlant::State x0 = mcsim::PmPlant::State::Zero();
        x0[mcsim::PmPlant::kIa] = v_bus * D / m.R_ohm;
        plant.reset(x0);
        plant.set_locked(true);
        const Inverter inv(p);
        const double cmd[2] = {D * v_bus, 0.0};
        double d[SwitchedPwm::kMaxLegs];
        ASSERT_EQ(SwitchedPwm::leg_duties(inv, 2, cmd, v_bus, d), 4);
        EXPECT_DOUBLE_EQ(d[0] - d[1], D);
        const double pp = locked_ripple(plant, p, d, v_bus);
        const double exact = ripple_closed_form(v_bus, D * T / 2.0, (1.0 - D) * T / 2.0, m.R_ohm, m.L_H);
        const double first_order = v_bus * D * (1.0 - D) * T / (2.0 * m.L_H);
        std::printf("stepper H-bridge, D = %.2f: ripple %.9g A pp, closed form %.9g A, V D (1-D) T / (2 L) = %.6g A\n",
                    D, pp, exact, first_order);
        EXPECT_NEAR(pp, exact, 1e-8 * exact);
        EXPECT_NEAR(pp, first_order, 0.01 * first_order);
    }
}

// The compute delay: the legs compare the carrier with the previous
// command's duty before D Ts, the new one's after. With two carrier periods
// a control period and D = 1/2 the switch falls between them (in V0, every
// leg low): the period's mean is half of each command's; D = 0 the new
// one's, D = 1 the previous one's.
// Broken once: the new duty over the whole period (t_switch ignored): the
// D = 1/2 and D = 1 cases fail.
TEST(Delay, PreviousDutyBeforeTheDelayNewAfter)
{
    InverterParams p;
    p.dead_time_s = 500e-9;
    p = with_hard_sign(p);
    const Inverter inv(p);
    const double i = 3.0;
    const double v_prev = -5.0, v_new = 8.0;
    const double d_prev = inv.duty(v_prev, kVdc), d_new = inv.duty(v_new, kVdc);
    const double avg_prev = inv.leg_voltage(v_prev, i, kVdc), avg_new = inv.leg_voltage(v_new, i, kVdc);
    for (double D : {0.0, 0.5, 1.0}) {
        SwitchedPwm pwm(p, 1, kTs);
        ASSERT_EQ(pwm.carrier_periods(), 2);
        ConstantCurrentLoad load(1, &i);
        pwm.run_period(load, &d_prev, &d_prev, 0.0, kVdc);  // the previous command established
        load.reset();
        pwm.run_period(load, &d_prev, &d_new, D * kTs, kVdc);
        EXPECT_NEAR(load.mean(0), D * avg_prev + (1.0 - D) * avg_new, 1e-9 * kVdc) << "D = " << D;
    }
}

TEST(Ratio, WholeNumberOfCarrierPeriods)
{
    EXPECT_EQ(SwitchedPwm::carrier_periods(20e3, 1e-4), 2);    // VESC 6 at 10 kHz
    EXPECT_EQ(SwitchedPwm::carrier_periods(24e3, 1.0 / 8e3), 3);  // ODrive: 8 kHz control
    EXPECT_EQ(SwitchedPwm::carrier_periods(10e3, 1e-4), 1);
    EXPECT_EQ(SwitchedPwm::carrier_periods(24e3, 1e-4), 0);    // ODrive's carrier at 10 kHz: 2.4
    EXPECT_EQ(SwitchedPwm::carrier_periods(20e3 * (1.0 + 1e-6), 1e-4), 0);  // one timer clock off
    EXPECT_EQ(SwitchedPwm::carrier_periods(5e3, 1e-4), 0);     // half a carrier period
    EXPECT_EQ(SwitchedPwm::carrier_periods(1.28e6, 1e-4), 128);
    EXPECT_EQ(SwitchedPwm::carrier_periods(1.29e6, 1e-4), 0);  // beyond pwm_plan()'s 128
}

// The backend: the drive's currents are the plant's at the period's
// boundary (the middle of V0, ripple included), and the plant is advanced
// exactly as SwitchedPwm advances a twin plant given the same duties and
// the compute delay's instant: bit for bit.
// Broken once: the backend's switched branch disabled (the averaged
// inverter): the twin's states differ, fails.
struct Ctx {
    int tick = 0;
};
void stepping_commands(void* ctx, const hal_sample_t*, hal_command_t* out)
{
    Ctx* c = static_cast<Ctx*>(ctx);
    out->n_phases = 3;
    const double a = 0.7 * static_cast<double>(c->tick);  // a turning 6 V vector
    out->v_V[0] = mcsim::to_mc(6.0 * std::cos(a));
    out->v_V[1] = mcsim::to_mc(6.0 * std::cos(a - 2.0943951023931953));
    out->v_V[2] = mcsim::to_mc(6.0 * std::cos(a + 2.0943951023931953));
    ++c->tick;
}

TEST(Backend, SamplesAtTheBoundaryAndHonoursTheComputeDelay)
{
    const mcsim::MotorParams m = paper001_motor();
    mcsim::PmPlant plant(m, mcsim::LoadProfile(), 1);
    mcsim::PmPlant twin(m, mcsim::LoadProfile(), 1);
    plant.reset(mcsim::PmPlant::State::Zero());
    twin.reset(mcsim::PmPlant::State::Zero());
    mcsim::CurrentSensor sensor(mcsim::SensorParams{}, 1);  // ideal: the sample is the current
    mcsim::Amplifier amp;
    amp.v_max_V = 0.5 * kVdc;
    InverterParams p;
    p.f_pwm_Hz = kFpwm;
    p.dead_time_s = 500e-9;
    p.r_switch_Ohm = 1.6e-3;
    p.pwm = PwmModel::kSwitched;
    const Inverter inv(p);
    const double delay = 0.3;
    hal_sw_plant_attach(&plant, &sensor, amp, kTs);
    ASSERT_TRUE(hal_sw_plant_set_compute_delay(delay));
    hal_sw_plant_set_inverter(&inv);
    Ctx ctx;
    ASSERT_TRUE(hal_start(stepping_commands, &ctx));
    SwitchedPwm pwm(p, 3, kTs);
    double d_prev[3] = {0.5, 0.5, 0.5};
    for (int n = 0; n < 40; ++n) {
        double i[3];
        twin.phase_currents(i);
        ASSERT_EQ(hal_sw_plant_run(1), 1u) << hal_last_error();
        const hal_sw_plant_period_t* rec = hal_sw_plant_last_period();
        EXPECT_EQ(rec->i_a_meas_A, i[0]) << n;
        EXPECT_EQ(rec->i_b_meas_A, i[1]) << n;
        const double cmd[3] = {rec->v_a_cmd_V, rec->v_b_cmd_V, rec->v_c_cmd_V};
        double d_new[3];
        SwitchedPwm::leg_duties(inv, 3, cmd, kVdc, d_new);
        mcsim::PlantLoad load(twin);
        pwm.run_period(load, d_prev, d_new, delay * kTs, kVdc);
        std::copy(d_new, d_new + 3, d_prev);
        for (int k = 0; k < 4; ++k) {
            EXPECT_EQ(plant.state()[k], twin.state()[k]) << "period " << n << ", state " << k;
        }
    }
    // the period's record: the averaged model's voltage for the command
    const hal_sw_plant_period_t* rec = hal_sw_plant_last_period();
    EXPECT_EQ(rec->v_a_V, inv.leg_voltage(rec->v_a_cmd_V, rec->i_a_meas_A, kVdc));
    hal_sw_plant_detach();
}

// A switched inverter whose carrier does not divide the control period:
// the backend refuses to start and to run (the scenario refuses it first).
TEST(Backend, RefusesAFractionalCarrierRatio)
{
    mcsim::PmPlant plant(paper001_motor(), mcsim::LoadProfile(), 1);
    plant.reset(mcsim::PmPlant::State::Zero());
    mcsim::CurrentSensor sensor(mcsim::SensorParams{}, 1);
    mcsim::Amplifier amp;
    amp.v_max_V = 0.5 * kVdc;
    InverterParams p;
    p.f_pwm_Hz = 24e3;
    p.pwm = PwmModel::kSwitched;
    const Inverter inv(p);
    hal_sw_plant_attach(&plant, &sensor, amp, kTs);
    hal_sw_plant_set_inverter(&inv);
    Ctx ctx;
    EXPECT_FALSE(hal_start(stepping_commands, &ctx));
    EXPECT_NE(std::string(hal_last_error()).find("whole number of carrier periods"), std::string::npos);
    EXPECT_EQ(hal_sw_plant_run(1), 0u);
    hal_sw_plant_detach();
}

}  // namespace
