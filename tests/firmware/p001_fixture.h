// p001_fixture.h - the design input of paper 001's PMSM shared by the
// firmware tests (sim/motors/paper001_pmsm.toml): 48 V bus, 8 A, trip 12 A,
// the profile 0 -> 5 rad/s in 1 s.
#ifndef TESTS_FIRMWARE_P001_FIXTURE_H
#define TESTS_FIRMWARE_P001_FIXTURE_H

extern "C" {
#include "design/paper001_design.h"
}

namespace fwtest {

// Paper 001's PMSM as the one design input (design/motor_design.h):
// 3 phases, R 0.225 ohm, L 3.8 mH, Phi 0.17 Wb (K = n_p Phi), n_p 3,
// J 0.012 kg m^2, no friction.
inline motor_design_input_t p001_motor()
{
    motor_design_input_t m{};
    m.n_phases = 3;
    m.R_ohm = 0.225;
    m.L_H = m.L_q_H = 3.8e-3;
    m.n_p = 3;
    m.K_Nm_per_A = 3 * 0.17;
    m.J_kgm2 = 0.012;
    return m;
}

inline p001_design_input_t p001_input()
{
    p001_design_input_t in;
    p001_design_defaults(&in);
    in.motor = p001_motor();
    in.ts_s = 1e-4;
    in.i_max_A = 8.0;
    in.i_trip_A = 12.0;
    in.n_points = 2;
    in.t_s[0] = 0.0;
    in.omega_rad_s[0] = 0.0;
    in.t_s[1] = 1.0;
    in.omega_rad_s[1] = 5.0;
    return in;
}

}  // namespace fwtest

#endif  // TESTS_FIRMWARE_P001_FIXTURE_H
