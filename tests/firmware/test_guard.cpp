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

// ---- the shell of a step (guard_shell_t, guard_begin ... guard_end): what
// every drive's sample does before and after its own computation.

namespace {

// A drive as the shell sees it: its supervisor, monitor, recorder, count,
// enable flag, reaction table; its own check of a sample and a re-lock with
// a budget.
struct Drive {
    supervisor_t sup;
    fault_monitor_t mon;
    flight_recorder_t rec;
    uint32_t tick;
    bool disabled;
    guard_reactions_t reaction;
    bool refuse;  // its own check refuses the sample
    int relocks_left;
    int relocks;
    int asked;    // its own check of the sample asked
    drive_fault_t own_fault;  // what its own last checks find
    int checked;  // its own last checks asked
    int stops;    // its stopped() called
    uint8_t phases;  // its phase count by configuration (paper 001's)
};

Drive make_drive(uint32_t tick0 = 0)
{
    Drive d{};
    d.tick = tick0;
    guard_start_closed_loop(&d.sup);
    flight_recorder_init(&d.rec);
    fault_monitor_config_t c{};
    c.i_trip_A = MC_C(100.0);  // nothing of the monitor fires but what a test provokes
    c.i_trip_samples = 1;
    c.i2t_cont_A2 = MC_C(100.0);
    c.i2t_gain = MC_C(0.001);
    c.i2t_limit_A2 = MC_C(1000.0);
    c.sat_max_ticks = 2;
    c.stuck_ticks = 1000;
    c.stuck_dv_V = MC_C(1000.0);
    c.rail_ticks = 1;
    c.overrun_weight = 1;
    c.overrun_limit = 1000;
    fault_monitor_init(&d.mon, &c);
    for (int f = 0; f < DRIVE_FAULT_COUNT; ++f) d.reaction[f] = static_cast<uint8_t>(FAULT_REACT_SAFE);
    return d;
}

bool drive_relock(void* self)
{
    Drive* d = static_cast<Drive*>(self);
    if (d->relocks_left == 0) return false;
    d->relocks_left -= 1;
    d->relocks += 1;
    return true;
}

bool drive_accepts(const void* self, const hal_sample_t* in)
{
    const Drive* d = static_cast<const Drive*>(self);
    const_cast<Drive*>(d)->asked += 1;
    (void)in;
    return !d->refuse;
}

drive_fault_t drive_check(void* self)
{
    Drive* d = static_cast<Drive*>(self);
    d->checked += 1;
    return d->own_fault;
}

void drive_stopped(void* self) { static_cast<Drive*>(self)->stops += 1; }

guard_shell_t shell_of(guard_tick_t ticks, uint8_t n_phases = 3u, bool with_relock = false, bool with_accepts = true)
{
    guard_shell_t g{};
    g.sup = offsetof(Drive, sup);
    g.mon = offsetof(Drive, mon);
    g.rec = offsetof(Drive, rec);
    g.tick = offsetof(Drive, tick);
    g.disabled = offsetof(Drive, disabled);
    g.reaction = offsetof(Drive, reaction);
    g.n_phases = n_phases;
    g.accepts = with_accepts ? drive_accepts : nullptr;
    g.check = drive_check;
    g.relock = with_relock ? drive_relock : nullptr;
    g.stopped = drive_stopped;
    g.ticks = ticks;
    return g;
}

hal_sample_t sample(uint8_t n_phases = 3u)
{
    hal_sample_t in{};
    in.n_phases = n_phases;
    in.i_A[0] = MC_C(1.0);
    in.i_A[1] = MC_C(-0.5);
    in.i_A[2] = MC_C(-0.5);
    in.v_bus_V = MC_C(24.0);
    return in;
}

// A command the drive computed: every leg non-zero, so 0 V is seen.
hal_command_t command()
{
    hal_command_t out{};
    out.n_phases = 3u;
    for (uint32_t k = 0; k < HAL_MAX_PHASES; ++k) out.v_V[k] = MC_C(2.0);
    return out;
}

void expect_zero(const hal_command_t& out, uint8_t n_phases)
{
    EXPECT_EQ(out.n_phases, n_phases);
    for (uint32_t k = 0; k < HAL_MAX_PHASES; ++k) EXPECT_EQ(out.v_V[k], MC_ZERO) << k;
}

}  // namespace

