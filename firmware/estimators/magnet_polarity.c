#include "estimators/magnet_polarity.h"

/* The rest: 8 L_d / R. The return pulse ends below zero by the R drop
 * over the pulse (about n_pulse Ts R / L_d of the peak, 3.6 A of 15 A on
 * paper 002's IPMSM); e^-8 leaves 1.2 mA of it, under a tenth of the
 * decision margin (with 5 L_d / R: 24 mA, a bias between the halves). */
#define MAGPOL_REST_TAUS 8
/* The longest pulse or rest accepted, in samples (1 s at 10 kHz). */
#define MAGPOL_MAX_SAMPLES 10000

bool magnet_polarity_design(magnet_polarity_config_t *cfg, mc_t v_p_V, mc_t i_peak_A, mc_t Ld_H, mc_t R_ohm,
                            mc_t ts_s, mc_t sigma_i_A)
{
    if (!(mc_gt(v_p_V, MC_ZERO) && mc_gt(i_peak_A, MC_ZERO) && mc_gt(Ld_H, MC_ZERO) && mc_gt(R_ohm, MC_ZERO) &&
          mc_gt(ts_s, MC_ZERO) && mc_gt(sigma_i_A, MC_ZERO))) {
        return false;
    }
    /* the samples of the pulse and of the rest, as real numbers first (no
     * integer overflow for absurd inputs) */
    const mc_t n_p = mc_div(mc_mul(i_peak_A, Ld_H), mc_mul(v_p_V, ts_s));
    const mc_t n_r = mc_div(mc_mul_i(mc_div(Ld_H, R_ohm), MAGPOL_REST_TAUS), ts_s);
    if (!mc_le(n_p, mc_from_i(MAGPOL_MAX_SAMPLES)) || !mc_le(n_r, mc_from_i(MAGPOL_MAX_SAMPLES))) {
        return false;
    }
    cfg->v_p_V = v_p_V;
    cfg->n_pulse = mc_round_i(n_p) + 1; /* at least the ceiling */
    cfg->n_rest = mc_round_i(n_r) + 1;
    cfg->margin_A = mc_mul(mc_mul(MAGPOL_MARGIN_SIGMAS, MAGPOL_DIFF_NOISE_PER_PHASE), sigma_i_A);
    return true;
}

/* A test from its first sample along the axis at theta_e_rad, nothing measured yet. */
static void magpol_begin(magnet_polarity_t *o, magpol_state_t state, mc_t theta_e_rad)
{
    o->state = state;
    o->k = 0;
    o->axis = mc_rot_from_angle(theta_e_rad);
    o->i_pos_A = MC_ZERO;
    o->i_neg_A = MC_ZERO;
    o->diff_A = MC_ZERO;
    o->result = 0;
}

void magnet_polarity_init(magnet_polarity_t *o, const magnet_polarity_config_t *cfg)
{
    o->cfg = *cfg;
    magpol_begin(o, MAGPOL_IDLE, MC_ZERO);
    o->u_V.alpha = MC_ZERO;
    o->u_V.beta = MC_ZERO;
}

void magnet_polarity_start(magnet_polarity_t *o, mc_t theta_e_rad) { magpol_begin(o, MAGPOL_RUNNING, theta_e_rad); }

void magnet_polarity_step(magnet_polarity_t *o, mc_ab_t i_A)
{
    const magnet_polarity_config_t *c = &o->cfg;
    o->u_V.alpha = MC_ZERO;
    o->u_V.beta = MC_ZERO;
    if (o->state != MAGPOL_RUNNING) {
        return;
    }
    const int32_t half = 2 * c->n_pulse + c->n_rest;
    /* the peaks over each half's window (k counts the samples measured) */
    mc_t i_d, i_q;
    mc_rot_fwd(o->axis, i_A.alpha, i_A.beta, &i_d, &i_q);
    (void)i_q;
    if (o->k > 0 && o->k <= half) {
        o->i_pos_A = mc_max(o->i_pos_A, i_d);
    } else if (o->k > half) {
        o->i_neg_A = mc_max(o->i_neg_A, mc_neg(i_d));
    }
    if (o->k >= 2 * half) {
        o->diff_A = mc_sub(o->i_pos_A, o->i_neg_A);
        o->result = mc_gt(o->diff_A, c->margin_A) ? 1 : (mc_lt(o->diff_A, mc_neg(c->margin_A)) ? -1 : 0);
        o->state = MAGPOL_DONE;
        return;
    }
    /* the voltage for the coming sample: k in [0, half) the first half
     * (+V_p, -V_p, rest), [half, 2 half) its mirror */
    const int32_t j = o->k % half;
    const int32_t s = (o->k < half) ? 1 : -1;
    mc_t v = MC_ZERO;
    if (j < c->n_pulse) {
        v = c->v_p_V;
    } else if (j < 2 * c->n_pulse) {
        v = mc_neg(c->v_p_V);
    }
    v = mc_mul_i(v, s);
    o->u_V.alpha = mc_mul(v, o->axis.c);
    o->u_V.beta = mc_mul(v, o->axis.s);
    o->k += 1;
}
