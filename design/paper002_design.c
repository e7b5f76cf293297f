#include "design/paper002_design.h"

#include <math.h>
#include <string.h>
#include <stdio.h>

#include "design/lock_monitor_design.h"
#include "design/paper000_design.h"
#include "math/mc_convert.h"

/* How the constants below were chosen. The structure of each one (what
 * it scales, its unit) is derived; its value is the result of a random
 * search (log-uniform, then local; about 1,800 parameter sets, two to
 * four motorsim runs each) over the
 * reference scenario sim/scenarios/paper002_reference.toml with and
 * without its noise, minimising max(RMSE_noise / 0.04, RMSE_nonoise /
 * 0.015, HF / 2 V), the thresholds and the steady-state voltage
 * above 1 kHz (metrics speed_rmse_rad_s, voltage_hf_rms_V). SOSMC first;
 * then HTSMC's own gains with the EKF and the current loop held at
 * SOSMC's values (one EKF for both controllers), its cases without
 * compensation and with the inductance error in the objective too; then
 * both switching parts again with the noise-free RMSE held under 0.0148.
 * Measured with these (rounded) values: SOSMC 0.0463 rad/s with noise,
 * 0.01486 without, HTSMC 0.0465 and 0.01479; HF 2.4 V with noise, 1.0 V
 * without. No search went below 0.043 with noise: what bounds it is the
 * angle noise through the speed estimate against the disturbance
 * estimate's lag at the pulses' edges (docs/paper002.md).
 *
 * The current loop's decay rate lambda of (8) per sample: lambda Ts = 0.2
 * (2000 rad/s at 10 kHz: inside IBCC_LAMBDA_TS_MAX with a sample of
 * computation delay, five samples per time constant). */
#define P002_LAMBDA_TS 0.2
/* The current references' filter (control/ibcc.h) at this multiple of the
 * current loop's rate: the inversion's feed-forward then asks at most
 * L lambda_ref per ampere of demand step, not L/Ts (without it the 5 mA
 * noise became 10.6 V of chattering above 1 kHz). 0.3: 600 rad/s. */
#define P002_REF_RATE_PER_LAMBDA 0.3
/* The speed loop's double pole a factor below the current loop's rate:
 * 4 gives 500 rad/s, under the references' filter (600 rad/s) and the
 * current loop (2000 rad/s), so the cascade keeps its separation. */
#define P002_SPEED_BELOW_CURRENT 4.0
/* SOSMC's switching gain [rad/s^3] and boundary layer [rad/s^2]: the
 * disturbance's second derivative the reference set's pulses reach (0.5
 * N m over 20 ms raised-cosine edges: (pi/0.02)^2 0.25 / J = 6e6 at the
 * peak) is taken by the EKF's compensation; what is left for the switching
 * term is slow. The layer is narrow against the sliding variable's noise
 * (the estimated acceleration alone is noisy by about 75 rad/s^2: the
 * disturbance estimate's 0.075 N m over J), so tanh(s/eps) switches like
 * the sign of (22) on most samples and the integral of (28) slopes at
 * +-J eta = +-1.8 N m/s. */
#define P002_SOSMC_ETA 1.8e3
#define P002_SOSMC_EPS 23.0
/* HTSMC: alpha_I [1/s] the integral's rate, the twisting gains [rad/s^3]
 * alpha_M = 2 alpha_m, the super-twisting part lambda |s|^(1/2) up to
 * s0 [rad/s], and a layer eps [rad/s]; nu's bound is the acceleration
 * the current limit gives (errata: not Levant's normalised 1). eps 0.96
 * rad/s is ten times the speed estimate's noise (0.1 rad/s RMS). */
#define P002_HTSMC_ALPHA_I 750.0
#define P002_HTSMC_ALPHA_m 240.0
#define P002_HTSMC_LAMBDA 610.0
#define P002_HTSMC_S0 0.58
#define P002_HTSMC_EPS 0.96
/* EKF process noise per sample (random walks): the currents 1e-4 A^2 (the
 * model's unmodelled voltage errors: 10 mA per sample against 5 mA of
 * sensor noise), the angle 1e-12 rad^2 (integrated exactly from the
 * speed), the speed 1e-3 (rad/s)^2 and the disturbance 4e-3 (N m)^2
 * (LuGre and the load pulses change within milliseconds: a slower M_0
 * lags the pulses' edges, a faster one lets the angle noise through). */
