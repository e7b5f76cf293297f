/*
 * k_identification.h - the back-EMF constant K measured in closed loop
 * (not in paper 000; it completes the standstill R, L measurement of
 * rl_identification.h, which K cannot be had from).
 *
 * Why: the position drive folds K into its references, observers and gains
 * (J/K and f_v/K of (39), 1/K of (30), K w of (28), the twisting gains
 * J L/K); a plant whose K differs from the model's by more than about 12 %
 * loses its reference mid-move (tools/sweep.py, README: with R, L +-20 %
 * and J x0.5-2 the experiment passes 99 % of runs with K within +-10 %,
 * 52 % with K +-20 %).
 *
 * How: in closed loop the rotor tracks the reference within 0.015 rad, so
 * its speed is the reference's, and the back-EMF magnitude the observer
 * estimates is |e| = K |w_r| (eq. (23): d = (K/L) w (sin, -cos)(n_p dtheta),
 * e_hat = L d_hat). Least squares over the samples with |w_r| >= w_min
 * (well above the observability floor), with x = |w_r| / w_scale <= 1:
 *   K w_scale = mean(|e| x) / mean(x^2),
 * running means (no sum leaves the fixed-point range), one sample in
 * K_ID_DECIMATION. The open loop is no place for it: there the rotor
 * swings about the reference and the estimate was 15 % off (README).
 * Offline on recorded runs this gave K within 0.3 % after 0.28 s of closed
 * loop (nominal, and a plant with K x1.15). Accepted within [1/2, 2] times
 * the model's K once n_window samples are in; applied once, and only when
 * it differs from the model's by more than the deadband (a change of the
 * gains within the measurement's own spread would only perturb the run).
 */
#ifndef STARTUP_K_IDENTIFICATION_H
#define STARTUP_K_IDENTIFICATION_H

#include <stdbool.h>
#include <stdint.h>

#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One sample in four enters the means: K is a constant, and the back-EMF
 * estimate moves little in 0.4 ms. A power of two. */
#define K_ID_DECIMATION 4u

typedef enum {
    K_ID_OFF = 0,
    K_ID_RUNNING = 1,
    K_ID_DONE = 2,       /* K_V_s holds the measurement (applied) */
    K_ID_REJECTED = 3,   /* implausible: the model's K kept */
    K_ID_KEPT = 4        /* within the deadband of the model's K: the model kept */
} k_id_state_t;

typedef struct {
    bool enabled;
    mc_t w_min_rad_s;       /* |w_r| from which a sample counts */
    mc_t inv_w_scale_s;     /* 1/w_scale, w_scale >= the largest |w_r| */
    int32_t n_window;       /* samples (decimated) for the result */
    mc_t K_model_V_s;       /* plausibility reference */
    mc_t deadband;          /* |K/K_model - 1| below it: the model is kept (state KEPT) */
} k_id_config_t;

typedef struct {
    k_id_config_t cfg;
    k_id_state_t state;
    int32_t n;
    mc_t m_ex_V;            /* running mean of |e| x [V] */
    mc_t m_x2;              /* running mean of x^2 */
    mc_t K_V_s;             /* result */
} k_id_t;

void k_id_init(k_id_t *k, const k_id_config_t *cfg);

/* One closed-loop sample (call on every K_ID_DECIMATION-th): |e_hat|^2
 * [V^2] and the reference speed. Returns true on the sample the result is
 * ready (state DONE or REJECTED from then on). */
bool k_id_step(k_id_t *k, mc_t e2_V2, mc_t omega_ref_rad_s);

#ifdef __cplusplus
}
#endif

#endif /* STARTUP_K_IDENTIFICATION_H */
