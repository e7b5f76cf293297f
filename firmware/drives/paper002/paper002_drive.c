/*
 * paper002_drive.c - paper 002's drive as a recipe (see paper002_drive.h):
 * the angle from the estimator cfg.angle_source names
 * (estimators/estimator.h: an encoder, the flux observer, the HF
 * injection), the EKF, the speed law, MTPA, the current control.
 */
#include "drives/paper002/paper002_drive.h"

#include <stddef.h>

#include "control/delay_comp.h"
#include "supervisor/guard.h"

#include "adapter/phase_adapter.h"
#include "math/frame_fg.h"

/* 1/sqrt(3): the largest phase voltage amplitude with min/max zero
 * sequence is v_bus/sqrt(3) */
#define P002_INV_SQRT3 MC_C(0.57735026918962576)

/* The angle estimators' configuration from the drive's (one type for all
 * of them: estimators/rotor_angle.h). */
static void p002_angle_config(const paper002_config_t *c, rotor_angle_config_t *a)
{
    a->n_p = c->model.n_p;
    a->ts_s = c->model.ts_s;
    a->theta0_rad = c->flux_theta0_rad;
    a->flux = c->flux;
    a->hfi = c->hfi;
    a->hfi_blend_lo_rad_s = c->hfi_blend_lo_rad_s;
    a->hfi_blend_hi_rad_s = c->hfi_blend_hi_rad_s;
    a->hfi_off_rad_s = c->hfi_off_rad_s;
    a->hfi_on_rad_s = c->hfi_on_rad_s;
    a->hfi_hold_gain_per_s = c->hfi_hold_gain_per_s;
    a->hfi_find_angle = c->hfi_find_angle;
    a->hfi_lock_ticks = c->hfi_lock_ticks;
    a->hfi_lock_window = c->hfi_lock_window;
    a->hfi_lock_amp_min = c->hfi_lock_amp_min;
    a->magpol = c->magpol;
}

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
    if (!deadtime_comp_init(&scratch.dtc, &c->deadtime)) return "deadtime: its coefficients must be >= 0";
    /* the angle's estimator: its number, then its own configuration */
    const estimator_ops_t *e = estimator_find(EST_FAMILY_ROTOR_ANGLE, (uint32_t)c->angle_source);
    if (e == NULL) return "angle_source: no rotor-angle estimator of that number (0 encoder, 1 flux, 2 hfi)";
    rotor_angle_config_t ac;
    p002_angle_config(c, &ac);
    return e->config_problem ? e->config_problem(&ac) : NULL;
}

/* Step 0 with cfg.iron saturating (model/iron_model.h), at the EKF's (a
 * priori) currents: the motor model's L_d, L_q, which the EKF, MTPA and
 * the current control read, set to L_i + w (L_s - L_i): the inductances
 * the currents' rates see, (I1), on the injection (w = 0, the estimator's
 * model weight of the last sample: the handover's), the secant ones (S2)
 * at speed (w = 1; an estimator without an injection always), where the
 * back-EMF terms w L i want the flux's; its psi to psi_s + (L_ds - L_d)
 * i_d, so that psi + L_d i_d is the secant flux psi_d; the flux observer's
 * L of (14) and the active flux's L_q the secant L_qs. A model whose L is above the iron's
 * incremental one is unstable with the EKF at low speed: a current rising
 * faster than the model's reads as less back-EMF, a lower speed, more
 * torque demanded (a 200-250 Hz limit cycle on the magnet's biased iron,
 * and the incremental values at speed lost synchronism:
 * docs/hf_injection.md). Returns L_qs / L_q0 for a model-based estimator;
 * linear: the configured model, untouched, and 0. */
