#include "drives/paper002/paper002_drive.h"

#include <stddef.h>

#include "control/delay_comp.h"
#include "supervisor/guard.h"

#include "adapter/phase_adapter.h"
#include "math/frame_fg.h"

/* 1/sqrt(3): the largest phase voltage amplitude with min/max zero
 * sequence is v_bus/sqrt(3) */
#define P002_INV_SQRT3 MC_C(0.57735026918962576)

/* The motor model the blocks start from: the configured one, with
 * cfg.iron saturating the unsaturated iron's L_d, L_q and psi, as at
 * power-up (a re-init after a run gets the configuration with the last
 * secant values). */
static void p002_start_model(const paper002_config_t *cfg, motor_model_t *m)
{
    *m = cfg->model;
    if (iron_model_saturates(&cfg->iron)) {
        m->Ld_H = cfg->iron.Ld0_H;
        m->Lq_H = cfg->iron.Lq0_H;
        m->psi_Wb = cfg->iron.psi_Wb;
    }
}

const char *paper002_config_problem(const paper002_config_t *c)
{
    motor_model_t m;
    p002_start_model(c, &m);
    /* the blocks whose own init checks their configuration, each asked
     * on scratch state (paper002_drive_init inits the drive's own) */
    union {
        ekf_ipmsm_t ekf;
        sosmc_t sosmc;
        htsmc_t htsmc;
        ibcc_t ibcc;
        deadtime_comp_t dtc;
    } scratch;
    if (!ekf_ipmsm_init(&scratch.ekf, &c->ekf, &m))
        return "ekf.q, ekf.r, ekf.p0: must be > 0; or model: R_ohm, Ld_H, Lq_H, J_kgm2, ts_s > 0, psi_Wb, fv_Nm_s >= 0, "
               "n_p >= 1";
    if (!sosmc_init(&scratch.sosmc, &c->sosmc, &m))
        return "sosmc: alpha_0, alpha_I, eps, M_max_Nm must be > 0, eta >= 0";
    if (!htsmc_init(&scratch.htsmc, &c->htsmc, &m))
        return "htsmc: alpha_I, alpha_m, lambda, s0, nu_max, eps, M_max_Nm must be > 0, alpha_M > alpha_m, rho in "
               "(0, 1/2]";
    if (!ibcc_init(&scratch.ibcc, &c->ibcc, &m))
        return "ibcc: lambda_per_s in (0, IBCC_LAMBDA_TS_MAX model.fs_hz], ref_alpha in (0, 1]; or model.fs_hz: must be > 0";
    if (!mc_gt(c->i_trip_A, MC_ZERO)) return "i_trip_A: must be > 0";
    if (!mc_gt(c->los_theta_rad, MC_ZERO)) return "los_theta_rad: must be > 0";
    if (c->los_ticks < 1) return "los_ticks: must be >= 1";
    if (!mc_ge(c->stall_tol, MC_ZERO)) return "stall_tol: must be >= 0";
    if (!mc_gt(c->stall_floor_rad_s, MC_ZERO)) return "stall_floor_rad_s: must be > 0";
    if (c->stall_ticks < 1) return "stall_ticks: must be >= 1";
    if (!mc_ge(c->compute_delay, MC_ZERO) || !mc_le(c->compute_delay, MC_ONE))
        return "compute_delay: must be in [0, 1]";
    if (c->angle_source != P002_ANGLE_ENCODER && c->angle_source != P002_ANGLE_FLUX &&
        c->angle_source != P002_ANGLE_HFI)
        return "angle_source: must be ENCODER, FLUX or HFI";
    if (c->angle_source == P002_ANGLE_HFI) {
        /* the injection's speeds (paper002_drive.h): 0 <= lo < hi <= on < off */
        if (!mc_ge(c->hfi_blend_lo_rad_s, MC_ZERO) || !mc_lt(c->hfi_blend_lo_rad_s, c->hfi_blend_hi_rad_s) ||
            !mc_le(c->hfi_blend_hi_rad_s, c->hfi_on_rad_s) || !mc_lt(c->hfi_on_rad_s, c->hfi_off_rad_s))
            return "hfi_blend_lo_rad_s, hfi_blend_hi_rad_s, hfi_on_rad_s, hfi_off_rad_s: must be 0 <= lo < hi <= on < off";
        if (!mc_ge(c->hfi_hold_gain_per_s, MC_ZERO)) return "hfi_hold_gain_per_s: must be >= 0";
    }
    if (!deadtime_comp_init(&scratch.dtc, &c->deadtime)) return "deadtime: its coefficients must be >= 0";
    if (c->angle_source == P002_ANGLE_HFI && c->hfi_find_angle) {
        if (c->hfi_lock_ticks < 1) return "hfi_lock_ticks: must be >= 1 (hfi_find_angle)";
        if (c->hfi_lock_window < 1 || c->hfi_lock_window > c->hfi_lock_ticks)
            return "hfi_lock_window: must be in [1, hfi_lock_ticks] (hfi_find_angle)";
        if (!mc_gt(c->hfi_lock_amp_min, MC_ZERO)) return "hfi_lock_amp_min: must be > 0 (hfi_find_angle)";
        if (c->magpol.n_pulse < 1) return "magpol.n_pulse: must be >= 1 (hfi_find_angle)";
        if (c->magpol.n_rest < 1) return "magpol.n_rest: must be >= 1 (hfi_find_angle)";
        if (!mc_gt(c->magpol.v_p_V, MC_ZERO)) return "magpol.v_p_V: must be > 0 (hfi_find_angle)";
        if (!mc_gt(c->magpol.margin_A, MC_ZERO)) return "magpol.margin_A: must be > 0 (hfi_find_angle)";
    }
    return NULL;
}

