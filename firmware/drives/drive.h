/*
 * drive.h - the one interface every drive implements, and the handle the
 * programs hold. A drive is a table of operations (drive_ops_t) over its
 * own state struct, the way NuttX's FOC lower half (foc_lower_ops_s) or
 * ODrive's control laws are one shape with many implementations: step one
 * sample at the PWM rate (the HAL sample in, the HAL command out), carry
 * out a command of the CAN command set (tools/can/drive.dbc) or name why
 * not, report what the telemetry carries, give the estimate, name the
 * first fault through the flight recorder, list and read the signals it
 * shows beyond the status (drive_signal_t). A program (motorsim, the CAN
 * node, an MCU image) finds a drive by name in the registry
 * (drives/registry.h) and never names one itself; a drive is added with a
 * folder of its own and one line in the registry. Configurations differ
 * per drive (each derives its own from its motor and bounds, host side);
 * init and config_problem take the drive's own config type through a
 * void pointer. Nothing allocates: the caller owns the state (static in an
 * image; drive_storage_t in registry.h holds any registered drive).
 */
#ifndef DRIVES_DRIVE_H
#define DRIVES_DRIVE_H

#include <stdbool.h>
#include <stdint.h>

#include "estimators/estimate.h"
#include "hal/hal_types.h"
#include "math/mc_num.h"
#include "supervisor/flight_recorder.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What a drive regulates. */
typedef enum { DRIVE_KIND_POSITION = 0, DRIVE_KIND_SPEED = 1 } drive_kind_t;

/* The command set: the DBC's commands that reach a drive (CmdSetRate is
 * the CAN node's own). The values are the CAN link's (comm/can_link.h). */
typedef enum {
    DRIVE_CMD_ENABLE = 1,        /* enable: true runs, false is the safe state (0 V) */
    DRIVE_CMD_MOVE = 2,          /* theta_to_rad over duration_s, eq. (70) of paper 000 */
    DRIVE_CMD_SPEED = 3,         /* omega_ref_rad_s with ramp_rad_s2 */
    DRIVE_CMD_STOP = 4,
    DRIVE_CMD_SET_OMEGA_LIM = 5, /* omega_lim_rad_s: where a sensorless drive closes its loop */
    DRIVE_CMD_CLEAR_FAULTS = 6   /* a latched fault only: a running drive is not restarted */
} drive_cmd_kind_t;

typedef struct {
    drive_cmd_kind_t kind;
    bool enable;
    mc_t theta_to_rad, duration_s;
    mc_t omega_ref_rad_s, ramp_rad_s2;
    mc_t omega_lim_rad_s;
} drive_cmd_t;

/* Why a command was not carried out (nothing changed then). */
typedef enum {
    DRIVE_REFUSE_NONE = 0,      /* carried out */
    DRIVE_REFUSE_UNSUPPORTED,   /* not a command of this drive (a move to a speed drive) */
    DRIVE_REFUSE_STATE,         /* refused in the drive's present state or beyond its design's
                                 * limits (the drive's header says when, per command) */
    DRIVE_REFUSE_NO_FAULT       /* clear-faults without a latched fault */
} drive_refusal_t;

/* "none", "unsupported", "state", "no fault"; never NULL. */
const char *drive_refusal_name(drive_refusal_t r);

/* What every drive reports, in SI (mc_t), for telemetry and logs: the CAN
 * message set's drive part (the DBC's comments say what each signal is for
 * each drive). The control frame (1, 2) is the drive's own: (f-g) for the
 * stepper, the estimated d-q frame for the PMSM drives. */
typedef struct {
    uint8_t mode;            /* the DBC's Mode: 0 open loop, 1 closed loop, 2 fault */
    uint8_t state;           /* sup_state_t */
    uint8_t fault_code;      /* drive_fault_t, 0 none */
    uint8_t first_fault;     /* the flight recorder's first fault since init */
    uint8_t fault_events;    /* faults seen since init, recovered ones included (mod 256) */
    uint8_t relocks;         /* RELOCK reactions taken (mod 256) */
    bool enabled, saturated;
    uint16_t overruns;       /* HAL-reported overruns (mod 65536) */
    bool estimate_valid;     /* the estimate is what the loop runs on (closed loop) */
    mc_t theta_ref_rad, theta_est_rad;
    mc_t omega_ref_rad_s, accel_ref_rad_s2, omega_est_rad_s, accel_est_rad_s2, load_est_Nm;
    mc_t theta_e_est_rad;    /* the electrical angle the drive runs on, in (-pi, pi] */
    mc_t i1_A, i2_A, i1_ref_A, i2_ref_A, i1_est_A, i2_est_A;
    mc_t emf1_V, emf2_V, v1_V, v2_V;
    mc_t v_alpha_V, v_beta_V; /* the command in the stator frame */
    mc_t estimate_quality;   /* the estimator's own consistency figure, 1 when consistent
                              * (paper 001's flux observer: |rho_hat|^2; 1 where none) */
} drive_status_t;