static mc_t p002_iron_step(paper002_drive_t *d, const estimator_ops_t *e)
{
    const paper002_config_t *c = &d->cfg;
    if (!iron_model_saturates(&c->iron)) {
        return MC_ZERO;
    }
    motor_model_t *m = &d->cfg.model;
    const mc_t i_d = d->ekf.x[EKF_ID];
    const mc_t i_q = d->ekf.x[EKF_IQ];
    iron_model_point_t pt;
    iron_model_at(&c->iron, i_d, i_q, &pt);
    const mc_t w = e->model_weight ? e->model_weight(&d->est_state) : MC_ONE;
    m->Ld_H = mc_mac(pt.Ldi_H, w, mc_sub(pt.Lds_H, pt.Ldi_H));
    m->Lq_H = mc_mac(pt.Lqi_H, w, mc_sub(pt.Lqs_H, pt.Lqi_H));
    m->psi_Wb = mc_mac(pt.psi_s_Wb, mc_sub(pt.Lds_H, m->Ld_H), i_d);
    d->iron_Lqs_H = pt.Lqs_H;
    return e->model_based ? mc_div(d->iron_Lqs_H, c->iron.Lq0_H) : MC_ZERO;
}

/* A model-based estimator's flux radius: the active flux's, psi + (L_d -
 * L_q) i_d at the EKF's i_d (with the iron's secant values of step 0,
 * model/iron_model.h (A1)), relative to the observer's psi. */
static mc_t p002_active_flux(const paper002_drive_t *d)
{
    const paper002_config_t *c = &d->cfg;
    const motor_model_t *m = &c->model;
    if (iron_model_saturates(&c->iron)) {
        /* psi_s + (L_ds - L_qs) i_d (A1): the model's psi + L_d i_d is psi_s + L_ds i_d (step 0) */
        const mc_t radius_Wb = mc_mac(m->psi_Wb, mc_sub(m->Ld_H, d->iron_Lqs_H), d->ekf.x[EKF_ID]);
        return mc_div(radius_Wb, c->iron.psi_Wb);
    }
    return mc_add(MC_ONE, mc_div(mc_mul(mc_sub(m->Ld_H, m->Lq_H), d->ekf.x[EKF_ID]), m->psi_Wb));
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
    /* the angle's estimator, found by the number the configuration holds */
    d->est = estimator_find(EST_FAMILY_ROTOR_ANGLE, (uint32_t)cfg->angle_source);
    rotor_angle_config_t ac;
    p002_angle_config(cfg, &ac);
    const bool ok_est = d->est != 0 && d->est->init(&d->est_state, &ac);
    d->starting = ok_est && d->est->starting && d->est->starting(&d->est_state);
    if (!ok_est || paper002_config_problem(cfg) != NULL) {
        guard_latch(&d->sup, &d->rec, DRIVE_FAULT_BAD_INPUT, d->tick);
        return false;
    }
    return true;
}

/* A sample the drive runs on: with the angle its estimator needs (an
 * encoder's; beyond the phase count, the shell's). */
static bool p002_accepts(const void *self, const hal_sample_t *in)
{
    const paper002_drive_t *d = (const paper002_drive_t *)self;
    return !(d->est->needs_angle && !in->has_angle);
}

/* The shell of this drive's step (supervisor/guard.h): three phases, its
 * own check of a sample, its reaction table, no re-lock (RELOCK acts as
 * SAFE), every step counted (the 0 V ones too; a fault found by a sample's
 * last checks recorded at that sample's tick). */
static const guard_shell_t p002_shell = {
    .sup = offsetof(paper002_drive_t, sup),
    .mon = offsetof(paper002_drive_t, mon),
    .rec = offsetof(paper002_drive_t, rec),
    .tick = offsetof(paper002_drive_t, tick),
    .disabled = offsetof(paper002_drive_t, disabled),
    .reaction = offsetof(paper002_drive_t, cfg.reaction),
    .n_phases = 3u,
    .accepts = p002_accepts,
    .check = NULL,
    .relock = NULL,
    .stopped = NULL,
    .ticks = GUARD_TICK_EVERY,
};

/* The end of the estimator's start (hfi_find_angle): it, the EKF and the
 * drive's monitors restarted at the electrical angle e found, the
 * mechanical e/p (the turn among the n_p is unknown, of no matter to a
 * speed drive). */
static void p002_start_at(paper002_drive_t *d, mc_t e)
{
    const paper002_config_t *c = &d->cfg;
    const motor_model_t *m = &c->model;
    d->est->seed(&d->est_state, e);
    ekf_ipmsm_config_t ec = c->ekf;
    ec.x0[EKF_THETA] = mc_div_i(e, m->n_p);
    (void)ekf_ipmsm_init(&d->ekf, &ec, m); /* the same configuration init accepted, one angle changed */
    /* the estimate's angle starts again there: no turn */
    d->theta_prev_rad = d->ekf.x[EKF_THETA];
    d->los.run = 0;
    d->stall.run = 0;
    lock_monitor_init(&d->lock, &c->lock);
    d->u_ab_prev_V.alpha = MC_ZERO;
    d->u_ab_prev_V.beta = MC_ZERO;
    d->starting = false;
}

