/*
 * load_angle.h - current-vector (load-angle) control of a stepper in the
 * reference's (f-g) frame: an alternative to paper 000's super-twisting
 * current and twisting position laws (46)-(54) that holds load steps the
 * estimation chain is too slow for (docs/paper000.md, "Load steps").
 *
 * A current vector of constant amplitude I_s is held in the frame of the
 * reference angle n_p theta_r (eq. (6)); its angle delta ahead of the
 * f axis is the load angle, set from the torque the reference needs:
 *   i_g,r = (J theta_r'' + f_v theta_r' + C_r-hat)/K - (J/K) k_d (w-hat - w_r)
 *   i_f,r = sqrt(I_s^2 - i_g,r^2)
 * With the rotor dtheta = theta - theta_r off the reference, the torque of
 * (9c) (errata sign) is K (i_g,r cos(n_p dtheta) - i_f,r sin(n_p dtheta)):
 * i_f,r is a magnetic spring of stiffness n_p K i_f,r that answers a load
 * step within the current loop's time, with no estimate at all; the
 * estimates only centre it (the observed load C_r of (35), fed forward)
 * and damp it (the observed speed of (35), k_d). Without an estimate (the
 * open-loop range below omega_lim) the last observed load is held and the
 * damping is off: the law is then an I/f drive with a load angle.
 *
 * The currents follow their references with a PI in the (f-g) frame on the
 * feed-forward of the reference model (38) (the back-EMF K w_r on g, as if
 * the rotor were on the reference; the PI's integral takes the rest). At
 * speed the spring current is cut to what v_limit_V drives in steady state
 * (n_p L w_r I_s alone can exceed the supply), the torque current first.
 * Fixed point: every intermediate stays within a few hundred for currents
 * of amperes and voltages of tens of volts (the voltage cut divides by
 * R^2 + (n_p L w_r)^2 before it squares).
 * Units: A, V, rad, s. No state outside the struct, no allocation.
 */
#ifndef CONTROL_LOAD_ANGLE_H
#define CONTROL_LOAD_ANGLE_H

#include <stdbool.h>

#include "math/mc_num.h"
#include "model/motor_model.h"
#include "trajectory/trajectory.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    mc_t i_s_A;              /* current vector amplitude I_s [A] (> 0) */
    mc_t i_g_max_A;          /* |i_g,r| cap below I_s, so that some spring i_f,r is always left [A] */
    mc_t damp_A_s_per_rad;   /* (J/K) k_d: i_g,r per rad/s of observed speed error [A s/rad] */
    mc_t load_ff_max_Nm;     /* the observed load is fed forward up to this [N m] */
    mc_t load_slew_Nm;       /* ... and moves by at most this per sample [N m] */
    mc_t L_over_KTs_V_per_Nm;/* L/(K Ts): the voltage of a fed-forward load change per sample [V/(N m)] */
    mc_t kp_ohm;             /* PI proportional gain [V/A] */
    mc_t ki_ohm;             /* PI integral gain per sample [V/A] */
    mc_t i_amp_slew_A;       /* after load_angle_start, the amplitude moves to I_s by this per sample [A] */
    mc_t v_limit_V;          /* i_f,r no larger than this voltage drives in steady state; 0: off */
} load_angle_config_t;

typedef struct {
    load_angle_config_t cfg;
    mc_t int_f_V, int_g_V;   /* PI integrals [V] */
    mc_t load_Nm;            /* the load fed forward at the last step with an estimate (held without one) */
    mc_t i_amp_A;            /* current vector amplitude in use: I_s, or on its way there after a start */
    mc_t i_f_ref_A, i_g_ref_A; /* references of the last step */
} load_angle_t;

void load_angle_init(load_angle_t *c, const load_angle_config_t *cfg);

/* Hand-over from another law (the open loop (68) of the R, L measurement):
 * the amplitude starts at the current's i_A [A], so that the voltage does
 * not step, and moves to I_s at i_amp_slew_A per sample; the PI restarts. */
void load_angle_start(load_angle_t *c, mc_t i_A);

/* One sample. r: the reference at this sample; i_f_A, i_g_A: the measured
 * (or, with a computation delay, predicted) currents in the reference's
 * (f-g) frame; has_estimate: the observed speed and load below are valid
 * (closed loop), else the last load is held and the damping is off;
 * hold_integral: the last command saturated (anti-windup). Writes the
 * (f-g) voltage. */
void load_angle_step(load_angle_t *c, const motor_model_t *m, const trajectory_point_t *r, mc_t i_f_A, mc_t i_g_A,
                     bool has_estimate, mc_t omega_est_rad_s, mc_t load_est_Nm, bool hold_integral, mc_t *v_f_V,
                     mc_t *v_g_V);

#ifdef __cplusplus
}
#endif

#endif /* CONTROL_LOAD_ANGLE_H */
