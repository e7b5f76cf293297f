#include "control/deadtime_comp.h"

bool deadtime_comp_init(deadtime_comp_t *d, const deadtime_comp_config_t *cfg)
{
    d->cfg = *cfg;
    const bool ok = mc_ge(cfg->k_bus, MC_ZERO) && mc_ge(cfg->v_drop_V, MC_ZERO) && mc_ge(cfg->r_drop_ohm, MC_ZERO) &&
                    mc_ge(cfg->inv_i_band_per_A, MC_ZERO);
    if (!ok) {
        d->cfg.enabled = false;
    }
    return ok;
}

/* |x| beyond it is taken as it (s = 0.9995): keeps 1/(2|x|) in range */
#define DTC_X_MAX MC_C(1000.0)

mc_t deadtime_comp_sign(const deadtime_comp_t *d, mc_t i_A)
{
    if (mc_eq(d->cfg.inv_i_band_per_A, MC_ZERO)) {
        return mc_sgn(i_A);
    }
    /* (2) */
    const mc_t x = mc_clamp(mc_mul(i_A, d->cfg.inv_i_band_per_A), mc_neg(DTC_X_MAX), DTC_X_MAX);
    const mc_t ax = mc_abs(x);
    if (mc_le(ax, MC_ONE)) {
        return mc_div_i(x, 2);
    }
    return mc_mul_sgn(mc_sub(MC_ONE, mc_div(MC_ONE, mc_mul_i(ax, 2))), x);
}

mc_t deadtime_comp_leg_error_V(const deadtime_comp_t *d, mc_t i_A, mc_t v_bus_V)
{
    if (!d->cfg.enabled) {
        return MC_ZERO;
    }
    /* (1) */
    const mc_t v_const = mc_mac(d->cfg.v_drop_V, d->cfg.k_bus, v_bus_V);
    return mc_neg(mc_mac(mc_mul(v_const, deadtime_comp_sign(d, i_A)), d->cfg.r_drop_ohm, i_A));
}

mc_ab_t deadtime_comp_step(const deadtime_comp_t *d, const mc_t *i_A, mc_t v_bus_V, hal_command_t *out)
{
    if (!d->cfg.enabled) {
        const mc_ab_t none = {MC_ZERO, MC_ZERO};
        return none;
    }
    const int n = (out->n_phases == 3u) ? 3 : 2;
    /* a leg swings +-V_dc/2 about the midpoint; a winding between two legs
     * +-V_dc and loses two legs' errors */
    const mc_t v_lim = (n == 3) ? mc_div_i(v_bus_V, 2) : v_bus_V;
    const int32_t legs = (n == 3) ? 1 : 2;
    mc_t r[3] = {MC_ZERO, MC_ZERO, MC_ZERO};
    for (int k = 0; k < n; ++k) {
        const mc_t want = mc_sub(out->v_V[k], mc_mul_i(deadtime_comp_leg_error_V(d, i_A[k], v_bus_V), legs));
        const mc_t got = mc_clamp(want, mc_neg(v_lim), v_lim);
        r[k] = mc_sub(got, want);
        out->v_V[k] = got;
    }
    /* what the clamp removed, in alpha-beta (its common mode does not reach
     * the star-connected motor) */
    mc_t common_V;
    return phase_adapter_clarke((uint8_t)n, r, &common_V);
}
