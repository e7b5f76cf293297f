// test_motors.h - the shipped motors' parameters as the sim tests build them
// by hand (no motor file read): one copy for every test that needs them.
#ifndef MCSIM_TESTS_TEST_MOTORS_H
#define MCSIM_TESTS_TEST_MOTORS_H

#include "model/pm_plant.h"

namespace mcsim_test {

// sim/motors/paper001_pmsm.toml
inline mcsim::MotorParams paper001_motor()
{
    mcsim::MotorParams m;
    m.type = mcsim::MotorType::kPmsm3;
    m.L_H = 3.8e-3;
    m.R_ohm = 0.225;
    m.K_Nm_per_A = 3 * 0.17;
    m.J_kgm2 = 0.012;
    m.n_p = 3;
    return m;
}

// sim/motors/paper000_stepper.toml (without its Coulomb smoothing speed)
inline mcsim::MotorParams paper000_stepper()
{
    mcsim::MotorParams m;
    m.L_H = 9e-3;
    m.R_ohm = 3.01;
    m.K_Nm_per_A = 0.27;
    m.J_kgm2 = 3.18e-4;
    m.fv_Nms_per_rad = 2.37e-3;
    m.coulomb_Nm = 0.0752;
    m.n_p = 50;
    return m;
}

}  // namespace mcsim_test

#endif  // MCSIM_TESTS_TEST_MOTORS_H
