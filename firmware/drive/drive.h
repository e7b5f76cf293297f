/*
 * drive.h - the paper-000 sensorless position drive (Delpoux & Floquet 2014).
 *
 * One call per sample (Ts = 100 us) takes the measured phase currents and
 * returns the phase voltages. Inside: the (f-g) frame of the reference
 * trajectory, the super-twisting back-EMF observer, arctan + jump counter
 * position and velocity reconstruction, the mechanical observer, the
 * flatness references, super-twisting i_f control and twisting position
 * control, the open-loop low-speed start with bumpless switching, and the
 * voltage and current limits. The state struct is fixed-size; nothing
 * allocates. Coefficients come from drive_design() (firmware/design/),
 * which derives them from the motor and its bounds.
 */
#ifndef DRIVE_DRIVE_H
#define DRIVE_DRIVE_H

#include <stdbool.h>
#include <stdint.h>

#include "control/super_twisting.h"
#include "control/twisting.h"
#include "math/frame_fg.h"
#include "math/mc_num.h"
#include "observers/emf_observer.h"
#include "observers/mech_observer.h"
#include "observers/position_estimator.h"
#include "startup/open_loop.h"
#include "startup/rl_identification.h"
#include "trajectory/trajectory.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    DRIVE_MODE_OPEN_LOOP = 0,   /* eq. (68), |omega_r| < omega_lim */
    DRIVE_MODE_CLOSED_LOOP = 1, /* eqs. (46)-(54) on the estimates */
    DRIVE_MODE_FAULT = 2        /* safe state: 0 V until drive_init */
} drive_mode_t;

typedef enum {
    DRIVE_FAULT_NONE = 0,
    DRIVE_FAULT_OVERCURRENT = 1,
    DRIVE_FAULT_BAD_INPUT = 2
} drive_fault_t;

/* Everything drive_init needs, in the firmware numeric type. Per-sample
 * coefficients already contain Ts (see firmware/design/drive_design.c). */
typedef struct {
    int32_t n_p;              /* pole pairs (rotor teeth) */
    int32_t fs_hz;            /* sample rate, 1/Ts */
    mc_t R_ohm;               /* phase resistance */
    mc_t L_H;                 /* phase inductance */
    mc_t npL_ohm_s;           /* n_p L [V per (A rad/s)] */
    mc_t K_V_s;               /* back-EMF constant [V s/rad = N m/A] */
    mc_t J_over_K_A_s2;       /* J/K: current per unit acceleration, eq. (39) */
    mc_t fv_over_K_A_s;       /* f_v/K: current per unit speed, eq. (39) */
    mc_t LJ_over_KTs_V_s2;    /* L J/(K Ts): L di_g,r/dt per change of theta_r'' over a sample */
    mc_t Lfv_over_KTs_V_s;    /* L f_v/(K Ts): the same per change of theta_r' */
    mc_t v_max_V;             /* supply limit per phase */
    mc_t i_max_A;             /* current limit (references, open loop) */
    mc_t i_trip_A;            /* over-current trip on a measured phase */
    mc_t omega_lim_rad_s;     /* open/closed-loop switch speed */
    mc_t blend_decay;         /* per-sample decay of the switch voltage offset, exp(-Ts/tau) */
    mc_t ref_blend_decay;     /* per-sample decay of the switch current-reference offset */
    mc_t ref_blend_L_over_tau_ohm; /* L/tau of that decay: its L di_r/dt voltage */
    mc_t i_f_ref_A;           /* flat output i_f,r (0: section 5.2) */
    mc_t load_ff_A_per_Nm;    /* 1/K to add the observed load C_r to i_g,r; 0 = paper (39) as printed */
    mc_t load_ff_max_Nm;      /* the feed-forward trusts the estimate only up to the design load bound */
    emf_observer_config_t emf;
    position_estimator_config_t pos;
    mech_observer_config_t mech;
    super_twisting_config_t cur;  /* i_f loop, eqs. (46)-(48), output in V */
    twisting_config_t pos_ctrl;   /* position loop, eqs. (52)-(54), output in V */
    mc_t k_surface_per_s;         /* k of S = k xi_theta + xi_omega, eq. (52) */
    mc_t v_k_i_V_per_A;           /* L (k - f_v/J): voltage form of -(k/J - f_v/J^2) K xi_g in (54) */
    mc_t v_k_w_V_s;               /* (L/K)(k - f_v/J) f_v: same for the xi_omega term */
    open_loop_config_t open_loop;
    rl_id_config_t rl_id;     /* standstill R, L measurement at the start (window 0: off) */
    trajectory_config_t traj;
} drive_config_t;

