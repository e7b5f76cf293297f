#include "supervisor/supervisor.h"

/* The transition table (see supervisor.h). SUP_STATE_COUNT as the source
 * state means "any state", as the target "the start state" (IDENTIFY or
 * OPEN_LOOP, fixed at supervisor_init). Scanned only when an event is raised, which the
 * recipes do on a change of condition, not every sample. */
typedef struct {
    sup_state_t from;
    sup_event_t event;
    sup_state_t to;
} sup_transition_t;

static const sup_transition_t k_transitions[] = {
    {SUP_STATE_ALIGN, SUP_EV_ALIGNED, SUP_STATE_COUNT}, /* to start_state */
    {SUP_STATE_IDENTIFY, SUP_EV_IDENTIFIED, SUP_STATE_OPEN_LOOP},
    {SUP_STATE_IDENTIFY, SUP_EV_ESTIMATE_TRUSTED, SUP_STATE_CLOSED_LOOP},
    {SUP_STATE_OPEN_LOOP, SUP_EV_ESTIMATE_TRUSTED, SUP_STATE_CLOSED_LOOP},
    {SUP_STATE_CLOSED_LOOP, SUP_EV_ESTIMATE_LOST, SUP_STATE_OPEN_LOOP},
    {SUP_STATE_COUNT, SUP_EV_FAULT, SUP_STATE_FAULT},
};

void supervisor_init(supervisor_t *s, const supervisor_config_t *cfg, bool align, bool identify)
{
    s->cfg = *cfg;
    s->start_state = identify ? SUP_STATE_IDENTIFY : SUP_STATE_OPEN_LOOP;
    s->state = align ? SUP_STATE_ALIGN : s->start_state;
    s->fault = DRIVE_FAULT_NONE;
    s->blend_V[0] = MC_ZERO;
    s->blend_V[1] = MC_ZERO;
    s->v_prev_V[0] = MC_ZERO;
    s->v_prev_V[1] = MC_ZERO;
    s->sat_prev = false;
}

bool supervisor_dispatch(supervisor_t *s, sup_event_t ev)
{
    if (s->state == SUP_STATE_FAULT) {
        return false; /* latched */
    }
    for (uint32_t k = 0; k < sizeof k_transitions / sizeof k_transitions[0]; ++k) {
        const sup_transition_t *t = &k_transitions[k];
        if (t->event == ev && (t->from == s->state || t->from == SUP_STATE_COUNT)) {
            s->state = (t->to == SUP_STATE_COUNT) ? s->start_state : t->to;
            return true;
        }
    }
    return false;
}

void supervisor_fault(supervisor_t *s, drive_fault_t f)
{
    if (s->fault == DRIVE_FAULT_NONE) {
        s->fault = f;
    }
    (void)supervisor_dispatch(s, SUP_EV_FAULT);
}

drive_mode_t supervisor_mode(const supervisor_t *s)
{
    switch (s->state) {
    case SUP_STATE_CLOSED_LOOP:
        return DRIVE_MODE_CLOSED_LOOP;
    case SUP_STATE_FAULT:
        return DRIVE_MODE_FAULT;
    default:
        return DRIVE_MODE_OPEN_LOOP;
    }
}

const char *drive_fault_name(drive_fault_t f)
{
    switch (f) {
    case DRIVE_FAULT_NONE: return "none";
    case DRIVE_FAULT_OVERCURRENT: return "over-current";
    case DRIVE_FAULT_BAD_INPUT: return "bad-input";
    case DRIVE_FAULT_I2T: return "i2t";
    case DRIVE_FAULT_VOLTAGE_SATURATION: return "voltage-saturation";
    case DRIVE_FAULT_LOSS_OF_SYNC: return "loss-of-sync";
    case DRIVE_FAULT_NON_FINITE: return "non-finite";
    case DRIVE_FAULT_SENSOR_STUCK: return "sensor-stuck";
    case DRIVE_FAULT_SENSOR_RAIL: return "sensor-rail";
    case DRIVE_FAULT_ADC: return "adc";
    case DRIVE_FAULT_HW_TRIP: return "hw-trip";
    case DRIVE_FAULT_OVERRUN: return "overrun";
    case DRIVE_FAULT_LOSS_OF_LOCK: return "loss-of-lock";
    default: return "unknown";
    }
}
