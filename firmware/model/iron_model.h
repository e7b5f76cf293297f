/*
 * iron_model.h - the drive's model of its motor's saturating iron, for the
 * active flux a sensorless observer of a salient PMSM runs on (paper 002's
 * flux and HF-injection variants, drives/paper002/paper002_drive.h). It
 * is the plant's saturation model (sim/model/saturation.h, (S1)-(S2);
 * docs/plant.md) in the drive's hands, as a commissioning's inductance map
 * L_q(i_d, i_q) would give it on a real motor: one factor k scales both
 * apparent (secant) inductances,
 *   u_b / u_s = ((i_d + i_b)^2 + (L_q0/L_d0) i_q^2) / i_sat^2,
 *   k = 1 / sqrt(1 + u_b/u_s),                       k_0 = k(0, 0),
 *   psi_d = Phi + L_d0 (k (i_d + i_b) - k_0 i_b),   psi_q = k L_q0 i_q  (S2)
 * with i_b the magnet's bias on the d-axis iron as a d current (0: the
 * iron's saturation even in i_d). The active flux (Boldea; paper 002's
 * flux variant) subtracts the q axis's secant inductance, L_qs = k L_q0:
 *   eta = lambda - L_qs i = (psi_d - L_qs i_d) (cos, sin)(theta_e),
 * exactly along the rotor's d axis, its radius
 *   a = Phi + L_d0 (k (i_d + i_b) - k_0 i_b) - k L_q0 i_d             (A1)
 * (without a bias Phi + k (L_d0 - L_q0) i_d). With the linear model's
 * L_q0 instead, eta has a q component -(1 - k) L_q0 i_q: an angle error of
 * -(1 - k) L_q0 i_q / a, -0.2 rad electrical at i_q = 9 A on paper 002's
 * IPMSM with the hardware-like plant's iron (k = 0.86; docs/hf_injection.md),
 * which lags the rotor, takes torque away and makes the speed loop ask for
 * more current: the flux variant's loss of synchronism on that plant.
 * Linear (i_sat = 0): k = 1, L_qs = L_q0, a = Phi + (L_d0 - L_q0) i_d.
 *
 * Not modelled, as in the plant: the magnet's flux moving with i_d or the
 * temperature (a warm magnet's Phi is the observer's own error), iron
 * losses, hysteresis.
 * Float: paper 002's drive is float only. Fixed point (Q14.17), if used:
 * the squared currents up to 3 i_max^2 and inv_isat2 near 1e-3 fit, the
 * latter to 0.5 % (its step 7.6e-6).
 */
#ifndef MODEL_IRON_MODEL_H
#define MODEL_IRON_MODEL_H

#include <stdbool.h>

#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    mc_t Ld0_H, Lq0_H;     /* the unsaturated inductances (the motor model's L_d, L_q) */
    mc_t psi_Wb;           /* the magnet's flux Phi */
    mc_t inv_isat2_per_A2; /* 1 / i_sat^2; 0: linear (k = 1 at every current) */
    mc_t lq_over_ld;       /* L_q0 / L_d0: the q current's weight in u_b/u_s */
    mc_t i_bias_A;         /* i_b, the magnet's bias (0: none) */
    mc_t k0;               /* k(0, 0) = 1 / sqrt(1 + (i_b / i_sat)^2) */
} iron_model_config_t;

/* From the unsaturated L_d0 < or > L_q0 (both > 0), Phi > 0, i_sat >= 0
 * (0: linear) and i_b >= 0 (needs i_sat > 0). False (cfg set linear) on
 * anything else. */
bool iron_model_init(iron_model_config_t *cfg, mc_t Ld0_H, mc_t Lq0_H, mc_t psi_Wb, mc_t i_sat_A, mc_t i_bias_A);

/* Whether the iron saturates at all (i_sat > 0). */
static inline bool iron_model_saturates(const iron_model_config_t *cfg)
{
    return mc_gt(cfg->inv_isat2_per_A2, MC_ZERO);
}

/* The factor k of (S2) at the rotor-frame currents (i_d, i_q), in (0, 1]. */
mc_t iron_model_factor(const iron_model_config_t *cfg, mc_t i_d_A, mc_t i_q_A);

/* The iron at the rotor-frame currents (i_d, i_q), from one factor k:
 *  - the linear model's parameters that reproduce (S2): psi_d = psi_s +
 *    L_ds i_d, psi_q = L_qs i_q with L_ds = k L_d0, L_qs = k L_q0 and
 *    psi_s = Phi + L_d0 (k - k_0) i_b (Phi without a bias) [H, H, Wb];
 *    the active flux's radius (A1) is psi_s + (L_ds - L_qs) i_d;
 *  - the inductances the currents' dynamics see on each axis alone (the
 *    plant integrates di/dt = L_inc^-1 r, sim/model/saturation.h (S3)):
 *    the inverses of L_inc^-1's diagonal,
 *      L_di = k L_d0 / (1 + ((i_d + i_b) / i_sat)^2),
 *      L_qi = k L_q0 / (1 + (L_q0/L_d0) (i_q / i_sat)^2)               (I1)
 *    (the off-diagonal, cross-saturation's, is left out: the drive's
 *    model is diagonal) [H, H]. Below the secant values wherever the iron
 *    saturates: on paper 002's IPMSM with the magnet's bias (i_b = 13.3 A,
 *    i_sat = 26.7 A) L_di = 0.72 L_d0 at zero current, where the secant
 *    k L_d0 = 0.89 L_d0.
 * Linear: L_d0, L_q0 both ways, Phi. */
typedef struct {
    mc_t Lds_H, Lqs_H, psi_s_Wb; /* secant (S2) */
    mc_t Ldi_H, Lqi_H;           /* incremental (I1) */
} iron_model_point_t;

void iron_model_at(const iron_model_config_t *cfg, mc_t i_d_A, mc_t i_q_A, iron_model_point_t *pt);

#ifdef __cplusplus
}
#endif

#endif /* MODEL_IRON_MODEL_H */
