/*
 * paper001_drive.c - the paper-001 drive as a recipe (see paper001_drive.h).
 *
 * Order inside one sample k (currents sampled at t_k, voltages held over
 * [t_k, t_k + Ts)):
 *   0. supervisor: latched fault, phase count, bus voltage, over-current;
 *   1. alpha-beta currents (adapter) and the reference w*, dw_ref/dt, theta*;
 *   2.-4. the estimator the configuration names (estimators/open_start.h):
 *      its measurement, its start (the probe, the open loop's hand-over:
 *      the supervisor's switch to closed loop is its), the currents, speed
 *      and load the law runs on, in its frame;
 *   5. the law in that frame: IDA-PBC (11), or the open-loop vector (68)
 *      while the loop is open; bumpless switch;
 *   6. to alpha-beta, limited by the measured bus, to the phases; the
 *      estimator told the voltage that will be held.
 */
#include "drives/paper001/paper001_drive.h"

#include <stddef.h>

#include "mc_version.h"
#include "supervisor/guard.h"

/* The step's parts are functions for the reader, one sample's flow in the
 * step; GCC 12 left some of them calls (PIL M4F float 699.4 -> 705.6
 * instructions per step on average), so they are kept in line. */
#if defined(__GNUC__)
#define P001_IN_LINE inline __attribute__((always_inline))
#else
#define P001_IN_LINE inline
#endif

static void p001_zero_output(paper001_drive_t *d, hal_command_t *out)
{
    guard_zero(out, d->cfg.n_phases);
    d->last.v_ab_V.alpha = MC_ZERO;
    d->last.v_ab_V.beta = MC_ZERO;
}

/* A fault: the guard records it and reacts as configured
 * (supervisor/guard.h; the speed drive has no re-lock: SAFE, or REPORT).
 * Returns true when the drive is now in FAULT. */
static bool p001_react(paper001_drive_t *d, drive_fault_t f)
{
    return guard_react(&d->sup, &d->rec, d->cfg.reaction, f, d->tick, false) == GUARD_SAFE;
}

/* The end of a sample that output a voltage: the loss-of-estimate
 * criteria (closed loop), the command's checks, the flight recorder.
 * Returns false if the drive went to FAULT (out is then 0 V). */
static bool p001_finish(paper001_drive_t *d, const hal_sample_t *in, hal_command_t *out,
                                                 const open_start_out_t *eo)
{
    const paper001_config_t *c = &d->cfg;
    drive_fault_t f = fault_monitor_command(&d->mon, out, d->sup.sat_prev);
    /* the estimator's own speed and electrical angle: what the criteria
     * and the recorder need */
    const mc_t w_hat = eo->omega_own_rad_s;
    const mc_t e_hat = eo->theta_e_own_rad;
    if (f == DRIVE_FAULT_NONE && (!mc_is_finite(w_hat) || !mc_is_finite(e_hat))) {
        f = DRIVE_FAULT_NON_FINITE;
    }
    if (f == DRIVE_FAULT_NONE && d->sup.state == SUP_STATE_CLOSED_LOOP) {
        const bool rho_bad = eo->lock_checkable && (mc_lt(eo->rho2, c->los_rho2_lo) || mc_gt(eo->rho2, c->los_rho2_hi));
        const mc_t w_ref = d->x.ref.omega_rad_s;
        const mc_t w_tol = mc_mac(c->los_speed_floor_rad_s, c->los_speed_tol, mc_abs(w_ref));
        const bool speed_bad = mc_gt(mc_abs(mc_sub(w_hat, w_ref)), w_tol);
        if (fault_persist_step(&d->rho_persist, rho_bad, c->los_ticks) ||
            fault_persist_step(&d->speed_persist, speed_bad, c->los_speed_ticks)) {
            f = DRIVE_FAULT_LOSS_OF_SYNC;
        } else if (eo->lock_checkable && lock_monitor_step_flux(&d->lock, eo->rho2, eo->rho2_target, w_hat,
                                                                d->last.i_d_A, d->last.i_q_A) != LOCK_CRIT_NONE) {
            f = DRIVE_FAULT_LOSS_OF_LOCK; /* the estimate no longer explains the currents */
        }
    }
    guard_record(&d->rec, d->tick, d->sup.state, in, out, d->x.ref.omega_rad_s, e_hat, w_hat);
    d->tick += 1u;
    if (f != DRIVE_FAULT_NONE && p001_react(d, f)) {
        p001_zero_output(d, out);
        return false;
    }
    return true;
}

