/* hfi_angle.c - see hfi_angle.h. */
#include "estimators/hfi_angle.h"

/* The first problem of the configuration (estimator.h), NULL if none: the
 * pole pairs, the injection's speeds 0 <= lo < hi <= on < off, the hold's
 * gain >= 0; with hfi_find_angle a lock of at least a sample, its window
 * within it, a positive least amplitude, a polarity test of pulses and
 * rests. */
static const char *hfi_problem(const void *cfg)
{
    const rotor_angle_config_t *c = (const rotor_angle_config_t *)cfg;
    const char *shared = rotor_angle_problem(c);
    if (shared != 0) return shared;
    if (!mc_ge(c->hfi_blend_lo_rad_s, MC_ZERO) || !mc_lt(c->hfi_blend_lo_rad_s, c->hfi_blend_hi_rad_s) ||
        !mc_le(c->hfi_blend_hi_rad_s, c->hfi_on_rad_s) || !mc_lt(c->hfi_on_rad_s, c->hfi_off_rad_s))
        return "hfi_blend_lo_rad_s, hfi_blend_hi_rad_s, hfi_on_rad_s, hfi_off_rad_s: must be 0 <= lo < hi <= on < off";
    if (!mc_ge(c->hfi_hold_gain_per_s, MC_ZERO)) return "hfi_hold_gain_per_s: must be >= 0";
    if (!c->hfi_find_angle) return 0;
    if (c->hfi_lock_ticks < 1) return "hfi_lock_ticks: must be >= 1 (hfi_find_angle)";
    if (c->hfi_lock_window < 1 || c->hfi_lock_window > c->hfi_lock_ticks)
        return "hfi_lock_window: must be in [1, hfi_lock_ticks] (hfi_find_angle)";
    if (!mc_gt(c->hfi_lock_amp_min, MC_ZERO)) return "hfi_lock_amp_min: must be > 0 (hfi_find_angle)";
    if (c->magpol.n_pulse < 1) return "magpol.n_pulse: must be >= 1 (hfi_find_angle)";
    if (c->magpol.n_rest < 1) return "magpol.n_rest: must be >= 1 (hfi_find_angle)";
    if (!mc_gt(c->magpol.v_p_V, MC_ZERO)) return "magpol.v_p_V: must be > 0 (hfi_find_angle)";
    if (!mc_gt(c->magpol.margin_A, MC_ZERO)) return "magpol.margin_A: must be > 0 (hfi_find_angle)";
    return 0;
}

static bool hfi_init(void *self, const void *cfg)
{
    hfi_angle_t *o = (hfi_angle_t *)self;
    const rotor_angle_config_t *c = (const rotor_angle_config_t *)cfg;
    if (hfi_problem(c) != 0) {
        return false;
    }
    o->cfg = *c;
    flux_angle_reset(&o->fa, c);
    const mc_t e0 = mc_elec_angle(c->theta0_rad, c->n_p);
    hf_injection_init(&o->hfi, &c->hfi, e0);
    hf_injection_set_on(&o->hfi, true);
    o->weight = MC_ZERO;
    o->hold_rad = mc_wrap_pi(c->theta0_rad);
    o->phase = c->hfi_find_angle ? HFI_ANGLE_LOCK : HFI_ANGLE_RUN;
    o->start_k = 0;
    o->polarity = 0;
    o->lock_amp = MC_ZERO;
    magnet_polarity_init(&o->magpol, &c->magpol);
    return true;
}

static bool hfi_starting(const void *self) { return ((const hfi_angle_t *)self)->phase != HFI_ANGLE_RUN; }

/* One sample of LOCK: the injection alone, its amplitude averaged over the
 * window at the lock's end; then the test's own rest at 0 V: the injection
 * leaves up to its triangle's 0.17 A (docs/hf_injection.md) in the
 * winding, which in the test's first pulse alone would be a false
 * difference of that size, three times the 55 mA margin (measured: without
 * the rest the test answered -1 from 16 of 16 angles on the plant without
 * the magnet's bias, which has nothing to decide). */
