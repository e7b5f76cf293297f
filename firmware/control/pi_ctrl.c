#include "control/pi_ctrl.h"

bool pi_ctrl_init(pi_ctrl_t *c, const pi_ctrl_config_t *cfg)
{
    c->cfg = *cfg;
    pi_ctrl_reset(c, MC_ZERO);
    return mc_ge(cfg->kp, MC_ZERO) && mc_ge(cfg->ki_ts, MC_ZERO);
}

mc_t pi_ctrl_step(pi_ctrl_t *c, mc_t e, mc_t ff, mc_t u_max)
{
    const mc_t u_raw = mc_add(mc_mac(c->integral, c->cfg.kp, e), ff);
    const mc_t u = mc_clamp(u_raw, mc_neg(u_max), u_max);
    c->saturated = mc_ne(u, u_raw);
    /* conditional integration: not while the output is limited and the
     * error drives it further into the limit */
    const bool winding = c->saturated && (mc_gt(u_raw, MC_ZERO) == mc_gt(e, MC_ZERO));
    if (!winding) {
        c->integral = mc_clamp(mc_mac(c->integral, c->cfg.ki_ts, e), mc_neg(u_max), u_max);
    }
    return u;
}