/* The first inconsistency of c, named by its field (a string literal), or
 * NULL when c is consistent: the fields, the estimator's (its own
 * config_problem), then the blocks whose own init checks their
 * configuration (the profile, the dead-time compensation), each asked on a
 * scratch copy. */
const char *paper001_config_problem(const paper001_config_t *c)
{
    const motor_model_t *m = &c->model;
    if (c->n_phases != 2u && c->n_phases != 3u) return "n_phases: must be 2 or 3";
    if (m->n_p < 1) return "model.n_p: must be >= 1";
    if (m->fs_hz <= 0) return "model.fs_hz: must be > 0";
    if (!mc_ge(m->R_ohm, MC_ZERO)) return "model.R_ohm: must be >= 0";
    if (!mc_gt(m->L_H, MC_ZERO)) return "model.L_H: must be > 0 (in the numeric type)";
    if (!mc_gt(m->K_V_s, MC_ZERO)) return "model.K_V_s: must be > 0 (in the numeric type)";
    if (!mc_gt(c->limits.i_trip_A, MC_ZERO)) return "limits.i_trip_A: must be > 0";
    if (!mc_gt(c->ctrl.r_ohm, MC_ZERO)) return "ctrl.r_ohm: must be > 0";
    if (!mc_gt(c->ctrl.i_max_A, MC_ZERO)) return "ctrl.i_max_A: must be > 0";
    if (!mc_ge(c->sup.blend_decay, MC_ZERO) || !mc_lt(c->sup.blend_decay, MC_ONE))
        return "sup.blend_decay: must be in [0, 1)";
    if (!mc_gt(c->v_bus_min_V, MC_ZERO)) return "v_bus_min_V: must be > 0";
    if (!mc_ge(c->compute_delay, MC_ZERO) || !mc_le(c->compute_delay, MC_ONE))
        return "compute_delay: must be in [0, 1]";
    const estimator_ops_t *e = estimator_find(EST_FAMILY_OPEN_START, c->estimator);
    if (e == NULL) return "estimator: must be an open-start estimator's number (0 flux, 1 back_emf)";
    const motor_model_t *em = &c->est.model;
    if (em->n_p != m->n_p || em->fs_hz != m->fs_hz || mc_ne(em->R_ohm, m->R_ohm) ||
        mc_ne(em->ts_over_L_A_per_V, m->ts_over_L_A_per_V))
        return "est.model: must be model (the drive's motor)";
    const char *why = e->config_problem ? e->config_problem(&c->est) : NULL;
    if (why != NULL) return why;
    speed_profile_t profile;
    if (!speed_profile_init(&profile, &c->profile))
        return "profile: 1 .. SPEED_PROFILE_MAX_POINTS points, t_tick from 0 strictly increasing, fs_hz > 0";
    deadtime_comp_t dtc;
    if (!deadtime_comp_init(&dtc, &c->deadtime)) return "deadtime: its coefficients must be >= 0";
    return NULL;
}

/* The step instantiated for the estimator e (below); false: none. */
static bool p001_run_for(const estimator_ops_t *e, paper001_run_fn *run);

