/*
 * paper000_drive.c - the paper-000 drive as a recipe (see paper000_drive.h).
 *
 * Order inside one sample k (currents sampled at t_k, voltages held over
 * [t_k, t_k + Ts)), paper000_drive_step top to bottom, a function per
 * stage and per state:
 *   0. prologue, the shell's (guard_begin, supervisor/guard.h): latched
 *      fault, disabled, phase count, the fault monitor's criteria
 *      (over-current trip, ...);
 *   1. measurement: reference theta_r[k], theta_r[k+1] (eq. 70) and the
 *      (f-g) frame (6)-(8) (p000_advance_reference); the adapter's
 *      alpha-beta currents turned into it; while aligning (ALIGN,
 *      p000_align, startup/align.h) the alignment's voltage and nothing else;
 *   2. estimator correction (25) and observability;
 *   3. supervisor event (p000_supervise): the watch over synchronism and,
 *      in CLOSED_LOOP, K's measurement (p000_check_sync, p000_identify_K);
 *      the re-lock's hold and confirmation (p000_relock); closed loop when
 *      |omega_r| >= omega_lim and the back-EMF is observable (paper 000
 *      section 4.2), open loop otherwise (p000_switch);
 *   4. estimates (29)-(32), (71), (33)-(37) and the state's law:
 *      CLOSED_LOOP fg_tracking (46)-(54) or the load-angle law
 *      (p000_closed_loop), OPEN_LOOP and IDENTIFY open loop (68)
 *      (p000_open_loop); bumpless transfer at a switch;
 *   5. voltage back to the phases at the mid-sample angle, limited;
 *   6. epilogue: estimator prediction to k+1 with the voltage actually
 *      applied (p000_predict), the standstill R/L measurement while
 *      identifying (IDENTIFY, p000_identify_rl); the output, its checks
 *      and the flight recorder (p000_output).
 * With a computation delay d (paper000_delay_config_t) the voltage acts over
 * [t_k + d Ts, t_k+1 + d Ts): the law of 4 acts on the currents predicted to
 * t_k + d Ts, 5 turns the output at the middle of that interval, 6 uses the
 * mean of the last and this command; d = 0 skips these paths.
 */
#include "drives/paper000/paper000_drive.h"

#include <stddef.h>

#include "control/delay_comp.h"
#include "supervisor/guard.h"
#include "mc_version.h"

/* Samples between exact recomputations of the (f-g) frame rotation: in
 * between it turns by composition (four products per sample instead of a
 * sincos of a large angle). Each composition rounds the sine and cosine by
 * at most about one LSB (7.6e-6 in Q14.17), so 32 of them drift by at most
 * 2.4e-4 rad electrical, 5e-6 rad of rotor angle at n_p = 50, before the
 * exact angle resets it; a power of two makes the test a mask. */
#define P000_FRAME_RESYNC 32u

/* Computation delay (paper000_delay_config_t): functions called only for
 * d != 0, and kept out of line (P000_OUT_OF_LINE), so that the step
 * without a delay stays as it was (its instruction budget on a Cortex-M3
 * is nearly spent, and inlined they cost it 17 instructions a sample in
 * registers, measured with tools/bench/pil.py).
 * The step's stages and states (p000_advance_reference to
 * p000_identify_rl) and its output (p000_output) are functions for the
 * reader and one function for the compiler (P000_IN_LINE). Left to
 * itself, GCC 12 kept the supervisor's decision and the alignment out of
 * line and split the step across its operation: 64 instructions a sample
 * more on the Cortex-M3 (1,570.6 instead of 1,506.3 on average); inlined,
 * p000_output in each of its two places (no call at the end of the
 * sample), 1,498.4 (M4F float 800.5 instead of 819.5). */
#if defined(__GNUC__)
#define P000_OUT_OF_LINE __attribute__((noinline))
#define P000_IN_LINE inline __attribute__((always_inline))
#else
#define P000_OUT_OF_LINE
#define P000_IN_LINE inline
#endif

/* The measured (f-g) currents i_f, i_g of this sample predicted to
 * t_k + d Ts, where its command starts to act, in the (f-g) frame of that
 * instant, then into the estimated frame (44) for the laws (46)-(54): they
 * replace the measured i_d, i_q of the estimator. Eq. (23) (errata (9a))
 * over d Ts, L di/dt = v - R i + e, with the voltage that holds until then
 * (the last command, in its own control frame, a fraction of a sample off
 * the interval's: second order) and the observed back-EMF e = L d-hat
 * (28a)-(28b); the frame's own turn over d Ts, the A_fg term of (23), as a
 * rotation by 2d half samples of the reference's rotation. */
static P000_OUT_OF_LINE void p000_delay_currents(paper000_drive_t *d, mc_rot_t rot_half, mc_t i_f, mc_t i_g)
{
    const paper000_delay_config_t *c = &d->cfg.delay;
    const mc_rot_t turn_x = delay_rot_fraction(rot_half, c->x, c->x2);
    const mc_rot_t turn = c->from_next ? mc_rot_compose(rot_half, turn_x) : turn_x;
    mc_t i_f_pred, i_g_pred;
    delay_predict_fg(c->d, d->model.ts_over_L_A_per_V, d->model.R_ohm, i_f, i_g, d->sup.v_prev_V[0],
                     d->sup.v_prev_V[1], d->est.emf.e_f_hat_V, d->est.emf.e_g_hat_V, &i_f_pred, &i_g_pred);
    mc_t p_f, p_g;
    mc_rot_fwd(turn, i_f_pred, i_g_pred, &p_f, &p_g);
    mc_rot_fwd(d->est.u_est, p_f, p_g, &d->est.i_d_A, &d->est.i_q_A); /* (44) */
}

/* Step 5 with a delay: the (f-g) command to the phases with the frame of
 * the reference at t_k + (1/2 + d) Ts, the middle of the interval where it
 * acts (eq. (7) inverse: the mid-sample frame for d < 1/2, the next
 * sample's for d >= 1/2, turned by x half samples), limited; and, unless
 * the caller gave it, the voltage really applied over this sample for the
 * observer (25), v[k-1] for d Ts then v[k], as paper000_drive_set_applied_voltage()
 * would. Returns the phase (alpha-beta) command. */
