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

bool speed_profile_retarget(speed_profile_t *p, uint32_t tick, mc_t omega_to_rad_s, mc_t ramp_rad_s2)
{
    if (!mc_gt(ramp_rad_s2, MC_ZERO)) {
        return false;
    }
    speed_point_t now;
    speed_profile_eval(p, tick, &now);
    const mc_t dw = mc_sub(omega_to_rad_s, now.omega_rad_s);
    /* T = |dw|/ramp [s]: below 6553.5 s for |dw| <= 655 rad/s and a ramp
     * >= 0.1 rad/s^2 (the DBC's ranges); n = T fs as whole seconds fs
     * plus the rounded fraction */
    const mc_t T_s = mc_div(mc_abs(dw), ramp_rad_s2);
    const int32_t fs = p->cfg.fs_hz;
    const int32_t whole = mc_round_i(T_s);
    const int64_t n64 = (int64_t)whole * fs + mc_round_i(mc_mul_i(mc_sub(T_s, mc_from_i(whole)), fs));
    if (whole < 0 || n64 > (int64_t)INT32_MAX / 2) {
        return false;
    }
    const uint32_t n = n64 < 1 ? 1u : (uint32_t)n64;
    speed_profile_config_t *c = &p->cfg;
    c->n_points = 2u;
    c->t_tick[0] = tick;
    c->omega_rad_s[0] = now.omega_rad_s;
    c->theta_rad[0] = now.theta_rad;
    /* the exact length of n samples and the slope that reaches w_to in it */
    c->length_s[0] = mc_ratio_i((int32_t)n, fs);
    c->slope_rad_s2[0] = mc_div(dw, c->length_s[0]);
    c->t_tick[1] = tick + n;
    c->omega_rad_s[1] = omega_to_rad_s;
    c->slope_rad_s2[1] = MC_ZERO;
    c->length_s[1] = MC_ZERO;
    /* theta at the corner: T (w0 + w1)/2, the integral of the line */
    c->theta_rad[1] = mc_mac(now.theta_rad, c->length_s[0], mc_div_i(mc_add(now.omega_rad_s, omega_to_rad_s), 2));
    p->seg = 0;
    return true;
}
