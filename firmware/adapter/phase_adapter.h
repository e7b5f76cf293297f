/*
 * phase_adapter.h - the motor's phases seen as one alpha-beta pair, both
 * ways, so a two-phase stepper and a three-phase PMSM look the same to the
 * estimators and controllers: the sample's 2 or 3 phase currents in, the
 * alpha-beta voltage out to 2 or 3 phase voltages, and the peak the power
 * stage limits. Clarke and its inverse live here and nowhere else.
 *
 * Two phases (windings a, b in quadrature, an H-bridge each): alpha = a,
 * beta = b, no arithmetic; the limit is on each winding, max(|v_a|, |v_b|).
 * Three phases (star, legs a, b, c): the amplitude-invariant Clarke
 * transform
 *   alpha = a - z,  beta = (b - c)/sqrt(3),  z = (a + b + c)/3,
 * where z, the zero-sequence current, is 0 for a star without a neutral
 * wire (a non-zero z means an offset or a fault in the measurement). Its
 * inverse with min/max zero-sequence injection (equivalent to centred
 * space-vector modulation):
 *   a = alpha, b = -alpha/2 + (sqrt(3)/2) beta, c = -alpha/2 - (sqrt(3)/2) beta,
 *   each then shifted by -(max + min)/2,
 * so the legs use the bus symmetrically; the linear range is |v_ab| <=
 * v_bus/sqrt(3) and the peak a leg needs is (max - min)/2 <= v_bus/2.
 *
 * Static inline like CMSIS-DSP's arm_clarke_f32: a few operations per
 * sample, called once. Fixed point: every intermediate is a sum of at most
 * three phase values (|x| <= 3 * 16384 would overflow Q14.17, so phase
 * values must stay below 5000 A or V, far above any drive here) and the
 * products by 1/sqrt(3), sqrt(3)/2 shrink them; rounding <= 2 LSB.
 */
#ifndef ADAPTER_PHASE_ADAPTER_H
#define ADAPTER_PHASE_ADAPTER_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal_types.h"
#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 1/sqrt(3) and sqrt(3)/2 of the Clarke transform and its inverse. */
#define PHASE_ADAPTER_INV_SQRT3 MC_C(0.57735026918962576451)
#define PHASE_ADAPTER_SQRT3_2 MC_C(0.86602540378443864676)

/* A pair in the stator frame: alpha along phase a. */
typedef struct {
    mc_t alpha;
    mc_t beta;
} mc_ab_t;

/* True if the sample carries the phase count the drive was built for. */
static inline bool phase_adapter_accepts(const hal_sample_t *in, uint8_t n_phases)
{
    return in->n_phases == n_phases;
}

/* Clarke of per-phase quantities x[0..n_phases-1] (currents [A], voltages
 * [V]) into alpha-beta; *zero gets the zero sequence (0 for two phases,
 * whose x are alpha and beta already). n_phases must be 2 or 3. */
static inline mc_ab_t phase_adapter_clarke(uint8_t n_phases, const mc_t *x, mc_t *zero)
{
    mc_ab_t v;
    if (n_phases == 3) {
        const mc_t z = mc_div_i(mc_add(mc_add(x[0], x[1]), x[2]), 3);
        v.alpha = mc_sub(x[0], z);
        v.beta = mc_mul(mc_sub(x[1], x[2]), PHASE_ADAPTER_INV_SQRT3);
        *zero = z;
    } else {
        v.alpha = x[0];
        v.beta = x[1];
        *zero = MC_ZERO;
    }
    return v;
}

/* The sample's phase currents as alpha-beta [A]; *i_zero_A gets the
 * zero-sequence current (0 for two phases). n_phases must be 2 or 3
 * (phase_adapter_accepts). */
static inline mc_ab_t phase_adapter_currents(const hal_sample_t *in, mc_t *i_zero_A)
{
    return phase_adapter_clarke(in->n_phases, in->i_A, i_zero_A);
}

/* Inverse Clarke: the three leg voltages of v, before any zero sequence. */
static inline void phase_adapter_inverse_clarke(mc_ab_t v, mc_t *a, mc_t *b, mc_t *c)
{
    const mc_t half_a = mc_div_i(v.alpha, 2);
    const mc_t kb = mc_mul(v.beta, PHASE_ADAPTER_SQRT3_2);
    *a = v.alpha;
    *b = mc_sub(kb, half_a);
    *c = mc_neg(mc_add(kb, half_a));
}

/* The three legs of v (inverse Clarke, before the zero sequence) with the
 * largest and the smallest of them: what the min/max zero sequence and the
 * peak a leg needs both start from, so a step that limits v and then
 * outputs it forms them once when the limit leaves v as it is. */
typedef struct {
    mc_t a, b, c;
    mc_t hi, lo;   /* max and min of a, b, c */
} phase_legs_t;

static inline void phase_adapter_legs(mc_ab_t v, phase_legs_t *l)
{
    phase_adapter_inverse_clarke(v, &l->a, &l->b, &l->c);
    l->hi = mc_max(l->a, mc_max(l->b, l->c));
    l->lo = mc_min(l->a, mc_min(l->b, l->c));
}

/* The legs shifted by -(max + min)/2 (min/max zero sequence) into *out. */
static inline void phase_adapter_legs_out(const phase_legs_t *l, hal_command_t *out)
{
    const mc_t a = l->a, b = l->b, c = l->c;
    const mc_t shift = mc_neg(mc_div_i(mc_add(l->hi, l->lo), 2));
    out->n_phases = 3u;
    out->v_V[0] = mc_add(a, shift);
    out->v_V[1] = mc_add(b, shift);
    out->v_V[2] = mc_add(c, shift);
}

/* The peak a leg needs about the bus midpoint after the zero sequence. */
static inline mc_t phase_adapter_legs_peak(const phase_legs_t *l) { return mc_div_i(mc_sub(l->hi, l->lo), 2); }

/* Alpha-beta voltage [V] to the phase voltages of *out (n_phases 2 or 3).
 * Three phases: inverse Clarke, then the min/max zero sequence. */
static inline void phase_adapter_voltages(uint8_t n_phases, mc_ab_t v, hal_command_t *out)
{
    if (n_phases == 3) {
        phase_legs_t l;
        phase_adapter_legs(v, &l);
        phase_adapter_legs_out(&l, out);
    } else {
        out->n_phases = n_phases;
        out->v_V[0] = v.alpha;
        out->v_V[1] = v.beta;
        out->v_V[2] = MC_ZERO;
    }
}

/* The largest voltage a winding (two phases) or a leg about the bus
 * midpoint (three phases, after the zero sequence) needs for v [V]: the
 * quantity the power stage limits. */
static inline mc_t phase_adapter_peak(uint8_t n_phases, mc_ab_t v)
{
    if (n_phases == 3) {
        phase_legs_t l;
        phase_adapter_legs(v, &l);
        return phase_adapter_legs_peak(&l);
    }
    return mc_max(mc_abs(v.alpha), mc_abs(v.beta));
}

#ifdef __cplusplus
}
#endif

#endif /* ADAPTER_PHASE_ADAPTER_H */
