/*
 * foc_current.h - the field-oriented current loops in the rotor's d-q
 * frame: one PI per axis (control/pi_ctrl.h) with the PMSM's cross-coupling
 * and back-EMF fed forward, and the voltage limited to a circle, d first.
 *
 * The PMSM's voltage equations in d-q (paper 002 eq. (1); L_d = L_q for a
 * surface motor, paper 001 eq. (1)):
 *   v_d = R i_d + L_d di_d/dt - w_e L_q i_q
 *   v_q = R i_q + L_q di_q/dt + w_e (L_d i_d + psi)
 * The coupling terms are fed forward from the measured currents and the
 * electrical speed w_e (decoupling), so each PI sees R + L s alone:
 *   v_d = PI_d(i_d* - i_d) - w_e L_q i_q          |v_d| <= u_max
 *   v_q = PI_q(i_q* - i_q) + w_e (L_d i_d + psi)  |v_q| <= sqrt(u_max^2 - v_d^2)
 * The d axis is served first (it holds the flux); both PIs integrate
 * conditionally at their limit. Fixed point: Q14.17 volts and amperes;
 * w_e L i and w_e psi stay within the supply's range for any speed the
 * supply can drive. L_d, L_q and psi are the drive's one motor model
 * (model/motor_model.h), read by const pointer.
 */
#ifndef CONTROL_FOC_CURRENT_H
#define CONTROL_FOC_CURRENT_H

#include <stdbool.h>

#include "control/pi_ctrl.h"
#include "math/mc_num.h"
#include "model/motor_model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    pi_ctrl_config_t pi_d, pi_q;  /* [V/A], [V/(A sample)] */
} foc_current_config_t;

typedef struct {
    foc_current_config_t cfg;
    pi_ctrl_t d, q;
    mc_t v_d_V, v_q_V;            /* the last step's output */
    bool saturated;               /* the last output was at the circle */
} foc_current_t;

/* Copies cfg, the integrals at 0. False for non-positive inductances, a
 * negative flux (of the motor m) or a negative gain. */
bool foc_current_init(foc_current_t *c, const foc_current_config_t *cfg, const motor_model_t *m);

/* One sample: the references and measured currents [A], the electrical
 * speed w_e [rad/s], the circle's radius u_max [V]; the voltages out in
 * c->v_d_V, c->v_q_V. */
void foc_current_step(foc_current_t *c, const motor_model_t *m, mc_t i_d_ref_A, mc_t i_q_ref_A, mc_t i_d_A,
                      mc_t i_q_A, mc_t w_e_rad_s, mc_t u_max_V);

#ifdef __cplusplus
}
#endif

#endif /* CONTROL_FOC_CURRENT_H */
