/*
 * mtpa.h - paper 002's current references from a torque demand: maximum
 * torque per ampere, eqs. (15)/(18), i_d from i_q (i_d = 0 when L_d = L_q),
 * and the inversion the paper leaves out (errata): the i_q that gives the
 * demanded torque (10) with that i_d, by Newton's method on
 *   g(i_q) = 3/2 p (psi i_q + (L_d - L_q) i_d(i_q) i_q) - M_d,
 *   g'(i_q) = 3/2 p (psi + (L_d - L_q)(i_d + i_q di_d/di_q)),
 *   di_d/di_q = -2 i_q / sqrt(a^2 + 4 i_q^2),  a = psi/(L_d - L_q) < 0,
 * from the non-salient guess M_d/(3/2 p psi), a fixed number of steps
 * (MTPA_NEWTON_STEPS: bounded cost; g is convex in i_q on each side of 0,
 * the iteration converges monotonically from the guess). The result is
 * limited to |i| <= i_max along the MTPA curve (the torque then falls
 * short: out->limited). The motor (L_d, L_q, psi, n_p) is the drive's one
 * model (model/motor_model.h), read by const pointer.
 */
#ifndef CONTROL_MTPA_H
#define CONTROL_MTPA_H

#include <stdbool.h>

#include "math/mc_num.h"
#include "model/motor_model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Newton steps, counted in double from the non-salient guess on the
 * reference motor (L_d/L_q = 1/3) at the current limit (20 A, 10.8 N m),
 * its hardest point: 3 leave 0.069 A of i_q (0.086 N m), 4 leave 1.4e-4 A
 * (1.7e-4 N m, 1.6e-5 of the torque), 5 leave 5e-10 A. 4: the error well
 * below the current sensor's noise (5 mA) at one step's cost more than 3
 * (Mtpa.NegativeTorqueOnTheCurveLimitedAndOdd holds it to 2e-4 A). */
#define MTPA_NEWTON_STEPS 4
/* Halvings that put |i| on i_max when limited: 16 leave 2^-16 of the range
 * (0.3 mA at 20 A). */
#define MTPA_LIMIT_STEPS 16

typedef struct {
    mc_t i_max_A;        /* |i| limit */
} mtpa_config_t;

typedef struct {
    mc_t i_d_A, i_q_A;   /* the references */
    bool limited;        /* |i| was limited to i_max */
} mtpa_out_t;

/* i_d of (18) (L_d < L_q) for i_q; 0 when L_d = L_q. */
mc_t mtpa_id_of_iq(const motor_model_t *m, mc_t i_q_A);

/* The torque (10) of the currents. */
mc_t mtpa_torque(const motor_model_t *m, mc_t i_d_A, mc_t i_q_A);

/* The MTPA currents for torque M_d. */
void mtpa_step(const mtpa_config_t *c, const motor_model_t *m, mc_t M_d_Nm, mtpa_out_t *out);

#ifdef __cplusplus
}
#endif

#endif /* CONTROL_MTPA_H */
