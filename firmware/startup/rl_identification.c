#include "startup/rl_identification.h"

#include "math/mc_mean.h"

void rl_id_init(rl_id_t *id, const rl_id_config_t *cfg)
{
    id->cfg = *cfg;
    id->state = (cfg->window_ticks > 0 && cfg->steady_ticks > 0 && cfg->steady_ticks < cfg->window_ticks)
                    ? RL_ID_RUNNING
                    : RL_ID_OFF;
    id->k = 0;
    id->i0_A = MC_ZERO;
    id->mean_v_V = MC_ZERO;
    id->mean_i_A = MC_ZERO;
    id->ss_v_V = MC_ZERO;
    id->ss_i_A = MC_ZERO;
    for (int j = 0; j < 4; ++j) {
        id->res[j] = MC_ZERO;
    }
    id->R_ohm = cfg->R_model_ohm;
    id->L_fs_ohm = cfg->L_fs_model_ohm;
}

static bool within_factor_two(mc_t x, mc_t ref)
{
    return !mc_lt(x, mc_div_i(ref, 2)) && !mc_gt(x, mc_mul_i(ref, 2));
}

bool rl_id_step(rl_id_t *id, mc_t i_f_A, mc_t v_f_V, mc_t omega_ref_rad_s)
{
    if (id->state != RL_ID_RUNNING) {
        return false;
    }
    const rl_id_config_t *c = &id->cfg;
    if (mc_gt(mc_abs(omega_ref_rad_s), c->omega_still_rad_s)) {
        id->state = RL_ID_REJECTED;
        return true;
    }
    if (id->k == 0) {
        id->i0_A = i_f_A;
    }
    const int32_t N = c->window_ticks;
    mc_mean_add(&id->mean_v_V, &id->res[0], v_f_V, N);
    mc_mean_add(&id->mean_i_A, &id->res[1], i_f_A, N);
    if (id->k >= N - c->steady_ticks) {
        mc_mean_add(&id->ss_v_V, &id->res[2], v_f_V, c->steady_ticks);
        mc_mean_add(&id->ss_i_A, &id->res[3], i_f_A, c->steady_ticks);
    }
    id->k += 1;
    if (id->k < N) {
        return false;
    }
    /* R from the steady tail; L from the integral of the voltage equation:
     * L (i_N - i_0) = Ts * sum(v - R i) - Ts R (i_N - i_0)/2 (trapezoid), so
     * L/Ts = N (mean v - R mean i) / (i_N - i_0) - R/2 */
    const mc_t di = mc_sub(id->ss_i_A, id->i0_A);
    if (!mc_gt(mc_abs(id->ss_i_A), MC_ZERO) || !mc_gt(mc_abs(di), MC_ZERO)) {
        id->state = RL_ID_REJECTED;
        return true;
    }
    const mc_t R = mc_div(id->ss_v_V, id->ss_i_A);
    const mc_t excess = mc_sub(id->mean_v_V, mc_mul(R, id->mean_i_A));
    const mc_t L_fs = mc_sub(mc_mul_i(mc_div(excess, di), N), mc_div_i(R, 2));
    if (within_factor_two(R, c->R_model_ohm) && within_factor_two(L_fs, c->L_fs_model_ohm)) {
        id->R_ohm = R;
        id->L_fs_ohm = L_fs;
        id->state = RL_ID_DONE;
    } else {
        id->state = RL_ID_REJECTED;
    }
    return true;
}