/* What one step computed, for telemetry, logs and tests. */
typedef struct {
    drive_mode_t mode;
    drive_fault_t fault;
    uint32_t tick;
    /* references, eqs. (38)-(39), (70) */
    mc_t theta_ref_rad, omega_ref_rad_s, accel_ref_rad_s2;
    mc_t i_f_ref_A, i_g_ref_A;
    /* measured currents in the (f-g) frame, eq. (6), and the observer's */
    mc_t i_f_A, i_g_A, i_f_hat_A, i_g_hat_A;
    /* back-EMF estimates as voltages, L*d_f_hat and L*d_g_hat [V] (eq. 28) */
    mc_t e_f_hat_V, e_g_hat_V;
    /* estimates */
    mc_t theta_est_rad, omega_est_rad_s, accel_est_rad_s2, load_est_Nm;
    mc_t delta_theta_est_rad; /* eq. (29), in (-pi/n_p, pi/n_p] */
    int32_t jump_count;        /* k of eq. (71) */
    /* commands */
    mc_t v_f_V, v_g_V, v_a_V, v_b_V;
    bool v_saturated;
    /* model in use: the configured one, or the standstill measurement */
    rl_id_state_t rl_id_state;
    mc_t R_model_ohm, L_model_H;
} drive_telemetry_t;

typedef struct {
    drive_config_t cfg;
    drive_mode_t mode;
    drive_fault_t fault;
    uint32_t tick;
    emf_observer_t emf;
    position_estimator_t pos;
    mech_observer_t mech;
    super_twisting_t cur;
    twisting_t pos_ctrl;
    trajectory_t traj;
    rl_id_t rl_id;
    mc_t blend_f_V, blend_g_V; /* decaying offset that removes the voltage step at a switch */
    mc_t i_f_off_A, i_g_off_A; /* decaying current-reference offset that removes the torque step */
    mc_t v_f_prev_V, v_g_prev_V; /* last command in the (f-g) frame */
    bool sat_prev;               /* last command hit the voltage limit */
    bool v_ext_set;              /* drive_set_applied_voltage() for the next step */
    mc_t v_a_ext_V, v_b_ext_V;
    trajectory_point_t ref;      /* reference of this sample */
    trajectory_point_t ref_next; /* reference of the next sample */
    mc_rot_t rot_k;              /* U(n_p theta_r) of this sample, eq. (8) */
    mc_rot_t rot_next;           /* the same for the next sample */
    /* what the last step computed that is not kept in a block's state */
    struct {
        uint32_t tick;
        mc_t i_f_A, i_g_A, i_f_ref_A, i_g_ref_A, v_f_V, v_g_V, v_a_V, v_b_V;
        bool v_saturated;
    } last;
} drive_t;

/* Validates cfg, copies it and resets every state. Returns false (drive in
 * FAULT, outputs 0 V) if cfg is inconsistent. */
bool drive_init(drive_t *d, const drive_config_t *cfg);

/* One sample: phase currents [A] in, phase voltages [V] out. Always writes
 * *v_a_V and *v_b_V (0 V in FAULT). Returns false when in FAULT. */
bool drive_step(drive_t *d, mc_t i_a_A, mc_t i_b_A, mc_t *v_a_V, mc_t *v_b_V);

/* The phase voltages that will really be applied over the coming sample,
 * when they differ from what drive_step commands: the observer of that
 * step then uses them. For replays of recorded runs (sim/replay), or a
 * power stage whose output is known better than the command. One-shot:
 * applies to the next drive_step only. */
void drive_set_applied_voltage(drive_t *d, mc_t v_a_V, mc_t v_b_V);

/* Telemetry of the last step, assembled from the state on request (the
 * step itself stores only what no block keeps). */
void drive_get_telemetry(const drive_t *d, drive_telemetry_t *t);

#ifdef __cplusplus
}
#endif

#endif /* DRIVE_DRIVE_H */
