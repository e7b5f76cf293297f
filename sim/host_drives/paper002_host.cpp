// paper002_host.cpp - paper 002's IPMSM speed drive's host part: its table
// is [paper002] (parsed by scenario.cpp: sim/scenarios/README.md), its
// design is design/paper002_design.h's through scenario/design_input.h,
// --estimator chooses the encoder (the paper) or paper 001's flux observer
// (sensorless), and its reference is a C^2 polynomial from w0 to w1.
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "host_drives/host_drive.h"
#include "scenario/design_input.h"

namespace mcsim {
namespace {

void p002_design(Scenario& sc, drive_config_storage_t* out)
{
    auto d = std::make_unique<paper002_drive_t>();
    design_and_init_paper002_drive(sc, d.get());
    out->paper002 = d->cfg;
}

void p002_select_estimator(Scenario* sc, const std::string& name)
{
    if (name == "encoder" || name == "flux") {
        sc->p002.estimator = (name == "flux") ? 1 : 0;
        return;
    }
    throw std::invalid_argument("--estimator: " + name + ": paper 002's drive takes encoder or flux");
}

// The C^2 polynomial's peak acceleration is 1.875 (w1 - w0)/(t1 - t0).
void p002_peak_demand(const Scenario& sc, double* w_pk, double* a_pk)
{
    *w_pk = std::max(std::fabs(sc.p002.omega_start_rad_s), std::fabs(sc.p002.omega_final_rad_s));
    *a_pk = 1.875 * std::fabs(sc.p002.omega_final_rad_s - sc.p002.omega_start_rad_s) / (sc.p002.t1_s - sc.p002.t0_s);
}

}  // namespace

extern const HostDrive kPaper002Host;
const HostDrive kPaper002Host = {"paper002", "paper002", nullptr, &p002_design, nullptr, &p002_select_estimator,
                                 &p002_peak_demand};

}  // namespace mcsim
