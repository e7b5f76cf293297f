#include "control/foc_current.h"

bool foc_current_init(foc_current_t *c, const foc_current_config_t *cfg, const motor_model_t *m)
{
    c->cfg = *cfg;
    c->v_d_V = MC_ZERO;
    c->v_q_V = MC_ZERO;
    c->saturated = false;
    const bool pi_ok = pi_ctrl_init(&c->d, &cfg->pi_d) && pi_ctrl_init(&c->q, &cfg->pi_q);
    return pi_ok && mc_gt(m->Ld_H, MC_ZERO) && mc_gt(m->Lq_H, MC_ZERO) && mc_ge(m->psi_Wb, MC_ZERO);
}

void foc_current_step(foc_current_t *c, const motor_model_t *m, mc_t i_d_ref_A, mc_t i_q_ref_A, mc_t i_d_A, mc_t i_q_A,
                      mc_t w_e_rad_s, mc_t u_max_V)
{
    /* the header's equations: the coupling fed forward (both terms before
     * the loops run: the motor is not needed after), d first */
    const mc_t ff_d = mc_neg(mc_mul(w_e_rad_s, mc_mul(m->Lq_H, i_q_A)));
    const mc_t ff_q = mc_mul(w_e_rad_s, mc_mac(m->psi_Wb, m->Ld_H, i_d_A));
    const mc_t v_d = pi_ctrl_step(&c->d, mc_sub(i_d_ref_A, i_d_A), ff_d, u_max_V);
    const mc_t u_q_max = mc_sqrt(mc_sub(mc_mul(u_max_V, u_max_V), mc_mul(v_d, v_d)));
    c->v_q_V = pi_ctrl_step(&c->q, mc_sub(i_q_ref_A, i_q_A), ff_q, u_q_max);
    c->v_d_V = v_d;
    c->saturated = c->d.saturated || c->q.saturated;
}
