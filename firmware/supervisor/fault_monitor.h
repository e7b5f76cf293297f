/*
 * fault_monitor.h - the faults every drive detects the same way, from the
 * HAL sample, the command and the backend's status, each with a stated
 * criterion (the thresholds are derived and justified in the drive's design,
 * design/): over-current (instantaneous, or on N consecutive
 * samples where single samples can carry glitches), I^2 t, voltage saturated
 * too long, non-finite values (float build), current samples stuck or at the
 * ADC rails, converter errors, the hardware trip and control-step overruns.
 * Faults that need the drive's estimates (loss of synchronism) are the
 * drive's; fault_persist_t is the "condition for N samples" counter they
 * share. The monitor only reports: what a fault does is the supervisor's
 * reaction table (supervisor.h). No allocation, fixed-size state.
 */
#ifndef SUPERVISOR_FAULT_MONITOR_H
#define SUPERVISOR_FAULT_MONITOR_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal_types.h"
#include "math/mc_num.h"
#include "supervisor/supervisor.h"

#ifdef __cplusplus
extern "C" {
#endif

/* I^2 t is integrated on the mean of FAULT_I2T_DECIMATION samples: the
 * per-block increment (mean excess) x (block time / allowed time) stays far
 * above the fixed-point resolution, which a per-sample increment of 1e-4
 * relative would not. A power of two: the mean is a shift. */
#define FAULT_I2T_DECIMATION 64
/* Of those, every FAULT_I2T_SUBSAMPLE-th sample enters the mean (16 per
 * block): a motor heats over seconds, and a 0.4 ms subsample of the
 * current's square follows that as well at a quarter of the cost. Powers
 * of two. */
#define FAULT_I2T_SUBSAMPLE 4

typedef struct {
    mc_t i_trip_A;          /* over-current: |i_phase| > i_trip_A ... */
    int32_t i_trip_samples; /* ... on this many consecutive samples (1: instantaneous) */
    mc_t i2t_cont_A2;       /* I_cont^2: a current vector |i|^2 below it cools the I^2 t integral */
    mc_t i2t_gain;          /* FAULT_I2T_DECIMATION Ts / t_overload: per-block weight of the mean excess */
    mc_t i2t_limit_A2;      /* trip when the integral of the excess, in A^2 x t_overload, exceeds it */
    int32_t sat_max_ticks;  /* voltage limit active for more than this many consecutive samples */
    int32_t stuck_ticks;    /* a phase sample bit-identical for this many samples ... */
    mc_t stuck_dv_V;        /* ... while its voltage command spanned at least this much */
    mc_t i_rail_A;          /* |i| at or beyond it is at the ADC rail (0: not checked) */
    int32_t rail_ticks;     /* ... for this many consecutive samples */
    int32_t overrun_weight; /* added per overrun; 1 leaks per sample */
    int32_t overrun_limit;  /* trip when the leaky overrun level reaches it */
} fault_monitor_config_t;

typedef struct {
    fault_monitor_config_t cfg;
    mc_t i2_sum_A2;                   /* sum of |i|^2 over the current block */
    int32_t i2_n;                     /* samples in it */
    mc_t i2t_A2;                      /* I^2 t integral (>= 0) */
    int32_t sat_run;                  /* consecutive saturated samples */
    mc_t i_last_A[HAL_MAX_PHASES];    /* previous sample of each phase */
    int32_t same_run[HAL_MAX_PHASES]; /* samples it has not changed */
    mc_t v_lo_V[HAL_MAX_PHASES];      /* command range over that run */
    mc_t v_hi_V[HAL_MAX_PHASES];
    mc_t v_last_V[HAL_MAX_PHASES];    /* the last command (acts on the next sample) */
    int32_t oc_run;                   /* consecutive samples beyond i_trip_A before this one */
    int32_t rail_run;
    mc_t rail_abs_A;                  /* i_rail_A, or MC_MAX without a rail */
    int32_t overrun_level;
    uint32_t overruns;                /* total, for telemetry */
} fault_monitor_t;

void fault_monitor_init(fault_monitor_t *m, const fault_monitor_config_t *cfg);

/* The sample's checks, first thing in a step: hardware trip and converter
 * status, non-finite inputs, instantaneous over-current, ADC rails, stuck
 * samples, I^2 t, overruns. Returns the first fault found (in that order)
 * or DRIVE_FAULT_NONE. n_phases: the drive's. */
drive_fault_t fault_monitor_sample(fault_monitor_t *m, const hal_sample_t *in, uint8_t n_phases);

/* The command's checks, last thing in a step: non-finite voltages, the
 * voltage limit active for too long; keeps the command for the stuck
 * check of the next sample. */
drive_fault_t fault_monitor_command(fault_monitor_t *m, const hal_command_t *out, bool saturated);

/* A condition that must hold for n consecutive samples. */
typedef struct {
    int32_t run;
} fault_persist_t;

static inline bool fault_persist_step(fault_persist_t *p, bool condition, int32_t n)
{
    p->run = condition ? (p->run < n ? p->run + 1 : n) : 0;
    return condition && p->run >= n;
}

#ifdef __cplusplus
}
#endif

#endif /* SUPERVISOR_FAULT_MONITOR_H */
