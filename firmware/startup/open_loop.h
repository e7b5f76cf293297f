/*
 * open_loop.h - the open-loop low-speed drive of paper 000, eq. (68)
 * (errata reading): below |omega_lim| the motor is driven like a stepper,
 *   v = min(V_max, sqrt((R^2 + (n_p omega_ref L)^2) I_max^2 + (K omega_ref)^2))
 * applied along the reference electrical angle (v_f = v, v_g = 0), i.e.
 * v_a = v cos(n_p theta_ref), v_b = v sin(n_p theta_ref).
 */
#ifndef STARTUP_OPEN_LOOP_H
#define STARTUP_OPEN_LOOP_H

#include "math/mc_num.h"
#include "model/motor_model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* R, n_p L and K come from the shared model (model/motor_model.h). */
typedef struct {
    mc_t i_max_A;    /* current amplitude of the start (I_max of (68), or a lower open-loop current) */
    mc_t v_max_V;
} open_loop_config_t;

/* Voltage magnitude of eq. (68) for the reference speed [V]. */
mc_t open_loop_voltage(const open_loop_config_t *c, const motor_model_t *m, mc_t omega_ref_rad_s);

#ifdef __cplusplus
}
#endif

#endif /* STARTUP_OPEN_LOOP_H */