static P000_OUT_OF_LINE mc_ab_t p000_delay_output(paper000_drive_t *d, mc_rot_t rot_mid, mc_rot_t rot_half, mc_t v_f, mc_t v_g)
{
    const paper000_delay_config_t *c = &d->cfg.delay;
    const mc_rot_t out = mc_rot_compose(c->from_next ? d->rot_next : rot_mid, delay_rot_fraction(rot_half, c->x, c->x2));
    mc_ab_t v_ab;
    mc_rot_inv(out, v_f, v_g, &v_ab.alpha, &v_ab.beta);
    (void)supervisor_limit(&d->sup, (uint8_t)P000_N_PHASES, d->cfg.limits.v_max_V, &v_ab, &v_f, &v_g);
    if (!d->v_ext_set) {
        const mc_ab_t v_last = {d->last.v_a_V, d->last.v_b_V};
        d->v_ext_V = delay_applied_mean(c->d, v_ab, v_last);
        d->v_ext_set = true;
    }
    return v_ab;
}

/* The last voltage the telemetry reports: 0, with the shell's 0 V out
 * (guard_shell_t.stopped) and at init. */
static void p000_zero_last(void *self)
{
    paper000_drive_t *d = (paper000_drive_t *)self;
    d->last.v_a_V = MC_ZERO;
    d->last.v_b_V = MC_ZERO;
}

/* This drive's re-lock (guard_shell_t.relock), asked when its reaction
 * table (paper000_protection_config_t) answers a fault with RELOCK: while
 * its budget lasts and not in the alignment, open loop from this sample on
 * (p000_switch, bumpless), closed again after the hold if the estimate is
 * trusted then. False: the fault is latched (SAFE). */
static bool p000_relock_start(void *self)
{
    paper000_drive_t *d = (paper000_drive_t *)self;
    const paper000_protection_config_t *p = &d->cfg.prot;
    if (!(d->relocks < p->relock_max && d->sup.state != SUP_STATE_ALIGN)) {
        return false;
    }
    d->relocks += 1;
    d->relock_hold = p->relock_hold_ticks;
    d->recovering = p->relock_hold_ticks + p->relock_confirm_ticks;
    d->branch_kept = d->sup.state == SUP_STATE_CLOSED_LOOP;
    return true;
}

/* The last check of a sample beyond the command's: the estimate the
 * drive runs on, finite. */
static drive_fault_t p000_check(void *self)
{
    const paper000_drive_t *d = (const paper000_drive_t *)self;
    return (mc_is_finite(d->est.pos.theta_est_rad) && mc_is_finite(d->est.mech.omega_est_rad_s))
               ? DRIVE_FAULT_NONE
               : DRIVE_FAULT_NON_FINITE;
}

/* The shell of this drive's step (supervisor/guard.h): two windings (the
 * phase count alone checked), its reaction table and re-lock, the samples
 * that ran counted. */
static const guard_shell_t p000_shell = {
    .sup = offsetof(paper000_drive_t, sup),
    .mon = offsetof(paper000_drive_t, mon),
    .rec = offsetof(paper000_drive_t, rec),
    .tick = offsetof(paper000_drive_t, tick),
    .disabled = offsetof(paper000_drive_t, disabled),
    .reaction = offsetof(paper000_drive_t, cfg.prot.reaction),
    .n_phases = (uint8_t)P000_N_PHASES,
    .accepts = NULL,
    .check = p000_check,
    .relock = p000_relock_start,
    .stopped = p000_zero_last,
    .ticks = GUARD_TICK_RUN,
};

/* A fault that no reaction but the safe state can answer. */
static bool p000_react_final(paper000_drive_t *d, drive_fault_t f)
{
    guard_latch(&d->sup, &d->rec, f, d->tick);
    return true;
}

/* The end of every sample that outputs a voltage: to the phases, the
 * command's and the estimate's checks, the shell's end (the flight
 * recorder, the count, the reaction). Returns false if the checks put the
 * drive in FAULT (out is then 0 V). */
static P000_IN_LINE bool p000_output(paper000_drive_t *d, const hal_sample_t *in, mc_ab_t v_ab, mc_t i_f, mc_t i_g,
                                     hal_command_t *out)
{
    phase_adapter_voltages((uint8_t)P000_N_PHASES, v_ab, out);
    if (d->dtc.cfg.enabled) {
        /* an inverter's expected error added to the command (each winding
         * an H-bridge). The observer has predicted with v_ab already: what
         * the bus clamp takes of the compensation is not fed back here (it
         * needs a command at the supply's limit, where the drive's own
         * limit flag is set) */
        (void)deadtime_comp_step(&d->dtc, in->i_A, in->v_bus_V, out);
    }
    d->last.i_f_A = i_f;
    d->last.i_g_A = i_g;
    d->last.v_a_V = v_ab.alpha;
    d->last.v_b_V = v_ab.beta;
    return guard_end(&p000_shell, d, in, out, d->sup.sat_prev, d->ref.theta_rad, d->est.pos.theta_est_rad,
                     d->est.mech.omega_est_rad_s) != GUARD_SAFE;
}

/* Loss of synchronism (paper000_protection_config_t), in closed loop. */
static bool p000_lost_sync(paper000_drive_t *d, bool observable)
{
    const paper000_protection_config_t *p = &d->cfg.prot;
    if (!observable) {
        /* the back-EMF vanished while the reference is fast: the twisting
         * law has lost its estimate. The load-angle law holds the rotor
         * without one: it goes on in its open-loop form (the loop opens,
         * want_closed in p000_supervise) and closes again once observable */
        return d->cfg.law != P000_LAW_LOAD_ANGLE;
    }
    if ((d->tick & (P000_LOS_DECIMATION - 1u)) != 0u) {
        return false; /* the criteria below run on every P000_LOS_DECIMATION-th sample */
    }
    const fg_estimator_t *e = &d->est;
    const mc_t theta_est = e->pos.theta_est_rad;
    /* a consistent estimate far from the reference: the rotor lags (an
     * overload) and the controller, at its limit, pulls it back; only if
     * that lasts los_track_ticks is the reference lost */
    if (fault_persist_step(&d->track_persist, mc_gt(mc_abs(mc_sub(theta_est, d->ref.theta_rad)), p->los_track_rad),
                           p->los_track_ticks)) {
        return true;
    }
    /* | |e| - K|w| | > tol K|w| + floor, on squares (no square root) */
    const mc_t kw = mc_mul(d->model.K_V_s, mc_abs(e->mech.omega_est_rad_s));
    const mc_t hi = mc_add(mc_mac(kw, kw, p->los_emf_tol), p->los_emf_floor_V);
    const mc_t lo = mc_max(MC_ZERO, mc_sub(mc_sub(kw, mc_mul(kw, p->los_emf_tol)), p->los_emf_floor_V));
    const bool emf_bad = mc_gt(e->pos.e2_V2, mc_mul(hi, hi)) || mc_lt(e->pos.e2_V2, mc_mul(lo, lo));
    /* the estimate's step against the reference's since the last check */
    const bool jump = mc_gt(mc_abs(mc_sub(mc_sub(theta_est, d->theta_est_prev_rad),
                                          mc_sub(d->ref.theta_rad, d->theta_ref_prev_rad))),
                            p->los_jump_rad);
    return fault_persist_step(&d->los_persist, emf_bad || jump, p->los_ticks);
}