bool paper001_drive_init(paper001_drive_t *d, const paper001_config_t *cfg)
{
    d->cfg = *cfg;
    d->tick = 0;
    d->last.tick = 0;
    d->last.i_d_A = MC_ZERO;
    d->last.i_q_A = MC_ZERO;
    /* the estimator, found by the number the configuration holds */
    d->est = estimator_find(EST_FAMILY_OPEN_START, cfg->estimator);
    /* its step (none: the first, whose prologue outputs 0 V in the FAULT latched below) */
    const bool ok_est = p001_run_for(d->est, &d->run) && d->est->init(&d->est_state, &cfg->est);
    d->x.sup = &d->sup;
    d->x.tick = 0;
    d->x.i_ab_A.alpha = MC_ZERO;
    d->x.i_ab_A.beta = MC_ZERO;
    d->x.u_held_ab_V = d->x.i_ab_A;
    d->x.ref.omega_rad_s = MC_ZERO;
    d->x.ref.accel_rad_s2 = MC_ZERO;
    d->x.ref.theta_rad = MC_ZERO;
    d->x.profile = &d->profile;
    d->x.frame_voltage_applied = !cfg->deadtime.enabled && mc_eq(cfg->compute_delay, MC_ZERO);
    (void)deadtime_comp_init(&d->dtc, &cfg->deadtime); /* refused: paper001_config_problem says so */
    ida_pbc_init(&d->ctrl);
    (void)speed_profile_init(&d->profile, &cfg->profile);
    supervisor_init(&d->sup, &cfg->sup, false, false);
    fault_monitor_init(&d->mon, &cfg->faults);
    flight_recorder_init(&d->rec);
    d->rho_persist.run = 0;
    d->speed_persist.run = 0;
    lock_monitor_init(&d->lock, &cfg->lock);
    hal_command_t unused;
    p001_zero_output(d, &unused);
    d->disabled = false;
    d->v_bus_V = MC_ZERO;
    d->stop_ramp_rad_s2 = MC_ZERO;
    for (uint32_t k = 0; k + 1u < cfg->profile.n_points && k < SPEED_PROFILE_MAX_POINTS; ++k) {
        d->stop_ramp_rad_s2 = mc_max(d->stop_ramp_rad_s2, mc_abs(cfg->profile.slope_rad_s2[k]));
    }
    if (!ok_est || paper001_config_problem(cfg) != NULL) {
        guard_latch(&d->sup, &d->rec, DRIVE_FAULT_BAD_INPUT, d->tick);
        return false;
    }
    return true;
}

/* Step 0, the supervisor: a latched fault or a disabled drive outputs 0 V
 * (the step returns false in FAULT, true disabled); a sample of the wrong
 * phase count or below the bus's least latches BAD_INPUT; the generic
 * checks of the sample (supervisor/fault_monitor.h) go through the
 * reaction table. Returns P001_GO_ON when the sample goes on, else the
 * step's result (0 false, 1 true). */
#define P001_GO_ON (-1)
static P001_IN_LINE int p001_prologue(paper001_drive_t *d, const hal_sample_t *in, hal_command_t *out)
{
    const paper001_config_t *c = &d->cfg;
    if (d->sup.state == SUP_STATE_FAULT) {
        p001_zero_output(d, out);
        return 0;
    }
    if (d->disabled) {
        p001_zero_output(d, out);
        return 1;
    }
    if (!phase_adapter_accepts(in, c->n_phases) || !mc_gt(in->v_bus_V, c->v_bus_min_V)) {
        guard_latch(&d->sup, &d->rec, DRIVE_FAULT_BAD_INPUT, d->tick);
        p001_zero_output(d, out);
        return 0;
    }
    d->v_bus_V = in->v_bus_V;
    const drive_fault_t f = fault_monitor_sample(&d->mon, in, c->n_phases);
    if (f != DRIVE_FAULT_NONE && p001_react(d, f)) {
        p001_zero_output(d, out);
        return 0;
    }
    return P001_GO_ON;
}

/* Step 6: the voltage in the estimator's frame to alpha-beta at its
 * angle (for paper 001's, the angle the rotor has on average while the
 * voltage acts), limited by the measured bus (a leg swings +-v_bus/2 about
 * the midpoint with three phases, an H-bridge +-v_bus with two); the
 * inverter's expected error added; the estimator told the mean voltage
 * the motor sees over the sample (with what the bus clamp takes of the
 * compensation) and the command in its frame as the limiter left it. */
