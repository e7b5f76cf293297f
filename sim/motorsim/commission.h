// commission.h - the PMSM commissioning run before a speed-drive run (a
// drive's host part that has one, HostDrive::pmsm_identification, e.g.
// paper 001's with [speed] identify = true): the firmware's identification
// (firmware/startup/pmsm_identification.h) on the scenario's plant,
// unloaded, from the scenario's initial angle, through the same
// software-plant HAL backend as the drive. Like a motor detection on a real
// drive, it runs before the run and its results replace the drive model's
// R, L and Phi.
#ifndef MCSIM_MOTORSIM_COMMISSION_H
#define MCSIM_MOTORSIM_COMMISSION_H

#include <string>

#include "host_drives/host_drive.h"
#include "motorsim/metrics.h"
#include "scenario/scenario.h"

namespace mcsim {

struct CommissionResult {
    bool ok = false;
    std::string why;  // reason of a rejection
    double R_ohm = 0.0, L_H = 0.0, Phi_Wb = 0.0;
    double duration_s = 0.0;  // simulated time the commissioning took
};

// Runs the identification cfg (for duration_s nominally, 1 s more at
// most) on sc's motor. Throws std::runtime_error if the HAL cannot start.
CommissionResult commission_pmsm(const Scenario& sc, const pmsm_id_config_t& cfg, double duration_s);

// The commissioning of the scenario's drive, when its host part has one
// and the scenario asks for it: its R, L (L_q = L) and K = Phi n_p replace
// sc->drive_model's, its figures (id_R_ohm, id_L_H, id_Phi_Wb, their
// errors against the plant's in %, id_time_s) are appended to *metrics.
// Throws std::runtime_error naming the scenario when it fails.
void commission_drive(const HostDrive& host, Scenario* sc, MetricList* metrics);

}  // namespace mcsim

#endif  // MCSIM_MOTORSIM_COMMISSION_H
