#include "control/foc_current.h"

bool foc_current_init(foc_current_t *c, const foc_current_config_t *cfg)
{
    c->cfg = *cfg;
    c->saturated = false;
    const bool pi_ok = pi_ctrl_init(&c->d, &cfg->pi_d) && pi_ctrl_init(&c->q, &cfg->pi_q);
    return pi_ok && mc_gt(cfg->L_d_H, MC_ZERO) && mc_gt(cfg->L_q_H, MC_ZERO) && mc_ge(cfg->psi_Wb, MC_ZERO);
}

void foc_current_step(foc_current_t *c, mc_t i_d_ref_A, mc_t i_q_ref_A, mc_t i_d_A, mc_t i_q_A, mc_t w_e_rad_s,
                      mc_t u_max_V, mc_t *v_d_V, mc_t *v_q_V)
{
    const foc_current_config_t *k = &c->cfg;
    /* the header's equations: the coupling fed forward, d first */
    const mc_t ff_d = mc_neg(mc_mul(w_e_rad_s, mc_mul(k->L_q_H, i_q_A)));
    const mc_t v_d = pi_ctrl_step(&c->d, mc_sub(i_d_ref_A, i_d_A), ff_d, u_max_V);
    const mc_t u_q_max = mc_sqrt(mc_sub(mc_mul(u_max_V, u_max_V), mc_mul(v_d, v_d)));
    const mc_t ff_q = mc_mul(w_e_rad_s, mc_mac(k->psi_Wb, k->L_d_H, i_d_A));
    *v_q_V = pi_ctrl_step(&c->q, mc_sub(i_q_ref_A, i_q_A), ff_q, u_q_max);
    *v_d_V = v_d;
    c->saturated = c->d.saturated || c->q.saturated;
}
