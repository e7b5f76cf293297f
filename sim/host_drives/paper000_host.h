// paper000_host.h - paper 000's position drive designed from a scenario,
// for the host code of that drive that designs it itself rather than
// through its host part (HostDrive.design): its tests and the Comedi
// loop. Defined in paper000_host.cpp, with the drive's tables.
#ifndef MCSIM_HOST_DRIVES_PAPER000_HOST_H
#define MCSIM_HOST_DRIVES_PAPER000_HOST_H

#include "design/paper000_design.h"
#include "scenario/scenario.h"

namespace mcsim {

// drive_design_defaults(), then the drive model, sample time, limits,
// segments and the scenario's [design], [protection], [gains], [bounds].
void make_design_input(const Scenario& sc, drive_design_input_t* in);

// make_design_input + drive_design + paper000_drive_init, and sc.pre_ticks =
// the drive's alignment (so a Rig built after it starts the plant at
// sc.t_start_s()). Throws ScenarioError ("FILE: design: reason") if the
// design or the drive rejects the input.
void design_and_init_drive(Scenario& sc, paper000_drive_t* drive);
// The same from a design input made already (the parameters' service's).
void init_drive_from(Scenario& sc, const drive_design_input_t& in, paper000_drive_t* drive);

}  // namespace mcsim

#endif  // MCSIM_HOST_DRIVES_PAPER000_HOST_H