/* The measured K replaces the model's everywhere it was folded in
 * (startup/k_identification.h): the model (J/K, f_v/K, ...), (30)'s 1/K
 * and the observability threshold (K omega_lim)^2, the twisting gains and
 * feed-forwards that carry J L/K or 1/K (design/paper000_design.c), the load
 * clamp 2 K I_max. r = K_old/K_new. The blocks keep their own copies of
 * their configuration, so those are what change. */
_Static_assert(K_ID_DECIMATION == P000_LOS_DECIMATION, "the K measurement runs on the loss-of-sync checks' samples");

static void p000_apply_K(paper000_drive_t *d, mc_t K_V_s)
{
    const mc_t r = mc_div(d->model.K_V_s, K_V_s);
    const mc_t inv_r = mc_div(K_V_s, d->model.K_V_s);
    motor_model_set_K(&d->model, K_V_s);
    position_estimator_config_t *pc = &d->est.pos.cfg;
    pc->inv_K_rad_s_per_V = mc_mul(pc->inv_K_rad_s_per_V, r);
    pc->e2_min_V2 = mc_mul(mc_mul(pc->e2_min_V2, inv_r), inv_r);
    d->est.mech.cfg.tau_max_Nm = mc_mul(d->est.mech.cfg.tau_max_Nm, inv_r);
    fg_tracking_config_t *cc = &d->ctrl.cfg;
    cc->pos.lambda_m = mc_mul(cc->pos.lambda_m, r);
    cc->pos.lambda_M = mc_mul(cc->pos.lambda_M, r);
    d->ctrl.pos.cfg = cc->pos;
    cc->v_k_w_V_s = mc_mul(cc->v_k_w_V_s, r);
    cc->load_ff_A_per_Nm = mc_mul(cc->load_ff_A_per_Nm, r);
    cc->load_ff_L_over_KTs = mc_mul(cc->load_ff_L_over_KTs, r);
}

/* The trajectory's sample for drive sample n: the alignment's samples all
 * map to 0 (the reference holds at its start). */
static uint32_t p000_traj_tick(const paper000_drive_t *d, uint32_t n)
{
    return n > d->align_ticks ? n - d->align_ticks : 0u;
}

/* The first inconsistency of c, named by its field (a string literal), or
 * NULL when c is consistent. The design (design/paper000_design.c) derives
 * every field; a motor or limit far outside what it was written for can
 * still give a gain that rounds to zero or overflows, and this says which. */
const char *paper000_config_problem(const paper000_config_t *c)
{
    const motor_model_t *m = &c->model;
    const drive_limits_t *l = &c->limits;
    if (m->n_p < 1) return "model.n_p: must be >= 1";
    if (m->fs_hz <= 0) return "model.fs_hz: must be > 0";
    if (!mc_ge(m->R_ohm, MC_ZERO)) return "model.R_ohm: must be >= 0";
    if (!mc_gt(m->L_H, MC_ZERO)) return "model.L_H: must be > 0 (in the numeric type)";
    if (!mc_gt(m->K_V_s, MC_ZERO)) return "model.K_V_s: must be > 0 (in the numeric type)";
    if (!mc_gt(l->v_max_V, MC_ZERO)) return "limits.v_max_V: must be > 0";
    if (!mc_gt(l->i_max_A, MC_ZERO)) return "limits.i_max_A: must be > 0";
    if (!mc_ge(l->i_trip_A, l->i_max_A)) return "limits.i_trip_A: must be >= limits.i_max_A";
    if (!mc_gt(l->omega_lim_rad_s, MC_ZERO)) return "limits.omega_lim_rad_s: must be > 0";
    if (!mc_ge(c->sup.blend_decay, MC_ZERO) || !mc_lt(c->sup.blend_decay, MC_ONE))
        return "sup.blend_decay: must be in [0, 1)";
    if (!mc_ge(c->ctrl.pos.lambda_m, MC_ZERO)) return "ctrl.pos.lambda_m: must be >= 0";
    if (!mc_ge(c->ctrl.pos.lambda_M, c->ctrl.pos.lambda_m)) return "ctrl.pos.lambda_M: must be >= ctrl.pos.lambda_m";
    if (!mc_ge(c->ctrl.cur.lambda, MC_ZERO)) return "ctrl.cur.lambda: must be >= 0";
    if (!mc_ge(c->ctrl.cur.alpha_ts, MC_ZERO)) return "ctrl.cur.alpha_ts: must be >= 0";
    if (!mc_ge(c->est.emf.alpha_V, MC_ZERO)) return "est.emf.alpha_V: must be >= 0";
    if (!mc_gt(c->est.emf.lpf_coeff, MC_ZERO) || !mc_le(c->est.emf.lpf_coeff, MC_ONE))
        return "est.emf.lpf_coeff: must be in (0, 1]";
    if (c->align.enabled &&
        !(c->align.ramp_ticks >= 1 && c->align.hold_ticks >= 0 && c->align.turn_ticks >= 1 && c->align.settle_ticks >= 0 &&
          c->align.off_ticks >= 0 && mc_gt(c->align.phi_turn_rad, MC_ZERO) && mc_lt(c->align.phi_turn_rad, MC_PI)))
        return "align: tick counts must be >= 1 (ramp, turn) or >= 0, phi_turn_rad in (0, pi)";
    if (!mc_ge(c->delay.d, MC_ZERO) || !mc_le(c->delay.d, MC_ONE)) return "delay.d: must be in [0, 1]";
    if (!mc_ge(c->delay.x, MC_ZERO) || !mc_le(c->delay.x, MC_ONE)) return "delay.x: must be in [0, 1]";
    if (!mc_ge(c->delay.x2, MC_ZERO) || !mc_le(c->delay.x2, c->delay.x)) return "delay.x2: must be in [0, delay.x]";
    return NULL; /* the trajectory: trajectory_init's own check */
}

