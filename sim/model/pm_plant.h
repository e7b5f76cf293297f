// pm_plant.h - the 2-phase PM stepper of paper 000, eq. (1), as a
// continuous-time plant integrated between control samples.
//
//   L di_a/dt = v_a - R i_a + K w sin(n_p theta)
//   L di_b/dt = v_b - R i_b - K w cos(n_p theta)
//   J dw/dt   = k_m K (i_b cos(n_p theta) - i_a sin(n_p theta)) - f_v w
//               - C tanh(w / w_s) - T_load(t)
//   dtheta/dt = w
// with k_m = 1 for two phases and 3/2 for three (amplitude-invariant
// Clarke: the power of three phases is 3/2 that of the alpha-beta pair).
// A salient motor (L_q != L_d, paper 002) is integrated in the rotor frame,
//   L_d di_d/dt = v_d - R i_d + n_p w L_q i_q,
//   L_q di_q/dt = v_q - R i_q - n_p w L_d i_d - n_p w Phi,
//   torque = k_m n_p (Phi i_q + (L_d - L_q) i_d i_q),
// and turned back to alpha-beta, so the state and the interface are the same.
// Optional (issue 30; absent, the equations above bit for bit): magnetic
// saturation and cross-saturation, the same rotor-frame integration with
// the flux linkages of model/saturation.h (set_saturation), and a winding
// temperature that R and Phi follow (model/thermal.h, set_thermal).
//
// Phases: the stepper's windings are driven by their own H-bridges
// (v_a, v_b are the winding voltages); the PMSM's legs are voltages about
// the DC-bus midpoint and the star point floats, so only the differential
// part reaches the windings: v_alpha = (2 v_a - v_b - v_c)/3,
// v_beta = (v_b - v_c)/sqrt(3), and the phase currents are the inverse
// Clarke of the state (they sum to zero).
//
// The voltages are held over a step (zero-order hold, as the DAC and the
// linear amplifiers of section 5.3 do) and the ODE, smooth within a step, is
// integrated with classical RK4 on `substeps` equal sub-steps. The system is
// not stiff at these parameters (L/R = 3 ms, J/f_v = 0.13 s; the steepest
// mode is the tanh friction near rest, C/(w_s J) = 4.7e3 1/s, i.e. h*lambda
// = 0.05 at 10 us), so an explicit method is the cheap and accurate choice.
#ifndef MCSIM_MODEL_PM_PLANT_H
#define MCSIM_MODEL_PM_PLANT_H

#include <optional>

#include <Eigen/Core>

#include "model/load_profile.h"
#include "model/motor_params.h"
#include "model/saturation.h"
#include "model/thermal.h"

namespace mcsim {

class PmPlant {
public:
    // x = [i_a [A], i_b [A], omega [rad/s], theta [rad]]
    using State = Eigen::Matrix<double, 4, 1>;
    enum : int { kIa = 0, kIb = 1, kOmega = 2, kTheta = 3 };

    // RK4 sub-steps per 100 us sample unless a scenario says otherwise
    // ([run] substeps). Over the paper-000 trajectory (open loop, eq. (68)
    // voltages) theta moves by 1.6e-9 rad between 1 and 2 sub-steps, 1e-10
    // rad between 2 and 4, and 1.7e-9 rad between 1 and 64: the ODE is
    // smooth within a sample (voltages held) and far from stiff, so one RK4
    // step per sample is already accurate to far below anything the drive
    // can resolve, and the closed-loop metrics agree to 1e-10 rad. One step
    // costs ~0.12 us, about as much as the rest of the loop without the
    // drive; the drive itself takes ~0.17 us per sample. The step-halving
    // test (tests/sim/test_plant.cpp) keeps this value honest (< 1e-5 rad
    // against twice as many sub-steps).
    static constexpr int kDefaultSubsteps = 1;
    // States below this magnitude are set to zero after each step (no
    // subnormal numbers in long holds; see step()).
    static constexpr double kStateFloor = 1e-200;

    PmPlant(const MotorParams& motor, const LoadProfile& load, int substeps);

    void reset(const State& x0, double t0_s = 0.0);

    // Advances the plant by dt_s with the alpha-beta voltages v_a_V (alpha),
    // v_b_V (beta) held constant.
    void step(double v_a_V, double v_b_V, double dt_s);

    // The same from the phase voltages (2 winding voltages, or 3 leg
    // voltages about the bus midpoint), n_phases() of them.
    void step_phases(const double* v_V, double dt_s);
    // The phase currents, n_phases() of them.
    void phase_currents(double* i_A) const;
    int n_phases() const { return m_.n_phases(); }
    // Electromagnetic torque of the current state [N m].
    double torque_Nm() const;

    // Right-hand side of eq. (1), evaluated with std::sin/std::cos (the
    // reference the fast in-step evaluation is tested against).
    State derivative(const State& x, double t_s, double v_a_V, double v_b_V) const;

