// rig.h - the simulated bench of a scenario: plant at its initial state,
// current sensor and amplifier, as motorsim and the PIL recorder attach them
// to the software-plant HAL backend. One place that turns a scenario into
// hardware models, so the tools cannot disagree on it.
#ifndef MCSIM_SCENARIO_RIG_H
#define MCSIM_SCENARIO_RIG_H

#include "model/amplifier.h"
#include "model/current_sensor.h"
#include "model/load_profile.h"
#include "model/pm_plant.h"
#include "scenario/scenario.h"

namespace mcsim {

struct Rig {
    explicit Rig(const Scenario& sc)
        : plant(sc.motor, LoadProfile(sc.load), sc.substeps), sensor(sc.sensor, sc.seed)
    {
        PmPlant::State x0 = PmPlant::State::Zero();
        x0[PmPlant::kTheta] = sc.theta0_rad;
        x0[PmPlant::kOmega] = sc.omega0_rad_s;  // the rotor's speed at the start (0 unless the scenario says)
        plant.reset(x0, sc.t_start_s());  // t = 0 is the move command, after pre_ticks
        amp.v_max_V = sc.v_max_V;
    }
    PmPlant plant;
    CurrentSensor sensor;
    Amplifier amp;
};

}  // namespace mcsim

#endif  // MCSIM_SCENARIO_RIG_H
