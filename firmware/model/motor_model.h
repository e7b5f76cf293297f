/*
 * motor_model.h - the one motor model and the one set of limits a drive
 * believes in, shared by reference: every block that needs R, L (L_d,
 * L_q), K, Phi, n_p, J or f_v reads them from here (passed as a const
 * pointer to its step), so a parameter measured at run time (the
 * standstill R/L measurement) is changed in one place, by
 * motor_model_set_rl(). Values are the design's (design/, from one
 * motor_design_input_t, design/motor_design.h), folded with the sample
 * time where a block needs a per-sample coefficient, so the same struct
 * serves float and fixed point. Every drive's config holds one
 * (`model`): paper 000's, paper 001's, paper 002's and the sensored
 * drive's blocks read it by const pointer.
 *
 * Models (all three motors are this struct):
 *  - the 2-phase stepper (paper 000 eq. (9), errata signs) and the
 *    non-salient PMSM in the alpha-beta frame (paper 001 eq. (1)):
 *      L di/dt = v - R i - e,   e = K w [-sin; cos](n_p theta),
 *      J dw/dt = K_t i_q - f_v w - C_r,
 *    K = n_p Phi (K_V_s), L = L_H = Ld_H = Lq_H;
 *  - the interior PMSM in the rotor's d-q frame (paper 002 eqs. (2), (6),
 *    (7)): L_d di_d/dt = u_d - R i_d + L_q n_p w i_q,
 *    L_q di_q/dt = u_q - R i_q - L_d n_p w i_d - psi n_p w,
 *    J dw/dt = 3/2 n_p (psi i_q + (L_d - L_q) i_d i_q) - f_v w - M_0,
 *    with L_H = Ld_H (the scenario's L_H is L_d), psi = Phi = psi_Wb.
 * A design fills what its drive's blocks read; the fields a drive does
 * not use are still the motor's (J_kgm2 in Q14.17 is coarse for a small
 * rotor: the fixed-point blocks use inv_J and ts_over_J).
 */
#ifndef MODEL_MOTOR_MODEL_H
#define MODEL_MOTOR_MODEL_H

#include <stdint.h>

#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    int32_t n_p;              /* pole pairs (rotor teeth of a stepper) */
    int32_t fs_hz;            /* sample rate 1/Ts */
    mc_t ts_s;                /* sample time Ts */
    mc_t R_ohm;               /* phase resistance */
    mc_t L_H;                 /* phase inductance (L_d of a salient PMSM) */
    mc_t Ld_H, Lq_H;          /* d- and q-axis inductances (paper 002 (2)); both L_H when non-salient */
    mc_t psi_Wb;              /* magnet flux linkage Phi (peak, per phase): K_V_s = n_p psi */
    mc_t J_kgm2;              /* inertia J (paper 002's float blocks divide by it) */
    mc_t ts_over_L_A_per_V;   /* Ts/L: current change per volt over a sample */
    mc_t npL_ohm_s;           /* n_p L [V per (A rad/s)]: rotation of the frame times L */
    mc_t K_V_s;               /* back-EMF constant [V s/rad = N m/A] */
    mc_t fv_Nm_s;             /* viscous friction f_v [N m s/rad] */
    mc_t inv_J;               /* 1/J [rad/s^2 per N m] */
    mc_t ts_over_J;           /* Ts/J [rad/s per N m over a sample] */
    mc_t J_over_K_A_s2;       /* J/K: current per unit acceleration, paper 000 eq. (39) */
    mc_t fv_over_K_A_s;       /* f_v/K: current per unit speed, eq. (39) */
    mc_t LJ_over_KTs_V_s2;    /* L J/(K Ts): L di_g,r/dt per change of theta_r'' over a sample */
    mc_t Lfv_over_KTs_V_s;    /* L f_v/(K Ts): the same per change of theta_r' */
} motor_model_t;

/* What the power stage and the motor allow. */
typedef struct {
    mc_t v_max_V;             /* largest phase voltage (supply) */
    mc_t i_max_A;             /* current limit of the references and the open-loop start */
    mc_t i_trip_A;            /* over-current trip on any measured phase, >= i_max_A */
    mc_t omega_lim_rad_s;     /* speed above which the estimates are trusted (paper 000 section 4.2) */
} drive_limits_t;

/* Replaces R and L (given as L/Ts [ohm]) and every coefficient derived
 * from them, with the same operations the design would have rounded.
 * Ld_H, Lq_H and psi_Wb stay the design's: the drive that measures at run
 * time (paper 000's) reads L_H and K_V_s, and the drive that reads them
 * (paper 002's) measures nothing. */
void motor_model_set_rl(motor_model_t *m, mc_t R_ohm, mc_t L_fs_ohm);

/* Replaces K by a measured K_V_s (startup/k_identification.h) and rescales
 * everything the model folded K into: J/K, f_v/K, L J/(K Ts), L f_v/(K Ts)
 * by K_old/K_new (a ratio near 1: no range issue in fixed point). */
void motor_model_set_K(motor_model_t *m, mc_t K_V_s);

#ifdef __cplusplus
}
#endif

#endif /* MODEL_MOTOR_MODEL_H */