bool paper000_drive_init(paper000_drive_t *d, const paper000_config_t *cfg)
{
    d->cfg = *cfg;
    d->model = cfg->model;
    d->tick = 0;
    d->observable_run = 0;
    d->disabled = false;
    d->omega_lim_rad_s = cfg->limits.omega_lim_rad_s;
    d->v_ext_set = false;
    d->v_ext_V.alpha = MC_ZERO;
    d->v_ext_V.beta = MC_ZERO;
    fg_estimator_init(&d->est, &cfg->est);
    fg_tracking_init(&d->ctrl, &cfg->ctrl);
    load_angle_init(&d->la, &cfg->load_angle);
    d->la_from_other = true;
    const bool traj_ok = trajectory_init(&d->traj, &cfg->traj) && deadtime_comp_init(&d->dtc, &cfg->deadtime);
    rl_id_init(&d->rl_id, &cfg->rl_id);
    k_id_init(&d->k_id, &cfg->k_id);
    fault_monitor_init(&d->mon, &cfg->faults);
    flight_recorder_init(&d->rec);
    d->relocks = 0;
    d->relock_hold = 0;
    d->recovering = 0;
    d->branch_kept = false;
    d->los_persist.run = 0;
    d->obs_persist.run = 0;
    d->track_persist.run = 0;
    d->theta_est_prev_rad = MC_ZERO;
    d->theta_ref_prev_rad = MC_ZERO;
    align_init(&d->align, &cfg->align);
    const int32_t n_align = align_total_ticks(&cfg->align);
    d->align_ticks = n_align > 0 ? (uint32_t)n_align : 0u;
    supervisor_init(&d->sup, &cfg->sup, n_align > 0, d->rl_id.state == RL_ID_RUNNING);
    d->last.tick = 0;
    d->last.i_f_A = MC_ZERO;
    d->last.i_g_A = MC_ZERO;
    p000_zero_last(d);
    if (paper000_config_problem(cfg) != NULL || !traj_ok) {
        guard_latch(&d->sup, &d->rec, DRIVE_FAULT_BAD_INPUT, d->tick);
        return false;
    }
    trajectory_eval(&d->traj, 0, &d->ref);
    trajectory_eval(&d->traj, p000_traj_tick(d, 1), &d->ref_next);
    d->rot_k = mc_rot_from_angle(mc_elec_angle(d->ref.theta_rad, cfg->model.n_p));
    d->rot_next = d->rot_k;
    d->rot_resync = d->rot_k; /* formed at sample P000_FRAME_RESYNC - 1 before its use */
    return true;
}

/* 1. The reference of this sample, eq. (70), and the frame's rotation
 * U(n_p theta_r[k]), eq. (8), that fg_estimator_front turns the currents
 * with; sample 0 keeps what paper000_drive_init formed. */
static P000_IN_LINE void p000_advance_reference(paper000_drive_t *d)
{
    if (d->tick > 0) {
        /* advance the reference: this sample's is the one computed last time */
        d->ref = d->ref_next;
        trajectory_eval(&d->traj, p000_traj_tick(d, d->tick + 1), &d->ref_next);
        /* the frame turns by the rotation applied last sample; every
         * P000_FRAME_RESYNC samples it is recomputed from theta_r, so the
         * rounding of the products cannot accumulate */
        if ((d->tick % P000_FRAME_RESYNC) == 0u) {
            /* U(n_p theta_r[k]) formed exactly by the last sample, from
             * this sample's reference (its ref_next, which nothing changes
             * in between: a move starts after it), the same value as
             * forming it here; spread so, the sincos does not land on
             * this sample, which also runs the decimated checks (their
             * period divides P000_FRAME_RESYNC) */
            d->rot_k = d->rot_resync;
            /* the observer's gain at the reference speed (discrete-time
             * design; a no-op otherwise): the speed moves by at most
             * |w'|max 32 Ts = 0.1 rad/s in between for the rig */
            fg_estimator_schedule(&d->est, d->ref.omega_rad_s);
        } else {
            d->rot_k = d->rot_next;
            if (((d->tick + 1u) % P000_FRAME_RESYNC) == 0u) {
                d->rot_resync = mc_rot_from_angle(mc_elec_angle(d->ref_next.theta_rad, d->model.n_p));
            }
        }
    }
}

/* ALIGN (startup/align.h): the alignment's voltage and nothing else.
 * Returns true while it aligns, *v_ab then the sample's phase voltage,
 * limited; at its end, false: the estimator starts again from its initial
 * state and the sample goes on in the start state (IDENTIFY or
 * OPEN_LOOP). */
static P000_IN_LINE bool p000_align(paper000_drive_t *d, mc_rot_t rot_k, mc_ab_t *v_ab)
{
    const paper000_config_t *c = &d->cfg;
    mc_t v_f, v_g;
    const mc_t v_hold = open_loop_voltage(&c->open_loop, &d->model, MC_ZERO); /* (68) at rest */
    if (!align_step(&d->align, v_hold, &v_f, &v_g)) {
        /* the reference holds, so the frame does not turn: rot_mid = rot_k */
        mc_rot_inv(rot_k, v_f, v_g, &v_ab->alpha, &v_ab->beta);
        (void)supervisor_limit(&d->sup, (uint8_t)P000_N_PHASES, c->limits.v_max_V, v_ab, &v_f, &v_g);
        return true;
    }
    /* aligned, current decayed: the start begins from rest as without
     * an alignment, with the estimator in its initial state */
    (void)supervisor_dispatch(&d->sup, SUP_EV_ALIGNED);
    fg_estimator_init(&d->est, &c->est);
    return false;
}

