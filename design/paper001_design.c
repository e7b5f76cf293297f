/*
 * paper001_design.c - the paper-001 drive's design (see paper001_design.h).
 *
 * Conventions. The alpha-beta model of paper 001's (1)-(3) is the one of a
 * two-phase machine: L di/dt = -R i - n_p w Phi Jm rho + v, torque
 * n_p Phi i^T Jm rho. A three-phase star machine written in amplitude-
 * invariant Clarke (the phase adapter's) has the same voltage equation with
 * Phi the peak phase flux linkage, and torque (3/2) n_p Phi i^T Jm rho. So
 *   K_e = n_p Phi       (back-EMF, both)
 *   K_t = (m/2) n_p Phi (torque, m = 2 or 3 phases).
 */
#include "design/paper001_design.h"
#include "design/lock_monitor_design.h"
#include "design/profile_design.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "math/mc_convert.h"

/* Paper 001 section 5.1's tuning: gamma = 5000 for the flux observer,
 * a1 = 20, a2 = 6 for the I&I observer. */
#define P001_PAPER_GAMMA 5000.0
/* gamma enters (12) as gamma Phi^2 (the radial rate 2 gamma Phi^2 of
 * |rho| towards 1, with rho = lambda/Phi): on another motor the default keeps
 * the paper's rate, 289 1/s, by gamma = 5000 (Phi_paper / Phi)^2 (the
 * paper's gamma on a stepper with Phi = 5.4 mWb would be 34 times slower,
 * and gamma Phi^3 would fall below the fixed-point coefficient range). */
#define P001_PAPER_PHI_WB 0.17
#define P001_PAPER_A1 20.0
#define P001_PAPER_A2 6.0
/* IDA-PBC damping: r puts the closed loop of (40) linearised about the
 * equilibrium, L J s^2 + r J s + K_e K_t = 0, at damping ratio 1 (no
 * overshoot of the speed after a load step; a larger r slows the speed
 * loop's slow pole K_e K_t / (r J), a smaller one rings). */
#define P001_LOOP_ZETA 1.0
/* Open-loop start current: the rotor follows the turning voltage vector
 * damped by the stator resistance (braking torque K_e K_t w_slip / R), so
 * its slip speed is at most R I / K_e; the default current is the one whose
 * slip bound is P001_START_SLIP_RAD_S, and it is capped at i_max. 2 rad/s
 * (19 rpm) keeps the start inside paper 001's benchmark transients. */
#define P001_START_SLIP_RAD_S 2.0
/* The switch to closed loop: after one electrical turn of the reference,
 * when the circle fit of the flux (startup/flux_circle_fit.h) has an arc
 * long enough. det Cov(q) is 1/4 for a full turn of evenly spread points;
 * 0.02, the least the fit is allowed to use, is an arc of about 150 degrees
 * (120 degrees gives 0.007). */
#define P001_HANDOVER_SWEEP_RAD (2.0 * 3.14159265358979323846)
#define P001_FIT_DET_MIN 0.02
/* One point of the fit every 8 samples (0.8 ms): an arc of the open-loop
 * start gives hundreds of points, and the running means cost 1/8 of the
 * work per sample. */
#define P001_FIT_DECIM 8
/* Decay of the voltage offset that removes the step at the switch: 5 ms,
 * a few electrical time constants L/R of the paper's motor (17 ms) is too
 * slow for the load step at 1 s; 5 ms is 50 samples. */
#define P001_BLEND_TAU_S 5e-3
/* The start-up probe (paper001_drive.h): a standstill vector whose current
 * would let the rotor creep at most P001_PROBE_SLIP_RAD_S (R I / K_e, the
 * resistance's damping as for the open loop), first along alpha, then along
 * the arc the rotor started. 1 rad/s (10 rpm) turns paper 001's rotor
 * through the 0.3 rad electrical the fit needs in about 0.1 s (0.1 rad
 * mechanical at 1 rad/s, n_p = 3); P001_PROBE_S bounds the probe at three
 * times that, after which the open loop starts at the reference angle. */
#define P001_PROBE_SLIP_RAD_S 1.0
#define P001_PROBE_S 0.3
/* The probe's fit takes a point each 0.01 rad of arc (points scaled by 8,
 * paper001_drive.c: step 0.08, squared 6.4e-3) and is trusted above
 * det M = 3e-3: an arc of 0.3 rad electrical (det M of evenly spread
 * points is 3.2e-3 there, 6th power of the arc). */
#define P001_PROBE_STEP2 6.4e-3
/* The probe's vector stays along alpha at most 50 ms: a rotor that alpha
 * has not moved 0.1 rad by then is within about 0.1 rad of 0 or pi, where
 * beta pulls it hardest. */