/* One sample of the estimator's own start (paper002_drive.h): its voltage
 * alone, no current command, the speed loop open; a refused start latches
 * LOSS_OF_LOCK (the safe state, whatever the reaction table). */
static bool p002_start_step(paper002_drive_t *d, const hal_sample_t *in, mc_ab_t i_ab, hal_command_t *out)
{
    mc_ab_t u;
    mc_t e = MC_ZERO;
    const estimator_start_t s = d->est->start(&d->est_state, i_ab, &u, &e);
    if (s == EST_START_REFUSED) {
        (void)guard_trip(&p002_shell, d, DRIVE_FAULT_LOSS_OF_LOCK, out);
        return false;
    }
    if (s == EST_START_DONE) {
        p002_start_at(d, e);
    }
    phase_adapter_voltages(3u, u, out);
    return guard_end(&p002_shell, d, in, out, false, MC_ZERO, d->ekf.x[EKF_THETA], d->ekf.x[EKF_OMEGA]) != GUARD_SAFE;
}

/* Steps 0-2: the iron's inductances, the estimator's angle, the d-q
 * currents in its frame, the EKF's correction, the reference; then the
 * loss of the estimate (the EKF's innovation, a stall) and, while a
 * model-based angle is in use, the loss of lock (supervisor/lock_monitor.h):
 * two named criteria, each stepped every sample: the flux observer's
 * residual along its rotor axis, gPhi3 |target - |rho|^2| of (12), against
 * the tolerance bound at the EKF's speed and the current in the observer's
 * frame (a steady drift); and the EKF's angle innovation against 6 sigma
 * of its noise (S = P^-_thth + r_th, the a priori covariance: C = [I_3 0],
 * the angle is measurement 2 and state 2) and the stall band's speed error
 * over a sample, by a leaky count (the limit cycle and the flips of the
 * sensorless variants' losses, docs/paper002.md). The encoder's angle is
 * measured: the EKF's innovation checks it. Float only, as the drive (the
 * fixed-point build refuses paper 002's design, docs/paper002.md). False:
 * the drive went to FAULT (0 V out). */
static bool p002_estimate_step(paper002_drive_t *d, const estimator_ops_t *e, const hal_sample_t *in, mc_ab_t i_ab,
                               estimator_out_t *eo,
                               mc_t *w_d, mc_t *dw_d, hal_command_t *out)
{
    const paper002_config_t *c = &d->cfg;
    estimator_in_t ei;
    ei.sample = in;
    ei.omega_hint_rad_s = d->ekf.x[EKF_OMEGA];
    ei.L_ratio = p002_iron_step(d, e);
    ei.flux_ratio = e->model_based ? p002_active_flux(d) : MC_ONE;
    const mc_rot_t rot_e = e->update(&d->est_state, &ei, &i_ab, eo);
    mc_t i_d, i_q;
    mc_rot_fwd(rot_e, i_ab.alpha, i_ab.beta, &i_d, &i_q);
    const mc_t s_theta_rad2 = eo->lock_checkable ? mc_add(d->ekf.P[EKF_THETA][EKF_THETA], d->ekf.cfg.r[EKF_THETA]) : MC_ZERO;
    const bool corrected = ekf_ipmsm_correct(&d->ekf, i_d, i_q, eo->theta_rad);
    speed_poly_eval(&d->reference, d->tick, w_d, dw_d);
    d->theta_ref_rad = mc_wrap_pi(mc_mac(d->theta_ref_rad, *w_d, c->model.ts_s));
    const bool lost = fault_persist_step(&d->los, !mc_le(mc_abs(d->ekf.innovation[2]), c->los_theta_rad), c->los_ticks);
    const mc_t stall_band = mc_mac(c->stall_floor_rad_s, c->stall_tol, mc_abs(*w_d));
    const bool stalled =
        fault_persist_step(&d->stall, !mc_le(mc_abs(mc_sub(d->ekf.x[EKF_OMEGA], *w_d)), stall_band), c->stall_ticks);
    if ((!corrected || lost || stalled) && guard_fault(&p002_shell, d, DRIVE_FAULT_LOSS_OF_SYNC, out) == GUARD_SAFE) {
        return false;
    }
    if (eo->lock_checkable) {
        const lock_criterion_t by_flux =
            lock_monitor_step_flux(&d->lock, eo->rho2, eo->rho2_target, d->ekf.x[EKF_OMEGA], i_d, i_q);
        const lock_criterion_t by_innov =
            lock_monitor_step_innovation(&d->lock, d->ekf.innovation[EKF_THETA], s_theta_rad2, stall_band);
        if ((by_flux != LOCK_CRIT_NONE || by_innov != LOCK_CRIT_NONE) &&
            guard_fault(&p002_shell, d, DRIVE_FAULT_LOSS_OF_LOCK, out) == GUARD_SAFE) {
            return false;
        }
    }
    d->last.theta_meas_rad = eo->theta_rad;
    d->last.i_d_A = i_d;
    d->last.i_q_A = i_q;
    const mc_t *x = d->ekf.x; /* the a posteriori estimate of this sample */
    d->last.i_d_hat_A = x[EKF_ID];
    d->last.i_q_hat_A = x[EKF_IQ];
    d->last.theta_hat_rad = x[EKF_THETA];
    p002_count_turns(d, x[EKF_THETA]);
    d->last.w_hat_rad_s = x[EKF_OMEGA];
    d->last.M0_hat_Nm = x[EKF_M0];
    return true;
}

