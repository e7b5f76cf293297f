/* flux_speed.c - see flux_speed.h. */
#include "estimators/flux_speed.h"

/* The probe's points are p = 8 (rho - rho(0)): det M of a through-origin
 * fit of points spread evenly along an arc is 1.3e-8 for an arc of 0.3 rad
 * (6th power of the arc), below the resolution of Q14.17 (7.6e-6); scaled
 * by 8 it is 4096 times larger (3.2e-3, 420 LSB). |p| <= 2 (two unit
 * vectors) keeps |8 p|^3 <= 4096, below the Q14.17 limit of 16384. */
#define FLUX_SPEED_PROBE_POINT_SCALE 8

bool flux_speed_init(flux_speed_t *o, const open_start_config_t *cfg)
{
    o->cfg = *cfg;
    /* rho_hat(0) = (1, 0) (errata): the angle is unknown, the open-loop
     * start makes it observable */
    const mc_rot_t angle0 = {MC_ZERO, MC_ONE};
    const mc_ab_t i0 = {MC_ZERO, MC_ZERO};
    flux_observer_init(&o->flux, &cfg->flux, angle0, i0);
    flux_observer_set_gradient(&o->flux, false); /* a pure integrator until the circle fit */
    flux_circle_fit_init(&o->fit, &cfg->fit);
    flux_circle_fit_init(&o->probe, &cfg->probe_fit);
    o->probe_anchor = o->flux.rho;
    o->probe_last.alpha = MC_ZERO;
    o->probe_last.beta = MC_ZERO;
    o->probing = cfg->probe_ticks > 0u;
    o->probe_sample = false;
    o->probe_turned = false;
    o->probe_dir.s = MC_ZERO; /* along alpha */
    o->probe_dir.c = MC_ONE;
    o->ol_origin = angle0;
    o->ol_theta0_rad = MC_ZERO;
    o->ol_origin_mech_rad = MC_ZERO;
    const bool rtrack_ok = resistance_tracker_init(&o->rtrack, &cfg->rtrack);
    speed_load_observer_init(&o->speed, &cfg->speed, angle0, MC_ZERO, MC_ZERO);
    return rtrack_ok && open_start_problem(cfg) == 0;
}

/* The start-up probe (flux_speed.h): offers the fit a point each time the flux has moved
 * sqrt(probe_step2)/8 along its arc; ends when the fit is trusted
 * (observer corrected, open-loop vector started at the estimate) or when
 * probe_ticks have passed (vector at the reference). */
void flux_speed_probe(flux_speed_t *o, const open_start_in_t *in)
{
    const open_start_config_t *c = &o->cfg;
    mc_ab_t p;
    p.alpha = mc_mul_i(mc_sub(o->flux.rho.alpha, o->probe_anchor.alpha), FLUX_SPEED_PROBE_POINT_SCALE);
    p.beta = mc_mul_i(mc_sub(o->flux.rho.beta, o->probe_anchor.beta), FLUX_SPEED_PROBE_POINT_SCALE);
    const mc_t da = mc_sub(p.alpha, o->probe_last.alpha);
    const mc_t db = mc_sub(p.beta, o->probe_last.beta);
    bool found = false;
    if (!mc_lt(mc_dot2(da, da, db, db), c->probe_step2)) {
        flux_circle_fit_add(&o->probe, p);
        o->probe_last = p;
        mc_ab_t centre;
        if (flux_circle_fit_center_origin(&o->probe, &centre)) {
            /* the centre in rho units: anchor + centre / 8 */
            centre.alpha = mc_add(o->probe_anchor.alpha, mc_div_i(centre.alpha, FLUX_SPEED_PROBE_POINT_SCALE));
            centre.beta = mc_add(o->probe_anchor.beta, mc_div_i(centre.beta, FLUX_SPEED_PROBE_POINT_SCALE));
            flux_observer_shift(&o->flux, centre);
            resistance_tracker_unprime(&o->rtrack); /* the angle jumped */
            found = true;
        }
    }
    const mc_t p2 = mc_dot2(p.alpha, p.alpha, p.beta, p.beta);
    if (!o->probe_turned && (!mc_lt(p2, c->probe_turn2) || in->tick + 1u >= c->probe_turn_ticks)) {
        /* along the chord: ahead of the rotor in its direction of motion,
         * for either of the mirror-image angles */
        o->probe_turned = true;
        if (mc_gt(p2, MC_ZERO) && !mc_lt(p2, mc_div_i(c->probe_turn2, 16))) {
            const mc_t k = mc_rsqrt(p2);
            o->probe_dir.c = mc_mul(p.alpha, k);
            o->probe_dir.s = mc_mul(p.beta, k);
        } else {
            o->probe_dir.c = MC_ZERO; /* not moved: the rotor is at 0 or pi, beta moves it */
            o->probe_dir.s = MC_ONE;
        }
    }
    if (found || in->tick + 1u >= c->probe_ticks) {
        /* the open-loop vector starts at the (corrected) estimate; without a
         * fit, at the reference angle */
        const mc_rot_t ref = mc_rot_from_angle(mc_elec_angle(in->ref.theta_rad, c->model.n_p));
        const mc_rot_t minus_ref = {mc_neg(ref.s), ref.c};
        const mc_rot_t at = found ? o->flux.unit : (mc_rot_t){MC_ZERO, MC_ONE};
        o->ol_origin = mc_rot_compose(at, minus_ref);
        o->ol_origin_mech_rad = mc_div_i(mc_atan2(o->ol_origin.s, o->ol_origin.c), c->model.n_p);
        o->ol_theta0_rad = in->ref.theta_rad;
        o->probing = false;
    }
}

static void fs_report(const void *self, const open_start_in_t *in, bool closed, open_start_report_t *r)
{
    const flux_speed_t *o = (const flux_speed_t *)self;
    const int32_t n_p = o->cfg.model.n_p;
    /* (e + 2 pi n)/n_p without forming the sum */
    r->est.theta_rad =
        mc_add(mc_div_i(o->speed.unwrap.e_rad, n_p), mc_mul_i(mc_div_i(MC_TWO_PI, n_p), o->speed.unwrap.n_turns));
    r->est.omega_rad_s = o->speed.omega_rad_s;
    /* (T_e - tau_hat)/J, the model acceleration of (3) */
    const speed_load_observer_config_t *sc = &o->cfg.speed;
    r->est.accel_rad_s2 = mc_mul_i(
        mc_sub(mc_mul(sc->ts_kt_over_J, o->speed.i_q_A), mc_mul(sc->ts_over_J, o->speed.load_Nm)), o->cfg.model.fs_hz);
    r->est.load_Nm = o->speed.load_Nm;
    (void)in;
    r->est.valid = closed;
    r->theta_e_turns = o->speed.unwrap.n_turns;
    r->theta_e_rad = o->speed.unwrap.e_rad;
    r->omega_rad_s = o->speed.omega_rad_s;
    r->load_Nm = o->speed.load_Nm;
    r->rho2 = o->flux.rho2;
    r->R_obs_ohm = o->flux.cfg.R_ohm;
}

static bool fs_init(void *self, const void *cfg)
{
    return flux_speed_init((flux_speed_t *)self, (const open_start_config_t *)cfg);
}

const estimator_ops_t flux_speed_ops = {
    .name = "flux",
    .family = EST_FAMILY_OPEN_START,
    .id = OPEN_START_FLUX,
    .state_bytes = (uint32_t)sizeof(flux_speed_t),
    .needs_angle = false,
    .model_based = false,
    .config_problem = open_start_problem,
    .init = fs_init,
    .report = fs_report,
};