static estimator_start_t hfi_lock(hfi_angle_t *o, mc_ab_t i_ab_A, mc_ab_t *u_ab_V)
{
    const rotor_angle_config_t *c = &o->cfg;
    if (o->start_k < c->hfi_lock_ticks) {
        hf_injection_step(&o->hfi, i_ab_A);
        *u_ab_V = o->hfi.u_h_V;
        hf_injection_hold(&o->hfi, (mc_ab_t){MC_ZERO, MC_ZERO});
        if (o->start_k >= c->hfi_lock_ticks - c->hfi_lock_window) {
            o->lock_amp = mc_add(o->lock_amp, o->hfi.amp);
        }
        if (o->start_k + 1 == c->hfi_lock_ticks) {
            hf_injection_set_on(&o->hfi, false);
            /* locked: the estimate within pi/4 of the d axis, else the
             * test's decision could take the wrong sign */
            o->lock_amp = mc_div_i(o->lock_amp, c->hfi_lock_window);
            if (mc_lt(o->lock_amp, c->hfi_lock_amp_min)) {
                return EST_START_REFUSED;
            }
        }
    }
    o->start_k += 1;
    if (o->start_k >= c->hfi_lock_ticks + c->magpol.n_rest) {
        /* the PLL on the d axis: the test along it */
        magnet_polarity_start(&o->magpol, o->hfi.theta_e_rad);
        o->phase = HFI_ANGLE_POLARITY;
    }
    return EST_START_RUNNING;
}

static estimator_start_t hfi_start(void *self, mc_ab_t i_ab_A, mc_ab_t *u_ab_V, mc_t *theta_e_rad)
{
    hfi_angle_t *o = (hfi_angle_t *)self;
    u_ab_V->alpha = MC_ZERO;
    u_ab_V->beta = MC_ZERO;
    if (o->phase == HFI_ANGLE_LOCK) {
        return hfi_lock(o, i_ab_A, u_ab_V);
    }
    magnet_polarity_step(&o->magpol, i_ab_A);
    *u_ab_V = o->magpol.u_V;
    if (o->magpol.state != MAGPOL_DONE) {
        return EST_START_RUNNING;
    }
    o->polarity = o->magpol.result;
    if (o->polarity == 0) {
        return EST_START_REFUSED; /* undecided: never a start that may run backwards */
    }
    const mc_t e = o->hfi.theta_e_rad;
    *theta_e_rad = (o->polarity > 0) ? e : mc_wrap_pi(mc_add(e, MC_PI));
    return EST_START_DONE;
}

/* At rest at e: the injection on, the observer there, the hold at e/p. */
static void hfi_seed(void *self, mc_t theta_e_rad)
{
    hfi_angle_t *o = (hfi_angle_t *)self;
    hf_injection_init(&o->hfi, &o->cfg.hfi, theta_e_rad);
    hf_injection_set_on(&o->hfi, true);
    flux_angle_seed(&o->fa, theta_e_rad);
    o->weight = MC_ZERO;
    o->hold_rad = mc_div_i(theta_e_rad, o->cfg.n_p);
    o->phase = HFI_ANGLE_RUN;
}

