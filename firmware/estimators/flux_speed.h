/*
 * flux_speed.h - paper 001's sensorless estimator as an open-start
 * estimator (estimators/open_start.h): the gradient flux observer
 * (12)-(14) (estimators/flux_observer.h), its resistance tracked on line
 * (estimators/resistance_tracker.h), and the I&I speed and load observer
 * (15)-(16) on its angle (estimators/speed_load_observer.h). The angle is
 * unknown at power-up: a probe at standstill (a short arc's
 * through-origin circle fit) corrects the observer and finds the
 * direction the open-loop vector starts in; the open loop then turns the
 * rotor until the flux estimate has swept handover_sweep_rad, when the
 * circle fit of the swept arc (startup/flux_circle_fit.h) removes the
 * observer's initial error and the estimate is trusted. The probe's
 * direction: along alpha, then along the arc's chord, ahead of the rotor in
 * its direction of motion for either of the mirror-image angles.
 */
#ifndef ESTIMATORS_FLUX_SPEED_H
#define ESTIMATORS_FLUX_SPEED_H

#include <stdbool.h>

#include "estimators/estimator.h"
#include "estimators/open_start.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    open_start_config_t cfg;
    flux_observer_t flux;
    resistance_tracker_t rtrack; /* cfg.rtrack.enabled: the R the flux observer subtracts */
    speed_load_observer_t speed;
    flux_circle_fit_t fit;
    flux_circle_fit_t probe; /* points FLUX_SPEED_PROBE_POINT_SCALE (rho - probe_anchor) */
    mc_ab_t probe_anchor;    /* rho_hat when the probe starts */
    mc_ab_t probe_last;      /* the last point offered to the probe's fit */
    bool probing;            /* the probe runs (the first samples of the open loop) */
    bool probe_sample;       /* the probe ran in this sample: its vector is the open loop's */
    bool probe_turned;       /* the probe's vector has turned to the arc's direction */
    mc_rot_t probe_dir;      /* the probe's vector direction */
    mc_rot_t ol_origin;      /* open-loop vector angle minus the reference angle (electrical) */
    mc_t ol_theta0_rad;      /* reference angle when the open-loop turn starts */
    mc_t ol_origin_mech_rad; /* ol_origin as a mechanical angle */
} flux_speed_t;

extern const estimator_ops_t flux_speed_ops;

/* Below this lead the output angle is not advanced: 1e-6 rad is far below
 * anything the drive resolves, and sin/cos of smaller angles would make
 * subnormal intermediates (x^3) in the float build at standstill. */
#define FLUX_SPEED_ADVANCE_MIN_RAD MC_C(1e-6)

/* The angle the voltage of (11) is turned to alpha-beta with: the estimate
 * rho advanced by w_hat n_p (1/2 + d) Ts, the angle the rotor has on
 * average while the voltage acts (held over the sample, d samples of
 * computation delay). Without it the voltage lags the rotor by half a
 * sample and more. */
static inline mc_rot_t flux_speed_output_rot(const open_start_config_t *c, mc_rot_t rho, mc_t omega_hat_rad_s)
{
    const mc_t adv = mc_div_i(mc_mul(omega_hat_rad_s, c->advance_np), c->model.fs_hz);
    if (mc_lt(mc_abs(adv), FLUX_SPEED_ADVANCE_MIN_RAD)) {
        return rho;
    }
    return mc_rot_compose(rho, mc_rot_from_angle(adv));
}

/* The sample's operations are in line here: a drive's step, instantiated
 * per estimator (estimator_registry.h, OPEN_START_ESTIMATORS), runs them
 * without a call, as it did when they were its own code (the control
 * step's cost: issue 43). */
#if defined(__GNUC__)
#define FLUX_SPEED_IN_LINE inline __attribute__((always_inline))
#else
#define FLUX_SPEED_IN_LINE inline
#endif

/* Resets every state (emf_speed.h's too: its probe is this estimator's);
 * false: cfg refused (open_start_problem names it). */
bool flux_speed_init(flux_speed_t *o, const open_start_config_t *cfg);
/* The start-up probe's sample, out of line: it runs only at start. */
void flux_speed_probe(flux_speed_t *o, const open_start_in_t *in);

/* In open loop after the probe: the swept arc's circle fit, and once the
 * reference has turned handover_sweep_rad, the observer corrected by the
 * fit's centre, its gradient on, the I&I observer started at the estimate
 * and w*, and the estimate trusted. Returns whether the loop closed. */
static FLUX_SPEED_IN_LINE bool flux_speed_handover(flux_speed_t *o, const open_start_in_t *in)
{
    const open_start_config_t *c = &o->cfg;
    flux_circle_fit_add(&o->fit, o->flux.rho);
    const mc_t swept = mc_mul_i(mc_abs(mc_sub(in->ref.theta_rad, o->ol_theta0_rad)), c->model.n_p);
    mc_ab_t centre;
    if (mc_lt(swept, c->handover_sweep_rad) || !flux_circle_fit_center(&o->fit, &centre)) {
        return false;
    }
    flux_observer_shift(&o->flux, centre);
    resistance_tracker_unprime(&o->rtrack); /* the angle jumped */
    flux_observer_set_gradient(&o->flux, true);
    speed_load_observer_init(&o->speed, &c->speed, o->flux.unit, in->ref.omega_rad_s, MC_ZERO);
    return supervisor_dispatch(in->sup, SUP_EV_ESTIMATE_TRUSTED);
}

