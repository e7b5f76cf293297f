#include "trajectory/speed_profile.h"

bool speed_profile_init(speed_profile_t *p, const speed_profile_config_t *cfg)
{
    p->cfg = *cfg;
    p->seg = 0;
    if (cfg->n_points < 1u || cfg->n_points > SPEED_PROFILE_MAX_POINTS || cfg->t_tick[0] != 0u || cfg->fs_hz <= 0) {
        return false;
    }
    for (uint32_t k = 1; k < cfg->n_points; ++k) {
        if (cfg->t_tick[k] <= cfg->t_tick[k - 1u]) {
            return false;
        }
    }
    return true;
}

void speed_profile_eval(speed_profile_t *p, uint32_t tick, speed_point_t *out)
{
    const speed_profile_config_t *c = &p->cfg;
    const uint32_t last = c->n_points - 1u;
    while (p->seg < last && tick >= c->t_tick[p->seg + 1u]) {
        p->seg += 1u;
    }
    const uint32_t k = p->seg;
    if (k == last) {
        /* held after the last corner */
        out->omega_rad_s = c->omega_rad_s[k];
        out->accel_rad_s2 = MC_ZERO;
        const int32_t n = (int32_t)(tick - c->t_tick[k]);
        out->theta_rad = mc_mac(c->theta_rad[k], c->omega_rad_s[k], mc_ratio_i(n, c->fs_hz));
        return;
    }
    const mc_t dw = mc_sub(c->omega_rad_s[k + 1u], c->omega_rad_s[k]);
    const mc_t x = mc_ratio_i((int32_t)(tick - c->t_tick[k]), (int32_t)(c->t_tick[k + 1u] - c->t_tick[k]));
    out->omega_rad_s = mc_mac(c->omega_rad_s[k], dw, x);
    out->accel_rad_s2 = c->slope_rad_s2[k];
    /* theta_k + T_k x (w_k + dw x/2) */
    const mc_t mean = mc_mac(c->omega_rad_s[k], mc_div_i(dw, 2), x);
    out->theta_rad = mc_mac(c->theta_rad[k], mc_mul(c->length_s[k], x), mean);
}
