/*
 * flux_circle_fit.h - finds the flux observer's initial error from the
 * motion of the open-loop start, so the sensorless drive starts from any
 * rotor angle (paper 001's result is local: a wrong initial estimate can
 * lock it in a stalled state; the gradient observer (12) alone removes a
 * large error only at the slow rate w_e^2/(2 gamma Phi^2) at low speed).
 *
 * Why it works: integrating v - R i measures the change of the stator flux
 * exactly (paper 001 section 4.2: d lambda/dt = v - R i), so with the
 * gradient term of (12) off, lambda_hat - lambda = lambda~ is constant and
 * the points q = (lambda_hat - L i)/Phi = rho + lambda~/Phi lie on the unit
 * circle centred at c = lambda~/Phi. Once the rotor has turned through an
 * arc, the circle fit (Kasa's algebraic fit: |q|^2 - 2 q.c + |c|^2 = 1 is
 * linear in c and |c|^2, whose least-squares solution is
 *   c = (1/2) Cov(q)^-1 Cov(|q|^2, q),
 * with sample means over the points) gives c exactly for exact data, from
 * any initial error; lambda_hat -= Phi c then starts the observer right.
 * It needs an arc, not a speed: det Cov(q) measures the arc (1/4 for a
 * full turn, 0 for no motion) and the fit is refused below det_min.
 *
 * The means are running means updated every `decim` samples (x_n = x_{n-1}
 * + (x - x_{n-1})/n): no sums that could overflow Q14.17, |q| <= 3 keeps
 * every mean below 27. R errors make lambda~ drift while the fit runs: the
 * drift of a current turning with the open-loop vector stays bounded by
 * dR I / w_e, so the fit degrades gracefully (see docs/paper001.md).
 */
#ifndef STARTUP_FLUX_CIRCLE_FIT_H
#define STARTUP_FLUX_CIRCLE_FIT_H

#include <stdbool.h>
#include <stdint.h>

#include "adapter/phase_adapter.h"
#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    int32_t decim;   /* samples between two points */
    mc_t det_min;    /* smallest det Cov(q) accepted (an arc long enough) */
} flux_circle_fit_config_t;

typedef struct {
    flux_circle_fit_config_t cfg;
    int32_t n;       /* points taken */
    int32_t phase;   /* samples since the last point */
    /* running means of q_x, q_y, q_x^2, q_x q_y, q_y^2, |q|^2, |q|^2 q_x, |q|^2 q_y */
    mc_t mx, my, mxx, mxy, myy, m2, m2x, m2y;
} flux_circle_fit_t;

void flux_circle_fit_init(flux_circle_fit_t *f, const flux_circle_fit_config_t *cfg);

/* Offers this sample's q = rho_hat (not normalised); takes every decim-th. */
void flux_circle_fit_add(flux_circle_fit_t *f, mc_ab_t q);

/* The centre c; false (c untouched) if the arc is too short. */
bool flux_circle_fit_center(const flux_circle_fit_t *f, mc_ab_t *c);

/* The centre c of a circle through the origin (the points offered are
 * p = q - q(0), so the first point of the motion is the origin):
 * |p|^2 = 2 p.c is linear in c alone, c = (1/2) M^-1 E(|p|^2 p) with
 * M = E(p p^T) the raw second moments. Two unknowns instead of three, so a
 * short arc suffices: the chord fixes c's direction up to a mirror, the
 * curvature (the arc's sagitta) picks the side. det M grows as arc^6
 * (about 1e-3 arc^6 for an arc from the origin): callers scale p up.
 * False (c untouched) if det M < det_min. */
bool flux_circle_fit_center_origin(const flux_circle_fit_t *f, mc_ab_t *c);

#ifdef __cplusplus
}
#endif

#endif /* STARTUP_FLUX_CIRCLE_FIT_H */