    // dw/dt of the current state; it does not depend on the voltages.
    double accel_rad_s2() const;
    // Everything that brakes the rotor besides viscous friction, as the
    // drive's load estimate sees it: C tanh(w/w_s) + T_load(t) [N m].
    double load_torque_Nm() const;
    // The same, for an arbitrary speed and time.
    double load_torque_Nm(double omega_rad_s, double t_s) const;

    // The LuGre friction of the current state (0 without LuGre) [N m] and
    // its bristle deflection z [rad] (paper 002 (45)-(46)); part of
    // load_torque_Nm().
    double lugre_torque_Nm() const;
    double lugre_z_rad() const { return z_; }

    const State& state() const { return x_; }
    double time_s() const { return t_s_; }
    double i_a_A() const { return x_[kIa]; }
    double i_b_A() const { return x_[kIb]; }
    double omega_rad_s() const { return x_[kOmega]; }
    double theta_rad() const { return x_[kTheta]; }

    // sin and cos of the electrical angle n_p theta of the current state,
    // kept with the state (one libm call per step serves the next step, the
    // acceleration and the loggers).
    double sin_elec() const { return sin_e_; }
    double cos_elec() const { return cos_e_; }

    // Injected faults (model/fault_injection.h): the rotor held where it is
    // (speed 0, angle frozen); a winding opened (stepper2: its current is 0
    // and stays 0; -1 closes them all again).
    void set_locked(bool locked);
    void set_open_winding(int k);
    // A prescribed speed (plant_replay's speed trajectory): the state's speed
    // set to omega; with an inertia of 1e30 it holds over the next step.
    void set_speed(double omega_rad_s) { x_[kOmega] = omega_rad_s; }

    const MotorParams& motor() const { return m_; }

    // Magnetic saturation and cross-saturation (model/saturation.h): from
    // now on the currents follow the co-energy model built on the motor's
    // L_d, L_q and Phi; p.enabled() false (i_sat 0) restores the linear
    // equations, bit for bit today's. Call before reset() or between steps.
    void set_saturation(const SaturationParams& p);
    bool saturated() const { return sat_.has_value(); }
    // The saturation model in use, or nullptr.
    const Saturation* saturation() const { return sat_ ? &*sat_ : nullptr; }
    // The winding's temperature (model/thermal.h): from now on R and Phi
    // follow it, advanced after each step() with the mean of |i_ab|^2 at
    // the step's start and end (the loss held over the step; the thermal
    // time constants are seconds to minutes, a step 100 us). The motor's
    // R and Phi as given are taken as R_20 and Phi_20; R and Phi are set to
    // their values at T0 at once. p.enabled() false: none (R and Phi as given).
    void set_thermal(const ThermalParams& p);
    // The thermal model in use, or nullptr.
    const ThermalModel* thermal() const { return thermal_ ? &*thermal_ : nullptr; }
    int substeps() const { return substeps_; }
    void set_substeps(int n) { substeps_ = (n < 1) ? 1 : n; }

    // sin and cos of a small angle |x| <= kSmallAngle_rad by their Taylor
    // series (error < 1e-16); larger angles fall back to libm. Public so the
    // tests can check it.
    static void small_sincos(double x, double* s, double* c);
    static constexpr double kSmallAngle_rad = 0.5;

private:
    MotorParams m_;
    LoadProfile load_;
    int substeps_;
    State x_ = State::Zero();
    double t_s_ = 0.0;
    double sin_e_ = 0.0, cos_e_ = 1.0;
    // Folded constants: 1/L, 1/J, K/L, k_m K/J, 1/w_s.
    double inv_L_, inv_J_, K_over_L_, K_over_J_, inv_ws_;
    bool salient_;
    double z_ = 0.0;  // LuGre bristle deflection
    bool locked_ = false;
    int open_winding_ = -1;
    // alpha-beta current rates and the electromagnetic part of dw/dt of a
    // salient motor at state x with sin/cos s, c of the electrical angle
    void salient_rates(const State& x, double s, double c, double v_a_V, double v_b_V, State* dx) const;
    // the same through the saturation model (saturation.h's rotor-frame
    // equations), salient or not
    void saturated_rates(const State& x, double s, double c, double v_a_V, double v_b_V, State* dx) const;
    // step() of the plant with the optional parts (saturation, temperature)
    void step_optional(double v_a_V, double v_b_V, double dt_s);
    // the RK4 step itself, linear (the default) or saturated
    template <bool kSaturated>
    void step_impl(double v_a_V, double v_b_V, double dt_s);
    bool optional_parts_ = false;  // sat_ or thermal_ set: step() takes step_optional
    std::optional<Saturation> sat_;
    std::optional<ThermalModel> thermal_;
    // R and Phi (K = n_p Phi) from the thermal model, with the folded constants
    void apply_temperature();
};

}  // namespace mcsim

#endif  // MCSIM_MODEL_PM_PLANT_H
