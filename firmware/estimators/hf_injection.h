/*
 * hf_injection.h - rotor angle of a salient PM motor at standstill and low
 * speed from a square-wave high-frequency voltage on the estimated d axis
 * (issue 31). The method is the square-wave injection of Yoon, Sul,
 * Morimoto, Ide, "High-bandwidth sensorless algorithm for AC machines based
 * on square-wave-type voltage injection", IEEE Trans. Ind. Appl. 47(3),
 * 2011 (their (5)-(9)); the equations below are derived here for this
 * project's sampling, the code is this project's.
 *
 * Why a square wave at half the control rate (not a pulsating sine): the
 * drive updates its voltage once per control period Ts, so fs/2 (5 kHz at
 * 10 kHz) is the highest injection it can make, far above the current and
 * speed loops (whose fundamental then needs no band-stop filter), and the
 * demodulation is a difference of three samples, no band-pass or low-pass
 * filter with its phase lag (a sine at a fraction of fs needs both). The
 * price: the injection is audible (5 kHz) and its current ripple is a
 * triangle at fs/2.
 *
 * Model (the HF part, R and back-EMF neglected over one Ts: R Ts / L_d =
 * 0.01 on paper 002's IPMSM): in the rotor frame di_d/dt = u_d / L_d,
 * di_q/dt = u_q / L_q. The voltage +-V_h along the estimated d axis, at
 * the angle error e = theta - theta_hat (electrical), is (V_h cos e,
 * -V_h sin e) in the rotor frame; over one sample, back in the estimated
 * frame,
 *   di_dhat = V_h Ts (cos^2 e / L_d + sin^2 e / L_q)                  (H1)
 *   di_qhat = V_h Ts / 2 (1/L_d - 1/L_q) sin 2e                         (H2)
 * With the sign s_k alternating every sample, the current difference
 * Delta i_k = i_k - i_{k-1} holds the fundamental's slope plus s_{k-1}
 * times (H1, H2); the slope changes from one sample to the next by what the
 * change of the fundamental voltage v drives, Ts L^-1 (v_k - v_{k-1})
 * (v_k the one held over [k-1, k]; L^-1 = diag(1/L_d, 1/L_q) taken in the
 * injection's frame, exact at e = 0), so
 *   h_k = s_{k-1} (Delta i_k - Delta i_{k-1} - Ts L^-1 (v_k - v_{k-1})) / 2
 *                                                                      (H3)
 * removes the slope and the controller's steps and keeps (H1, H2) (without
 * the voltage term a 1 V step of the q voltage would read as 0.05 rad of
 * angle: a current controller's own steps fed back into the angle), and
 *   eps = h_qhat / (g V_h Ts (1/L_d - 1/L_q) / 2) = sin 2e              (H4)
 * is the demodulated error, 2e for small e. g = 1 - 2 d accounts for the
 * board's computation delay d (the voltage over a sample is (1 - d) u_k +
 * d u_{k-1}, i.e. g s_k V_h for an alternating u): d must stay within
 * [0, 1/4] or [3/4, 1] (|g| >= 1/2). The fundamental current without the
 * injection's triangle (exact for a current linear in time and for the
 * alternating part):
 *   i_f = (3 i_k + 2 i_{k-1} - i_{k-2}) / 4.                           (H5)
 * (H5) is exact while the voltage alternates; where the injection starts
 * or stops, the triangle starts from or ends at its centre, and (H5) of
 * it alone is a glitch of up to 3/4 of its amplitude (0.13 A, 26 sigma of
 * the sensor's noise to the EKF downstream, which took it for a speed
 * step: docs/hf_injection.md, the handover). So (H5) runs on the current
 * less the triangle's model,
 *   r_k = r_{k-1} + (Ts / L_d) ((1 - d) u_h,k-1 + d u_h,k-2)           (H8)
 * (the injection taken along the d axis, e = 0; u_h,k the injection
 * commanded at step k), zero before the first pulse and after the stop
 * pulse, and of zero (H5) while the voltage alternates. With the
 * half-amplitude first and last pulses (+-V_h/2) the triangle is centred
 * from the sample after the first pulse on, for any d, and back at zero
 * two samples after the stop pulse.
 * A type-2 tracking loop (PLL) on e_hat = eps/2:
 *   omega_hat += k_i e_hat,   theta_hat += Ts (omega_hat + k_p e_hat)  (H6)
 * with k_p = 2 zeta w_n, k_i = w_n^2 Ts (zeta = 1); and the angle each
 * sample measures, without the loop's filter (for a model-based observer
 * downstream, which then does the filtering without the loop's lag):
 *   theta_raw = theta_inj + eps / 2,                                    (H7)
 * theta_inj the direction of the injection (H3) answers. The loop's noise
 * bandwidth
 * B_n = w_n (zeta + 1/(4 zeta)) / 2 = 0.625 w_n. The sign of (H4) makes e
 * = 0 stable and e = +-pi/2 unstable: it locks to the d axis from any
 * |e| < pi/2 and to the axis pi away otherwise (the magnet's polarity is
 * not in (H1)-(H4): estimators/magnet_polarity.h settles it).
 *
 * The numbers on paper 002's IPMSM (L_d 3 mH, L_q 9 mH: L_q / L_d = 3) in
 * the hardware-like plant (docs/plant.md: 5 mA Gaussian noise per phase,
 * VESC 6: 500 ns dead time at 20 kHz on 48 V), HF_INJ_* below:
 *  - signal: (H2)'s slope, V_h Ts (1/L_d - 1/L_q) = V_h 0.0222 A/rad
 *    (electrical) per sample; at V_h = 10 V 0.222 A/rad;
 *  - noise: (H3) is (i_k - 2 i_{k-1} + i_{k-2})/2, sqrt(6)/2 the phase
 *    noise on one axis; the axis carries up to sqrt(5/3) of a phase's
 *    (Clarke's beta = (a + 2 b)/sqrt(3)): 5 mA x 1.29 x 1.22 = 7.9 mA per
 *    sample, 0.036 rad of e per sample at 10 V; the PLL averages it over
 *    1/(2 B_n Ts) samples: sigma_e = 0.036 sqrt(2 B_n Ts) = 0.007 rad
 *    electrical at B_n = 196 Hz (w_n = 2 pi 50 Hz);
 *  - dead time: its voltage error is about v_bus t_dead f_pwm = 48 x 500
 *    ns x 20 kHz = 0.48 V per leg, and the injection's current (a few
 *    hundred mA) stays inside the VESC 6's 0.4 A transition, where the
 *    error is a resistance-like 1.2 ohm. V_h = 10 V keeps the error below
 *    5 % of the injection, the binding constraint (the noise alone would
 *    allow 4.5 V for sigma_e = 0.01 rad at B_n = 100 Hz);
 *  - ADC: a 12-bit converter over +-40 A (20 mA a count) would see the
 *    d axis's step V_h Ts / L_d = 0.33 A as 17 counts and add 5.6 mA
 *    (a count / sqrt(12)) of noise, as much again as the sensor's;
 *  - cost: the d-axis ripple +-V_h Ts / (2 L_d) = +-0.17 A, 10 V of
 *    27.7 V (v_bus / sqrt(3)) of voltage.
 * The saliency the injection sees is the incremental one: the plant's
 * saturation (sim/model/saturation.h, i_sat = 26.7 A) lowers both
 * inductances by the same factor at the operating point (L_q / L_d stays
 * near 3 at the rated 0.5 N m, about 2 A); with i_d and i_q together its
 * cross term turns the HF axis (not compensated here: docs/hf_injection.md).
 *
 * Float: the fixed-point build compiles it (mc_t) but no design uses it
 * there, as paper 002's drive.
 */
