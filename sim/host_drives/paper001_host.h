// paper001_host.h - paper 001's speed drive designed from a scenario, for
// the host code of that drive outside its host part: its tests.
// Defined in paper001_host.cpp, with the drive's table [speed].
#ifndef MCSIM_HOST_DRIVES_PAPER001_HOST_H
#define MCSIM_HOST_DRIVES_PAPER001_HOST_H

#include "design/paper001_design.h"
#include "scenario/scenario.h"

namespace mcsim {

// p001_design_defaults(), then the drive model, sample time, limits,
// [speed]'s gains and estimator, the delay and the speed profile.
void make_speed_design_input(const Scenario& sc, p001_design_input_t* in);

// make_speed_design_input + p001_design (its report in *rep, may be
// nullptr) + paper001_drive_init. Throws ScenarioError ("FILE: design:
// reason") if the design or the drive rejects the input.
void design_and_init_speed_drive(const Scenario& sc, paper001_drive_t* drive, p001_design_report_t* rep);
// The same from a design input made already (the parameters' service's).
void init_speed_drive_from(const Scenario& sc, const p001_design_input_t& in, paper001_drive_t* drive,
                           p001_design_report_t* rep);

}  // namespace mcsim

#endif  // MCSIM_HOST_DRIVES_PAPER001_HOST_H