#define P001_PROBE_TURN_S 0.05
/* The probe's vector turns from alpha to the arc once the flux has moved
 * 0.1 rad (scaled by 8: 0.8, squared 0.64): a chord long enough to give its
 * direction to a few degrees; below a quarter of it (0.025 rad) the rotor
 * counts as not moved. */
#define P001_PROBE_TURN2 0.64
#define P001_PROBE_DET_MIN 3e-3
/* Paper 000's estimator on this drive (estimator = BACK_EMF): the loop
 * closes from the speed whose back-EMF K_e omega_lim is paper 000's own,
 * 0.27 V s/rad x 3 rad/s = 0.81 V (section 5.3): 1.6 rad/s on paper 001's
 * motor, 3 rad/s on paper 000's stepper. Its gains follow paper 000's
 * bounds (design/paper000_design.c) with that design's defaults for what a
 * speed profile does not give: 1 rad/s of closed-loop speed error and
 * 2 N m/s of load rate. */
#define P001_EMF_AT_OMEGA_LIM_V 0.81
#define P001_EMF_DELTA_OMEGA_RAD_S 1.0
#define P001_EMF_LOAD_RATE_NM_S 2.0
/* The start within i_max (docs/paper001.md, "Start-up within i_max"):
 * the open loop begins when the probe's fit is trusted, at the probe's
 * nominal end: up to P001_PROBE_TURN_S along alpha, then the 0.3 rad
 * electrical arc the fit needs (P001_PROBE_DET_MIN) at the probe's slip
 * speed P001_PROBE_SLIP_RAD_S (0.15 s on paper 001's motor, measured
 * 0.16 s with the benchmark's and a 300 rpm/s ramp). The vector then
 * turns with the reference at (68)'s voltage, R I_ol + K_e w*, while the
 * rotor is still nearly at rest: the current is I_ol + K_e |w*| / R in the
 * worst phase. It stays within i_max while |w*| at that time is at most
 * R (i_max - I_ol) / K_e; a profile whose reference is faster there is
 * refused at configuration, naming the ramp and the numbers. */
#define P001_PROBE_ARC_RAD 0.3
/* The open-loop vector's magnitude is not capped below the bus. */
#define P001_OPEN_LOOP_VCAP_V 1000.0
/* A bus below 1 V is no bus: the drive refuses the sample. */
#define P001_V_BUS_MIN_V 1.0
/* Fixed point keeps coefficients in [1e-3, 1e4] (mc_num.h). */
#define P001_COEFF_MIN 1e-3
#define P001_COEFF_MAX 1e4


/* Loss of the estimate (paper001_drive.h, docs/faults.md). |rho_hat| is 1
 * when the observer's flux agrees with Phi (13); a rotor flux off by half
 * (|rho| outside [0.5, 1.5], 0.87-1.15 with the 15 % Phi error of
 * paper001_Phi115) for 5 ms means the observer has lost the rotor. The
 * estimated speed may differ from the reference by half of it plus
 * 10 rad/s (95 rpm: the benchmark's load steps dip the speed by less) for
 * 0.2 s, about twice the speed loop's settling time: longer, the rotor has
 * stalled or the estimate is lost (ODrive users ask for exactly this). */
#define P001_LOS_RHO_LO 0.5
#define P001_LOS_RHO_HI 1.5
#define P001_LOS_PERSIST_S 5e-3
#define P001_LOS_SPEED_TOL 0.5
#define P001_LOS_SPEED_FLOOR_RAD_S 10.0
#define P001_LOS_SPEED_S 0.2
/* Loss of lock (supervisor/lock_monitor.h, design/lock_monitor_design.c):
 * the flux observer's residual along the estimated rotor axis must stay
 * beyond its tolerance bound for 5/w_n, w_n = sqrt(K_e K_t / (L J)) the
 * natural frequency of the closed loop (r, P001_LOOP_ZETA = 1): a
 * critically damped transient (1 + w_n t) e^(-w_n t) of the loop (a load
 * step, the switch to closed loop) has fallen to 4 % by then, while the
 * drift it detects grows over the mechanical time (0.1-1 s). 54 ms on
 * paper 001's motor. */
