// paper001_commission.h - the PMSM commissioning run before a speed-drive run
// ([speed] identify = true): the firmware's identification
// (firmware/startup/pmsm_identification.h) on the scenario's plant, unloaded,
// from the scenario's initial angle, through the same software-plant HAL
// backend as the drive. Like a motor detection on a real drive, it runs
// before the run and its results replace the drive model's R, L and Phi.
#ifndef MCSIM_MOTORSIM_DRIVE_RUNS_PAPER001_COMMISSION_H
#define MCSIM_MOTORSIM_DRIVE_RUNS_PAPER001_COMMISSION_H

#include <string>

#include "scenario/scenario.h"

namespace mcsim {

struct CommissionResult {
    bool ok = false;
    std::string why;        // reason of a rejection
    double R_ohm = 0.0, L_H = 0.0, Phi_Wb = 0.0;
    double duration_s = 0.0;  // simulated time the commissioning took
};

// Runs the commissioning of sc's motor with sc.drive_model as the nominal
// model. Throws std::runtime_error if the HAL cannot start.
CommissionResult commission_pmsm(const Scenario& sc);

}  // namespace mcsim

#endif  // MCSIM_MOTORSIM_DRIVE_RUNS_PAPER001_COMMISSION_H