/* K identification (startup/k_identification.h), in CLOSED_LOOP on the
 * loss-of-sync checks' samples (its K_ID_DECIMATION is
 * P000_LOS_DECIMATION), not while a loss is recovered from: from the
 * back-EMF's magnitude (28) at the reference speed; once measured, K
 * replaces the model's everywhere (p000_apply_K). Its state is looked at
 * first: once K is measured, rejected or kept, k_id_step does nothing, and
 * the checks' samples no longer call it. */
static P000_IN_LINE void p000_identify_K(paper000_drive_t *d)
{
    if (d->k_id.state == K_ID_RUNNING && k_id_step(&d->k_id, d->est.pos.e2_V2, d->ref.omega_rad_s) &&
        d->k_id.state == K_ID_DONE) {
        p000_apply_K(d, d->k_id.K_V_s);
    }
}

/* The watch over synchronism: the current observer's error (every state
 * but the alignment) and, in closed loop while the reference is fast, the
 * loss-of-synchronism criteria (p000_lost_sync); a loss is a
 * LOSS_OF_SYNC fault, reacted to as configured (guard_reaction: RELOCK
 * starts a re-lock, p000_relock_start). On the checks' samples, the
 * estimate and reference kept for the jump criterion, and K's measurement
 * in closed loop. Returns false when the drive is now in FAULT (the step
 * outputs 0 V, guard_stop). */
static P000_IN_LINE bool p000_check_sync(paper000_drive_t *d, bool fast, bool observable)
{
    const paper000_protection_config_t *p = &d->cfg.prot;
    const bool check = (d->tick & (P000_LOS_DECIMATION - 1u)) == 0u;
    const bool obs_bad =
        check && fault_persist_step(&d->obs_persist,
                                    mc_gt(mc_max(mc_abs(d->est.emf.err_f_A), mc_abs(d->est.emf.err_g_A)),
                                          p->los_obs_err_A),
                                    p->los_ticks);
    const bool lost = d->sup.state == SUP_STATE_CLOSED_LOOP && fast && p000_lost_sync(d, observable);
    if ((lost || obs_bad) && guard_reaction(&p000_shell, d, DRIVE_FAULT_LOSS_OF_SYNC) == GUARD_SAFE) {
        return false;
    }
    if (lost || obs_bad) {
        d->los_persist.run = 0;
        d->obs_persist.run = 0;
    }
    if (check) {
        d->theta_est_prev_rad = d->est.pos.theta_est_rad;
        d->theta_ref_prev_rad = d->ref.theta_rad;
        if (d->sup.state == SUP_STATE_CLOSED_LOOP && d->recovering == 0) {
            p000_identify_K(d);
        }
    }
    return true;
}

/* The re-lock (started by p000_relock_start after a loss of
 * synchronism): open loop for relock_hold_ticks, then closed again if the
 * estimate is trusted; confirmed by relock_confirm_ticks of closed loop.
 * Returns false when the loss stands (the drive is now in FAULT). */
static P000_IN_LINE bool p000_relock(paper000_drive_t *d, bool fast, bool observable)
{
    if (d->relock_hold > 0) {
        /* while recovering, (29) and (71) went on counting the rotor's
         * turns as long as the back-EMF stayed observable: the branch is
         * then kept at the re-lock (the rotor need not be on the
         * reference, and slipped pitches are made good), else it is
         * chosen again next to the reference */
        d->relock_hold -= 1;
        d->branch_kept = d->branch_kept && fast && observable;
    }
    /* a recovery ends when the loop has stayed closed for
     * relock_confirm_ticks after the hold; if the reference slows below
     * omega_lim first, the rotor's position can no longer be checked: the
     * loss stands, and the drive goes to the safe state */
    if (d->recovering > 0) {
        if (!fast) {
            (void)p000_react_final(d, DRIVE_FAULT_LOSS_OF_SYNC);
            return false;
        }
        d->recovering -= (d->relock_hold == 0 && d->sup.state == SUP_STATE_CLOSED_LOOP) ? 1 : 0;
    }
    return true;
}

/* The switch between OPEN_LOOP (or IDENTIFY) and CLOSED_LOOP that the
 * decision asks for; at a close, the branch of the jump count (71) is
 * chosen next to the reference unless a re-lock kept it. Returns true when
 * the state changed (the law's bumpless transfer then starts). */
static P000_IN_LINE bool p000_switch(paper000_drive_t *d, bool want_closed)
{
    bool switched = false;
    if (want_closed != (d->sup.state == SUP_STATE_CLOSED_LOOP)) {
        switched = supervisor_dispatch(&d->sup, want_closed ? SUP_EV_ESTIMATE_TRUSTED : SUP_EV_ESTIMATE_LOST);
        if (switched && want_closed) {
            if (!d->branch_kept) {
                fg_estimator_lock_branch(&d->est, d->ref.theta_rad);
            }
            d->branch_kept = false;
        }
    }
    return switched;
}

/* 3. The supervisor's event: closed loop when the reference is fast, the
 * back-EMF observable and no loss of synchronism is being recovered
 * from (a loss detected in closed loop is a fault: p000_lost_sync).
 * The loop closes only on an estimate that has been observable for
 * close_dwell_ticks samples in a row, so that a back-EMF hovering at
 * the threshold cannot toggle the mode (and pile up the switch
 * offsets) sample after sample; it opens at once. Returns false when a
 * fault put the drive in FAULT (the step outputs 0 V); else *switched
 * says whether the state changed between open and closed loop. */
static P000_IN_LINE bool p000_supervise(paper000_drive_t *d, bool *switched)
{
    const paper000_config_t *c = &d->cfg;
    const bool fast = !mc_lt(mc_abs(d->ref.omega_rad_s), d->omega_lim_rad_s);
    const bool observable = fg_estimator_observable(&d->est);
    if (!observable) {
        d->observable_run = 0;
    } else if (d->observable_run < c->close_dwell_ticks) {
        d->observable_run += 1u;
    }
    const bool dwell_ok = d->sup.state == SUP_STATE_CLOSED_LOOP || !(d->observable_run < c->close_dwell_ticks);
    /* (29), (71) where the angle is used, and through a re-lock's hold
     * (the jump count goes on counting the rotor's turns) */
    if (fast && observable && (dwell_ok || d->relock_hold > 0)) {
        fg_estimator_track(&d->est, d->ref.theta_rad, d->ref.omega_rad_s);
    }
    if (!p000_check_sync(d, fast, observable) || !p000_relock(d, fast, observable)) {
        return false;
    }
    const bool want_closed = fast && observable && d->relock_hold == 0 && dwell_ok;
    /* the hand-over to open loop as the reference slows: the open loop
     * (68) pulls the rotor to the nearest equilibrium of the reference's
     * field, so a rotor that the estimate puts more than half a pitch away
     * would be pulled onto another tooth, silently: a loss of synchronism */
    if (!fast && d->sup.state == SUP_STATE_CLOSED_LOOP &&
        mc_gt(mc_abs(mc_sub(d->est.pos.theta_est_rad, d->ref.theta_rad)), c->prot.los_track_rad)) {
        (void)p000_react_final(d, DRIVE_FAULT_LOSS_OF_SYNC);
        return false;
    }
    *switched = p000_switch(d, want_closed);
    return true;
}

