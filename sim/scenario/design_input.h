// design_input.h - what every drive's design input takes from a scenario
// alike: the motor the drive believes in ([drive_model]) as the one motor
// design input (design/motor_design.h), the sample time, the current limit
// and trip, the current at the ADC's rail and the computation delay. Each
// drive's own mapping (its supply, its table's keys, its design's
// switches) is in its host part, sim/host_drives/<name>_host.cpp.
#ifndef MCSIM_SCENARIO_DESIGN_INPUT_H
#define MCSIM_SCENARIO_DESIGN_INPUT_H

#include <cstddef>
#include <iterator>

#include "design/deadtime_comp_design.h"
#include "design/motor_design.h"
#include "model/current_sensor.h"
#include "model/motor_params.h"
#include "scenario/scenario.h"

namespace mcsim {

// The one design input for the motor, the same for every design.
motor_design_input_t motor_design_input(const MotorParams& m);

// The current at the ADC's rail for the fault monitor (0: no ADC, no check).
double adc_rail_A(const SensorParams& p);

// The fields every drive's design input has, of these names, from the
// scenario: motor ([drive_model]), ts_s, i_max_A, i_trip_A,
// i_trip_samples, i_rail_A and compute_delay_samples (the board's, known
// to its drive).
template <typename DesignInput>
void shared_design_input(const Scenario& sc, DesignInput* in)
{
    in->motor = motor_design_input(sc.drive_model);
    in->ts_s = sc.ts_s;
    in->i_max_A = sc.i_max_A;
    in->i_trip_A = sc.i_trip_A;
    in->i_trip_samples = sc.i_trip_samples;
    in->i_rail_A = adc_rail_A(sc.sensor);
    in->compute_delay_samples = sc.compute_delay_samples;
}

// A speed drive's reference corners (sc.speed_points) into its design
// input's n_points, t_s[] and omega_rad_s[] (at most their length).
// The drive's dead-time compensation (firmware/control/deadtime_comp.h)
// from the scenario's [inverter] (design/deadtime_comp_design.h, the
// sensor's noise widening its band): disabled (all zero) without an
// inverter or with [inverter] compensation = false. Every host part whose
// drive has the block puts it into the drive's configuration before
// *_drive_init; throws ScenarioError naming [inverter] if the design
// refuses it.
deadtime_comp_config_t deadtime_comp_config(const Scenario& sc);

// The dead-time compensation's design input (design/deadtime_comp_design.h)
// of an inverter as the simulator describes it (model/inverter.h), with the
// current sensor's noise i_noise_A (0: none).
deadtime_comp_design_input_t deadtime_comp_input(const InverterParams& p, double i_noise_A);

template <typename DesignInput>
void speed_points_design_input(const Scenario& sc, DesignInput* in)
{
    in->n_points = sc.speed_points.size();
    for (std::size_t k = 0; k < sc.speed_points.size() && k < std::size(in->t_s); ++k) {
        in->t_s[k] = sc.speed_points[k].first;
        in->omega_rad_s[k] = sc.speed_points[k].second;
    }
}

}  // namespace mcsim

#endif  // MCSIM_SCENARIO_DESIGN_INPUT_H
