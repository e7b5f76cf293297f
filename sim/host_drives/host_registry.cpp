// host_registry.cpp - the drives motorsim runs by [drive] kind: one line
// per drive (its host part is in sim/host_drives/<name>_host.cpp).
#include "host_drives/host_drive.h"

namespace mcsim {

extern const HostDrive kPaper000Host;
extern const HostDrive kPaper001Host;
extern const HostDrive kPaper002Host;
extern const HostDrive kSensoredFocHost;

const std::vector<const HostDrive*>& host_drives()
{
    static const std::vector<const HostDrive*> all = {
        &kPaper000Host,
        &kPaper001Host,
        &kPaper002Host,
        &kSensoredFocHost,
    };
    return all;
}

const HostDrive* host_drive_find(const std::string& name)
{
    for (const HostDrive* d : host_drives()) {
        if (name == d->name) {
            return d;
        }
    }
    return nullptr;
}

const HostDrive* host_drive_of_table(const std::string& table)
{
    for (const HostDrive* d : host_drives()) {
        if (table == d->table) {
            return d;
        }
    }
    return nullptr;
}

drive_t design_scenario_drive(Scenario& sc, drive_storage_t* storage, drive_config_storage_t* cfg)
{
    const HostDrive* host = host_drive_find(sc.drive_kind);
    const drive_ops_t* ops = drive_find(sc.drive_kind.c_str());
    drive_t d{};
    if (host == nullptr || ops == nullptr || !drive_bind(&d, ops, storage)) {
        throw ScenarioError(sc.path + ": drive.kind: \"" + sc.drive_kind + "\" is not in this build");
    }
    host->design(sc, cfg);
    if (!drive_init(&d, cfg)) {
        const char* why = (ops->config_problem != nullptr) ? ops->config_problem(cfg) : nullptr;
        throw ScenarioError(sc.path + ": design: " + sc.drive_kind + ": the drive refused its configuration" +
                            (why != nullptr ? std::string(": ") + why : std::string()));
    }
    return d;
}

}  // namespace mcsim