#define P001_LOCK_SETTLE_PER_WN 5.0
/* Resistance and flux tracking (estimators/resistance_tracker.h), with
 * track_resistance:
 * - tau_R = 15 time constants of the I&I observer (its poles' real part
 *   -n_p a1/2: 33 ms on paper 001's motor, tau_R 0.5 s): slow against the
 *   speed loop and the observer's transients after a load step, fast
 *   against the winding's heating (900 s) and the benchmark's holds
 *   (1.5-5 s).
 * - i_gate = 10 % of i_max (0.8 A on paper 001's motor): below a voltage
 *   of R i_gate (0.18 V) in m^2 the steps shrink; there the dead time's
 *   error is in its transition near zero current, not a resistance, and
 *   the residual is sensor noise.
 * - e_clamp = half the largest resistive drop, R i_max / 2 (0.9 V): a
 *   voltage error beyond it in one sample is a transient, not R or Phi.
 * - dR_max = R: R_hat within [0, 2 R] (copper from the model's
 *   temperature to 255 K above it, and the equivalent resistance of a
 *   dead-time compensation off by half on paper 001's motor under
 *   1 N m, 0.3 V / 1.3 A = 0.23 Ohm = 1.0 R).
 * - dPhi_rel_max = 0.2: NdFeB loses about 0.1 %/K, 20 % over 200 K. */
#define P001_RTRACK_TAU_PER_OBSERVER 15.0
#define P001_RTRACK_I_GATE_SHARE 0.1
#define P001_RTRACK_E_CLAMP_SHARE 0.5
#define P001_RTRACK_DR_MAX_SHARE 1.0
#define P001_RTRACK_DPHI_REL_MAX 0.2
/* The fixed-point accumulators of the tracker hold up to (R + dR_max)
 * tau_R/Ts (Q14.17 ends at 16384). */
#define P001_RTRACK_ACC_MAX 16000.0

static bool p001_fail(char *err, size_t n, const char *field, const char *why, double got)
{
    if (err != NULL && n > 0) {
        snprintf(err, n, "%s: %s (got %g)", field, why, got);
    }
    return false;
}

void p001_design_defaults(p001_design_input_t *in)
{
    in->gamma = 0.0;
    in->a1 = 0.0;
    in->a2 = 0.0;
    in->r_ohm = 0.0;
    in->blend_tau_s = 0.0;
    in->handover_sweep_rad = 0.0;
    in->fit_det_min = 0.0;
    in->i_open_loop_A = 0.0;
    in->probe_s = P001_PROBE_S;
    in->estimator = OPEN_START_FLUX;
    in->omega_lim_rad_s = 0.0;
    in->compute_delay_samples = 0.0; /* a DAC card; an MCU's PWM is 1 */
    in->i_rail_A = 0.0;              /* unknown: no rail check */
    in->i_trip_samples = 1;          /* the instantaneous trip */
    in->track_resistance = false;
}

/* A per-sample coefficient the fixed-point build can hold. */
static bool p001_coeff(double x, const char *field, mc_t *dst, char *err, size_t n)
{
    const double a = fabs(x);
    if (!(a == 0.0 || (a >= P001_COEFF_MIN && a <= P001_COEFF_MAX))) {
        return p001_fail(err, n, field, "folded coefficient outside [1e-3, 1e4]", x);
    }
    *dst = mc_from_double(x);
    return true;
}

