/* flux_angle.c - see flux_angle.h. */
#include "estimators/flux_angle.h"

void flux_angle_reset(flux_angle_t *o, const rotor_angle_config_t *cfg)
{
    const mc_ab_t i0 = {MC_ZERO, MC_ZERO};
    const mc_t e0 = mc_elec_angle(cfg->theta0_rad, cfg->n_p);
    o->n_p = cfg->n_p;
    o->flux0 = cfg->flux;
    flux_observer_init(&o->flux, &cfg->flux, mc_rot_from_angle(e0), i0);
    angle_unwrap_init(&o->unwrap, e0);
    /* the electrical angle fixes the mechanical one up to 2 pi/p: the
     * start's turn among the p is kept as an offset */
    o->theta_offset_rad = mc_sub(mc_wrap_pi(cfg->theta0_rad), mc_div_i(e0, cfg->n_p));
}

void flux_angle_seed(flux_angle_t *o, mc_t theta_e_rad)
{
    const mc_ab_t i0 = {MC_ZERO, MC_ZERO};
    flux_observer_init(&o->flux, &o->flux0, mc_rot_from_angle(theta_e_rad), i0);
    angle_unwrap_init(&o->unwrap, theta_e_rad);
    o->theta_offset_rad = MC_ZERO;
}

void flux_angle_model(flux_angle_t *o, const estimator_in_t *in)
{
    if (mc_ne(in->L_ratio, MC_ZERO)) {
        /* (14)'s L the iron's secant L_q (model/iron_model.h) */
        flux_observer_set_L(&o->flux, mc_mul(o->flux0.L_fs_ohm, in->L_ratio));
    }
    /* the gradient term's target: the active flux's radius, squared */
    flux_observer_set_target(&o->flux, mc_mul(in->flux_ratio, in->flux_ratio));
}

mc_t flux_angle_mechanical(flux_angle_t *o, mc_rot_t r)
{
    angle_unwrap_step(&o->unwrap, r.s, r.c);
    /* (e + 2 pi n)/p, with n taken modulo p first (n p-fold is a whole
     * mechanical turn) so the sum stays small */
    const int32_t p = o->n_p;
    const int32_t n_mod = ((o->unwrap.n_turns % p) + p) % p;
    return mc_wrap_pi(mc_add(mc_div_i(mc_add(o->unwrap.e_rad, mc_mul_i(MC_TWO_PI, n_mod)), p), o->theta_offset_rad));
}

static bool fa_init(void *self, const void *cfg)
{
    const rotor_angle_config_t *c = (const rotor_angle_config_t *)cfg;
    if (c->n_p < 1) {
        return false;
    }
    flux_angle_reset((flux_angle_t *)self, c);
    return true;
}

static void fa_seed(void *self, mc_t theta_e_rad) { flux_angle_seed((flux_angle_t *)self, theta_e_rad); }

static mc_rot_t fa_update(void *self, const estimator_in_t *in, mc_ab_t *i_ab_A, estimator_out_t *out)
{
    flux_angle_t *o = (flux_angle_t *)self;
    flux_angle_model(o, in);
    flux_observer_step(&o->flux, *i_ab_A);
    out->theta_rad = flux_angle_mechanical(o, o->flux.unit);
    out->lock_checkable = true;
    out->rho2 = o->flux.rho2;
    out->rho2_target = o->flux.rho2_target;
    return o->flux.unit;
}

static void fa_hold(void *self, mc_ab_t u_mean_ab_V, mc_ab_t u_cmd_ab_V)
{
    (void)u_cmd_ab_V;
    flux_observer_hold(&((flux_angle_t *)self)->flux, u_mean_ab_V);
}

const estimator_ops_t flux_angle_ops = {
    .name = "flux",
    .family = EST_FAMILY_ROTOR_ANGLE,
    .id = ROTOR_ANGLE_FLUX,
    .state_bytes = (uint32_t)sizeof(flux_angle_t),
    .needs_angle = false,
    .model_based = true,
    .config_problem = rotor_angle_problem,
    .init = fa_init,
    .starting = 0,
    .start = 0,
    .seed = fa_seed,
    .update = fa_update,
    .model_weight = 0,
    .reference = 0,
    .injection = 0,
    .hold = fa_hold,
};
