/*
 * emf_speed.h - paper 000's sensorless estimator as an open-start
 * estimator (estimators/open_start.h) for paper 001's speed drive: the
 * super-twisting back-EMF observer (23)-(28) in the (f-g) frame of the
 * open-loop vector, the arctan with its jump counter (29)-(32), (71) and
 * the mechanical observer (33)-(37) (estimators/fg_estimator.h). The (f-g)
 * frame is the open-loop vector's: its origin (found by paper 001's
 * standstill probe, flux_speed.h, which this estimator runs first) turned
 * by the reference each sample, as paper 000's drive turns it. The
 * estimate is trusted from |w*| >= omega_lim_rad_s on while the back-EMF
 * is observable (paper 000 section 4.2), and lost below; the law runs in
 * the estimated frame U(n_p (theta_hat - theta_r)) of (44), its voltage
 * turned back to (f-g).
 */
#ifndef ESTIMATORS_EMF_SPEED_H
#define ESTIMATORS_EMF_SPEED_H

#include <stdbool.h>

#include "estimators/estimator.h"
#include "estimators/fg_estimator.h"
#include "estimators/flux_speed.h"
#include "estimators/open_start.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    flux_speed_t fs;      /* the probe (and the flux observer's figures the status shows) */
    fg_estimator_t emf;   /* paper 000's chain */
    fg_frame_t fr;        /* this sample's (f-g) frame */
    mc_t i_f_A, i_g_A;    /* this sample's currents in it */
    mc_t omega_lim_rad_s; /* in use: cfg's or raised at run time (set_omega_lim) */
    bool probe_ran;       /* this sample was the probe's (flux_speed) */
} emf_speed_t;

extern const estimator_ops_t emf_speed_ops;

/* The configuration's own problems beyond the family's (open_start_problem). */
const char *emf_speed_problem(const void *cfg);

/* The sample's operations, in line as flux_speed.h's (estimator.h's
 * signatures; the ops table holds them too; C only, as there). */
#ifndef __cplusplus
/* One sample after the probe: the frame's front (6)-(8) at the open-loop
 * vector's angle, the observer's correction, the tracking where the angle
 * is trusted, the hand-over either way (the jump counter's branch at the
 * switch to closed loop), the mechanics (31)-(37) and the estimated frame
 * (44). */
static FLUX_SPEED_IN_LINE void emf_speed_measure_op(void *self, const open_start_in_t *in, open_start_out_t *out)
{
    emf_speed_t *o = self;
    o->probe_ran = o->fs.probing;
    if (o->probe_ran) {
        flux_speed_measure(&o->fs, in, out);
    } else {
        const open_start_config_t *c = &o->fs.cfg;
        /* read once: the profile's evaluation below writes through a pointer */
        const int32_t n_p = c->model.n_p;
        const mc_t theta_ref = in->ref.theta_rad;
        const mc_t theta_r = mc_add(theta_ref, o->fs.ol_origin_mech_rad);
        const mc_t w_r = in->ref.omega_rad_s;
        speed_point_t ahead;
        speed_profile_eval(in->profile, in->tick + 1u, &ahead);
        /* the (f-g) frame: the open-loop vector's origin turned by the reference */
        const mc_rot_t rot_k = mc_rot_compose(o->fs.ol_origin, mc_rot_from_angle(mc_elec_angle(theta_ref, n_p)));
        fg_estimator_front(&o->fr, rot_k, theta_ref, ahead.theta_rad, n_p, in->i_ab_A, &o->i_f_A, &o->i_g_A);
        fg_estimator_correct(&o->emf, o->i_f_A, o->i_g_A);
        const bool want_closed = !mc_lt(mc_abs(w_r), o->omega_lim_rad_s) && fg_estimator_observable(&o->emf);
        if (want_closed) {
            fg_estimator_track(&o->emf, theta_r, w_r);
        }
        out->switched = false;
        out->own_vector = false;
        if (want_closed != (in->sup->state == SUP_STATE_CLOSED_LOOP)) {
            out->switched = supervisor_dispatch(in->sup, want_closed ? SUP_EV_ESTIMATE_TRUSTED : SUP_EV_ESTIMATE_LOST);
            if (out->switched && want_closed) {
                fg_estimator_lock_branch(&o->emf, theta_r);
            }
        }
        const bool closed = in->sup->state == SUP_STATE_CLOSED_LOOP;
        fg_estimator_mechanics(&o->emf, &c->emf_torque_model, closed, w_r, o->i_f_A, o->i_g_A);
        out->i_d_A = o->emf.i_d_A;
        out->i_q_A = o->emf.i_q_A;
        out->omega_rad_s = o->emf.mech.omega_est_rad_s; /* fg_estimator_get's in closed loop */
        out->load_Nm = o->emf.mech.load_est_Nm;
        out->out_rot = o->fr.mid;
    }
    /* the law's (44) frame to (f-g) */
    out->law_rot = o->emf.u_est;
    out->law_turned = !o->probe_ran;
    out->omega_own_rad_s = o->emf.mech.omega_est_rad_s;
    out->theta_e_own_rad = o->emf.pos.theta_est_rad;
    out->lock_checkable = false;
}

/* Paper 000 (68): the open-loop vector along f, the frame's own axis. */
static FLUX_SPEED_IN_LINE void emf_speed_open_loop_op(const void *self, const open_start_in_t *in, mc_t v_V,
                                                      mc_t *v_d_V, mc_t *v_q_V)
{
    const emf_speed_t *o = self;
    if (o->probe_ran) {
        flux_speed_open_loop(&o->fs, in, v_V, v_d_V, v_q_V);
        return;
    }
    *v_d_V = v_V;
    *v_q_V = MC_ZERO;
}

/* The observer's prediction (paper 000 (23)-(28)) with the voltage the
 * motor sees over the sample, in the frame of the sample's middle. */
static FLUX_SPEED_IN_LINE void emf_speed_hold_op(void *self, const open_start_in_t *in, mc_ab_t u_mean_ab_V, mc_t u_d_V,
                                                 mc_t u_q_V)
{
    emf_speed_t *o = self;
    if (o->probe_ran) {
        return; /* the probe's flux observer integrates it at the next measure */
    }
    mc_t v_f = u_d_V, v_g = u_q_V;
    if (!in->frame_voltage_applied) {
        mc_rot_fwd(o->fr.mid, u_mean_ab_V.alpha, u_mean_ab_V.beta, &v_f, &v_g);
    }
    fg_estimator_predict(&o->emf, &o->fs.cfg.model, v_f, v_g, o->i_f_A, o->i_g_A, o->fr.half);
}
#endif /* !__cplusplus */

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_EMF_SPEED_H */
