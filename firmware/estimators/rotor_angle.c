/* rotor_angle.c - see rotor_angle.h. */
#include "estimators/rotor_angle.h"

const char *rotor_angle_problem(const void *cfg)
{
    const rotor_angle_config_t *c = (const rotor_angle_config_t *)cfg;
    return (c->n_p >= 1) ? 0 : "model.n_p: must be >= 1";
}
