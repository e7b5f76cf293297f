/*
 * lock_monitor_design.h - the thresholds of supervisor/lock_monitor.h
 * derived from the motor the drive believes in, its flux observer's gain
 * and the tolerances the drive is meant to survive (docs/faults.md, "Loss
 * of lock"). Host side, double precision.
 */
#ifndef DESIGN_LOCK_MONITOR_DESIGN_H
#define DESIGN_LOCK_MONITOR_DESIGN_H

#include <stdbool.h>
#include <stddef.h>

#include "supervisor/lock_monitor.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    double R_ohm, L_H, Phi_Wb; /* the drive's model (L: the one of (14); Phi: the flux |eta| is pulled to) */
    /* A salient motor observed on its active flux (paper002_drive.h; the
     * defaults, 0 and 1, are paper 001's non-salient motor at i_d* = 0):
     * L_radial_H: the inductance whose error moves |eta| radially, L_d of
     * paper 002 (1) for a drive that drives i_d (MTPA (18)); 0 when i_d* = 0
     * (paper 001 (11)). rho_max: the largest |eta|/Phi of a lock that holds,
     * 1 + (L_q - L_d) |i_d| / psi at the largest MTPA i_d (>= 1). */
    double L_radial_H, rho_max;
    int n_p;
    double gPhi3_V;            /* the flux observer's gamma Phi^3 */
    double i_max_A;
    double settle_s;           /* the closed loop's settling time: the persistence */
    double ts_s;
    /* tolerances (lock_monitor_design.c: LOCK_* for the defaults) */
    double eps_R, eps_L, eps_Phi; /* relative model errors the lock must survive */
    double delta_max_rad;      /* the largest angle error the drive accepts */
    double di_rel;             /* current sensing error relative to i_max */
} lock_monitor_design_input_t;

/* The defaults of the tolerances (LOCK_EPS_*, LOCK_DELTA_MAX_RAD, LOCK_DI_REL),
 * and of a non-salient motor (L_radial_H = 0, rho_max = 1). */
void lock_monitor_design_defaults(lock_monitor_design_input_t *in);

/* Fills cfg; false with a message in err when an input is out of range. */
bool lock_monitor_design(const lock_monitor_design_input_t *in, lock_monitor_config_t *cfg, char *err, size_t err_len);

/* LOCK_CRIT_ANGLE_INNOVATION (supervisor/lock_monitor.h) for an estimator
 * that corrects its angle with a measured or observed one. */
typedef struct {
    double k_sigma;   /* the bound's noise part in standard deviations of the innovation (LOCK_INNOV_K_SIGMA) */
    double glitch_s;  /* the longest run of samples beyond the bound a lock rides out: the count's persistence */
    double forget_s;  /* the time a full count drains in (and so the share of samples beyond that is a loss) */
    double ts_s;
} lock_innovation_design_input_t;

/* k_sigma = LOCK_INNOV_K_SIGMA; the times and Ts 0 (the drive's to give). */
void lock_innovation_design_defaults(lock_innovation_design_input_t *in);

/* Fills cfg's innov_* and ts_s (nothing else); false with a message in err
 * when an input is out of range. */
bool lock_monitor_design_innovation(const lock_innovation_design_input_t *in, lock_monitor_config_t *cfg, char *err,
                                    size_t err_len);

#ifdef __cplusplus
}
#endif

#endif /* DESIGN_LOCK_MONITOR_DESIGN_H */
