/*
 * motor_model.h - the one motor model and the one set of limits a drive
 * believes in, shared by reference: every block that needs R, L, K, J or
 * f_v reads them from here (passed as a const pointer to its step), so a
 * parameter measured at run time (the standstill R/L measurement) is
 * changed in one place, by motor_model_set_rl(). Values are the design's
 * (design/), folded with the sample time where a block needs a
 * per-sample coefficient, so the same struct serves float and fixed point.
 *
 * Model (paper 000 eq. (9), errata signs; per phase of a 2-phase stepper or
 * in the alpha-beta frame of a 3-phase PMSM):
 *   L di/dt = v - R i - e,   e = K w [-sin; cos](n_p theta),
 *   J dw/dt = K i_q - f_v w - C_r.
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
    mc_t R_ohm;               /* phase resistance */
    mc_t L_H;                 /* phase inductance */
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
 * from them, with the same operations the design would have rounded. */
void motor_model_set_rl(motor_model_t *m, mc_t R_ohm, mc_t L_fs_ohm);

/* Replaces K by a measured K_V_s (startup/k_identification.h) and rescales
 * everything the model folded K into: J/K, f_v/K, L J/(K Ts), L f_v/(K Ts)
 * by K_old/K_new (a ratio near 1: no range issue in fixed point). */
void motor_model_set_K(motor_model_t *m, mc_t K_V_s);

#ifdef __cplusplus
}
#endif

#endif /* MODEL_MOTOR_MODEL_H */
