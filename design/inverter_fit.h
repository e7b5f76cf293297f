/*
 * inverter_fit.h - the phase resistance and the inverter's voltage error
 * from the current levels of firmware/startup/inverter_id.h (issue 45's
 * commissioning), in double precision: on the host and on the float
 * images that design on the board.
 *
 * The model (sim/model/inverter.h, the averaged leg of Sukegawa et al.
 * 1991 and Choi and Sul 1996): a leg carrying i loses
 *   e(i) = V g(i / i_tr) + r i
 * of its commanded voltage, V the error voltage well above the transition
 * (V_dc t_err f_pwm and the body diode's constant drop over the dead
 * times), g(x) = x / 2 for |x| <= 1 and sgn(x) (1 - 1 / (2 |x|)) beyond,
 * r the devices' slope. A current i along alpha (phase a i, phases b and c
 * -i/2, star with an isolated neutral) then needs
 *   v_alpha = (R_w + r) i + (2/3) V (g(x) + g(x / 2)),   x = i / i_tr,
 * and for i > 2 i_tr, where both legs' g are past their knee,
 *   v_alpha = R i + (4/3) V - V i_tr / i,                R = R_w + r      (1)
 * linear in (R, (4/3) V, V i_tr) over the basis (i, 1, 1/i). The fit
 * takes the levels above 2 i_tr (i_tr from the fit itself, iterated until
 * the set is stable), solves (1) by least squares and gives each result's
 * standard deviation from the residuals (the covariance s^2 (A^T A)^-1,
 * s^2 the residuals' sum of squares over n - 3). R is what the current
 * loops see (the winding and the devices' slope); V and i_tr are what the
 * dead-time compensation needs (design/deadtime_comp_design.h: k_bus =
 * V / V_dc, i_band from i_tr).
 */
#ifndef DESIGN_INVERTER_FIT_H
#define DESIGN_INVERTER_FIT_H

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The levels above INVERTER_FIT_KNEE times i_tr are the ones (1) holds
 * for: 2 exactly, with 10 % of margin for the fit's own i_tr. */
#define INVERTER_FIT_KNEE 2.2
/* The levels above the knee a fit needs: one more than its three unknowns,
 * so that the residuals check the model and give the spreads (three
 * levels always fit exactly, whatever the truth). */
#define INVERTER_FIT_MIN_LEVELS 4

typedef struct inverter_fit {
    double R_ohm;       /* as the current loops see it: winding and devices */
    double v_err_V;     /* a leg's error voltage well above the transition */
    double i_tr_A;      /* the transition current (0: none seen) */
    double sigma_R_ohm; /* their standard deviations from the residuals */
    double sigma_v_err_V;
    double residual_rms_V; /* the fit's residual over the levels it used */
    int n_used;            /* the levels it used (the highest ones) */
} inverter_fit_t;

/* The fit of n levels (currents i_A[], > 0 and ascending, and the mean
 * commanded alpha voltages v_V[]). False with the reason in err: fewer than
 * INVERTER_FIT_MIN_LEVELS above the knee (raise the test current), a
 * non-positive R or V. */
bool inverter_fit(const double *i_A, const double *v_V, int n, inverter_fit_t *out, char *err, size_t err_len);

/* The alpha voltage the fitted model needs at i (the whole g, below the
 * knee too): for checks against levels the fit did not use. */
double inverter_fit_alpha_V(const inverter_fit_t *f, double i_A);

#ifdef __cplusplus
}
#endif

#endif /* DESIGN_INVERTER_FIT_H */