#ifndef ESTIMATORS_HF_INJECTION_H
#define ESTIMATORS_HF_INJECTION_H

#include <stdbool.h>
#include <stdint.h>

#include "adapter/phase_adapter.h"
#include "math/frame_fg.h"
#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Injection amplitude: the dead time's 0.48 V error (v_bus t_dead f_pwm
 * on the VESC 6) below 5 % of it (header). */
#define HF_INJ_VOLTAGE_V MC_C(10.0)
/* The PLL's natural frequency: 2 pi 50 Hz, B_n = 196 Hz (header: 0.007
 * rad electrical of noise at V_h = 10 V); a decade under the injection's
 * 5 kHz and over paper 002's speed loop. */
#define HF_INJ_PLL_WN_RAD_S MC_C(314.159265)
/* |g| = |1 - 2 d| below this: the delayed voltage cancels the injection
 * (d near 1/2), refused. */
#define HF_INJ_MIN_DELAY_GAIN MC_C(0.5)
/* The largest w_n Ts accepted: the discrete loop (H6), Euler-integrated
 * once per sample, stays within a few percent of the continuous one it is
 * designed as (its poles e^{-w_n Ts} against 1 - w_n Ts: 2.3 % apart at
 * 0.2); 2 pi 50 Hz at 10 kHz is 0.031. */
#define HF_INJ_MAX_WN_TS MC_C(0.2)
/* Demodulation starts this many samples after the injection starts:
 * (H3) needs three samples of the alternating voltage. */
#define HF_INJ_WARMUP_SAMPLES 3

