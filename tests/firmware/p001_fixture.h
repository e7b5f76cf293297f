// p001_fixture.h - the design input of paper 001's PMSM shared by the
// firmware tests (sim/motors/paper001_pmsm.toml): 48 V bus, 8 A, trip 12 A,
// the profile 0 -> 5 rad/s in 1 s.
#ifndef TESTS_FIRMWARE_P001_FIXTURE_H
#define TESTS_FIRMWARE_P001_FIXTURE_H

extern "C" {
#include "design/paper001_design.h"
}

namespace fwtest {

inline p001_design_input_t p001_input()
{
    p001_design_input_t in;
    p001_design_defaults(&in);
    in.motor = {3, 0.225, 3.8e-3, 0.17, 3, 0.012};
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