static P001_IN_LINE void p001_output(paper001_drive_t *d, const hal_sample_t *in, const open_start_out_t *eo, mc_t v_d,
                                     mc_t v_q, void (*hold)(void *, const open_start_in_t *, mc_ab_t, mc_t, mc_t),
                                     hal_command_t *out)
{
    const paper001_config_t *c = &d->cfg;
    mc_ab_t v_ab;
    mc_rot_inv(eo->out_rot, v_d, v_q, &v_ab.alpha, &v_ab.beta);
    const mc_t v_max = (c->n_phases == 3u) ? mc_div_i(in->v_bus_V, 2) : in->v_bus_V;
    (void)supervisor_limit_output(&d->sup, c->n_phases, v_max, &v_ab, &v_d, &v_q, out);
    if (d->dtc.cfg.enabled) {
        const mc_ab_t lost = deadtime_comp_step(&d->dtc, in->i_A, in->v_bus_V, out);
        v_ab.alpha = mc_add(v_ab.alpha, lost.alpha);
        v_ab.beta = mc_add(v_ab.beta, lost.beta);
    }
    const mc_ab_t v_mean = paper001_applied_mean(c, v_ab, d->last.v_ab_V);
    hold(&d->est_state, &d->x, v_mean, v_d, v_q);
    d->x.u_held_ab_V = v_mean;
    d->last.i_d_A = eo->i_d_A;
    d->last.i_q_A = eo->i_q_A;
    d->last.v_ab_V = v_ab;
}

/* The estimator's operations, as a drive's step takes them. */
typedef void (*p001_measure_fn)(void *self, const open_start_in_t *in, open_start_out_t *out);
typedef void (*p001_open_loop_fn)(const void *self, const open_start_in_t *in, mc_t v_V, mc_t *v_d_V, mc_t *v_q_V);
typedef void (*p001_hold_fn)(void *self, const open_start_in_t *in, mc_ab_t u_mean_ab_V, mc_t u_d_V, mc_t u_q_V);

/* One sample with the estimator whose operations are given: constants
 * where the step is instantiated (below), so that they run in line. */
static P001_IN_LINE bool p001_sample(paper001_drive_t *d, const hal_sample_t *in, hal_command_t *out,
                                     p001_measure_fn measure, p001_open_loop_fn open_loop, p001_hold_fn hold)
{
    const paper001_config_t *c = &d->cfg;
    d->last.tick = d->tick;
    /* 0. supervisor */
    const int pre = p001_prologue(d, in, out);
    if (pre != P001_GO_ON) {
        return pre != 0;
    }
    /* 1. currents and reference */
    mc_t i_zero_A;
    d->x.i_ab_A = phase_adapter_currents(in, &i_zero_A);
    (void)i_zero_A; /* star without neutral: the measurement's offset, unused here */
    d->x.sup = &d->sup; /* (a copied drive's state points at its own) */
    d->x.profile = &d->profile;
    d->x.tick = d->tick;
    speed_profile_eval(&d->profile, d->tick, &d->x.ref);
    /* 2.-4. the estimator: measurement, start, hand-over */
    open_start_out_t eo;
    measure(&d->est_state, &d->x, &eo);
    /* 5. the law in its frame: IDA-PBC (11), or the open-loop vector (paper 000 (68)) */
    mc_t v_d, v_q;
    if (d->sup.state == SUP_STATE_CLOSED_LOOP) {
        ida_pbc_step(&d->ctrl, &c->ctrl, eo.i_d_A, eo.i_q_A, eo.omega_rad_s, eo.load_Nm, d->x.ref.omega_rad_s,
                     d->x.ref.accel_rad_s2, &v_d, &v_q); /* (11) */
        if (eo.law_turned) {
            const mc_t v1 = v_d, v2 = v_q;
            mc_rot_inv(eo.law_rot, v1, v2, &v_d, &v_q);
        }
    } else {
        const mc_t v_ol = eo.own_vector ? MC_ZERO : open_loop_voltage(&c->open_loop, &c->model, d->x.ref.omega_rad_s);
        open_loop(&d->est_state, &d->x, v_ol, &v_d, &v_q);
    }
    supervisor_blend(&d->sup, eo.switched, &v_d, &v_q);
    /* 6. to the phases, the estimator told the applied voltage */
    p001_output(d, in, &eo, v_d, v_q, hold, out);
    return p001_finish(d, in, out, &eo);
}

