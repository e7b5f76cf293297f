#include "trajectory/trajectory.h"

/* eq. (70) with the errata coefficients, p(D) = 35D^4 - 84D^5 + 70D^6 - 20D^7,
 * written around the middle of the move, x = D - 1/2, u = D(1 - D) = 1/4 - x^2:
 *   p    = 1/2 + x (35/16 - x^2 (35/4 - x^2 (21 - 20 x^2)))
 *   p'   = 140 u^3
 *   p''  = 420 u^2 (1 - 2D) = -840 x u^2
 *   p''' = 840 u (1 - 5u)                        (1 - 5D + 5D^2 = 1 - 5u)
 * so that the derivatives need no power of D beyond u^3 and no cancellation. */
void trajectory_poly7(mc_t D, mc_t *p, mc_t *dp, mc_t *ddp, mc_t *dddp)
{
    const mc_t x = mc_sub(D, MC_C(0.5));
    const mc_t x2 = mc_mul(x, x);
    const mc_t u = mc_sub(MC_C(0.25), x2);
    mc_t g = mc_sub(MC_C(21.0), mc_mul_i(x2, 20));
    g = mc_sub(MC_C(8.75), mc_mul(x2, g));
    g = mc_sub(MC_C(2.1875), mc_mul(x2, g));
    *p = mc_mac(MC_C(0.5), x, g);
    *dp = mc_mul(mc_mul(mc_mul_i(u, 140), u), u);
    *ddp = mc_mul(mc_mul(mc_mul_i(x, -840), u), u);
    *dddp = mc_mul(mc_mul_i(u, 840), mc_sub(MC_ONE, mc_mul_i(u, 5)));
}

bool trajectory_init(trajectory_t *t, const trajectory_config_t *cfg)
{
    if (cfg->n_segments < 0 || cfg->n_segments > TRAJECTORY_MAX_SEGMENTS || cfg->fs_hz <= 0) {
        return false;
    }
    t->cfg = *cfg;
    mc_t from = cfg->theta_start_rad;
    uint32_t prev_end = 0;
    for (int32_t i = 0; i < cfg->n_segments; ++i) {
        trajectory_segment_t *s = &t->cfg.seg[i];
        if (s->duration_ticks == 0 || s->duration_ticks > (uint32_t)INT32_MAX / 2u || s->start_tick < prev_end) {
            return false;
        }
        t->theta_from_rad[i] = from;
        const mc_t delta = mc_sub(s->theta_to_rad, from);
        if (mc_eq(s->v_scale, MC_ZERO) && mc_eq(s->a_scale, MC_ZERO) && mc_eq(s->j_scale, MC_ZERO)) {
            /* (theta_f - theta_i)/T^n; T = duration_ticks / fs_hz */
            const mc_t T_s = mc_ratio_i((int32_t)s->duration_ticks, cfg->fs_hz);
            s->v_scale = mc_div(delta, T_s);
            s->a_scale = mc_div(s->v_scale, T_s);
            s->j_scale = mc_div(s->a_scale, T_s);
        }
        if (mc_eq(s->c0, MC_ZERO) && mc_eq(s->c1, MC_ZERO) && mc_eq(s->c2, MC_ZERO) && mc_eq(s->c3, MC_ZERO)) {
            s->c0 = mc_mul(delta, MC_C(2.1875));
            s->c1 = mc_mul(delta, MC_C(8.75));
            s->c2 = mc_mul_i(delta, 21);
            s->c3 = mc_mul_i(delta, 20);
            s->theta_mid_rad = mc_add(from, mc_div_i(delta, 2));
        }
        from = s->theta_to_rad;
        prev_end = s->start_tick + s->duration_ticks;
    }
    return true;
}

void trajectory_eval(const trajectory_t *t, uint32_t tick, trajectory_point_t *out)
{
    out->theta_rad = t->cfg.theta_start_rad;
    out->omega_rad_s = MC_ZERO;
    out->accel_rad_s2 = MC_ZERO;
    for (int32_t i = 0; i < t->cfg.n_segments; ++i) {
        const trajectory_segment_t *s = &t->cfg.seg[i];
        if (tick < s->start_tick) {
            return; /* holding before segment i */
        }
        if (tick >= s->start_tick + s->duration_ticks) {
            out->theta_rad = s->theta_to_rad; /* segment done: hold its end */
            continue;
        }
        /* x = D - 1/2 = (2 (t - t_i) - T) / (2 T), exactly rounded */
        const int32_t n = (int32_t)(tick - s->start_tick);
        const int32_t N = (int32_t)s->duration_ticks;
        const mc_t x = mc_ratio_i(2 * n - N, 2 * N);
        const mc_t x2 = mc_mul(x, x);
        const mc_t u = mc_sub(MC_C(0.25), x2);
        /* theta: delta already inside c0..c3 (see trajectory.h) */
        mc_t g = mc_sub(s->c2, mc_mul(x2, s->c3));
        g = mc_sub(s->c1, mc_mul(x2, g));
        g = mc_sub(s->c0, mc_mul(x2, g));
        out->theta_rad = mc_mac(s->theta_mid_rad, x, g);
        /* small exact integer factors first, the segment scale last */
        const mc_t u2 = mc_mul(u, u);
        out->omega_rad_s = mc_mul(mc_mul(mc_mul_i(u2, 140), u), s->v_scale);
        out->accel_rad_s2 = mc_mul(mc_mul(mc_mul_i(x, -840), u2), s->a_scale);
        return;
    }
}
