/*
 * fg_estimator.h - paper 000's estimator: position, speed, acceleration and
 * load from the measured currents in the (f-g) frame of the reference,
 * composed of the super-twisting back-EMF observer (eqs. (23)-(28),
 * emf_observer.h), the arctan and jump counter (29)-(32), (71)
 * (position_estimator.h) and the mechanical observer (33)-(37)
 * (mech_observer.h). One mc_estimate_t out (estimate.h).
 *
 * Per sample, in this order (the drive's recipe calls them; paper 000's
 * position drive and paper 001's speed drive with its BACK_EMF estimator
 * both run exactly this, the drive deciding only when the loop is closed
 * and with which voltage):
 *   fg_estimator_schedule   the observer's gain at the reference speed (discrete-time design)
 *   fg_estimator_front      the (f-g) frame of the sample (6)-(8) and the measured currents in it (6)
 *   fg_estimator_correct    measured (f-g) currents: observer correction, observability
 *   fg_estimator_track      (29), (71) where the angle is used (closed loop, the switch)
 *   fg_estimator_lock_branch at the open-to-closed switch: the branch nearest the reference
 *   fg_estimator_mechanics  (31)-(32) in closed loop, the estimated frame (44), (33)-(37)
 *   fg_estimator_predict    observer prediction with the voltage applied over the sample
 *                           (the command in (f-g), or the applied alpha-beta voltage turned
 *                           into the frame's middle, f.mid: the drive knows which)
 * The frame's rotation at the sample, rot_k, is the drive's: paper 000
 * turns it by composition and recomputes it every 32 samples, paper 001
 * composes the open-loop vector's origin with the reference's angle.
 */
#ifndef ESTIMATORS_FG_ESTIMATOR_H
#define ESTIMATORS_FG_ESTIMATOR_H

#include <stdbool.h>

#include "adapter/phase_adapter.h"
#include "estimators/emf_observer.h"
#include "estimators/estimate.h"
#include "estimators/mech_observer.h"
#include "estimators/position_estimator.h"
#include "math/frame_fg.h"
#include "model/motor_model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    emf_observer_config_t emf;
    position_estimator_config_t pos;
    mech_observer_config_t mech;
} fg_estimator_config_t;

/* The (f-g) frame of one sample, paper 000 (6)-(8): the reference's
 * electrical rotation at the sample, its turn over half the sample and the
 * frame at the sample's middle (where the voltage held over the sample
 * averages). */
typedef struct {
    mc_rot_t k;            /* U(n_p theta_r[k]) */
    mc_rot_t half;         /* U(n_p (theta_r[k+1] - theta_r[k]) / 2) */
    mc_rot_t mid;          /* k turned by half */
} fg_frame_t;

typedef struct {
    emf_observer_t emf;
    position_estimator_t pos;
    mech_observer_t mech;
    mc_rot_t u_est;        /* U(n_p (theta_est - theta_r)) of (44) */
    mc_t i_d_A, i_q_A;     /* measured currents in the estimated rotor frame, (44) (a drive with a
                            * computation delay replaces them by their prediction for its law) */
} fg_estimator_t;

void fg_estimator_init(fg_estimator_t *e, const fg_estimator_config_t *cfg);

/* The front of the sample: the frame (6)-(8) of rot_k = U(n_p theta_r[k])
 * turned over the sample to theta_r[k+1], and the measured alpha-beta
 * currents in it, eq. (6). The correction (fg_estimator_correct) follows;
 * paper 000's alignment uses the frame and the currents alone. */
static inline void fg_estimator_front(fg_frame_t *f, mc_rot_t rot_k, mc_t theta_r_rad, mc_t theta_r_next_rad, int32_t n_p,
                                      mc_ab_t i_ab, mc_t *i_f_A, mc_t *i_g_A)
{
    /* n_p (theta_r[k+1] - theta_r[k]): exact (difference, then an integer
     * multiple), small, so no wrap */
    const mc_t dphi = mc_mul_i(mc_sub(theta_r_next_rad, theta_r_rad), n_p);
    f->k = rot_k;
    f->half = mc_rot_from_angle(mc_div_i(dphi, 2));
    f->mid = mc_rot_compose(rot_k, f->half);
    mc_rot_fwd(rot_k, i_ab.alpha, i_ab.beta, i_f_A, i_g_A); /* eq. (6) */
}

/* The observer's injection amplitude for the reference speed of this
 * sample (the discrete-time design; nothing with constant gains). */
static inline void fg_estimator_schedule(fg_estimator_t *e, mc_t omega_r_rad_s)
{
    emf_observer_schedule(&e->emf, mc_abs(omega_r_rad_s));
}

/* Observer correction (25) with the measured (f-g) currents [A], and the
 * observability test of the back-EMF. */
