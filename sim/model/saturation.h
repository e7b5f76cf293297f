// saturation.h - magnetic saturation and cross-saturation of a PM machine's
// stator iron (issue 30), one analytic model derived from a co-energy so
// that it stays energy-consistent, for the salient PMSM (L_d0 != L_q0) and
// the non-salient motors alike (the stepper's L(i) is the case L_d0 = L_q0).
//
// Co-energy of the rotor-frame currents (i_d, i_q) (the magnet's part and a
// saturating armature part of the linear co-energy u):
//
//   u(i)  = (L_d0 i_d^2 + L_q0 i_q^2) / 2,        u_s = L_d0 i_sat^2 / 2,
//   W'(i) = Phi i_d + 2 u_s (sqrt(1 + u/u_s) - 1)                        (S1)
//
// The flux linkages are its gradient, psi = dW'/di (which makes the
// incremental inductance matrix a Hessian, hence symmetric: the reciprocity
// d psi_d / d i_q = d psi_q / d i_d that any lossless magnetic model must
// keep; A. E. Fitzgerald, C. Kingsley, S. D. Umans, "Electric Machinery",
// 6th ed., McGraw-Hill 2003, chapter 3: energy, co-energy and the forces
// and torques derived from them):
//
//   k(u)  = dW'/du = 1 / sqrt(1 + u/u_s)             (the saturation factor)
//   psi_d = Phi + k L_d0 i_d,   psi_q = k L_q0 i_q                      (S2)
//
// so the apparent (secant) inductances are L_d = k L_d0, L_q = k L_q0:
// both fall by the same factor, which depends on both currents. That is how
// cross-saturation enters: i_q lowers L_d and i_d lowers L_q, through the
// one energy of the shared iron. Along the d axis (i_q = 0),
// x = i_d / i_sat:  L_d = L_d0 / sqrt(1 + x^2) (L_d0/sqrt(2) at i_sat), and
// psi_d - Phi = L_d0 i_d / sqrt(1 + x^2), monotonic and bounded by
// L_d0 i_sat (the iron's limit); the incremental inductance is
// d psi_d/d i_d = L_d0 / (1 + x^2)^(3/2) (L_d0 / 2^(3/2) at i_sat). (The
// simpler L = L0 / (1 + x^2) as an apparent inductance would make the flux
// fall above i_sat, a negative incremental inductance; the square root
// keeps it positive everywhere.) The q axis saturates at
// i_sat sqrt(L_d0/L_q0): earlier on an interior PMSM (L_q0 > L_d0), as the
// q-axis path, with no magnet in it, does.
//
// Incremental inductance matrix (the Hessian of (S1), k' = dk/du = -k^3/(2 u_s)):
//   L_inc = k diag(L_d0, L_q0) + k' b b^T,   b = (L_d0 i_d, L_q0 i_q)
// and its inverse applied to a voltage r in closed form (Sherman-Morrison;
// the denominator 1 + (k'/k) 2u simplifies to k^2):
//   L_inc^-1 r = (1/k) (diag(1/L_d0, 1/L_q0) r + i (i . r) / (2 u_s))   (S3)
// one square root, no matrix solve per evaluation.
//
// The plant (model/pm_plant.h) then integrates, in the rotor frame,
//   d psi/dt = v - R i - w_e J psi  ->  di/dt = L_inc^-1 (v - R i - w_e J psi),
//   (r_d = v_d - R i_d + w_e psi_q, r_q = v_q - R i_q - w_e psi_d)
// with the torque k_m n_p (psi_d i_q - psi_q i_d) = k_m n_p (Phi i_q +
// k (L_d0 - L_q0) i_d i_q), the co-energy's derivative in the rotor angle
// (Fitzgerald et al. chapter 3 again), so the electrical power in equals
// R i^2 + dW/dt + T w with W = i.psi - W' the stored field energy.
// The magnet's bias (i_bias_A > 0, optional): the magnet's flux also runs
// through the stator's d-axis iron, so that iron is already part saturated
// at zero current and saturates further when i_d adds to the magnet than
// when it opposes it (what the polarity test of HF-injection drives reads:
// estimators/magnet_polarity.h). Modelled by shifting the d current the
// iron sees by i_b, the magnet's bias expressed as a d-axis current, in the
// saturating part of (S1), and taking off the linear part that shift adds
// at zero current, so that psi_d(0) stays Phi:
//   u_b(i) = (L_d0 (i_d + i_b)^2 + L_q0 i_q^2) / 2,   k_b = 1/sqrt(1 + u_b/u_s),
//   W'(i)  = Phi i_d + 2 u_s (sqrt(1 + u_b/u_s) - sqrt(1 + u_b(0)/u_s)) - k_b(0) L_d0 i_b i_d
//   psi_d  = Phi + L_d0 (k_b (i_d + i_b) - k_b(0) i_b),   psi_q = k_b L_q0 i_q
// The Hessian, and so (S3), is that of (S1) with i_d + i_b in place of i_d
// (the linear term has none). The incremental L_d at zero current is then
// L_d0 / (1 + (i_b/i_sat)^2)^(3/2): L_d0 is the unbiased iron's, and a
// scenario that gives a bias states how it chose L_d0 and i_b. i_b = 0:
// (S1)-(S3) as above, bit for bit.
// Not modelled: the magnet's operating point moving with i_d (Phi does not
// saturate), iron losses, hysteresis.
//
// i_sat = 0 (the default): no saturation; the plant keeps its linear
// equations and gives exactly today's results.
#ifndef MCSIM_MODEL_SATURATION_H
#define MCSIM_MODEL_SATURATION_H

