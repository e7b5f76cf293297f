#include "estimators/flux_observer.h"

/* rho = (w - (L/Ts) i) (2^-s) (2^s Ts/Phi), eqs. (13)-(14) in w units */
static mc_t flux_observer_rho(const flux_observer_config_t *c, mc_t w, mc_t i)
{
    return mc_mul(mc_mul(mc_sub(w, mc_mul(c->L_fs_ohm, i)), c->rho_pre), c->rho_gain);
}

static void flux_observer_eval(flux_observer_t *o, mc_ab_t i_A)
{
    const flux_observer_config_t *c = &o->cfg;
    o->rho.alpha = flux_observer_rho(c, o->w_V.alpha, i_A.alpha);
    o->rho.beta = flux_observer_rho(c, o->w_V.beta, i_A.beta);
    o->rho2 = mc_dot2(o->rho.alpha, o->rho.alpha, o->rho.beta, o->rho.beta);
    /* unit vector; rho = 0 (never reached: |rho| is pulled to 1) keeps the last */
    if (mc_gt(o->rho2, MC_ZERO)) {
        const mc_t k = mc_rsqrt(o->rho2);
        o->unit.c = mc_mul(o->rho.alpha, k);
        o->unit.s = mc_mul(o->rho.beta, k);
    }
    o->i_prev_A = i_A;
}

void flux_observer_init(flux_observer_t *o, const flux_observer_config_t *cfg, mc_rot_t angle0, mc_ab_t i0_A)
{
    o->cfg = *cfg;
    /* w = (L i0 + Phi rho0)/Ts */
    o->w_V.alpha = mc_add(mc_mul(cfg->L_fs_ohm, i0_A.alpha), mc_mul(cfg->Phi_fs_V, angle0.c));
    o->w_V.beta = mc_add(mc_mul(cfg->L_fs_ohm, i0_A.beta), mc_mul(cfg->Phi_fs_V, angle0.s));
    o->v_prev_V.alpha = MC_ZERO;
    o->v_prev_V.beta = MC_ZERO;
    o->unit = angle0;
    o->gradient_on = true;
    o->rho2_target = MC_ONE;
    flux_observer_eval(o, i0_A);
}

void flux_observer_seed(flux_observer_t *o, mc_rot_t angle, mc_ab_t i_A, mc_t radius)
{
    const flux_observer_config_t *c = &o->cfg;
    /* w = (L i + r Phi (cos, sin))/Ts, (14) solved for lambda_hat */
    const mc_t r_fs = mc_mul(c->Phi_fs_V, radius);
    o->w_V.alpha = mc_add(mc_mul(c->L_fs_ohm, i_A.alpha), mc_mul(r_fs, angle.c));
    o->w_V.beta = mc_add(mc_mul(c->L_fs_ohm, i_A.beta), mc_mul(r_fs, angle.s));
    o->unit = angle;
    flux_observer_eval(o, i_A);
}

void flux_observer_step(flux_observer_t *o, mc_ab_t i_A)
{
    const flux_observer_config_t *c = &o->cfg;
    /* (12) over [k-1, k]: gradient term at the start of the sample */
    const mc_t grad = o->gradient_on ? mc_mul(c->gPhi3_V, mc_sub(o->rho2_target, o->rho2)) : MC_ZERO;
    /* v - R (i[k-1] + i[k])/2 */
    const mc_t ia_mid = mc_div_i(mc_add(o->i_prev_A.alpha, i_A.alpha), 2);
    const mc_t ib_mid = mc_div_i(mc_add(o->i_prev_A.beta, i_A.beta), 2);
    o->w_V.alpha = mc_add(o->w_V.alpha, mc_mac(mc_sub(o->v_prev_V.alpha, mc_mul(c->R_ohm, ia_mid)), grad, o->rho.alpha));
    o->w_V.beta = mc_add(o->w_V.beta, mc_mac(mc_sub(o->v_prev_V.beta, mc_mul(c->R_ohm, ib_mid)), grad, o->rho.beta));
    flux_observer_eval(o, i_A);
}

void flux_observer_shift(flux_observer_t *o, mc_ab_t c)
{
    o->w_V.alpha = mc_sub(o->w_V.alpha, mc_mul(o->cfg.Phi_fs_V, c.alpha));
    o->w_V.beta = mc_sub(o->w_V.beta, mc_mul(o->cfg.Phi_fs_V, c.beta));
    flux_observer_eval(o, o->i_prev_A);
}
