// motor_params.h - physical parameters of a permanent-magnet motor in SI
// units: the 2-phase PM stepper of paper 000 (eq. (1)) or a 3-phase PMSM
// (paper 001 section 5; paper 002 adds saliency, L_q != L_d). One source of
// truth for each motor's values is its file in sim/motors/; this struct is
// what the plant consumes. Both motors are the same alpha-beta physics:
//   L di/dt = v - R i + K w [sin; -cos](n_p theta)  (non-salient),
// with K = n_p Phi; they differ in the winding (2 phases in quadrature, or 3
// in star, seen through amplitude-invariant Clarke) and so in the torque,
// K (m/2) (i_b cos - i_a sin) for m phases.
#ifndef MCSIM_MODEL_MOTOR_PARAMS_H
#define MCSIM_MODEL_MOTOR_PARAMS_H

namespace mcsim {

enum class MotorType { kStepper2, kPmsm3 };

struct MotorParams {
    MotorType type = MotorType::kStepper2;
    double L_H = 0.0;             // phase inductance (the d-axis one, L_d, of a PMSM)
    double L_q_H = 0.0;           // q-axis inductance; 0 = L_H (non-salient)
    double R_ohm = 0.0;           // phase resistance
    double K_Nm_per_A = 0.0;      // back-EMF / torque constant [N m/A = V s/rad]
    double J_kgm2 = 0.0;          // rotor + load inertia
    double fv_Nms_per_rad = 0.0;  // viscous friction
    double coulomb_Nm = 0.0;      // Coulomb friction level (C_r of section 5.3)
    // Coulomb friction is C tanh(omega/omega_s): a smooth stand-in for
    // C sgn(omega) that keeps the ODE Lipschitz so RK4 converges at rest.
    double coulomb_omega_s_rad_s = 0.05;
    int n_p = 1;                  // pole pairs (rotor teeth)
    // LuGre friction, paper 002 eqs. (45)-(46) (sigma0 = 0: none):
    //   dz/dt = w - sigma0 |w| z / g(w),  g(w) = M_c + (M_s - M_c) exp(-(w/w_s)^2)
    //   M_LuGre = sigma0 z + sigma1 dz/dt + sigma2 w
    double lugre_sigma0_Nm_per_rad = 0.0;
    double lugre_sigma1_Nms_per_rad = 0.0;
    double lugre_sigma2_Nms_per_rad = 0.0;
    double lugre_Mc_Nm = 0.0;     // Coulomb level
    double lugre_Ms_Nm = 0.0;     // stiction level
    double lugre_ws_rad_s = 0.0;  // Stribeck speed
    bool lugre() const { return lugre_sigma0_Nm_per_rad > 0.0; }
    // The plant's hardware effects (issue 30; docs/plant.md), none by
    // default: magnetic saturation (model/saturation.h, i_sat_A > 0) and
    // the winding temperature (model/thermal.h): R_ohm and Phi are taken at
    // 20 C; T0_C is the winding's temperature at the start (R and Phi at
    // T0 from t = 0, held there without a thermal model), R_th and C_th the
    // first-order thermal model (both > 0: T follows the copper loss).
    double i_sat_A = 0.0;
    double i_sat_bias_A = 0.0;  // the magnet's bias on the d-axis iron (saturation.h), 0: none
    double R_th_K_per_W = 0.0;
    double C_th_J_per_K = 0.0;
    double T_ambient_C = 20.0;
    double T0_C = 20.0;
    double alpha_cu_per_K = 0.0039;
    double beta_pm_per_K = -0.001;

    int n_phases() const { return type == MotorType::kPmsm3 ? 3 : 2; }
    // Torque per (K i) of the alpha-beta model: m/2 for m phases.
    double torque_scale() const { return type == MotorType::kPmsm3 ? 1.5 : 1.0; }
    double L_q() const { return L_q_H > 0.0 ? L_q_H : L_H; }
    bool salient() const { return L_q() != L_H; }
    // Peak flux linkage per phase [Wb] (K / n_p).
    double Phi_Wb() const { return K_Nm_per_A / static_cast<double>(n_p); }
};

}  // namespace mcsim

#endif  // MCSIM_MODEL_MOTOR_PARAMS_H
