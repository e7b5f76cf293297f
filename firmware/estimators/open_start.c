/* open_start.c - see open_start.h. */
#include "estimators/open_start.h"

const char *open_start_problem(const void *cfg)
{
    const open_start_config_t *c = (const open_start_config_t *)cfg;
    const motor_model_t *m = &c->model;
    if (m->n_p < 1) return "est.model.n_p: must be >= 1";
    if (m->fs_hz <= 0) return "est.model.fs_hz: must be > 0";
    if (!mc_gt(c->flux.Phi_fs_V, MC_ZERO)) return "est.flux.Phi_fs_V: must be > 0";
    if (!mc_gt(c->flux.rho_gain, MC_ZERO)) return "est.flux.rho_gain: must be > 0";
    if (!mc_ge(c->flux.gPhi3_V, MC_ZERO)) return "est.flux.gPhi3_V: must be >= 0";
    if (!mc_ge(c->speed.k_omega, MC_ZERO)) return "est.speed.k_omega: must be >= 0";
    if (!mc_ge(c->speed.k_load_Nm_s, MC_ZERO)) return "est.speed.k_load_Nm_s: must be >= 0";
    if (c->fit.decim < 1) return "est.fit.decim: must be >= 1";
    if (!mc_gt(c->fit.det_min, MC_ZERO)) return "est.fit.det_min: must be > 0";
    resistance_tracker_t rtrack;
    if (!resistance_tracker_init(&rtrack, &c->rtrack)) return "est.rtrack: enabled with a coefficient out of range";
    return 0;
}
