/*
 * flight_recorder.h - the last FLIGHT_RECORDER_DEPTH samples of a drive,
 * kept in a ring, and frozen into a snapshot at the first fault: what the
 * currents, voltages, reference and estimate were just before it. The
 * snapshot, the fault's code and tick stay until the fault is cleared by
 * command (the drive's *_clear_fault). Fixed size, no allocation; one record
 * per sample is a handful of stores.
 */
#ifndef SUPERVISOR_FLIGHT_RECORDER_H
#define SUPERVISOR_FLIGHT_RECORDER_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal_types.h"
#include "math/mc_num.h"
#include "supervisor/supervisor.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 64 samples = 6.4 ms at 10 kHz: two L/R time constants of the rig's
 * current, enough to see how a current ran away or a sensor froze;
 * 64 x 48 bytes = 3 kB of RAM. A power of two: the ring index is a mask. */
#define FLIGHT_RECORDER_DEPTH 64u

/* One sample. ref/est/speed are the drive's reference, angle estimate and
 * speed estimate, as each drive records them (supervisor/guard.h's
 * guard_record): paper 000 the position reference, position estimate and
 * speed; paper 001 the speed reference, the electrical angle and the
 * speed; paper 002 the speed reference, the EKF's mechanical angle and
 * speed; the sensored drive the speed reference, the encoder's electrical
 * angle and the observer's speed. */
typedef struct {
    uint32_t tick;
    uint8_t state;                 /* sup_state_t */
    mc_t i_A[HAL_MAX_PHASES];      /* measured phase currents */
    mc_t v_V[HAL_MAX_PHASES];      /* commanded phase voltages */
    mc_t ref, est, speed;
} flight_record_t;

typedef struct {
    flight_record_t ring[FLIGHT_RECORDER_DEPTH];
    uint32_t n;                    /* records written, past 2^32 from DEPTH again (the newest is ring[(n - 1) % DEPTH]) */
    bool frozen;                   /* a fault froze it */
    drive_fault_t fault;           /* the first fault */
    uint32_t fault_tick;           /* the drive tick it was detected at */
    uint32_t events;               /* faults seen since init, recovered ones included */
} flight_recorder_t;

void flight_recorder_init(flight_recorder_t *r);

/* Appending one sample, without a copy: the slot it goes to (NULL once
 * frozen), to be filled in place and then committed with
 * flight_recorder_commit(). */
static inline flight_record_t *flight_recorder_slot(flight_recorder_t *r)
{
    return r->frozen ? 0 : &r->ring[r->n & (FLIGHT_RECORDER_DEPTH - 1u)];
}
static inline void flight_recorder_commit(flight_recorder_t *r)
{
    if (!r->frozen) {
        r->n += 1u;
        /* n wraps after 2^32 samples (5 days at 10 kHz): it goes on at
         * DEPTH, the same slot (DEPTH divides 2^32), so the ring still
         * counts as full and a fault just after the wrap keeps all of it */
        if (r->n == 0u) {
            r->n = FLIGHT_RECORDER_DEPTH;
        }
    }
}

/* A fault at tick: counts it, and freezes the ring with the first one. */
void flight_recorder_fault(flight_recorder_t *r, drive_fault_t f, uint32_t tick);

/* The k-th oldest record of the snapshot, k in [0, flight_recorder_count);
 * NULL outside. */
const flight_record_t *flight_recorder_get(const flight_recorder_t *r, uint32_t k);
uint32_t flight_recorder_count(const flight_recorder_t *r);

#ifdef __cplusplus
}
#endif

#endif /* SUPERVISOR_FLIGHT_RECORDER_H */
