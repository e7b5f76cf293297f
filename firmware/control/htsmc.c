#include "control/htsmc.h"

#include "control/sosmc.h" /* smc_tanh */

bool htsmc_init(htsmc_t *c, const htsmc_config_t *cfg, const motor_model_t *m)
{
    c->int_err = MC_ZERO;
    c->nu1 = MC_ZERO;
    c->s = MC_ZERO;
    c->s_prev = MC_ZERO;
    c->first = true;
    return mc_gt(m->J_kgm2, MC_ZERO) && mc_ge(m->fv_Nm_s, MC_ZERO) && mc_gt(cfg->alpha_I, MC_ZERO) &&
           mc_gt(cfg->alpha_m, MC_ZERO) && mc_gt(cfg->alpha_M, cfg->alpha_m) && mc_gt(cfg->lambda, MC_ZERO) &&
           mc_gt(cfg->rho, MC_ZERO) && !mc_gt(cfg->rho, MC_C(0.5)) && mc_gt(cfg->s0, MC_ZERO) &&
           mc_gt(cfg->nu_max, MC_ZERO) && mc_gt(cfg->eps, MC_ZERO) && mc_gt(cfg->M_max_Nm, MC_ZERO) &&
           mc_gt(m->ts_s, MC_ZERO);
}

/* |x|^rho by square roots, no libm: rho = 1/2 (sqrt) or 1/4 (sqrt of
 * sqrt), the exponents the design uses; htsmc_init accepts rho in
 * (0, 1/2] and rounds anything below 3/8 to 1/4. */
static mc_t pow_rho(mc_t x, mc_t rho)
{
    const mc_t r = mc_sqrt(x);
    return mc_lt(rho, MC_C(0.375)) ? mc_sqrt(r) : r;
}

mc_t htsmc_step(htsmc_t *c, const htsmc_config_t *cfg, const motor_model_t *m, mc_t w_d, mc_t dw_d, mc_t w_hat,
                mc_t M0_hat)
{
    const mc_t e = mc_sub(w_d, w_hat);
    c->s = mc_mac(e, cfg->alpha_I, c->int_err);
    const mc_t ds = c->first ? MC_ZERO : mc_div(mc_sub(c->s, c->s_prev), m->ts_s);
    c->first = false;
    c->s_prev = c->s;
    const mc_t sgn = smc_tanh(mc_div(c->s, cfg->eps));
    /* nu_2: -lambda |s|^rho sign(s), |s| capped at s0 */
    const mc_t as = mc_min(mc_abs(c->s), cfg->s0);
    const mc_t nu2 = mc_neg(mc_mul(mc_mul(cfg->lambda, pow_rho(as, cfg->rho)), sgn));
    const mc_t nu = mc_add(c->nu1, nu2);
    /* (35): the twisting part's rate */
    mc_t dnu1;
    if (mc_gt(mc_abs(nu), cfg->nu_max)) {
        dnu1 = mc_neg(nu);
    } else if (!mc_gt(mc_mul(c->s, ds), MC_ZERO)) {
        dnu1 = mc_neg(mc_mul(cfg->alpha_m, sgn));
    } else {
        dnu1 = mc_neg(mc_mul(cfg->alpha_M, sgn));
    }
    /* (29), (30) */
    mc_t M = mc_mul(m->J_kgm2, mc_mac(dw_d, cfg->alpha_I, e));
    M = mc_mac(M, m->fv_Nm_s, w_hat);
    if (cfg->compensate) {
        M = mc_add(M, M0_hat);
    }
    M = mc_sub(M, mc_mul(m->J_kgm2, nu));
    c->nu1 = mc_mac(c->nu1, m->ts_s, dnu1);
    c->int_err = mc_mac(c->int_err, m->ts_s, e);
    return mc_clamp(M, mc_neg(cfg->M_max_Nm), cfg->M_max_Nm);
}
