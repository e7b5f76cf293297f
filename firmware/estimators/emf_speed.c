/* emf_speed.c - see emf_speed.h. */
#include "estimators/emf_speed.h"

const char *emf_speed_problem(const void *cfg)
{
    const open_start_config_t *c = (const open_start_config_t *)cfg;
    const char *why = open_start_problem(cfg);
    if (why != 0) return why;
    if (!mc_gt(c->omega_lim_rad_s, MC_ZERO)) return "est.omega_lim_rad_s: must be > 0 (estimator back_emf)";
    if (!mc_gt(c->emf_torque_model.K_V_s, MC_ZERO))
        return "est.emf_torque_model.K_V_s: must be > 0 (estimator back_emf)";
    if (c->emf.pos.n_p != c->model.n_p) return "est.emf.pos.n_p: must be est.model.n_p (estimator back_emf)";
    return 0;
}

static bool es_init(void *self, const void *cfg)
{
    emf_speed_t *o = (emf_speed_t *)self;
    const open_start_config_t *c = (const open_start_config_t *)cfg;
    const bool ok = flux_speed_init(&o->fs, c);
    fg_estimator_init(&o->emf, &c->emf);
    o->omega_lim_rad_s = c->omega_lim_rad_s;
    o->probe_ran = false;
    o->i_f_A = MC_ZERO;
    o->i_g_A = MC_ZERO;
    return ok && emf_speed_problem(c) == 0;
}

/* In open loop paper 000's estimator reports the reference (the rotor follows it). */
static void es_report(const void *self, const open_start_in_t *in, bool closed, open_start_report_t *r)
{
    const emf_speed_t *o = (const emf_speed_t *)self;
    const int32_t n_p = o->fs.cfg.model.n_p;
    fg_estimator_get(&o->emf, closed, mc_add(in->ref.theta_rad, o->fs.ol_origin_mech_rad), in->ref.omega_rad_s,
                     in->ref.accel_rad_s2, &r->est);
    r->est.valid = closed;
    const mc_t e_rad = mc_elec_angle(r->est.theta_rad, n_p);
    /* whole electrical turns: (n_p theta - e)/(2 pi), an integer up to rounding */
    const mc_t turns = mc_mul(mc_sub(mc_mul_i(r->est.theta_rad, n_p), e_rad), MC_C(0.15915494309189535));
    r->theta_e_turns = mc_round_i(turns);
    r->theta_e_rad = e_rad;
    r->omega_rad_s = r->est.omega_rad_s;
    r->load_Nm = r->est.load_Nm;
    r->rho2 = o->fs.flux.rho2;
    r->R_obs_ohm = o->fs.flux.cfg.R_ohm;
}

static bool es_set_omega_lim(void *self, mc_t omega_lim_rad_s)
{
    emf_speed_t *o = (emf_speed_t *)self;
    if (mc_lt(omega_lim_rad_s, o->fs.cfg.omega_lim_rad_s)) {
        return false;
    }
    o->omega_lim_rad_s = omega_lim_rad_s;
    return true;
}

const estimator_ops_t emf_speed_ops = {
    .name = "back_emf",
    .family = EST_FAMILY_OPEN_START,
    .id = OPEN_START_BACK_EMF,
    .state_bytes = (uint32_t)sizeof(emf_speed_t),
    .needs_angle = false,
    .model_based = false,
    .config_problem = emf_speed_problem,
    .init = es_init,
    .report = es_report,
    .set_omega_lim = es_set_omega_lim,
};
