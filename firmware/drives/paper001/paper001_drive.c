/*
 * paper001_drive.c - the paper-001 drive as a recipe (see paper001_drive.h).
 *
 * Order inside one sample k (currents sampled at t_k, voltages held over
 * [t_k, t_k + Ts)):
 *   0. supervisor: latched fault, phase count, bus voltage, over-current;
 *   1. alpha-beta currents (adapter) and the reference w*, dw_ref/dt, theta*;
 *   2. flux observer (12)-(14): integrates the last sample, angle of this one;
 *   3. speed and load observer (15)-(16) on that angle (runs in open loop
 *      too, so its state has converged when the loop closes);
 *   4. open loop -> closed loop once the reference has turned far enough
 *      and the observer agrees with the open-loop angle;
 *   5. the law in the estimated dq frame: IDA-PBC (11) or the open-loop
 *      vector (68) along theta*; bumpless switch; back to alpha-beta;
 *   6. limited by the measured bus, to the phases; the flux observer is
 *      told the voltage that will be held.
 */
#include "drives/paper001/paper001_drive.h"

#include <stddef.h>

#include "mc_version.h"
#include "supervisor/guard.h"

/* The probe's points are p = 8 (rho - rho(0)): det M of a through-origin
 * fit of points spread evenly along an arc is 1.3e-8 for an arc of 0.3 rad
 * (6th power of the arc), below the resolution of Q14.17 (7.6e-6); scaled
 * by 8 it is 4096 times larger (3.2e-3, 420 LSB). |p| <= 2 (two unit
 * vectors) keeps |8 p|^3 <= 4096, below the Q14.17 limit of 16384. */
#define P001_PROBE_POINT_SCALE 8

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
static bool p001_finish(paper001_drive_t *d, const hal_sample_t *in, hal_command_t *out)
{
    const paper001_config_t *c = &d->cfg;
    drive_fault_t f = fault_monitor_command(&d->mon, out, d->sup.sat_prev);
    /* the estimator's own state, not paper001_drive_estimate (which forms
     * the mechanical angle and the acceleration): the speed and the
     * electrical angle are what the criteria and the recorder need */
    const bool emf = c->estimator == P001_ESTIMATOR_BACK_EMF;
    const mc_t w_hat = emf ? d->emf.mech.omega_est_rad_s : d->speed.omega_rad_s;
    const mc_t e_hat = emf ? d->emf.pos.theta_est_rad : d->speed.unwrap.e_rad;
    if (f == DRIVE_FAULT_NONE && (!mc_is_finite(w_hat) || !mc_is_finite(e_hat))) {
        f = DRIVE_FAULT_NON_FINITE;
    }
    if (f == DRIVE_FAULT_NONE && d->sup.state == SUP_STATE_CLOSED_LOOP) {
        const bool rho_bad = !emf && (mc_lt(d->flux.rho2, c->los_rho2_lo) || mc_gt(d->flux.rho2, c->los_rho2_hi));
        const mc_t w_ref = d->ref.omega_rad_s;
        const mc_t w_tol = mc_mac(c->los_speed_floor_rad_s, c->los_speed_tol, mc_abs(w_ref));
        const bool speed_bad = mc_gt(mc_abs(mc_sub(w_hat, w_ref)), w_tol);
        if (fault_persist_step(&d->rho_persist, rho_bad, c->los_ticks) ||
            fault_persist_step(&d->speed_persist, speed_bad, c->los_speed_ticks)) {
            f = DRIVE_FAULT_LOSS_OF_SYNC;
        } else if (!emf && lock_monitor_step_flux(&d->lock, d->flux.rho2, d->flux.rho2_target, w_hat, d->last.i_d_A,
                                                  d->last.i_q_A) != LOCK_CRIT_NONE) {
            f = DRIVE_FAULT_LOSS_OF_LOCK; /* the estimate no longer explains the currents */
        }
    }
    guard_record(&d->rec, d->tick, d->sup.state, in, out, d->ref.omega_rad_s, e_hat, w_hat);
    d->tick += 1u;
    if (f != DRIVE_FAULT_NONE && p001_react(d, f)) {
        p001_zero_output(d, out);
        return false;
    }
    return true;
}

