#include "supervisor/guard.h"

/* What runs only on a fault or while the drive outputs 0 V stays a call
 * (supervisor/guard.h): inlined by link-time optimisation into the one
 * drive of an image, it costs the sample's own path (registers, the
 * inliner's budget). */
#if defined(__GNUC__)
#define GUARD_OUT_OF_LINE __attribute__((noinline))
#else
#define GUARD_OUT_OF_LINE
#endif

guard_action_t guard_react(supervisor_t *sup, flight_recorder_t *rec, const uint8_t reaction[DRIVE_FAULT_COUNT],
                           drive_fault_t f, uint32_t tick, bool can_relock)
{
    flight_recorder_fault(rec, f, tick);
    const uint8_t react = reaction[(uint32_t)f < (uint32_t)DRIVE_FAULT_COUNT ? (uint32_t)f : 0u];
    if (react == (uint8_t)FAULT_REACT_REPORT) {
        return GUARD_GO_ON;
    }
    if (react == (uint8_t)FAULT_REACT_RELOCK && can_relock) {
        return GUARD_RELOCK;
    }
    supervisor_fault(sup, f);
    return GUARD_SAFE;
}

guard_action_t guard_react_with(supervisor_t *sup, flight_recorder_t *rec, const uint8_t reaction[DRIVE_FAULT_COUNT],
                                drive_fault_t f, uint32_t tick, guard_relock_fn relock, void *drive)
{
    /* the drive is asked only when its table says RELOCK; its answer is
     * guard_react's can_relock (the re-lock started before the fault is
     * recorded: neither touches what the other does) */
    const uint8_t react = reaction[(uint32_t)f < (uint32_t)DRIVE_FAULT_COUNT ? (uint32_t)f : 0u];
    const bool relocked = react == (uint8_t)FAULT_REACT_RELOCK && relock != 0 && relock(drive);
    return guard_react(sup, rec, reaction, f, tick, relocked);
}

void guard_latch(supervisor_t *sup, flight_recorder_t *rec, drive_fault_t f, uint32_t tick)
{
    flight_recorder_fault(rec, f, tick);
    supervisor_fault(sup, f);
}

GUARD_OUT_OF_LINE guard_action_t guard_stop(const guard_shell_t *g, void *drive, guard_action_t a, hal_command_t *out)
{
    guard_zero(out, guard_phases(g, drive));
    if (g->stopped != 0) {
        g->stopped(drive);
    }
    if (g->ticks == GUARD_TICK_EVERY) {
        *GUARD_MEMBER(drive, g->tick, uint32_t) += 1u;
    }
    return a;
}

GUARD_OUT_OF_LINE guard_action_t guard_reaction(const guard_shell_t *g, void *drive, drive_fault_t f)
{
    return guard_react_with(GUARD_MEMBER(drive, g->sup, supervisor_t), GUARD_MEMBER(drive, g->rec, flight_recorder_t),
                            *GUARD_MEMBER(drive, g->reaction, const guard_reactions_t), f,
                            *GUARD_MEMBER(drive, g->tick, uint32_t), g->relock, drive);
}

GUARD_OUT_OF_LINE guard_action_t guard_fault(const guard_shell_t *g, void *drive, drive_fault_t f, hal_command_t *out)
{
    const guard_action_t a = guard_reaction(g, drive, f);
    return a == GUARD_SAFE ? guard_stop(g, drive, GUARD_SAFE, out) : a;
}

GUARD_OUT_OF_LINE guard_action_t guard_trip(const guard_shell_t *g, void *drive, drive_fault_t f, hal_command_t *out)
{
    guard_latch(GUARD_MEMBER(drive, g->sup, supervisor_t), GUARD_MEMBER(drive, g->rec, flight_recorder_t), f,
                *GUARD_MEMBER(drive, g->tick, uint32_t));
    return guard_stop(g, drive, GUARD_SAFE, out);
}

void guard_start_closed_loop(supervisor_t *sup)
{
    /* no switch ever blends: the decay is never used */
    const supervisor_config_t no_blend = {MC_ZERO};
    supervisor_init(sup, &no_blend, false, false);
    (void)supervisor_dispatch(sup, SUP_EV_ESTIMATE_TRUSTED);
}
