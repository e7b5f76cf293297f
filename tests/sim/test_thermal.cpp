// The first-order winding temperature of sim/model/thermal.h (issue 30)
// against the closed-form step response, R(T) and Phi(T) at the issue's
// coefficients, and the plant following it (and unchanged without it).
// ctest: sim.thermal.*
#include <cmath>

#include <gtest/gtest.h>

#include "model/load_profile.h"
#include "model/pm_plant.h"
#include "model/thermal.h"
#include "test_motors.h"

namespace {

using mcsim_test::paper001_motor;

using mcsim::PmPlant;
using mcsim::ThermalModel;
using mcsim::ThermalParams;

ThermalParams params(double alpha)
{
    ThermalParams p;
    p.R_th_K_per_W = 1.5;
    p.C_th_J_per_K = 400.0;  // tau = 600 s
    p.T_ambient_C = 25.0;
    p.T0_C = 25.0;
    p.alpha_cu_per_K = alpha;
    return p;
}

TEST(Model, StepResponseClosedForm)
{
    // constant resistance (alpha = 0): a current step of 10 A (|i_ab|^2 =
    // 100) in a 3-phase motor of R = 0.225 ohm: P = 1.5 * 0.225 * 100 =
    // 33.75 W, T_inf = 25 + 1.5 * 33.75 = 75.625 C, tau = 1.5 * 400 = 600 s:
    //   T(t) = T_inf + (T0 - T_inf) exp(-t / tau)
    ThermalModel th(params(0.0), 0.225, 0.17, 1.5);
    const double T_inf = 75.625, tau = 600.0;
    double t = 0.0;
    for (int k = 0; k < 3000; ++k) {
        th.step(100.0, 1.0);
        t += 1.0;
        const double T = T_inf + (25.0 - T_inf) * std::exp(-t / tau);
        ASSERT_NEAR(th.temperature_C(), T, 1e-9) << t;
    }
    // one time constant: 63.2 % of the rise
    ThermalModel one(params(0.0), 0.225, 0.17, 1.5);
    one.step(100.0, 600.0);
    EXPECT_NEAR(one.temperature_C(), 25.0 + (1.0 - std::exp(-1.0)) * 50.625, 1e-9);
    // the step is exact for a held loss: one big step = many small ones
    ThermalModel many(params(0.0), 0.225, 0.17, 1.5);
    for (int k = 0; k < 600000; ++k) {
        many.step(100.0, 1e-3);
    }
    EXPECT_NEAR(many.temperature_C(), one.temperature_C(), 1e-8);
}

TEST(Model, StepResponseWithCopperCoefficient)
{
    // R(T) = R_20 (1 + 0.0039 (T - 20)): the loss grows with T, so the
    // response is still first order but slower and higher:
    //   C dT/dt = k R20 (1 + a (T - 20)) I^2 - (T - Ta)/R_th
    //   1/tau' = 1/(R_th C) - k R20 a I^2 / C
    //   T_inf  = (Ta/R_th + k R20 (1 - 20 a) I^2) / (1/R_th - k R20 a I^2)
    const double a = 0.0039, k = 1.5, R20 = 0.225, I2 = 100.0, Rth = 1.5, C = 400.0, Ta = 25.0;
    const double inv_tau = 1.0 / (Rth * C) - k * R20 * a * I2 / C;
    const double T_inf = (Ta / Rth + k * R20 * (1.0 - 20.0 * a) * I2) / (1.0 / Rth - k * R20 * a * I2);
    ThermalModel th(params(a), R20, 0.17, k);
    for (int n = 1; n <= 4000; ++n) {
        th.step(I2, 1.0);
        const double T = T_inf + (Ta - T_inf) * std::exp(-n * inv_tau);
        ASSERT_NEAR(th.temperature_C(), T, 1e-9) << n;
    }
    EXPECT_GT(T_inf, 75.625);  // hotter than with a constant R
}

TEST(Model, ResistanceAndFluxAtTemperature)
{
    ThermalParams p = params(0.0039);
    p.T0_C = 80.0;  // the 60 K warm winding
    ThermalModel th(p, 0.225, 0.17, 1.5);
    EXPECT_NEAR(th.R_ohm(), 0.225 * (1.0 + 0.0039 * 60.0), 1e-15);  // +23.4 %
    EXPECT_NEAR(th.Phi_Wb(), 0.17 * (1.0 - 0.001 * 60.0), 1e-15);  // -6 %
    p.T0_C = 20.0;
    ThermalModel cold(p, 0.225, 0.17, 1.5);
    EXPECT_EQ(cold.R_ohm(), 0.225);
    EXPECT_EQ(cold.Phi_Wb(), 0.17);
    EXPECT_EQ(p.problem(), nullptr);
    ThermalParams half = p;
    half.C_th_J_per_K = 0.0;
    EXPECT_NE(half.problem(), nullptr);
}


TEST(Plant, WarmWindingAndItsSteadyState)
{
    // the plant takes R and Phi at T0 at once; a locked rotor with a held
    // alpha voltage then settles where the current V/R(T) heats the winding
    // to T = Ta + R_th k_m R(T) I^2 (a short C_th so it settles within 20 s)
    PmPlant p(paper001_motor(), mcsim::LoadProfile(), 1);
    ThermalParams tp = params(0.0039);
    tp.C_th_J_per_K = 0.5;  // tau under 1 s
    tp.T0_C = 80.0;
    p.set_thermal(tp);
    EXPECT_NEAR(p.motor().R_ohm, 0.225 * 1.234, 1e-15);
    EXPECT_NEAR(p.motor().Phi_Wb(), 0.17 * 0.94, 1e-15);
    p.reset(PmPlant::State::Zero());
    p.set_locked(true);
    const double v = 2.0;
    for (int k = 0; k < 200000; ++k) {  // 20 s
        p.step(v, 0.0, 1e-4);
    }
    const double T = p.thermal()->temperature_C();
    const double R = 0.225 * (1.0 + 0.0039 * (T - 20.0));
    EXPECT_NEAR(p.i_a_A(), v / R, 1e-9);
    EXPECT_NEAR(T, 25.0 + 1.5 * 1.5 * R * (v / R) * (v / R), 1e-6);
    EXPECT_NEAR(p.motor().R_ohm, R, 1e-12);
}

TEST(Plant, OffIsThePlantBitForBit)
{
    PmPlant a(paper001_motor(), mcsim::LoadProfile(), 1);
    PmPlant b(paper001_motor(), mcsim::LoadProfile(), 1);
    b.set_thermal(ThermalParams{});  // R_th = C_th = 0: none
    PmPlant::State x0 = PmPlant::State::Zero();
    x0[PmPlant::kOmega] = 10.0;
    a.reset(x0);
    b.reset(x0);
    for (int k = 0; k < 2000; ++k) {
        a.step(20.0 * std::cos(k * 0.003), 20.0 * std::sin(k * 0.003), 1e-4);
        b.step(20.0 * std::cos(k * 0.003), 20.0 * std::sin(k * 0.003), 1e-4);
        ASSERT_EQ(a.state(), b.state());
    }
    EXPECT_EQ(b.thermal(), nullptr);
}

}  // namespace
