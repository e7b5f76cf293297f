#include "estimators/emf_observer.h"

void emf_observer_init(emf_observer_t *o, const emf_observer_config_t *cfg)
{
    o->cfg = *cfg;
    o->alpha_V_now = cfg->alpha_V;
    o->alpha_V_s_now = cfg->alpha_V_s;
    emf_observer_reset(o, MC_ZERO, MC_ZERO);
}

void emf_observer_reset(emf_observer_t *o, mc_t i_f_A, mc_t i_g_A)
{
    o->i_f_hat_A = i_f_A;
    o->i_g_hat_A = i_g_A;
    o->e_f_hat_V = MC_ZERO;
    o->e_g_hat_V = MC_ZERO;
    o->z_f_V_s = MC_ZERO;
    o->z_g_V_s = MC_ZERO;
    o->err_f_A = MC_ZERO;
    o->err_g_A = MC_ZERO;
}

void emf_observer_correct(emf_observer_t *o, mc_t i_f_A, mc_t i_g_A)
{
    const emf_observer_config_t *c = &o->cfg;
    o->err_f_A = mc_sub(i_f_A, o->i_f_hat_A);
    o->err_g_A = mc_sub(i_g_A, o->i_g_hat_A);
    /* lower rows of chi_fg in (25): d-hat' = alpha sgn(eps), as voltages */
    o->e_f_hat_V = mc_add(o->e_f_hat_V, mc_mul_sgn(o->alpha_V_now, o->err_f_A));
    o->e_g_hat_V = mc_add(o->e_g_hat_V, mc_mul_sgn(o->alpha_V_now, o->err_g_A));
    /* alpha sgn_eq(eps) of (28c)-(28d): the injection through a first-order
     * low-pass (the raw one chatters at the sample rate) */
    o->z_f_V_s = mc_mac(o->z_f_V_s, c->lpf_coeff, mc_sub(mc_mul_sgn(o->alpha_V_s_now, o->err_f_A), o->z_f_V_s));
    o->z_g_V_s = mc_mac(o->z_g_V_s, c->lpf_coeff, mc_sub(mc_mul_sgn(o->alpha_V_s_now, o->err_g_A), o->z_g_V_s));
}

void emf_observer_predict(emf_observer_t *o, const motor_model_t *m, mc_t v_f_V, mc_t v_g_V, mc_t i_f_A, mc_t i_g_A,
                          mc_rot_t half)
{
    const emf_observer_config_t *c = &o->cfg;
    /* upper rows of (25): i-hat' = A i-hat + (v - R i)/L + d-hat
     *                              + lambda |eps|^(1/2) sgn(eps) + l eps,
     * over one sample: exp(Ts A_fg) = U(dphi) is applied as two half turns,
     * the state and the injections before the first, the held voltage
     * (given in the mid-sample frame, where it is exact), back-EMF and
     * resistive drop (constant in (f-g)) between the two. */
    const mc_t xf = mc_add(o->i_f_hat_A, mc_dot2(c->lambda_A, mc_sqrt_abs_sgn(o->err_f_A), c->l_ts, o->err_f_A));
    const mc_t xg = mc_add(o->i_g_hat_A, mc_dot2(c->lambda_A, mc_sqrt_abs_sgn(o->err_g_A), c->l_ts, o->err_g_A));
    mc_t yf, yg;
    mc_rot_fwd(half, xf, xg, &yf, &yg);
    const mc_t uf = mc_cross2(MC_ONE, mc_add(v_f_V, o->e_f_hat_V), m->R_ohm, i_f_A);
    const mc_t ug = mc_cross2(MC_ONE, mc_add(v_g_V, o->e_g_hat_V), m->R_ohm, i_g_A);
    mc_rot_fwd(half, mc_mac(yf, m->ts_over_L_A_per_V, uf), mc_mac(yg, m->ts_over_L_A_per_V, ug), &o->i_f_hat_A,
               &o->i_g_hat_A);
}
