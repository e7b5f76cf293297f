/*
 * supervisor.h - the state machine every drive runs under: start-up with
 * identification, open loop, closed loop and the latched fault, as a table
 * of states and transitions (supervisor.c); the fault latch; the bumpless
 * transfer of the applied voltage at a switch; and the voltage limit.
 * Which conditions raise which event is the drive's business (its recipe in
 * firmware/drives/); what an event does in which state is decided here,
 * once for every drive.
 *
 * States and transitions (an event not listed for a state is ignored):
 *
 *   ALIGN ------aligned------------> IDENTIFY, or OPEN_LOOP without identification
 *   IDENTIFY ---identified---------> OPEN_LOOP
 *   IDENTIFY ---estimate_trusted---> CLOSED_LOOP   (identification abandoned)
 *   OPEN_LOOP --estimate_trusted---> CLOSED_LOOP
 *   CLOSED_LOOP-estimate_lost------> OPEN_LOOP
 *   any --------fault--------------> FAULT         (latched: 0 V until *_init)
 *
 * Voltage offsets, limits and the last command are kept in the drive's
 * control frame (two components), whatever the phase count.
 */
#ifndef SUPERVISOR_SUPERVISOR_H
#define SUPERVISOR_SUPERVISOR_H

#include <stdbool.h>
#include <stdint.h>

#include "adapter/phase_adapter.h"
#include "math/decay.h"
#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    SUP_STATE_IDENTIFY = 0,   /* open-loop start while the standstill R/L measurement runs */
    SUP_STATE_OPEN_LOOP = 1,  /* open-loop drive below omega_lim (paper 000 eq. (68)) */
    SUP_STATE_CLOSED_LOOP = 2,/* control on the estimates */
    SUP_STATE_FAULT = 3,      /* safe state: 0 V until the drive is initialised again */
    SUP_STATE_ALIGN = 4,      /* rotor alignment before the start (startup/align.h) */
    SUP_STATE_COUNT = 5
} sup_state_t;

typedef enum {
    SUP_EV_IDENTIFIED = 0,       /* the identification finished (measured, rejected or off) */
    SUP_EV_ESTIMATE_TRUSTED = 1, /* the estimate is observable and the speed asks for closed loop */
    SUP_EV_ESTIMATE_LOST = 2,    /* no longer */
    SUP_EV_FAULT = 3,            /* supervisor_fault() raises it */
    SUP_EV_ALIGNED = 4           /* the alignment is over */
} sup_event_t;

/* Telemetry view of the state, stable across versions. */
typedef enum {
    DRIVE_MODE_OPEN_LOOP = 0,   /* IDENTIFY or OPEN_LOOP */
    DRIVE_MODE_CLOSED_LOOP = 1,
    DRIVE_MODE_FAULT = 2
} drive_mode_t;

/* Fault codes: why the drive is in FAULT, or what it recovered from (the
 * first cause is kept). The criteria are in fault_monitor.h (generic) and
 * in each drive's recipe (loss of synchronism); docs/faults.md lists each
 * criterion, threshold, detection time and default reaction. The numbers
 * are stable (telemetry, logs, CAN). */
typedef enum {
    DRIVE_FAULT_NONE = 0,
    DRIVE_FAULT_OVERCURRENT = 1,   /* a measured phase current beyond i_trip_A */
    DRIVE_FAULT_BAD_INPUT = 2,     /* inconsistent configuration or a sample of the wrong phase count */
    DRIVE_FAULT_I2T = 3,           /* the I^2 t integral beyond its limit (thermal overload) */
    DRIVE_FAULT_VOLTAGE_SATURATION = 4, /* the voltage limit active for too long */
    DRIVE_FAULT_LOSS_OF_SYNC = 5,  /* the estimate is inconsistent or the rotor lost the reference */
    DRIVE_FAULT_NON_FINITE = 6,    /* NaN or inf in a sample, a state or a command (float build) */
    DRIVE_FAULT_SENSOR_STUCK = 7,  /* a current sample that does not change while its voltage does */
    DRIVE_FAULT_SENSOR_RAIL = 8,   /* a current sample at the ADC's full scale */
    DRIVE_FAULT_ADC = 9,           /* the backend reported a converter error (HAL_STATUS_ADC_FAULT) */
    DRIVE_FAULT_HW_TRIP = 10,      /* the power stage's own trip fired (HAL_STATUS_PWM_TRIP) */
    DRIVE_FAULT_OVERRUN = 11,      /* control steps overran their period too often (HAL_STATUS_OVERRUN) */
    DRIVE_FAULT_LOSS_OF_LOCK = 12, /* a speed drive's estimate no longer explains the currents (lock_monitor.h) */
    DRIVE_FAULT_COUNT = 13         /* number of codes, NONE included */
} drive_fault_t;

/* What a fault does (per fault, in the drive's configuration). */
typedef enum {
    FAULT_REACT_SAFE = 0,   /* FAULT: 0 V (the bridge shorts the windings) until cleared */
    FAULT_REACT_RELOCK = 1, /* fall back to open loop, close again after a hold; bounded retries, then SAFE */
    FAULT_REACT_REPORT = 2  /* record it and go on (commissioning, tests) */
} fault_reaction_t;

