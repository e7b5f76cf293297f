// rig_hal.h - a scenario's bench (scenario/rig.h) attached to the
// software-plant HAL backend (model/hal_sw_plant.h) the one way every
// program that runs a drive on it does: plant, sensor and amplifier, the
// computation delay, and the scenario's [inverter] (the MCU board's PWM
// inverter instead of the amplifier). motorsim, the PIL recorder
// (tools/bench/pil_gen.cpp) and the commissioning run call it, so that a
// part of the bench cannot be left out of one of them (the PIL recorder
// once ran the hardware-like scenarios without their inverter while the
// drive compensated its dead time). Sensors that only some programs read
// (the encoder, injected faults, the DAC board) are attached by them.
#ifndef MCSIM_SCENARIO_RIG_HAL_H
#define MCSIM_SCENARIO_RIG_HAL_H

#include "hal_sw_plant.h"
#include "scenario/rig.h"
#include "scenario/scenario.h"

namespace mcsim {

inline void attach_rig(Rig& rig, const Scenario& sc)
{
    hal_sw_plant_attach(&rig.plant, &rig.sensor, rig.amp, sc.ts_s);
    (void)hal_sw_plant_set_compute_delay(sc.compute_delay_samples);  // validated at load
    hal_sw_plant_set_inverter(rig.inverter_or_null());
}

}  // namespace mcsim

#endif  // MCSIM_SCENARIO_RIG_HAL_H