bool p001_design(const p001_design_input_t *in, paper001_config_t *cfg, p001_design_report_t *rep, char *err,
                 size_t err_len)
{
    const motor_design_input_t *m = &in->motor;
    if (m->n_phases != 2 && m->n_phases != 3) {
        return p001_fail(err, err_len, "motor.n_phases", "must be 2 or 3", m->n_phases);
    }
    if (!(m->R_ohm >= 0.0)) return p001_fail(err, err_len, "motor.R_ohm", "must be >= 0", m->R_ohm);
    if (!(m->L_H > 0.0)) return p001_fail(err, err_len, "motor.L_H", "must be > 0", m->L_H);
    if (m->n_p < 1) return p001_fail(err, err_len, "motor.n_p", "must be >= 1", m->n_p);
    const double Phi = motor_design_phi_Wb(m); /* paper 001's Phi: K = n_p Phi */
    if (!(Phi > 0.0)) return p001_fail(err, err_len, "motor.Phi_Wb", "must be > 0", Phi);
    if (!(m->J_kgm2 > 0.0)) return p001_fail(err, err_len, "motor.J_kgm2", "must be > 0", m->J_kgm2);
    if (!(in->ts_s > 0.0)) return p001_fail(err, err_len, "ts_s", "must be > 0", in->ts_s);
    if (!(in->i_max_A > 0.0)) return p001_fail(err, err_len, "i_max_A", "must be > 0", in->i_max_A);
    if (!(in->i_trip_A >= in->i_max_A)) return p001_fail(err, err_len, "i_trip_A", "must be >= i_max_A", in->i_trip_A);
    if (!fault_trip_samples_ok(in->i_trip_samples))
        return p001_fail(err, err_len, "limits.i_trip_samples", "must be 1..8 (0: 1)", (double)in->i_trip_samples);
    if (in->n_points < 1 || in->n_points > SPEED_PROFILE_MAX_POINTS) {
        return p001_fail(err, err_len, "profile", "needs 1..16 points", (double)in->n_points);
    }
    memset(cfg, 0, sizeof *cfg);
    const double ts = in->ts_s;
    const double fs = 1.0 / ts;
    const double np = (double)m->n_p;
    const double Ke = np * Phi;
    const double Kt = 0.5 * (double)m->n_phases * np * Phi;
    const double phi_ratio = P001_PAPER_PHI_WB / Phi;
    const double gamma = (in->gamma > 0.0) ? in->gamma : P001_PAPER_GAMMA * phi_ratio * phi_ratio;
    const double a1 = (in->a1 > 0.0) ? in->a1 : P001_PAPER_A1;
    const double a2 = (in->a2 > 0.0) ? in->a2 : P001_PAPER_A2;
    const double r = (in->r_ohm > 0.0) ? in->r_ohm
                                       : 2.0 * P001_LOOP_ZETA * sqrt(m->L_H * Ke * Kt / m->J_kgm2);
    const double radial = 2.0 * gamma * Phi * Phi * ts;
    if (!(radial < 1.0)) {
        return p001_fail(err, err_len, "gamma", "2 gamma Phi^2 Ts must be < 1 for the explicit step of (12)", gamma);
    }
    double i_ol = (in->i_open_loop_A > 0.0) ? in->i_open_loop_A
                                            : ((m->R_ohm > 0.0) ? P001_START_SLIP_RAD_S * Ke / m->R_ohm : in->i_max_A);
    if (i_ol > in->i_max_A) {
        i_ol = in->i_max_A;
    }
    const double fsr = round(fs);
    if (fabs(fs - fsr) > 1e-6 * fs || fsr > 2e9) {
        return p001_fail(err, err_len, "ts_s", "1/Ts must be a whole number of hertz", ts);
    }

    cfg->n_phases = (uint8_t)m->n_phases;
    /* model (the open-loop start reads R, n_p L, K_e from it) */
    motor_model_t *mm = &cfg->model;
    mm->n_p = m->n_p;
    mm->fs_hz = (int32_t)fsr;
    mm->ts_s = mc_from_double(ts);
    mm->R_ohm = mc_from_double(m->R_ohm);
    mm->L_H = mc_from_double(m->L_H);
    mm->Ld_H = mm->L_H; /* paper 001's motor is non-salient */
    mm->Lq_H = mm->L_H;
    mm->psi_Wb = mc_from_double(Phi);
    mm->J_kgm2 = mc_from_double(m->J_kgm2);
    mm->ts_over_L_A_per_V = mc_from_double(ts / m->L_H);
    mm->npL_ohm_s = mc_from_double(np * m->L_H);
    mm->K_V_s = mc_from_double(Ke);
    mm->inv_J = mc_from_double(1.0 / m->J_kgm2);
    mm->ts_over_J = mc_from_double(ts / m->J_kgm2);
    cfg->limits.i_max_A = mc_from_double(in->i_max_A);
    cfg->limits.i_trip_A = mc_from_double(in->i_trip_A);
    /* faults (docs/faults.md): the generic set, and the loss of the
     * estimate (paper001_drive.h) */
    fault_monitor_design(&cfg->faults, (int)m->n_phases, in->i_max_A, in->i_trip_A, in->i_trip_samples, in->i_rail_A,
                         ts);
    for (int f = 0; f < DRIVE_FAULT_COUNT; ++f) {
        cfg->reaction[f] = (uint8_t)FAULT_REACT_SAFE;
    }
    cfg->los_rho2_lo = mc_from_double(P001_LOS_RHO_LO * P001_LOS_RHO_LO);
    cfg->los_rho2_hi = mc_from_double(P001_LOS_RHO_HI * P001_LOS_RHO_HI);
    cfg->los_ticks = (int32_t)ceil(P001_LOS_PERSIST_S * fsr - 1e-9);
    cfg->los_speed_tol = mc_from_double(P001_LOS_SPEED_TOL);
    cfg->los_speed_floor_rad_s = mc_from_double(P001_LOS_SPEED_FLOOR_RAD_S);
    cfg->los_speed_ticks = (int32_t)ceil(P001_LOS_SPEED_S * fsr - 1e-9);

    {
        lock_monitor_design_input_t li;
        lock_monitor_design_defaults(&li);
        li.R_ohm = m->R_ohm;
        li.L_H = m->L_H;
        li.Phi_Wb = Phi;
        li.n_p = m->n_p;
        li.gPhi3_V = gamma * Phi * Phi * Phi;
        li.i_max_A = in->i_max_A;
        li.settle_s = P001_LOCK_SETTLE_PER_WN / sqrt(Ke * Kt / (m->L_H * m->J_kgm2));
        li.ts_s = ts;
        if (!lock_monitor_design(&li, &cfg->lock, err, err_len)) {
            return false;
        }
        if (rep != NULL) {
            rep->lock_settle_s = (double)cfg->lock.ticks * ts;
        }
    }
    /* flux observer (12)-(14) in w = lambda/Ts units (flux_observer.h) */
    const double phi_fs = Phi / ts;
    const int s = (int)floor(log2(phi_fs)) + 1;
    flux_observer_config_t *fo = &cfg->est.flux;
    bool ok = p001_coeff(m->R_ohm, "flux.R_ohm", &fo->R_ohm, err, err_len) &&
              p001_coeff(m->L_H / ts, "flux.L_fs_ohm", &fo->L_fs_ohm, err, err_len) &&
              p001_coeff(phi_fs, "flux.Phi_fs_V", &fo->Phi_fs_V, err, err_len) &&
              p001_coeff(ldexp(ts / Phi, s), "flux.rho_gain", &fo->rho_gain, err, err_len) &&
              p001_coeff(gamma * Phi * Phi * Phi, "flux.gPhi3_V", &fo->gPhi3_V, err, err_len);
    /* 2^-s is exact in both builds (a power of two of at least 2^-17) */
    if (s > 17) {
        return p001_fail(err, err_len, "motor.Phi_Wb", "Phi/Ts above 2^17 V", phi_fs);
    }
    fo->rho_pre = mc_from_double(ldexp(1.0, -s));
    /* resistance tracking (estimators/resistance_tracker.h; constants above) */
    {
        resistance_tracker_config_t *rt = &cfg->est.rtrack;
        const double tau_R = P001_RTRACK_TAU_PER_OBSERVER * 2.0 / (np * a1);
        const double i_gate = P001_RTRACK_I_GATE_SHARE * in->i_max_A;
        const double e_clamp = P001_RTRACK_E_CLAMP_SHARE * m->R_ohm * in->i_max_A;
        const double dR_max = P001_RTRACK_DR_MAX_SHARE * m->R_ohm;
        const double n_tau = round(tau_R * fsr);
        rt->enabled = in->track_resistance && in->estimator == OPEN_START_FLUX;
        if (rt->enabled) {
            if (!(m->R_ohm > 0.0)) {
                return p001_fail(err, err_len, "motor.R_ohm", "must be > 0 to track R", m->R_ohm);
            }
            if (!((m->R_ohm + dR_max) * n_tau <= P001_RTRACK_ACC_MAX)) {
                return p001_fail(err, err_len, "track_resistance",
                                 "2 R tau_R/Ts must stay below 16000 (the fixed-point accumulator)",
                                 (m->R_ohm + dR_max) * n_tau);
            }
        }
        rt->R0_ohm = mc_from_double(m->R_ohm);
        rt->L_fs_ohm = mc_from_double(m->L_H / ts);
        rt->Phi0_fs_V = mc_from_double(Phi / ts);
        rt->K_e_V_s = mc_from_double(Ke);
        rt->v_gate2_V2 = mc_from_double(m->R_ohm * i_gate * m->R_ohm * i_gate);
        rt->e_clamp_V = mc_from_double(e_clamp);
        rt->dR_max_ohm = mc_from_double(dR_max);
        rt->dPhi_rel_max = mc_from_double(P001_RTRACK_DPHI_REL_MAX);
        rt->n_tau = (int32_t)n_tau;
        if (rep != NULL) {
            rep->rtrack_tau_s = n_tau * ts;
            rep->rtrack_i_gate_A = i_gate;
            rep->rtrack_e_clamp_V = e_clamp;
            rep->rtrack_dR_max_ohm = dR_max;
        }
    }
    /* I&I observer (15)-(16), increment form (speed_load_observer.h) */
    speed_load_observer_config_t *so = &cfg->est.speed;
    ok = ok && p001_coeff(ts * Kt / m->J_kgm2, "speed.ts_kt_over_J", &so->ts_kt_over_J, err, err_len) &&
         p001_coeff(ts / m->J_kgm2, "speed.ts_over_J", &so->ts_over_J, err, err_len) &&
         p001_coeff(fs / np, "speed.fs_over_np", &so->fs_over_np, err, err_len) &&
         p001_coeff(a1 * np * ts, "speed.k_omega", &so->k_omega, err, err_len) &&
         p001_coeff(a2 * np * ts, "speed.k_load_Nm_s", &so->k_load_Nm_s, err, err_len);
    /* IDA-PBC (11) */
    ida_pbc_config_t *co = &cfg->ctrl;
    ok = ok && p001_coeff(m->R_ohm - r, "ctrl.R_minus_r_ohm", &co->R_minus_r_ohm, err, err_len) &&
         p001_coeff(r, "ctrl.r_ohm", &co->r_ohm, err, err_len) &&
         p001_coeff(np * m->L_H, "ctrl.npL_ohm_s", &co->npL_ohm_s, err, err_len) &&
         p001_coeff(Ke, "ctrl.Ke_V_s", &co->Ke_V_s, err, err_len) &&
         p001_coeff(1.0 / Kt, "ctrl.inv_Kt_A_Nm", &co->inv_Kt_A_Nm, err, err_len) &&
         p001_coeff(m->J_kgm2 / Kt, "ctrl.J_over_Kt_A_s2", &co->J_over_Kt_A_s2, err, err_len);
    if (!ok) {
        return false;
    }
    co->i_max_A = mc_from_double(in->i_max_A);
    cfg->open_loop.i_max_A = mc_from_double(i_ol);
    cfg->open_loop.v_max_V = mc_from_double(P001_OPEN_LOOP_VCAP_V);
    const double blend = (in->blend_tau_s > 0.0) ? in->blend_tau_s : P001_BLEND_TAU_S;
    cfg->sup.blend_decay = mc_from_double(exp(-ts / blend));
    cfg->est.handover_sweep_rad =
        mc_from_double((in->handover_sweep_rad > 0.0) ? in->handover_sweep_rad : P001_HANDOVER_SWEEP_RAD);
    cfg->est.fit.decim = P001_FIT_DECIM;
    cfg->est.fit.det_min = mc_from_double((in->fit_det_min > 0.0) ? in->fit_det_min : P001_FIT_DET_MIN);
    cfg->v_bus_min_V = mc_from_double(P001_V_BUS_MIN_V);
    if (!(in->probe_s >= 0.0 && in->probe_s <= 10.0)) {
        return p001_fail(err, err_len, "probe_s", "must be in [0, 10] s", in->probe_s);
    }
    cfg->est.probe_ticks = (uint32_t)llround(in->probe_s * fs);
    cfg->est.probe_turn_ticks = (uint32_t)llround(fmin(P001_PROBE_TURN_S, 0.5 * in->probe_s) * fs);
    cfg->est.probe_fit.decim = 1;
    cfg->est.probe_fit.det_min = mc_from_double(P001_PROBE_DET_MIN);
    cfg->est.probe_step2 = mc_from_double(P001_PROBE_STEP2);
    cfg->est.probe_turn2 = mc_from_double(P001_PROBE_TURN2);
    {
        double i_probe = (m->R_ohm > 0.0) ? P001_PROBE_SLIP_RAD_S * Ke / m->R_ohm : i_ol;
        if (i_probe > i_ol) {
            i_probe = i_ol;
        }
        cfg->est.probe_v_V = mc_from_double(m->R_ohm * i_probe);
        if (rep != NULL) {
            rep->i_probe_A = i_probe;
        }
    }

    /* estimator */
    double a_max = 0.0, w_max = 0.0;
    for (size_t k = 0; k < in->n_points; ++k) {
        w_max = fmax(w_max, fabs(in->omega_rad_s[k]));
        if (k + 1 < in->n_points && in->t_s[k + 1] > in->t_s[k]) {
            a_max = fmax(a_max, fabs(in->omega_rad_s[k + 1] - in->omega_rad_s[k]) / (in->t_s[k + 1] - in->t_s[k]));
        }
    }
    if (in->estimator != OPEN_START_FLUX && in->estimator != OPEN_START_BACK_EMF) {
        return p001_fail(err, err_len, "estimator", "must be FLUX (0) or BACK_EMF (1)", in->estimator);
    }
    cfg->estimator = (uint8_t)in->estimator;
    if (!(in->compute_delay_samples >= 0.0 && in->compute_delay_samples <= 1.0)) {
        return p001_fail(err, err_len, "compute_delay_samples", "must be in [0, 1]", in->compute_delay_samples);
    }
    cfg->compute_delay = mc_from_double(in->compute_delay_samples);
    cfg->est.advance_np = mc_from_double(np * (0.5 + in->compute_delay_samples));
    cfg->est.model = cfg->model; /* the estimator's motor is the drive's */
    {
        const double w_lim = (in->omega_lim_rad_s > 0.0) ? in->omega_lim_rad_s : P001_EMF_AT_OMEGA_LIM_V / Ke;
        fg_estimator_design_t ed;
        memset(&ed, 0, sizeof ed);
        ed.K_emf_V_s = Ke;
        ed.K_torque_Nm_A = Kt;
        ed.L_H = m->L_H;
        ed.J_kgm2 = m->J_kgm2;
        ed.n_p = m->n_p;
        ed.ts_s = ts;
        ed.accel_max_rad_s2 = a_max;
        ed.speed_max_rad_s = fmax(w_max, w_lim);
        ed.delta_omega_max_rad_s = P001_EMF_DELTA_OMEGA_RAD_S;
        ed.load_rate_max_Nm_s = P001_EMF_LOAD_RATE_NM_S;
        ed.omega_lim_rad_s = w_lim;
        ed.i_max_A = in->i_max_A;
        fg_estimator_design(&ed, &cfg->est.emf, NULL);
        cfg->est.emf_torque_model = cfg->model;
        cfg->est.emf_torque_model.K_V_s = mc_from_double(Kt);
        cfg->est.omega_lim_rad_s = mc_from_double(w_lim);
    }

    /* speed profile: ticks, slopes, lengths, angles at the corners */
    double bad_t = 0.0;
    if (!speed_profile_design(&cfg->profile, in->n_points, in->t_s, in->omega_rad_s, mm->fs_hz, ts, &bad_t)) {
        return p001_fail(err, err_len, "profile", "corner times must start at 0 and increase", bad_t);
    }
    {
        /* the reference when the open loop begins (P001_PROBE_ARC_RAD) */
        const double t_ol = (in->probe_s > 0.0)
                                ? fmin(in->probe_s, fmin(P001_PROBE_TURN_S, 0.5 * in->probe_s) +
                                                        P001_PROBE_ARC_RAD / (np * P001_PROBE_SLIP_RAD_S))
                                : 0.0;
        double w_ol = in->omega_rad_s[in->n_points - 1];
        size_t seg = in->n_points - 1;
        for (size_t k = 0; k + 1 < in->n_points; ++k) {
            if (t_ol < in->t_s[k + 1]) {
                const double f = (t_ol - in->t_s[k]) / (in->t_s[k + 1] - in->t_s[k]);
                w_ol = in->omega_rad_s[k] + f * (in->omega_rad_s[k + 1] - in->omega_rad_s[k]);
                seg = k;
                break;
            }
        }
        const double w_step = (m->R_ohm > 0.0) ? m->R_ohm * (in->i_max_A - i_ol) / Ke : 0.0;
        if (in->i_max_A > i_ol && fabs(w_ol) > w_step) {
            const double rpm = 30.0 / 3.14159265358979323846;
            const double t0 = in->t_s[seg];
            const double t1 = (seg + 1 < in->n_points) ? in->t_s[seg + 1] : t0;
            if (err != NULL && err_len > 0) {
                snprintf(err, err_len,
                         "speed.profile_rpm: the ramp %g -> %g rpm over [%g, %g] s reaches %.3g rpm at %.3g s, where "
                         "the open-loop start begins with the rotor at rest: I_ol + K_e w*/R = %.3g + %.3g A > "
                         "[limits] i_max_A = %g A; at most %.3g rpm there (%.3g rpm/s from rest)",
                         in->omega_rad_s[seg] * rpm, (seg + 1 < in->n_points ? in->omega_rad_s[seg + 1] : w_ol) * rpm,
                         t0, t1, w_ol * rpm, t_ol, i_ol, Ke * fabs(w_ol) / m->R_ohm, in->i_max_A, w_step * rpm,
                         (t_ol > 0.0 ? w_step / t_ol : 0.0) * rpm);
            }
            return false;
        }
    }
    if (rep != NULL) {
        rep->gamma = gamma;
        rep->a1 = a1;
        rep->a2 = a2;
        rep->r_ohm = r;
        rep->Ke = Ke;
        rep->Kt = Kt;
        rep->radial_rate_per_sample = radial;
        rep->observer_poles_re = -0.5 * np * a1;
        rep->loop_wn_rad_s = sqrt(Ke * Kt / (m->L_H * m->J_kgm2));
        rep->loop_zeta = r * m->J_kgm2 / (2.0 * sqrt(m->L_H * m->J_kgm2 * Ke * Kt));
        rep->i_open_loop_A = i_ol;
        rep->probe_s = (double)cfg->est.probe_ticks * ts;
    }
    return true;
}