/* The first inconsistency of c, named by its field (a string literal), or
 * NULL when c is consistent: the fields, then the blocks whose own init
 * checks their configuration (the profile, the dead-time compensation,
 * the resistance tracker), each asked on a scratch copy. */
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
    if (!mc_gt(c->flux.Phi_fs_V, MC_ZERO)) return "flux.Phi_fs_V: must be > 0";
    if (!mc_gt(c->flux.rho_gain, MC_ZERO)) return "flux.rho_gain: must be > 0";
    if (!mc_ge(c->flux.gPhi3_V, MC_ZERO)) return "flux.gPhi3_V: must be >= 0";
    if (!mc_ge(c->speed.k_omega, MC_ZERO)) return "speed.k_omega: must be >= 0";
    if (!mc_ge(c->speed.k_load_Nm_s, MC_ZERO)) return "speed.k_load_Nm_s: must be >= 0";
    if (!mc_ge(c->sup.blend_decay, MC_ZERO) || !mc_lt(c->sup.blend_decay, MC_ONE))
        return "sup.blend_decay: must be in [0, 1)";
    if (c->fit.decim < 1) return "fit.decim: must be >= 1";
    if (!mc_gt(c->fit.det_min, MC_ZERO)) return "fit.det_min: must be > 0";
    if (!mc_gt(c->v_bus_min_V, MC_ZERO)) return "v_bus_min_V: must be > 0";
    if (!mc_ge(c->compute_delay, MC_ZERO) || !mc_le(c->compute_delay, MC_ONE))
        return "compute_delay: must be in [0, 1]";
    if (c->estimator != P001_ESTIMATOR_FLUX && c->estimator != P001_ESTIMATOR_BACK_EMF)
        return "estimator: must be FLUX or BACK_EMF";
    if (c->estimator == P001_ESTIMATOR_BACK_EMF) {
        if (!mc_gt(c->omega_lim_rad_s, MC_ZERO)) return "omega_lim_rad_s: must be > 0 (estimator BACK_EMF)";
        if (!mc_gt(c->emf_torque_model.K_V_s, MC_ZERO))
            return "emf_torque_model.K_V_s: must be > 0 (estimator BACK_EMF)";
        if (c->emf.pos.n_p != m->n_p) return "emf.pos.n_p: must be model.n_p (estimator BACK_EMF)";
    }
    speed_profile_t profile;
    if (!speed_profile_init(&profile, &c->profile))
        return "profile: 1 .. SPEED_PROFILE_MAX_POINTS points, t_tick from 0 strictly increasing, fs_hz > 0";
    deadtime_comp_t dtc;
    if (!deadtime_comp_init(&dtc, &c->deadtime)) return "deadtime: its coefficients must be >= 0";
    resistance_tracker_t rtrack;
    if (!resistance_tracker_init(&rtrack, &c->rtrack)) return "rtrack: enabled with a coefficient out of range";
    return NULL;
}

