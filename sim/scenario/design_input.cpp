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

deadtime_comp_design_input_t deadtime_comp_input(const InverterParams& p, double i_noise_A)
{
    deadtime_comp_design_input_t in{};
    in.f_pwm_Hz = p.f_pwm_Hz;
    in.dead_time_s = p.dead_time_s;
    in.t_on_s = p.t_on_s;
    in.t_off_s = p.t_off_s;
    in.v_switch_V = p.v_switch_V;
    in.r_switch_Ohm = p.r_switch_Ohm;
    in.v_diode_V = p.v_diode_V;
    in.r_diode_Ohm = p.r_diode_Ohm;
    in.i_transition_A = p.i_transition_A;
    in.synchronous = p.synchronous;
    in.i_noise_A = i_noise_A;
    return in;
}

deadtime_comp_config_t deadtime_comp_config(const Scenario& sc)
{
    deadtime_comp_config_t c{};
    if (!sc.inverter_given || !sc.inverter_compensation) {
        return c;
    }
    deadtime_comp_design_input_t in =
        deadtime_comp_input(sc.inverter, sc.sensor.noise == NoiseKind::kNone ? 0.0 : sc.sensor.noise_A);
    // what the drive believes: the plant's, unless the scenario says (a
    // Monte Carlo of the board's dead time keeps the drive's nominal)
    if (sc.compensation_dead_time_s >= 0.0) {
        in.dead_time_s = sc.compensation_dead_time_s;
    }
    char err[256] = {0};
    if (!deadtime_comp_design(&in, &c, err, sizeof(err))) {
        throw ScenarioError(sc.path + ": inverter: " + err);
    }
    return c;
}

}  // namespace mcsim