/* ---- commissioning (startup/pmsm_identification.h) --------------------
 * The vector of the alignment and of the R/L step: the open-loop current
 * of the start through the model's R. A voltage-fed rotor turns towards
 * it with the time constant J-free K_e / V (the resistance's damping
 * 1.5 K_e^2 / R against the stiffness 1.5 K_e V / R): 0.5 s on paper
 * 001's motor, whatever the motor's real R. */
#define P001_ID_ALIGN_BETA_S 1.5  /* 3 time constants: a start for the second step, not an end */
#define P001_ID_ALIGN_ALPHA_S 2.5 /* 5 time constants from a quarter turn: 0.013 rad left */
/* 0 V for 6 electrical time constants L/R (17 ms on paper 001's motor):
 * the current is gone before the step. */
#define P001_ID_REST_TAU 6.0
/* The step: 9 L/R in all, R from the last 3 (the first 6 leave 0.25 %
 * of the step undecayed). */
#define P001_ID_RL_TAU 9.0
#define P001_ID_RL_STEADY_TAU 3.0
/* The spin: 100 rpm, where the back-EMF (6 V on paper 001's motor) is
 * six times R I, so a 1 % error of the measured R moves Phi by 0.2 %;
 * reached in 1 s (10 rad/s^2: 0.12 N m of the 3.4 N m the start current
 * gives), held 1 s, measured over the last 0.5 s. */