/* The step once per open-start estimator (estimator_registry.h,
 * OPEN_START_ESTIMATORS); init picks the one the configuration names. */
#if defined(__GNUC__)
#define P001_FLATTEN __attribute__((flatten)) /* its blocks in line: one call per sample */
#else
#define P001_FLATTEN
#endif
#define P001_STEP_OF(name)                                                                                    \
    static P001_FLATTEN bool p001_step_##name(void *self, const hal_sample_t *in, hal_command_t *out)        \
    {                                                                                                         \
        return p001_sample((paper001_drive_t *)self, in, out, name##_measure_op, name##_open_loop_op,         \
                           name##_hold_op);                                                                   \
    }
OPEN_START_ESTIMATORS(P001_STEP_OF)

static const struct {
    const estimator_ops_t *est;
    paper001_run_fn run;
} p001_steps[] = {
#define P001_STEP_ENTRY(name) {&name##_ops, p001_step_##name},
    OPEN_START_ESTIMATORS(P001_STEP_ENTRY)
#undef P001_STEP_ENTRY
};

static bool p001_run_for(const estimator_ops_t *e, paper001_run_fn *run)
{
    *run = p001_steps[0].run;
    for (size_t k = 0; k < sizeof p001_steps / sizeof p001_steps[0]; ++k) {
        if (e != NULL && p001_steps[k].est == e) {
            *run = p001_steps[k].run;
            return true;
        }
    }
    return false;
}

bool paper001_drive_step(paper001_drive_t *d, const hal_sample_t *in, hal_command_t *out)
{
    return d->run(d, in, out);
}

bool paper001_drive_clear_fault(paper001_drive_t *d)
{
    /* an exact self-copy (d->cfg = *cfg with cfg == &d->cfg) is allowed (C11 6.5.16.1) */
    return paper001_drive_init(d, &d->cfg);
}

/* The estimator's report (a drive whose configuration named no estimator:
 * zeros, not valid). */
static void p001_report(const paper001_drive_t *d, open_start_report_t *r)
{
    if (d->est == NULL) {
        const open_start_report_t none = {{MC_ZERO, MC_ZERO, MC_ZERO, MC_ZERO, false}, 0, MC_ZERO, MC_ZERO,
                                          MC_ZERO, MC_ZERO, MC_ZERO};
        *r = none;
        return;
    }
    d->est->report(&d->est_state, &d->x, d->sup.state == SUP_STATE_CLOSED_LOOP, r);
}

void paper001_drive_estimate(const paper001_drive_t *d, mc_estimate_t *e)
{
    open_start_report_t r;
    p001_report(d, &r);
    *e = r.est;
}

void paper001_drive_get_telemetry(const paper001_drive_t *d, paper001_telemetry_t *t)
{
    t->fw_version = MC_VERSION_U32;
    const bool fault = d->sup.state == SUP_STATE_FAULT;
    t->mode = supervisor_mode(&d->sup);
    t->fault = d->sup.fault;
    t->state = d->sup.state;
    t->tick = d->last.tick;
    t->omega_ref_rad_s = d->x.ref.omega_rad_s;
    t->accel_ref_rad_s2 = d->x.ref.accel_rad_s2;
    t->theta_ref_rad = d->x.ref.theta_rad;
    open_start_report_t r;
    p001_report(d, &r);
    t->theta_e_turns = r.theta_e_turns;
    t->theta_e_rad = r.theta_e_rad;
    t->omega_est_rad_s = r.omega_rad_s;
    t->load_est_Nm = r.load_Nm;
    t->rho2 = r.rho2;
    t->R_obs_ohm = r.R_obs_ohm;
    t->estimate_valid = d->sup.state == SUP_STATE_CLOSED_LOOP;
    t->i_d_A = d->last.i_d_A;
    t->i_q_A = d->last.i_q_A;
    t->i_q_ref_A = (d->sup.state == SUP_STATE_CLOSED_LOOP) ? d->ctrl.i_q_ref_A : MC_ZERO;
    t->v_d_V = fault ? MC_ZERO : d->sup.v_prev_V[0];
    t->v_q_V = fault ? MC_ZERO : d->sup.v_prev_V[1];
    t->v_alpha_V = d->last.v_ab_V.alpha;
    t->v_beta_V = d->last.v_ab_V.beta;
    t->v_saturated = !fault && d->sup.sat_prev;
    t->fault_events = d->rec.events;
    t->overruns = d->mon.overruns;
}

bool paper001_drive_set_enabled(paper001_drive_t *d, bool on)
{
    if (d->sup.state == SUP_STATE_FAULT) {
        return false;
    }
    if (!on) {
        d->disabled = true;
        return true;
    }
    if (!d->disabled) {
        return true;
    }
    return paper001_drive_init(d, &d->cfg);
}

bool paper001_drive_set_speed(paper001_drive_t *d, mc_t omega_rad_s, mc_t ramp_rad_s2)
{
    const paper001_config_t *c = &d->cfg;
    if (d->disabled || d->sup.state == SUP_STATE_FAULT || !mc_gt(ramp_rad_s2, MC_ZERO)) {
        return false;
    }
    /* the back-EMF K_e |w| within a share of the phase voltage the bus
     * gives: v_bus/sqrt(3) for three legs (space vector), v_bus for an
     * H-bridge per winding */
    const mc_t v_phase = (c->n_phases == 3u) ? mc_mul(d->v_bus_V, MC_C(0.57735027)) : d->v_bus_V;
    if (mc_gt(mc_mul(c->model.K_V_s, mc_abs(omega_rad_s)), mc_mul(P001_CMD_VOLTAGE_SHARE, v_phase))) {
        return false;
    }
    /* the ramp within K_t i_max / J (K_t = 3/2 K_e with three phases, K_e
     * with two); the product saturates above the DBC's largest ramp */
    mc_t a_max = mc_mul(mc_mul(c->model.K_V_s, c->limits.i_max_A), c->model.inv_J);
    if (c->n_phases == 3u) {
        a_max = mc_mul(a_max, MC_C(1.5));
    }
    if (mc_gt(ramp_rad_s2, a_max)) {
        return false;
    }
    if (!speed_profile_retarget(&d->profile, d->tick, omega_rad_s, ramp_rad_s2)) {
        return false;
    }
    d->stop_ramp_rad_s2 = ramp_rad_s2;
    return true;
}

bool paper001_drive_stop(paper001_drive_t *d)
{
    if (d->sup.state == SUP_STATE_FAULT) {
        return false;
    }
    /* a profile without a ramp (a constant speed) stops in one second */
    mc_t ramp = d->stop_ramp_rad_s2;
    if (!mc_gt(ramp, MC_ZERO)) {
        ramp = mc_max(mc_abs(d->x.ref.omega_rad_s), MC_C(0.1));
    }
    return speed_profile_retarget(&d->profile, d->tick, MC_ZERO, ramp);
}

bool paper001_drive_set_omega_lim(paper001_drive_t *d, mc_t omega_lim_rad_s)
{
    if (d->est == NULL || d->est->set_omega_lim == NULL || d->sup.state == SUP_STATE_CLOSED_LOOP) {
        return false;
    }
    return d->est->set_omega_lim(&d->est_state, omega_lim_rad_s);
}
