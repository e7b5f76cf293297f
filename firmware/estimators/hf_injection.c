#include "estimators/hf_injection.h"

bool hf_injection_design(hf_injection_config_t *cfg, mc_t Ld_H, mc_t Lq_H, mc_t ts_s, mc_t v_h_V, mc_t wn_rad_s,
                         mc_t delay)
{
    if (!(mc_gt(Ld_H, MC_ZERO) && mc_lt(Ld_H, Lq_H) && mc_gt(ts_s, MC_ZERO) && mc_gt(v_h_V, MC_ZERO) &&
          mc_gt(wn_rad_s, MC_ZERO) && mc_lt(mc_mul(wn_rad_s, ts_s), HF_INJ_MAX_WN_TS) && mc_ge(delay, MC_ZERO) &&
          mc_le(delay, MC_ONE))) {
        return false;
    }
    /* g = 1 - 2 d (header) */
    const mc_t g = mc_sub(MC_ONE, mc_mul_i(delay, 2));
    if (mc_lt(mc_abs(g), HF_INJ_MIN_DELAY_GAIN)) {
        return false;
    }
    const mc_t gvt = mc_mul(mc_mul(g, v_h_V), ts_s);
    /* (H4): 1 / (g V_h Ts (1/L_d - 1/L_q) / 2) */
    const mc_t dinv = mc_sub(mc_div(MC_ONE, Ld_H), mc_div(MC_ONE, Lq_H));
    cfg->ts_s = ts_s;
    cfg->v_h_V = v_h_V;
    cfg->eps_gain_per_A = mc_div(MC_C(2.0), mc_mul(gvt, dinv));
    /* (H1) at e = 0 is g V_h Ts / L_d */
    cfg->amp_gain_per_A = mc_div(Ld_H, gvt);
    /* (H6), zeta = 1 */
    cfg->kp_per_s = mc_mul_i(wn_rad_s, 2);
    cfg->ki_per_s = mc_mul(mc_mul(wn_rad_s, wn_rad_s), ts_s);
    cfg->lead_s = mc_mul(mc_add(MC_C(0.5), delay), ts_s);
    cfg->delay = delay;
    cfg->ts_over_Ld_A_per_V = mc_div(ts_s, Ld_H);
    cfg->ts_over_Lq_A_per_V = mc_div(ts_s, Lq_H);
    return true;
}

void hf_injection_init(hf_injection_t *o, const hf_injection_config_t *cfg, mc_t theta_e_rad)
{
    const mc_ab_t z = {MC_ZERO, MC_ZERO};
    o->cfg = *cfg;
    o->i1_A = z;
    o->i2_A = z;
    o->di1_A = z;
    o->uf1_V = z;
    o->uf2_V = z;
    o->uf3_V = z;
    o->theta_e_rad = mc_wrap_pi(theta_e_rad);
    o->theta_inj_rad = o->theta_e_rad;
    o->rot_inj = mc_rot_from_angle(o->theta_e_rad);
    o->theta_raw_e_rad = o->theta_e_rad;
    o->omega_e_rad_s = MC_ZERO;
    o->sign = -1;
    o->n = 0;
    o->on = false;
    o->stopping = false;
    o->uh1_V = z;
    o->r_A = z;
    o->r1_A = z;
    o->r2_A = z;
    o->u_h_amp_V = MC_ZERO;
    o->eps = MC_ZERO;
    o->amp = MC_ZERO;
    o->i_f_A = z;
    o->u_h_V = z;
}

void hf_injection_set_on(hf_injection_t *o, bool on)
{
    if (on && !o->on) {
        o->n = 0;
    }
    /* switched on again before the stop pulse: no stop pulse, a first one */
    o->stopping = !on && (o->on || o->stopping);
    o->on = on;
}

void hf_injection_track(hf_injection_t *o, mc_t theta_e_rad, mc_t omega_e_rad_s)
{
    if (!o->on) {
        o->theta_e_rad = mc_wrap_pi(theta_e_rad);
        o->omega_e_rad_s = omega_e_rad_s;
    }
}