bool paper001_drive_init(paper001_drive_t *d, const paper001_config_t *cfg)
{
    d->cfg = *cfg;
    d->tick = 0;
    d->last.tick = 0;
    d->last.i_d_A = MC_ZERO;
    d->last.i_q_A = MC_ZERO;
    /* rho_hat(0) = (1, 0) (errata): the angle is unknown, the open-loop
     * start makes it observable */
    const mc_rot_t angle0 = {MC_ZERO, MC_ONE};
    const mc_ab_t i0 = {MC_ZERO, MC_ZERO};
    flux_observer_init(&d->flux, &cfg->flux, angle0, i0);
    flux_observer_set_gradient(&d->flux, false); /* a pure integrator until the circle fit */
    flux_circle_fit_init(&d->fit, &cfg->fit);
    flux_circle_fit_init(&d->probe, &cfg->probe_fit);
    d->probe_anchor = d->flux.rho;
    d->probe_last.alpha = MC_ZERO;
    d->probe_last.beta = MC_ZERO;
    d->probing = cfg->probe_ticks > 0u;
    d->probe_turned = false;
    d->probe_dir.s = MC_ZERO; /* along alpha */
    d->probe_dir.c = MC_ONE;
    d->ol_origin = angle0;
    d->ol_theta0_rad = MC_ZERO;
    d->ol_origin_mech_rad = MC_ZERO;
    fg_estimator_init(&d->emf, &cfg->emf);
    (void)deadtime_comp_init(&d->dtc, &cfg->deadtime); /* refused: paper001_config_problem says so */
    (void)resistance_tracker_init(&d->rtrack, &cfg->rtrack);
    speed_load_observer_init(&d->speed, &cfg->speed, angle0, MC_ZERO, MC_ZERO);
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
    d->ref.omega_rad_s = MC_ZERO;
    d->ref.accel_rad_s2 = MC_ZERO;
    d->ref.theta_rad = MC_ZERO;
    d->disabled = false;
    d->omega_lim_rad_s = cfg->omega_lim_rad_s;
    d->v_bus_V = MC_ZERO;
    d->stop_ramp_rad_s2 = MC_ZERO;
    for (uint32_t k = 0; k + 1u < cfg->profile.n_points && k < SPEED_PROFILE_MAX_POINTS; ++k) {
        d->stop_ramp_rad_s2 = mc_max(d->stop_ramp_rad_s2, mc_abs(cfg->profile.slope_rad_s2[k]));
    }
    if (paper001_config_problem(cfg) != NULL) {
        guard_latch(&d->sup, &d->rec, DRIVE_FAULT_BAD_INPUT, d->tick);
        return false;
    }
    return true;
}

/* The start-up probe (paper001_drive.h): offers the fit a point each time
 * the flux has moved sqrt(probe_step2)/8 along its arc; ends when the fit
 * is trusted (observer corrected, open-loop vector started at the
 * estimate) or when probe_ticks have passed (vector at the reference). */
static void p001_probe(paper001_drive_t *d)
{
    const paper001_config_t *c = &d->cfg;
    mc_ab_t p;
    p.alpha = mc_mul_i(mc_sub(d->flux.rho.alpha, d->probe_anchor.alpha), P001_PROBE_POINT_SCALE);
    p.beta = mc_mul_i(mc_sub(d->flux.rho.beta, d->probe_anchor.beta), P001_PROBE_POINT_SCALE);
    const mc_t da = mc_sub(p.alpha, d->probe_last.alpha);
    const mc_t db = mc_sub(p.beta, d->probe_last.beta);
    bool found = false;
    if (!mc_lt(mc_dot2(da, da, db, db), c->probe_step2)) {
        flux_circle_fit_add(&d->probe, p);
        d->probe_last = p;
        mc_ab_t centre;
        if (flux_circle_fit_center_origin(&d->probe, &centre)) {
            /* the centre in rho units: anchor + centre / 8 */
            centre.alpha = mc_add(d->probe_anchor.alpha, mc_div_i(centre.alpha, P001_PROBE_POINT_SCALE));
            centre.beta = mc_add(d->probe_anchor.beta, mc_div_i(centre.beta, P001_PROBE_POINT_SCALE));
            flux_observer_shift(&d->flux, centre);
            resistance_tracker_unprime(&d->rtrack); /* the angle jumped */
            found = true;
        }
    }
    const mc_t p2 = mc_dot2(p.alpha, p.alpha, p.beta, p.beta);
    if (!d->probe_turned && (!mc_lt(p2, c->probe_turn2) || d->tick + 1u >= c->probe_turn_ticks)) {
        /* along the chord: ahead of the rotor in its direction of motion,
         * for either of the mirror-image angles (paper001_drive.h) */
        d->probe_turned = true;
        if (mc_gt(p2, MC_ZERO) && !mc_lt(p2, mc_div_i(c->probe_turn2, 16))) {
            const mc_t k = mc_rsqrt(p2);
            d->probe_dir.c = mc_mul(p.alpha, k);
            d->probe_dir.s = mc_mul(p.beta, k);
        } else {
            d->probe_dir.c = MC_ZERO; /* not moved: the rotor is at 0 or pi, beta moves it */
            d->probe_dir.s = MC_ONE;
        }
    }
    if (found || d->tick + 1u >= c->probe_ticks) {
        /* the open-loop vector starts at the (corrected) estimate; without a
         * fit, at the reference angle */
        const mc_rot_t ref = mc_rot_from_angle(mc_elec_angle(d->ref.theta_rad, c->model.n_p));
        const mc_rot_t minus_ref = {mc_neg(ref.s), ref.c};
        const mc_rot_t at = found ? d->flux.unit : (mc_rot_t){MC_ZERO, MC_ONE};
        d->ol_origin = mc_rot_compose(at, minus_ref);
        d->ol_origin_mech_rad = mc_div_i(mc_atan2(d->ol_origin.s, d->ol_origin.c), c->model.n_p);
        d->ol_theta0_rad = d->ref.theta_rad;
        d->probing = false;
    }
}