#define P002_Q_I 1e-4
#define P002_Q_THETA 1e-12
#define P002_Q_OMEGA 1e-3
#define P002_Q_M0 4e-3
/* The sensorless variant's flux observer (12): the radial rate 2 gamma
 * psi^2 of its gradient term [1/s]. Paper 001's tuning gives 289 1/s
 * (gamma = 5000 at Phi = 0.17 Wb, design/paper001_design.c); here the
 * term's target, the active flux's radius psi + (L_d - L_q) i_d, is taken
 * at the EKF's a priori i_d, whose error the gradient turns into a radial
 * offset and the rotation into an angle ripple at the electrical
 * frequency: 3e-4 rad RMS at 289 1/s (0.62 rad/s of speed RMSE without
 * noise), 2.5e-5 rad at 50 1/s, 1.1e-5 at 10 1/s (measured on the
 * reference scenario, docs/paper002.md). 50 1/s still pulls a flux drift
 * back within 20 ms. */
#define P002_FLUX_RADIAL_RATE_PER_S 50.0
/* Loss of the estimate (paper002_drive.h): the EKF's angle innovation
 * beyond 0.02 rad (mechanical; 0.08 rad electrical) for 5 ms. That is 200
 * times the encoder's noise and 90 times the flux observer's (2.2e-4 rad),
 * and a fifth of the angle at which a d-q frame error costs 8 % of the
 * torque (0.4 rad electrical); a healthy run's largest innovation is
 * under 1e-3 rad. 5 ms rides out a single glitch. */
#define P002_LOS_THETA_RAD 0.02
#define P002_LOS_S 5e-3
/* A stalled (or runaway) rotor: the EKF's speed off the reference by more
 * than half the reference plus 10 rad/s for 0.1 s. The 16 cases' largest
 * speed error is 5 rad/s (the start from w(0) = 5, and the ring of SOSMC
 * without compensation with the inductance error, docs/paper002.md);
 * 10 rad/s is twice that; 0.1 s lets such a start settle. */
#define P002_STALL_TOL 0.5
#define P002_STALL_FLOOR_RAD_S 10.0
#define P002_STALL_S 0.1
/* Loss of lock of the sensorless variant (supervisor/lock_monitor.h,
 * design/lock_monitor_design.c; docs/faults.md): the flux observer's
 * residual along the estimated rotor axis must stay beyond its tolerance
 * bound for this many time constants of the observer's radial dynamics,
 * 1/(2 gamma psi^2) = 1/P002_FLUX_RADIAL_RATE_PER_S (20 ms): the residual
 * is the gradient term of (12) (paper 001), and a radial transient of a
 * lock that holds (the start, a step of the active flux's target with
 * i_d) decays at that rate, to e^-5 = 0.7 % after five (0.1 s). The
 * speed loop (500 rad/s) and the current loop are faster. */
#define P002_LOCK_SETTLE_PER_RADIAL_TAU 5.0
/* ... and by its angle innovation (LOCK_CRIT_ANGLE_INNOVATION, the EKF's
 * angle innovation against the flux observer's angle): the flux
 * residual sees a steady drift, but this variant's losses are a limit
 * cycle and 180-degree flips (docs/paper002.md). The bound's noise part
 * is 6 sigma of the innovation (LOCK_INNOV_K_SIGMA, S = P^-_thth + r_th
 * at run time), its tolerance part the speed error the drive accepts
 * from a lock, its stall band 0.5 |w_d| + 10 rad/s, times Ts (the EKF
 * predicts the angle a sample ahead with its speed). The count's
 * persistence is the glitch the angle innovation's LOSS_OF_SYNC already
 * rides out, P002_LOS_S (5 ms, 50 samples in a row), and a full count
 * drains in the stall criterion's P002_STALL_S (0.1 s): up = 20, limit
 * 1000; a loss is more than 1 sample in 21 beyond the bound. */
