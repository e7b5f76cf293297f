// The paper-000 drive on the simulated rig, through the software-plant HAL:
// behaviour that only shows in closed loop (the limiter and its anti-windup).
#include <cmath>
#include <iomanip>
#include <vector>

#include <gtest/gtest.h>

#include "hal/hal.h"
#include "hal_sw_plant.h"
#include "mc_convert.h"
#include "host_drives/paper000_host.h"
#include "host_drives/paper001_host.h"
#include "scenario/rig.h"
#include "scenario/scenario.h"

namespace {

// One period as the drive saw it.
struct Period {
    bool ok;            // paper000_drive_step's return value
    drive_mode_t mode;
    double v_a_V, v_b_V;
    bool saturated;
    double u1_before_V, u1_after_V;  // integral of the i_f super-twisting loop
};

struct Ctx {
    paper000_drive_t* drive;
    std::uint32_t offset_from, offset_to;  // ticks with a fake current offset
    double offset_A;
    std::vector<Period> log;
};

void control(void* p, const hal_sample_t* in, hal_command_t* out)
{
    Ctx* c = static_cast<Ctx*>(p);
    const bool fake = in->tick >= c->offset_from && in->tick < c->offset_to;
    const mc_t off = mcsim::to_mc(fake ? c->offset_A : 0.0);
    Period q{};
    q.u1_before_V = mcsim::to_double(c->drive->ctrl.cur.u1);
    hal_sample_t faked = *in;
    faked.i_A[0] = mc_add(in->i_A[0], off);
    faked.i_A[1] = mc_add(in->i_A[1], off);
    q.ok = paper000_drive_step(c->drive, &faked, out);
    q.u1_after_V = mcsim::to_double(c->drive->ctrl.cur.u1);
    paper000_telemetry_t t;
    paper000_drive_get_telemetry(c->drive, &t);
    q.mode = t.mode;
    q.v_a_V = mcsim::to_double(out->v_V[0]);
    q.v_b_V = mcsim::to_double(out->v_V[1]);
    q.saturated = t.v_saturated;
    c->log.push_back(q);
    if (!q.ok) hal_safe_state();
}

// rounding of the limiter's scale V_max/|v|: float, or in fixed point one
// Q14.17 LSB (7.6e-6) of the scale times the unlimited voltage, up to about
// twice V_max here: 1.5e-5 of V_max
constexpr double kRel = MC_FIXED ? 2e-5 : 1e-6;

}  // namespace

// In closed loop at speed, a 2.5 A error on both measured currents (a
// sensor glitch, below the 4.5 A trip) makes the laws ask for more than a
// 12 V supply: every phase voltage stays within +-V_max, the limited
// vector touches the limit, the step still succeeds, and the i_f integral
// is frozen on the samples after a saturated one (anti-windup).
TEST(DriveOnPlant, ClosedLoopSaturationLimitsAndHoldsTheIntegral)
{
    mcsim::Scenario sc = mcsim::load_scenario(std::string(MC_SOURCE_DIR) + "/sim/scenarios/paper000_ideal.toml");
    sc.v_max_V = 12.0;
    sc.align_rotor = 0;  // the ticks below count from the start of the move
    paper000_drive_t drive;
    mcsim::design_and_init_drive(sc, &drive);
    mcsim::Rig rig(sc);
    hal_sw_plant_attach(&rig.plant, &rig.sensor, rig.amp, sc.ts_s);
    Ctx ctx{&drive, 10000u, 10050u, 2.5, {}};
    ASSERT_TRUE(hal_start(control, &ctx));
    hal_sw_plant_run(10200u);
    hal_sw_plant_detach();
    ASSERT_EQ(ctx.log.size(), 10200u);

    int saturated = 0, held = 0;
    for (std::uint32_t k = 10000u; k < 10050u; ++k) {
        const Period& q = ctx.log[k];
        ASSERT_TRUE(q.ok) << "tick " << k;
        ASSERT_EQ(q.mode, DRIVE_MODE_CLOSED_LOOP) << "tick " << k;
        const double peak = std::fmax(std::fabs(q.v_a_V), std::fabs(q.v_b_V));
        EXPECT_LE(peak, 12.0 * (1 + kRel)) << std::setprecision(9) << peak << " at tick " << k;
        if (q.saturated) {
            ++saturated;
            EXPECT_NEAR(peak, 12.0, 1e-3) << "tick " << k;  // scaled onto the limit, not below it
        }
        if (ctx.log[k - 1].saturated) {
            ++held;
            EXPECT_EQ(q.u1_after_V, q.u1_before_V) << "tick " << k << ": integral moved while saturated";
        }
    }
    EXPECT_GE(saturated, 10) << "the test did not drive the limiter";
    EXPECT_GE(held, 10);
}

