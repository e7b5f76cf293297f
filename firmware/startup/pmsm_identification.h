/*
 * pmsm_identification.h - commissioning of a PMSM without a position
 * sensor: phase resistance R and inductance L at standstill, then the
 * flux linkage Phi from an open-loop spin (not in paper 001, whose drive
 * assumes R, L, Phi known; its scheme loses the speed at standstill with
 * R +50 % and tracks with an error with Phi +15 %, section 5.2).
 *
 * Why a separate commissioning run: the stepper of paper 000 rests on a
 * detent, aligned with the first open-loop vector, so its R/L measurement
 * runs inside the start. A PMSM rotor rests anywhere; a vector that is not
 * along its flux turns it, and a voltage-fed rotor turning at its slip
 * speed R I / K_e induces a back-EMF as large as R I itself: R would be
 * off by up to 100 %. So the rotor is aligned first, which takes seconds
 * (the resistance damps it: time constant K_e / (R I)), as VESC's and
 * ODrive's motor detection do before a run.
 *
 * Phases (each a whole number of samples, voltages along alpha-beta):
 *   ALIGN_BETA  v_align along beta: the rotor turns towards beta from
 *               anywhere but the unstable -beta;
 *   ALIGN_ALPHA v_align along alpha: a quarter turn at most, and never the
 *               unstable half turn; the rotor settles on alpha;
 *   REST        0 V: the current decays, the rotor stays (no torque);
 *   RL          v_rl along alpha, the rotor's own axis (no torque): the
 *               standstill R/L step of startup/rl_identification.h;
 *   SPIN        a vector of eq. (68)'s magnitude (paper 000, with the
 *               measured R and L) turning at w_e, ramped up, held, ramped
 *               down. Over the held part, with the measured R and L,
 *                 e = v - R i - L di/dt = w_e Phi Jm rho   (paper 001 (1))
 *               so |e| / w_e averages to Phi, whatever the rotor angle and
 *               the load angle; v is the voltage held over the sample, i
 *               the trapezoid mean of its ends (as in flux_observer.c).
 * Results outside [1/2, 2] times the model's are rejected, and so is the
 * run if a phase current passes the trip level.
 */
#ifndef STARTUP_PMSM_IDENTIFICATION_H
#define STARTUP_PMSM_IDENTIFICATION_H

#include <stdbool.h>
#include <stdint.h>

#include "adapter/phase_adapter.h"
#include "math/frame_fg.h"
#include "math/mc_num.h"
#include "model/motor_model.h"
#include "startup/rl_identification.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    PMSM_ID_ALIGN_BETA = 0,
    PMSM_ID_ALIGN_ALPHA = 1,
    PMSM_ID_REST = 2,
    PMSM_ID_RL = 3,
    PMSM_ID_SPIN = 4,
    PMSM_ID_DONE = 5,      /* R_ohm, L_fs_ohm, Phi_Wb hold the results */
    PMSM_ID_REJECTED = 6   /* see `why`; the model's values are kept */
} pmsm_id_phase_t;

typedef struct {
    motor_model_t model;        /* the nominal model: R, L, K_e = n_p Phi, n_p, fs */
    mc_t Phi_model_Wb;          /* plausibility reference */
    mc_t i_trip_A;              /* any phase above: rejected */
    mc_t v_align_V;             /* alignment vector */
    int32_t align_beta_ticks, align_alpha_ticks, rest_ticks;
    rl_id_config_t rl;          /* the standstill step (window, steady tail, model R, L/Ts) */
    mc_t v_rl_V;                /* the step's voltage */
    mc_t i_spin_A;              /* current amplitude of the spin (I of (68)) */
    mc_t omega_spin_e_rad_s;    /* electrical speed of the held spin */
    mc_t theta_step_rad;        /* its angle step per sample, ~ omega_spin Ts; Phi uses theta_step fs */
    mc_t omega_step_e_rad_s;    /* speed change per sample on the ramps */
    int32_t hold_ticks;         /* held spin, of which the last meas_ticks are measured */
    int32_t meas_ticks;
} pmsm_id_config_t;

typedef struct {
    pmsm_id_config_t cfg;
    pmsm_id_phase_t phase;
    int32_t k;                  /* samples in this phase */
    rl_id_t rl;
    motor_model_t measured;     /* the model with the measured R, L (for (68) in the spin) */
    mc_t theta_e_rad;           /* angle of the spin's vector, in (-pi, pi] */
    mc_t omega_e_rad_s;         /* its speed */
    bool ramping_down;
    mc_ab_t v_prev_V;           /* voltage held over the last sample */
    mc_ab_t i_prev_A;
    mc_t mean_e_V, res_e;       /* mean |e| over the measurement and its rounding residual */
    mc_t R_ohm, L_fs_ohm, Phi_Wb; /* results (model values until DONE) */
    const char *why;            /* reason of a rejection, static text */
} pmsm_id_t;

/* Copies cfg and starts at ALIGN_BETA. False (REJECTED) if cfg is unusable. */
bool pmsm_id_init(pmsm_id_t *id, const pmsm_id_config_t *cfg);

/* One sample: alpha-beta currents measured now, the phase currents for the
 * trip check (n of them), the bus-limited voltage magnitude v_max_V. Writes
 * the alpha-beta voltage to hold over the coming sample (0 V once DONE or
 * REJECTED). Returns true while running. */
bool pmsm_id_step(pmsm_id_t *id, mc_ab_t i_ab_A, const mc_t *i_phase_A, uint32_t n, mc_t v_max_V, mc_ab_t *v_ab_V);

#ifdef __cplusplus
}
#endif

#endif /* STARTUP_PMSM_IDENTIFICATION_H */