#define P002_LOCK_INNOV_GLITCH_S P002_LOS_S
#define P002_LOCK_INNOV_FORGET_S P002_STALL_S
/* The HF injection's handover (angle_source HFI, paper002_drive.h), by
 * the EKF's |speed| (mechanical). The flux observer's angle error from a
 * voltage error dV is about dV / (p psi w): the dead time's 0.48 V on the
 * VESC 6 (v_bus t_dead f_pwm, what its compensation leaves is a part of
 * that) and the 60 K warm winding's R error (0.07 ohm x a few A) are
 * fractions of a volt, so the blend starts at 15 rad/s (back-EMF p psi w =
 * 2.4 V, five times 0.48 V) and is complete at 30 rad/s (4.8 V, ten
 * times); the injection is on below 30 rad/s and off above 40: 10 rad/s
 * of hysteresis, twice the speed loop's largest error in the 16 cases
 * (P002_STALL_FLOOR_RAD_S's note), so it does not chatter. */
#define P002_HFI_BLEND_LO_RAD_S 15.0
#define P002_HFI_BLEND_HI_RAD_S 30.0
#define P002_HFI_ON_RAD_S 30.0
#define P002_HFI_OFF_RAD_S 40.0
/* With the injection the speed loop's double pole at most a third of the
 * EKF's speed bandwidth (paper002_design.c): its phase lag at the loop's
 * crossover stays under 20 degrees (a second-order estimator at a third of
 * its natural frequency, damping 0.7). */
#define P002_HFI_SPEED_BELOW_EKF 3.0
/* The angle hold's gain (paper002_drive.h) a quarter of the speed loop's
 * pole: the outer loop a factor below the inner one, as the speed loop
 * under the current loop (P002_SPEED_BELOW_CURRENT). */
#define P002_HFI_HOLD_BELOW_SPEED 4.0
/* The start from an unknown angle (hfi_find_angle, paper002_drive.h).
 * LOCK: 0.1 s of injection alone, twice the 50 ms in which the unit
 * tests' PLL locked from +-1.3 rad (docs/hf_injection.md; the loop's w_n
 * 2 pi 50 Hz, zeta 1: a start near the unstable pi/2 leaves it first on
 * the noise). The polarity test's pulses: 20 V to 5 A on L_d, the sizing
 * measured on the plant's biased iron (tests/sim/test_hfi_polarity.cpp:
 * 9.6 A with the magnet, 6.8 A against, under the 20 A i_max; sized to 15
 * A they reach 35 A, beyond the 30 A trip), 18 + 8 L_d/R samples a half
 * (magnet_polarity.c). */
#define P002_HFI_LOCK_S 0.1
/* The lock's check before the test: the mean of (H1)'s relative amplitude
 * over the LOCK's last quarter (25 ms, after the 50 ms the PLL took to
 * lock in the unit tests) at least its value at |e| = pi/4, (1 + L_d/L_q)/2
 * (cos^2 e + (L_d/L_q) sin^2 e: 1 on the d axis, L_d/L_q across it). Within
 * pi/4 the test's pulses along the estimate still meet the magnet's axis
 * at cos e >= 1/sqrt(2): the decision keeps its sign. Below, the PLL is
 * near the unstable quadrature or still moving, and the drive refuses. */
#define P002_HFI_LOCK_WINDOW_FRACTION 0.25
#define P002_POLARITY_PULSE_V 20.0
#define P002_POLARITY_PEAK_A 5.0
/* The margin's noise floor: a noiseless simulated sensor still gets 6
 * sqrt(10/3) x 1 mA = 11 mA of margin; a real sensor's is larger (a 12-bit
 * converter over +-40 A alone: 5.6 mA, docs/hf_injection.md). */
#define P002_POLARITY_SIGMA_FLOOR_A 1e-3
/* the initial covariance: what a start at rest leaves unknown */
#define P002_P0 1e-3

static bool p002_fail(char *err, size_t n, const char *field, const char *why, double got)
{
    if (err != NULL && n > 0) {
        snprintf(err, n, "%s: %s (got %g)", field, why, got);
    }
    return false;
}

#if !MC_FIXED
/* true if any of the n entries is non-zero: the user gave the matrix */
static bool p002_given(const double *v, int n)
{
    for (int i = 0; i < n; ++i) {
        if (v[i] != 0.0) {
            return true;
        }
    }
    return false;
}
#endif

