/*
 * guard.h - the fault shell every drive runs its sample in, with one
 * semantics for all of them. A fault found in a sample (by the generic
 * checks of supervisor/fault_monitor.h before and after the control law, or
 * by the drive's own loss-of-estimate criteria) is first counted in the
 * flight recorder, which the first fault freezes (flight_recorder.h); then
 * the drive's reaction table (one entry per drive_fault_t) decides:
 *   FAULT_REACT_REPORT  recorded, the sample goes on;
 *   FAULT_REACT_RELOCK  the drive's re-lock, where it has one and its
 *                       budget is not spent; otherwise as SAFE;
 *   FAULT_REACT_SAFE    the supervisor latches FAULT (supervisor.h):
 *                       0 V from this sample on, until the drive is
 *                       cleared (its *_clear_fault re-initialises it as at
 *                       power-up; refused without a fault, drives/drive.h).
 * A fault no reaction can answer (a sample of the wrong phase count, a
 * configuration the drive refused) is latched the same way with
 * guard_latch. Every sample that outputs a voltage is recorded with
 * guard_record (inline: it runs every sample). The reactions are calls:
 * they run only on a fault. No allocation; the state is the drive's own supervisor_t
 * and flight_recorder_t.
 */
#ifndef SUPERVISOR_GUARD_H
#define SUPERVISOR_GUARD_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal_types.h"
#include "math/mc_num.h"
#include "supervisor/flight_recorder.h"
#include "supervisor/supervisor.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What the drive does after guard_react. */
typedef enum {
    GUARD_GO_ON = 0,  /* REPORT: recorded, the sample goes on */
    GUARD_RELOCK = 1, /* RELOCK: the drive falls back and closes its loop again */
    GUARD_SAFE = 2    /* latched: the drive outputs 0 V (guard_zero) */
} guard_action_t;

/* A fault f found at tick: counted in rec (the first one freezes it), then
 * reaction[f] (reaction[0], the entry of NONE, for a code outside the
 * enum). RELOCK is answered GUARD_RELOCK only when can_relock (the drive
 * has a re-lock and budget left), else the fault is latched as SAFE. */
guard_action_t guard_react(supervisor_t *sup, flight_recorder_t *rec, const uint8_t reaction[DRIVE_FAULT_COUNT],
                           drive_fault_t f, uint32_t tick, bool can_relock);

/* A fault only the safe state answers: counted in rec and latched. */
void guard_latch(supervisor_t *sup, flight_recorder_t *rec, drive_fault_t f, uint32_t tick);

/* One sample into the flight recorder (nothing once frozen): the measured
 * currents and the commanded voltages of every leg (hal_types.h: an unused
 * phase's entries are 0), the state and the drive's reference, estimate
 * and speed (flight_record_t). Inline: it runs every sample, a handful of
 * stores. */
static inline void guard_record(flight_recorder_t *rec, uint32_t tick, sup_state_t state, const hal_sample_t *in,
                                const hal_command_t *out, mc_t ref, mc_t est, mc_t speed)
{
    flight_record_t *r = flight_recorder_slot(rec);
    if (r == 0) {
        return;
    }
    r->tick = tick;
    r->state = (uint8_t)state;
    for (uint32_t k = 0; k < HAL_MAX_PHASES; ++k) {
        r->i_A[k] = in->i_A[k];
        r->v_V[k] = out->v_V[k];
    }
    r->ref = ref;
    r->est = est;
    r->speed = speed;
    flight_recorder_commit(rec);
}

/* The supervisor of a drive whose angle is measured or observed from its
 * first sample (no open-loop start, no alignment, no blend): CLOSED_LOOP,
 * no fault. */
void guard_start_closed_loop(supervisor_t *sup);

/* The safe state's command: 0 V on every leg, n_phases of them. */
static inline void guard_zero(hal_command_t *out, uint8_t n_phases)
{
    out->n_phases = n_phases;
    for (uint32_t k = 0; k < HAL_MAX_PHASES; ++k) {
        out->v_V[k] = MC_ZERO;
    }
}

#ifdef __cplusplus
}
#endif

#endif /* SUPERVISOR_GUARD_H */
