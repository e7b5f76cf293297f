/*
 * inverter_id.h - the phase resistance and the inverter's voltage error
 * against current, measured at standstill from a few current levels held
 * along the rotor's axis (not in the papers; issue 45's commissioning).
 *
 * Why several currents: a single level gives v / i = R + V_inv(i) / i,
 * where V_inv is what the inverter takes from the commanded voltage (dead
 * time and switching delays, V_dc t_err f_pwm a leg, and the devices'
 * drops: sim/model/inverter.h). On the VESC 6 at 48 V with 500 ns
 * (sim/inverters/vesc6.toml) that is 0.48 V a leg, 0.64 V on the alpha
 * axis well above the transition current: one level of 8 A on paper 001's
 * motor (R 0.225 ohm) reads R 36 % high, one of 3 A 95 % high, and the
 * dead-time compensation is told nothing about its board. The levels' means separate the slope R from the error, and the
 * error's shape against current is what the compensation needs (its
 * voltage and transition current: design/inverter_fit.h fits them), as
 * MESC measures its dead time and VESC its R from two currents.
 *
 * How: the rotor rests aligned on the alpha axis (startup/align.h, or the
 * ALIGN phases of startup/pmsm_identification.h), so a current along alpha
 * makes no torque. A PI loop holds i_alpha at each level
 * i_k = k i_test / n (k = 1 .. n, lowest first: no step larger than
 * i_test / n) and i_beta at 0; each level settles for settle_ticks, then
 * the commanded voltages and the measured currents are averaged over
 * meas_ticks (math/mc_mean.h: no sum leaves the fixed-point range). The
 * commanded voltage is what the loop asks of the inverter; in a steady
 * state it is the voltage applied over every sample, whatever the
 * computation delay. The PI (v = kp e + ki Ts sum e, the integrator clamped
 * so that v stays within +-v_max) is the caller's design: kp = L w_c,
 * ki = R w_c cancels the winding's pole (w_c well below the sample rate).
 * A phase current beyond i_trip_A, or a level's current off its target
 * by more than 5 % at the end of its settling (an open phase: the current
 * does not come, the voltage rising to v_max; or gains too slow for
 * settle_ticks) ends the run REJECTED with the reason in `why` and 0 V
 * out.
 *
 * Float and fixed point (Q14.17: currents and voltages well inside
 * +-16384). No allocation; the state is the caller's.
 */
#ifndef STARTUP_INVERTER_ID_H
#define STARTUP_INVERTER_ID_H

#include <stdbool.h>
#include <stdint.h>

#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The most levels a run holds. */
#define INV_ID_MAX_LEVELS 12

typedef enum {
    INV_ID_RUNNING = 0,
    INV_ID_DONE = 1,    /* i_mean_A[], v_mean_V[] hold the n levels' means */
    INV_ID_REJECTED = 2 /* see why; 0 V out from then on */
} inv_id_state_t;

typedef struct {
    mc_t i_test_A;        /* the highest level, > 0, below i_trip_A */
    int32_t n_levels;     /* 2 .. INV_ID_MAX_LEVELS */
    int32_t settle_ticks; /* samples each level settles, >= 1 */
    int32_t meas_ticks;   /* samples each level is averaged over, >= 1 */
    mc_t kp_V_per_A;      /* the current loop's proportional gain, > 0 */
    mc_t ki_ts_V_per_A;   /* its integral gain times the sample time Ts, >= 0 */
    mc_t v_max_V;         /* the loop's voltage limit (the bus's share), > 0 */
    mc_t i_trip_A;        /* any phase current beyond: rejected */
} inv_id_config_t;

typedef struct {
    inv_id_config_t cfg;
    inv_id_state_t state;
    int32_t level; /* 0 .. n_levels - 1: the level held */
    int32_t k;     /* samples into it */
    mc_t integ_alpha_V, integ_beta_V;
    mc_t v_sum_res[2]; /* the means' rounding residuals (math/mc_mean.h) */
    mc_t i_mean_A[INV_ID_MAX_LEVELS], v_mean_V[INV_ID_MAX_LEVELS];
    const char *why; /* REJECTED: a literal naming the reason */
} inv_id_t;

/* NULL if c can run, else its first problem (a literal naming the field). */
const char *inv_id_config_problem(const inv_id_config_t *c);

/* False (and nothing set) if the configuration cannot run. */
bool inv_id_init(inv_id_t *id, const inv_id_config_t *c);

/* One sample: the phase currents as alpha-beta (A, measured now) and the
 * largest phase current's magnitude (the trip check); out the alpha-beta
 * voltages to apply over the coming sample (0 V once not RUNNING). Returns
 * the state after the sample. */
inv_id_state_t inv_id_step(inv_id_t *id, mc_t i_alpha_A, mc_t i_beta_A, mc_t i_phase_max_A, mc_t *v_alpha_V,
                           mc_t *v_beta_V);

#ifdef __cplusplus
}
#endif

#endif /* STARTUP_INVERTER_ID_H */
