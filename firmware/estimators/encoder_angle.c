/* encoder_angle.c - see encoder_angle.h. */
#include "estimators/encoder_angle.h"

static bool enc_init(void *self, const void *cfg)
{
    encoder_angle_t *o = (encoder_angle_t *)self;
    o->n_p = ((const rotor_angle_config_t *)cfg)->n_p;
    return o->n_p >= 1;
}

static void enc_seed(void *self, mc_t theta_e_rad)
{
    (void)self;
    (void)theta_e_rad; /* measured: nothing to seed */
}

static void enc_update(void *self, const estimator_in_t *in, estimator_out_t *out)
{
    const encoder_angle_t *o = (const encoder_angle_t *)self;
    out->theta_rad = in->sample->angle_rad;
    out->rot_e = mc_rot_from_angle(mc_elec_angle(in->sample->angle_rad, o->n_p));
    out->i_ab_A = in->i_ab_A;
    out->lock_checkable = false;
    out->rho2 = MC_ONE;
    out->rho2_target = MC_ONE;
    out->u_reserve_V = MC_ZERO;
}

static void enc_hold(void *self, mc_ab_t u_mean_ab_V, mc_ab_t u_cmd_ab_V)
{
    (void)self;
    (void)u_mean_ab_V;
    (void)u_cmd_ab_V;
}

const estimator_ops_t encoder_angle_ops = {
    .name = "encoder",
    .family = EST_FAMILY_ROTOR_ANGLE,
    .id = ROTOR_ANGLE_ENCODER,
    .state_bytes = (uint32_t)sizeof(encoder_angle_t),
    .needs_angle = true,
    .model_based = false,
    .init = enc_init,
    .starting = 0,
    .start = 0,
    .seed = enc_seed,
    .update = enc_update,
    .model_weight = 0,
    .reference = 0,
    .injection = 0,
    .hold = enc_hold,
};
