// The software-plant HAL backend: hal.h contract (start, rate, time, safe
// state, errors) and the period order sample -> callback -> amplifier ->
// plant with the voltages held.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "hal/hal.h"
#include "hal_sw_plant.h"
#include "mc_convert.h"
#include "test_motors.h"

namespace {

using mcsim_test::paper000_stepper;

struct Ctx {
    double v_a_V = 0.0;
    double v_b_V = 0.0;
    int safe_at_tick = -1;
    std::vector<hal_sample_t> samples;
};

void callback(void* ctx, const hal_sample_t* in, hal_command_t* out)
{
    Ctx* c = static_cast<Ctx*>(ctx);
    c->samples.push_back(*in);
    out->n_phases = 2;
    out->v_V[0] = mcsim::to_mc(c->v_a_V);
    out->v_V[1] = mcsim::to_mc(c->v_b_V);
    if (static_cast<int>(in->tick) == c->safe_at_tick) {
        hal_safe_state();
    }
}

std::vector<hal_sw_plant_period_t> g_periods;
void monitor(void*, const hal_sw_plant_period_t* p) { g_periods.push_back(*p); }

class HalSwPlant : public ::testing::Test {
protected:
    HalSwPlant() : plant(paper000_stepper(), mcsim::LoadProfile(), 4), sensor(mcsim::SensorParams{}, 1)
    {
        plant.reset(mcsim::PmPlant::State::Zero());
        amp.v_max_V = 30.0;
        g_periods.clear();
    }
    ~HalSwPlant() override { hal_sw_plant_detach(); }

    mcsim::PmPlant plant;
    mcsim::CurrentSensor sensor;
    mcsim::Amplifier amp;
    Ctx ctx;
};

TEST_F(HalSwPlant, StartNeedsAPlant)
{
    hal_sw_plant_detach();
    EXPECT_FALSE(hal_start(callback, &ctx));
    EXPECT_STRNE(hal_last_error(), "");
    EXPECT_EQ(hal_sw_plant_run(10), 0u);
    EXPECT_TRUE(ctx.samples.empty());
}

TEST_F(HalSwPlant, RateTimeAndTicks)
{
    hal_sw_plant_attach(&plant, &sensor, amp, 1e-4);
    EXPECT_EQ(hal_control_rate_hz(), 10000u);
    ASSERT_TRUE(hal_start(callback, &ctx));
    EXPECT_EQ(hal_time_us(), 0u);
    EXPECT_EQ(hal_sw_plant_run(25), 25u);
    EXPECT_EQ(hal_time_us(), 2500u);
    ASSERT_EQ(ctx.samples.size(), 25u);
    for (std::uint32_t k = 0; k < 25; ++k) {
        EXPECT_EQ(ctx.samples[k].tick, k);
        // a two-phase stepper on a stiff 30 V supply, no position sensor
        EXPECT_EQ(ctx.samples[k].n_phases, 2);
        EXPECT_EQ(mcsim::to_double(ctx.samples[k].v_bus_V), mcsim::to_double(mcsim::to_mc(30.0)));
        EXPECT_FALSE(ctx.samples[k].has_angle);
        EXPECT_EQ(ctx.samples[k].status, 0u);
        EXPECT_EQ(mcsim::to_double(ctx.samples[k].i_A[2]), 0.0);
    }
    EXPECT_NEAR(plant.time_s(), 25e-4, 1e-15);
}

TEST_F(HalSwPlant, VoltagesHeldAndClampedCurrentsSampledAtPeriodStart)
{
    hal_sw_plant_attach(&plant, &sensor, amp, 1e-4);
    hal_sw_plant_set_monitor(monitor, nullptr);
    ctx.v_a_V = 45.0;  // beyond the supply: the amplifier gives 30 V
    ASSERT_TRUE(hal_start(callback, &ctx));
    hal_sw_plant_run(50);
    const mcsim::MotorParams m = paper000_stepper();
    ASSERT_EQ(g_periods.size(), 50u);
    for (std::size_t k = 0; k < 50; ++k) {
        EXPECT_EQ(g_periods[k].v_a_cmd_V, 45.0);
        EXPECT_EQ(g_periods[k].v_a_V, 30.0);
        EXPECT_EQ(g_periods[k].v_b_V, 0.0);
        // Sample k sees the current at t_k = k Ts of the RL step (locked
        // rotor at theta = 0): the command of sample k acts only afterwards.
        const double t = static_cast<double>(k) * 1e-4;
        const double i = 30.0 / m.R_ohm * (1.0 - std::exp(-t * m.R_ohm / m.L_H));
        EXPECT_NEAR(mcsim::to_double(ctx.samples[k].i_A[0]), i, 1e-5);
        EXPECT_NEAR(g_periods[k].i_a_meas_A, i, 1e-9);
        EXPECT_TRUE(g_periods[k].control_called);
    }
    EXPECT_EQ(hal_sw_plant_last_period()->tick, 49u);
}

TEST_F(HalSwPlant, SafeStateStopsCallbackAndZeroesVoltage)
{
    hal_sw_plant_attach(&plant, &sensor, amp, 1e-4);
    hal_sw_plant_set_monitor(monitor, nullptr);
    ctx.v_a_V = 10.0;
    ctx.safe_at_tick = 5;
    ASSERT_TRUE(hal_start(callback, &ctx));
    hal_sw_plant_run(20);
    EXPECT_TRUE(hal_sw_plant_in_safe_state());
    EXPECT_EQ(ctx.samples.size(), 6u);  // ticks 0..5
    ASSERT_EQ(g_periods.size(), 20u);
    EXPECT_EQ(g_periods[4].v_a_V, 10.0);
    for (std::size_t k = 5; k < 20; ++k) {
        EXPECT_EQ(g_periods[k].v_a_V, 0.0) << k;  // from the period that asked for it
        EXPECT_EQ(g_periods[k].control_called, k == 5);
    }
    // A new start leaves the safe state.
    ASSERT_TRUE(hal_start(callback, &ctx));
    EXPECT_FALSE(hal_sw_plant_in_safe_state());
}

}  // namespace
