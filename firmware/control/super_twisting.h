/*
 * super_twisting.h - the super-twisting algorithm of paper 000, eqs. (13)-(14):
 *   u = u_1 - lambda |S|^(1/2) sgn(S),   du_1/dt = -alpha sgn(S)
 * in discrete time (forward Euler on u_1), with the integral clamped to
 * +-u1_max and frozen while the actuator saturates (anti-windup). Used for
 * the i_f current loop (46)-(48), where the output is a voltage: gains are
 * then L*lambda [V/A^(1/2)] and L*alpha*Ts [V per sample].
 */
#ifndef CONTROL_SUPER_TWISTING_H
#define CONTROL_SUPER_TWISTING_H

#include <stdbool.h>

#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    mc_t lambda;     /* output per unit of |S|^(1/2) */
    mc_t alpha_ts;   /* alpha * Ts: integral step per sample, output units */
    mc_t u1_max;     /* clamp of the integral term */
} super_twisting_config_t;

typedef struct {
    super_twisting_config_t cfg;
    mc_t u1;
} super_twisting_t;

void super_twisting_init(super_twisting_t *st, const super_twisting_config_t *cfg);
void super_twisting_reset(super_twisting_t *st, mc_t u1);

/* Returns u for the sliding variable S; hold_integral freezes u_1. */
mc_t super_twisting_step(super_twisting_t *st, mc_t S, bool hold_integral);

#ifdef __cplusplus
}
#endif

#endif /* CONTROL_SUPER_TWISTING_H */
