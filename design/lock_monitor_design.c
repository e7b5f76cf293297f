#include "design/lock_monitor_design.h"

#include <math.h>
#include <stdio.h>

#include "math/mc_convert.h"

/* Tolerances the lock must survive without a fault (and beyond which a
 * drive is not claimed to work), each the largest model error a shipped
 * robustness scenario of paper 001 runs with while the speed is tracked:
 * R +50 % (paper 001 section 5.1's largest variation, paper001_R150),
 * L +50 % (paper001_L150), Phi +15 % (paper001_Phi115). */
#define LOCK_EPS_R 0.5
#define LOCK_EPS_L 0.5
#define LOCK_EPS_PHI 0.15
/* The largest angle error accepted while turning: 30 degrees costs
 * 1 - cos 30 = 13 % of the torque per ampere and puts half the current on
 * the d axis; paper001_R150's 20 degrees under load at 50 rpm stay below. */
#define LOCK_DELTA_MAX_RAD (30.0 * 3.14159265358979323846 / 180.0)
/* The current sensing's error, 1 % of i_max (a shunt amplifier's gain
 * error): in eta = lambda - L i of (14) it moves |rho|^2 by 2 L di / Phi,
 * which the gradient term answers with 2 gamma Phi^2 L di volts. */
#define LOCK_DI_REL 0.01

/* LOCK_CRIT_ANGLE_INNOVATION's noise part: 6 standard deviations of the
 * innovation. A Gaussian innovation leaves +-6 sigma with probability
 * 2.0e-9 per sample (one sample in 14 hours at 10 kHz), and the leaky
 * count needs glitch_s / Ts such samples before a leak of one per sample
 * within drains them, so the noise alone never fills it; the innovation
 * of a consistent filter is not heavier-tailed than that unless the
 * model is wrong, which is what the tolerance part answers. */
#define LOCK_INNOV_K_SIGMA 6.0

static bool lock_fail(char *err, size_t n, const char *field, const char *why, double got)
{
    if (err != NULL && n > 0) {
        snprintf(err, n, "lock_monitor.%s: %s (got %g)", field, why, got);
    }
    return false;
}

void lock_monitor_design_defaults(lock_monitor_design_input_t *in)
{
    in->eps_R = LOCK_EPS_R;
    in->eps_L = LOCK_EPS_L;
    in->eps_Phi = LOCK_EPS_PHI;
    in->delta_max_rad = LOCK_DELTA_MAX_RAD;
    in->di_rel = LOCK_DI_REL;
    in->L_radial_H = 0.0; /* paper 001: non-salient, i_d* = 0 */
    in->rho_max = 1.0;
}