void p002_design_defaults(p002_design_input_t *in)
{
    in->motor.n_phases = 3;
    in->motor.R_ohm = 0.3;
    in->motor.L_H = 3e-3;
    in->motor.L_q_H = 9e-3;
    in->motor.K_Nm_per_A = 0.16; /* psi = 0.04 Wb at p = 4 */
    in->motor.J_kgm2 = 1e-3;
    in->motor.fv_Nms_per_rad = 5e-4;
    in->motor.coulomb_Nm = 0.0;
    in->motor.n_p = 4;
    in->ts_s = 1e-4;
    in->i_max_A = 20.0;
    in->i_trip_A = 30.0;
    in->i_rail_A = 0.0;
    in->i_trip_samples = 1; /* the instantaneous trip */
    in->sigma_i_A = 5e-3;
    in->sigma_theta_rad = 1e-4;
    in->encoder_counts = 65536;
    in->controller = P002_SOSMC;
    in->compensate = true;
    in->angle_source = P002_ANGLE_ENCODER;
    in->theta0_rad = 0.0;
    in->hfi_find_angle = false;
    in->iron_i_sat_A = 0.0; /* the linear iron of (2) */
    in->iron_i_bias_A = 0.0;
    in->compute_delay_samples = 0.0; /* a DAC card; an MCU's PWM is 1 */
    for (int i = 0; i < EKF_N; ++i) {
        in->ekf_q[i] = 0.0; /* the design's Q */
    }
    for (int i = 0; i < EKF_M; ++i) {
        in->ekf_r[i] = 0.0; /* the design's R */
    }
    in->t0_s = 0.2;
    in->t1_s = 0.4;
    in->w0_rad_s = 0.0;
    in->w1_rad_s = 100.0;
}

