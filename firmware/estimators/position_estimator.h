/*
 * position_estimator.h - rotor position and velocity from the back-EMF
 * estimates, paper 000 eqs. (29)-(32) and the jump counter of (71).
 *
 * (29) with the errata: n_p dtheta_est = atan2(s e_f, -s e_g), s = sgn(w_r),
 * which is right for both signs of speed; dtheta_est lies in
 * (-pi/n_p, pi/n_p]. The jump counter k of (71) follows dtheta_est across
 * the +-pi/n_p boundary, so theta_est = theta_r + dtheta_est + 2 pi k/n_p
 * is continuous. (30) with the errata factor: |w| = |e|/K. (31):
 *   dw_est = (z_g e_f - z_f e_g) / (n_p (e_f^2 + e_g^2))
 * with z the filtered equivalent injections (same L scaling on both, so it
 * cancels), and (32) w_est = w_r + dw_est.
 */
#ifndef OBSERVERS_POSITION_ESTIMATOR_H
#define OBSERVERS_POSITION_ESTIMATOR_H

#include <stdbool.h>
#include <stdint.h>

#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    int32_t n_p;
    mc_t pitch_rad;     /* 2 pi / n_p: one electrical period in mechanical rad */
    mc_t half_pitch_rad; /* set by position_estimator_init */
    mc_t inv_n_p;        /* 1/n_p, set by position_estimator_init */
    mc_t inv_K_rad_s_per_V; /* 1/K of eq. (30), |w| = |e|/K: not needed by the control */
    mc_t e2_min_V2;     /* below this |e|^2 the angle is not observable (w ~ 0) */
} position_estimator_config_t;

typedef struct {
    position_estimator_config_t cfg;
    mc_t dtheta_prev_rad;
    int32_t k;          /* jump counter of eq. (71) */
    bool valid;         /* |e|^2 >= e2_min: estimate usable */
    mc_t e2_V2;         /* |e|^2 of the last step */
    mc_t dtheta_est_rad;
    mc_t theta_est_rad;
    mc_t omega_est_rad_s;
} position_estimator_t;

void position_estimator_init(position_estimator_t *p, const position_estimator_config_t *cfg);

/* |e|^2 and observability only (what the open-loop start needs each sample). */
static inline void position_estimator_observe(position_estimator_t *p, mc_t e_f_V, mc_t e_g_V)
{
    p->e2_V2 = mc_dot2(e_f_V, e_f_V, e_g_V, e_g_V);
    p->valid = !mc_lt(p->e2_V2, p->cfg.e2_min_V2);
}

/* dtheta_est of (29) from e and the sign of omega_r, in (-pi/n_p, pi/n_p]. */
mc_t position_estimator_angle(const position_estimator_t *p, mc_t e_f_V, mc_t e_g_V, mc_t omega_r_rad_s);

/* One sample of (29) and (71) for the e of the last
 * position_estimator_observe (its |e|^2 and observability are not formed
 * again). e_*: back-EMF estimates [V]; theta_r, omega_r: the reference of
 * this sample. */
void position_estimator_track(position_estimator_t *p, mc_t e_f_V, mc_t e_g_V, mc_t theta_r_rad, mc_t omega_r_rad_s);

/* (31)-(32) for the sample of the last position_estimator_track (separate:
 * the open-loop start does not need it). z_*: filtered equivalent
 * injections [V/s]. */
void position_estimator_speed(position_estimator_t *p, mc_t e_f_V, mc_t e_g_V, mc_t z_f_V_s, mc_t z_g_V_s,
                              mc_t omega_r_rad_s);

/* Chooses the jump count k that puts theta_est closest to theta_near_rad
 * (used at the open-to-closed-loop switch) and updates theta_est. */
void position_estimator_set_branch(position_estimator_t *p, mc_t theta_r_rad, mc_t theta_near_rad);

#ifdef __cplusplus
}
#endif

#endif /* OBSERVERS_POSITION_ESTIMATOR_H */