/* CLOSED_LOOP: the estimates (29)-(32), (71), (33)-(37) and the law on
 * them, fg_tracking (46)-(54) (started at the switch, bumpless) or the
 * load-angle law. */
static P000_IN_LINE void p000_closed_loop(paper000_drive_t *d, mc_rot_t rot_half, mc_t i_f, mc_t i_g, bool switched,
                                          mc_t *v_f, mc_t *v_g)
{
    const paper000_config_t *c = &d->cfg;
    mc_estimate_t est;
    fg_estimator_get(&d->est, true, d->ref.theta_rad, d->ref.omega_rad_s, d->ref.accel_rad_s2, &est);
    if (mc_ne(c->delay.d, MC_ZERO)) {
        /* the law acts on the currents predicted to where its command
         * starts to act (they replace the measured ones of (44)) */
        p000_delay_currents(d, rot_half, i_f, i_g);
    }
    if (c->law == P000_LAW_LOAD_ANGLE) {
        /* the law's currents in the reference's frame: the measured
         * ones, or their prediction turned back from the estimated frame */
        mc_t i_f_law = i_f, i_g_law = i_g;
        if (mc_ne(c->delay.d, MC_ZERO)) {
            mc_rot_inv(d->est.u_est, d->est.i_d_A, d->est.i_q_A, &i_f_law, &i_g_law);
        }
        load_angle_step(&d->la, &d->model, &d->ref, i_f_law, i_g_law, true, est.omega_rad_s, est.load_Nm,
                        d->sup.sat_prev, v_f, v_g);
    } else {
        if (switched) {
            fg_tracking_start(&d->ctrl, &d->model, c->limits.i_max_A, &d->ref, &d->ref_next, est.load_Nm,
                              d->est.i_d_A, d->est.i_q_A);
        }
        fg_tracking_step(&d->ctrl, &d->model, c->limits.i_max_A, &d->ref, &d->ref_next, &est, d->est.u_est,
                         d->est.i_d_A, d->est.i_q_A, d->sup.sat_prev, v_f, v_g);
    }
}

/* OPEN_LOOP and IDENTIFY (the reference below omega_lim, or the estimate
 * not trusted): the open-loop drive (68); with the load-angle law, its
 * form without an estimate in OPEN_LOOP (after the R, L measurement). */
static P000_IN_LINE void p000_open_loop(paper000_drive_t *d, mc_t i_f, mc_t i_g, mc_t *v_f, mc_t *v_g)
{
    const paper000_config_t *c = &d->cfg;
    if (c->law == P000_LAW_LOAD_ANGLE && d->sup.state == SUP_STATE_OPEN_LOOP) {
        if (d->la_from_other) {
            /* from (68): the amplitude starts at the current's */
            load_angle_start(&d->la, mc_hypot(i_f, i_g));
        }
        /* no estimate: the last observed load held, no damping */
        load_angle_step(&d->la, &d->model, &d->ref, i_f, i_g, false, MC_ZERO, MC_ZERO, d->sup.sat_prev, v_f, v_g);
    } else {
        *v_f = open_loop_voltage(&c->open_loop, &d->model, d->ref.omega_rad_s); /* eq. (68) */
        *v_g = MC_ZERO;
    }
}

/* 6. The observer's prediction (25) to k+1 with the voltage applied over
 * the sample, in the mid-sample frame: the command, or what
 * paper000_drive_set_applied_voltage() or the delay's mean gave. Returns
 * that voltage's f component. */
static P000_IN_LINE mc_t p000_predict(paper000_drive_t *d, mc_rot_t rot_mid, mc_rot_t rot_half, mc_t v_f, mc_t v_g,
                                      mc_t i_f, mc_t i_g)
{
    mc_t v_f_obs = v_f, v_g_obs = v_g;
    if (d->v_ext_set) {
        mc_rot_fwd(rot_mid, d->v_ext_V.alpha, d->v_ext_V.beta, &v_f_obs, &v_g_obs);
        d->v_ext_set = false;
    }
    fg_estimator_predict(&d->est, &d->model, v_f_obs, v_g_obs, i_f, i_g, rot_half);
    return v_f_obs;
}

/* IDENTIFY: the standstill R, L measurement (startup/rl_identification.h)
 * on the open-loop start's current (68) and the voltage applied (at rest
 * the frames coincide); at its end the drive goes to OPEN_LOOP. */
static P000_IN_LINE void p000_identify_rl(paper000_drive_t *d, mc_t i_f, mc_t v_f)
{
    if (rl_id_step(&d->rl_id, i_f, v_f, d->ref.omega_rad_s)) {
        if (d->rl_id.state == RL_ID_DONE) {
            /* the measured R and L replace the model's everywhere at once:
             * observer (23), references (39), decoupling (48), (54), (68) */
            motor_model_set_rl(&d->model, d->rl_id.R_ohm, d->rl_id.L_fs_ohm);
        }
        (void)supervisor_dispatch(&d->sup, SUP_EV_IDENTIFIED);
    }
}

/* One sample, top to bottom (the file's head gives the order and the
 * delay's paths). */
