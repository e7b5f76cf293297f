#include "startup/open_loop.h"

mc_t open_loop_voltage(const open_loop_config_t *c, const motor_model_t *m, mc_t omega_ref_rad_s)
{
    /* sqrt((R^2 + (n_p w L)^2) I^2 + (K w)^2) as nested hypot: no squares
     * of large values, so it cannot overflow in fixed point */
    if (mc_eq(omega_ref_rad_s, MC_ZERO)) {
        return mc_min(mc_mul(m->R_ohm, c->i_max_A), c->v_max_V); /* at rest: R I_max */
    }
    const mc_t z = mc_hypot(m->R_ohm, mc_mul(m->npL_ohm_s, omega_ref_rad_s));
    const mc_t v = mc_hypot(mc_mul(z, c->i_max_A), mc_mul(m->K_V_s, omega_ref_rad_s));
    return mc_min(v, c->v_max_V);
}
