// thermal.h - a first-order thermal model of the winding (issue 30): its
// temperature driven by the copper loss, the winding resistance and the
// magnet's flux linkage following it.
//
//   C_th dT/dt = P_cu - (T - T_amb) / R_th,   P_cu = k_m R(T) |i_ab|^2     (T1)
//   R(T)   = R_20 (1 + alpha_Cu (T - 20 C)),    alpha_Cu = +0.0039 1/K     (T2)
//   Phi(T) = Phi_20 (1 + beta_PM (T - 20 C)),   beta_PM  = -0.001 1/K      (T3)
//
// One lumped node (winding and magnet at one temperature: a simplification
// that overstates how fast the magnet warms; its own node would lag behind
// the winding's). |i_ab|^2 = i_alpha^2 + i_beta^2 of the plant's state and
// k_m its power factor (1 for two phases, 3/2 for three in the
// amplitude-invariant Clarke frame: model/motor_params.h), so
// k_m R |i_ab|^2 is the total copper loss of the phases. Iron and friction
// losses are not counted.
//
// Sources of the coefficients: alpha_Cu, the temperature coefficient of
// resistance of annealed copper at 20 C, 3930 ppm/K (International
// Annealed Copper Standard: 3.93e-3 1/K at 100 % IACS conductivity, K. C.
// Agrawal, "Industrial Power Engineering and Applications Handbook",
// Newnes 2001, table of conductor properties, p. 970; the same 3930 ppm/K
// quoted from the IEICE handbook in Hioki's RM3545 manual, appendix 4);
// 0.0039 is the rounding. beta_PM, the reversible temperature
// coefficient of the remanence B_r of sintered NdFeB, -0.09 to -0.12 %/K
// by grade (Advanced Magnets' note "What are temperature coefficients
// alpha and beta of permanent magnets"; e-magnetsuk's NdFeB temperature
// table: -0.12 %/K for N/M grades, -0.10 %/K for SH); -0.1 %/K is the
// issue's value. Phi is proportional to B_r at a fixed magnetic circuit.
//
// The step advances (T1) exactly for a current magnitude held over the step:
// with R(T) linear in T, (T1) is dT/dt = a + b T,
//   b = (k_m R_20 alpha_Cu |i|^2 - 1/R_th) / C_th,
//   a = (k_m R_20 (1 - 20 alpha_Cu) |i|^2 + T_amb/R_th) / C_th,
// whose solution over h is T + (a + b T) h phi(b h), phi(z) = (e^z - 1)/z
// (computed with expm1; phi(0) = 1). For b < 0 it is the familiar
// first-order approach to T_inf = -a/b with the time constant -1/b, which
// is R_th C_th at zero current; b > 0 is thermal runaway (the copper's
// rising resistance heats faster than R_th cools), followed, not refused.
#ifndef MCSIM_MODEL_THERMAL_H
#define MCSIM_MODEL_THERMAL_H

namespace mcsim {

struct ThermalParams {
    double R_th_K_per_W = 0.0;    // winding to ambient; 0: no thermal model (R, Phi constant)
    double C_th_J_per_K = 0.0;    // heat capacity of the winding node
    double T_ambient_C = 20.0;    // coolant / ambient temperature
    double T0_C = 20.0;           // the winding's (and magnet's) temperature at the start
    double alpha_cu_per_K = 0.0039;   // (T2)
    double beta_pm_per_K = -0.001;    // (T3)
    bool enabled() const { return R_th_K_per_W > 0.0 && C_th_J_per_K > 0.0; }
    // nullptr, or the first problem (R_th or C_th negative or only one set,
    // a temperature below absolute zero, a non-finite value).
    const char* problem() const;
};

class ThermalModel {
public:
    // The reference temperature of R_20 and Phi_20 (the motor file's values).
    static constexpr double kTref_C = 20.0;
    // No temperature below it [C].
    static constexpr double kAbsoluteZero_C = -273.15;

    // R_20_ohm, Phi_20_Wb: the motor file's R and Phi, taken at 20 C;
    // power_scale: k_m of (T1).
    ThermalModel(const ThermalParams& p, double R_20_ohm, double Phi_20_Wb, double power_scale);

    void reset() { T_C_ = p_.T0_C; }
    // Advances (T1) over dt_s with |i_ab|^2 = i_sq_A2 held.
    void step(double i_sq_A2, double dt_s);

    double temperature_C() const { return T_C_; }
    double R_ohm() const { return R20_ * (1.0 + p_.alpha_cu_per_K * (T_C_ - kTref_C)); }
    double Phi_Wb() const { return Phi20_ * (1.0 + p_.beta_pm_per_K * (T_C_ - kTref_C)); }
    // The copper loss at the current temperature for |i_ab|^2 [W].
    double copper_loss_W(double i_sq_A2) const { return km_ * R_ohm() * i_sq_A2; }
    const ThermalParams& params() const { return p_; }

private:
    ThermalParams p_;
    double R20_, Phi20_, km_;
    double T_C_;
};

}  // namespace mcsim

#endif  // MCSIM_MODEL_THERMAL_H