/* Step 0 with cfg.iron saturating (model/iron_model.h), at the EKF's (a
 * priori) currents: the motor model's L_d, L_q, which the EKF, MTPA and
 * the current control read, set to L_i + w (L_s - L_i): the inductances
 * the currents' rates see, (I1), on the injection (w = 0, the handover's
 * last weight), the secant ones (S2) at speed (w = 1; the encoder and
 * flux variants always), where the back-EMF terms w L i want the flux's;
 * its psi to psi_s + (L_ds - L_d) i_d, so that psi + L_d i_d is the
 * secant flux psi_d; the flux observer's L of (14) and the active flux's
 * L_q the secant L_qs. A model whose L is above the iron's incremental
 * one is unstable with the EKF at low speed: a current rising faster
 * than the model's reads as less back-EMF, a lower speed, more torque
 * demanded (a 200-250 Hz limit cycle on the magnet's biased iron, and
 * the incremental values at speed lost synchronism:
 * docs/hf_injection.md). Linear: the configured model, untouched. */
static void p002_iron_step(paper002_drive_t *d)
{
    const paper002_config_t *c = &d->cfg;
    if (!iron_model_saturates(&c->iron)) {
        return;
    }
    motor_model_t *m = &d->cfg.model;
    const mc_t i_d = d->ekf.x[EKF_ID];
    const mc_t i_q = d->ekf.x[EKF_IQ];
    iron_model_point_t pt;
    iron_model_at(&c->iron, i_d, i_q, &pt);
    const mc_t w = (c->angle_source == P002_ANGLE_HFI) ? d->hfi_weight : MC_ONE;
    m->Ld_H = mc_mac(pt.Ldi_H, w, mc_sub(pt.Lds_H, pt.Ldi_H));
    m->Lq_H = mc_mac(pt.Lqi_H, w, mc_sub(pt.Lqs_H, pt.Lqi_H));
    m->psi_Wb = mc_mac(pt.psi_s_Wb, mc_sub(pt.Lds_H, m->Ld_H), i_d);
    d->iron_Lqs_H = pt.Lqs_H;
    flux_observer_set_L(&d->flux, mc_mul(c->flux.L_fs_ohm, mc_div(d->iron_Lqs_H, c->iron.Lq0_H)));
}

/* angle_source = FLUX, HFI: the gradient term's target, the active flux's
 * radius psi + (L_d - L_q) i_d at the EKF's i_d (with the iron's secant
 * values of step 0, model/iron_model.h (A1)) relative to the observer's
 * psi, squared; the ratio is returned (the seed's radius). */
static mc_t p002_active_flux(paper002_drive_t *d)
{
    const paper002_config_t *c = &d->cfg;
    const motor_model_t *m = &c->model;
    mc_t ratio;
    if (iron_model_saturates(&c->iron)) {
        /* psi_s + (L_ds - L_qs) i_d (A1): the model's psi + L_d i_d is psi_s + L_ds i_d (step 0) */
        const mc_t radius_Wb = mc_mac(m->psi_Wb, mc_sub(m->Ld_H, d->iron_Lqs_H), d->ekf.x[EKF_ID]);
        ratio = mc_div(radius_Wb, c->iron.psi_Wb);
    } else {
        ratio = mc_add(MC_ONE, mc_div(mc_mul(mc_sub(m->Ld_H, m->Lq_H), d->ekf.x[EKF_ID]), m->psi_Wb));
    }
    flux_observer_set_target(&d->flux, mc_mul(ratio, ratio));
    return ratio;
}

