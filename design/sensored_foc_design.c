#include "design/sensored_foc_design.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "design/paper000_design.h"
#include "design/profile_design.h"
#include "math/mc_convert.h"

/* The default bandwidths (header): current, speed, observer, position [Hz]. */
#define SFOC_CURRENT_BW_HZ 500.0
#define SFOC_SPEED_BW_HZ 20.0
#define SFOC_OBSERVER_BW_HZ 50.0
#define SFOC_LOAD_BW_HZ 5.0
#define SFOC_POSITION_BW_HZ 5.0
/* The speed loop's PI zero a quarter of its crossover below it. */
#define SFOC_SPEED_ZERO_RATIO 0.25
/* A bus below half the nominal is bad input (a sagging or lost supply). */
#define SFOC_BUS_MIN_RATIO 0.5
/* CmdSpeed: the back-EMF n_p psi |w| within this share of the phase
 * voltage v_bus/sqrt(3) (the rest for R i and L di/dt), as the other speed
 * drives (P001_CMD_VOLTAGE_SHARE). */
#define SFOC_CMD_VOLTAGE_SHARE 0.9
/* CmdSpeed's ramp and a move's peak acceleration: within what i_max gives
 * the rotor alone, K_t i_max / J, with half of it left for a load. */
#define SFOC_CMD_ACCEL_SHARE 0.5
/* The largest bandwidth the sample rate allows each loop: a tenth of fs
 * (the delay's phase then costs at most 2 pi 0.1 (1 + d) = 72 deg). */
#define SFOC_BW_MAX_OF_FS 0.1
/* pi in double (SFOC_PI is POSIX, not C11) */
#define SFOC_PI 3.14159265358979323846

static bool sfoc_fail(char *err, size_t n, const char *field, const char *why, double got)
{
    if (err != NULL && n > 0) {
        snprintf(err, n, "%s: %s (got %g)", field, why, got);
    }
    return false;
}

void sfoc_design_defaults(sfoc_design_input_t *in)
{
    in->compute_delay_samples = 0.0;
    in->i_trip_samples = 1;
    in->i_rail_A = 0.0;
    in->current_bw_hz = SFOC_CURRENT_BW_HZ;
    in->speed_bw_hz = SFOC_SPEED_BW_HZ;
    in->observer_bw_hz = SFOC_OBSERVER_BW_HZ;
    in->load_bw_hz = SFOC_LOAD_BW_HZ;
    in->position_bw_hz = SFOC_POSITION_BW_HZ;
    in->n_points = 1;
    in->t_s[0] = 0.0;
    in->omega_rad_s[0] = 0.0;
}

