#include "estimators/position_estimator.h"

void position_estimator_init(position_estimator_t *p, const position_estimator_config_t *cfg)
{
    p->cfg = *cfg;
    p->cfg.half_pitch_rad = mc_div_i(cfg->pitch_rad, 2);
    p->cfg.inv_n_p = mc_ratio_i(1, cfg->n_p);
    p->dtheta_prev_rad = MC_ZERO;
    p->k = 0;
    p->valid = false;
    p->dtheta_est_rad = MC_ZERO;
    p->theta_est_rad = MC_ZERO;
    p->omega_est_rad_s = MC_ZERO;
    p->e2_V2 = MC_ZERO;
}

mc_t position_estimator_angle(const position_estimator_t *p, mc_t e_f_V, mc_t e_g_V, mc_t omega_r_rad_s)
{
    /* eq. (29) (errata form): the sign of the speed is taken from the reference */
    const bool neg = mc_lt(omega_r_rad_s, MC_ZERO);
    const mc_t y = neg ? mc_neg(e_f_V) : e_f_V;
    const mc_t x = neg ? e_g_V : mc_neg(e_g_V);
    return mc_mul(mc_atan2(y, x), p->cfg.inv_n_p);
}

void position_estimator_track(position_estimator_t *p, mc_t e_f_V, mc_t e_g_V, mc_t theta_r_rad, mc_t omega_r_rad_s)
{
    const position_estimator_config_t *c = &p->cfg;
    const mc_t dth = p->valid ? position_estimator_angle(p, e_f_V, e_g_V, omega_r_rad_s) : p->dtheta_prev_rad;

    /* eq. (71): a step of more than half a pitch is a wrap of the arctan */
    const mc_t step = mc_sub(dth, p->dtheta_prev_rad);
    if (mc_lt(step, mc_neg(c->half_pitch_rad))) {
        p->k += 1;
    } else if (mc_gt(step, c->half_pitch_rad)) {
        p->k -= 1;
    }
    p->dtheta_prev_rad = dth;
    p->dtheta_est_rad = dth;
    p->theta_est_rad = mc_add(mc_add(theta_r_rad, dth), mc_mul_i(c->pitch_rad, p->k));
}

void position_estimator_speed(position_estimator_t *p, mc_t e_f_V, mc_t e_g_V, mc_t z_f_V_s, mc_t z_g_V_s,
                              mc_t omega_r_rad_s)
{
    /* eqs. (31)-(32) */
    mc_t dw = MC_ZERO;
    if (p->valid) {
        const mc_t num = mc_cross2(z_g_V_s, e_f_V, z_f_V_s, e_g_V);
        /* divide by n_p first: e2 * n_p would leave the fixed-point range at speed */
        dw = mc_div(mc_div_i(num, p->cfg.n_p), p->e2_V2);
    }
    p->omega_est_rad_s = mc_add(omega_r_rad_s, dw);
}

void position_estimator_set_branch(position_estimator_t *p, mc_t theta_r_rad, mc_t theta_near_rad)
{
    const mc_t off = mc_sub(theta_near_rad, mc_add(theta_r_rad, p->dtheta_est_rad));
    p->k = mc_round_i(mc_div(off, p->cfg.pitch_rad));
    p->theta_est_rad = mc_add(mc_add(theta_r_rad, p->dtheta_est_rad), mc_mul_i(p->cfg.pitch_rad, p->k));
}