/* angle_source = HFI, step 1: the injection on or off by the EKF's speed
 * (hysteresis), one step of it (the fundamental current, H5, back in
 * *i_ab), the flux observer on the fundamental, and the blended electrical
 * angle. */
static mc_rot_t p002_hfi_angle(paper002_drive_t *d, mc_ab_t *i_ab)
{
    const paper002_config_t *c = &d->cfg;
    const motor_model_t *m = &c->model;
    const mc_t w_abs = mc_abs(d->ekf.x[EKF_OMEGA]);
    if (d->hfi.on && mc_gt(w_abs, c->hfi_off_rad_s)) {
        hf_injection_set_on(&d->hfi, false);
    } else if (!d->hfi.on && mc_lt(w_abs, c->hfi_on_rad_s)) {
        hf_injection_set_on(&d->hfi, true);
    }
    if (!d->hfi.on) {
        /* off: the loop follows the observer, to start from it when on */
        hf_injection_track(&d->hfi, mc_atan2(d->flux.unit.s, d->flux.unit.c),
                           mc_mul_i(d->ekf.x[EKF_OMEGA], m->n_p));
    }
    hf_injection_step(&d->hfi, *i_ab);
    *i_ab = d->hfi.i_f_A;
    /* the flux observer on the fundamental, on the active flux as the
     * flux variant's */
    const mc_t ratio = p002_active_flux(d);
    flux_observer_step(&d->flux, *i_ab);
    /* the blend's weight, 0 below lo, 1 above hi */
    const mc_t w = mc_clamp(mc_div(mc_sub(w_abs, c->hfi_blend_lo_rad_s),
                                   mc_sub(c->hfi_blend_hi_rad_s, c->hfi_blend_lo_rad_s)),
                            MC_ZERO, MC_ONE);
    d->hfi_weight = w;
    /* the injection's tracked angle (H6) */
    const mc_t th_h = d->hfi.theta_e_rad;
    if (mc_eq(w, MC_ZERO)) {
        /* the observer knows nothing here: it takes the injection's
         * angle, at the active flux's radius */
        flux_observer_seed(&d->flux, mc_rot_from_angle(th_h), *i_ab, ratio);
        return mc_rot_from_angle(th_h);
    }
    const mc_t th_f = mc_atan2(d->flux.unit.s, d->flux.unit.c);
    return mc_rot_from_angle(mc_wrap_pi(mc_mac(th_h, w, mc_wrap_pi(mc_sub(th_f, th_h)))));
}

/* angle_source = HFI, step 3: the angle hold (paper002_drive.h). The held
 * angle follows the integral of w_d, and the EKF's angle once the blend is
 * complete; the correction k (1 - w) wrap(hold - theta_hat) is added to
 * the speed reference. */
static mc_t p002_hfi_hold(paper002_drive_t *d, mc_t w_d)
{
    const paper002_config_t *c = &d->cfg;
    const mc_t th = d->ekf.x[EKF_THETA];
    d->hfi_hold_rad = mc_wrap_pi(mc_mac(d->hfi_hold_rad, w_d, c->model.ts_s));
    if (mc_eq(d->hfi_weight, MC_ONE)) {
        d->hfi_hold_rad = th;
    }
    const mc_t k = mc_mul(c->hfi_hold_gain_per_s, mc_sub(MC_ONE, d->hfi_weight));
    return mc_mac(w_d, k, mc_wrap_pi(mc_sub(d->hfi_hold_rad, th)));
}

/* The EKF's angle is kept in [-pi, pi) (estimators/ekf_ipmsm.h); the
 * estimate's is unwrapped: a step of the angle beyond pi is a wrap, a
 * turn (|w| Ts < pi, far above any speed the drive runs at). */
static void p002_count_turns(paper002_drive_t *d, mc_t theta_rad)
{
    const mc_t step = mc_sub(theta_rad, d->theta_prev_rad);
    if (mc_gt(mc_abs(step), MC_PI)) {
        d->theta_turns += mc_lt(step, MC_ZERO) ? 1 : -1;
    }
    d->theta_prev_rad = theta_rad;
}