/* Steps 6-7: the command to alpha-beta at the angle the voltage acts
 * around (the estimate advanced to the middle of the sample it acts over,
 * (1/2 + d) Ts ahead), an estimator's injection on top, the inverter's
 * expected error added; then the EKF's prediction with the voltage the
 * motor sees over the coming sample (and the estimator's): this command,
 * or with a delay the mean (1 - d) u + d u_prev, brought into the frame of
 * the sample's middle. */
static void p002_output(paper002_drive_t *d, const estimator_ops_t *e, const hal_sample_t *in, mc_t u_d, mc_t u_q,
                        hal_command_t *out)
{
    const paper002_config_t *c = &d->cfg;
    const motor_model_t *m = &c->model;
    const mc_t *x = d->ekf.x;
    const mc_t half_ts = mc_div_i(m->ts_s, 2);
    const mc_t lead = mc_mac(half_ts, c->compute_delay, m->ts_s);
    const mc_t th_el = mc_elec_angle(mc_mac(x[EKF_THETA], lead, x[EKF_OMEGA]), m->n_p);
    const mc_rot_t rot_out = mc_rot_from_angle(th_el); /* also the compensation's way back */
    mc_ab_t u_ab;
    mc_rot_inv(rot_out, u_d, u_q, &u_ab.alpha, &u_ab.beta);
    if (e->injection) {
        /* the estimator's injection on top of the command; the estimators
         * see the command alone */
        const mc_ab_t u_h = e->injection(&d->est_state);
        const mc_ab_t u_out = {mc_add(u_ab.alpha, u_h.alpha), mc_add(u_ab.beta, u_h.beta)};
        phase_adapter_voltages(3u, u_out, out);
    } else {
        phase_adapter_voltages(3u, u_ab, out);
    }
    /* what the bus clamp takes of the compensation is in the voltage the
     * estimators use */
    mc_t u_d_est = u_d, u_q_est = u_q;
    if (d->dtc.cfg.enabled) {
        const mc_ab_t clamped = deadtime_comp_step(&d->dtc, in->i_A, in->v_bus_V, out);
        u_ab.alpha = mc_add(u_ab.alpha, clamped.alpha);
        u_ab.beta = mc_add(u_ab.beta, clamped.beta);
        mc_rot_fwd(rot_out, u_ab.alpha, u_ab.beta, &u_d_est, &u_q_est);
    }
    if (mc_eq(c->compute_delay, MC_ZERO)) {
        if (e->hold) {
            e->hold(&d->est_state, u_ab, u_ab);
        }
        ekf_ipmsm_predict(&d->ekf, m, u_d_est, u_q_est);
    } else {
        const mc_ab_t u_mean = delay_applied_mean(c->compute_delay, u_ab, d->u_ab_prev_V);
        if (e->hold) {
            e->hold(&d->est_state, u_mean, u_ab);
        }
        const mc_t th_mid = mc_elec_angle(mc_mac(x[EKF_THETA], half_ts, x[EKF_OMEGA]), m->n_p);
        mc_t u_d_mean, u_q_mean;
        mc_rot_fwd(mc_rot_from_angle(th_mid), u_mean.alpha, u_mean.beta, &u_d_mean, &u_q_mean);
        ekf_ipmsm_predict(&d->ekf, m, u_d_mean, u_q_mean);
    }
    d->u_ab_prev_V = u_ab;
}