/* What a drive shows beyond drive_status_t: its own frame's quantities
 * (paper 000's (f-g) frame, a PMSM drive's d-q currents and voltages), its
 * observers' states (an EKF's covariance, an injection's voltage), its
 * figures (the model it identified, a start's test result). A drive lists
 * them (signals: static, fixed-size) and reads their values (read_signals,
 * one mc_t each, in the list's order); the programs take them by name
 * (motorsim's CSV columns and the metrics that need a drive's quantity,
 * the plots through the CSV) and never look into the drive's state.
 * Names are stable (they are CSV columns and metric inputs): letters,
 * digits and _, a letter first, the SI unit as the suffix where there is
 * one (i_d_meas_A, ekf_P_00), unique in the list, and what the
 * quantity is to the drive: _meas its measurement, _est its estimate, _ref
 * its reference (a name without them is the drive's own quantity, e.g. a
 * command or a state). A value is SI in mc_t; an integer one (a count, a
 * code, a state: DRIVE_SIGNAL_INTEGER) is exact in mc_t up to 2^14 in
 * magnitude (Q14.17). A setting (DRIVE_SIGNAL_SETTING) is constant after
 * init (a configuration's figure): the programs read it once, not per
 * sample (motorsim reports it as a metric where a scoring asks for it,
 * never as a column). */
enum {
    DRIVE_SIGNAL_INTEGER = 1u << 0, /* a whole number: printed without decimals */
    DRIVE_SIGNAL_SETTING = 1u << 1  /* constant after init: not a column */
};

typedef struct {
    const char *name;        /* "ekf_P_00": a CSV column, never NULL */
    const char *unit;        /* SI: "A", "V", "rad", "rad/s", "N m", "ohm", "H", "V s", "A^2";
                              * "1" when dimensionless (counts and codes too); never "" */
    const char *description; /* one line for the docs and the CSV's readers */
    uint8_t flags;           /* DRIVE_SIGNAL_* */
} drive_signal_t;

/* The most signals a drive lists: a reader's fixed buffer (mc_t
 * values[DRIVE_SIGNALS_MAX]) holds any drive's. */
#define DRIVE_SIGNALS_MAX 48u

/* The operations of one drive. self is the drive's own state struct
 * (state_bytes long); cfg its own config type. */
typedef struct drive_ops {
    const char *name;          /* registry key, as in scenarios and --drive options: "paper000" */
    const char *title;         /* one line for --help and the docs */
    drive_kind_t kind;
    uint8_t can_kind;          /* the DBC's DriveKind (heartbeat) */
    uint32_t state_bytes;      /* sizeof the state struct */
    uint32_t config_bytes;     /* sizeof the config struct */
    /* NULL if cfg is consistent, else its first problem (a literal naming the field) */
    const char *(*config_problem)(const void *cfg);
    /* validates cfg, copies it, resets every state; false: the drive is in
     * FAULT with 0 V out (config_problem says why) */
    bool (*init)(void *self, const void *cfg);
    /* one sample: always fills *out (0 V in FAULT or disabled); false in FAULT */
    bool (*step)(void *self, const hal_sample_t *in, hal_command_t *out);
    drive_refusal_t (*command)(void *self, const drive_cmd_t *cmd);
    void (*status)(const void *self, drive_status_t *s);
    void (*estimate)(const void *self, mc_estimate_t *e);
    /* the first fault's code, tick and the samples before it */
    const flight_recorder_t *(*recorder)(const void *self);
    /* its signals (static storage) and their number in *count (at most
     * DRIVE_SIGNALS_MAX); after init the list may depend on the
     * configuration (an estimator's signals only where it runs), and
     * stays the same until the next init */
    const drive_signal_t *(*signals)(const void *self, uint32_t *count);
    /* the values of that list after the last step (or init), values[0 ..
     * count); reads only, allocates nothing */
    void (*read_signals)(const void *self, mc_t *values);
} drive_ops_t;

/* A drive as the programs hold it: its operations and its state. */
typedef struct {
    const drive_ops_t *ops;
    void *self;
} drive_t;

static inline bool drive_init(drive_t *d, const void *cfg) { return d->ops->init(d->self, cfg); }
static inline bool drive_step(drive_t *d, const hal_sample_t *in, hal_command_t *out)
{
    return d->ops->step(d->self, in, out);
}
static inline drive_refusal_t drive_command(drive_t *d, const drive_cmd_t *cmd)
{
    return d->ops->command(d->self, cmd);
}
static inline void drive_status(const drive_t *d, drive_status_t *s) { d->ops->status(d->self, s); }
static inline void drive_estimate(const drive_t *d, mc_estimate_t *e) { d->ops->estimate(d->self, e); }
static inline const flight_recorder_t *drive_recorder(const drive_t *d) { return d->ops->recorder(d->self); }
static inline const drive_signal_t *drive_signals(const drive_t *d, uint32_t *count)
{
    return d->ops->signals(d->self, count);
}
static inline void drive_read_signals(const drive_t *d, mc_t *values) { d->ops->read_signals(d->self, values); }

#ifdef __cplusplus
}
#endif

#endif /* DRIVES_DRIVE_H */
