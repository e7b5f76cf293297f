// design_input.h - what every drive's design input takes from a scenario
// alike: the motor the drive believes in ([drive_model]) as the one motor
// design input (design/motor_design.h), and the current at the ADC's rail.
// Each drive's own mapping (its limits, its table's keys, its design's
// switches) is in its host part, sim/host_drives/<name>_host.cpp.
#ifndef MCSIM_SCENARIO_DESIGN_INPUT_H
#define MCSIM_SCENARIO_DESIGN_INPUT_H

#include "design/motor_design.h"
#include "model/current_sensor.h"
#include "model/motor_params.h"

namespace mcsim {

// The one design input for the motor, the same for every design.
motor_design_input_t motor_design_input(const MotorParams& m);

// The current at the ADC's rail for the fault monitor (0: no ADC, no check).
double adc_rail_A(const SensorParams& p);

}  // namespace mcsim

#endif  // MCSIM_SCENARIO_DESIGN_INPUT_H