bool paper002_drive_init(paper002_drive_t *d, const paper002_config_t *cfg)
{
    d->cfg = *cfg;
    p002_start_model(cfg, &d->cfg.model);
    d->iron_Lqs_H = d->cfg.model.Lq_H;
    guard_start_closed_loop(&d->sup);
    flight_recorder_init(&d->rec);
    d->tick = 0;
    d->los.run = 0;
    d->stall.run = 0;
    lock_monitor_init(&d->lock, &cfg->lock);
    d->u_ab_prev_V.alpha = MC_ZERO;
    d->u_ab_prev_V.beta = MC_ZERO;
    d->reference = cfg->reference;
    d->disabled = false;
    d->v_bus_V = MC_ZERO;
    d->theta_ref_rad = MC_ZERO;
    const motor_model_t *m = &d->cfg.model;
    d->stop_ramp_rad_s2 = mc_div(mc_mul(mc_mul_i(mc_mul(MC_C(1.5), m->psi_Wb), m->n_p), cfg->mtpa.i_max_A),
                                 mc_mul_i(m->J_kgm2, 4));
    fault_monitor_init(&d->mon, &cfg->faults);
    /* every block's state; whether cfg is consistent: paper002_config_problem, below */
    (void)ekf_ipmsm_init(&d->ekf, &cfg->ekf, m);
    (void)sosmc_init(&d->sosmc, &cfg->sosmc, m);
    (void)htsmc_init(&d->htsmc, &cfg->htsmc, m);
    (void)ibcc_init(&d->ibcc, &cfg->ibcc, m);
    (void)deadtime_comp_init(&d->dtc, &cfg->deadtime);
    d->theta_prev_rad = d->ekf.x[EKF_THETA];
    d->theta_turns = 0;
    const mc_ab_t i0 = {MC_ZERO, MC_ZERO};
    const mc_t e0 = mc_elec_angle(cfg->flux_theta0_rad, m->n_p);
    flux_observer_init(&d->flux, &cfg->flux, mc_rot_from_angle(e0), i0);
    angle_unwrap_init(&d->unwrap, e0);
    hf_injection_init(&d->hfi, &cfg->hfi, e0);
    hf_injection_set_on(&d->hfi, cfg->angle_source == P002_ANGLE_HFI);
    d->hfi_weight = MC_ZERO;
    d->hfi_hold_rad = mc_wrap_pi(cfg->flux_theta0_rad);
    /* the electrical angle fixes the mechanical one up to 2 pi/p: the
     * start's turn among the p is kept as an offset */
    d->theta_offset_rad = mc_sub(mc_wrap_pi(cfg->flux_theta0_rad), mc_div_i(e0, m->n_p));
    const bool find = cfg->angle_source == P002_ANGLE_HFI && cfg->hfi_find_angle;
    d->start_phase = find ? P002_START_LOCK : P002_START_RUN;
    d->start_k = 0;
    d->polarity = 0;
    d->hfi_lock_amp = MC_ZERO;
    magnet_polarity_init(&d->magpol, &cfg->magpol);
    if (paper002_config_problem(cfg) != NULL) {
        guard_latch(&d->sup, &d->rec, DRIVE_FAULT_BAD_INPUT, d->tick);
        return false;
    }
    return true;
}

static bool p002_zero(paper002_drive_t *d, hal_command_t *out)
{
    guard_zero(out, 3u);
    d->tick += 1u;
    return false;
}

/* A fault only the safe state answers: latched with its sample, 0 V out. */
static bool p002_trip(paper002_drive_t *d, drive_fault_t f, hal_command_t *out)
{
    guard_latch(&d->sup, &d->rec, f, d->tick);
    return p002_zero(d, out);
}

/* A fault: recorded, then the reaction table (supervisor/guard.h; no
 * re-lock). True when the drive is now in FAULT (0 V out, the sample
 * counted); false: REPORT, the sample goes on. */
static bool p002_fault(paper002_drive_t *d, drive_fault_t f, hal_command_t *out)
{
    if (guard_react(&d->sup, &d->rec, d->cfg.reaction, f, d->tick, false) != GUARD_SAFE) {
        return false;
    }
    (void)p002_zero(d, out);
    return true;
}

/* hfi_find_angle, the end of the start (paper002_drive.h, step 3): the
 * injection, the flux observer, the angle's unwrapping and the EKF
 * restarted at the electrical angle e found, the mechanical e/p (offset 0:
 * the turn among the n_p is unknown), the hold there. */