TEST(GuardShell, ACleanSampleGoesOnUntouchedAndUncounted)
{
    for (guard_tick_t ticks : {GUARD_TICK_RUN, GUARD_TICK_EVERY}) {
        Drive d = make_drive(5u);
        const guard_shell_t g = shell_of(ticks);
        const hal_sample_t in = sample();
        hal_command_t out = command();
        EXPECT_EQ(guard_begin(&g, &d, &in, &out), GUARD_GO_ON);
        EXPECT_EQ(out.v_V[0], MC_C(2.0)) << "the shell leaves a running sample's output alone";
        EXPECT_EQ(d.tick, 5u) << "counted at the sample's end, not its start";
        EXPECT_EQ(d.asked, 1) << "the drive's own check of the sample";
        EXPECT_EQ(d.stops, 0);
        EXPECT_EQ(d.rec.events, 0u);
        EXPECT_EQ(d.sup.state, SUP_STATE_CLOSED_LOOP);
    }
}

TEST(GuardShell, ALatchedFaultOutputs0VEverySample)
{
    for (guard_tick_t ticks : {GUARD_TICK_RUN, GUARD_TICK_EVERY}) {
        Drive d = make_drive(5u);
        const guard_shell_t g = shell_of(ticks, 2u);
        guard_latch(&d.sup, &d.rec, DRIVE_FAULT_OVERCURRENT, 4u);
        const hal_sample_t in = sample(2u);
        for (int k = 0; k < 3; ++k) {
            hal_command_t out = command();
            EXPECT_EQ(guard_begin(&g, &d, &in, &out), GUARD_SAFE) << k;
            expect_zero(out, 2u);
        }
        EXPECT_EQ(d.rec.events, 1u) << "the latched fault is not counted again";
        EXPECT_EQ(d.sup.fault, DRIVE_FAULT_OVERCURRENT);
        EXPECT_EQ(d.asked, 0) << "a latched drive's own check is not asked (it may be unset)";
        EXPECT_EQ(d.stops, 3) << "the drive clears its last voltage with each 0 V sample";
        EXPECT_EQ(d.tick, ticks == GUARD_TICK_EVERY ? 8u : 5u) << "only GUARD_TICK_EVERY counts a 0 V step";
    }
}

TEST(GuardShell, ADisabledDriveIdlesAt0VWithoutAFault)
{
    for (guard_tick_t ticks : {GUARD_TICK_RUN, GUARD_TICK_EVERY}) {
        Drive d = make_drive(5u);
        d.disabled = true;
        d.refuse = true;
        const guard_shell_t g = shell_of(ticks);
        const hal_sample_t in = sample(2u);  // not even looked at
        hal_command_t out = command();
        EXPECT_EQ(guard_begin(&g, &d, &in, &out), GUARD_IDLE);
        expect_zero(out, 3u);
        EXPECT_EQ(d.stops, 1);
        EXPECT_EQ(d.sup.state, SUP_STATE_CLOSED_LOOP);
        EXPECT_EQ(d.rec.events, 0u);
        EXPECT_EQ(d.tick, ticks == GUARD_TICK_EVERY ? 6u : 5u);
    }
}

TEST(GuardShell, AnotherPhaseCountOrTheDrivesOwnCheckIsBadInput)
{
    for (bool phases_wrong : {true, false}) {
        for (guard_tick_t ticks : {GUARD_TICK_RUN, GUARD_TICK_EVERY}) {
            Drive d = make_drive(7u);
            d.reaction[DRIVE_FAULT_BAD_INPUT] = static_cast<uint8_t>(FAULT_REACT_REPORT);  // latched whatever the table
            d.relocks_left = 1;
            d.refuse = !phases_wrong;
            const guard_shell_t g = shell_of(ticks, 3u, true);
            const hal_sample_t in = sample(phases_wrong ? 2u : 3u);
            hal_command_t out = command();
            EXPECT_EQ(guard_begin(&g, &d, &in, &out), GUARD_SAFE);
            expect_zero(out, 3u);
            EXPECT_EQ(d.sup.state, SUP_STATE_FAULT);
            EXPECT_EQ(d.sup.fault, DRIVE_FAULT_BAD_INPUT);
            EXPECT_EQ(d.rec.fault_tick, 7u) << "at the sample's own tick";
            EXPECT_EQ(d.relocks, 0) << "no re-lock for a refused sample";
            EXPECT_EQ(d.stops, 1);
            EXPECT_EQ(d.tick, ticks == GUARD_TICK_EVERY ? 8u : 7u);
        }
    }
    // without a check of its own, the phase count alone
    Drive d = make_drive();
    d.refuse = true;
    const guard_shell_t g = shell_of(GUARD_TICK_RUN, 3u, false, false);
    const hal_sample_t in = sample();
    hal_command_t out = command();
    EXPECT_EQ(guard_begin(&g, &d, &in, &out), GUARD_GO_ON);
}

