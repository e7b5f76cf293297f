#include "control/twisting.h"

#include <stdbool.h>

void twisting_init(twisting_t *tw, const twisting_config_t *cfg) { tw->cfg = *cfg; }

mc_t twisting_step(const twisting_t *tw, mc_t S, mc_t S_dot)
{
    const bool away = (S > MC_ZERO && S_dot > MC_ZERO) || (S < MC_ZERO && S_dot < MC_ZERO);
    const mc_t gain = away ? tw->cfg.lambda_M : tw->cfg.lambda_m;
    return mc_neg(mc_mul_sgn(gain, S));
}