namespace mcsim {

struct SaturationParams {
    // The d-axis current (with i_q = 0) at which the apparent L_d has fallen
    // to L_d0 / sqrt(2) [A]; 0: linear (no saturation).
    double i_sat_A = 0.0;
    // The magnet's bias on the d-axis iron as a d current [A] (see above;
    // 0: none, the iron's saturation even in i_d).
    double i_bias_A = 0.0;
    bool enabled() const { return i_sat_A > 0.0; }
    // The i_sat that makes the apparent inductance of a non-salient motor
    // (1 - fraction) L0 at the current magnitude i_A (e.g. 20 % at i_max):
    //   1/sqrt(1 + (i/i_sat)^2) = 1 - f  ->  i_sat = i / sqrt(1/(1-f)^2 - 1).
    // fraction in (0, 1), i_A > 0; anything else gives 0 (linear).
    static double i_sat_for_reduction(double i_A, double fraction);
};

class Saturation {
public:
    // L_d0_H, L_q0_H: the unsaturated inductances (the motor file's, i.e.
    // the linear model's); Phi_Wb: the magnet's flux linkage. p.i_sat_A > 0.
    Saturation(const SaturationParams& p, double L_d0_H, double L_q0_H, double Phi_Wb);

    // u(i) / u_s of (S1) and the factor k = 1/sqrt(1 + u/u_s) of (S2).
    double u_ratio(double i_d_A, double i_q_A) const;
    double factor(double i_d_A, double i_q_A) const;
    // Apparent inductances k L_d0, k L_q0 [H].
    double L_d_H(double i_d_A, double i_q_A) const { return factor(i_d_A, i_q_A) * L_d0_; }
    double L_q_H(double i_d_A, double i_q_A) const { return factor(i_d_A, i_q_A) * L_q0_; }
    // Flux linkages (S2) [Wb].
    void flux(double i_d_A, double i_q_A, double* psi_d_Wb, double* psi_q_Wb) const;
    // Co-energy (S1) [J].
    double coenergy_J(double i_d_A, double i_q_A) const;
    // Incremental inductance matrix d psi / d i: L[0] = dd, L[1] = dq = qd,
    // L[2] = qq [H].
    void incremental(double i_d_A, double i_q_A, double L[3]) const;
    // (S3): the current rates di = L_inc^-1 r for the voltage r [V].
    void solve(double i_d_A, double i_q_A, double r_d_V, double r_q_V, double* di_d, double* di_q) const;
    // The plant's rates in one pass (one square root): the flux linkages
    // (S2), then (S3) for r = (a_d + w_e psi_q, a_q - w_e psi_d), the rotor
    // frame's d psi/dt with a = v - R i; bit for bit flux() then solve().
    void rates(double i_d_A, double i_q_A, double a_d_V, double a_q_V, double w_e_rad_s, double* di_d,
               double* di_q, double* psi_d_Wb, double* psi_q_Wb) const;
    // The electromagnetic torque per k_m n_p: psi_d i_q - psi_q i_d [Wb A].
    double torque_per_np(double i_d_A, double i_q_A) const;

    double Phi_Wb() const { return Phi_; }
    void set_Phi_Wb(double Phi_Wb) { Phi_ = Phi_Wb; }

private:
    double L_d0_, L_q0_, Phi_;
    double inv_2us_;  // 1 / (2 u_s) = 1 / (L_d0 i_sat^2)
    double i_b_;      // the magnet's bias, i_b
    double c0_;       // k_b(0) L_d0 i_b: psi_d's offset at zero current (0 without a bias)
};

}  // namespace mcsim

#endif  // MCSIM_MODEL_SATURATION_H