// Issue 9: long holds must not drive the firmware into subnormal numbers
// (they cost tens to hundreds of cycles per operation on many FPUs and in
// soft-float). Each drive step runs with the underflow flag cleared and is
// checked after: the flag is raised when a result is subnormal (and
// inexact). The move of paper 000's experiment, then 60 s of hold at rest;
// the paper-001 speed drive's benchmark stops at 9 s and holds to 10 s, so
// its profile is stretched with a 60 s hold at zero speed. Float build only
// (the fixed-point build has no floating point to underflow).
#include <cfenv>

namespace {

struct UnderflowCtx {
    void* drive;
    bool speed;
    std::uint32_t first_tick = 0, count = 0;
};

void control_underflow(void* p, const hal_sample_t* in, hal_command_t* out)
{
    UnderflowCtx* c = static_cast<UnderflowCtx*>(p);
    std::feclearexcept(FE_UNDERFLOW);
    const bool ok = c->speed ? paper001_drive_step(static_cast<paper001_drive_t*>(c->drive), in, out)
                             : paper000_drive_step(static_cast<paper000_drive_t*>(c->drive), in, out);
    if (std::fetestexcept(FE_UNDERFLOW)) {
        if (c->count == 0) {
            c->first_tick = in->tick;
        }
        ++c->count;
    }
    if (!ok) hal_safe_state();
}

}  // namespace

TEST(DriveOnPlant, LongHoldGivesNoSubnormalsInThePositionDrive)
{
    if (MC_FIXED) GTEST_SKIP() << "no floating point in the fixed-point firmware";
    mcsim::Scenario sc = mcsim::load_scenario(std::string(MC_SOURCE_DIR) + "/sim/scenarios/paper000_experiment.toml");
    sc.duration_s = 64.25;
    paper000_drive_t drive;
    mcsim::design_and_init_drive(sc, &drive);
    mcsim::Rig rig(sc);
    hal_sw_plant_attach(&rig.plant, &rig.sensor, rig.amp, sc.ts_s);
    UnderflowCtx ctx{&drive, false};
    ASSERT_TRUE(hal_start(control_underflow, &ctx));
    hal_sw_plant_run(sc.n_ticks());
    hal_sw_plant_detach();
    EXPECT_EQ(ctx.count, 0u) << "first underflow at tick " << ctx.first_tick;
}

TEST(DriveOnPlant, LongHoldGivesNoSubnormalsInTheSpeedDrive)
{
    if (MC_FIXED) GTEST_SKIP() << "no floating point in the fixed-point firmware";
    mcsim::Scenario sc = mcsim::load_scenario(std::string(MC_SOURCE_DIR) + "/sim/scenarios/paper001_benchmark.toml");
    sc.speed_points.back().first = 70.0;
    sc.duration_s = 70.0;
    paper001_drive_t drive;
    mcsim::design_and_init_speed_drive(sc, &drive, nullptr);
    mcsim::Rig rig(sc);
    hal_sw_plant_attach(&rig.plant, &rig.sensor, rig.amp, sc.ts_s);
    UnderflowCtx ctx{&drive, true};
    ASSERT_TRUE(hal_start(control_underflow, &ctx));
    hal_sw_plant_run(sc.n_ticks());
    hal_sw_plant_detach();
    EXPECT_EQ(ctx.count, 0u) << "first underflow at tick " << ctx.first_tick;
}
