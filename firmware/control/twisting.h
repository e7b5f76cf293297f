/*
 * twisting.h - the twisting algorithm of paper 000, eq. (21):
 *   w = -lambda_M sgn(S) if S dS/dt > 0,  -lambda_m sgn(S) otherwise,
 * for a relative-degree-2 sliding variable. The position loop (52)-(54)
 * uses it with the output scaled to a voltage (gains times JL/K).
 * Finite-time convergence needs conditions (22), see paper000_design.c.
 */
#ifndef CONTROL_TWISTING_H
#define CONTROL_TWISTING_H

#include <stdbool.h>

#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    mc_t lambda_m; /* gain when S moves toward 0 */
    mc_t lambda_M; /* gain when S moves away from 0, > lambda_m */
} twisting_config_t;

typedef struct {
    twisting_config_t cfg;
} twisting_t;

void twisting_init(twisting_t *tw, const twisting_config_t *cfg);

/* The product S*dS is decided from the signs, so it cannot overflow. */
static inline mc_t twisting_step(const twisting_t *tw, mc_t S, mc_t S_dot)
{
    const bool away = (mc_gt(S, MC_ZERO) && mc_gt(S_dot, MC_ZERO)) || (mc_lt(S, MC_ZERO) && mc_lt(S_dot, MC_ZERO));
    const mc_t gain = away ? tw->cfg.lambda_M : tw->cfg.lambda_m;
    return mc_neg(mc_mul_sgn(gain, S));
}

#ifdef __cplusplus
}
#endif

#endif /* CONTROL_TWISTING_H */
