// paper000_host.cpp - paper 000's position drive's host part: its table is
// [trajectory] (parsed by scenario.cpp with [design], [gains], [bounds] and
// [protection]: sim/scenarios/README.md), its design is
// design/paper000_design.h's through scenario/design_input.h, and its
// reference's peak demand is that of eq. (70)'s polynomial.
#include <algorithm>
#include <cmath>
#include <memory>

#include "host_drives/host_drive.h"
#include "scenario/design_input.h"

namespace mcsim {
namespace {

void p000_design(Scenario& sc, drive_config_storage_t* out)
{
    // designed and tried on the drive (the refusals in the scenario's
    // terms); the run's drive gets the configuration it was tried with
    auto d = std::make_unique<paper000_drive_t>();
    design_and_init_drive(sc, d.get());  // sets sc.pre_ticks, the rotor alignment
    out->paper000 = d->cfg;
}

// The peak speed and acceleration of eq. (70) are 2.1875 d/T and
// 7.5132 d/T^2 for a move d over T.
void p000_peak_demand(const Scenario& sc, double* w_pk, double* a_pk)
{
    double from = 0.0;
    for (const auto& g : sc.segments) {
        const double d = std::fabs(g.theta_to_rad - from);
        *w_pk = std::max(*w_pk, 2.1875 * d / g.duration_s);
        *a_pk = std::max(*a_pk, 7.5132 * d / (g.duration_s * g.duration_s));
        from = g.theta_to_rad;
    }
}

}  // namespace

extern const HostDrive kPaper000Host;
const HostDrive kPaper000Host = {"paper000", "trajectory", false, nullptr, &p000_design, nullptr, nullptr, &p000_peak_demand};

}  // namespace mcsim