/* Steps 2-6 with paper 000's estimator (estimator = BACK_EMF), after the
 * probe: the (f-g) frame is the open-loop vector's, turned by the reference
 * each sample as in paper000_drive.c; IDA-PBC (11) in the estimated frame
 * U(n_p (theta_hat - theta_r)) of (44), its voltage back to (f-g). */
static void p001_step_back_emf(paper001_drive_t *d, const hal_sample_t *in, mc_ab_t i_ab, mc_t v_max, hal_command_t *out)
{
    const paper001_config_t *c = &d->cfg;
    const int32_t n_p = c->model.n_p;
    speed_point_t next;
    speed_profile_eval(&d->profile, d->tick + 1u, &next);
    const mc_t theta_r = mc_add(d->ref.theta_rad, d->ol_origin_mech_rad);
    /* paper 000's estimator, as paper000_drive.c runs it (its front, the
     * correction, the tracking where the angle is used, the branch at the
     * switch, the mechanics, the prediction); the frame's rotation is the
     * open-loop vector's: its origin turned by the reference's angle */
    const mc_rot_t rot_k = mc_rot_compose(d->ol_origin, mc_rot_from_angle(mc_elec_angle(d->ref.theta_rad, n_p)));
    fg_frame_t fr;
    mc_t i_f, i_g;
    fg_estimator_front(&fr, rot_k, d->ref.theta_rad, next.theta_rad, n_p, i_ab, &i_f, &i_g);
    fg_estimator_correct(&d->emf, i_f, i_g);
    const bool want_closed =
        !mc_lt(mc_abs(d->ref.omega_rad_s), d->omega_lim_rad_s) && fg_estimator_observable(&d->emf);
    if (want_closed) {
        fg_estimator_track(&d->emf, theta_r, d->ref.omega_rad_s);
    }
    bool switched = false;
    if (want_closed != (d->sup.state == SUP_STATE_CLOSED_LOOP)) {
        switched = supervisor_dispatch(&d->sup, want_closed ? SUP_EV_ESTIMATE_TRUSTED : SUP_EV_ESTIMATE_LOST);
        if (switched && want_closed) {
            fg_estimator_lock_branch(&d->emf, theta_r);
        }
    }
    const bool closed = d->sup.state == SUP_STATE_CLOSED_LOOP;
    fg_estimator_mechanics(&d->emf, &c->emf_torque_model, closed, d->ref.omega_rad_s, i_f, i_g);
    mc_t v_f, v_g;
    if (closed) {
        mc_estimate_t est;
        fg_estimator_get(&d->emf, true, theta_r, d->ref.omega_rad_s, d->ref.accel_rad_s2, &est);
        mc_t v_d, v_q;
        ida_pbc_step(&d->ctrl, &c->ctrl, d->emf.i_d_A, d->emf.i_q_A, est.omega_rad_s, est.load_Nm, d->ref.omega_rad_s,
                     d->ref.accel_rad_s2, &v_d, &v_q); /* (11) */
        mc_rot_inv(d->emf.u_est, v_d, v_q, &v_f, &v_g); /* estimated frame (44) -> (f-g) */
    } else {
        v_f = open_loop_voltage(&c->open_loop, &c->model, d->ref.omega_rad_s); /* paper 000 (68) */
        v_g = MC_ZERO;
    }
    supervisor_blend(&d->sup, switched, &v_f, &v_g);
    /* to alpha-beta at the mid-sample angle, limited by the measured bus */
    mc_ab_t v_ab;
    mc_rot_inv(fr.mid, v_f, v_g, &v_ab.alpha, &v_ab.beta);
    (void)supervisor_limit_output(&d->sup, c->n_phases, v_max, &v_ab, &v_f, &v_g, out);
    if (d->dtc.cfg.enabled) {
        /* the inverter's expected error added to the command; what the bus
         * clamp takes of it is in the voltage the observer integrates */
        const mc_ab_t lost = deadtime_comp_step(&d->dtc, in->i_A, in->v_bus_V, out);
        v_ab.alpha = mc_add(v_ab.alpha, lost.alpha);
        v_ab.beta = mc_add(v_ab.beta, lost.beta);
        mc_rot_fwd(fr.mid, v_ab.alpha, v_ab.beta, &v_f, &v_g);
    }
    /* with a computation delay the observer integrates the applied mean,
     * in the frame of the sample's middle (as paper000_drive.c) */
    mc_t v_f_obs = v_f, v_g_obs = v_g;
    if (mc_ne(c->compute_delay, MC_ZERO)) {
        const mc_ab_t v_mean = paper001_applied_mean(c, v_ab, d->last.v_ab_V);
        mc_rot_fwd(fr.mid, v_mean.alpha, v_mean.beta, &v_f_obs, &v_g_obs);
    }
    fg_estimator_predict(&d->emf, &c->model, v_f_obs, v_g_obs, i_f, i_g, fr.half);
    d->last.i_d_A = d->emf.i_d_A;
    d->last.i_q_A = d->emf.i_q_A;
    d->last.v_ab_V = v_ab;
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

/* Steps 2-4 with the flux estimator (and the probe of either): the flux
 * observer (12)-(14), the R it subtracts tracked from the q-axis voltage
 * balance of the sample it just integrated (closed loop only); in open
 * loop the probe, the circle fit and the switch to closed loop; the
 * current in the estimated dq frame rho (its q component is the i^T Jm rho
 * of the I&I observer) and the speed and load observer (15)-(16). Returns
 * whether the loop closed in this sample; *probing: the probe ran. */
static P001_IN_LINE bool p001_flux_estimate(paper001_drive_t *d, mc_ab_t i_ab, bool *probing, mc_t *i_d, mc_t *i_q)
{
    const paper001_config_t *c = &d->cfg;
    const mc_ab_t v_held = d->flux.v_prev_V;
    flux_observer_step(&d->flux, i_ab);
    if (d->rtrack.cfg.enabled) {
        resistance_tracker_step(&d->rtrack, v_held, i_ab, d->flux.unit, d->speed.omega_rad_s,
                                d->sup.state == SUP_STATE_CLOSED_LOOP);
        flux_observer_set_R(&d->flux, d->rtrack.R_ohm);
        flux_observer_set_target(&d->flux, mc_mul(d->rtrack.Phi_rel, d->rtrack.Phi_rel)); /* |eta| -> Phi_hat */
    }
    bool switched = false;
    *probing = d->probing && d->sup.state == SUP_STATE_OPEN_LOOP;
    if (*probing) {
        p001_probe(d);
    } else if (d->sup.state == SUP_STATE_OPEN_LOOP) {
        flux_circle_fit_add(&d->fit, d->flux.rho);
        const mc_t swept = mc_mul_i(mc_abs(mc_sub(d->ref.theta_rad, d->ol_theta0_rad)), c->model.n_p);
        mc_ab_t centre;
        if (!mc_lt(swept, c->handover_sweep_rad) && flux_circle_fit_center(&d->fit, &centre)) {
            flux_observer_shift(&d->flux, centre);
            resistance_tracker_unprime(&d->rtrack); /* the angle jumped */
            flux_observer_set_gradient(&d->flux, true);
            speed_load_observer_init(&d->speed, &c->speed, d->flux.unit, d->ref.omega_rad_s, MC_ZERO);
            switched = supervisor_dispatch(&d->sup, SUP_EV_ESTIMATE_TRUSTED);
        }
    } else if (d->sup.state == SUP_STATE_IDENTIFY) {
        (void)supervisor_dispatch(&d->sup, SUP_EV_IDENTIFIED);
    }
    const mc_rot_t rho = d->flux.unit;
    mc_rot_fwd(rho, i_ab.alpha, i_ab.beta, i_d, i_q);
    speed_load_observer_step_iq(&d->speed, rho, *i_q);
    return switched;
}

/* Steps 5-6 with the flux estimator: the law in the estimated dq frame,
 * IDA-PBC (11) in closed loop, else the open-loop vector (68) along the
 * reference angle (the probe's along alpha, then along the arc) expressed
 * in that frame; the bumpless switch; to alpha-beta, v_ab = (rho_a I +
 * rho_b Jm) v, (11), at the angle the rotor has on average while the
 * voltage acts ((1/2 + d) of a sample ahead in closed loop); limited by the
 * measured bus (a leg swings +-v_bus/2 about the midpoint with three
 * phases, an H-bridge +-v_bus with two); the inverter's expected error
 * added, and what the bus clamp takes of it in the voltage the observer
 * integrates. */
static P001_IN_LINE void p001_flux_output(paper001_drive_t *d, const hal_sample_t *in, bool probing, bool switched, mc_t i_d,
                             mc_t i_q, hal_command_t *out)
{
    const paper001_config_t *c = &d->cfg;
    const mc_rot_t rho = d->flux.unit;
    const bool closed = d->sup.state == SUP_STATE_CLOSED_LOOP;
    mc_t v_d, v_q;
    if (closed) {
        ida_pbc_step(&d->ctrl, &c->ctrl, i_d, i_q, d->speed.omega_rad_s, d->speed.load_Nm, d->ref.omega_rad_s,
                     d->ref.accel_rad_s2, &v_d, &v_q); /* (11) */
    } else {
        mc_rot_t ol;
        mc_t v;
        if (probing) {
            v = c->probe_v_V;
            ol = d->probe_dir;
        } else {
            v = open_loop_voltage(&c->open_loop, &c->model, d->ref.omega_rad_s);
            ol = mc_rot_compose(d->ol_origin, mc_rot_from_angle(mc_elec_angle(d->ref.theta_rad, c->model.n_p)));
        }
        mc_rot_fwd(rho, mc_mul(v, ol.c), mc_mul(v, ol.s), &v_d, &v_q);
    }
    supervisor_blend(&d->sup, switched, &v_d, &v_q);
    mc_ab_t v_ab;
    const mc_rot_t rho_out = closed ? paper001_output_rot(c, rho, d->speed.omega_rad_s) : rho;
    mc_rot_inv(rho_out, v_d, v_q, &v_ab.alpha, &v_ab.beta);
    const mc_t v_max = (c->n_phases == 3u) ? mc_div_i(in->v_bus_V, 2) : in->v_bus_V;
    (void)supervisor_limit_output(&d->sup, c->n_phases, v_max, &v_ab, &v_d, &v_q, out);
    if (d->dtc.cfg.enabled) {
        const mc_ab_t lost = deadtime_comp_step(&d->dtc, in->i_A, in->v_bus_V, out);
        v_ab.alpha = mc_add(v_ab.alpha, lost.alpha);
        v_ab.beta = mc_add(v_ab.beta, lost.beta);
    }
    flux_observer_hold(&d->flux, paper001_applied_mean(c, v_ab, d->last.v_ab_V));
    d->last.i_d_A = i_d;
    d->last.i_q_A = i_q;
    d->last.v_ab_V = v_ab;
}

bool paper001_drive_step(paper001_drive_t *d, const hal_sample_t *in, hal_command_t *out)
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
    const mc_ab_t i_ab = phase_adapter_currents(in, &i_zero_A);
    (void)i_zero_A; /* star without neutral: the measurement's offset, unused here */
    speed_profile_eval(&d->profile, d->tick, &d->ref);
    if (c->estimator == P001_ESTIMATOR_BACK_EMF && !d->probing) {
        p001_step_back_emf(d, in, i_ab, (c->n_phases == 3u) ? mc_div_i(in->v_bus_V, 2) : in->v_bus_V, out);
        return p001_finish(d, in, out);
    }
    /* 2.-4. flux observer, probe or fit or switch, speed and load observer */
    bool probing;
    mc_t i_d, i_q;
    const bool switched = p001_flux_estimate(d, i_ab, &probing, &i_d, &i_q);
    /* 5.-6. the law, to the phases, the observer told the applied voltage */
    p001_flux_output(d, in, probing, switched, i_d, i_q, out);
    return p001_finish(d, in, out);
}

