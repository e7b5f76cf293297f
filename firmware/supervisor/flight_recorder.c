#include "supervisor/flight_recorder.h"

void flight_recorder_init(flight_recorder_t *r)
{
    r->n = 0u;
    r->frozen = false;
    r->fault = DRIVE_FAULT_NONE;
    r->fault_tick = 0u;
    r->events = 0u;
}

void flight_recorder_fault(flight_recorder_t *r, drive_fault_t f, uint32_t tick)
{
    r->events += 1u;
    if (!r->frozen) {
        r->frozen = true;
        r->fault = f;
        r->fault_tick = tick;
    }
}

uint32_t flight_recorder_count(const flight_recorder_t *r)
{
    return r->n < FLIGHT_RECORDER_DEPTH ? r->n : FLIGHT_RECORDER_DEPTH;
}

const flight_record_t *flight_recorder_get(const flight_recorder_t *r, uint32_t k)
{
    const uint32_t count = flight_recorder_count(r);
    if (k >= count) {
        return 0;
    }
    const uint32_t oldest = r->n - count;
    return &r->ring[(oldest + k) & (FLIGHT_RECORDER_DEPTH - 1u)];
}
