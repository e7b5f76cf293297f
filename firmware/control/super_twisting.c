#include "control/super_twisting.h"

void super_twisting_init(super_twisting_t *st, const super_twisting_config_t *cfg)
{
    st->cfg = *cfg;
    st->u1 = MC_ZERO;
}

void super_twisting_reset(super_twisting_t *st, mc_t u1) { st->u1 = u1; }

mc_t super_twisting_step(super_twisting_t *st, mc_t S, bool hold_integral)
{
    const mc_t u = mc_sub(st->u1, mc_mul(st->cfg.lambda, mc_sqrt_abs_sgn(S)));
    if (!hold_integral) {
        st->u1 = mc_clamp(mc_sub(st->u1, mc_mul_sgn(st->cfg.alpha_ts, S)), mc_neg(st->cfg.u1_max), st->cfg.u1_max);
    }
    return u;
}