static void p002_start_at(paper002_drive_t *d, mc_t e)
{
    const paper002_config_t *c = &d->cfg;
    const motor_model_t *m = &c->model;
    const mc_ab_t i0 = {MC_ZERO, MC_ZERO};
    hf_injection_init(&d->hfi, &c->hfi, e);
    hf_injection_set_on(&d->hfi, true);
    flux_observer_init(&d->flux, &c->flux, mc_rot_from_angle(e), i0);
    angle_unwrap_init(&d->unwrap, e);
    d->theta_offset_rad = MC_ZERO;
    ekf_ipmsm_config_t ec = c->ekf;
    ec.x0[EKF_THETA] = mc_div_i(e, m->n_p);
    (void)ekf_ipmsm_init(&d->ekf, &ec, m); /* the same configuration init accepted, one angle changed */
    /* the estimate's angle starts again there: no turn */
    d->theta_prev_rad = d->ekf.x[EKF_THETA];
    d->hfi_weight = MC_ZERO;
    d->hfi_hold_rad = ec.x0[EKF_THETA];
    d->los.run = 0;
    d->stall.run = 0;
    lock_monitor_init(&d->lock, &c->lock);
    d->u_ab_prev_V = i0;
    d->start_phase = P002_START_RUN;
}

/* hfi_find_angle, one sample of the start's LOCK or POLARITY phase
 * (paper002_drive.h): no current command, the speed loop open. */
static bool p002_start_step(paper002_drive_t *d, const hal_sample_t *in, mc_ab_t i_ab, hal_command_t *out)
{
    const paper002_config_t *c = &d->cfg;
    mc_ab_t u = {MC_ZERO, MC_ZERO};
    if (d->start_phase == P002_START_LOCK) {
        if (d->start_k < c->hfi_lock_ticks) {
            hf_injection_step(&d->hfi, i_ab);
            u = d->hfi.u_h_V;
            hf_injection_hold(&d->hfi, (mc_ab_t){MC_ZERO, MC_ZERO});
            if (d->start_k >= c->hfi_lock_ticks - c->hfi_lock_window) {
                d->hfi_lock_amp = mc_add(d->hfi_lock_amp, d->hfi.amp);
            }
            if (d->start_k + 1 == c->hfi_lock_ticks) {
                hf_injection_set_on(&d->hfi, false);
                /* locked: the estimate within pi/4 of the d axis, else
                 * the test's decision could take the wrong sign */
                d->hfi_lock_amp = mc_div_i(d->hfi_lock_amp, c->hfi_lock_window);
                if (mc_lt(d->hfi_lock_amp, c->hfi_lock_amp_min)) {
                    return p002_trip(d, DRIVE_FAULT_LOSS_OF_LOCK, out);
                }
            }
        }
        /* then the test's own rest at 0 V: the injection leaves up to its
         * triangle's 0.17 A (docs/hf_injection.md) in the winding, which in
         * the test's first pulse alone would be a false difference of that
         * size, three times the 55 mA margin (measured: without the rest the
         * test answered -1 from 16 of 16 angles on the plant without the
         * magnet's bias, which has nothing to decide) */
        d->start_k += 1;
        if (d->start_k >= c->hfi_lock_ticks + c->magpol.n_rest) {
            /* the PLL on the d axis: the test along it */
            magnet_polarity_start(&d->magpol, d->hfi.theta_e_rad);
            d->start_phase = P002_START_POLARITY;
        }
    } else {
        magnet_polarity_step(&d->magpol, i_ab);
        u = d->magpol.u_V;
        if (d->magpol.state == MAGPOL_DONE) {
            d->polarity = d->magpol.result;
            if (d->polarity == 0) {
                /* undecided: never a start that may run backwards */
                return p002_trip(d, DRIVE_FAULT_LOSS_OF_LOCK, out);
            }
            const mc_t e = d->hfi.theta_e_rad;
            p002_start_at(d, (d->polarity > 0) ? e : mc_wrap_pi(mc_add(e, MC_PI)));
        }
    }
    phase_adapter_voltages(3u, u, out);
    const drive_fault_t f_out = fault_monitor_command(&d->mon, out, false);
    guard_record(&d->rec, d->tick, d->sup.state, in, out, MC_ZERO, d->ekf.x[EKF_THETA], d->ekf.x[EKF_OMEGA]);
    if (f_out != DRIVE_FAULT_NONE && p002_fault(d, f_out, out)) {
        return false;
    }
    d->tick += 1u;
    return true;
}

