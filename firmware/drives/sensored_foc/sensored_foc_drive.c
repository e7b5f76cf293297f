/*
 * sensored_foc_drive.c - the sensored FOC drive as a recipe
 * (sensored_foc_drive.h). Order inside one sample k (currents and the
 * encoder's angle sampled at t_k, the voltage acting d Ts later):
 *   0. the shell (supervisor/guard.h): latch, enable, the sample's
 *      checks, the fault monitor;
 *   1. Clarke and Park at the encoder's electrical angle: i_d, i_q;
 *   2. the encoder observer with the torque K_t i_q: angle, speed, load;
 *   3. the reference: speed profile, or the move (and its position loop);
 *   4. speed PI -> i_q* (load and J a_ref fed forward), i_d* = 0;
 *   5. current PIs with the decoupling terms, limited to the bus's circle;
 *   6. inverse Park at the angle the rotor has on average while the voltage
 *      acts, (1/2 + d) Ts ahead; the command's checks; the flight recorder.
 */
#include "drives/sensored_foc/sensored_foc_drive.h"

#include <stddef.h>

#include "control/delay_comp.h"
#include "supervisor/guard.h"
#include "trajectory/trajectory.h"

/* The largest phase voltage three legs give with the zero sequence the
 * phase adapter adds (min-max injection): v_bus / sqrt(3). */
#define SFOC_INV_SQRT3 MC_C(0.57735026918962576)

/* A sample the drive runs on: the encoder's angle, finite, and the bus
 * above its minimum (beyond the phase count, the shell's). */
static bool sfoc_accepts(const void *self, const hal_sample_t *in)
{
    const sensored_foc_drive_t *d = (const sensored_foc_drive_t *)self;
    return in->has_angle && mc_gt(in->v_bus_V, d->cfg.v_bus_min_V) && mc_is_finite(in->angle_rad);
}

/* The last check of a sample beyond the command's: the estimate the
 * drive runs on, finite. */
static drive_fault_t sfoc_check(void *self)
{
    const sensored_foc_drive_t *d = (const sensored_foc_drive_t *)self;
    return (mc_is_finite(d->obs.theta_rad) && mc_is_finite(d->obs.omega_rad_s)) ? DRIVE_FAULT_NONE
                                                                                 : DRIVE_FAULT_NON_FINITE;
}

/* The last voltage the telemetry reports: 0, with the shell's 0 V out
 * (guard_shell_t.stopped) and at init. */
static void sfoc_zero_last(void *self)
{
    sensored_foc_drive_t *d = (sensored_foc_drive_t *)self;
    d->last.v_ab_V.alpha = MC_ZERO;
    d->last.v_ab_V.beta = MC_ZERO;
    d->last.v_d_V = MC_ZERO;
    d->last.v_q_V = MC_ZERO;
}

/* The shell of this drive's step (supervisor/guard.h): three phases, its
 * own checks of a sample, its reaction table, no re-lock (an encoder's
 * angle is not lost: RELOCK acts as SAFE), the samples that ran counted. */
static const guard_shell_t sfoc_shell = {
    .sup = offsetof(sensored_foc_drive_t, sup),
    .mon = offsetof(sensored_foc_drive_t, mon),
    .rec = offsetof(sensored_foc_drive_t, rec),
    .tick = offsetof(sensored_foc_drive_t, tick),
    .disabled = offsetof(sensored_foc_drive_t, disabled),
    .reaction = offsetof(sensored_foc_drive_t, cfg.reaction),
    .n_phases = (uint8_t)SFOC_N_PHASES,
    .accepts = sfoc_accepts,
    .check = sfoc_check,
    .relock = NULL,
    .stopped = sfoc_zero_last,
    .ticks = GUARD_TICK_RUN,
};

