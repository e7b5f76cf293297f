/*
 * motor_design.h - the one design input for the motor, shared by the
 * designs of paper 000 (paper000_design.h), paper 001 (paper001_design.h),
 * paper 002 (paper002_design.h) and the sensored FOC drive
 * (sensored_foc_design.h): the motor the drive believes in, in
 * SI and double precision, filled once from the scenario's motor
 * ([drive_model], sim/scenario/design_input.cpp) and folded by each
 * design into the firmware's one motor model (model/motor_model.h) and
 * its gains. What each design reads of it:
 *   paper 000 (2-phase stepper): L_H, R_ohm, K_Nm_per_A, J_kgm2,
 *     fv_Nms_per_rad, n_p, coulomb_Nm (the load bound's default);
 *   paper 001 (non-salient PMSM or stepper): n_phases, R_ohm, L_H,
 *     Phi = K_Nm_per_A / n_p, n_p, J_kgm2 (its model (3) has no
 *     friction: the speed loop and the load estimate take it);
 *   paper 002 (interior PMSM): R_ohm, L_d = L_H, L_q_H, psi = Phi, n_p,
 *     J_kgm2, d = fv_Nms_per_rad;
 *   the sensored FOC drive (PMSM): n_p, R_ohm, L_d = L_H, L_q_H,
 *     psi = Phi, J_kgm2 (friction: its speed loop's integral and its load
 *     estimate take it).
 * The field order begins as paper 000's former motor struct's (L, R, K,
 * J, f_v, n_p, Coulomb), so its aggregate initialisers keep their meaning.
 */
#ifndef DESIGN_MOTOR_DESIGN_H
#define DESIGN_MOTOR_DESIGN_H

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    double L_H;              /* phase inductance (alpha-beta model); L_d of a salient PMSM */
    double R_ohm;            /* phase resistance */
    double K_Nm_per_A;       /* back-EMF constant K = n_p Phi [V s/rad = N m/A per (m/2)] */
    double J_kgm2;           /* rotor and load inertia */
    double fv_Nms_per_rad;   /* viscous friction f_v (paper 002's d) */
    int n_p;                 /* pole pairs (rotor teeth of a stepper) */
    double coulomb_Nm;       /* Coulomb friction level: paper 000's load bound when none is given */
    int n_phases;            /* 2 (stepper) or 3 (PMSM in star) */
    double L_q_H;            /* q-axis inductance: L_H when non-salient */
} motor_design_input_t;

/* Phi [Wb], the magnet's peak flux linkage per phase: K / n_p (the same
 * division as the scenario's MotorParams::Phi_Wb()). */
static inline double motor_design_phi_Wb(const motor_design_input_t *m)
{
    return m->K_Nm_per_A / (double)m->n_p;
}

#ifdef __cplusplus
}
#endif

#endif /* DESIGN_MOTOR_DESIGN_H */
