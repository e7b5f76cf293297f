#include "startup/inverter_id.h"

#include "math/mc_mean.h"

/* A level's current at the end of its settling must be within this share
 * of its target (the loop's steady state; an open phase or a voltage
 * limit too low leaves it far below). */
#define INV_ID_SETTLED_TOL MC_C(0.05)

const char *inv_id_config_problem(const inv_id_config_t *c)
{
    if (c->n_levels < 2 || c->n_levels > INV_ID_MAX_LEVELS) return "n_levels: 2 .. INV_ID_MAX_LEVELS";
    if (!mc_gt(c->i_test_A, MC_ZERO)) return "i_test_A: > 0";
    if (!mc_lt(c->i_test_A, c->i_trip_A)) return "i_test_A: below i_trip_A";
    if (c->settle_ticks < 1) return "settle_ticks: >= 1";
    if (c->meas_ticks < 1) return "meas_ticks: >= 1";
    if (!mc_gt(c->kp_V_per_A, MC_ZERO)) return "kp_V_per_A: > 0";
    if (mc_lt(c->ki_ts_V_per_A, MC_ZERO)) return "ki_ts_V_per_A: >= 0";
    if (!mc_gt(c->v_max_V, MC_ZERO)) return "v_max_V: > 0";
    return 0;
}

bool inv_id_init(inv_id_t *id, const inv_id_config_t *c)
{
    if (inv_id_config_problem(c) != 0) return false;
    id->cfg = *c;
    id->state = INV_ID_RUNNING;
    id->level = 0;
    id->k = 0;
    id->integ_alpha_V = MC_ZERO;
    id->integ_beta_V = MC_ZERO;
    id->v_sum_res[0] = MC_ZERO;
    id->v_sum_res[1] = MC_ZERO;
    for (int32_t j = 0; j < INV_ID_MAX_LEVELS; ++j) {
        id->i_mean_A[j] = MC_ZERO;
        id->v_mean_V[j] = MC_ZERO;
    }
    id->why = 0;
    return true;
}

/* One axis of the PI: v = kp e + integ, the integrator moved by ki Ts e
 * only while v stays within +-v_max (conditional integration: no windup
 * while the voltage limit holds the loop). */
static mc_t pi_axis(const inv_id_config_t *c, mc_t *integ, mc_t err, bool *saturated)
{
    const mc_t p = mc_mul(c->kp_V_per_A, err);
    const mc_t next = mc_mac(*integ, c->ki_ts_V_per_A, err);
    const mc_t v = mc_add(p, next);
    if (mc_gt(mc_abs(v), c->v_max_V)) {
        *saturated = true;
        return mc_clamp(mc_add(p, *integ), mc_neg(c->v_max_V), c->v_max_V);
    }
    *integ = next;
    return v;
}

static inv_id_state_t reject(inv_id_t *id, const char *why, mc_t *v_alpha_V, mc_t *v_beta_V)
{
    id->state = INV_ID_REJECTED;
    id->why = why;
    *v_alpha_V = MC_ZERO;
    *v_beta_V = MC_ZERO;
    return id->state;
}

inv_id_state_t inv_id_step(inv_id_t *id, mc_t i_alpha_A, mc_t i_beta_A, mc_t i_phase_max_A, mc_t *v_alpha_V,
                           mc_t *v_beta_V)
{
    const inv_id_config_t *c = &id->cfg;
    if (id->state != INV_ID_RUNNING) {
        *v_alpha_V = MC_ZERO;
        *v_beta_V = MC_ZERO;
        return id->state;
    }
    if (!mc_lt(i_phase_max_A, c->i_trip_A)) {
        return reject(id, "a phase current reached i_trip_A (a shorted winding, or the loop's gains)", v_alpha_V,
                      v_beta_V);
    }
    /* the level's target: (level + 1) i_test / n */
    const mc_t target = mc_div_i(mc_mul_i(c->i_test_A, id->level + 1), c->n_levels);
    bool saturated = false;
    const mc_t va = pi_axis(c, &id->integ_alpha_V, mc_sub(target, i_alpha_A), &saturated);
    const mc_t vb = pi_axis(c, &id->integ_beta_V, mc_neg(i_beta_A), &saturated);
    if (id->k == c->settle_ticks - 1) {
        /* the end of the settling: the loop must hold the level */
        const mc_t off = mc_abs(mc_sub(i_alpha_A, target));
        if (mc_gt(off, mc_mul(INV_ID_SETTLED_TOL, target))) {
            return reject(id,
                          saturated ? "a level not reached within v_max_V (an open phase, or the bus too low)"
                                    : "a level not reached at the end of its settling (an open phase, or the loop's "
                                      "gains too slow for settle_ticks)",
                          v_alpha_V, v_beta_V);
        }
    } else if (id->k >= c->settle_ticks) {
        /* the means over the measured window: the current measured now,
         * the voltage commanded now (in the steady state, the voltage of
         * every sample) */
        mc_mean_add(&id->i_mean_A[id->level], &id->v_sum_res[0], i_alpha_A, c->meas_ticks);
        mc_mean_add(&id->v_mean_V[id->level], &id->v_sum_res[1], va, c->meas_ticks);
    }
    *v_alpha_V = va;
    *v_beta_V = vb;
    id->k += 1;
    if (id->k >= c->settle_ticks + c->meas_ticks) {
        id->k = 0;
        id->v_sum_res[0] = MC_ZERO;
        id->v_sum_res[1] = MC_ZERO;
        id->level += 1;
        if (id->level >= c->n_levels) {
            id->state = INV_ID_DONE;
            id->level = c->n_levels - 1;
            *v_alpha_V = MC_ZERO;
            *v_beta_V = MC_ZERO;
        }
    }
    return id->state;
}
