#include "trajectory/trajectory.h"

void trajectory_poly7(mc_t D, mc_t *p, mc_t *dp, mc_t *ddp, mc_t *dddp)
{
    /* eq. (70) with the errata coefficients, Horner form:
     * p    = D^4 (35 + D(-84 + D(70 - 20 D)))
     * p'   = 140 D^3 (1-D)^3
     * p''  = 420 D^2 (1-D)^2 (1-2D)
     * p''' = 840 D (1-D) (1 - 5D + 5D^2) */
    const mc_t D2 = mc_mul(D, D);
    const mc_t D4 = mc_mul(D2, D2);
    const mc_t om = mc_sub(MC_ONE, D);
    const mc_t om2 = mc_mul(om, om);
    mc_t h = mc_sub(MC_C(70.0), mc_mul(MC_C(20.0), D));
    h = mc_add(MC_C(-84.0), mc_mul(D, h));
    h = mc_add(MC_C(35.0), mc_mul(D, h));
    *p = mc_mul(D4, h);
    *dp = mc_mul(mc_mul(MC_C(140.0), mc_mul(D2, D)), mc_mul(om2, om));
    *ddp = mc_mul(mc_mul(MC_C(420.0), mc_mul(D2, om2)), mc_sub(MC_ONE, mc_mul(MC_C(2.0), D)));
    *dddp = mc_mul(mc_mul(MC_C(840.0), mc_mul(D, om)),
                   mc_add(mc_sub(MC_ONE, mc_mul(MC_C(5.0), D)), mc_mul(MC_C(5.0), D2)));
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
        if (s->duration_ticks == 0 || s->start_tick < prev_end) {
            return false;
        }
        t->theta_from_rad[i] = from;
        if (s->v_scale == MC_ZERO && s->a_scale == MC_ZERO && s->j_scale == MC_ZERO) {
            /* Derive (theta_f - theta_i)/T^n; T = duration_ticks / fs_hz. */
            const mc_t T_s = mc_ratio_i((int32_t)s->duration_ticks, cfg->fs_hz);
            const mc_t delta = mc_sub(s->theta_to_rad, from);
            s->v_scale = mc_div(delta, T_s);
            s->a_scale = mc_div(s->v_scale, T_s);
            s->j_scale = mc_div(s->a_scale, T_s);
        }
        from = s->theta_to_rad;
        prev_end = s->start_tick + s->duration_ticks;
    }
    return true;
}

uint32_t trajectory_end_tick(const trajectory_t *t)
{
    if (t->cfg.n_segments == 0) {
        return 0;
    }
    const trajectory_segment_t *s = &t->cfg.seg[t->cfg.n_segments - 1];
    return s->start_tick + s->duration_ticks;
}

void trajectory_eval(const trajectory_t *t, uint32_t tick, trajectory_point_t *out)
{
    out->theta_rad = t->cfg.theta_start_rad;
    out->omega_rad_s = MC_ZERO;
    out->accel_rad_s2 = MC_ZERO;
    out->jerk_rad_s3 = MC_ZERO;
    for (int32_t i = 0; i < t->cfg.n_segments; ++i) {
        const trajectory_segment_t *s = &t->cfg.seg[i];
        if (tick < s->start_tick) {
            return; /* holding before segment i */
        }
        if (tick >= s->start_tick + s->duration_ticks) {
            out->theta_rad = s->theta_to_rad; /* segment done: hold its end */
            continue;
        }
        const mc_t D = mc_ratio_i((int32_t)(tick - s->start_tick), (int32_t)s->duration_ticks);
        mc_t p, dp, ddp, dddp;
        trajectory_poly7(D, &p, &dp, &ddp, &dddp);
        const mc_t delta = mc_sub(s->theta_to_rad, t->theta_from_rad[i]);
        out->theta_rad = mc_add(t->theta_from_rad[i], mc_mul(delta, p));
        out->omega_rad_s = mc_mul(s->v_scale, dp);
        out->accel_rad_s2 = mc_mul(s->a_scale, ddp);
        out->jerk_rad_s3 = mc_mul(s->j_scale, dddp);
        return;
    }
}
