// The dead-time compensation (control/deadtime_comp.h) and its design
// (design/deadtime_comp_design.h) against hand-computed cases, in this
// build's numeric type; and the compensation against the plant's inverter
// model (sim/model/inverter.h): the compensated command through the
// inverter gives back the intended voltage.
#include <gtest/gtest.h>

#include <cmath>

extern "C" {
#include "control/deadtime_comp.h"
#include "design/deadtime_comp_design.h"
#include "math/mc_convert.h"
}

#include "fw_test_util.h"
#include "model/inverter.h"

using fwtest::D;
using fwtest::M;

namespace {
#if MC_FIXED
constexpr double kTol = 2e-4;
#else
constexpr double kTol = 1e-5;
#endif

// The VESC 6 of sim/inverters/vesc6.toml: 20 kHz, 500 ns, 1.6 mOhm channel,
// 0.8 V / 0.5 mOhm diode, i_tr 0.4 A.
deadtime_comp_design_input_t vesc6()
{
    deadtime_comp_design_input_t in{};
    in.f_pwm_Hz = 20e3;
    in.dead_time_s = 500e-9;
    in.r_switch_Ohm = 1.6e-3;
    in.v_diode_V = 0.8;
    in.r_diode_Ohm = 0.5e-3;
    in.i_transition_A = 0.4;
    in.synchronous = true;
    return in;
}
const deadtime_comp_design_input_t* vesc6_in()
{
    static const deadtime_comp_design_input_t in = vesc6();
    return &in;
}
}  // namespace

TEST(DeadtimeComp, DesignHandComputed)
{
    deadtime_comp_config_t c;
    char err[128];
    ASSERT_TRUE(deadtime_comp_design(vesc6_in(), &c, err, sizeof err));
    EXPECT_TRUE(c.enabled);
    // k_bus = 500 ns * 20 kHz = 0.01; the diode conducts 2 * 0.01 = 2 % of
    // the period: V_0 = 0.02 * 0.8 = 0.016 V, r = 0.98 * 1.6e-3 + 0.02 * 0.5e-3
    EXPECT_NEAR(D(c.k_bus), 0.01, 1e-5);  // Q14.17: 0.01 to 2.1e-6
    EXPECT_NEAR(D(c.v_drop_V), 0.016, 1e-5);
    EXPECT_NEAR(D(c.r_drop_ohm), 0.98 * 1.6e-3 + 0.02 * 0.5e-3, 1e-5);
    EXPECT_NEAR(D(c.inv_i_band_per_A), 2.5, 1e-5);
    // the sensor's noise widens the band: 3 sigma of 0.2 A = 0.6 A > 0.4 A
    deadtime_comp_design_input_t noisy = vesc6();
    noisy.i_noise_A = 0.2;
    ASSERT_TRUE(deadtime_comp_design(&noisy, &c, err, sizeof err));
    EXPECT_NEAR(D(c.inv_i_band_per_A), 1.0 / 0.6, 1e-5);
    // refusals name the problem
    deadtime_comp_design_input_t bad = vesc6();
    bad.dead_time_s = -1e-9;
    EXPECT_FALSE(deadtime_comp_design(&bad, &c, err, sizeof err));
    EXPECT_NE(std::string(err).find("must be finite and >= 0"), std::string::npos);
    bad = vesc6();
    bad.dead_time_s = 20e-6;
    EXPECT_FALSE(deadtime_comp_design(&bad, &c, err, sizeof err));
    EXPECT_NE(std::string(err).find("half the PWM period"), std::string::npos);
}

TEST(DeadtimeComp, LegErrorHandComputed)
{
    deadtime_comp_config_t c;
    char err[128];
    ASSERT_TRUE(deadtime_comp_design(vesc6_in(), &c, err, sizeof err));
    deadtime_comp_t d;
    ASSERT_TRUE(deadtime_comp_init(&d, &c));
    // 48 V bus, 2 A (x = 5 of the 0.4 A band, s = 0.9): -0.9 (48 * 0.01 + 0.016) - r * 2
    const double r = 0.98 * 1.6e-3 + 0.02 * 0.5e-3;
    EXPECT_NEAR(D(deadtime_comp_leg_error_V(&d, M(2.0), M(48.0))), -0.9 * (0.48 + 0.016) - 2.0 * r, kTol);
    EXPECT_NEAR(D(deadtime_comp_leg_error_V(&d, M(-2.0), M(48.0))), 0.9 * (0.48 + 0.016) + 2.0 * r, kTol);
    // inside the band x/2: 0.1 A of 0.4 A is x = 1/4, s = 1/8
    EXPECT_NEAR(D(deadtime_comp_leg_error_V(&d, M(0.1), M(48.0))), -0.125 * 0.496 - 0.1 * r, kTol);
    // beyond it 1 - 1/(2x): 2 A is x = 5, s = 0.9 (above: 2 A as 0.9 of it)
    EXPECT_NEAR(D(deadtime_comp_sign(&d, M(2.0))), 0.9, kTol);
    EXPECT_NEAR(D(deadtime_comp_sign(&d, M(-0.4))), -0.5, kTol);
    EXPECT_NEAR(D(deadtime_comp_leg_error_V(&d, M(0.0), M(48.0))), 0.0, kTol);
    // disabled: nothing, and the command untouched
    deadtime_comp_config_t off{};
    deadtime_comp_t d0;
    ASSERT_TRUE(deadtime_comp_init(&d0, &off));
    EXPECT_EQ(D(deadtime_comp_leg_error_V(&d0, M(2.0), M(48.0))), 0.0);
    hal_command_t out{};
    out.n_phases = 3u;
    out.v_V[0] = M(1.0);
    out.v_V[1] = M(-2.0);
    out.v_V[2] = M(1.0);
    const mc_t i[3] = {M(2.0), M(-1.0), M(-1.0)};
    const mc_ab_t lost = deadtime_comp_step(&d0, i, M(48.0), &out);
    EXPECT_EQ(D(out.v_V[0]), 1.0);
    EXPECT_EQ(D(out.v_V[1]), -2.0);
    EXPECT_EQ(D(lost.alpha), 0.0);
    EXPECT_EQ(D(lost.beta), 0.0);
}

