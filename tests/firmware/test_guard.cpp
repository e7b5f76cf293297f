// The guard every drive runs its sample in (supervisor/guard.h): the
// reaction table, the re-lock budget, the latch and the flight recorder,
// one semantics for all drives.
#include <gtest/gtest.h>

#include <cstdint>

extern "C" {
#include "supervisor/guard.h"
}

namespace {

struct Shell {
    supervisor_t sup;
    flight_recorder_t rec;
    uint8_t reaction[DRIVE_FAULT_COUNT];
    Shell()
    {
        guard_start_closed_loop(&sup);
        flight_recorder_init(&rec);
        for (int f = 0; f < DRIVE_FAULT_COUNT; ++f) reaction[f] = static_cast<uint8_t>(FAULT_REACT_SAFE);
    }
};

}  // namespace

TEST(Guard, StartsClosedLoopWithoutFault)
{
    Shell s;
    EXPECT_EQ(s.sup.state, SUP_STATE_CLOSED_LOOP);
    EXPECT_EQ(s.sup.fault, DRIVE_FAULT_NONE);
    EXPECT_EQ(supervisor_mode(&s.sup), DRIVE_MODE_CLOSED_LOOP);
}

TEST(Guard, SafeLatchesAndKeepsTheFirstFault)
{
    Shell s;
    EXPECT_EQ(guard_react(&s.sup, &s.rec, s.reaction, DRIVE_FAULT_OVERCURRENT, 7u, true), GUARD_SAFE);
    EXPECT_EQ(s.sup.state, SUP_STATE_FAULT);
    EXPECT_EQ(s.sup.fault, DRIVE_FAULT_OVERCURRENT);
    EXPECT_TRUE(s.rec.frozen);
    EXPECT_EQ(s.rec.fault, DRIVE_FAULT_OVERCURRENT);
    EXPECT_EQ(s.rec.fault_tick, 7u);
    // a second fault is counted, the first stays
    EXPECT_EQ(guard_react(&s.sup, &s.rec, s.reaction, DRIVE_FAULT_I2T, 8u, true), GUARD_SAFE);
    EXPECT_EQ(s.sup.fault, DRIVE_FAULT_OVERCURRENT);
    EXPECT_EQ(s.rec.fault, DRIVE_FAULT_OVERCURRENT);
    EXPECT_EQ(s.rec.fault_tick, 7u);
    EXPECT_EQ(s.rec.events, 2u);
}

TEST(Guard, ReportRecordsAndGoesOn)
{
    Shell s;
    s.reaction[DRIVE_FAULT_SENSOR_STUCK] = static_cast<uint8_t>(FAULT_REACT_REPORT);
    EXPECT_EQ(guard_react(&s.sup, &s.rec, s.reaction, DRIVE_FAULT_SENSOR_STUCK, 3u, false), GUARD_GO_ON);
    EXPECT_EQ(s.sup.state, SUP_STATE_CLOSED_LOOP);
    EXPECT_EQ(s.sup.fault, DRIVE_FAULT_NONE);
    EXPECT_EQ(s.rec.events, 1u);
    EXPECT_EQ(s.rec.fault, DRIVE_FAULT_SENSOR_STUCK);
}

TEST(Guard, RelockOnlyWhereTheDriveCanElseSafe)
{
    Shell s;
    s.reaction[DRIVE_FAULT_LOSS_OF_SYNC] = static_cast<uint8_t>(FAULT_REACT_RELOCK);
    EXPECT_EQ(guard_react(&s.sup, &s.rec, s.reaction, DRIVE_FAULT_LOSS_OF_SYNC, 1u, true), GUARD_RELOCK);
    EXPECT_EQ(s.sup.state, SUP_STATE_CLOSED_LOOP) << "the drive's re-lock, not the latch";
    EXPECT_EQ(s.rec.events, 1u);
    // budget spent (or no re-lock in this drive): latched
    EXPECT_EQ(guard_react(&s.sup, &s.rec, s.reaction, DRIVE_FAULT_LOSS_OF_SYNC, 2u, false), GUARD_SAFE);
    EXPECT_EQ(s.sup.state, SUP_STATE_FAULT);
    EXPECT_EQ(s.sup.fault, DRIVE_FAULT_LOSS_OF_SYNC);
    EXPECT_EQ(s.rec.events, 2u);
}

