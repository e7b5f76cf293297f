#include "design/deadtime_comp_design.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "design/inverter_fit.h"
#include "math/mc_convert.h"

bool deadtime_comp_design(const deadtime_comp_design_input_t *in, deadtime_comp_config_t *out, char *err, size_t n)
{
    memset(out, 0, sizeof(*out));
    const double vals[] = {in->dead_time_s, in->t_on_s,      in->t_off_s,        in->v_switch_V, in->r_switch_Ohm,
                           in->v_diode_V,   in->r_diode_Ohm, in->i_transition_A, in->i_noise_A};
    if (!(in->f_pwm_Hz > 0.0) || !isfinite(in->f_pwm_Hz)) {
        snprintf(err, n, "deadtime compensation: f_pwm_Hz must be > 0 (got %g)", in->f_pwm_Hz);
        return false;
    }
    for (size_t k = 0; k < sizeof(vals) / sizeof(vals[0]); ++k) {
        if (!(vals[k] >= 0.0) || !isfinite(vals[k])) {
            snprintf(err, n, "deadtime compensation: times, drops and currents must be finite and >= 0");
            return false;
        }
    }
    const double t_err = in->dead_time_s + in->t_on_s - in->t_off_s;
    if (!(2.0 * fabs(t_err) * in->f_pwm_Hz < 1.0) || !(4.0 * in->dead_time_s * in->f_pwm_Hz < 1.0)) {
        snprintf(err, n, "deadtime compensation: the dead time and delays must be shorter than half the PWM period");
        return false;
    }
    /* the dead-time error's sign: an error time below zero (t_off beyond
     * the dead time) lengthens the pulse; the block's k_bus is >= 0, so
     * such a leg is compensated as none (its few ns are not worth a sign) */
    const double k_bus = t_err > 0.0 ? t_err * in->f_pwm_Hz : 0.0;
    double f_d; /* the diodes' share of the period */
    if (in->synchronous) {
        f_d = 2.0 * in->dead_time_s * in->f_pwm_Hz;
    } else {
        f_d = 0.5;
    }
    const double f_s = 1.0 - f_d;
    const double i_band = fmax(in->i_transition_A, DTC_NOISE_BANDS * in->i_noise_A);
    out->enabled = true;
    out->k_bus = mc_from_double(k_bus);
    out->v_drop_V = mc_from_double(f_s * in->v_switch_V + f_d * in->v_diode_V);
    out->r_drop_ohm = mc_from_double(f_s * in->r_switch_Ohm + f_d * in->r_diode_Ohm);
    out->inv_i_band_per_A = i_band > 0.0 ? mc_from_double(1.0 / i_band) : mc_from_double(0.0);
    return true;
}

bool deadtime_comp_from_fit(const struct inverter_fit *f, double v_bus_V, double i_noise_A, deadtime_comp_config_t *out,
                            char *err, size_t n)
{
    memset(out, 0, sizeof(*out));
    if (!(v_bus_V > 0.0) || !isfinite(v_bus_V) || !(f->v_err_V > 0.0) || !isfinite(f->v_err_V) || !(f->i_tr_A >= 0.0) ||
        !(i_noise_A >= 0.0)) {
        snprintf(err, n,
                 "deadtime compensation from a measurement: the bus and the error voltage must be > 0, "
                 "the transition and noise currents >= 0");
        return false;
    }
    const double i_band = fmax(f->i_tr_A, DTC_NOISE_BANDS * i_noise_A);
    out->enabled = true;
    out->k_bus = mc_from_double(f->v_err_V / v_bus_V);
    out->v_drop_V = mc_from_double(0.0);
    out->r_drop_ohm = mc_from_double(0.0);
    out->inv_i_band_per_A = i_band > 0.0 ? mc_from_double(1.0 / i_band) : mc_from_double(0.0);
    return true;
}
