#include "startup/flux_circle_fit.h"

void flux_circle_fit_init(flux_circle_fit_t *f, const flux_circle_fit_config_t *cfg)
{
    f->cfg = *cfg;
    f->n = 0;
    f->phase = 0;
    f->mx = f->my = f->mxx = f->mxy = f->myy = f->m2 = f->m2x = f->m2y = MC_ZERO;
}

/* m += (x - m)/n */
static mc_t fit_mean(mc_t m, mc_t x, int32_t n) { return mc_add(m, mc_div_i(mc_sub(x, m), n)); }

void flux_circle_fit_add(flux_circle_fit_t *f, mc_ab_t q)
{
    f->phase += 1;
    if (f->phase < f->cfg.decim) {
        return;
    }
    f->phase = 0;
    f->n += 1;
    const int32_t n = f->n;
    const mc_t q2 = mc_dot2(q.alpha, q.alpha, q.beta, q.beta);
    f->mx = fit_mean(f->mx, q.alpha, n);
    f->my = fit_mean(f->my, q.beta, n);
    f->mxx = fit_mean(f->mxx, mc_mul(q.alpha, q.alpha), n);
    f->mxy = fit_mean(f->mxy, mc_mul(q.alpha, q.beta), n);
    f->myy = fit_mean(f->myy, mc_mul(q.beta, q.beta), n);
    f->m2 = fit_mean(f->m2, q2, n);
    f->m2x = fit_mean(f->m2x, mc_mul(q2, q.alpha), n);
    f->m2y = fit_mean(f->m2y, mc_mul(q2, q.beta), n);
}

bool flux_circle_fit_center(const flux_circle_fit_t *f, mc_ab_t *c)
{
    if (f->n < 3) {
        return false;
    }
    /* Cov(q) and Cov(|q|^2, q) from the means */
    const mc_t cxx = mc_sub(f->mxx, mc_mul(f->mx, f->mx));
    const mc_t cxy = mc_sub(f->mxy, mc_mul(f->mx, f->my));
    const mc_t cyy = mc_sub(f->myy, mc_mul(f->my, f->my));
    const mc_t ux = mc_sub(f->m2x, mc_mul(f->m2, f->mx));
    const mc_t uy = mc_sub(f->m2y, mc_mul(f->m2, f->my));
    const mc_t det = mc_cross2(cxx, cyy, cxy, cxy);
    if (mc_lt(det, f->cfg.det_min)) {
        return false;
    }
    /* c = (1/2) Cov(q)^-1 u */
    const mc_t two_det = mc_mul_i(det, 2);
    c->alpha = mc_div(mc_cross2(cyy, ux, cxy, uy), two_det);
    c->beta = mc_div(mc_cross2(cxx, uy, cxy, ux), two_det);
    return true;
}

bool flux_circle_fit_center_origin(const flux_circle_fit_t *f, mc_ab_t *c)
{
    if (f->n < 3) {
        return false;
    }
    const mc_t det = mc_cross2(f->mxx, f->myy, f->mxy, f->mxy);
    if (mc_lt(det, f->cfg.det_min)) {
        return false;
    }
    /* c = (1/2) M^-1 E(|p|^2 p) */
    const mc_t two_det = mc_mul_i(det, 2);
    c->alpha = mc_div(mc_cross2(f->myy, f->m2x, f->mxy, f->m2y), two_det);
    c->beta = mc_div(mc_cross2(f->mxx, f->m2y, f->mxy, f->m2x), two_det);
    return true;
}