bool paper001_drive_clear_fault(paper001_drive_t *d)
{
    /* an exact self-copy (d->cfg = *cfg with cfg == &d->cfg) is allowed (C11 6.5.16.1) */
    return paper001_drive_init(d, &d->cfg);
}

void paper001_drive_estimate(const paper001_drive_t *d, mc_estimate_t *e)
{
    const int32_t n_p = d->cfg.model.n_p;
    if (d->cfg.estimator == P001_ESTIMATOR_BACK_EMF) {
        /* in open loop paper 000's estimator reports the reference (the rotor follows it) */
        const bool closed = d->sup.state == SUP_STATE_CLOSED_LOOP;
        fg_estimator_get(&d->emf, closed, mc_add(d->ref.theta_rad, d->ol_origin_mech_rad), d->ref.omega_rad_s,
                         d->ref.accel_rad_s2, e);
        e->valid = closed;
        return;
    }
    /* (e + 2 pi n)/n_p without forming the sum */
    e->theta_rad = mc_add(mc_div_i(d->speed.unwrap.e_rad, n_p),
                          mc_mul_i(mc_div_i(MC_TWO_PI, n_p), d->speed.unwrap.n_turns));
    e->omega_rad_s = d->speed.omega_rad_s;
    /* (T_e - tau_hat)/J, the model acceleration of (3) */
    const speed_load_observer_config_t *sc = &d->cfg.speed;
    e->accel_rad_s2 = mc_mul_i(mc_sub(mc_mul(sc->ts_kt_over_J, d->speed.i_q_A), mc_mul(sc->ts_over_J, d->speed.load_Nm)),
                               d->cfg.model.fs_hz);
    e->load_Nm = d->speed.load_Nm;
    e->valid = d->sup.state == SUP_STATE_CLOSED_LOOP;
}