bool paper000_drive_step(paper000_drive_t *d, const hal_sample_t *in, hal_command_t *out)
{
    const paper000_config_t *c = &d->cfg;
    d->last.tick = d->tick;
    /* 0. prologue, the shell's (supervisor/guard.h): a latched fault, a
     * disabled drive, a sample of another phase count, the fault monitor's
     * criteria on the sample (over-current, ...; RELOCK starts a re-lock) */
    const guard_action_t a = guard_begin(&p000_shell, d, in, out);
    if (a == GUARD_SAFE || a == GUARD_IDLE) {
        return a == GUARD_IDLE; /* 0 V out */
    }

    /* 1. measurement: the currents, the reference and the frame (6)-(8)
     * of this sample, its rotation over the sample, the currents in it
     * (the estimator's front, estimators/fg_estimator.h) */
    mc_t i_zero_A;
    const mc_ab_t i_ab = phase_adapter_currents(in, &i_zero_A);
    (void)i_zero_A; /* two separate windings: no zero sequence */
    p000_advance_reference(d);
    fg_frame_t fr;
    mc_t i_f, i_g;
    fg_estimator_front(&fr, d->rot_k, d->ref.theta_rad, d->ref_next.theta_rad, d->model.n_p, i_ab, &i_f, &i_g);
    const mc_rot_t rot_k = fr.k, rot_half = fr.half, rot_mid = fr.mid;
    d->rot_next = mc_rot_compose(rot_mid, rot_half);
    mc_ab_t v_ab;
    if (d->sup.state == SUP_STATE_ALIGN && p000_align(d, rot_k, &v_ab)) {
        return p000_output(d, in, v_ab, i_f, i_g, out);
    }

    /* 2. estimator correction (25) */
    fg_estimator_correct(&d->est, i_f, i_g);

    /* 3. supervisor: faults, the re-lock, open or closed loop */
    bool switched = false;
    if (!p000_supervise(d, &switched)) {
        (void)guard_stop(&p000_shell, d, GUARD_SAFE, out);
        return false;
    }

    /* 4. the state's estimates and law; bumpless transfer at a switch */
    const bool closed = d->sup.state == SUP_STATE_CLOSED_LOOP;
    fg_estimator_mechanics(&d->est, &d->model, closed, d->ref.omega_rad_s, i_f, i_g);
    mc_t v_f, v_g;
    if (closed) {
        p000_closed_loop(d, rot_half, i_f, i_g, switched, &v_f, &v_g);
    } else {
        p000_open_loop(d, i_f, i_g, &v_f, &v_g);
    }
    /* the load-angle law runs in OPEN_LOOP and CLOSED_LOOP; any other state
     * (the R, L measurement, the alignment) drives another law */
    d->la_from_other = d->sup.state != SUP_STATE_OPEN_LOOP && d->sup.state != SUP_STATE_CLOSED_LOOP;
    supervisor_blend(&d->sup, switched, &v_f, &v_g);
    fg_tracking_relax(&d->ctrl);

    /* 5. to the phases at the mid-sample angle (the average (f-g) voltage over
     * the hold is then the commanded one; with a delay, the middle of the
     * interval where it acts), limited per phase to +-V_max with the
     * direction kept */
    if (mc_eq(c->delay.d, MC_ZERO)) {
        mc_rot_inv(rot_mid, v_f, v_g, &v_ab.alpha, &v_ab.beta);
        /* the supervisor keeps the saturation (sat_prev) for the next step's
         * anti-windup and for the telemetry */
        (void)supervisor_limit(&d->sup, (uint8_t)P000_N_PHASES, c->limits.v_max_V, &v_ab, &v_f, &v_g);
    } else {
        v_ab = p000_delay_output(d, rot_mid, rot_half, v_f, v_g);
        v_f = d->sup.v_prev_V[0]; /* the command as limited */
        v_g = d->sup.v_prev_V[1];
    }

    /* 6. epilogue: the observer's prediction with the applied voltage; in
     * IDENTIFY, the R, L measurement integrates it too */
    const mc_t v_f_obs = p000_predict(d, rot_mid, rot_half, v_f, v_g, i_f, i_g);
    if (d->sup.state == SUP_STATE_IDENTIFY) {
        p000_identify_rl(d, i_f, mc_ne(c->delay.d, MC_ZERO) ? v_f_obs : v_f);
    }
    return p000_output(d, in, v_ab, i_f, i_g, out);
}

bool paper000_drive_clear_fault(paper000_drive_t *d)
{
    /* an exact self-copy (d->cfg = *cfg with cfg == &d->cfg) is allowed (C11 6.5.16.1) */
    return paper000_drive_init(d, &d->cfg);
}

bool paper000_drive_set_enabled(paper000_drive_t *d, bool on)
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
    return paper000_drive_init(d, &d->cfg);
}

/* Samples of a duration of s seconds at fs_hz, rounded, in integer
 * arithmetic on the whole and fractional seconds (s fs overflows Q14.17). */
static uint32_t p000_ticks_of(mc_t s, int32_t fs_hz)
{
    const int32_t whole = mc_round_i(s);
    const int32_t frac = mc_round_i(mc_mul_i(mc_sub(s, mc_from_i(whole)), fs_hz));
    const int64_t n = (int64_t)whole * fs_hz + frac;
    return n < 1 ? 1u : (uint32_t)n;
}

/* The end of the last configured move, in trajectory samples. */
static uint32_t p000_traj_end(const paper000_drive_t *d)
{
    const trajectory_config_t *tc = &d->traj.cfg;
    if (tc->n_segments <= 0) {
        return 0u;
    }
    const trajectory_segment_t *s = &tc->seg[tc->n_segments - 1];
    return s->start_tick + s->duration_ticks;
}

