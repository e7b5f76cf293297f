#include "model/pm_plant.h"

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

// sin and cos of |x| <= PmPlant::kSmallAngle_rad by their Taylor
// series in y = x^2, Horner form with the coefficients folded at compile
// time (short series for |x| <= 1/8, the usual case: n_p |dtheta| is 0.1 rad
// over a whole sample at 20 rad/s). The first omitted term stays below
// 3e-18 (short) or 3e-17 (long). Inline: this runs four times per RK4
// sub-step, on the critical path of the stage chain.
inline void small_sincos_inline(double x, double* s, double* c)
{
    const double ax = std::fabs(x);
    if (ax > PmPlant::kSmallAngle_rad) {
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

PmPlant::PmPlant(const MotorParams& motor, const LoadProfile& load, int substeps)
    : m_(motor),
      load_(load),
      substeps_(substeps < 1 ? 1 : substeps),
      inv_L_(1.0 / motor.L_H),
      inv_J_(1.0 / motor.J_kgm2),
      K_over_L_(motor.K_Nm_per_A / motor.L_H),
      K_over_J_(motor.torque_scale() * motor.K_Nm_per_A / motor.J_kgm2),
      inv_ws_(1.0 / motor.coulomb_omega_s_rad_s),
      salient_(motor.salient())
{
}

namespace {
constexpr double kInvSqrt3 = 0.57735026918962576451;
constexpr double kSqrt3_2 = 0.86602540378443864676;
}  // namespace

void PmPlant::step_phases(const double* v_V, double dt_s)
{
    if (m_.n_phases() == 3) {
        // the floating star point removes the zero sequence
        step((2.0 * v_V[0] - v_V[1] - v_V[2]) / 3.0, (v_V[1] - v_V[2]) * kInvSqrt3, dt_s);
    } else {
        step(v_V[0], v_V[1], dt_s);
    }
}

void PmPlant::phase_currents(double* i_A) const
{
    if (m_.n_phases() == 3) {
        i_A[0] = x_[kIa];
        i_A[1] = -0.5 * x_[kIa] + kSqrt3_2 * x_[kIb];
        i_A[2] = -0.5 * x_[kIa] - kSqrt3_2 * x_[kIb];
    } else {
        i_A[0] = x_[kIa];
        i_A[1] = x_[kIb];
    }
}

double PmPlant::torque_Nm() const
{
    const double i_d = cos_e_ * x_[kIa] + sin_e_ * x_[kIb];
    const double i_q = cos_e_ * x_[kIb] - sin_e_ * x_[kIa];
    if (sat_) {
        // k_m n_p (psi_d i_q - psi_q i_d) (saturation.h)
        return m_.torque_scale() * static_cast<double>(m_.n_p) * sat_->torque_per_np(i_d, i_q);
    }
    return m_.torque_scale() * (m_.K_Nm_per_A * i_q + static_cast<double>(m_.n_p) * (m_.L_H - m_.L_q()) * i_d * i_q);
}

void PmPlant::reset(const State& x0, double t0_s)
{
    x_ = x0;
    t_s_ = t0_s;
    const double e = static_cast<double>(m_.n_p) * x_[kTheta];
    sin_e_ = std::sin(e);
    cos_e_ = std::cos(e);
}

void PmPlant::small_sincos(double x, double* s, double* c) { small_sincos_inline(x, s, c); }

void PmPlant::set_locked(bool locked)
{
    locked_ = locked;
    if (locked) {
        x_[kOmega] = 0.0;
    }
}

void PmPlant::set_open_winding(int k)
{
    open_winding_ = (k >= 0 && k < 2 && m_.n_phases() == 2) ? k : -1;
    if (open_winding_ >= 0) {
        x_[open_winding_] = 0.0;  // the winding's current is interrupted
    }
}

namespace {
// LuGre's g(w) and the rate a(w) = sigma0 |w| / g(w) of dz/dt = w - a z
double lugre_g(const MotorParams& m, double w)
{
    const double r = w / m.lugre_ws_rad_s;
    return m.lugre_Mc_Nm + (m.lugre_Ms_Nm - m.lugre_Mc_Nm) * std::exp(-r * r);
}
}  // namespace

double PmPlant::lugre_torque_Nm() const
{
    if (!m_.lugre()) {
        return 0.0;
    }
    const double w = x_[kOmega];
    const double zdot = w - m_.lugre_sigma0_Nm_per_rad * std::fabs(w) * z_ / lugre_g(m_, w);
    return m_.lugre_sigma0_Nm_per_rad * z_ + m_.lugre_sigma1_Nms_per_rad * zdot + m_.lugre_sigma2_Nms_per_rad * w;
}

double PmPlant::load_torque_Nm(double omega_rad_s, double t_s) const
{
    return m_.coulomb_Nm * tanh_fast(omega_rad_s * inv_ws_) + load_.torque_Nm(t_s) + lugre_torque_Nm();
}

double PmPlant::load_torque_Nm() const { return load_torque_Nm(x_[kOmega], t_s_); }

PmPlant::State PmPlant::derivative(const State& x, double t_s, double v_a_V, double v_b_V) const
{
    const double e = static_cast<double>(m_.n_p) * x[kTheta];
    const double s = std::sin(e);
    const double c = std::cos(e);
    const double w = x[kOmega];
    State dx;
    if (sat_ || salient_) {
        if (sat_) {
            saturated_rates(x, s, c, v_a_V, v_b_V, &dx);
        } else {
            salient_rates(x, s, c, v_a_V, v_b_V, &dx);
        }
        dx[kOmega] -= m_.fv_Nms_per_rad * inv_J_ * w + inv_J_ * load_torque_Nm(w, t_s);
        dx[kTheta] = w;
        return dx;
    }
    dx[kIa] = (v_a_V - m_.R_ohm * x[kIa]) * inv_L_ + K_over_L_ * w * s;
    dx[kIb] = (v_b_V - m_.R_ohm * x[kIb]) * inv_L_ - K_over_L_ * w * c;
    dx[kOmega] = K_over_J_ * (x[kIb] * c - x[kIa] * s) - m_.fv_Nms_per_rad * inv_J_ * w
                 - inv_J_ * load_torque_Nm(w, t_s);
    dx[kTheta] = w;
    return dx;
}

void PmPlant::salient_rates(const State& x, double s, double c, double v_a_V, double v_b_V, State* dx) const
{
    // rotor frame (see the header), then back to alpha-beta:
    // d/dt i_ab = e^{J th}(d/dt i_dq) + n_p w J i_ab
    const double np = static_cast<double>(m_.n_p);
    const double we = np * x[kOmega];
    const double Ld = m_.L_H, Lq = m_.L_q(), Phi = m_.Phi_Wb();
    const double i_d = c * x[kIa] + s * x[kIb];
    const double i_q = c * x[kIb] - s * x[kIa];
    const double v_d = c * v_a_V + s * v_b_V;
    const double v_q = c * v_b_V - s * v_a_V;
    const double did = (v_d - m_.R_ohm * i_d + we * Lq * i_q) / Ld;
    const double diq = (v_q - m_.R_ohm * i_q - we * Ld * i_d - we * Phi) / Lq;
    (*dx)[kIa] = c * did - s * diq - we * x[kIb];
    (*dx)[kIb] = s * did + c * diq + we * x[kIa];
    (*dx)[kOmega] = inv_J_ * m_.torque_scale() * np * (Phi * i_q + (Ld - Lq) * i_d * i_q);
}

void PmPlant::saturated_rates(const State& x, double s, double c, double v_a_V, double v_b_V, State* dx) const
{
    // saturation.h: d psi/dt = v - R i - w_e J psi in the rotor frame,
    // di = L_inc^-1 (that), turned back to alpha-beta as salient_rates does
    const double np = static_cast<double>(m_.n_p);
    const double we = np * x[kOmega];
    const double i_d = c * x[kIa] + s * x[kIb];
    const double i_q = c * x[kIb] - s * x[kIa];
    const double v_d = c * v_a_V + s * v_b_V;
    const double v_q = c * v_b_V - s * v_a_V;
    double psi_d;
    double psi_q;
    double did;
    double diq;
    sat_->rates(i_d, i_q, v_d - m_.R_ohm * i_d, v_q - m_.R_ohm * i_q, we, &did, &diq, &psi_d, &psi_q);
    (*dx)[kIa] = c * did - s * diq - we * x[kIb];
    (*dx)[kIb] = s * did + c * diq + we * x[kIa];
    (*dx)[kOmega] = inv_J_ * m_.torque_scale() * np * (psi_d * i_q - psi_q * i_d);
}

void PmPlant::set_saturation(const SaturationParams& p)
{
    if (p.enabled()) {
        sat_.emplace(p, m_.L_H, m_.L_q(), m_.Phi_Wb());
    } else {
        sat_.reset();
    }
    optional_parts_ = sat_.has_value() || thermal_.has_value();
}

void PmPlant::set_thermal(const ThermalParams& p)
{
    if (!p.enabled()) {
        thermal_.reset();
    } else {
        thermal_.emplace(p, m_.R_ohm, m_.Phi_Wb(), m_.torque_scale());
        apply_temperature();
    }
    optional_parts_ = sat_.has_value() || thermal_.has_value();
}

void PmPlant::apply_temperature()
{
    m_.R_ohm = thermal_->R_ohm();
    m_.K_Nm_per_A = static_cast<double>(m_.n_p) * thermal_->Phi_Wb();
    K_over_L_ = m_.K_Nm_per_A / m_.L_H;
    K_over_J_ = m_.torque_scale() * m_.K_Nm_per_A / m_.J_kgm2;
    if (sat_) {
        sat_->set_Phi_Wb(thermal_->Phi_Wb());
    }
}

double PmPlant::accel_rad_s2() const
{
    // eq. (1), third line, with the cached sin/cos of n_p theta
    const double w = x_[kOmega];
    if (salient_ || sat_) {
        return inv_J_ * (torque_Nm() - m_.fv_Nms_per_rad * w - load_torque_Nm(w, t_s_));
    }
    return K_over_J_ * (x_[kIb] * cos_e_ - x_[kIa] * sin_e_) - m_.fv_Nms_per_rad * inv_J_ * w -
           inv_J_ * load_torque_Nm(w, t_s_);
}

void PmPlant::step(double v_a_V, double v_b_V, double dt_s)
{
    if (__builtin_expect(optional_parts_, false)) {
        step_optional(v_a_V, v_b_V, dt_s);
        return;
    }
    step_impl<false>(v_a_V, v_b_V, dt_s);
}

void PmPlant::step_optional(double v_a_V, double v_b_V, double dt_s)
{
    const double i_sq0 = x_[kIa] * x_[kIa] + x_[kIb] * x_[kIb];
    if (sat_) {
        step_impl<true>(v_a_V, v_b_V, dt_s);
    } else {
        step_impl<false>(v_a_V, v_b_V, dt_s);
    }
    if (thermal_) {
        // the copper loss held over the step at the mean of its ends' |i|^2
        const double i_sq1 = x_[kIa] * x_[kIa] + x_[kIb] * x_[kIb];
        thermal_->step(0.5 * (i_sq0 + i_sq1), dt_s);
        apply_temperature();
    }
}

template <bool kSaturated>
void PmPlant::step_impl(double v_a_V, double v_b_V, double dt_s)
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
    const bool has_coulomb = m_.coulomb_Nm != 0.0;
    const bool has_lugre = m_.lugre();
    double T_lugre = 0.0;  // LuGre's torque, held over each sub-step (below)
    const bool faulted = locked_ || open_winding_ >= 0;

    auto f = [&](const State& x, double t) -> State {
        double sd;
        double cd;
        small_sincos_inline(np * (x[kTheta] - theta0), &sd, &cd);
        const double s = s0 * cd + c0 * sd;  // sin(n_p theta)
        const double c = c0 * cd - s0 * sd;  // cos(n_p theta)
        const double w = x[kOmega];
        // no Coulomb friction (a PMSM's motor file): skip the tanh, same value
        double T_ext = has_coulomb ? m_.coulomb_Nm * tanh_fast(w * inv_ws_) : 0.0;
        if (has_load) {
            T_ext += load_.torque_Nm(t);
        }
        T_ext += T_lugre;
        State dx;
        if (salient_) {
            salient_rates(x, s, c, v_a_V, v_b_V, &dx);
            dx[kOmega] -= fv_J * w + inv_J_ * T_ext;
            dx[kTheta] = w;
            if (locked_) {
                dx[kOmega] = 0.0;
                dx[kTheta] = 0.0;
            }
            return dx;
        }
        dx[kIa] = va_L - R_L * x[kIa] + K_over_L_ * w * s;
        dx[kIb] = vb_L - R_L * x[kIb] - K_over_L_ * w * c;
        dx[kOmega] = K_over_J_ * (x[kIb] * c - x[kIa] * s) - fv_J * w - inv_J_ * T_ext;
        dx[kTheta] = w;
        if (faulted) {
            if (locked_) {
                dx[kOmega] = 0.0;
                dx[kTheta] = 0.0;
            }
            if (open_winding_ >= 0) {
                dx[open_winding_] = 0.0;
            }
        }
        return dx;
    };
    // The same through the saturation model (saturation.h), salient or not.
    // A rates function of its own, in an instantiation of its own, so that
    // the default's step stays as it was and is compiled as before (one
    // more branch in f cost 5-7 % of the instructions of paper 001's
    // benchmark, a shared generic RK4 loop still 0.8 %; cachegrind).
    auto fs = [&](const State& x, double t) -> State {
        double sd;
        double cd;
        small_sincos_inline(np * (x[kTheta] - theta0), &sd, &cd);
        const double s = s0 * cd + c0 * sd;
        const double c = c0 * cd - s0 * sd;
        const double w = x[kOmega];
        double T_ext = has_coulomb ? m_.coulomb_Nm * tanh_fast(w * inv_ws_) : 0.0;
        if (has_load) {
            T_ext += load_.torque_Nm(t);
        }
        T_ext += T_lugre;
        State dx;
        saturated_rates(x, s, c, v_a_V, v_b_V, &dx);
        dx[kOmega] -= fv_J * w + inv_J_ * T_ext;
        dx[kTheta] = w;
        if (locked_) {
            dx[kOmega] = 0.0;
            dx[kTheta] = 0.0;
        }
        if (open_winding_ >= 0) {
            dx[open_winding_] = 0.0;
        }
        return dx;
    };

    auto rates = [&](const State& x, double t) -> State {
        if constexpr (kSaturated) {
            return fs(x, t);
        } else {
            return f(x, t);
        }
    };

    const double h = dt_s / static_cast<double>(substeps_);
    const double t0 = t_s_;
    State x = x_;
    for (int k = 0; k < substeps_; ++k) {
        // Stage times from t0 + k h (not an accumulated sum) so that long
        // runs see the load profile at exact times.
        const double t = t0 + static_cast<double>(k) * h;
        // LuGre (paper 002 (45)-(46)) by splitting: its torque at the
        // sub-step's start is held through the RK4 stages; then z, whose
        // dynamics are stiff (sigma0 |w| / g up to 2e4 1/s at 100 rad/s for
        // the reference set), is advanced exactly for the sub-step's mean
        // speed held: z(h) = z_ss + (z - z_ss) exp(-a h), a = sigma0 |w| / g(w),
        // z_ss = w / a (dz/dt = w at w = 0). The splitting is first order in
        // h: [run] substeps refines it (tests/sim/test_plant.cpp).
        const double w0 = x[kOmega];
        if (has_lugre) {
            const double zdot = w0 - m_.lugre_sigma0_Nm_per_rad * std::fabs(w0) * z_ / lugre_g(m_, w0);
            T_lugre = m_.lugre_sigma0_Nm_per_rad * z_ + m_.lugre_sigma1_Nms_per_rad * zdot +
                      m_.lugre_sigma2_Nms_per_rad * w0;
        }
        const State k1 = rates(x, t);
        const State k2 = rates(x + (0.5 * h) * k1, t + 0.5 * h);
        const State k3 = rates(x + (0.5 * h) * k2, t + 0.5 * h);
        const State k4 = rates(x + h * k3, t + h);
        x += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        if (has_lugre) {
            const double wm = 0.5 * (w0 + x[kOmega]);
            const double a = m_.lugre_sigma0_Nm_per_rad * std::fabs(wm) / lugre_g(m_, wm);
            if (a * h < 1e-12) {
                z_ += wm * h;
            } else {
                const double z_ss = wm / a;
                z_ = z_ss + (z_ - z_ss) * std::exp(-a * h);
            }
        }
    }
    // A state that decays towards zero (a rotor coming to rest, a current
    // dying out) would otherwise end in subnormal numbers after a few
    // hundred seconds of hold, and every operation on them costs tens of
    // cycles on x86 (long runs slowed down tenfold): below kStateFloor a
    // component is zero. 1e-200 of an ampere, a radian or a rad/s is far
    // below anything the model resolves (double's epsilon at 1 is 2e-16).
    for (int i = 0; i < 4; ++i) {
        if (std::fabs(x[i]) < kStateFloor) {
            x[i] = 0.0;
        }
    }
    x_ = x;
    t_s_ = t0 + dt_s;
    // Fresh from libm (not rotated) so no error accumulates over a run.
    sin_e_ = std::sin(np * x_[kTheta]);
    cos_e_ = std::cos(np * x_[kTheta]);
}

}  // namespace mcsim
