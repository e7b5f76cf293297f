#include "scenario/design_input.h"

#include <cmath>

namespace mcsim {

motor_design_input_t motor_design_input(const MotorParams& m)
{
    motor_design_input_t d;
    d.L_H = m.L_H;
    d.R_ohm = m.R_ohm;
    d.K_Nm_per_A = m.K_Nm_per_A;
    d.J_kgm2 = m.J_kgm2;
    d.fv_Nms_per_rad = m.fv_Nms_per_rad;
    d.n_p = m.n_p;
    d.coulomb_Nm = m.coulomb_Nm;
    d.n_phases = m.n_phases();
    d.L_q_H = m.L_q();
    return d;
}

// The ADC's rail for the fault monitor: its largest code is full scale
// minus one LSB; 1.5 LSB below full scale catches it without catching the
// code below. 0 (no check) without an ADC.
double adc_rail_A(const SensorParams& p)
{
    if (p.adc_bits <= 0) {
        return 0.0;
    }
    const double lsb = 2.0 * p.adc_full_scale_A / std::ldexp(1.0, p.adc_bits);
    return p.adc_full_scale_A - 1.5 * lsb;
}

}  // namespace mcsim
