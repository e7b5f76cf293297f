// saturation.cpp - the co-energy saturation model (see saturation.h for
// (S1)-(S3) and their sources).
#include "model/saturation.h"

#include <cmath>

namespace mcsim {

double SaturationParams::i_sat_for_reduction(double i_A, double fraction)
{
    if (!(i_A > 0.0) || !(fraction > 0.0) || !(fraction < 1.0)) {
        return 0.0;
    }
    const double r = 1.0 / (1.0 - fraction);
    return i_A / std::sqrt(r * r - 1.0);
}

Saturation::Saturation(const SaturationParams& p, double L_d0_H, double L_q0_H, double Phi_Wb)
    : L_d0_(L_d0_H),
      L_q0_(L_q0_H),
      Phi_(Phi_Wb),
      inv_2us_(1.0 / (L_d0_H * p.i_sat_A * p.i_sat_A)),
      i_b_(p.i_bias_A > 0.0 ? p.i_bias_A : 0.0),
      c0_(0.0)
{
    if (i_b_ > 0.0) {
        c0_ = L_d0_ * i_b_ / std::sqrt(1.0 + L_d0_ * i_b_ * i_b_ * inv_2us_);
    }
}

double Saturation::u_ratio(double i_d_A, double i_q_A) const
{
    // u_b / u_s = (L_d0 (i_d + i_b)^2 + L_q0 i_q^2) / (2 u_s) (i_b = 0: u/u_s)
    const double id = i_d_A + i_b_;
    return (L_d0_ * id * id + L_q0_ * i_q_A * i_q_A) * inv_2us_;
}

double Saturation::factor(double i_d_A, double i_q_A) const
{
    return 1.0 / std::sqrt(1.0 + u_ratio(i_d_A, i_q_A));
}

void Saturation::flux(double i_d_A, double i_q_A, double* psi_d_Wb, double* psi_q_Wb) const
{
    const double k = factor(i_d_A, i_q_A);
    *psi_d_Wb = Phi_ + k * L_d0_ * (i_d_A + i_b_) - c0_;
    *psi_q_Wb = k * L_q0_ * i_q_A;
}

double Saturation::coenergy_J(double i_d_A, double i_q_A) const
{
    // 2 u_s (sqrt(1 + u/u_s) - 1), written as 2 u_s (u/u_s) / (sqrt(1 + u/u_s) + 1)
    // so it keeps its precision at small currents
    const double x = u_ratio(i_d_A, i_q_A);
    const double w = Phi_ * i_d_A + (x / (std::sqrt(1.0 + x) + 1.0)) / inv_2us_;
    if (i_b_ == 0.0) {
        return w;
    }
    // minus the shift's value at zero current, 2 u_s (sqrt(1 + x0) - 1), and its linear part
    const double x0 = u_ratio(0.0, 0.0);
    return w - (x0 / (std::sqrt(1.0 + x0) + 1.0)) / inv_2us_ - c0_ * i_d_A;
}

void Saturation::incremental(double i_d_A, double i_q_A, double L[3]) const
{
    const double k = factor(i_d_A, i_q_A);
    // k' = dk/du = -k^3 / (2 u_s); L_inc = k diag(L0) + k' b b^T
    const double kp = -k * k * k * inv_2us_;
    const double b_d = L_d0_ * (i_d_A + i_b_);
    const double b_q = L_q0_ * i_q_A;
    L[0] = k * L_d0_ + kp * b_d * b_d;
    L[1] = kp * b_d * b_q;
    L[2] = k * L_q0_ + kp * b_q * b_q;
}

void Saturation::solve(double i_d_A, double i_q_A, double r_d_V, double r_q_V, double* di_d, double* di_q) const
{
    // (S3): (1/k) (r ./ L0 + i (i . r) / (2 u_s)), 1/k = sqrt(1 + u/u_s)
    const double inv_k = std::sqrt(1.0 + u_ratio(i_d_A, i_q_A));
    const double id = i_d_A + i_b_;  // the current the iron sees
    const double ir = (id * r_d_V + i_q_A * r_q_V) * inv_2us_;
    *di_d = inv_k * (r_d_V / L_d0_ + id * ir);
    *di_q = inv_k * (r_q_V / L_q0_ + i_q_A * ir);
}

void Saturation::rates(double i_d_A, double i_q_A, double a_d_V, double a_q_V, double w_e_rad_s, double* di_d,
                       double* di_q, double* psi_d_Wb, double* psi_q_Wb) const
{
    const double inv_k = std::sqrt(1.0 + u_ratio(i_d_A, i_q_A));
    const double k = 1.0 / inv_k;  // factor()'s expression, so the same bits
    const double id = i_d_A + i_b_;  // the current the iron sees
    *psi_d_Wb = Phi_ + k * L_d0_ * id - c0_;
    *psi_q_Wb = k * L_q0_ * i_q_A;
    const double r_d = a_d_V + w_e_rad_s * *psi_q_Wb;
    const double r_q = a_q_V - w_e_rad_s * *psi_d_Wb;
    const double ir = (id * r_d + i_q_A * r_q) * inv_2us_;
    *di_d = inv_k * (r_d / L_d0_ + id * ir);
    *di_q = inv_k * (r_q / L_q0_ + i_q_A * ir);
}

double Saturation::torque_per_np(double i_d_A, double i_q_A) const
{
    // psi_d i_q - psi_q i_d with (S2) and the bias's part (zero without one)
    const double k = factor(i_d_A, i_q_A);
    const double t = Phi_ * i_q_A + k * (L_d0_ - L_q0_) * i_d_A * i_q_A;
    if (i_b_ == 0.0) {
        return t;
    }
    return t + (k * L_d0_ * i_b_ - c0_) * i_q_A;
}

}  // namespace mcsim