/* One sample: the flux observer (12)-(14) integrates the voltage held over
 * the last sample, the R it subtracts tracked from the q-axis voltage
 * balance of that sample (closed loop only); in open loop the probe, or the
 * fit and the hand-over; the current in the estimated dq frame rho (its q
 * component is the i^T Jm rho of the I&I observer) and the speed and load
 * observer (15)-(16). */
static FLUX_SPEED_IN_LINE void flux_speed_measure(flux_speed_t *o, const open_start_in_t *in, open_start_out_t *out)
{
    const mc_ab_t i_ab = in->i_ab_A;
    flux_observer_hold(&o->flux, in->u_held_ab_V);
    flux_observer_step(&o->flux, i_ab);
    if (o->rtrack.cfg.enabled) {
        resistance_tracker_step(&o->rtrack, in->u_held_ab_V, i_ab, o->flux.unit, o->speed.omega_rad_s,
                                in->sup->state == SUP_STATE_CLOSED_LOOP);
        flux_observer_set_R(&o->flux, o->rtrack.R_ohm);
        flux_observer_set_target(&o->flux, mc_mul(o->rtrack.Phi_rel, o->rtrack.Phi_rel)); /* |eta| -> Phi_hat */
    }
    const bool open = in->sup->state == SUP_STATE_OPEN_LOOP;
    o->probe_sample = o->probing && open;
    out->switched = false;
    out->own_vector = o->probe_sample;
    if (o->probe_sample) {
        flux_speed_probe(o, in);
    } else if (open) {
        out->switched = flux_speed_handover(o, in);
    }
    const mc_rot_t rho = o->flux.unit;
    mc_rot_fwd(rho, i_ab.alpha, i_ab.beta, &out->i_d_A, &out->i_q_A);
    speed_load_observer_step_iq(&o->speed, rho, out->i_q_A);
    out->law_turned = false;
    out->omega_rad_s = o->speed.omega_rad_s;
    out->load_Nm = o->speed.load_Nm;
    out->out_rot =
        (in->sup->state == SUP_STATE_CLOSED_LOOP) ? flux_speed_output_rot(&o->cfg, rho, o->speed.omega_rad_s) : rho;
    out->omega_own_rad_s = o->speed.omega_rad_s;
    out->theta_e_own_rad = o->speed.unwrap.e_rad;
    out->lock_checkable = true;
    out->rho2 = o->flux.rho2;
    out->rho2_target = o->flux.rho2_target;
}

static FLUX_SPEED_IN_LINE mc_rot_t flux_speed_open_loop_rot(const flux_speed_t *o, const open_start_in_t *in)
{
    return mc_rot_compose(o->ol_origin, mc_rot_from_angle(mc_elec_angle(in->ref.theta_rad, o->cfg.model.n_p)));
}

/* The open-loop vector (paper 000 (68), its magnitude v_V the drive's)
 * along the reference angle, or the probe's, expressed in the estimated
 * frame rho. */
static FLUX_SPEED_IN_LINE void flux_speed_open_loop(const flux_speed_t *o, const open_start_in_t *in, mc_t v_V,
                                                    mc_t *v_d_V, mc_t *v_q_V)
{
    mc_t v = v_V;
    mc_rot_t ol = o->probe_dir;
    if (o->probe_sample) {
        v = o->cfg.probe_v_V;
    } else {
        ol = flux_speed_open_loop_rot(o, in);
    }
    mc_rot_fwd(o->flux.unit, mc_mul(v, ol.c), mc_mul(v, ol.s), v_d_V, v_q_V);
}

/* The operations the drive's step calls (estimator.h's signatures; the
 * ops table holds them too), in line: see OPEN_START_ESTIMATORS. C only:
 * the drives' steps are C, and C converts self without a cast. */
#ifndef __cplusplus
static FLUX_SPEED_IN_LINE void flux_speed_measure_op(void *self, const open_start_in_t *in, open_start_out_t *out)
{
    flux_speed_t *o = self;
    flux_speed_measure(o, in, out);
}
static FLUX_SPEED_IN_LINE void flux_speed_open_loop_op(const void *self, const open_start_in_t *in, mc_t v_V,
                                                       mc_t *v_d_V, mc_t *v_q_V)
{
    const flux_speed_t *o = self;
    flux_speed_open_loop(o, in, v_V, v_d_V, v_q_V);
}
static FLUX_SPEED_IN_LINE void flux_speed_hold_op(void *self, const open_start_in_t *in, mc_ab_t u_mean_ab_V,
                                                  mc_t u_d_V, mc_t u_q_V)
{
    (void)self; /* the next measure integrates in->u_held_ab_V */
    (void)in;
    (void)u_mean_ab_V;
    (void)u_d_V;
    (void)u_q_V;
}
#endif /* !__cplusplus */

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_FLUX_SPEED_H */
