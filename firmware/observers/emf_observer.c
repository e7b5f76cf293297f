#include "observers/emf_observer.h"

void emf_observer_init(emf_observer_t *o, const emf_observer_config_t *cfg)
{
    o->cfg = *cfg;
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
    const mc_t sf = mc_sgn(o->err_f_A);
    const mc_t sg = mc_sgn(o->err_g_A);
    /* lower rows of chi_fg in (25): d-hat' = alpha sgn(eps), as voltages */
    o->e_f_hat_V = mc_add(o->e_f_hat_V, mc_mul(c->alpha_V, sf));
    o->e_g_hat_V = mc_add(o->e_g_hat_V, mc_mul(c->alpha_V, sg));
    /* alpha sgn_eq(eps) of (28c)-(28d): the injection through a first-order
     * low-pass (the raw one chatters at the sample rate) */
    o->z_f_V_s = mc_add(o->z_f_V_s, mc_mul(c->lpf_coeff, mc_sub(mc_mul(c->alpha_V_s, sf), o->z_f_V_s)));
    o->z_g_V_s = mc_add(o->z_g_V_s, mc_mul(c->lpf_coeff, mc_sub(mc_mul(c->alpha_V_s, sg), o->z_g_V_s)));
}

void emf_observer_predict(emf_observer_t *o, mc_t v_f_V, mc_t v_g_V, mc_t i_f_A, mc_t i_g_A, mc_rot_t half)
{
    const emf_observer_config_t *c = &o->cfg;
    /* upper rows of (25): i-hat' = A i-hat + (v - R i)/L + d-hat
     *                              + lambda |eps|^(1/2) sgn(eps) + l eps */
    const mc_t inj_f = mc_add(mc_mul(c->lambda_A, mc_sqrt_abs_sgn(o->err_f_A)), mc_mul(c->l_ts, o->err_f_A));
    const mc_t inj_g = mc_add(mc_mul(c->lambda_A, mc_sqrt_abs_sgn(o->err_g_A)), mc_mul(c->l_ts, o->err_g_A));
    /* terms carried by the full rotation: state, held voltage, injections */
    const mc_t xf = mc_add(mc_add(o->i_f_hat_A, mc_mul(c->ts_over_L_A_per_V, v_f_V)), inj_f);
    const mc_t xg = mc_add(mc_add(o->i_g_hat_A, mc_mul(c->ts_over_L_A_per_V, v_g_V)), inj_g);
    /* terms constant in the (f-g) frame: back-EMF and resistive drop */
    const mc_t bf = mc_mul(c->ts_over_L_A_per_V, mc_sub(o->e_f_hat_V, mc_mul(c->R_ohm, i_f_A)));
    const mc_t bg = mc_mul(c->ts_over_L_A_per_V, mc_sub(o->e_g_hat_V, mc_mul(c->R_ohm, i_g_A)));
    /* exp(Ts A_fg) is U(dphi): the frame turns by dphi = n_p (theta_r[k+1] - theta_r[k]) */
    const mc_rot_t full = mc_rot_double(half);
    mc_t yf, yg, hf, hg;
    mc_rot_fwd(full, xf, xg, &yf, &yg);
    mc_rot_fwd(half, bf, bg, &hf, &hg);
    o->i_f_hat_A = mc_add(yf, hf);
    o->i_g_hat_A = mc_add(yg, hg);
}