bool paper002_drive_step(paper002_drive_t *d, const hal_sample_t *in, hal_command_t *out)
{
    const paper002_config_t *c = &d->cfg;
    const motor_model_t *m = &c->model;
    if (d->sup.state == SUP_STATE_FAULT) {
        return p002_zero(d, out);
    }
    if (d->disabled) {
        (void)p002_zero(d, out); /* 0 V, the sample counted; not a fault (drives/drive.h) */
        return true;
    }
    d->v_bus_V = in->v_bus_V;
    const bool flux = c->angle_source == P002_ANGLE_FLUX;
    const bool hfi = c->angle_source == P002_ANGLE_HFI;
    if (!phase_adapter_accepts(in, 3u) || (!flux && !hfi && !in->has_angle)) {
        return p002_trip(d, DRIVE_FAULT_BAD_INPUT, out);
    }
    const drive_fault_t f_in = fault_monitor_sample(&d->mon, in, 3u);
    if (f_in != DRIVE_FAULT_NONE && p002_fault(d, f_in, out)) {
        return false;
    }
    /* 1. d-q currents with the encoder's electrical angle, or the flux
     * observer's */
    mc_t i_zero;
    mc_ab_t i_ab = phase_adapter_currents(in, &i_zero);
    (void)i_zero;
    if (d->start_phase != P002_START_RUN) {
        return p002_start_step(d, in, i_ab, out);
    }
    /* 0. the saturating iron's inductances at the EKF's currents */
    p002_iron_step(d);
    mc_rot_t r_meas;
    mc_t theta_meas;
    if (flux || hfi) {
        if (hfi) {
            /* the injection's angle blended into the observer's; the
             * fundamental current from here on */
            r_meas = p002_hfi_angle(d, &i_ab);
        } else {
            (void)p002_active_flux(d);
            flux_observer_step(&d->flux, i_ab);
            r_meas = d->flux.unit;
        }
        angle_unwrap_step(&d->unwrap, r_meas.s, r_meas.c);
        /* the mechanical angle: (e + 2 pi n)/p, with n taken modulo p first
         * (n p-fold is a whole mechanical turn) so the sum stays small */
        const int32_t p = m->n_p;
        const int32_t n_mod = ((d->unwrap.n_turns % p) + p) % p;
        theta_meas = mc_wrap_pi(mc_add(mc_div_i(mc_add(d->unwrap.e_rad, mc_mul_i(MC_TWO_PI, n_mod)), p), d->theta_offset_rad));
    } else {
        theta_meas = in->angle_rad;
        r_meas = mc_rot_from_angle(mc_elec_angle(in->angle_rad, m->n_p));
    }
    mc_t i_d, i_q;
    mc_rot_fwd(r_meas, i_ab.alpha, i_ab.beta, &i_d, &i_q);
    /* 2. the EKF's correction; sensorless, the angle innovation's variance
     * S = P^-_thth + r_th first (the a priori covariance, C = [I_3 0]: the
     * angle is measurement 2 and state 2), for the loss of lock below */
    const mc_t s_theta_rad2 = (flux || hfi) ? mc_add(d->ekf.P[EKF_THETA][EKF_THETA], d->ekf.cfg.r[EKF_THETA]) : MC_ZERO;
    const bool corrected = ekf_ipmsm_correct(&d->ekf, i_d, i_q, theta_meas);
    mc_t w_d, dw_d;
    speed_poly_eval(&d->reference, d->tick, &w_d, &dw_d);
    d->theta_ref_rad = mc_wrap_pi(mc_mac(d->theta_ref_rad, w_d, m->ts_s));
    const bool lost = fault_persist_step(&d->los, !mc_le(mc_abs(d->ekf.innovation[2]), c->los_theta_rad), c->los_ticks);
    const mc_t stall_band = mc_mac(c->stall_floor_rad_s, c->stall_tol, mc_abs(w_d));
    const bool stalled =
        fault_persist_step(&d->stall, !mc_le(mc_abs(mc_sub(d->ekf.x[EKF_OMEGA], w_d)), stall_band), c->stall_ticks);
    if ((!corrected || lost || stalled) && p002_fault(d, DRIVE_FAULT_LOSS_OF_SYNC, out)) {
        return false;
    }
    /* the sensorless variant's loss of lock (supervisor/lock_monitor.h),
     * two named criteria, each stepped every sample: the flux observer's
     * residual along its rotor axis, gPhi3 |target - |rho|^2| of (12),
     * against the tolerance bound at the EKF's speed and the current in
     * the observer's frame (a steady drift); and the EKF's angle
     * innovation against 6 sigma of its noise and the stall band's speed
     * error over a sample, by a leaky count (the limit cycle and the flips
     * of this variant's losses, docs/paper002.md). Only for the flux
     * angle: the encoder's is measured (the EKF's innovation above checks
     * it). With the injection (HFI) only while it is off, the flux
     * observer's angle then in use. No product of its own here; float
     * only, as the drive (the fixed-point build refuses paper 002's
     * design, docs/paper002.md). */
    if (flux || (hfi && !d->hfi.on)) {
        const lock_criterion_t by_flux =
            lock_monitor_step_flux(&d->lock, d->flux.rho2, d->flux.rho2_target, d->ekf.x[EKF_OMEGA], i_d, i_q);
        const lock_criterion_t by_innov =
            lock_monitor_step_innovation(&d->lock, d->ekf.innovation[EKF_THETA], s_theta_rad2, stall_band);
        if ((by_flux != LOCK_CRIT_NONE || by_innov != LOCK_CRIT_NONE) &&
            p002_fault(d, DRIVE_FAULT_LOSS_OF_LOCK, out)) {
            return false;
        }
    }
    d->last.theta_meas_rad = theta_meas;
    const mc_t *x = d->ekf.x;
    d->last.i_d_hat_A = x[EKF_ID];
    d->last.i_q_hat_A = x[EKF_IQ];
    d->last.theta_hat_rad = x[EKF_THETA];
    p002_count_turns(d, x[EKF_THETA]);
    d->last.w_hat_rad_s = x[EKF_OMEGA];
    d->last.M0_hat_Nm = x[EKF_M0];
    /* 3. reference and torque demand; with the injection, the hold's
     * correction on the speed reference */
    const mc_t w_c = hfi ? p002_hfi_hold(d, w_d) : w_d;
    const mc_t M_d = (c->controller == P002_SOSMC)
                         ? sosmc_step(&d->sosmc, &c->sosmc, m, w_c, dw_d, x[EKF_OMEGA], ekf_ipmsm_accel(&d->ekf, m),
                                      x[EKF_M0])
                         : htsmc_step(&d->htsmc, &c->htsmc, m, w_c, dw_d, x[EKF_OMEGA], x[EKF_M0]);
    /* 4. MTPA */
    mtpa_out_t ref;
    mtpa_step(&c->mtpa, m, M_d, &ref);
    /* 5. current control on the EKF's currents and speed */
    mc_t u_max = mc_mul(in->v_bus_V, P002_INV_SQRT3);
    if (hfi) {
        /* the injection's share of the voltage kept free (0 when off) */
        u_max = mc_max(MC_ZERO, mc_sub(u_max, d->hfi.u_h_amp_V));
    }
    ibcc_out_t u_dq;
    ibcc_step(&d->ibcc, &c->ibcc, m, ref.i_d_A, ref.i_q_A, x[EKF_ID], x[EKF_IQ], x[EKF_OMEGA], u_max, &u_dq);
    const mc_t u_d = u_dq.u_d_V, u_q = u_dq.u_q_V;
    /* 6. back to alpha-beta at the angle the voltage acts around: the
     * estimate advanced to the middle of the sample it acts over, (1/2 +
     * d) Ts ahead */
    const mc_t half_ts = mc_div_i(m->ts_s, 2);
    const mc_t lead = mc_mac(half_ts, c->compute_delay, m->ts_s);
    const mc_t th_el = mc_elec_angle(mc_mac(x[EKF_THETA], lead, x[EKF_OMEGA]), m->n_p);
    const mc_rot_t rot_out = mc_rot_from_angle(th_el); /* also the compensation's way back */
    mc_ab_t u_ab;
    mc_rot_inv(rot_out, u_d, u_q, &u_ab.alpha, &u_ab.beta);
    if (hfi) {
        /* the injection on top of the command (0 when off, but for its
         * stop pulse); the estimators see the command alone */
        const mc_ab_t u_out = {mc_add(u_ab.alpha, d->hfi.u_h_V.alpha), mc_add(u_ab.beta, d->hfi.u_h_V.beta)};
        phase_adapter_voltages(3u, u_out, out);
    } else {
        phase_adapter_voltages(3u, u_ab, out);
    }
    /* the inverter's expected error added to the command; what the bus
     * clamp takes of it is in the voltage the estimators use */
    mc_t u_d_est = u_d, u_q_est = u_q;
    if (d->dtc.cfg.enabled) {
        const mc_ab_t clamped = deadtime_comp_step(&d->dtc, in->i_A, in->v_bus_V, out);
        u_ab.alpha = mc_add(u_ab.alpha, clamped.alpha);
        u_ab.beta = mc_add(u_ab.beta, clamped.beta);
        mc_rot_fwd(rot_out, u_ab.alpha, u_ab.beta, &u_d_est, &u_q_est);
    }
    /* 7. the EKF's prediction with the voltage the motor sees over the
     * coming sample (and the flux observer's): this command, or with a
     * delay the mean (1 - d) u + d u_prev, brought into the frame of the
     * sample's middle */
    if (mc_eq(c->compute_delay, MC_ZERO)) {
        flux_observer_hold(&d->flux, u_ab);
        ekf_ipmsm_predict(&d->ekf, m, u_d_est, u_q_est);
    } else {
        const mc_ab_t u_mean = delay_applied_mean(c->compute_delay, u_ab, d->u_ab_prev_V);
        flux_observer_hold(&d->flux, u_mean);
        const mc_t th_mid = mc_elec_angle(mc_mac(x[EKF_THETA], half_ts, x[EKF_OMEGA]), m->n_p);
        mc_t u_d_mean, u_q_mean;
        mc_rot_fwd(mc_rot_from_angle(th_mid), u_mean.alpha, u_mean.beta, &u_d_mean, &u_q_mean);
        ekf_ipmsm_predict(&d->ekf, m, u_d_mean, u_q_mean);
    }
    d->u_ab_prev_V = u_ab;
    if (hfi) {
        hf_injection_hold(&d->hfi, u_ab);
    }
    d->last.w_d_rad_s = w_d;
    d->last.M_d_Nm = M_d;
    d->last.i_dd_A = ref.i_d_A;
    d->last.i_qd_A = ref.i_q_A;
    d->last.i_d_A = i_d;
    d->last.i_q_A = i_q;
    d->last.u_d_V = u_d;
    d->last.u_q_V = u_q;
    d->last.saturated = d->ibcc.saturated;
    const drive_fault_t f_out = fault_monitor_command(&d->mon, out, d->ibcc.saturated);
    guard_record(&d->rec, d->tick, d->sup.state, in, out, w_d, x[EKF_THETA], x[EKF_OMEGA]);
    if (f_out != DRIVE_FAULT_NONE && p002_fault(d, f_out, out)) {
        return false;
    }
    d->tick += 1u;
    return true;
}