bool p002_design(const p002_design_input_t *in, paper002_config_t *cfg, char *err, size_t err_len)
{
#if MC_FIXED
    (void)in;
    (void)cfg;
    return p002_fail(err, err_len, "paper002", "the EKF needs the float build: its angle variance 1e-8 rad^2 is "
                                               "below Q14.17's step of 7.6e-6 (docs/paper002.md)", 0.0);
#else
    /* what this design does not set is zero: the dead-time compensation
     * disabled (no inverter; the host part sets it from [inverter]) */
    memset(cfg, 0, sizeof *cfg);
    /* the motor in paper 002's names */
    const motor_design_input_t *mo = &in->motor;
    const double Ld = mo->L_H, Lq = mo->L_q_H, R = mo->R_ohm, J = mo->J_kgm2, d = mo->fv_Nms_per_rad;
    const int p = mo->n_p;
    if (!(Ld > 0.0)) return p002_fail(err, err_len, "motor.L_d_H", "must be > 0", Ld);
    if (!(Lq > 0.0)) return p002_fail(err, err_len, "motor.L_q_H", "must be > 0", Lq);
    if (!(R >= 0.0)) return p002_fail(err, err_len, "motor.R_ohm", "must be >= 0", R);
    if (p < 1) return p002_fail(err, err_len, "motor.n_p", "must be >= 1", p);
    const double psi = motor_design_phi_Wb(mo);
    if (!(psi > 0.0)) return p002_fail(err, err_len, "motor.Phi_Wb", "must be > 0", psi);
    if (!(J > 0.0)) return p002_fail(err, err_len, "motor.J_kgm2", "must be > 0", J);
    if (!(d >= 0.0)) return p002_fail(err, err_len, "motor.fv_Nms_per_rad", "must be >= 0", d);
    if (!(in->ts_s > 0.0)) return p002_fail(err, err_len, "run.Ts_s", "must be > 0", in->ts_s);
    if (!(in->i_max_A > 0.0)) return p002_fail(err, err_len, "limits.i_max_A", "must be > 0", in->i_max_A);
    if (!(in->i_trip_A >= in->i_max_A)) return p002_fail(err, err_len, "limits.i_trip_A", "must be >= i_max_A", in->i_trip_A);
    if (!fault_trip_samples_ok(in->i_trip_samples))
        return p002_fail(err, err_len, "limits.i_trip_samples", "must be 1..8 (0: 1)", (double)in->i_trip_samples);
    const bool hfi = in->angle_source == P002_ANGLE_HFI;
    /* the sensorless variants: the flux observer alone, or behind the injection */
    const bool flux = in->angle_source == P002_ANGLE_FLUX || hfi;
    if (!flux && in->angle_source != P002_ANGLE_ENCODER) return p002_fail(err, err_len, "paper002.estimator", "unknown angle source", in->angle_source);
    if (hfi && !(Lq > Ld)) return p002_fail(err, err_len, "motor.L_q_H", "the HF injection needs a salient motor, L_q > L_d", Lq);
    if (!flux && in->encoder_counts < 1) return p002_fail(err, err_len, "encoder.counts_per_turn", "must be >= 1", (double)in->encoder_counts);
    if (!(in->sigma_i_A >= 0.0)) return p002_fail(err, err_len, "sensor.noise_A", "must be >= 0", in->sigma_i_A);
    if (!(in->sigma_theta_rad >= 0.0)) return p002_fail(err, err_len, "encoder.noise_rad", "must be >= 0", in->sigma_theta_rad);
    if (!(in->t1_s > in->t0_s && in->t0_s >= 0.0)) return p002_fail(err, err_len, "reference.t1_s", "must be > t0_s >= 0", in->t1_s);
    if (!(in->compute_delay_samples >= 0.0 && in->compute_delay_samples <= 1.0))
        return p002_fail(err, err_len, "run.compute_delay_samples", "must be in [0, 1]", in->compute_delay_samples);
    /* a user's Q or R: all entries given (> 0) or none (all 0) */
    const bool user_q = p002_given(in->ekf_q, EKF_N), user_r = p002_given(in->ekf_r, EKF_M);
    char key[32]; /* "paper002.ekf_q[" + an int + "]" */
    for (int i = 0; user_q && i < EKF_N; ++i) {
        if (!(in->ekf_q[i] > 0.0 && isfinite(in->ekf_q[i]))) {
            snprintf(key, sizeof key, "paper002.ekf_q[%d]", i);
            return p002_fail(err, err_len, key, "must be > 0 and finite (Q positive definite)", in->ekf_q[i]);
        }
    }
    for (int i = 0; user_r && i < EKF_M; ++i) {
        if (!(in->ekf_r[i] > 0.0 && isfinite(in->ekf_r[i]))) {
            snprintf(key, sizeof key, "paper002.ekf_r[%d]", i);
            return p002_fail(err, err_len, key, "must be > 0 and finite (R positive definite)", in->ekf_r[i]);
        }
    }
    const double fs = 1.0 / in->ts_s;
    const double fsr = floor(fs + 0.5);
    if (fabs(fs - fsr) > 1e-6 * fs) return p002_fail(err, err_len, "run.Ts_s", "1/Ts must be a whole number of hertz", in->ts_s);
    const double Kt = 1.5 * p * psi;
    const double M_max = Kt * in->i_max_A;

    /* the EKF: R from the sensors (the encoder's quantisation step^2/12
     * added to its noise; a floor of 1e-12 keeps R positive definite with
     * ideal sensors), Q and P0 as above */
    /* the one motor model (model/motor_model.h): every block reads it; L_H
     * is L_d (the scenario's convention), K_V_s = n_p psi */
    motor_model_t *mm = &cfg->model;
    mm->n_p = p;
    mm->fs_hz = (int32_t)fsr;
    mm->ts_s = mc_from_double(in->ts_s);
    mm->R_ohm = mc_from_double(R);
    mm->L_H = mc_from_double(Ld);
    mm->Ld_H = mc_from_double(Ld);
    mm->Lq_H = mc_from_double(Lq);
    mm->psi_Wb = mc_from_double(psi);
    mm->J_kgm2 = mc_from_double(J);
    mm->fv_Nm_s = mc_from_double(d);
    mm->ts_over_L_A_per_V = mc_from_double(in->ts_s / Ld);
    mm->npL_ohm_s = mc_from_double(p * Ld);
    mm->K_V_s = mc_from_double(p * psi);
    mm->inv_J = mc_from_double(1.0 / J);
    mm->ts_over_J = mc_from_double(in->ts_s / J);
    mm->J_over_K_A_s2 = mc_from_double(J / (p * psi));
    mm->fv_over_K_A_s = mc_from_double(d / (p * psi));
    mm->LJ_over_KTs_V_s2 = mc_from_double(Ld * J / (p * psi * in->ts_s));
    mm->Lfv_over_KTs_V_s = mc_from_double(Ld * d / (p * psi * in->ts_s));
    ekf_ipmsm_config_t *e = &cfg->ekf;
    const double q[EKF_N] = {P002_Q_I, P002_Q_I, P002_Q_THETA, P002_Q_OMEGA, P002_Q_M0};
    for (int i = 0; i < EKF_N; ++i) {
        e->q[i] = mc_from_double(user_q ? in->ekf_q[i] : q[i]);
        e->p0[i] = mc_from_double(P002_P0);
        e->x0[i] = MC_ZERO;
    }
    const double step = 2.0 * 3.14159265358979323846 / (double)in->encoder_counts;
    const double r_i = fmax(in->sigma_i_A * in->sigma_i_A, 1e-12);
    double r_th = fmax(in->sigma_theta_rad * in->sigma_theta_rad + step * step / 12.0, 1e-12);
    if (flux) {
        /* the flux observer's angle: eta = lambda_hat - L_q i carries the
         * alpha-beta current noise (sigma_i sqrt(2/3) after the amplitude-
         * invariant Clarke) times L_q, across psi: L_q sigma_ab / psi rad
         * electrical, over p mechanical (the integrated R i noise, R sigma
         * Ts per sample, is three orders smaller) */
        const double s_th = Lq * in->sigma_i_A * sqrt(2.0 / 3.0) / psi / (double)p;
        r_th = fmax(s_th * s_th, 1e-12);
    }
    if (hfi) {
        /* the injection's angle at standstill (estimators/hf_injection.h):
         * the EKF gets the tracking loop's angle (H6), whose noise is
         * filtered and so correlated from sample to sample, and is told
         * the noise of the unfiltered measurement (H7) per sample: the
         * demodulated error's sigma_i sqrt(5/3) sqrt(6)/2 times (H4)'s
         * gain, halved (e = eps/2), over p mechanical (0.0089 rad). Told
         * the loop's own 0.0018 rad the EKF took it as white, its speed
         * bandwidth and the speed loop's rose 2.2 times and the
         * reversal and the handover lost synchronism; given the unfiltered
         * angle (H7) instead, the EKF's angle was 1.6-3 times worse at 0
         * rpm (docs/hf_injection.md). */
        const double dinv = 1.0 / Ld - 1.0 / Lq;
        const double g = 1.0 - 2.0 * in->compute_delay_samples;
        const double s_eps = in->sigma_i_A * sqrt(5.0 / 3.0) * sqrt(6.0) / 2.0 * 2.0 /
                             fabs(g * mc_to_double(HF_INJ_VOLTAGE_V) * in->ts_s * dinv);
        const double s_th = 0.5 * s_eps / (double)p;
        r_th = fmax(s_th * s_th, 1e-12);
    }
    e->r[0] = mc_from_double(user_r ? in->ekf_r[0] : r_i);
    e->r[1] = mc_from_double(user_r ? in->ekf_r[1] : r_i);
    e->r[2] = mc_from_double(user_r ? in->ekf_r[2] : r_th);

    /* the current loop (9) */
    const double lambda = P002_LAMBDA_TS * fsr;
    cfg->ibcc = (ibcc_config_t){mc_from_double(lambda),
                                mc_from_double(1.0 - exp(-P002_REF_RATE_PER_LAMBDA * lambda * in->ts_s))};
    /* MTPA (15)/(18) */
    cfg->mtpa = (mtpa_config_t){mc_from_double(in->i_max_A)};
    /* SOSMC: s^2 + alpha_0 s + alpha_I with a double pole at w_s */
    double ws = lambda / P002_SPEED_BELOW_CURRENT;
    if (hfi) {
        /* the injection's angle is 40 times noisier than the encoder's: the
         * EKF's speed from it has the bandwidth of a Kalman filter on a
         * double integrator, (q_omega / (r_theta Ts^2))^(1/4) (188 rad/s on
         * the reference set), and the speed loop stays a factor below it */
        const double w_ekf = pow((user_q ? in->ekf_q[3] : P002_Q_OMEGA) / (e->r[2] * in->ts_s * in->ts_s), 0.25);
        ws = fmin(ws, w_ekf / P002_HFI_SPEED_BELOW_EKF);
    }
    cfg->sosmc = (sosmc_config_t){mc_from_double(2.0 * ws), mc_from_double(ws * ws), mc_from_double(P002_SOSMC_ETA),
                                  mc_from_double(P002_SOSMC_EPS), mc_from_double(M_max), in->compensate};
    /* HTSMC */
    const double nu_max = M_max / J;
    cfg->htsmc = (htsmc_config_t){mc_from_double(P002_HTSMC_ALPHA_I), mc_from_double(P002_HTSMC_ALPHA_m),
                                  mc_from_double(2.0 * P002_HTSMC_ALPHA_m), mc_from_double(P002_HTSMC_LAMBDA),
                                  mc_from_double(0.5), mc_from_double(P002_HTSMC_S0), mc_from_double(nu_max),
                                  mc_from_double(P002_HTSMC_EPS), mc_from_double(M_max), in->compensate};
    cfg->controller = (in->controller == P002_HTSMC) ? P002_HTSMC : P002_SOSMC;
    /* the angle source; the flux observer (12)-(14) on the active flux
     * (L = L_q, paper002_drive.h) in w = lambda/Ts units (flux_observer.h) */
    cfg->angle_source = hfi ? P002_ANGLE_HFI : (flux ? P002_ANGLE_FLUX : P002_ANGLE_ENCODER);
    if (hfi) {
        if (!hf_injection_design(&cfg->hfi, mc_from_double(Ld), mc_from_double(Lq), mc_from_double(in->ts_s),
                                 HF_INJ_VOLTAGE_V, HF_INJ_PLL_WN_RAD_S, mc_from_double(in->compute_delay_samples))) {
            return p002_fail(err, err_len, "run.compute_delay_samples",
                             "the HF injection needs a delay within [0, 0.25] or [0.75, 1] (hf_injection.h)",
                             in->compute_delay_samples);
        }
        cfg->hfi_blend_lo_rad_s = mc_from_double(P002_HFI_BLEND_LO_RAD_S);
        cfg->hfi_blend_hi_rad_s = mc_from_double(P002_HFI_BLEND_HI_RAD_S);
        cfg->hfi_on_rad_s = mc_from_double(P002_HFI_ON_RAD_S);
        cfg->hfi_off_rad_s = mc_from_double(P002_HFI_OFF_RAD_S);
        cfg->hfi_hold_gain_per_s = mc_from_double(ws / P002_HFI_HOLD_BELOW_SPEED);
        cfg->hfi_find_angle = in->hfi_find_angle;
        if (in->hfi_find_angle) {
            cfg->hfi_lock_ticks = (int32_t)ceil(P002_HFI_LOCK_S / in->ts_s);
            cfg->hfi_lock_window = (int32_t)ceil(P002_HFI_LOCK_WINDOW_FRACTION * cfg->hfi_lock_ticks);
            cfg->hfi_lock_amp_min = mc_from_double(0.5 * (1.0 + Ld / Lq));
            if (!magnet_polarity_design(&cfg->magpol, mc_from_double(P002_POLARITY_PULSE_V),
                                        mc_from_double(P002_POLARITY_PEAK_A), mc_from_double(Ld), mc_from_double(R),
                                        mc_from_double(in->ts_s), mc_from_double(fmax(in->sigma_i_A, P002_POLARITY_SIGMA_FLOOR_A)))) {
                return p002_fail(err, err_len, "paper002.hfi_find_angle",
                                 "the magnet polarity test's design refused the motor (magnet_polarity.h)", Ld);
            }
        }
    }
    /* hfi_find_angle with another angle source (motorsim --estimator over
     * an hfi scenario): that variant is told theta0_rad, as it always is */
    const double gamma = P002_FLUX_RADIAL_RATE_PER_S / (2.0 * psi * psi);
    const double phi_fs = psi * fsr;
    const int sh = (int)floor(log2(phi_fs)) + 1;
    cfg->flux = (flux_observer_config_t){mc_from_double(R), mc_from_double(Lq * fsr),
                                         mc_from_double(phi_fs), mc_from_double(ldexp(1.0, -sh)),
                                         mc_from_double(ldexp(1.0 / phi_fs, sh)),
                                         mc_from_double(gamma * psi * psi * psi)};
    /* the iron's saturation the active flux is taken with
     * (model/iron_model.h): none unless given (the paper's linear model) */
    if (!iron_model_init(&cfg->iron, mc_from_double(Ld), mc_from_double(Lq), mc_from_double(psi),
                         mc_from_double(in->iron_i_sat_A), mc_from_double(in->iron_i_bias_A))) {
        return p002_fail(err, err_len, "paper002.iron_model",
                         "the iron's i_sat_A and i_sat_bias_A must be >= 0, the bias only with i_sat_A > 0",
                         in->iron_i_sat_A);
    }
    /* the start angle: told (an alignment), or found by the drive */
    cfg->flux_theta0_rad = mc_from_double((hfi && in->hfi_find_angle) ? 0.0 : in->theta0_rad);
    /* loss of lock of the sensorless variant: the shared derivation
     * (design/lock_monitor_design.c) with paper 001's tolerances (R, L
     * +-50 %, Phi +15 %, 30 degrees, 1 % of i_max in the current) on the
     * active flux: L of (14) is L_q, the radius psi + (L_d - L_q) i_d moves
     * with L_d i_d (paper 002 (1)), and |eta|/psi reaches at most rho_max =
     * 1 + |L_q - L_d| |i_d| / psi at the MTPA point of magnitude i_max: (18)
     * with i_q^2 = i_max^2 - i_d^2 gives 2 i_d^2 + (psi/(L_d - L_q)) i_d -
     * i_max^2 = 0, |i_d| = (sqrt(psi^2 + 8 dL^2 i_max^2) - psi) / (4 dL),
     * dL = |L_q - L_d| (12.6 A, rho_max 2.89 for the reference motor at
     * 20 A; MTPA's i_d makes the radius grow for either sign of dL). A
     * non-salient motor (dL = 0) keeps i_d at 0 (control/mtpa.h): paper
     * 001's case, L_radial 0 and rho_max 1. The encoder variant needs no
     * lock monitor (ticks 0: off): its angle is measured, not estimated,
     * and the EKF's angle innovation (LOSS_OF_SYNC) already checks it. */
    if (flux) {
        const double dL = fabs(Lq - Ld);
        const double id_max_A =
            dL > 0.0 ? (sqrt(psi * psi + 8.0 * dL * dL * in->i_max_A * in->i_max_A) - psi) / (4.0 * dL) : 0.0;
        lock_monitor_design_input_t li;
        lock_monitor_design_defaults(&li);
        li.R_ohm = R;
        li.L_H = Lq;
        li.Phi_Wb = psi;
        li.L_radial_H = dL > 0.0 ? Ld : 0.0;
        li.rho_max = 1.0 + dL * id_max_A / psi;
        li.n_p = p;
        li.gPhi3_V = gamma * psi * psi * psi;
        li.i_max_A = in->i_max_A;
        li.settle_s = P002_LOCK_SETTLE_PER_RADIAL_TAU / P002_FLUX_RADIAL_RATE_PER_S;
        li.ts_s = in->ts_s;
        if (!lock_monitor_design(&li, &cfg->lock, err, err_len)) {
            return false;
        }
        lock_innovation_design_input_t ii;
        lock_innovation_design_defaults(&ii);
        ii.glitch_s = P002_LOCK_INNOV_GLITCH_S;
        ii.forget_s = P002_LOCK_INNOV_FORGET_S;
        ii.ts_s = in->ts_s;
        if (!lock_monitor_design_innovation(&ii, &cfg->lock, err, err_len)) {
            return false;
        }
    }
    /* faults (docs/faults.md): the generic set, designed as the other
     * drives' are, and the loss of the estimate */
    fault_monitor_design(&cfg->faults, 3, in->i_max_A, in->i_trip_A, in->i_trip_samples, in->i_rail_A, in->ts_s);
    for (int f = 0; f < DRIVE_FAULT_COUNT; ++f) {
        cfg->reaction[f] = (uint8_t)FAULT_REACT_SAFE; /* no re-lock: an estimate lost stays lost */
    }
    cfg->los_theta_rad = mc_from_double(P002_LOS_THETA_RAD);
    cfg->los_ticks = (int32_t)ceil(P002_LOS_S * fsr - 1e-9);
    cfg->stall_tol = mc_from_double(P002_STALL_TOL);
    cfg->stall_floor_rad_s = mc_from_double(P002_STALL_FLOOR_RAD_S);
    cfg->stall_ticks = (int32_t)ceil(P002_STALL_S * fsr - 1e-9);
    cfg->compute_delay = mc_from_double(in->compute_delay_samples);
    cfg->i_trip_A = mc_from_double(in->i_trip_A);
    if (!speed_poly_init(&cfg->reference, (uint32_t)llround(in->t0_s * fsr), (uint32_t)llround(in->t1_s * fsr),
                         mc_from_double(in->w0_rad_s), mc_from_double(in->w1_rad_s), (int32_t)fsr)) {
        return p002_fail(err, err_len, "reference.t1_s", "the reference's change must last at least a sample", in->t1_s);
    }
    return true;
#endif
}