TEST(GuardShell, ThePhaseCountMayBeTheDrivesOwn)
{
    // n_phases 0: the count of the drive's state (2 or 3 by configuration)
    for (uint8_t phases : {uint8_t{2}, uint8_t{3}}) {
        Drive d = make_drive();
        d.phases = phases;
        guard_shell_t g = shell_of(GUARD_TICK_RUN, 0u);
        g.n_phases_at = offsetof(Drive, phases);
        const hal_sample_t in = sample(phases);
        hal_command_t out = command();
        EXPECT_EQ(guard_begin(&g, &d, &in, &out), GUARD_GO_ON) << int(phases);
        const hal_sample_t other = sample(phases == 2u ? 3u : 2u);
        EXPECT_EQ(guard_begin(&g, &d, &other, &out), GUARD_SAFE) << int(phases);
        EXPECT_EQ(d.sup.fault, DRIVE_FAULT_BAD_INPUT);
        expect_zero(out, phases);
    }
}

TEST(GuardShell, TheMonitorsFaultTakesTheTablesReaction)
{
    hal_sample_t in = sample();
    in.status = HAL_STATUS_PWM_TRIP;  // fault_monitor_sample: HW_TRIP
    {   // SAFE: latched at this tick, 0 V
        Drive d = make_drive(9u);
        const guard_shell_t g = shell_of(GUARD_TICK_RUN);
        hal_command_t out = command();
        EXPECT_EQ(guard_begin(&g, &d, &in, &out), GUARD_SAFE);
        expect_zero(out, 3u);
        EXPECT_EQ(d.sup.fault, DRIVE_FAULT_HW_TRIP);
        EXPECT_EQ(d.rec.fault_tick, 9u);
        EXPECT_EQ(d.tick, 9u);
    }
    {   // REPORT: recorded, the sample goes on with its output
        Drive d = make_drive(9u);
        d.reaction[DRIVE_FAULT_HW_TRIP] = static_cast<uint8_t>(FAULT_REACT_REPORT);
        const guard_shell_t g = shell_of(GUARD_TICK_EVERY);
        hal_command_t out = command();
        EXPECT_EQ(guard_begin(&g, &d, &in, &out), GUARD_GO_ON);
        EXPECT_EQ(out.v_V[0], MC_C(2.0));
        EXPECT_EQ(d.sup.state, SUP_STATE_CLOSED_LOOP);
        EXPECT_EQ(d.rec.events, 1u);
        EXPECT_EQ(d.tick, 9u);
    }
    {   // RELOCK: the drive's re-lock while its budget lasts, then SAFE; none without one
        Drive d = make_drive(9u);
        d.reaction[DRIVE_FAULT_HW_TRIP] = static_cast<uint8_t>(FAULT_REACT_RELOCK);
        d.relocks_left = 1;
        const guard_shell_t g = shell_of(GUARD_TICK_RUN, 3u, true);
        hal_command_t out = command();
        EXPECT_EQ(guard_begin(&g, &d, &in, &out), GUARD_RELOCK);
        EXPECT_EQ(d.relocks, 1);
        EXPECT_EQ(out.v_V[0], MC_C(2.0)) << "the sample goes on";
        EXPECT_EQ(d.stops, 0);
        EXPECT_EQ(d.sup.state, SUP_STATE_CLOSED_LOOP);
        EXPECT_EQ(guard_begin(&g, &d, &in, &out), GUARD_SAFE) << "the budget is spent";
        expect_zero(out, 3u);
        EXPECT_EQ(d.rec.events, 2u);
        Drive n = make_drive(9u);
        n.reaction[DRIVE_FAULT_HW_TRIP] = static_cast<uint8_t>(FAULT_REACT_RELOCK);
        const guard_shell_t gn = shell_of(GUARD_TICK_RUN);
        EXPECT_EQ(guard_begin(&gn, &n, &in, &out), GUARD_SAFE) << "a drive without a re-lock";
    }
}