bool paper002_drive_step(paper002_drive_t *d, const hal_sample_t *in, hal_command_t *out)
{
    const paper002_config_t *c = &d->cfg;
    const motor_model_t *m = &c->model;
    /* 0. the shell: latch, enable, the sample's checks, the fault monitor;
     * 0 V when it stops the sample: false in FAULT, true while disabled
     * (drives/drive.h) */
    const guard_action_t a = guard_begin(&p002_shell, d, in, out);
    if (a == GUARD_SAFE || a == GUARD_IDLE) {
        return a == GUARD_IDLE;
    }
    d->v_bus_V = in->v_bus_V; /* of a sample the drive runs (the speed command's check) */
    const estimator_ops_t *const e = d->est;
    /* 1. alpha-beta currents; the estimator's own start first */
    mc_t i_zero;
    const mc_ab_t i_ab = phase_adapter_currents(in, &i_zero);
    (void)i_zero;
    if (d->starting) {
        return p002_start_step(d, in, i_ab, out);
    }
    /* 0.-2. the angle, the EKF's correction, the reference, the checks */
    estimator_out_t eo;
    mc_t w_d, dw_d;
    if (!p002_estimate_step(d, e, in, i_ab, &eo, &w_d, &dw_d, out)) {
        return false;
    }
    const mc_t *x = d->ekf.x;
    /* 3. reference and torque demand; the estimator's correction of the
     * speed reference (an angle hold) */
    const mc_t w_c = e->reference ? e->reference(&d->est_state, w_d, x[EKF_THETA]) : w_d;
    const mc_t M_d = (c->controller == P002_SOSMC)
                         ? sosmc_step(&d->sosmc, &c->sosmc, m, w_c, dw_d, x[EKF_OMEGA], ekf_ipmsm_accel(&d->ekf, m),
                                      x[EKF_M0])
                         : htsmc_step(&d->htsmc, &c->htsmc, m, w_c, dw_d, x[EKF_OMEGA], x[EKF_M0]);
    /* 4. MTPA */
    mtpa_out_t ref;
    mtpa_step(&c->mtpa, m, M_d, &ref);
    /* 5. current control on the EKF's currents and speed, within the bus
     * less an injection's share (0 when off) */
    mc_t u_max = mc_mul(in->v_bus_V, P002_INV_SQRT3);
    if (e->injection) {
        u_max = mc_max(MC_ZERO, mc_sub(u_max, eo.u_reserve_V));
    }
    ibcc_out_t u_dq;
    ibcc_step(&d->ibcc, &c->ibcc, m, ref.i_d_A, ref.i_q_A, x[EKF_ID], x[EKF_IQ], x[EKF_OMEGA], u_max, &u_dq);
    /* 6.-7. output and prediction */
    p002_output(d, e, in, u_dq.u_d_V, u_dq.u_q_V, out);
    d->last.w_d_rad_s = w_d;
    d->last.M_d_Nm = M_d;
    d->last.i_dd_A = ref.i_d_A;
    d->last.i_qd_A = ref.i_q_A;
    d->last.u_d_V = u_dq.u_d_V;
    d->last.u_q_V = u_dq.u_q_V;
    d->last.saturated = d->ibcc.saturated;
    return guard_end(&p002_shell, d, in, out, d->ibcc.saturated, w_d, x[EKF_THETA], x[EKF_OMEGA]) != GUARD_SAFE;
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