bool paper002_drive_set_enabled(paper002_drive_t *d, bool on)
{
    if (d->sup.state == SUP_STATE_FAULT || on == !d->disabled) {
        return false;
    }
    if (on) {
        const paper002_config_t cfg = d->cfg;
        return paper002_drive_init(d, &cfg);
    }
    d->disabled = true;
    return true;
}

bool paper002_drive_set_speed(paper002_drive_t *d, mc_t omega_rad_s, mc_t ramp_rad_s2)
{
    const paper002_config_t *c = &d->cfg;
    if (d->disabled || d->sup.state == SUP_STATE_FAULT || !mc_gt(ramp_rad_s2, MC_ZERO)) {
        return false;
    }
    /* the back-EMF p psi |w| within a share of v_bus/sqrt(3) */
    const motor_model_t *m = &c->model;
    const mc_t k_e = mc_mul_i(m->psi_Wb, m->n_p);
    if (mc_gt(mc_mul(k_e, mc_abs(omega_rad_s)), mc_mul(P002_CMD_VOLTAGE_SHARE, mc_mul(d->v_bus_V, P002_INV_SQRT3)))) {
        return false;
    }
    /* the ramp within K_t i_max / J */
    const mc_t a_max = mc_div(mc_mul(mc_mul(MC_C(1.5), k_e), c->mtpa.i_max_A), m->J_kgm2);
    if (mc_gt(ramp_rad_s2, a_max)) {
        return false;
    }
    mc_t w_now, dw_now;
    speed_poly_eval(&d->reference, d->tick, &w_now, &dw_now);
    (void)dw_now;
    /* T = 1.875 |dw| / ramp, at least a sample */
    const mc_t t_s = mc_div(mc_mul(P002_POLY_PEAK_OVER_MEAN, mc_abs(mc_sub(omega_rad_s, w_now))), ramp_rad_s2);
    int32_t n = mc_round_i(mc_mul_i(t_s, m->fs_hz)) + 1;
    if (n < 1) {
        n = 1;
    }
    speed_poly_t next;
    if (!speed_poly_init(&next, d->tick, d->tick + (uint32_t)n, w_now, omega_rad_s, m->fs_hz)) {
        return false;
    }
    d->reference = next;
    d->stop_ramp_rad_s2 = ramp_rad_s2;
    return true;
}

bool paper002_drive_stop(paper002_drive_t *d) { return paper002_drive_set_speed(d, MC_ZERO, d->stop_ramp_rad_s2); }

bool paper002_drive_clear_fault(paper002_drive_t *d)
{
    if (d->sup.state != SUP_STATE_FAULT) {
        return false;
    }
    const paper002_config_t cfg = d->cfg;
    return paper002_drive_init(d, &cfg);
}