TEST(GuardShell, AFaultMidSampleStopsItAt0VOrGoesOn)
{
    for (guard_tick_t ticks : {GUARD_TICK_RUN, GUARD_TICK_EVERY}) {
        Drive d = make_drive(3u);
        d.reaction[DRIVE_FAULT_LOSS_OF_LOCK] = static_cast<uint8_t>(FAULT_REACT_REPORT);
        const guard_shell_t g = shell_of(ticks);
        hal_command_t out = command();
        EXPECT_EQ(guard_fault(&g, &d, DRIVE_FAULT_LOSS_OF_LOCK, &out), GUARD_GO_ON);
        EXPECT_EQ(out.v_V[0], MC_C(2.0));
        EXPECT_EQ(d.tick, 3u);
        EXPECT_EQ(guard_fault(&g, &d, DRIVE_FAULT_LOSS_OF_SYNC, &out), GUARD_SAFE);
        expect_zero(out, 3u);
        EXPECT_EQ(d.sup.fault, DRIVE_FAULT_LOSS_OF_SYNC);
        EXPECT_EQ(d.tick, ticks == GUARD_TICK_EVERY ? 4u : 3u);
        // the reaction alone leaves the output to the drive (guard_stop)
        Drive r = make_drive(3u);
        out = command();
        EXPECT_EQ(guard_reaction(&g, &r, DRIVE_FAULT_LOSS_OF_SYNC), GUARD_SAFE);
        EXPECT_EQ(out.v_V[0], MC_C(2.0));
        EXPECT_EQ(r.tick, 3u);
        EXPECT_EQ(guard_stop(&g, &r, GUARD_SAFE, &out), GUARD_SAFE);
        expect_zero(out, 3u);
        EXPECT_EQ(r.tick, ticks == GUARD_TICK_EVERY ? 4u : 3u);
        // a fault only the safe state answers, whatever the table says
        Drive t = make_drive(3u);
        for (int f = 0; f < DRIVE_FAULT_COUNT; ++f) t.reaction[f] = static_cast<uint8_t>(FAULT_REACT_REPORT);
        const guard_shell_t gt = shell_of(ticks, 2u);
        out = command();
        EXPECT_EQ(guard_trip(&gt, &t, DRIVE_FAULT_LOSS_OF_LOCK, &out), GUARD_SAFE);
        expect_zero(out, 2u);
        EXPECT_EQ(t.sup.fault, DRIVE_FAULT_LOSS_OF_LOCK);
        EXPECT_EQ(t.rec.fault_tick, 3u);
        EXPECT_EQ(t.tick, ticks == GUARD_TICK_EVERY ? 4u : 3u);
    }
}

TEST(GuardShell, TheEndChecksTheCommandThenTheDrivesOwn)
{
    Drive d = make_drive();
    const guard_shell_t g = shell_of(GUARD_TICK_RUN);
    const hal_sample_t in = sample();
    hal_command_t out = command();
    d.own_fault = DRIVE_FAULT_LOSS_OF_LOCK;
    d.reaction[DRIVE_FAULT_LOSS_OF_LOCK] = static_cast<uint8_t>(FAULT_REACT_REPORT);
    d.reaction[DRIVE_FAULT_VOLTAGE_SATURATION] = static_cast<uint8_t>(FAULT_REACT_REPORT);
    EXPECT_EQ(guard_end(&g, &d, &in, &out, false, MC_ZERO, MC_ZERO, MC_ZERO), GUARD_GO_ON);
    EXPECT_EQ(d.checked, 1);
    EXPECT_EQ(d.rec.fault, DRIVE_FAULT_LOSS_OF_LOCK) << "the drive's own fault, reacted to";
    // the voltage limit beyond sat_max_ticks = 2 samples: the command's fault, the drive's checks not asked
    EXPECT_EQ(guard_end(&g, &d, &in, &out, true, MC_ZERO, MC_ZERO, MC_ZERO), GUARD_GO_ON);
    EXPECT_EQ(guard_end(&g, &d, &in, &out, true, MC_ZERO, MC_ZERO, MC_ZERO), GUARD_GO_ON);
    EXPECT_EQ(d.checked, 3);
    EXPECT_EQ(guard_end(&g, &d, &in, &out, true, MC_ZERO, MC_ZERO, MC_ZERO), GUARD_GO_ON);
    EXPECT_EQ(d.checked, 3) << "asked only when the command's checks pass";
    EXPECT_EQ(d.rec.events, 4u);
    EXPECT_EQ(d.tick, 4u);
}