static mc_rot_t hfi_update(void *self, const estimator_in_t *in, mc_ab_t *i_ab_A, estimator_out_t *out)
{
    hfi_angle_t *o = (hfi_angle_t *)self;
    const rotor_angle_config_t *c = &o->cfg;
    flux_observer_t *flux = &o->fa.flux;
    flux_angle_model(&o->fa, in);
    const mc_t w_abs = mc_abs(in->omega_hint_rad_s);
    if (o->hfi.on && mc_gt(w_abs, c->hfi_off_rad_s)) {
        hf_injection_set_on(&o->hfi, false);
    } else if (!o->hfi.on && mc_lt(w_abs, c->hfi_on_rad_s)) {
        hf_injection_set_on(&o->hfi, true);
    }
    if (!o->hfi.on) {
        /* off: the loop follows the observer, to start from it when on */
        hf_injection_track(&o->hfi, mc_atan2(flux->unit.s, flux->unit.c), mc_mul_i(in->omega_hint_rad_s, c->n_p));
    }
    hf_injection_step(&o->hfi, *i_ab_A);
    const mc_ab_t i_f = o->hfi.i_f_A; /* (H5): the fundamental from here on */
    *i_ab_A = i_f;
    flux_observer_step(flux, i_f);
    /* the blend's weight, 0 below lo, 1 above hi */
    const mc_t w =
        mc_clamp(mc_div(mc_sub(w_abs, c->hfi_blend_lo_rad_s), mc_sub(c->hfi_blend_hi_rad_s, c->hfi_blend_lo_rad_s)),
                 MC_ZERO, MC_ONE);
    o->weight = w;
    const mc_t th_h = o->hfi.theta_e_rad; /* the injection's tracked angle (H6) */
    mc_rot_t r;
    if (mc_eq(w, MC_ZERO)) {
        /* the observer knows nothing here: it takes the injection's angle,
         * at the active flux's radius */
        flux_observer_seed(flux, mc_rot_from_angle(th_h), i_f, in->flux_ratio);
        r = mc_rot_from_angle(th_h);
    } else {
        const mc_t th_f = mc_atan2(flux->unit.s, flux->unit.c);
        r = mc_rot_from_angle(mc_wrap_pi(mc_mac(th_h, w, mc_wrap_pi(mc_sub(th_f, th_h)))));
    }
    out->theta_rad = flux_angle_mechanical(&o->fa, r);
    out->lock_checkable = !o->hfi.on; /* the observer's check with the injection off only */
    out->rho2 = flux->rho2;
    out->rho2_target = flux->rho2_target;
    out->u_reserve_V = o->hfi.u_h_amp_V; /* 0 when off */
    return r;
}

static mc_t hfi_weight(const void *self) { return ((const hfi_angle_t *)self)->weight; }

/* The angle hold (header): the held angle follows the integral of the
 * reference, and the drive's angle once the blend is complete. */
static mc_t hfi_reference(void *self, mc_t omega_ref_rad_s, mc_t theta_hat_rad)
{
    hfi_angle_t *o = (hfi_angle_t *)self;
    const rotor_angle_config_t *c = &o->cfg;
    o->hold_rad = mc_wrap_pi(mc_mac(o->hold_rad, omega_ref_rad_s, c->ts_s));
    if (mc_eq(o->weight, MC_ONE)) {
        o->hold_rad = theta_hat_rad;
    }
    const mc_t k = mc_mul(c->hfi_hold_gain_per_s, mc_sub(MC_ONE, o->weight));
    return mc_mac(omega_ref_rad_s, k, mc_wrap_pi(mc_sub(o->hold_rad, theta_hat_rad)));
}

static mc_ab_t hfi_injection(const void *self) { return ((const hfi_angle_t *)self)->hfi.u_h_V; }

static void hfi_hold(void *self, mc_ab_t u_mean_ab_V, mc_ab_t u_cmd_ab_V)
{
    hfi_angle_t *o = (hfi_angle_t *)self;
    flux_observer_hold(&o->fa.flux, u_mean_ab_V);
    hf_injection_hold(&o->hfi, u_cmd_ab_V);
}

const estimator_ops_t hfi_angle_ops = {
    .name = "hfi",
    .family = EST_FAMILY_ROTOR_ANGLE,
    .id = ROTOR_ANGLE_HFI,
    .state_bytes = (uint32_t)sizeof(hfi_angle_t),
    .needs_angle = false,
    .model_based = true,
    .config_problem = hfi_problem,
    .init = hfi_init,
    .starting = hfi_starting,
    .start = hfi_start,
    .seed = hfi_seed,
    .update = hfi_update,
    .model_weight = hfi_weight,
    .reference = hfi_reference,
    .injection = hfi_injection,
    .hold = hfi_hold,
};
