/*
 * magnet_polarity.h - which end of the d axis the magnet's north is, at
 * standstill, from the saturation it adds (issue 31). The HF injection
 * (estimators/hf_injection.h) finds the d axis but not its sign: (H1)-(H4)
 * are the same at theta and theta + pi. The magnet's flux biases the d-axis
 * iron: a current that adds to it (i_d > 0) saturates the iron further and
 * meets a smaller incremental inductance than the same current against it,
 * so the same volt-seconds drive a larger current. The test (the classic
 * one, e.g. M. J. Corley, R. D. Lorenz, "Rotor position and velocity
 * estimation for a salient-pole PMSM at standstill and high speeds", IEEE
 * Trans. Ind. Appl. 34(4), 1998, and the short-pulse variants since):
 *
 *   along the estimated d axis: +V_p for n_pulse samples, -V_p for
 *   n_pulse (back near zero current), 0 V for n_rest; then the mirror
 *   image (-V_p, +V_p, rest). Each part's peak of s i_d (s its sign),
 *   i_pos and i_neg, over its whole window (so a computation delay of a
 *   sample moves nothing). diff = i_pos - i_neg:
 *     diff >  margin: the estimate's d axis is the magnet's   (+1)
 *     diff < -margin: it is pi away: flip it                  (-1)
 *     else: undecided                                          (0)
 *
 * The margin (MAGPOL_MARGIN_SIGMAS below) is 6 standard deviations of the
 * difference of two peaks under the current sensor's noise: each peak is one
 * sample of i_d, whose noise is up to sqrt(5/3) a phase's (Clarke's
 * beta), the difference sqrt(2) of that: margin = 6 sqrt(2) sqrt(5/3)
 * sigma_i (55 mA at 5 mA): a wrong decision by noise alone below 1e-9.
 * The pulse: the current it reaches, V_p n_pulse Ts / L_d, should be near
 * the iron's knee (the drive's i_max) for a measurable difference.
 *
 * What it cannot do: a plant whose saturation is even in i_d has no
 * difference to see. This project's simulated plant (sim/model/saturation.h)
 * is such a one by default (its co-energy holds L_d0 i_d^2): the two peaks
 * are equal up to the noise and the test answers 0; with the magnet's bias
 * ([motor] i_sat_bias_A) it decides (tests/sim/test_hfi_polarity.cpp,
 * docs/hf_injection.md). The unit tests use a motor whose d-axis flux
 * saturates as a whole, magnet included. Size the pulse on the saturated
 * iron: along the magnet the current rises far above V_p n_pulse Ts / L_d
 * (9.6 A for 5 A on the biased plant).
 *
 * Float: the fixed-point build compiles it; no design uses it there.
 */
#ifndef ESTIMATORS_MAGNET_POLARITY_H
#define ESTIMATORS_MAGNET_POLARITY_H

#include <stdbool.h>
#include <stdint.h>

#include "adapter/phase_adapter.h"
#include "math/frame_fg.h"
#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The margin in standard deviations of the difference of two peaks
 * (header): one-sided 6 sigma, a wrong decision below 1e-9. */
#define MAGPOL_MARGIN_SIGMAS MC_C(6.0)
/* The noise of one i_d sample per phase's, worst case: sqrt(5/3), and the
 * difference of two: sqrt(2); together sqrt(10/3). */
#define MAGPOL_DIFF_NOISE_PER_PHASE MC_C(1.8257419)

typedef enum { MAGPOL_IDLE = 0, MAGPOL_RUNNING = 1, MAGPOL_DONE = 2 } magpol_state_t;

typedef struct {
    mc_t v_p_V;        /* V_p: the pulses' voltage */
    int32_t n_pulse;   /* samples of each pulse (and of its return) */
    int32_t n_rest;    /* samples at 0 V after each pair (the current decays) */
    mc_t margin_A;     /* the decision's margin on diff */
} magnet_polarity_config_t;

typedef struct {
    magnet_polarity_config_t cfg;
    magpol_state_t state;
    int32_t k;         /* sample within the test, 0 .. 2 (2 n_pulse + n_rest) */
    mc_rot_t axis;     /* the estimated d axis under test */
    mc_t i_pos_A;      /* peak of +i_d over the first half */
    mc_t i_neg_A;      /* peak of -i_d over the second */
    mc_t diff_A;       /* i_pos - i_neg (DONE) */
    int32_t result;    /* +1 the axis is the magnet's, -1 flip it by pi, 0 undecided (DONE) */
    mc_ab_t u_V;       /* the voltage for the coming sample */
} magnet_polarity_t;

/* Derives the configuration: the pulse reaching i_peak_A on L_d (n_pulse =
 * ceil(i_peak L_d / (V_p Ts))), the rest 8 L_d / R (the current down to
 * e^-8: magnet_polarity.c), the margin from sigma_i_A (the sensor's noise per
 * phase, > 0). False (cfg untouched) for non-positive values or more than
 * 10000 samples of pulse or rest. */
bool magnet_polarity_design(magnet_polarity_config_t *cfg, mc_t v_p_V, mc_t i_peak_A, mc_t Ld_H, mc_t R_ohm,
                            mc_t ts_s, mc_t sigma_i_A);

void magnet_polarity_init(magnet_polarity_t *o, const magnet_polarity_config_t *cfg);

/* Starts the test along the electrical angle theta_e_rad (the injection's
 * estimate); the first pulse is in u_V after the next step. */
void magnet_polarity_start(magnet_polarity_t *o, mc_t theta_e_rad);

/* One sample: i_A the measured alpha-beta current. Sets u_V for the coming
 * sample (0 when not running); DONE with diff_A and result after the
 * 2 (2 n_pulse + n_rest) samples of the test. */
void magnet_polarity_step(magnet_polarity_t *o, mc_ab_t i_A);

/* The test's length in samples. */
static inline int32_t magnet_polarity_samples(const magnet_polarity_config_t *cfg)
{
    return 2 * (2 * cfg->n_pulse + cfg->n_rest);
}

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_MAGNET_POLARITY_H */
