// drive_runs.h - what motorsim does for a drive beyond the drive interface
// (firmware/drives/drive.h) and its host part (sim/host_drives/): its own
// probe of the recorder, for a drive whose telemetry says more than
// drive_status_t (motorsim/run_recorder.h), and a commissioning run before
// the run. One line per such drive in drive_runs/registry.cpp; a speed
// drive with neither needs none (the speed probe reads any speed drive
// through the interface).
#ifndef MCSIM_MOTORSIM_DRIVE_RUNS_DRIVE_RUNS_H
#define MCSIM_MOTORSIM_DRIVE_RUNS_DRIVE_RUNS_H

#include <memory>
#include <string>

#include "motorsim/run_recorder.h"

namespace mcsim {

struct DriveRun {
    const char* name;  // the firmware registry's name
    // Its probe (nullptr: the speed probe, speed_recorder.h).
    std::unique_ptr<RunRecorder> (*recorder)(const Scenario& sc, const PmPlant& plant, const drive_t& d,
                                             bool record_rows);
    // Before the drive is designed (nullptr: none): a commissioning run on
    // the scenario's plant whose results replace sc->drive_model, its
    // figures appended to *metrics. Throws std::runtime_error when it fails.
    void (*commission)(Scenario* sc, MetricList* metrics);
};

// The entry of that drive, or nullptr.
const DriveRun* drive_run_find(const std::string& name);

}  // namespace mcsim

#endif  // MCSIM_MOTORSIM_DRIVE_RUNS_DRIVE_RUNS_H
