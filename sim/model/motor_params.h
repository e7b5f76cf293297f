// motor_params.h - physical parameters of the 2-phase PM stepper of paper 000,
// eq. (1), in SI units. One source of truth for the rig's values is
// sim/motors/paper000_stepper.toml; this struct is what the plant consumes.
#ifndef MCSIM_MODEL_MOTOR_PARAMS_H
#define MCSIM_MODEL_MOTOR_PARAMS_H

namespace mcsim {

struct MotorParams {
    double L_H = 0.0;             // phase inductance
    double R_ohm = 0.0;           // phase resistance
    double K_Nm_per_A = 0.0;      // back-EMF / torque constant [N m/A = V s/rad]
    double J_kgm2 = 0.0;          // rotor + load inertia
    double fv_Nms_per_rad = 0.0;  // viscous friction
    double coulomb_Nm = 0.0;      // Coulomb friction level (C_r of section 5.3)
    // Coulomb friction is C tanh(omega/omega_s): a smooth stand-in for
    // C sgn(omega) that keeps the ODE Lipschitz so RK4 converges at rest.
    double coulomb_omega_s_rad_s = 0.05;
    int n_p = 1;                  // pole pairs (rotor teeth)
};

}  // namespace mcsim

#endif  // MCSIM_MODEL_MOTOR_PARAMS_H
