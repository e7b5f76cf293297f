// host_drive.h - a drive's host part: what motorsim needs to run a drive
// of the firmware registry (firmware/drives/registry.h) from a scenario.
// Each drive that is chosen by [drive] kind = "<name>" brings one: the
// keys of its own scenario table [<name>] (parsed and validated with the
// scenario's toml_view.h, errors naming file and key) and the design of
// its configuration from the scenario. The programs look drives up here
// and never name one; a drive is added with its file in sim/host_drives/ and
// one line in host_registry.cpp.
#ifndef MCSIM_DRIVES_HOST_DRIVE_H
#define MCSIM_DRIVES_HOST_DRIVE_H

#include <string>
#include <vector>

#include "scenario/scenario.h"
#include "scenario/toml_view.h"

extern "C" {
#include "drives/registry.h"
}

namespace mcsim {

struct HostDrive {
    const char* name;  // the firmware registry's name, and the scenario table's
    // The keys of [<name>] (absent: t is nullptr): each validated into sc
    // (sc->speed_points, sc->drive_params). Throws ScenarioError.
    void (*parse)(const View* t, Scenario* sc);
    // The configuration from the scenario (motor, limits, Ts, delay, the
    // table's keys). Throws ScenarioError naming the scenario's field.
    void (*design)(const Scenario& sc, drive_config_storage_t* cfg);
    // The keys of [<name>], for sim/scenarios/README.md and the checks.
    std::vector<std::string> (*keys)();
};

// The drive of that name, or nullptr.
const HostDrive* host_drive_find(const std::string& name);
// Every registered host part.
const std::vector<const HostDrive*>& host_drives();

}  // namespace mcsim

#endif  // MCSIM_DRIVES_HOST_DRIVE_H