TEST(Guard, ACodeOutsideTheEnumTakesTheReactionOfNone)
{
    Shell s;
    s.reaction[DRIVE_FAULT_NONE] = static_cast<uint8_t>(FAULT_REACT_REPORT);
    EXPECT_EQ(guard_react(&s.sup, &s.rec, s.reaction, static_cast<drive_fault_t>(200), 0u, false), GUARD_GO_ON);
    s.reaction[DRIVE_FAULT_NONE] = static_cast<uint8_t>(FAULT_REACT_SAFE);
    EXPECT_EQ(guard_react(&s.sup, &s.rec, s.reaction, static_cast<drive_fault_t>(200), 0u, false), GUARD_SAFE);
}

TEST(Guard, LatchIsRecordedAndFinal)
{
    Shell s;
    guard_latch(&s.sup, &s.rec, DRIVE_FAULT_BAD_INPUT, 42u);
    EXPECT_EQ(s.sup.state, SUP_STATE_FAULT);
    EXPECT_EQ(s.sup.fault, DRIVE_FAULT_BAD_INPUT);
    EXPECT_EQ(s.rec.fault, DRIVE_FAULT_BAD_INPUT);
    EXPECT_EQ(s.rec.fault_tick, 42u);
    EXPECT_EQ(s.rec.events, 1u);
    EXPECT_FALSE(supervisor_dispatch(&s.sup, SUP_EV_ESTIMATE_TRUSTED)) << "latched";
}

TEST(Guard, RecordKeepsEveryLegAndStopsWhenFrozen)
{
    Shell s;
    hal_sample_t in{};
    hal_command_t out{};
    for (uint32_t k = 0; k < HAL_MAX_PHASES; ++k) {
        in.i_A[k] = MC_C(1.5) * static_cast<int32_t>(k + 1);
        out.v_V[k] = MC_C(-2.0) * static_cast<int32_t>(k + 1);
    }
    guard_record(&s.rec, 5u, SUP_STATE_CLOSED_LOOP, &in, &out, MC_C(1.0), MC_C(2.0), MC_C(3.0));
    ASSERT_EQ(flight_recorder_count(&s.rec), 1u);
    const flight_record_t* r = flight_recorder_get(&s.rec, 0);
    EXPECT_EQ(r->tick, 5u);
    EXPECT_EQ(r->state, static_cast<uint8_t>(SUP_STATE_CLOSED_LOOP));
    for (uint32_t k = 0; k < HAL_MAX_PHASES; ++k) {
        EXPECT_EQ(r->i_A[k], in.i_A[k]) << k;
        EXPECT_EQ(r->v_V[k], out.v_V[k]) << k;
    }
    EXPECT_EQ(r->ref, MC_C(1.0));
    EXPECT_EQ(r->est, MC_C(2.0));
    EXPECT_EQ(r->speed, MC_C(3.0));
    guard_latch(&s.sup, &s.rec, DRIVE_FAULT_OVERCURRENT, 6u);
    guard_record(&s.rec, 6u, SUP_STATE_FAULT, &in, &out, MC_ZERO, MC_ZERO, MC_ZERO);
    EXPECT_EQ(flight_recorder_count(&s.rec), 1u) << "frozen at the fault";
}

TEST(Guard, ZeroSetsEveryLeg)
{
    hal_command_t out{};
    for (uint32_t k = 0; k < HAL_MAX_PHASES; ++k) out.v_V[k] = MC_C(7.0);
    guard_zero(&out, 2u);
    EXPECT_EQ(out.n_phases, 2u);
    for (uint32_t k = 0; k < HAL_MAX_PHASES; ++k) EXPECT_EQ(out.v_V[k], MC_ZERO) << k;
}
