// thermal.cpp - the first-order winding temperature (see thermal.h for
// (T1)-(T3), the exact step and the sources).
#include "model/thermal.h"

#include <cmath>

namespace mcsim {

namespace {
// Absolute zero [C]: the floor of any temperature a scenario may give.
constexpr double kAbsoluteZero_C = -273.15;
}  // namespace

const char* ThermalParams::problem() const
{
    const double vals[] = {R_th_K_per_W, C_th_J_per_K, T_ambient_C, T0_C, alpha_cu_per_K, beta_pm_per_K};
    for (double v : vals) {
        if (!std::isfinite(v)) {
            return "every thermal parameter must be finite";
        }
    }
    if (R_th_K_per_W < 0.0 || C_th_J_per_K < 0.0) {
        return "R_th_K_per_W and C_th_J_per_K must be >= 0";
    }
    if ((R_th_K_per_W > 0.0) != (C_th_J_per_K > 0.0)) {
        return "R_th_K_per_W and C_th_J_per_K go together (both > 0, or both 0 for no thermal model)";
    }
    if (T_ambient_C < kAbsoluteZero_C || T0_C < kAbsoluteZero_C) {
        return "temperatures must be above absolute zero";
    }
    return nullptr;
}

ThermalModel::ThermalModel(const ThermalParams& p, double R_20_ohm, double Phi_20_Wb, double power_scale)
    : p_(p), R20_(R_20_ohm), Phi20_(Phi_20_Wb), km_(power_scale), T_C_(p.T0_C)
{
}

void ThermalModel::step(double i_sq_A2, double dt_s)
{
    if (!p_.enabled() || !(dt_s > 0.0)) {
        return;
    }
    // dT/dt = a + b T for the held |i|^2 (thermal.h)
    const double g = km_ * R20_ * i_sq_A2;  // k_m R_20 |i|^2
    const double inv_Rth = 1.0 / p_.R_th_K_per_W;
    const double b = (g * p_.alpha_cu_per_K - inv_Rth) / p_.C_th_J_per_K;
    const double a = (g * (1.0 - kTref_C * p_.alpha_cu_per_K) + p_.T_ambient_C * inv_Rth) / p_.C_th_J_per_K;
    const double z = b * dt_s;
    // phi(z) = expm1(z)/z, 1 at z = 0 (and within rounding below 1e-300)
    const double phi = (std::fabs(z) < 1e-300) ? 1.0 : std::expm1(z) / z;
    T_C_ += (a + b * T_C_) * dt_s * phi;
}

}  // namespace mcsim
