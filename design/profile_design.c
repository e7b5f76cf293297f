#include "design/profile_design.h"

#include <math.h>

#include "math/mc_convert.h"

bool speed_profile_design(speed_profile_config_t *pc, size_t n, const double *t_s, const double *omega_rad_s,
                          int32_t fs_hz, double ts_s, double *bad_t)
{
    const double fs = 1.0 / ts_s;
    pc->n_points = (uint32_t)n;
    pc->fs_hz = fs_hz;
    double theta = 0.0;
    for (size_t k = 0; k < n; ++k) {
        const double tk = t_s[k];
        if (!(tk >= 0.0) || (k == 0 && tk != 0.0) || (k > 0 && !(tk > t_s[k - 1])) || !isfinite(omega_rad_s[k])) {
            *bad_t = tk;
            return false;
        }
        pc->t_tick[k] = (uint32_t)llround(tk * fs);
        pc->omega_rad_s[k] = mc_from_double(omega_rad_s[k]);
        pc->theta_rad[k] = mc_from_double(theta);
        if (k + 1 < n) {
            const double T = (double)((uint32_t)llround(t_s[k + 1] * fs) - pc->t_tick[k]) * ts_s;
            pc->length_s[k] = mc_from_double(T);
            pc->slope_rad_s2[k] = mc_from_double((omega_rad_s[k + 1] - omega_rad_s[k]) / T);
            theta += 0.5 * (omega_rad_s[k] + omega_rad_s[k + 1]) * T;
        }
    }
    return true;
}
