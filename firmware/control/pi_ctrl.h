/*
 * pi_ctrl.h - a discrete PI controller with output limits and
 * anti-windup by conditional integration, the loop every field-oriented
 * drive ships (ODrive's current and velocity loops, SimpleFOC's PIDController,
 * CMSIS-DSP's arm_pid_f32 without the derivative). Used by the sensored FOC
 * drive's current loops (d, q) and speed loop.
 *
 *   u[k] = clamp(kp e[k] + I[k] + ff, -u_max, u_max)
 *   I[k+1] = I[k] + ki_ts e[k]   unless u[k] is at a limit and e[k] pushes
 *                                 further into it (Astrom & Hagglund,
 *                                 "Advanced PID control", 2006, sec. 3.5:
 *                                 conditional integration)
 *
 * ki_ts = ki Ts: the gain per sample (forward Euler). The limit is given per
 * call (it can follow the bus). Fixed point: Q14.17; kp e and the integral
 * stay within +-u_max by the clamp and the conditional integration (u_max
 * below 16384 in the output's unit), e itself within the format.
 */
#ifndef CONTROL_PI_CTRL_H
#define CONTROL_PI_CTRL_H

#include <stdbool.h>

#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    mc_t kp;      /* proportional gain [output / input] */
    mc_t ki_ts;   /* integral gain per sample, ki Ts [output / (input sample)] */
} pi_ctrl_config_t;

typedef struct {
    pi_ctrl_config_t cfg;
    mc_t integral;   /* I[k], in the output's unit */
    bool saturated;  /* the last output was at a limit */
} pi_ctrl_t;

/* Copies cfg; the integral starts at 0. False for a negative gain. */
bool pi_ctrl_init(pi_ctrl_t *c, const pi_ctrl_config_t *cfg);

/* Sets the integral (bumpless start from a known output). */
static inline void pi_ctrl_reset(pi_ctrl_t *c, mc_t integral)
{
    c->integral = integral;
    c->saturated = false;
}

/* One sample: error e, feedforward ff (added before the limit, not
 * integrated), limit u_max > 0. Returns u[k]. */
mc_t pi_ctrl_step(pi_ctrl_t *c, mc_t e, mc_t ff, mc_t u_max);

#ifdef __cplusplus
}
#endif

#endif /* CONTROL_PI_CTRL_H */