const char *sensored_foc_config_problem(const sensored_foc_config_t *c)
{
    if (c->model.n_p < 1) {
        return "model.n_p: must be >= 1";
    }
    if (c->model.fs_hz <= 0 || !mc_gt(c->model.ts_s, MC_ZERO)) {
        return "model.fs_hz, model.ts_s: must be > 0";
    }
    if (!mc_gt(c->kt_Nm_per_A, MC_ZERO) || !mc_gt(c->inv_kt_A_per_Nm, MC_ZERO) || !mc_gt(c->model.J_kgm2, MC_ZERO)) {
        return "kt_Nm_per_A, inv_kt_A_per_Nm, model.J_kgm2: must be > 0";
    }
    if (!mc_gt(c->i_max_A, MC_ZERO) || !mc_gt(c->v_bus_min_V, MC_ZERO)) {
        return "i_max_A, v_bus_min_V: must be > 0";
    }
    if (!mc_ge(c->compute_delay, MC_ZERO) || !mc_le(c->compute_delay, MC_ONE)) {
        return "compute_delay: must be in [0, 1]";
    }
    if (!mc_ge(c->pos_kp_per_s, MC_ZERO) || !mc_gt(c->speed_cmd_max_rad_s, MC_ZERO) ||
        !mc_gt(c->accel_cmd_max_rad_s2, MC_ZERO)) {
        return "pos_kp_per_s >= 0, speed_cmd_max_rad_s and accel_cmd_max_rad_s2 > 0";
    }
    return 0;
}

bool sensored_foc_drive_init(sensored_foc_drive_t *d, const sensored_foc_config_t *cfg)
{
    d->cfg = *cfg;
    guard_start_closed_loop(&d->sup);
    d->disabled = false;
    d->started = false;
    d->mode = SFOC_MODE_SPEED;
    d->tick = 0u;
    d->stop_ramp_rad_s2 = cfg->accel_cmd_max_rad_s2;
    d->move.theta0_rad = MC_ZERO;
    d->move.delta_rad = MC_ZERO;
    d->move.inv_ticks = MC_ZERO;
    d->move.inv_T_s = MC_ZERO;
    d->move.t0_tick = 0u;
    d->move.n_ticks = 0u;
    d->last.theta_ref_rad = MC_ZERO;
    d->last.omega_ref_rad_s = MC_ZERO;
    d->last.accel_ref_rad_s2 = MC_ZERO;
    d->last.i_d_A = MC_ZERO;
    d->last.i_q_A = MC_ZERO;
    d->last.i_d_ref_A = MC_ZERO;
    d->last.i_q_ref_A = MC_ZERO;
    d->last.theta_e_rad = MC_ZERO;
    d->last.saturated = false;
    sfoc_zero_last(d);
    fault_monitor_init(&d->mon, &cfg->faults);
    flight_recorder_init(&d->rec);
    const bool ok = sensored_foc_config_problem(cfg) == 0 && foc_current_init(&d->current, &cfg->current, &d->cfg.model) &&
                    pi_ctrl_init(&d->pi_speed, &cfg->pi_speed) &&
                    encoder_observer_init(&d->obs, &cfg->obs, MC_ZERO) && speed_profile_init(&d->profile, &cfg->profile) &&
                    deadtime_comp_init(&d->dtc, &cfg->deadtime);
    if (!ok) {
        guard_latch(&d->sup, &d->rec, DRIVE_FAULT_BAD_INPUT, d->tick);
        return false;
    }
    return true;
}

/* Step 3: the reference of this sample, and the speed the loop is to
 * follow (the position loop's correction added in a move). */
static mc_t sfoc_reference(sensored_foc_drive_t *d)
{
    if (d->mode == SFOC_MODE_SPEED) {
        speed_point_t p;
        speed_profile_eval(&d->profile, d->tick, &p);
        d->last.theta_ref_rad = p.theta_rad;
        d->last.omega_ref_rad_s = p.omega_rad_s;
        d->last.accel_ref_rad_s2 = p.accel_rad_s2;
        return p.omega_rad_s;
    }
    /* the move: theta0 + delta p(D), D = (k - k0) / n in [0, 1], its
     * derivatives scaled by 1/T and 1/T^2 (paper 000 eq. (70)) */
    const uint32_t k = d->tick - d->move.t0_tick;
    const mc_t D = (k >= d->move.n_ticks) ? MC_ONE : mc_mul_i(d->move.inv_ticks, (int32_t)k);
    mc_t p, dp, ddp, dddp;
    trajectory_poly7(D, &p, &dp, &ddp, &dddp);
    const mc_t w_over_d = mc_mul(dp, d->move.inv_T_s);
    d->last.theta_ref_rad = mc_mac(d->move.theta0_rad, d->move.delta_rad, p);
    d->last.omega_ref_rad_s = mc_mul(d->move.delta_rad, w_over_d);
    d->last.accel_ref_rad_s2 = mc_mul(mc_mul(d->move.delta_rad, ddp), mc_mul(d->move.inv_T_s, d->move.inv_T_s));
    const mc_t err = mc_sub(d->last.theta_ref_rad, d->obs.theta_rad);
    return mc_mac(d->last.omega_ref_rad_s, d->cfg.pos_kp_per_s, err);
}