static inline void fg_estimator_correct(fg_estimator_t *e, mc_t i_f_A, mc_t i_g_A)
{
    emf_observer_correct(&e->emf, i_f_A, i_g_A);
    /* (29) and (71) only where they are used: in closed loop and at the
     * switch (the branch is chosen there); here only observability */
    position_estimator_observe(&e->pos, e->emf.e_f_hat_V, e->emf.e_g_hat_V);
}

/* The back-EMF is large enough for (29) to give an angle. */
static inline bool fg_estimator_observable(const fg_estimator_t *e) { return e->pos.valid; }

/* (29) and (71) for the reference theta_r, omega_r of this sample, on the
 * back-EMF whose |e|^2 and observability fg_estimator_correct formed. */
static inline void fg_estimator_track(fg_estimator_t *e, mc_t theta_r_rad, mc_t omega_r_rad_s)
{
    position_estimator_track(&e->pos, e->emf.e_f_hat_V, e->emf.e_g_hat_V, theta_r_rad, omega_r_rad_s);
}

/* At the open-to-closed switch: in open loop the rotor sits on the
 * reference, so the jump count is the one nearest theta_r. */
static inline void fg_estimator_lock_branch(fg_estimator_t *e, mc_t theta_r_rad)
{
    position_estimator_set_branch(&e->pos, theta_r_rad, theta_r_rad);
}

/* Speed (31)-(32) (closed loop only), the estimated frame and currents
 * (44), and the mechanical observer (33)-(37), whose speed input is (32)
 * in closed loop and the reference speed in open loop (the rotor follows
 * it). i_f, i_g: the measured currents of this sample. */
static inline void fg_estimator_mechanics(fg_estimator_t *e, const motor_model_t *m, bool closed, mc_t omega_r_rad_s, mc_t i_f_A,
                            mc_t i_g_A)
{
    if (closed) {
        position_estimator_speed(&e->pos, e->emf.e_f_hat_V, e->emf.e_g_hat_V, e->emf.z_f_V_s, e->emf.z_g_V_s,
                                 omega_r_rad_s);
    }
    /* U(n_p (theta_est - theta_r)) of (44): n_p dtheta_est is the arctan of
     * (29) and the jump count adds whole turns, so its sine and cosine are
     * the normalised arguments of that arctan (no sincos needed). Before the
     * back-EMF is observable: the reference frame. */
    if (e->pos.valid) {
        const mc_t inv_e = mc_rsqrt(e->pos.e2_V2);
        const bool neg = mc_lt(omega_r_rad_s, MC_ZERO);
        e->u_est.s = mc_mul(neg ? mc_neg(e->emf.e_f_hat_V) : e->emf.e_f_hat_V, inv_e);
        e->u_est.c = mc_mul(neg ? e->emf.e_g_hat_V : mc_neg(e->emf.e_g_hat_V), inv_e);
        mc_rot_fwd(e->u_est, i_f_A, i_g_A, &e->i_d_A, &e->i_q_A); /* (44) */
    } else {
        /* the identity, exactly (c x1 + s x2 = x1 for c = 1, s = 0), for free */
        e->u_est.s = MC_ZERO;
        e->u_est.c = MC_ONE;
        e->i_d_A = i_f_A;
        e->i_q_A = i_g_A;
    }
    /* (33)-(37): in closed loop on the (32) estimate; in open loop the
     * rotor follows the reference, so theta_r' serves as the measurement */
    mech_observer_step(&e->mech, m, closed ? e->pos.omega_est_rad_s : omega_r_rad_s, e->i_q_A);
}

/* Observer prediction to the next sample (see emf_observer_predict). */
static inline void fg_estimator_predict(fg_estimator_t *e, const motor_model_t *m, mc_t v_f_V, mc_t v_g_V,
                                        mc_t i_f_A, mc_t i_g_A, mc_rot_t half)
{
    emf_observer_predict(&e->emf, m, v_f_V, v_g_V, i_f_A, i_g_A, half);
}

/* The estimate of this sample. In open loop the rotor follows the
 * reference (paper 000 Fig. 7), so the reference is reported. */
static inline void fg_estimator_get(const fg_estimator_t *e, bool closed, mc_t theta_r_rad, mc_t omega_r_rad_s,
                      mc_t accel_r_rad_s2, mc_estimate_t *out)
{
    out->theta_rad = closed ? e->pos.theta_est_rad : theta_r_rad;
    out->omega_rad_s = closed ? e->mech.omega_est_rad_s : omega_r_rad_s;
    out->accel_rad_s2 = closed ? e->mech.accel_est_rad_s2 : accel_r_rad_s2;
    out->load_Nm = e->mech.load_est_Nm;
    out->valid = e->pos.valid;
}

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_FG_ESTIMATOR_H */