typedef struct {
    mc_t ts_s;           /* the control period Ts */
    mc_t v_h_V;          /* V_h: the injection's amplitude */
    mc_t eps_gain_per_A; /* 1 / (g V_h Ts (1/L_d - 1/L_q) / 2) of (H4) */
    mc_t amp_gain_per_A; /* L_d / (g V_h Ts): (H1) relative to its aligned value (1 at e = 0, L_d/L_q at pi/2) */
    mc_t kp_per_s;       /* k_p = 2 zeta w_n of (H6) */
    mc_t ki_per_s;       /* k_i = w_n^2 Ts of (H6), rad/s per rad per sample */
    mc_t lead_s;         /* the output's angle advanced by (1/2 + d) Ts of speed */
    mc_t delay;          /* d: the voltage over a sample is (1 - d) u_k + d u_{k-1} */
    mc_t ts_over_Ld_A_per_V; /* Ts / L_d, Ts / L_q of (H3)'s voltage term */
    mc_t ts_over_Lq_A_per_V;
} hf_injection_config_t;

typedef struct {
    hf_injection_config_t cfg;
    mc_ab_t i1_A, i2_A;  /* i_{k-1}, i_{k-2} */
    mc_ab_t di1_A;       /* Delta i_{k-1} */
    mc_ab_t uf1_V, uf2_V, uf3_V; /* the fundamental commands of the last three steps (hf_injection_hold) */
    mc_rot_t rot_inj;    /* the direction of the last injection (estimated d axis) */
    int32_t sign;        /* s of the last output: +1 or -1 */
    int32_t n;           /* samples since the injection started (saturates) */
    bool on;             /* injecting and demodulating; off: no voltage, the PLL follows hf_injection_track */
    bool stopping;       /* switched off while on: the stop pulse (H8) is still to come */
    mc_ab_t uh1_V;       /* u_h_V of the step before the last (the delay's share of a sample, (H8)) */
    mc_ab_t r_A, r1_A, r2_A; /* (H8): the triangle's model at this sample and the two before */
    /* outputs of the last step */
    mc_t theta_e_rad;    /* electrical angle, wrapped to [-pi, pi) */
    mc_t omega_e_rad_s;  /* electrical speed */
    mc_t theta_inj_rad;  /* the electrical angle of the last injection (its d axis) */
    mc_t eps;            /* (H4), about sin 2e (0 before the warm-up) */
    mc_t theta_raw_e_rad; /* (H7): the angle this sample measures, unfiltered */
    mc_t amp;            /* (H1) relative: 1 aligned, L_d/L_q at pi/2 */
    mc_ab_t i_f_A;       /* (H5): the current without the injection */
    mc_ab_t u_h_V;       /* the injection voltage for the coming sample */
    mc_t u_h_amp_V;      /* its amplitude: V_h, V_h/2 (the first and the stop pulse) or 0 */
} hf_injection_t;

/* Derives the configuration: L_d < L_q (a salient interior machine), Ts >
 * 0, v_h_V > 0, wn_rad_s > 0 with wn Ts < HF_INJ_MAX_WN_TS (the discrete
 * loop near the continuous one), delay d in [0, 1] with |1 - 2 d| >= 1/2. False (cfg
 * untouched): any other input. */
bool hf_injection_design(hf_injection_config_t *cfg, mc_t Ld_H, mc_t Lq_H, mc_t ts_s, mc_t v_h_V, mc_t wn_rad_s,
                         mc_t delay);

/* Starts off, at the electrical angle theta_e_rad, at rest. */
void hf_injection_init(hf_injection_t *o, const hf_injection_config_t *cfg, mc_t theta_e_rad);

/* On: the next step outputs half an amplitude (so the triangle of current
 * is centred from its first period), then +-V_h. Off (while on): the next
 * step outputs the stop pulse, half an amplitude against the last (the
 * triangle back to its centre, (H8)), then no voltage; nothing is
 * demodulated from the switch on. */
void hf_injection_set_on(hf_injection_t *o, bool on);

/* Off only: the PLL's angle and speed set to another source's (the
 * observer at speed), so that switching on again starts from them. */
void hf_injection_track(hf_injection_t *o, mc_t theta_e_rad, mc_t omega_e_rad_s);

/* The fundamental voltage commanded for the coming sample (the injection
 * not included), for (H3)'s voltage term; call it after every step (0 V
 * if not). */
void hf_injection_hold(hf_injection_t *o, mc_ab_t u_f_V);

/* One sample: i_A, the measured alpha-beta current of this sample. Updates
 * i_f_A (H5, H8), and when on eps, amp, the PLL and theta_raw (H3)-(H7)
 * (off or warming up: theta_raw = theta_e), and u_h_V, the voltage to add
 * to the command for the coming sample (zero when off, but for the stop
 * pulse), its amplitude u_h_amp_V. */
void hf_injection_step(hf_injection_t *o, mc_ab_t i_A);

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_HF_INJECTION_H */
