#include "trajectory/step_shaper.h"

bool step_shaper_init(step_shaper_t *s, const step_shaper_config_t *cfg, int32_t count0)
{
    s->cfg = *cfg;
    s->count_last = count0;
    s->count_moved = count0;
    s->count_offered = count0;
    s->offered = false;
    s->credit = STEP_SHAPER_BUCKET_STEPS * STEP_SHAPER_CREDIT_UNIT;
    s->excess_steps = 0u;
    s->moves = 0u;
    s->rate_credit = 0;
    s->max_move_steps = 0;
    s->ts_s = MC_ZERO;
    if (!mc_gt(cfg->step_angle_rad, MC_ZERO) || !mc_gt(cfg->speed_max_rad_s, MC_ZERO) ||
        !mc_gt(cfg->accel_max_rad_s2, MC_ZERO) || cfg->fs_hz <= 0) {
        return false;
    }
    s->ts_s = mc_ratio_i(1, cfg->fs_hz);
    /* the mean speed of moves peaking at w_max, in steps a sample:
     * w_max / ((35/16) phi f_s) */
    const mc_t rate =
        mc_div(cfg->speed_max_rad_s, mc_mul(STEP_SHAPER_PEAK_SPEED, mc_mul_i(cfg->step_angle_rad, cfg->fs_hz)));
    if (!mc_is_finite(rate) || !mc_lt(rate, MC_C(256.0))) {
        return false;
    }
    s->rate_credit = mc_round_i(mc_mul_i(rate, STEP_SHAPER_CREDIT_UNIT));
    /* the longest move: T = (35/16) d phi / w_max at most STEP_SHAPER_MOVE_MAX_S
     * (fixed point: at most 16384 steps, mc_t's range; a shorter longest
     * move only splits a long backlog into more moves) */
    const mc_t longest_rad = mc_div(mc_mul(STEP_SHAPER_MOVE_MAX_S, cfg->speed_max_rad_s), STEP_SHAPER_PEAK_SPEED);
    const mc_t steps = mc_div(longest_rad, cfg->step_angle_rad);
    if (!mc_is_finite(steps) || !mc_ge(steps, MC_ONE)) {
        return false;
    }
    s->max_move_steps = mc_round_i(steps);
    return s->rate_credit > 0;
}

/* the shortest duration of an eq. (70) move of dist_rad (>= 0) within the
 * limits, plus two samples */
static mc_t move_duration(const step_shaper_t *s, mc_t dist_rad)
{
    const mc_t t_speed = mc_div(mc_mul(STEP_SHAPER_PEAK_SPEED, dist_rad), s->cfg.speed_max_rad_s);
    const mc_t t_accel = mc_sqrt(mc_div(mc_mul(STEP_SHAPER_PEAK_ACCEL, dist_rad), s->cfg.accel_max_rad_s2));
    return mc_add(mc_max(t_speed, t_accel), mc_mul_i(s->ts_s, 2));
}

void step_shaper_step(step_shaper_t *s, int32_t count, mc_t theta_rest_rad, step_shaper_move_t *out)
{
    out->move = false;
    out->theta_to_rad = MC_ZERO;
    out->duration_s = MC_ZERO;
    s->offered = false;
    if (s->rate_credit <= 0) {
        return; /* not configured */
    }
    /* the limit's token bucket */
    const int64_t delta = (int64_t)count - (int64_t)s->count_last;
    s->count_last = count;
    const int64_t bucket = (int64_t)STEP_SHAPER_BUCKET_STEPS * STEP_SHAPER_CREDIT_UNIT;
    int64_t credit = (int64_t)s->credit + s->rate_credit;
    credit = credit > bucket ? bucket : credit;
    const int64_t n = delta < 0 ? -delta : delta;
    const int64_t covered = credit / STEP_SHAPER_CREDIT_UNIT; /* whole steps of credit */
    if (n <= covered) {
        credit -= n * STEP_SHAPER_CREDIT_UNIT;
    } else {
        credit -= covered * STEP_SHAPER_CREDIT_UNIT;
        s->excess_steps += (uint32_t)(n - covered);
    }
    s->credit = (int32_t)credit;
    /* a move when steps wait */
    if (count == s->count_moved) {
        return;
    }
    int64_t d = (int64_t)count - (int64_t)s->count_moved;
    d = d > s->max_move_steps ? s->max_move_steps : (d < -s->max_move_steps ? -s->max_move_steps : d);
    const int32_t to = (int32_t)((int64_t)s->count_moved + d);
    const mc_t theta_to = mc_mul_i(s->cfg.step_angle_rad, to);
    out->move = true;
    out->theta_to_rad = theta_to;
    out->duration_s = move_duration(s, mc_abs(mc_sub(theta_to, theta_rest_rad)));
    s->count_offered = to;
    s->offered = true;
}

void step_shaper_answer(step_shaper_t *s, bool accepted)
{
    if (s->offered && accepted) {
        s->count_moved = s->count_offered;
        s->moves += 1u;
    }
    s->offered = false;
}