bool paper000_drive_move(paper000_drive_t *d, mc_t theta_to_rad, mc_t duration_s)
{
    const paper000_config_t *c = &d->cfg;
    const bool running = d->sup.state == SUP_STATE_OPEN_LOOP || d->sup.state == SUP_STATE_CLOSED_LOOP;
    /* the reference of the next step was evaluated at traj(tick + 1) by the
     * last step (ref_next): the move starts after it, from the rest value */
    const uint32_t now = p000_traj_tick(d, d->tick + 1u);
    if (d->disabled || !running || now < p000_traj_end(d) || !mc_gt(duration_s, MC_ZERO) ||
        !mc_gt(c->move_speed_max_rad_s, MC_ZERO)) {
        return false;
    }
    /* eq. (70)'s peaks: 2.1875 |d|/T and 7.5132 |d|/T^2 (POLY7_DP_MAX,
     * POLY7_DDP_MAX of design/paper000_design.c), checked as products so
     * nothing overflows: |v| T <= ..., with v = d/T */
    const mc_t from = d->ref_next.theta_rad;
    const mc_t dist = mc_abs(mc_sub(theta_to_rad, from));
    if (mc_gt(mc_mul(dist, MC_C(2.1875)), mc_mul(c->move_speed_max_rad_s, duration_s))) {
        return false;
    }
    const mc_t v = mc_div(dist, duration_s);
    if (mc_gt(mc_mul(v, MC_C(7.5132)), mc_mul(c->move_accel_max_rad_s2, duration_s))) {
        return false;
    }
    /* the jerk scale d/T^3 and 21 d (the polynomial's largest
     * coefficient) within half the numeric range */
    const mc_t a = mc_div(v, duration_s);
    if (mc_gt(a, mc_mul(MC_C(8192.0), duration_s)) || mc_gt(dist, MC_C(390.0))) {
        return false;
    }
    trajectory_config_t tc = d->traj.cfg;
    tc.theta_start_rad = from;
    tc.n_segments = 1;
    trajectory_segment_t *s = &tc.seg[0];
    *s = (trajectory_segment_t){0};
    s->start_tick = now + 1u;
    s->duration_ticks = p000_ticks_of(duration_s, tc.fs_hz);
    s->theta_to_rad = theta_to_rad;
    trajectory_t t;
    if (!trajectory_init(&t, &tc)) {
        return false;
    }
    d->traj = t;
    return true;
}

bool paper000_drive_stop(paper000_drive_t *d)
{
    if (d->sup.state == SUP_STATE_FAULT) {
        return false;
    }
    /* keep the moves that have started by the next step's reference */
    const uint32_t now = p000_traj_tick(d, d->tick + 1u);
    trajectory_config_t tc = d->traj.cfg;
    int32_t n = 0;
    while (n < tc.n_segments && tc.seg[n].start_tick <= now) {
        n += 1;
    }
    if (n == tc.n_segments) {
        return true;
    }
    tc.n_segments = n;
    trajectory_t t;
    if (!trajectory_init(&t, &tc)) {
        return false;
    }
    d->traj = t;
    return true;
}

bool paper000_drive_set_omega_lim(paper000_drive_t *d, mc_t omega_lim_rad_s)
{
    const paper000_config_t *c = &d->cfg;
    if (d->sup.state == SUP_STATE_CLOSED_LOOP || mc_lt(omega_lim_rad_s, c->limits.omega_lim_rad_s) ||
        mc_gt(omega_lim_rad_s, c->move_speed_max_rad_s)) {
        return false;
    }
    d->omega_lim_rad_s = omega_lim_rad_s;
    return true;
}

void paper000_drive_get_telemetry(const paper000_drive_t *d, paper000_telemetry_t *t)
{
    t->fw_version = MC_VERSION_U32;
    const bool closed = d->sup.state == SUP_STATE_CLOSED_LOOP;
    const fg_estimator_t *e = &d->est;
    t->mode = supervisor_mode(&d->sup);
    t->fault = d->sup.fault;
    t->state = d->sup.state;
    t->tick = d->last.tick;
    t->theta_ref_rad = d->ref.theta_rad;
    t->omega_ref_rad_s = d->ref.omega_rad_s;
    t->accel_ref_rad_s2 = d->ref.accel_rad_s2;
    /* references: the law's in closed loop; the open-loop start (68)
     * drives i_max along f; none in FAULT */
    const bool fault = d->sup.state == SUP_STATE_FAULT;
    if (d->cfg.law == P000_LAW_LOAD_ANGLE && (closed || d->sup.state == SUP_STATE_OPEN_LOOP)) {
        t->i_f_ref_A = d->la.i_f_ref_A;
        t->i_g_ref_A = d->la.i_g_ref_A;
    } else {
        t->i_f_ref_A = closed ? d->ctrl.i_f_ref_A : (fault ? MC_ZERO : d->cfg.open_loop.i_max_A);
        t->i_g_ref_A = closed ? d->ctrl.i_g_ref_A : MC_ZERO;
    }
    t->i_f_A = d->last.i_f_A;
    t->i_g_A = d->last.i_g_A;
    /* the estimate the last sample was corrected with */
    t->i_f_hat_A = mc_sub(d->last.i_f_A, e->emf.err_f_A);
    t->i_g_hat_A = mc_sub(d->last.i_g_A, e->emf.err_g_A);
    t->e_f_hat_V = e->emf.e_f_hat_V;
    t->e_g_hat_V = e->emf.e_g_hat_V;
    t->delta_theta_est_rad = closed ? e->pos.dtheta_est_rad
                                    : (e->pos.valid ? position_estimator_angle(&e->pos, e->emf.e_f_hat_V,
                                                                               e->emf.e_g_hat_V, d->ref.omega_rad_s)
                                                    : MC_ZERO);
    t->jump_count = e->pos.k;
    mc_estimate_t est;
    fg_estimator_get(e, closed, d->ref.theta_rad, d->ref.omega_rad_s, d->ref.accel_rad_s2, &est);
    t->theta_est_rad = est.theta_rad;
    t->omega_est_rad_s = est.omega_rad_s;
    t->accel_est_rad_s2 = est.accel_rad_s2;
    t->load_est_Nm = est.load_Nm;
    /* the command of the last step, after the limit, is the supervisor's
     * (0 V in FAULT) */
    t->v_f_V = fault ? MC_ZERO : d->sup.v_prev_V[0];
    t->v_g_V = fault ? MC_ZERO : d->sup.v_prev_V[1];
    t->v_a_V = d->last.v_a_V;
    t->v_b_V = d->last.v_b_V;
    t->v_saturated = !fault && d->sup.sat_prev;
    t->rl_id_state = d->rl_id.state;
    t->fault_events = d->rec.events;
    t->relocks = d->relocks;
    t->overruns = d->mon.overruns;
    t->R_model_ohm = d->model.R_ohm;
    t->L_model_H = d->model.L_H;
    t->k_id_state = d->k_id.state;
    t->K_model_V_s = d->model.K_V_s;
}

void paper000_drive_set_applied_voltage(paper000_drive_t *d, mc_t v_a_V, mc_t v_b_V)
{
    d->v_ext_V.alpha = v_a_V;
    d->v_ext_V.beta = v_b_V;
    d->v_ext_set = true;
}
