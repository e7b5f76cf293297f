#include "control/ibcc.h"

bool ibcc_init(ibcc_t *s, const ibcc_config_t *c, const motor_model_t *m)
{
    s->i_dd_prev_A = MC_ZERO;
    s->i_qd_prev_A = MC_ZERO;
    s->first = true;
    s->saturated = false;
    return mc_gt(m->Ld_H, MC_ZERO) && mc_gt(m->Lq_H, MC_ZERO) && mc_ge(m->R_ohm, MC_ZERO) && m->fs_hz > 0 &&
           mc_gt(c->lambda_per_s, MC_ZERO) && !mc_gt(mc_div_i(c->lambda_per_s, m->fs_hz), IBCC_LAMBDA_TS_MAX) &&
           mc_gt(c->ref_alpha, MC_ZERO) && !mc_gt(c->ref_alpha, MC_ONE);
}

void ibcc_step(ibcc_t *s, const ibcc_config_t *c, const motor_model_t *m, mc_t i_dd_A, mc_t i_qd_A, mc_t i_d_A,
               mc_t i_q_A, mc_t w_hat_rad_s, mc_t u_max_V, ibcc_out_t *out)
{
    /* the filtered references and their change over the sample */
    if (s->first) {
        s->i_dd_prev_A = i_dd_A;
        s->i_qd_prev_A = i_qd_A;
        s->first = false;
    }
    const mc_t step_d = mc_mul(c->ref_alpha, mc_sub(i_dd_A, s->i_dd_prev_A));
    const mc_t step_q = mc_mul(c->ref_alpha, mc_sub(i_qd_A, s->i_qd_prev_A));
    i_dd_A = mc_add(s->i_dd_prev_A, step_d);
    i_qd_A = mc_add(s->i_qd_prev_A, step_q);
    s->i_dd_prev_A = i_dd_A;
    s->i_qd_prev_A = i_qd_A;
    const mc_t did = mc_mul_i(step_d, m->fs_hz);
    const mc_t diq = mc_mul_i(step_q, m->fs_hz);
    const mc_t w_el = mc_mul_i(w_hat_rad_s, m->n_p);
    /* (9) with (3)'s u_p */
    mc_t ud = mc_mul(m->Ld_H, mc_mac(did, c->lambda_per_s, mc_sub(i_dd_A, i_d_A)));
    ud = mc_mac(ud, m->R_ohm, i_d_A);
    ud = mc_sub(ud, mc_mul(mc_mul(m->Lq_H, w_el), i_q_A));
    mc_t uq = mc_mul(m->Lq_H, mc_mac(diq, c->lambda_per_s, mc_sub(i_qd_A, i_q_A)));
    uq = mc_mac(uq, m->R_ohm, i_q_A);
    uq = mc_add(uq, mc_mul(w_el, mc_mac(m->psi_Wb, m->Ld_H, i_d_A)));
    /* the bus's limit, the direction kept */
    const mc_t mag = mc_hypot(ud, uq);
    s->saturated = mc_gt(mag, u_max_V);
    if (s->saturated) {
        const mc_t k = mc_div(u_max_V, mag);
        ud = mc_mul(ud, k);
        uq = mc_mul(uq, k);
    }
    out->u_d_V = ud;
    out->u_q_V = uq;
}