TEST(DeadtimeComp, CompensatedCommandThroughThePlantsInverterIsTheIntendedVoltage)
{
    // the same leg in the plant's model, with its transition through zero
    // (the same law (2)), at currents inside and beyond the band
    deadtime_comp_config_t c;
    char err[128];
    ASSERT_TRUE(deadtime_comp_design(vesc6_in(), &c, err, sizeof err));
    deadtime_comp_t d;
    ASSERT_TRUE(deadtime_comp_init(&d, &c));
    mcsim::InverterParams p;
    p.f_pwm_Hz = 20e3;
    p.dead_time_s = 500e-9;
    p.r_switch_Ohm = 1.6e-3;
    p.v_diode_V = 0.8;
    p.r_diode_Ohm = 0.5e-3;
    p.i_transition_A = 0.4;
    const mcsim::Inverter inv(p);
    const double v_bus = 48.0;
    const double v_want[3] = {5.0, -3.0, -2.0};
    const double i_leg[3] = {3.0, -0.2, -2.8};
    hal_command_t out{};
    out.n_phases = 3u;
    mc_t i_mc[3];
    for (int k = 0; k < 3; ++k) {
        out.v_V[k] = M(v_want[k]);
        i_mc[k] = M(i_leg[k]);
    }
    const mc_ab_t lost = deadtime_comp_step(&d, i_mc, M(v_bus), &out);
    EXPECT_EQ(D(lost.alpha), 0.0);
    double v_cmd[3], v_leg[3], v_ph[3], v_ph_want[3];
    for (int k = 0; k < 3; ++k) {
        v_cmd[k] = D(out.v_V[k]);
    }
    inv.apply(3, v_cmd, i_leg, v_bus, v_leg);
    mcsim::Inverter::phase_voltages(v_leg, v_ph);
    mcsim::Inverter::phase_voltages(v_want, v_ph_want);
    for (int k = 0; k < 3; ++k) {
        // the leg's drop weighting is the design's (the diode in the dead
        // times): exact to the numeric type's resolution
        EXPECT_NEAR(v_ph[k], v_ph_want[k], 1e-3) << k;
    }
    // without the compensation the same command misses by the dead time
    inv.apply(3, v_want, i_leg, v_bus, v_leg);
    mcsim::Inverter::phase_voltages(v_leg, v_ph);
    EXPECT_GT(std::fabs(v_ph[0] - v_ph_want[0]), 0.3);
}

TEST(DeadtimeComp, ClampedCompensationIsReturnedForTheEstimator)
{
    deadtime_comp_config_t c;
    char err[128];
    ASSERT_TRUE(deadtime_comp_design(vesc6_in(), &c, err, sizeof err));
    deadtime_comp_t d;
    ASSERT_TRUE(deadtime_comp_init(&d, &c));
    // leg a at the +24 V rail wants +0.5 V more: it gets none of it
    hal_command_t out{};
    out.n_phases = 3u;
    out.v_V[0] = M(24.0);
    out.v_V[1] = M(-12.0);
    out.v_V[2] = M(-12.0);
    const mc_t i[3] = {M(2.0), M(-1.0), M(-1.0)};
    const mc_ab_t lost = deadtime_comp_step(&d, i, M(48.0), &out);
    EXPECT_NEAR(D(out.v_V[0]), 24.0, kTol);
    const double r = 0.98 * 1.6e-3 + 0.02 * 0.5e-3;
    const double comp_a = 0.9 * 0.496 + 2.0 * r;
    // lost on leg a only: r = (-comp_a, 0, 0); alpha = r_a - mean = -2/3 comp_a,
    // beta = (r_b - r_c)/sqrt(3) = 0
    EXPECT_NEAR(D(lost.alpha), -2.0 / 3.0 * comp_a, kTol);
    EXPECT_NEAR(D(lost.beta), 0.0, kTol);
    // a stepper's H-bridge winding: two legs' errors, clamped at +-V_bus
    hal_command_t w{};
    w.n_phases = 2u;
    w.v_V[0] = M(10.0);
    w.v_V[1] = M(-30.0);
    const mc_t iw[2] = {M(1.0), M(-1.0)};
    const mc_ab_t lw = deadtime_comp_step(&d, iw, M(30.0), &w);
    const double e1 = 2.0 * (0.8 * (30.0 * 0.01 + 0.016) + 1.0 * r);
    EXPECT_NEAR(D(w.v_V[0]), 10.0 + e1, kTol);
    EXPECT_NEAR(D(w.v_V[1]), -30.0, kTol);
    EXPECT_NEAR(D(lw.alpha), 0.0, kTol);
    EXPECT_NEAR(D(lw.beta), e1, kTol);
}
