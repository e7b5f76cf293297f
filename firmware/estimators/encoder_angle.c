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

static mc_rot_t enc_update(void *self, const estimator_in_t *in, mc_ab_t *i_ab_A, estimator_out_t *out)
{
    const encoder_angle_t *o = (const encoder_angle_t *)self;
    (void)i_ab_A; /* the currents as measured */
    out->theta_rad = in->sample->angle_rad;
    out->lock_checkable = false; /* measured: rho2 and u_reserve_V are left alone (estimator.h) */
    return mc_rot_from_angle(mc_elec_angle(in->sample->angle_rad, o->n_p));
}

const estimator_ops_t encoder_angle_ops = {
    .name = "encoder",
    .family = EST_FAMILY_ROTOR_ANGLE,
    .id = ROTOR_ANGLE_ENCODER,
    .state_bytes = (uint32_t)sizeof(encoder_angle_t),
    .needs_angle = true,
    .model_based = false,
    .config_problem = rotor_angle_problem,
    .init = enc_init,
    .starting = 0,
    .start = 0,
    .seed = enc_seed,
    .update = enc_update,
    .model_weight = 0,
    .reference = 0,
    .injection = 0,
    .hold = 0, /* measured: no time update */
};
