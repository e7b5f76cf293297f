#include "design/inverter_fit.h"

#include <math.h>
#include <stdio.h>

/* g of inverter_fit.h: the leg's transition through zero current */
static double transition(double x)
{
    const double a = fabs(x);
    if (a <= 1.0) return 0.5 * x;
    return (x > 0.0 ? 1.0 : -1.0) * (1.0 - 0.5 / a);
}

double inverter_fit_alpha_V(const inverter_fit_t *f, double i_A)
{
    if (f->i_tr_A <= 0.0) {
        const double s = i_A > 0.0 ? 1.0 : (i_A < 0.0 ? -1.0 : 0.0);
        return f->R_ohm * i_A + (4.0 / 3.0) * f->v_err_V * s;
    }
    const double x = i_A / f->i_tr_A;
    return f->R_ohm * i_A + (2.0 / 3.0) * f->v_err_V * (transition(x) + transition(0.5 * x));
}

/* 3x3 inverse by cofactors; false if singular. */
static bool invert3(const double a[3][3], double inv[3][3])
{
    const double c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1];
    const double c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2];
    const double c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
    const double det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
    if (!(fabs(det) > 0.0)) return false;
    inv[0][0] = c00 / det;
    inv[1][0] = c01 / det;
    inv[2][0] = c02 / det;
    inv[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) / det;
    inv[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) / det;
    inv[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) / det;
    inv[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) / det;
    inv[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) / det;
    inv[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) / det;
    return true;
}

/* Least squares of (1) over the levels from `first` on: p = (R, (4/3) V,
 * -V i_tr); the residuals' sum of squares in *rss, (A^T A)^-1 in cov. */
static bool solve(const double *i_A, const double *v_V, int first, int n, double p[3], double cov[3][3], double *rss)
{
    double ata[3][3] = {{0.0}}, atb[3] = {0.0, 0.0, 0.0};
    for (int k = first; k < n; ++k) {
        const double row[3] = {i_A[k], 1.0, 1.0 / i_A[k]};
        for (int r = 0; r < 3; ++r) {
            atb[r] += row[r] * v_V[k];
            for (int c = 0; c < 3; ++c) ata[r][c] += row[r] * row[c];
        }
    }
    if (!invert3(ata, cov)) return false;
    for (int r = 0; r < 3; ++r) p[r] = cov[r][0] * atb[0] + cov[r][1] * atb[1] + cov[r][2] * atb[2];
    *rss = 0.0;
    for (int k = first; k < n; ++k) {
        const double e = v_V[k] - (p[0] * i_A[k] + p[1] + p[2] / i_A[k]);
        *rss += e * e;
    }
    return true;
}

bool inverter_fit(const double *i_A, const double *v_V, int n, inverter_fit_t *out, char *err, size_t err_len)
{
    for (int k = 0; k < n; ++k) {
        if (!(i_A[k] > 0.0) || !isfinite(v_V[k]) || (k > 0 && !(i_A[k] > i_A[k - 1]))) {
            snprintf(err, err_len, "level %d: the currents must be positive and ascending, the voltages finite", k);
            return false;
        }
    }
    /* every level first; then those above the knee of the fit's own i_tr,
     * until the set stops changing (it only shrinks: at most n rounds) */
    int first = 0;
    double p[3] = {0.0, 0.0, 0.0}, cov[3][3] = {{0.0}}, rss = 0.0;
    for (int round = 0; round <= n; ++round) {
        if (n - first < INVERTER_FIT_MIN_LEVELS) {
            snprintf(err, err_len,
                     "%d level(s) above %.1f times the transition current, %d needed: raise the test current",
                     n - first, INVERTER_FIT_KNEE, INVERTER_FIT_MIN_LEVELS);
            return false;
        }
        if (!solve(i_A, v_V, first, n, p, cov, &rss)) {
            snprintf(err, err_len, "the levels do not determine the fit (equal currents)");
            return false;
        }
        const double v_err = 0.75 * p[1];
        const double i_tr = (v_err > 0.0 && p[2] < 0.0) ? -p[2] / v_err : 0.0;
        int next = first;
        while (next < n && !(i_A[next] > INVERTER_FIT_KNEE * i_tr)) ++next;
        if (next == first) break;
        first = next;
    }
    const int used = n - first;
    out->R_ohm = p[0];
    out->v_err_V = 0.75 * p[1];
    out->i_tr_A = (out->v_err_V > 0.0 && p[2] < 0.0) ? -p[2] / out->v_err_V : 0.0;
    const double s2 = rss / (double)(used - 3);
    out->sigma_R_ohm = sqrt(s2 * cov[0][0]);
    out->sigma_v_err_V = 0.75 * sqrt(s2 * cov[1][1]);
    out->residual_rms_V = sqrt(rss / (double)used);
    out->n_used = used;
    if (!(out->R_ohm > 0.0)) {
        snprintf(err, err_len, "R = %g ohm: not positive (a current sensor's sign or scale, or a phase open)",
                 out->R_ohm);
        return false;
    }
    if (!(out->v_err_V > 0.0)) {
        snprintf(err, err_len, "the inverter's error voltage = %g V: not positive (the levels' noise)", out->v_err_V);
        return false;
    }
    return true;
}
