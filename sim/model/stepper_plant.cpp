#include "model/stepper_plant.h"

#include <cmath>

namespace mcsim {
namespace {

// tanh(x) rounds to exactly +-1 in double for |x| > 19.1; skipping the libm
// call there changes no bit and makes the friction term nearly free away
// from rest, where the rotor spends most of a run.
inline double tanh_fast(double x)
{
    if (x > 19.5) {
        return 1.0;
    }
    if (x < -19.5) {
        return -1.0;
    }
    return std::tanh(x);
}

// sin and cos of |x| <= StepperPlant::kSmallAngle_rad by their Taylor
// series in y = x^2, Horner form with the coefficients folded at compile
// time (short series for |x| <= 1/8, the usual case: n_p |dtheta| is 0.1 rad
// over a whole sample at 20 rad/s). The first omitted term stays below
// 3e-18 (short) or 3e-17 (long). Inline: this runs four times per RK4
// sub-step, on the critical path of the stage chain.
inline void small_sincos_inline(double x, double* s, double* c)
{
    const double ax = std::fabs(x);
    if (ax > StepperPlant::kSmallAngle_rad) {
        *s = std::sin(x);
        *c = std::cos(x);
        return;
    }
    // (-1)^k / (2k+1)! and (-1)^k / (2k)!
    constexpr double S1 = -1.0 / 6.0, S2 = 1.0 / 120.0, S3 = -1.0 / 5040.0, S4 = 1.0 / 362880.0,
                     S5 = -1.0 / 39916800.0, S6 = 1.0 / 6227020800.0;
    constexpr double C1 = -1.0 / 2.0, C2 = 1.0 / 24.0, C3 = -1.0 / 720.0, C4 = 1.0 / 40320.0,
                     C5 = -1.0 / 3628800.0, C6 = 1.0 / 479001600.0, C7 = -1.0 / 87178291200.0;
    const double y = x * x;
    if (ax <= 0.125) {
        // to x^9 / x^10: omitted x^11/11! < 3e-18, x^12/12! < 2e-19
        *s = x + x * y * (S1 + y * (S2 + y * (S3 + y * S4)));
        *c = 1.0 + y * (C1 + y * (C2 + y * (C3 + y * (C4 + y * C5))));
        return;
    }
    // to x^13 / x^14: omitted x^15/15! < 3e-17, x^16/16! < 1e-18
    *s = x + x * y * (S1 + y * (S2 + y * (S3 + y * (S4 + y * (S5 + y * S6)))));
    *c = 1.0 + y * (C1 + y * (C2 + y * (C3 + y * (C4 + y * (C5 + y * (C6 + y * C7))))));
}

}  // namespace

StepperPlant::StepperPlant(const MotorParams& motor, const LoadProfile& load, int substeps)
    : m_(motor),
      load_(load),
      substeps_(substeps < 1 ? 1 : substeps),
      inv_L_(1.0 / motor.L_H),
      inv_J_(1.0 / motor.J_kgm2),
      K_over_L_(motor.K_Nm_per_A / motor.L_H),
      K_over_J_(motor.K_Nm_per_A / motor.J_kgm2),
      C_over_J_(motor.coulomb_Nm / motor.J_kgm2),
      inv_ws_(1.0 / motor.coulomb_omega_s_rad_s)
{
}

void StepperPlant::reset(const State& x0, double t0_s)
{
    x_ = x0;
    t_s_ = t0_s;
    const double e = static_cast<double>(m_.n_p) * x_[kTheta];
    sin_e_ = std::sin(e);
    cos_e_ = std::cos(e);
}

void StepperPlant::small_sincos(double x, double* s, double* c) { small_sincos_inline(x, s, c); }

double StepperPlant::load_torque_Nm(double omega_rad_s, double t_s) const
{
    return m_.coulomb_Nm * tanh_fast(omega_rad_s * inv_ws_) + load_.torque_Nm(t_s);
}

double StepperPlant::load_torque_Nm() const { return load_torque_Nm(x_[kOmega], t_s_); }

StepperPlant::State StepperPlant::derivative(const State& x, double t_s, double v_a_V, double v_b_V) const
{
    const double e = static_cast<double>(m_.n_p) * x[kTheta];
    const double s = std::sin(e);
    const double c = std::cos(e);
    const double w = x[kOmega];
    State dx;
    dx[kIa] = (v_a_V - m_.R_ohm * x[kIa]) * inv_L_ + K_over_L_ * w * s;
    dx[kIb] = (v_b_V - m_.R_ohm * x[kIb]) * inv_L_ - K_over_L_ * w * c;
    dx[kOmega] = K_over_J_ * (x[kIb] * c - x[kIa] * s) - m_.fv_Nms_per_rad * inv_J_ * w
                 - inv_J_ * load_torque_Nm(w, t_s);
    dx[kTheta] = w;
    return dx;
}

double StepperPlant::accel_rad_s2() const
{
    // eq. (1), third line, with the cached sin/cos of n_p theta
    const double w = x_[kOmega];
    return K_over_J_ * (x_[kIb] * cos_e_ - x_[kIa] * sin_e_) - m_.fv_Nms_per_rad * inv_J_ * w -
           inv_J_ * load_torque_Nm(w, t_s_);
}

void StepperPlant::step(double v_a_V, double v_b_V, double dt_s)
{
    // sin/cos of the electrical angle come from libm once per call (cached
    // with the state); the RK4 stages rotate them by the small change of
    // n_p*theta within the step (|n_p dtheta| = 0.1 rad at 20 rad/s over
    // 100 us), which keeps the inner loop free of transcendental calls.
    const double np = static_cast<double>(m_.n_p);
    const double theta0 = x_[kTheta];
    const double s0 = sin_e_;
    const double c0 = cos_e_;
    const double va_L = v_a_V * inv_L_;
    const double vb_L = v_b_V * inv_L_;
    const double R_L = m_.R_ohm * inv_L_;
    const double fv_J = m_.fv_Nms_per_rad * inv_J_;
    const bool has_load = !load_.empty();

    auto f = [&](const State& x, double t) -> State {
        double sd;
        double cd;
        small_sincos_inline(np * (x[kTheta] - theta0), &sd, &cd);
        const double s = s0 * cd + c0 * sd;  // sin(n_p theta)
        const double c = c0 * cd - s0 * sd;  // cos(n_p theta)
        const double w = x[kOmega];
        double T_ext = m_.coulomb_Nm * tanh_fast(w * inv_ws_);
        if (has_load) {
            T_ext += load_.torque_Nm(t);
        }
        State dx;
        dx[kIa] = va_L - R_L * x[kIa] + K_over_L_ * w * s;
        dx[kIb] = vb_L - R_L * x[kIb] - K_over_L_ * w * c;
        dx[kOmega] = K_over_J_ * (x[kIb] * c - x[kIa] * s) - fv_J * w - inv_J_ * T_ext;
        dx[kTheta] = w;
        return dx;
    };

    const double h = dt_s / static_cast<double>(substeps_);
    const double t0 = t_s_;
    State x = x_;
    for (int k = 0; k < substeps_; ++k) {
        // Stage times from t0 + k h (not an accumulated sum) so that long
        // runs see the load profile at exact times.
        const double t = t0 + static_cast<double>(k) * h;
        const State k1 = f(x, t);
        const State k2 = f(x + (0.5 * h) * k1, t + 0.5 * h);
        const State k3 = f(x + (0.5 * h) * k2, t + 0.5 * h);
        const State k4 = f(x + h * k3, t + h);
        x += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    x_ = x;
    t_s_ = t0 + dt_s;
    // Fresh from libm (not rotated) so no error accumulates over a run.
    sin_e_ = std::sin(np * x_[kTheta]);
    cos_e_ = std::cos(np * x_[kTheta]);
}

}  // namespace mcsim
