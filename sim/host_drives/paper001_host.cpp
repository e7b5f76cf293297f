// paper001_host.cpp - paper 001's speed drive's host part: its table is
// [speed] (parsed by scenario.cpp: sim/scenarios/README.md), its design is
// design/paper001_design.h's through scenario/design_input.h, and
// --estimator chooses paper 001's flux and I&I observers (flux) or paper
// 000's back-EMF chain (back_emf).
#include <memory>
#include <stdexcept>

#include "host_drives/host_drive.h"
#include "scenario/design_input.h"

namespace mcsim {
namespace {

void p001_design(Scenario& sc, drive_config_storage_t* out)
{
    auto d = std::make_unique<paper001_drive_t>();
    p001_design_report_t rep{};
    design_and_init_speed_drive(sc, d.get(), &rep);
    out->paper001 = d->cfg;
}

void p001_select_estimator(Scenario* sc, const std::string& name)
{
    if (name == "flux" || name == "back_emf") {
        sc->speed_gains.estimator = (name == "back_emf") ? 1 : 0;
        return;
    }
    throw std::invalid_argument("--estimator: " + name + ": paper 001's drive is sensorless (flux or back_emf)");
}

}  // namespace

extern const HostDrive kPaper001Host;
const HostDrive kPaper001Host = {"paper001", "speed", nullptr, &p001_design, nullptr, &p001_select_estimator, nullptr};

}  // namespace mcsim