TEST(GuardShell, TheEndRecordsCountsThenReactsAtTheNextTick)
{
    // GUARD_TICK_RUN (papers 000 and 001, the sensored drive)
    Drive d = make_drive(20u);
    const guard_shell_t g = shell_of(GUARD_TICK_RUN);
    const hal_sample_t in = sample();
    hal_command_t out = command();
    EXPECT_EQ(guard_end(&g, &d, &in, &out, false, MC_C(1.0), MC_C(2.0), MC_C(3.0)), GUARD_GO_ON);
    EXPECT_EQ(d.tick, 21u);
    ASSERT_EQ(flight_recorder_count(&d.rec), 1u);
    const flight_record_t* r = flight_recorder_get(&d.rec, 0);
    EXPECT_EQ(r->tick, 20u);
    EXPECT_EQ(r->state, static_cast<uint8_t>(SUP_STATE_CLOSED_LOOP));
    EXPECT_EQ(r->v_V[0], MC_C(2.0)) << "the command the sample output";
    EXPECT_EQ(r->i_A[0], in.i_A[0]);
    EXPECT_EQ(r->ref, MC_C(1.0));
    EXPECT_EQ(r->est, MC_C(2.0));
    EXPECT_EQ(r->speed, MC_C(3.0));
    EXPECT_EQ(out.v_V[0], MC_C(2.0));
    d.own_fault = DRIVE_FAULT_NON_FINITE;
    EXPECT_EQ(guard_end(&g, &d, &in, &out, false, MC_ZERO, MC_ZERO, MC_ZERO), GUARD_SAFE);
    expect_zero(out, 3u);
    EXPECT_EQ(d.stops, 1);
    EXPECT_EQ(d.tick, 22u);
    EXPECT_EQ(d.sup.fault, DRIVE_FAULT_NON_FINITE);
    EXPECT_EQ(d.rec.fault_tick, 22u) << "counted before the reaction";
    EXPECT_EQ(flight_recorder_get(&d.rec, 1)->v_V[0], MC_C(2.0)) << "recorded before the reaction's 0 V";
}

TEST(GuardShell, UnderEveryStepTheEndReactsAtTheSamplesTickThenCounts)
{
    // GUARD_TICK_EVERY (paper 002)
    for (bool safe : {true, false}) {
        Drive d = make_drive(20u);
        d.own_fault = DRIVE_FAULT_LOSS_OF_SYNC;
        d.reaction[DRIVE_FAULT_LOSS_OF_SYNC] = static_cast<uint8_t>(safe ? FAULT_REACT_SAFE : FAULT_REACT_REPORT);
        const guard_shell_t g = shell_of(GUARD_TICK_EVERY);
        const hal_sample_t in = sample();
        hal_command_t out = command();
        EXPECT_EQ(guard_end(&g, &d, &in, &out, false, MC_ZERO, MC_ZERO, MC_ZERO), safe ? GUARD_SAFE : GUARD_GO_ON);
        EXPECT_EQ(d.rec.fault_tick, 20u) << "at the sample's own tick";
        EXPECT_EQ(d.tick, 21u) << "counted once";
        EXPECT_EQ(flight_recorder_get(&d.rec, 0)->tick, 20u);
        EXPECT_EQ(out.v_V[0], safe ? MC_ZERO : MC_C(2.0));
        d.own_fault = DRIVE_FAULT_NONE;
        EXPECT_EQ(guard_end(&g, &d, &in, &out, false, MC_ZERO, MC_ZERO, MC_ZERO), GUARD_GO_ON);
        EXPECT_EQ(d.tick, 22u);
    }
}