bool sfoc_design(const sfoc_design_input_t *in, sensored_foc_config_t *cfg, char *err, size_t err_len)
{
    const motor_design_input_t *mo = &in->motor;
    if (mo->n_p < 1) return sfoc_fail(err, err_len, "motor.n_p", "must be >= 1", mo->n_p);
    const double psi_Wb = motor_design_phi_Wb(mo);
    if (!(mo->R_ohm >= 0.0)) return sfoc_fail(err, err_len, "motor.R_ohm", "must be >= 0", mo->R_ohm);
    if (!(mo->L_H > 0.0)) return sfoc_fail(err, err_len, "motor.L_d_H", "must be > 0", mo->L_H);
    if (!(mo->L_q_H > 0.0)) return sfoc_fail(err, err_len, "motor.L_q_H", "must be > 0", mo->L_q_H);
    if (!(psi_Wb > 0.0)) return sfoc_fail(err, err_len, "motor.Phi_Wb", "must be > 0", psi_Wb);
    if (!(mo->J_kgm2 > 0.0)) return sfoc_fail(err, err_len, "motor.J_kgm2", "must be > 0", mo->J_kgm2);
    if (!(in->ts_s > 0.0)) return sfoc_fail(err, err_len, "run.Ts_s", "must be > 0", in->ts_s);
    if (!(in->compute_delay_samples >= 0.0 && in->compute_delay_samples <= 1.0))
        return sfoc_fail(err, err_len, "run.compute_delay_samples", "must be in [0, 1]", in->compute_delay_samples);
    if (!(in->v_bus_V > 0.0)) return sfoc_fail(err, err_len, "supply.v_bus_V", "must be > 0", in->v_bus_V);
    if (!(in->i_max_A > 0.0)) return sfoc_fail(err, err_len, "limits.i_max_A", "must be > 0", in->i_max_A);
    if (!(in->i_trip_A >= in->i_max_A))
        return sfoc_fail(err, err_len, "limits.i_trip_A", "must be >= i_max_A", in->i_trip_A);
    if (!fault_trip_samples_ok(in->i_trip_samples))
        return sfoc_fail(err, err_len, "limits.i_trip_samples", "must be 1..8 (0: 1)", (double)in->i_trip_samples);
    const double fs = 1.0 / in->ts_s;
    const double fsr = round(fs);
    if (fabs(fs - fsr) > 1e-6 * fs || fsr > 2e9) {
        return sfoc_fail(err, err_len, "run.Ts_s", "1/Ts must be a whole number of hertz", in->ts_s);
    }
    const double bw_max = SFOC_BW_MAX_OF_FS * fs;
    const struct {
        const char *name;
        double hz;
    } bws[] = {{"sensored_foc.current_bw_hz", in->current_bw_hz},
               {"sensored_foc.speed_bw_hz", in->speed_bw_hz},
               {"sensored_foc.observer_bw_hz", in->observer_bw_hz},
               {"sensored_foc.load_bw_hz", in->load_bw_hz},
               {"sensored_foc.position_bw_hz", in->position_bw_hz}};
    for (size_t k = 0; k < sizeof bws / sizeof bws[0]; ++k) {
        if (!(bws[k].hz > 0.0 && bws[k].hz <= bw_max)) {
            return sfoc_fail(err, err_len, bws[k].name, "must be in (0, fs/10]", bws[k].hz);
        }
    }
    if (!(in->speed_bw_hz < in->current_bw_hz) || !(in->speed_bw_hz < in->observer_bw_hz) ||
        !(in->position_bw_hz < in->speed_bw_hz)) {
        return sfoc_fail(err, err_len, "sensored_foc.speed_bw_hz",
                         "the loops must nest: position < speed < current, and speed < observer", in->speed_bw_hz);
    }
    if (in->n_points < 1 || in->n_points > SPEED_PROFILE_MAX_POINTS) {
        return sfoc_fail(err, err_len, "profile", "needs 1..16 points", (double)in->n_points);
    }
    memset(cfg, 0, sizeof *cfg);
    const double ts = in->ts_s;
    const double kt = 1.5 * (double)mo->n_p * psi_Wb; /* amplitude-invariant Clarke (phase_adapter.h) */
    const double wc = 2.0 * SFOC_PI * in->current_bw_hz;
    const double ws = 2.0 * SFOC_PI * in->speed_bw_hz;
    const double wo = 2.0 * SFOC_PI * in->observer_bw_hz;
    const double wl = 2.0 * SFOC_PI * in->load_bw_hz;
    /* the one motor model (model/motor_model.h); friction is left to the
     * speed loop's integral and the load estimate (f_v = 0) */
    motor_model_t *mm = &cfg->model;
    mm->n_p = mo->n_p;
    mm->fs_hz = (int32_t)fsr;
    mm->ts_s = mc_from_double(ts);
    mm->R_ohm = mc_from_double(mo->R_ohm);
    mm->L_H = mc_from_double(mo->L_H);
    mm->Ld_H = mc_from_double(mo->L_H);
    mm->Lq_H = mc_from_double(mo->L_q_H);
    mm->psi_Wb = mc_from_double(psi_Wb);
    mm->J_kgm2 = mc_from_double(mo->J_kgm2);
    mm->ts_over_L_A_per_V = mc_from_double(ts / mo->L_H);
    mm->npL_ohm_s = mc_from_double((double)mo->n_p * mo->L_H);
    mm->K_V_s = mc_from_double((double)mo->n_p * psi_Wb);
    mm->inv_J = mc_from_double(1.0 / mo->J_kgm2);
    mm->ts_over_J = mc_from_double(ts / mo->J_kgm2);
    cfg->kt_Nm_per_A = mc_from_double(kt);
    cfg->inv_kt_A_per_Nm = mc_from_double(1.0 / kt);
    /* current loops: kp = L w_c, ki = R w_c (header) */
    cfg->current.pi_d.kp = mc_from_double(mo->L_H * wc);
    cfg->current.pi_d.ki_ts = mc_from_double(mo->R_ohm * wc * ts);
    cfg->current.pi_q.kp = mc_from_double(mo->L_q_H * wc);
    cfg->current.pi_q.ki_ts = mc_from_double(mo->R_ohm * wc * ts);
    /* speed loop: kp = J w_s / K_t, ki = kp w_s / 4 */
    const double kp_w = mo->J_kgm2 * ws / kt;
    cfg->pi_speed.kp = mc_from_double(kp_w);
    cfg->pi_speed.ki_ts = mc_from_double(kp_w * SFOC_SPEED_ZERO_RATIO * ws * ts);
    cfg->pos_kp_per_s = mc_from_double(2.0 * SFOC_PI * in->position_bw_hz);
    /* encoder observer: (s + w_o)^2 (s + w_L) (header) */
    cfg->obs.l1_ts_scaled = mc_from_double((2.0 * wo + wl) * ts * (double)(1 << ENC_OBS_SHIFT));
    cfg->obs.ts_scaled = mc_from_double(ts * (double)(1 << ENC_OBS_SHIFT));
    cfg->obs.l2_ts = mc_from_double((wo * wo + 2.0 * wo * wl) * ts);
    cfg->obs.l3_ts = mc_from_double(mo->J_kgm2 * wo * wo * wl * ts);
    cfg->obs.ts_over_J = mc_from_double(ts / mo->J_kgm2);
    cfg->obs.inv_J = mc_from_double(1.0 / mo->J_kgm2);
    cfg->i_max_A = mc_from_double(in->i_max_A);
    cfg->v_bus_min_V = mc_from_double(SFOC_BUS_MIN_RATIO * in->v_bus_V);
    cfg->compute_delay = mc_from_double(in->compute_delay_samples);
    cfg->speed_cmd_max_rad_s =
        mc_from_double(SFOC_CMD_VOLTAGE_SHARE * in->v_bus_V / sqrt(3.0) / ((double)mo->n_p * psi_Wb));
    cfg->accel_cmd_max_rad_s2 = mc_from_double(SFOC_CMD_ACCEL_SHARE * kt * in->i_max_A / mo->J_kgm2);
    fault_monitor_design(&cfg->faults, 3, in->i_max_A, in->i_trip_A, in->i_trip_samples, in->i_rail_A, ts);
    for (int f = 0; f < DRIVE_FAULT_COUNT; ++f) {
        cfg->reaction[f] = (uint8_t)FAULT_REACT_SAFE; /* a sensor: nothing to re-lock */
    }
    double bad_t = 0.0;
    if (!speed_profile_design(&cfg->profile, in->n_points, in->t_s, in->omega_rad_s, mm->fs_hz, ts, &bad_t)) {
        return sfoc_fail(err, err_len, "profile", "corner times must start at 0 and increase", bad_t);
    }
    const char *why = sensored_foc_config_problem(cfg);
    if (why != NULL) {
        return sfoc_fail(err, err_len, "sensored_foc", why, 0.0);
    }
    return true;
}
