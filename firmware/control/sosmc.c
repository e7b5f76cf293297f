#include "control/sosmc.h"

bool sosmc_init(sosmc_t *c, const sosmc_config_t *cfg, const motor_model_t *m)
{
    c->int_err = MC_ZERO;
    c->int_torque = MC_ZERO;
    c->s = MC_ZERO;
    c->limited = false;
    return mc_gt(m->J_kgm2, MC_ZERO) && mc_ge(m->fv_Nm_s, MC_ZERO) && mc_gt(cfg->alpha_0, MC_ZERO) &&
           mc_gt(cfg->alpha_I, MC_ZERO) && mc_ge(cfg->eta, MC_ZERO) && mc_gt(cfg->eps, MC_ZERO) &&
           mc_gt(cfg->M_max_Nm, MC_ZERO) && mc_gt(m->ts_s, MC_ZERO);
}

mc_t smc_tanh(mc_t x)
{
    /* tanh by its continued fraction to 5 levels (error below 1e-6 for
     * |x| <= 1) after halving |x| to <= 1 (at most 4 times: |x| <= 8),
     * undone with tanh 2y = 2 tanh y / (1 + tanh^2 y); beyond 8 it is +-1
     * to float32 resolution. No libm: the same in fixed point. */
    const mc_t ax = mc_abs(x);
    if (mc_gt(ax, MC_C(8.0))) {
        return mc_lt(x, MC_ZERO) ? mc_neg(MC_ONE) : MC_ONE;
    }
    int halvings = 0;
    mc_t y = ax;
    while (mc_gt(y, MC_ONE) && halvings < 4) {
        y = mc_div_i(y, 2);
        ++halvings;
    }
    /* tanh y = y / (1 + y^2 / (3 + y^2 / (5 + y^2 / (7 + y^2 / 9)))) */
    const mc_t y2 = mc_mul(y, y);
    mc_t t = mc_add(MC_C(7.0), mc_div(y2, MC_C(9.0)));
    t = mc_add(MC_C(5.0), mc_div(y2, t));
    t = mc_add(MC_C(3.0), mc_div(y2, t));
    t = mc_add(MC_ONE, mc_div(y2, t));
    t = mc_div(y, t);
    for (int k = 0; k < halvings; ++k) {
        t = mc_div(mc_mul_i(t, 2), mc_add(MC_ONE, mc_mul(t, t)));
    }
    return mc_lt(x, MC_ZERO) ? mc_neg(t) : t;
}

mc_t sosmc_step(sosmc_t *c, const sosmc_config_t *cfg, const motor_model_t *m, mc_t w_d, mc_t dw_d, mc_t w_hat,
                mc_t a_hat, mc_t M0_hat)
{
    const mc_t e = mc_sub(w_d, w_hat);     /* w~ */
    const mc_t de = mc_sub(dw_d, a_hat);   /* dw~/dt */
    /* s = dw~/dt + alpha_0 w~ + alpha_I int w~ */
    c->s = mc_mac(mc_mac(de, cfg->alpha_0, e), cfg->alpha_I, c->int_err);
    /* (27): the continuous part */
    mc_t M = mc_mul(m->J_kgm2, mc_mac(dw_d, cfg->alpha_0, e));
    M = mc_mac(M, m->fv_Nm_s, w_hat);
    if (cfg->compensate) {
        M = mc_add(M, M0_hat);
    }
    M = mc_add(M, c->int_torque);
    c->limited = mc_gt(mc_abs(M), cfg->M_max_Nm);
    const mc_t M_out = mc_clamp(M, mc_neg(cfg->M_max_Nm), cfg->M_max_Nm);
    /* (28): the integral, J (alpha_I w~ + eta tanh(s/eps)); frozen while
     * the torque is limited and the integrand would push further */
    const mc_t rate = mc_mul(m->J_kgm2, mc_mac(mc_mul(cfg->alpha_I, e), cfg->eta, smc_tanh(mc_div(c->s, cfg->eps))));
    const bool windup = c->limited && ((mc_gt(M, MC_ZERO) && mc_gt(rate, MC_ZERO)) || (mc_lt(M, MC_ZERO) && mc_lt(rate, MC_ZERO)));
    if (!windup) {
        c->int_torque = mc_mac(c->int_torque, m->ts_s, rate);
        c->int_err = mc_mac(c->int_err, m->ts_s, e);
    }
    return M_out;
}