#define P001_ID_SPIN_RPM 50.0
#define P001_ID_SPIN_RAMP_S 1.0
#define P001_ID_SPIN_HOLD_S 1.0
#define P001_ID_SPIN_MEAS_S 0.5
/* The standstill step is refused if the reference moves (none here). */
#define P001_ID_OMEGA_STILL_RAD_S 1e-3

bool p001_identification_design(const p001_design_input_t *in, pmsm_id_config_t *cfg, double *duration_s,
                                char *err, size_t err_len)
{
    paper001_config_t drive;
    p001_design_report_t rep;
    if (!p001_design(in, &drive, &rep, err, err_len)) {
        return false;
    }
    const motor_design_input_t *m = &in->motor;
    const double Phi = motor_design_phi_Wb(m);
    if (!(m->R_ohm > 0.0)) {
        return p001_fail(err, err_len, "motor.R_ohm", "identification needs a model R > 0", m->R_ohm);
    }
    const double ts = in->ts_s;
    const double tau_e = m->L_H / m->R_ohm;
    memset(cfg, 0, sizeof *cfg);
    cfg->model = drive.model;
    cfg->Phi_model_Wb = mc_from_double(Phi);
    cfg->i_trip_A = mc_from_double(in->i_trip_A);
    const double v = m->R_ohm * rep.i_open_loop_A;
    cfg->v_align_V = mc_from_double(v);
    cfg->v_rl_V = mc_from_double(v);
    cfg->align_beta_ticks = (int32_t)llround(P001_ID_ALIGN_BETA_S / ts);
    cfg->align_alpha_ticks = (int32_t)llround(P001_ID_ALIGN_ALPHA_S / ts);
    cfg->rest_ticks = (int32_t)llround(P001_ID_REST_TAU * tau_e / ts);
    cfg->rl.window_ticks = (int32_t)llround(P001_ID_RL_TAU * tau_e / ts);
    cfg->rl.steady_ticks = (int32_t)llround(P001_ID_RL_STEADY_TAU * tau_e / ts);
    cfg->rl.R_model_ohm = drive.model.R_ohm;
    cfg->rl.L_fs_model_ohm = mc_from_double(m->L_H / ts);
    cfg->rl.omega_still_rad_s = mc_from_double(P001_ID_OMEGA_STILL_RAD_S);
    cfg->i_spin_A = mc_from_double(rep.i_open_loop_A);
    const double we = P001_ID_SPIN_RPM * 2.0 * 3.14159265358979323846 / 60.0 * (double)m->n_p;
    cfg->omega_spin_e_rad_s = mc_from_double(we);
    cfg->theta_step_rad = mc_from_double(we * ts);
    cfg->omega_step_e_rad_s = mc_from_double(we * ts / P001_ID_SPIN_RAMP_S);
    cfg->hold_ticks = (int32_t)llround(P001_ID_SPIN_HOLD_S / ts);
    cfg->meas_ticks = (int32_t)llround(P001_ID_SPIN_MEAS_S / ts);
    if (cfg->rl.steady_ticks < 1 || cfg->rl.window_ticks <= cfg->rl.steady_ticks) {
        return p001_fail(err, err_len, "ts_s", "too long for the standstill step of L/R", ts);
    }
    if (duration_s != NULL) {
        *duration_s = ts * (double)(cfg->align_beta_ticks + cfg->align_alpha_ticks + cfg->rest_ticks +
                                    cfg->rl.window_ticks + cfg->hold_ticks) +
                      2.0 * P001_ID_SPIN_RAMP_S;
    }
    return true;
}
