#include "estimators/encoder_observer.h"

/* pi and 2 pi times the angle's scale */
#define ENC_OBS_PI_S MC_C(3216.9908772759483)
#define ENC_OBS_TWO_PI_S MC_C(6433.9817545518966)

void encoder_observer_set_angle(encoder_observer_t *o, mc_t theta_rad)
{
    o->turns = 0;
    o->theta_s = mc_mul(mc_wrap_pi(theta_rad), ENC_OBS_SCALE);
    o->theta_rad = mc_mul(o->theta_s, ENC_OBS_INV_SCALE);
}

bool encoder_observer_init(encoder_observer_t *o, const encoder_observer_config_t *cfg, mc_t theta0_rad)
{
    o->cfg = *cfg;
    encoder_observer_set_angle(o, theta0_rad);
    o->omega_rad_s = MC_ZERO;
    o->accel_rad_s2 = MC_ZERO;
    o->load_Nm = MC_ZERO;
    o->eps_rad = MC_ZERO;
    return mc_gt(cfg->ts_over_J, MC_ZERO) && mc_gt(cfg->inv_J, MC_ZERO) && mc_ge(cfg->l1_ts_scaled, MC_ZERO) && mc_gt(cfg->ts_scaled, MC_ZERO) &&
           mc_ge(cfg->l2_ts, MC_ZERO) && mc_ge(cfg->l3_ts, MC_ZERO);
}

void encoder_observer_step(encoder_observer_t *o, mc_t theta_meas_rad, mc_t torque_Nm)
{
    const encoder_observer_config_t *c = &o->cfg;
    /* the error of the wrapped angles: the estimate keeps its turns */
    const mc_t th = mc_mul(o->theta_s, ENC_OBS_INV_SCALE);
    const mc_t eps = mc_wrap_pi(mc_sub(theta_meas_rad, th));
    o->eps_rad = eps;
    const mc_t net_Nm = mc_sub(torque_Nm, o->load_Nm); /* T_e - T_L_hat */
    o->accel_rad_s2 = mc_mul(net_Nm, c->inv_J);
    /* forward Euler of the three observer equations (header), the angle
     * scaled by 2^ENC_OBS_SHIFT and wrapped, its turns counted */
    o->theta_s = mc_add(o->theta_s, mc_mac(mc_mul(o->omega_rad_s, c->ts_scaled), c->l1_ts_scaled, eps));
    if (!mc_lt(o->theta_s, ENC_OBS_PI_S)) {
        o->theta_s = mc_sub(o->theta_s, ENC_OBS_TWO_PI_S);
        o->turns += 1;
    } else if (mc_lt(o->theta_s, mc_neg(ENC_OBS_PI_S))) {
        o->theta_s = mc_add(o->theta_s, ENC_OBS_TWO_PI_S);
        o->turns -= 1;
    }
    o->theta_rad = mc_add(mc_mul(o->theta_s, ENC_OBS_INV_SCALE), mc_mul_i(MC_TWO_PI, o->turns));
    o->omega_rad_s = mc_add(o->omega_rad_s, mc_mac(mc_mul(net_Nm, c->ts_over_J), c->l2_ts, eps));
    o->load_Nm = mc_sub(o->load_Nm, mc_mul(c->l3_ts, eps));
}

void encoder_observer_get(const encoder_observer_t *o, mc_estimate_t *e)
{
    e->theta_rad = o->theta_rad;
    e->omega_rad_s = o->omega_rad_s;
    e->accel_rad_s2 = o->accel_rad_s2;
    e->load_Nm = o->load_Nm;
    e->valid = true;
}