void paper001_drive_get_telemetry(const paper001_drive_t *d, paper001_telemetry_t *t)
{
    t->fw_version = MC_VERSION_U32;
    const bool fault = d->sup.state == SUP_STATE_FAULT;
    t->mode = supervisor_mode(&d->sup);
    t->fault = d->sup.fault;
    t->state = d->sup.state;
    t->tick = d->last.tick;
    t->omega_ref_rad_s = d->ref.omega_rad_s;
    t->accel_ref_rad_s2 = d->ref.accel_rad_s2;
    t->theta_ref_rad = d->ref.theta_rad;
    if (d->cfg.estimator == P001_ESTIMATOR_BACK_EMF) {
        mc_estimate_t e;
        paper001_drive_estimate(d, &e);
        const mc_t e_rad = mc_elec_angle(e.theta_rad, d->cfg.model.n_p);
        /* whole electrical turns: (n_p theta - e)/(2 pi), an integer up to rounding */
        const mc_t turns = mc_mul(mc_sub(mc_mul_i(e.theta_rad, d->cfg.model.n_p), e_rad), MC_C(0.15915494309189535));
        t->theta_e_turns = mc_round_i(turns);
        t->theta_e_rad = e_rad;
        t->omega_est_rad_s = e.omega_rad_s;
        t->load_est_Nm = e.load_Nm;
    } else {
        t->theta_e_turns = d->speed.unwrap.n_turns;
        t->theta_e_rad = d->speed.unwrap.e_rad;
        t->omega_est_rad_s = d->speed.omega_rad_s;
        t->load_est_Nm = d->speed.load_Nm;
    }
    t->rho2 = d->flux.rho2;
    t->R_obs_ohm = d->flux.cfg.R_ohm;
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
        ramp = mc_max(mc_abs(d->ref.omega_rad_s), MC_C(0.1));
    }
    return speed_profile_retarget(&d->profile, d->tick, MC_ZERO, ramp);
}

bool paper001_drive_set_omega_lim(paper001_drive_t *d, mc_t omega_lim_rad_s)
{
    const paper001_config_t *c = &d->cfg;
    if (c->estimator != P001_ESTIMATOR_BACK_EMF || d->sup.state == SUP_STATE_CLOSED_LOOP ||
        mc_lt(omega_lim_rad_s, c->omega_lim_rad_s)) {
        return false;
    }
    d->omega_lim_rad_s = omega_lim_rad_s;
    return true;
}
