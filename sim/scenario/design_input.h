// design_input.h - maps a scenario onto drive_design_input_t
// (design/paper000_design.h), the one place that knows the design
// field names the [gains] and [bounds] tables may override.
#ifndef MCSIM_SCENARIO_DESIGN_INPUT_H
#define MCSIM_SCENARIO_DESIGN_INPUT_H

#include <string>
#include <vector>

#include "design/paper000_design.h"
#include "design/paper001_design.h"
#include "design/paper002_design.h"
#include "scenario/scenario.h"

namespace mcsim {

// Keys accepted in [gains]: the fields of drive_gain_override_t.
// The current at the ADC's rail for the fault monitor (0: no ADC, no check).
double adc_rail_A(const SensorParams& p);

const std::vector<std::string>& gain_override_keys();
// Keys accepted in [bounds]: the bound_* fields of drive_design_input_t.
const std::vector<std::string>& design_bound_keys();

// drive_design_defaults(), then the drive model, sample time, limits,
// segments and the scenario's overrides.
void make_design_input(const Scenario& sc, drive_design_input_t* in);

// make_design_input + drive_design + paper000_drive_init, and sc.pre_ticks = the
// drive's alignment (so a Rig built after it starts the plant at
// sc.t_start_s()). Throws ScenarioError ("FILE: design: reason") if the
// design or the drive rejects the input.
void design_and_init_drive(Scenario& sc, paper000_drive_t* drive);

// The same for the speed drive of paper 001 ([speed] scenarios).
void make_speed_design_input(const Scenario& sc, p001_design_input_t* in);
void design_and_init_speed_drive(const Scenario& sc, paper001_drive_t* drive, p001_design_report_t* rep);

// The same for paper 002's drive ([paper002] scenarios): the drive model,
// limits, sensor noise (a uniform half-width a as its sigma a/sqrt(3)),
// encoder and reference. The fixed-point build's design refuses it.
void make_paper002_design_input(const Scenario& sc, p002_design_input_t* in);
void design_and_init_paper002_drive(const Scenario& sc, paper002_drive_t* drive);

}  // namespace mcsim

#endif  // MCSIM_SCENARIO_DESIGN_INPUT_H
