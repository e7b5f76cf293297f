/*
 * rl_identification.h - phase resistance and inductance from the first
 * open-loop samples at standstill (not in paper 000).
 *
 * Why: at the open-to-closed switch the open-loop current (I_max = 3 A)
 * flows in the f axis while the back-EMF is only K*omega_lim = 0.8 V, so a
 * resistance error dR or an inductance error dL puts dR*I or n_p*omega*dL*I
 * volts across the back-EMF estimate: 5 % of R already turns it by tens of
 * electrical degrees and the drive slips poles. Measured as part of the
 * start, R and L make the switch robust.
 *
 * How: the open-loop start applies a constant voltage along the reference
 * angle while the rotor is held (eq. (68) at omega_ref ~ 0). Over a window
 * of N samples from the first one, with i_0 the first sample and i_N the
 * mean of the last N_s samples (steady state),
 *   R   = mean(v) / mean(i)                over the last N_s samples,
 *   L   = integral of (v - R i) dt / (i_N - i_0)   (no differentiation of
 *         the noisy current; the integral uses the trapezoid rule).
 * Results outside [1/2, 2] times the model values are rejected.
 * Values are in the (f-g) frame; only the f axis carries the excitation.
 */
#ifndef STARTUP_RL_IDENTIFICATION_H
#define STARTUP_RL_IDENTIFICATION_H

#include <stdbool.h>
#include <stdint.h>

#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    RL_ID_OFF = 0,      /* disabled by configuration */
    RL_ID_RUNNING = 1,
    RL_ID_DONE = 2,     /* r_ohm / l_fs_ohm hold the measured values */
    RL_ID_REJECTED = 3  /* excitation moved or results implausible: model kept */
} rl_id_state_t;

typedef struct {
    int32_t window_ticks;     /* N: whole window, 0 disables */
    int32_t steady_ticks;     /* N_s: steady-state tail of the window, < N */
    mc_t R_model_ohm;         /* plausibility reference */
    mc_t L_fs_model_ohm;      /* L / Ts of the model [ohm] */
    mc_t omega_still_rad_s;   /* reference speed above which the rotor is not "held" */
} rl_id_config_t;

typedef struct {
    rl_id_config_t cfg;
    rl_id_state_t state;
    int32_t k;
    mc_t i0_A;                /* first sample */
    mc_t mean_v_V, mean_i_A;  /* over the whole window */
    mc_t ss_v_V, ss_i_A;      /* over the steady tail */
    mc_t res[4];              /* rounding residuals of the four means (error feedback) */
    mc_t R_ohm;               /* result */
    mc_t L_fs_ohm;            /* result L/Ts (= L * fs) */
} rl_id_t;

void rl_id_init(rl_id_t *id, const rl_id_config_t *cfg);

/* One sample: i_f [A] measured now, v_f [V] applied over the coming
 * sample, omega_ref of the start. Returns true on the sample where the
 * identification completes (state DONE or REJECTED). */
bool rl_id_step(rl_id_t *id, mc_t i_f_A, mc_t v_f_V, mc_t omega_ref_rad_s);

#ifdef __cplusplus
}
#endif

#endif /* STARTUP_RL_IDENTIFICATION_H */
