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
 *
 * The shell of a step (guard_shell_t): what every drive's sample does
 * before and after its own computation, written once. A drive describes
 * itself once, in a static const guard_shell_t beside its drive_ops_t
 * (where its supervisor, fault monitor, flight recorder, sample count,
 * enable flag and reaction table are in its state, and what differs from
 * drive to drive, below), and its step reads
 *
 *     const guard_action_t a = guard_begin(&<drive>_shell, d, in, out);
 *     if (a == GUARD_SAFE || a == GUARD_IDLE) {
 *         return a == GUARD_IDLE;                 (0 V out)
 *     }
 *     ... the sample: estimate, law, voltages into out ...
 *     return guard_end(&<drive>_shell, d, in, out, saturated, ref, est, speed) != GUARD_SAFE;
 *
 * with guard_fault (a fault found in the middle of the sample, 0 V out on
 * SAFE), guard_reaction and guard_stop (the same in two halves, for a
 * drive that finds it deep in its sample) and guard_trip (one only the
 * safe state answers) in between. The drives differ in these, each a
 * field of guard_shell_t:
 *   n_phases  the sample's and the command's phase count (or, 0, the
 *             drive's own, read from its state at n_phases_at: paper
 *             001's, 2 or 3 by configuration);
 *   accepts   its own checks of a sample beyond the phase count (an
 *             encoder's angle, a bus above a minimum), asked only of a
 *             sample of a running drive;
 *   check     its own last checks after the command's (the estimate it
 *             runs on finite, its loss-of-estimate criteria), asked only
 *             when the command's pass;
 *   reaction  its table; relock, its re-lock (NULL: none, RELOCK acts as
 *             SAFE), asked only when the table says RELOCK;
 *   stopped   what it clears when the shell stops a sample at 0 V (its
 *             record of the last voltage, for the telemetry);
 *   ticks     how its sample count runs (guard_tick_t): the samples that
 *             ran, or every step; this also sets the tick a fault found by
 *             the sample's last checks is recorded at.
 * guard_begin and guard_end, which run every sample, are inline: the
 * description's fields fold to constants, the callbacks to direct calls
 * (inlined where small). What runs only on a fault or while the drive
 * outputs 0 V is a call (guard.c), kept one (GUARD_OUT_OF_LINE there):
 * so the drives' PIL and STM32 images cost no more per step than with
 * their own helpers (tools/bench/pil.py, stm32_qemu.py; inlined by
 * link-time optimisation, these calls cost paper 000's M3 step up to 8
 * instructions in closed loop).
 */
#ifndef SUPERVISOR_GUARD_H
#define SUPERVISOR_GUARD_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "adapter/phase_adapter.h"
#include "hal/hal_types.h"
#include "math/mc_num.h"
#include "supervisor/fault_monitor.h"
#include "supervisor/flight_recorder.h"
#include "supervisor/supervisor.h"

#ifdef __cplusplus
extern "C" {
#endif

/* guard_begin and guard_end run every sample: inlined whatever the
 * compiler's own estimate (GCC 12 keeps small static helpers as calls,
 * paper000_drive.c), so that the description's fields fold to constants
 * and the drive's members are reached at their offsets. */
#if defined(__GNUC__)
#define GUARD_IN_LINE inline __attribute__((always_inline))
#else
#define GUARD_IN_LINE inline
#endif

/* What the drive does after guard_react or a step of the shell. */
typedef enum {
    GUARD_GO_ON = 0,  /* no fault, or REPORT: recorded, the sample goes on */
    GUARD_RELOCK = 1, /* RELOCK: the drive falls back and closes its loop again; the sample goes on */
    GUARD_SAFE = 2,   /* latched (now or before): the drive outputs 0 V (guard_zero), its step returns false */
    GUARD_IDLE = 3    /* guard_begin only: the drive is disabled, 0 V out, no fault */
} guard_action_t;

/* A drive's re-lock (guard_shell_t.relock): asked only when the reaction
 * table says RELOCK. Starts the re-lock and returns true if the drive can
 * (its budget not spent, its state one it re-locks from); false: the
 * fault is latched as SAFE. */
typedef bool (*guard_relock_fn)(void *drive);

/* A fault f found at tick: counted in rec (the first one freezes it), then
 * reaction[f] (reaction[0], the entry of NONE, for a code outside the
 * enum). RELOCK is answered GUARD_RELOCK only when relock is not NULL and
 * relock(drive) started the re-lock, else the fault is latched as SAFE. */
guard_action_t guard_react_with(supervisor_t *sup, flight_recorder_t *rec, const uint8_t reaction[DRIVE_FAULT_COUNT],
                                drive_fault_t f, uint32_t tick, guard_relock_fn relock, void *drive);

/* The same with the re-lock's answer given: RELOCK is answered
 * GUARD_RELOCK only when can_relock (the drive has a re-lock and budget
 * left; it then starts it itself), else the fault is latched as SAFE. */
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

/* How a drive counts its samples (the tick of guard_shell_t):
 *   GUARD_TICK_RUN    the samples that ran (passed guard_begin): the 0 V
 *                     samples of a latched fault, of a disabled drive, of a
 *                     refused sample are not counted, nor one a fault
 *                     stopped in the middle; guard_end counts the sample
 *                     after recording it, so a fault found by the sample's
 *                     last checks is recorded at the next sample's tick
 *                     (papers 000 and 001, the sensored drive);
 *   GUARD_TICK_EVERY  every step, the 0 V ones included; a fault found by
 *                     the sample's last checks is recorded at the sample's
 *                     own tick, and the sample counted after it (paper 002). */
typedef enum { GUARD_TICK_RUN = 0, GUARD_TICK_EVERY = 1 } guard_tick_t;

/* A drive's own checks of a sample beyond its phase count
 * (guard_shell_t.accepts): false refuses it (BAD_INPUT, latched). Asked
 * only of a sample of a running drive, so it may read what a refused
 * configuration leaves unset. */
typedef bool (*guard_accepts_fn)(const void *drive, const hal_sample_t *in);

/* A drive's own last checks of a sample (guard_shell_t.check), asked by
 * guard_end only when the command's passed: the estimate it runs on
 * (NON_FINITE), its loss-of-estimate criteria. DRIVE_FAULT_NONE: none. */
typedef drive_fault_t (*guard_check_fn)(void *drive);

/* A drive's reaction table (fault_reaction_t per drive_fault_t). */
typedef uint8_t guard_reactions_t[DRIVE_FAULT_COUNT];

/* What the shell knows of a drive: one static const per drive, as its
 * drive_ops_t. The first six fields are where the members are in the
 * drive's state (offsetof of the drive's struct: its supervisor_t, its
 * fault_monitor_t, its flight_recorder_t, its uint32_t sample count, its
 * bool "disabled", its guard_reactions_t); every function of the shell
 * takes this and the drive's state. The callbacks are given the drive's
 * state. */
typedef struct {
    size_t sup;
    size_t mon;
    size_t rec;
    size_t tick;
    size_t disabled;
    size_t reaction;
    uint8_t n_phases;         /* of the sample it accepts and of the command; 0: its state's uint8_t at n_phases_at */
    size_t n_phases_at;       /* where its phase count is in its state, when n_phases is 0 */
    guard_accepts_fn accepts; /* its own checks of a sample, NULL: the phase count alone */
    guard_check_fn check;     /* its own last checks, NULL: the command's alone */
    guard_relock_fn relock;   /* its re-lock, NULL without one (RELOCK then acts as SAFE) */
    void (*stopped)(void *drive); /* what it clears at a 0 V stop (its last voltage), NULL: nothing */
    guard_tick_t ticks;           /* how its sample count runs */
} guard_shell_t;

/* A member of the drive's state, from its offset. */
#define GUARD_MEMBER(drive, offset, type) ((type *)(void *)((char *)(drive) + (offset)))

/* The drive's phase count: its description's, or where that is 0 its
 * state's (a constant for most drives: the test folds away). */
static GUARD_IN_LINE uint8_t guard_phases(const guard_shell_t *g, void *drive)
{
    return g->n_phases != 0u ? g->n_phases : *GUARD_MEMBER(drive, g->n_phases_at, uint8_t);
}

/* The end of a sample the shell stops: 0 V out, the drive's stopped();
 * under GUARD_TICK_EVERY the step is counted. Returns a. Called by the
 * shell; by a drive itself where guard_reaction answered GUARD_SAFE deep
 * in its sample. */
guard_action_t guard_stop(const guard_shell_t *g, void *drive, guard_action_t a, hal_command_t *out);

/* A fault found during the sample, reacted to (guard_react_with: the
 * drive's table and re-lock) without touching the output: for a drive
 * that stops its sample itself on GUARD_SAFE (guard_stop on its way out). */
guard_action_t guard_reaction(const guard_shell_t *g, void *drive, drive_fault_t f);

/* A fault found during the sample: its reaction; on GUARD_SAFE 0 V out
 * (and the step counted under GUARD_TICK_EVERY). GUARD_GO_ON, GUARD_RELOCK:
 * the sample goes on. */
guard_action_t guard_fault(const guard_shell_t *g, void *drive, drive_fault_t f, hal_command_t *out);

/* A fault only the safe state answers (a refused sample, a start that
 * failed): counted and latched at this sample's tick, 0 V out (the step
 * counted under GUARD_TICK_EVERY). Returns GUARD_SAFE. */
guard_action_t guard_trip(const guard_shell_t *g, void *drive, drive_fault_t f, hal_command_t *out);

/* The start of every step, before anything is computed, in this order:
 * a latched fault (GUARD_SAFE), a disabled drive (GUARD_IDLE), a sample of
 * another phase count than the drive's or one its own checks refuse
 * (BAD_INPUT latched, GUARD_SAFE), the fault monitor's checks of the
 * sample (fault_monitor_sample; reacted to as guard_fault). GUARD_SAFE and
 * GUARD_IDLE: 0 V out, the step ends (returning a == GUARD_IDLE);
 * GUARD_GO_ON, GUARD_RELOCK: the sample goes on. */
static GUARD_IN_LINE guard_action_t guard_begin(const guard_shell_t *g, void *drive, const hal_sample_t *in,
                                                hal_command_t *out)
{
    if (GUARD_MEMBER(drive, g->sup, supervisor_t)->state == SUP_STATE_FAULT) {
        return guard_stop(g, drive, GUARD_SAFE, out);
    }
    if (*GUARD_MEMBER(drive, g->disabled, bool)) {
        return guard_stop(g, drive, GUARD_IDLE, out);
    }
    const uint8_t n_phases = guard_phases(g, drive);
    if (!phase_adapter_accepts(in, n_phases) || (g->accepts != 0 && !g->accepts(drive, in))) {
        return guard_trip(g, drive, DRIVE_FAULT_BAD_INPUT, out);
    }
    const drive_fault_t f = fault_monitor_sample(GUARD_MEMBER(drive, g->mon, fault_monitor_t), in, n_phases);
    return f == DRIVE_FAULT_NONE ? GUARD_GO_ON : guard_fault(g, drive, f, out);
}

/* The end of every sample that output a voltage: the last checks (the
 * command's, fault_monitor_command with saturated, the voltage limit's
 * flag of this sample; then the drive's own, guard_shell_t.check), the
 * sample into the flight recorder (guard_record: ref, est, speed as
 * there), the sample counted, and the checks' fault reacted to as
 * guard_fault: on GUARD_SAFE 0 V out and the step returns false. Under
 * GUARD_TICK_RUN the count comes before the reaction (the fault at the
 * next tick), under GUARD_TICK_EVERY after it. */
static GUARD_IN_LINE guard_action_t guard_end(const guard_shell_t *g, void *drive, const hal_sample_t *in,
                                              hal_command_t *out, bool saturated, mc_t ref, mc_t est, mc_t speed)
{
    drive_fault_t f = fault_monitor_command(GUARD_MEMBER(drive, g->mon, fault_monitor_t), out, saturated);
    if (f == DRIVE_FAULT_NONE && g->check != 0) {
        f = g->check(drive);
    }
    uint32_t *tick = GUARD_MEMBER(drive, g->tick, uint32_t);
    const uint32_t k = *tick;
    guard_record(GUARD_MEMBER(drive, g->rec, flight_recorder_t), k, GUARD_MEMBER(drive, g->sup, supervisor_t)->state,
                 in, out, ref, est, speed);
    if (g->ticks == GUARD_TICK_RUN) {
        *tick = k + 1u;
        return f == DRIVE_FAULT_NONE ? GUARD_GO_ON : guard_fault(g, drive, f, out);
    }
    if (f == DRIVE_FAULT_NONE) {
        *tick = k + 1u;
        return GUARD_GO_ON;
    }
    const guard_action_t a = guard_fault(g, drive, f, out);
    if (a != GUARD_SAFE) {
        *tick = k + 1u; /* on GUARD_SAFE guard_fault counted it */
    }
    return a;
}

#ifdef __cplusplus
}
#endif

#endif /* SUPERVISOR_GUARD_H */