bool sensored_foc_drive_step(sensored_foc_drive_t *d, const hal_sample_t *in, hal_command_t *out)
{
    const sensored_foc_config_t *c = &d->cfg;
    /* 0. the shell: latch, enable, the sample's checks, the fault monitor */
    const guard_action_t a = guard_begin(&sfoc_shell, d, in, out);
    if (a == GUARD_SAFE || a == GUARD_IDLE) {
        return a == GUARD_IDLE; /* 0 V out */
    }
    /* 1. currents in the rotor frame of the encoder's angle */
    if (!d->started) {
        encoder_observer_set_angle(&d->obs, in->angle_rad); /* the first angle: no start transient */
        d->started = true;
    }
    mc_t i_zero_A;
    const mc_ab_t i_ab = phase_adapter_currents(in, &i_zero_A);
    (void)i_zero_A; /* star without neutral */
    const mc_t th_e = mc_elec_angle(in->angle_rad, c->model.n_p);
    mc_t i_d, i_q;
    mc_rot_fwd(mc_rot_from_angle(th_e), i_ab.alpha, i_ab.beta, &i_d, &i_q);
    /* 2. the mechanical observer with the torque of this sample's current */
    encoder_observer_step(&d->obs, in->angle_rad, mc_mul(c->kt_Nm_per_A, i_q));
    /* 3. the reference */
    const mc_t w_cmd = sfoc_reference(d);
    /* 4. speed loop: i_q* with the load and J a_ref fed forward, |i_q*| <= i_max */
    const mc_t ff_q = mc_mul(mc_mac(d->obs.load_Nm, c->model.J_kgm2, d->last.accel_ref_rad_s2), c->inv_kt_A_per_Nm);
    const mc_t i_q_ref = pi_ctrl_step(&d->pi_speed, mc_sub(w_cmd, d->obs.omega_rad_s), ff_q, c->i_max_A);
    const mc_t i_d_ref = MC_ZERO;
    /* 5. current loops with the decoupling terms (control/foc_current.h),
     * limited to the circle of radius v_bus/sqrt(3), d first */
    const mc_t w_e = mc_mul_i(d->obs.omega_rad_s, c->model.n_p);
    const mc_t u_max = mc_mul(in->v_bus_V, SFOC_INV_SQRT3);
    foc_current_step(&d->current, &c->model, i_d_ref, i_q_ref, i_d, i_q, w_e, u_max);
    const mc_t v_d = d->current.v_d_V, v_q = d->current.v_q_V;
    /* 6. to the phases at the angle of the middle of the interval the
     * voltage acts over, (1/2 + d) Ts after the sample */
    const mc_t lead_s = delay_output_lead_s(c->compute_delay, c->model.ts_s);
    const mc_t th_out = mc_elec_angle(mc_mac(in->angle_rad, lead_s, d->obs.omega_rad_s), c->model.n_p);
    mc_ab_t v_ab;
    mc_rot_inv(mc_rot_from_angle(th_out), v_d, v_q, &v_ab.alpha, &v_ab.beta);
    phase_adapter_voltages((uint8_t)SFOC_N_PHASES, v_ab, out);
    if (d->dtc.cfg.enabled) {
        /* the inverter's expected error added to the command (no estimator
         * here uses the voltage: the encoder gives the angle) */
        (void)deadtime_comp_step(&d->dtc, in->i_A, in->v_bus_V, out);
    }
    d->last.i_d_A = i_d;
    d->last.i_q_A = i_q;
    d->last.i_d_ref_A = i_d_ref;
    d->last.i_q_ref_A = i_q_ref;
    d->last.v_d_V = v_d;
    d->last.v_q_V = v_q;
    d->last.v_ab_V = v_ab;
    d->last.theta_e_rad = th_e;
    d->last.saturated = d->current.saturated;
    /* the shell's end: the command's checks, the estimate's (sfoc_check),
     * the flight recorder, the count, the reaction */
    return guard_end(&sfoc_shell, d, in, out, d->last.saturated, d->last.omega_ref_rad_s, d->last.theta_e_rad,
                     d->obs.omega_rad_s) != GUARD_SAFE;
}

