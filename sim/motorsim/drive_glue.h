// drive_glue.h - the HAL control callback that runs a drive: one
// drive_step() per period with the sampled currents, its voltages back to
// the backend. This is all an application needs between hal.h and
// drives/drive.h, for any drive of the registry.
#ifndef MCSIM_MOTORSIM_DRIVE_GLUE_H
#define MCSIM_MOTORSIM_DRIVE_GLUE_H

#include "drives/drive.h"
#include "hal/hal.h"

namespace mcsim {

// ctx is the drive_t (drives/drive.h). A drive fault puts the power stage
// in its safe state (the drive already outputs 0 V; the backend then stops
// calling back).
void drive_control_callback(void* ctx, const hal_sample_t* in, hal_command_t* out);

}  // namespace mcsim

#endif  // MCSIM_MOTORSIM_DRIVE_GLUE_H
