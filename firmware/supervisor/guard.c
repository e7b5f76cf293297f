#include "supervisor/guard.h"

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

void guard_latch(supervisor_t *sup, flight_recorder_t *rec, drive_fault_t f, uint32_t tick)
{
    flight_recorder_fault(rec, f, tick);
    supervisor_fault(sup, f);
}

void guard_start_closed_loop(supervisor_t *sup)
{
    /* no switch ever blends: the decay is never used */
    const supervisor_config_t no_blend = {MC_ZERO};
    supervisor_init(sup, &no_blend, false, false);
    (void)supervisor_dispatch(sup, SUP_EV_ESTIMATE_TRUSTED);
}