void hf_injection_hold(hf_injection_t *o, mc_ab_t u_f_V)
{
    o->uf3_V = o->uf2_V;
    o->uf2_V = o->uf1_V;
    o->uf1_V = u_f_V;
}

/* The fundamental voltage over the sample that ends now, (1 - d) u_{k-1} +
 * d u_{k-2}, minus the one over the sample before. */
static mc_ab_t hf_voltage_change(const hf_injection_t *o)
{
    const mc_t d = o->cfg.delay;
    const mc_t a1 = mc_add(o->uf1_V.alpha, mc_mul(d, mc_sub(o->uf2_V.alpha, o->uf1_V.alpha)));
    const mc_t b1 = mc_add(o->uf1_V.beta, mc_mul(d, mc_sub(o->uf2_V.beta, o->uf1_V.beta)));
    const mc_t a2 = mc_add(o->uf2_V.alpha, mc_mul(d, mc_sub(o->uf3_V.alpha, o->uf2_V.alpha)));
    const mc_t b2 = mc_add(o->uf2_V.beta, mc_mul(d, mc_sub(o->uf3_V.beta, o->uf2_V.beta)));
    const mc_ab_t dv = {mc_sub(a1, a2), mc_sub(b1, b2)};
    return dv;
}

void hf_injection_step(hf_injection_t *o, mc_ab_t i_A)
{
    const hf_injection_config_t *c = &o->cfg;
    /* Delta i_k */
    const mc_ab_t di = {mc_sub(i_A.alpha, o->i1_A.alpha), mc_sub(i_A.beta, o->i1_A.beta)};
    /* (H8): the triangle's model at this sample, from the injection over
     * the sample that ends now ((1 - d) of the last command, d of the one
     * before); exactly zero once neither acts */
    const mc_t d = c->delay;
    const mc_ab_t uh = {mc_add(o->u_h_V.alpha, mc_mul(d, mc_sub(o->uh1_V.alpha, o->u_h_V.alpha))),
                        mc_add(o->u_h_V.beta, mc_mul(d, mc_sub(o->uh1_V.beta, o->u_h_V.beta)))};
    o->r2_A = o->r1_A;
    o->r1_A = o->r_A;
    if (mc_eq(o->u_h_amp_V, MC_ZERO) && mc_eq(o->uh1_V.alpha, MC_ZERO) && mc_eq(o->uh1_V.beta, MC_ZERO)) {
        o->r_A.alpha = MC_ZERO;
        o->r_A.beta = MC_ZERO;
    } else {
        o->r_A.alpha = mc_mac(o->r_A.alpha, c->ts_over_Ld_A_per_V, uh.alpha);
        o->r_A.beta = mc_mac(o->r_A.beta, c->ts_over_Ld_A_per_V, uh.beta);
    }
    o->uh1_V = o->u_h_V;
    /* (H5) on the current less (H8): the current without the injection's
     * part */
    const mc_ab_t c0 = {mc_sub(i_A.alpha, o->r_A.alpha), mc_sub(i_A.beta, o->r_A.beta)};
    const mc_ab_t c1 = {mc_sub(o->i1_A.alpha, o->r1_A.alpha), mc_sub(o->i1_A.beta, o->r1_A.beta)};
    const mc_ab_t c2 = {mc_sub(o->i2_A.alpha, o->r2_A.alpha), mc_sub(o->i2_A.beta, o->r2_A.beta)};
    o->i_f_A.alpha = mc_div_i(mc_sub(mc_add(mc_mul_i(c0.alpha, 3), mc_mul_i(c1.alpha, 2)), c2.alpha), 4);
    o->i_f_A.beta = mc_div_i(mc_sub(mc_add(mc_mul_i(c0.beta, 3), mc_mul_i(c1.beta, 2)), c2.beta), 4);
    if (o->on && o->n >= HF_INJ_WARMUP_SAMPLES) {
        /* (H3): s_{k-1} (Delta i_k - Delta i_{k-1}) / 2, into the frame of
         * the injection it answers */
        mc_t h_d, h_q, dv_d, dv_q;
        mc_rot_fwd(o->rot_inj, mc_sub(di.alpha, o->di1_A.alpha), mc_sub(di.beta, o->di1_A.beta), &h_d, &h_q);
        const mc_ab_t dv = hf_voltage_change(o);
        mc_rot_fwd(o->rot_inj, dv.alpha, dv.beta, &dv_d, &dv_q);
        h_d = mc_div_i(mc_mul_i(mc_sub(h_d, mc_mul(c->ts_over_Ld_A_per_V, dv_d)), o->sign), 2);
        h_q = mc_div_i(mc_mul_i(mc_sub(h_q, mc_mul(c->ts_over_Lq_A_per_V, dv_q)), o->sign), 2);
        /* (H4), limited to the range of sin 2e */
        o->eps = mc_clamp(mc_mul(h_q, c->eps_gain_per_A), mc_neg(MC_ONE), MC_ONE);
        o->amp = mc_mul(h_d, c->amp_gain_per_A);
        /* (H6) on e_hat = eps / 2 */
        const mc_t e = mc_div_i(o->eps, 2);
        /* (H7) */
        o->theta_raw_e_rad = mc_wrap_pi(mc_add(o->theta_inj_rad, e));
        o->omega_e_rad_s = mc_mac(o->omega_e_rad_s, c->ki_per_s, e);
        o->theta_e_rad = mc_wrap_pi(mc_mac(o->theta_e_rad, c->ts_s, mc_mac(o->omega_e_rad_s, c->kp_per_s, e)));
    } else if (o->on) {
        /* warm-up: the PLL coasts on its speed */
        o->theta_e_rad = mc_wrap_pi(mc_mac(o->theta_e_rad, c->ts_s, o->omega_e_rad_s));
        o->theta_raw_e_rad = o->theta_e_rad;
    } else {
        o->theta_raw_e_rad = o->theta_e_rad;
    }
    o->i2_A = o->i1_A;
    o->i1_A = i_A;
    o->di1_A = di;
    /* the injection for the coming sample along the estimated d axis,
     * advanced to the middle of the sample it acts over */
    if (o->on) {
        o->theta_inj_rad = mc_wrap_pi(mc_mac(o->theta_e_rad, c->lead_s, o->omega_e_rad_s));
        o->rot_inj = mc_rot_from_angle(o->theta_inj_rad);
        o->sign = -o->sign;
        /* the first: half an amplitude, so the triangle is centred */
        const mc_t v = (o->n == 0) ? mc_div_i(c->v_h_V, 2) : c->v_h_V;
        const mc_t vs = (o->sign > 0) ? v : mc_neg(v);
        o->u_h_V.alpha = mc_mul(vs, o->rot_inj.c);
        o->u_h_V.beta = mc_mul(vs, o->rot_inj.s);
        o->u_h_amp_V = v;
        if (o->n < HF_INJ_WARMUP_SAMPLES) {
            o->n += 1;
        }
    } else if (o->stopping) {
        /* the stop pulse: half an amplitude against the last, along the
         * last injection's axis (H8) */
        o->sign = -o->sign;
        const mc_t v = mc_div_i(c->v_h_V, 2);
        const mc_t vs = (o->sign > 0) ? v : mc_neg(v);
        o->u_h_V.alpha = mc_mul(vs, o->rot_inj.c);
        o->u_h_V.beta = mc_mul(vs, o->rot_inj.s);
        o->u_h_amp_V = v;
        o->stopping = false;
        o->eps = MC_ZERO;
    } else {
        o->u_h_V.alpha = MC_ZERO;
        o->u_h_V.beta = MC_ZERO;
        o->u_h_amp_V = MC_ZERO;
        o->theta_inj_rad = o->theta_e_rad;
        o->rot_inj = mc_rot_from_angle(o->theta_e_rad);
        o->eps = MC_ZERO;
    }
}
