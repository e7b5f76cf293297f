#include "estimators/fg_estimator.h"

void fg_estimator_init(fg_estimator_t *e, const fg_estimator_config_t *cfg)
{
    emf_observer_init(&e->emf, &cfg->emf);
    position_estimator_init(&e->pos, &cfg->pos);
    mech_observer_init(&e->mech, &cfg->mech);
    e->u_est.s = MC_ZERO;
    e->u_est.c = MC_ONE;
    e->i_d_A = MC_ZERO;
    e->i_q_A = MC_ZERO;
}
