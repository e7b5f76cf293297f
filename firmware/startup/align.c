#include "startup/align.h"

void align_init(align_t *a, const align_config_t *cfg)
{
    a->cfg = *cfg;
    a->k = 0;
}

int32_t align_total_ticks(const align_config_t *c)
{
    if (!c->enabled) {
        return 0;
    }
    return 2 * c->ramp_ticks + c->hold_ticks + 2 * c->turn_ticks + c->settle_ticks + c->off_ticks;
}

bool align_step(align_t *a, mc_t v_hold_V, mc_t *v_f_V, mc_t *v_g_V)
{
    const align_config_t *c = &a->cfg;
    *v_f_V = MC_ZERO;
    *v_g_V = MC_ZERO;
    if (a->k >= align_total_ticks(c)) {
        return true;
    }
    int32_t k = a->k;
    a->k += 1;
    const mc_t mag = v_hold_V;
    /* stage 1: ramp up (linear in k, never a step), hold at angle 0 */
    if (k < c->ramp_ticks) {
        *v_f_V = mc_mul(v_hold_V, mc_ratio_i(k + 1, c->ramp_ticks));
        return false;
    }
    k -= c->ramp_ticks;
    if (k < c->hold_ticks) {
        *v_f_V = mag;
        return false;
    }
    k -= c->hold_ticks;
    /* stage 2: out to phi_turn and back at a constant rate */
    if (k < 2 * c->turn_ticks) {
        const int32_t n = k < c->turn_ticks ? k + 1 : 2 * c->turn_ticks - (k + 1);
        const mc_rot_t r = mc_rot_from_angle(mc_mul(c->phi_turn_rad, mc_ratio_i(n, c->turn_ticks)));
        *v_f_V = mc_mul(mag, r.c);
        *v_g_V = mc_mul(mag, r.s);
        return false;
    }
    k -= 2 * c->turn_ticks;
    /* stage 3: settle at angle 0 */
    if (k < c->settle_ticks) {
        *v_f_V = mag;
        return false;
    }
    k -= c->settle_ticks;
    /* stage 4: ramp down, then 0 V while the current decays */
    if (k < c->ramp_ticks) {
        *v_f_V = mc_mul(v_hold_V, mc_ratio_i(c->ramp_ticks - (k + 1), c->ramp_ticks));
    }
    return false;
}