bool sensored_foc_set_enabled(sensored_foc_drive_t *d, bool on)
{
    if (d->sup.state == SUP_STATE_FAULT) {
        return false;
    }
    if (on && d->disabled) {
        return sensored_foc_drive_init(d, &d->cfg); /* as at power-up */
    }
    d->disabled = !on;
    return true;
}

bool sensored_foc_set_speed(sensored_foc_drive_t *d, mc_t omega_rad_s, mc_t ramp_rad_s2)
{
    const sensored_foc_config_t *c = &d->cfg;
    if (d->sup.state == SUP_STATE_FAULT || d->disabled || mc_gt(mc_abs(omega_rad_s), c->speed_cmd_max_rad_s) ||
        !mc_gt(ramp_rad_s2, MC_ZERO) || mc_gt(ramp_rad_s2, c->accel_cmd_max_rad_s2)) {
        return false;
    }
    if (d->mode == SFOC_MODE_POSITION && d->tick - d->move.t0_tick < d->move.n_ticks) {
        return false; /* a move in progress */
    }
    if (!speed_profile_retarget(&d->profile, d->tick, omega_rad_s, ramp_rad_s2)) {
        return false;
    }
    d->mode = SFOC_MODE_SPEED;
    d->stop_ramp_rad_s2 = ramp_rad_s2;
    return true;
}

bool sensored_foc_move(sensored_foc_drive_t *d, mc_t theta_to_rad, mc_t duration_s)
{
    const sensored_foc_config_t *c = &d->cfg;
    if (d->sup.state == SUP_STATE_FAULT || d->disabled || !mc_gt(duration_s, MC_ZERO)) {
        return false;
    }
    if (d->mode == SFOC_MODE_SPEED && mc_ne(d->last.omega_ref_rad_s, MC_ZERO)) {
        return false; /* the speed reference is not at rest */
    }
    if (d->mode == SFOC_MODE_POSITION && d->tick - d->move.t0_tick < d->move.n_ticks) {
        return false; /* a move in progress */
    }
    const mc_t start = (d->mode == SFOC_MODE_POSITION) ? d->last.theta_ref_rad : d->obs.theta_rad;
    const mc_t delta = mc_sub(theta_to_rad, start);
    const mc_t inv_T = mc_div(MC_ONE, duration_s);
    const mc_t peak_w = mc_mul(mc_mul(SFOC_MOVE_PEAK_SPEED, mc_abs(delta)), inv_T);
    const mc_t peak_a = mc_mul(mc_mul(SFOC_MOVE_PEAK_ACCEL, mc_abs(delta)), mc_mul(inv_T, inv_T));
    if (mc_gt(peak_w, c->speed_cmd_max_rad_s) || mc_gt(peak_a, c->accel_cmd_max_rad_s2)) {
        return false;
    }
    const int32_t n = mc_round_i(mc_mul_i(duration_s, c->model.fs_hz));
    if (n < 1) {
        return false;
    }
    d->move.theta0_rad = start;
    d->move.delta_rad = delta;
    d->move.inv_T_s = inv_T;
    d->move.inv_ticks = mc_div_i(MC_ONE, n);
    d->move.t0_tick = d->tick;
    d->move.n_ticks = (uint32_t)n;
    d->mode = SFOC_MODE_POSITION;
    return true;
}

bool sensored_foc_stop(sensored_foc_drive_t *d)
{
    if (d->sup.state == SUP_STATE_FAULT) {
        return false;
    }
    if (d->mode == SFOC_MODE_POSITION) {
        return true; /* rest-to-rest: the move ends at its end point */
    }
    return speed_profile_retarget(&d->profile, d->tick, MC_ZERO, d->stop_ramp_rad_s2);
}
