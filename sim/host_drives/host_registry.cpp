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

}  // namespace mcsim