bool lock_monitor_design(const lock_monitor_design_input_t *in, lock_monitor_config_t *cfg, char *err, size_t err_len)
{
    if (!(in->Phi_Wb > 0.0)) return lock_fail(err, err_len, "Phi_Wb", "must be > 0", in->Phi_Wb);
    if (!(in->L_H > 0.0)) return lock_fail(err, err_len, "L_H", "must be > 0", in->L_H);
    if (!(in->R_ohm >= 0.0)) return lock_fail(err, err_len, "R_ohm", "must be >= 0", in->R_ohm);
    if (in->n_p < 1) return lock_fail(err, err_len, "n_p", "must be >= 1", in->n_p);
    if (!(in->settle_s > 0.0 && in->ts_s > 0.0))
        return lock_fail(err, err_len, "settle_s", "settling time and Ts must be > 0", in->settle_s);
    if (!(in->eps_Phi >= 0.0 && in->eps_R >= 0.0 && in->eps_L >= 0.0 && in->di_rel >= 0.0 &&
          in->delta_max_rad > 0.0 && in->delta_max_rad < 1.5707963267948966))
        return lock_fail(err, err_len, "tolerances", "eps >= 0, 0 < delta_max < pi/2", in->delta_max_rad);
    if (!(in->L_radial_H >= 0.0)) return lock_fail(err, err_len, "L_radial_H", "must be >= 0", in->L_radial_H);
    if (!(in->rho_max >= 1.0)) return lock_fail(err, err_len, "rho_max", "must be >= 1", in->rho_max);
    if (in->L_radial_H > 0.0 && !(in->eps_Phi > 0.0))
        return lock_fail(err, err_len, "eps_Phi", "must be > 0 with L_radial_H > 0 (the tangent below)", in->eps_Phi);
    const double np = (double)in->n_p;
    /* a lock that holds, at electrical speed w_e = n_p w: an angle error up
     * to delta_max shows Phi w_e sin(delta_max) along the estimated d axis;
     * a flux (1 + eps) Phi turned at the same speed by an observer pulled to
     * Phi settles at the angle whose cos is 1/(1 + eps), where the radial
     * correction is Phi w_e sqrt((1 + eps)^2 - 1) (lock_monitor.h). On a
     * salient motor's active flux of radius a (below) the angle error shows
     * e_d = a w_e sin(delta), of which the monitor sees e_d / |rho| = Phi
     * w_e sin(delta) (|rho| = a / Phi): the same with Phi = psi_p; the flux
     * error's relative size eps_Phi psi_p / a is at most eps_Phi. */
    const double k_speed =
        np * in->Phi_Wb * (sin(in->delta_max_rad) + sqrt((1.0 + in->eps_Phi) * (1.0 + in->eps_Phi) - 1.0));
    /* eps_L L di/dt of a current turning at w_e: eps_L L n_p w |i| (the
     * error of the L in (14) times the current across the estimated axis:
     * a tangential offset of eta, which the rotation turns into a radial
     * correction w_e eps_L L |i_q|).
     * A salient motor on its active flux (paper 002 (1): psi_d = L_d i_d +
     * psi_p, psi_q = L_q i_q; eta = lambda - L_q i lies along d with the
     * radius a = psi_p + (L_d - L_q) i_d, the target of (12)): an L_d error
     * also moves the radius, by eps_L L_d |i_d|, a flux error as eps_Phi's
     * but relative to a >= psi (i_d <= 0 by MTPA (18) with L_d < L_q). The
     * monitor's residual gPhi3 |target - |rho|^2| is e_d / |rho| (e_d =
     * gPhi3 |rho| (target - |rho|^2), (12) along rho), so a radial error
     * x = dr/a shows psi w_e f(x), f(x) = sqrt((1 + x)^2 - 1), as eps_Phi
     * above. f is concave: f(eps_Phi + y) <= f(eps_Phi) + f'(eps_Phi) y,
     * f'(x) = (1 + x)/f(x), and with y <= eps_L L_d |i|/psi the radial part
     * adds f'(eps_Phi) eps_L L_d n_p |w| |i| (2.02 eps_L L_d at eps_Phi =
     * 0.15). 0 for L_radial_H = 0 (paper 001: i_d* = 0). */
    const double radial_H =
        in->L_radial_H > 0.0
            ? in->L_radial_H * (1.0 + in->eps_Phi) / sqrt((1.0 + in->eps_Phi) * (1.0 + in->eps_Phi) - 1.0)
            : 0.0;
    const double k_speed_cur = in->eps_L * (in->L_H + radial_H) * np;
    /* eps_R R |i| (along the estimated axis; e_d / |rho| <= e_d with
     * |rho| >= 1) */
    const double k_cur = in->eps_R * in->R_ohm;
    /* 2 gamma Phi^2 L di (LOCK_DI_REL): gamma Phi^2 = gPhi3 / Phi; on a
     * radius |rho| the same di moves |rho|^2 by 2 |rho| L di / Phi: times
     * rho_max (1 for paper 001) */
    const double floor_v =
        2.0 * (in->gPhi3_V / in->Phi_Wb) * in->L_H * in->di_rel * in->i_max_A * in->rho_max;
    cfg->gPhi3_V = mc_from_double(in->gPhi3_V);
    cfg->k_speed_V_s = mc_from_double(k_speed);
    cfg->k_speed_cur_H = mc_from_double(k_speed_cur);
    cfg->k_cur_ohm = mc_from_double(k_cur);
    cfg->floor_V = mc_from_double(floor_v);
    cfg->ticks = (int32_t)ceil(in->settle_s / in->ts_s - 1e-9);
    return true;
}

void lock_innovation_design_defaults(lock_innovation_design_input_t *in)
{
    in->k_sigma = LOCK_INNOV_K_SIGMA;
    in->glitch_s = 0.0;
    in->forget_s = 0.0;
    in->ts_s = 0.0;
}

bool lock_monitor_design_innovation(const lock_innovation_design_input_t *in, lock_monitor_config_t *cfg, char *err,
                                    size_t err_len)
{
    if (!(in->ts_s > 0.0)) return lock_fail(err, err_len, "ts_s", "must be > 0", in->ts_s);
    if (!(in->k_sigma > 0.0)) return lock_fail(err, err_len, "k_sigma", "must be > 0", in->k_sigma);
    if (!(in->glitch_s >= in->ts_s))
        return lock_fail(err, err_len, "glitch_s", "must be at least a sample (Ts)", in->glitch_s);
    if (!(in->forget_s >= in->glitch_s))
        return lock_fail(err, err_len, "forget_s", "must be >= glitch_s", in->forget_s);
    /* the persistence: glitch_s / Ts consecutive samples beyond the bound
     * (the count's limit over its step up); a full count drains at one per
     * sample within in about forget_s: up = forget / glitch samples, so a
     * loss is more than 1 sample in (up + 1) beyond the bound, sustained
     * (lock_monitor.h) */
    const double glitch_n = ceil(in->glitch_s / in->ts_s - 1e-9);
    const double forget_n = ceil(in->forget_s / in->ts_s - 1e-9);
    if (!(forget_n <= 1e8)) return lock_fail(err, err_len, "forget_s", "at most 1e8 samples", forget_n);
    double up = floor(forget_n / glitch_n + 1e-9);
    if (up < 1.0) {
        up = 1.0;
    }
    cfg->innov_k2 = mc_from_double(in->k_sigma * in->k_sigma);
    cfg->ts_s = mc_from_double(in->ts_s);
    cfg->innov_up = (int32_t)up;
    cfg->innov_limit = (int32_t)(up * glitch_n);
    return true;
}