/* One-word name of a fault code ("none", "over-current", "bad-input";
 * "unknown" outside the enum): the one place the names live, for logs,
 * telemetry and tools. Static strings; nothing is formatted. */
const char *drive_fault_name(drive_fault_t f);

typedef struct {
    mc_t blend_decay;  /* per-sample decay exp(-Ts/tau) of the voltage offset added at a switch */
} supervisor_config_t;

typedef struct {
    supervisor_config_t cfg;
    sup_state_t state;
    sup_state_t start_state;  /* where ALIGN goes: IDENTIFY or OPEN_LOOP */
    drive_fault_t fault;
    mc_t blend_V[2];   /* decaying offset that removes the voltage step of a switch (control frame) */
    mc_t v_prev_V[2];  /* the last command (control frame), after the limit */
    bool sat_prev;     /* the last command hit the voltage limit */
} supervisor_t;

/* Starts in ALIGN (align), else in IDENTIFY (identify) or OPEN_LOOP; no
 * fault, no offset. */
void supervisor_init(supervisor_t *s, const supervisor_config_t *cfg, bool align, bool identify);

/* Applies the transition of the table for ev in the current state.
 * Returns true if the state changed. */
bool supervisor_dispatch(supervisor_t *s, sup_event_t ev);

/* Latches f (the first fault is kept) and goes to FAULT. */
void supervisor_fault(supervisor_t *s, drive_fault_t f);

/* Telemetry mode of the state. */
drive_mode_t supervisor_mode(const supervisor_t *s);

/* Bumpless transfer: on a switch (switched), the step between the last
 * command and the new law's v becomes an offset added to v that decays
 * with blend_decay, so the applied voltage has no step. Call every sample. */
static inline void supervisor_blend(supervisor_t *s, bool switched, mc_t *v1_V, mc_t *v2_V)
{
    if (switched) {
        /* v_prev already holds what the last offset added: the new offset
         * replaces it (adding to it stepped by the old offset's remainder
         * when two switches came within a few decay times: a re-lock) */
        s->blend_V[0] = mc_sub(s->v_prev_V[0], *v1_V);
        s->blend_V[1] = mc_sub(s->v_prev_V[1], *v2_V);
    }
    if (mc_ne(s->blend_V[0], MC_ZERO) || mc_ne(s->blend_V[1], MC_ZERO)) {
        *v1_V = mc_add(*v1_V, s->blend_V[0]);
        *v2_V = mc_add(*v2_V, s->blend_V[1]);
        s->blend_V[0] = mc_decay(s->blend_V[0], s->cfg.blend_decay);
        s->blend_V[1] = mc_decay(s->blend_V[1], s->cfg.blend_decay);
    }
}

/* The scaling of supervisor_limit once the peak v_peak is known. */
static inline bool supervisor__limit_peak(supervisor_t *s, mc_t v_peak, mc_t v_max_V, mc_ab_t *v_ab, mc_t *v1_V,
                                          mc_t *v2_V)
{
    const bool sat = mc_gt(v_peak, v_max_V);
    if (sat) {
        const mc_t scale = mc_div(v_max_V, v_peak);
        v_ab->alpha = mc_mul(v_ab->alpha, scale);
        v_ab->beta = mc_mul(v_ab->beta, scale);
        *v1_V = mc_mul(*v1_V, scale);
        *v2_V = mc_mul(*v2_V, scale);
    }
    s->sat_prev = sat;
    s->v_prev_V[0] = *v1_V;
    s->v_prev_V[1] = *v2_V;
    return sat;
}

/* Voltage limit: when the peak the power stage needs for v_ab (phase
 * adapter) exceeds v_max_V, v_ab and the control-frame command v1, v2 are
 * scaled by the same factor (direction kept). Records the command and the
 * saturation for the next sample; returns true if it limited. */
static inline bool supervisor_limit(supervisor_t *s, uint8_t n_phases, mc_t v_max_V, mc_ab_t *v_ab, mc_t *v1_V, mc_t *v2_V)
{
    return supervisor__limit_peak(s, phase_adapter_peak(n_phases, *v_ab), v_max_V, v_ab, v1_V, v2_V);
}

/* supervisor_limit, then the limited v_ab to the phase voltages of *out
 * (phase_adapter_voltages): the same values, with the three legs and
 * their min/max formed once when the limit leaves v_ab as it is. */
static inline bool supervisor_limit_output(supervisor_t *s, uint8_t n_phases, mc_t v_max_V, mc_ab_t *v_ab, mc_t *v1_V,
                                           mc_t *v2_V, hal_command_t *out)
{
    if (n_phases != 3) {
        const bool sat = supervisor_limit(s, n_phases, v_max_V, v_ab, v1_V, v2_V);
        phase_adapter_voltages(n_phases, *v_ab, out);
        return sat;
    }
    phase_legs_t l;
    phase_adapter_legs(*v_ab, &l);
    const bool sat = supervisor__limit_peak(s, phase_adapter_legs_peak(&l), v_max_V, v_ab, v1_V, v2_V);
    if (sat) {
        phase_adapter_legs(*v_ab, &l);
    }
    phase_adapter_legs_out(&l, out);
    return sat;
}

#ifdef __cplusplus
}
#endif

#endif /* SUPERVISOR_SUPERVISOR_H */
