// registry.cpp - the drives with a part of their own in motorsim's run: one
// line each (drive_runs.h).
#include <cstring>
#include <stdexcept>

#include "motorsim/drive_runs/paper001_commission.h"
#include "motorsim/drive_runs/drive_runs.h"
#include "motorsim/drive_runs/paper000_recorder.h"
#include "motorsim/drive_runs/paper002_recorder.h"
#include "motorsim/speed_recorder.h"

namespace mcsim {
namespace {

// A probe of drive type D: its state is the drive_t's self (checked by size
// against the drive's operations, so a wrong line here fails loudly).
template <typename R, typename D>
std::unique_ptr<RunRecorder> probe_of(const Scenario& sc, const PmPlant& plant, const drive_t& d, bool record_rows)
{
    if (d.ops->state_bytes != sizeof(D)) {
        throw std::logic_error(std::string("drive_runs/registry.cpp: the probe of ") + d.ops->name +
                               " is for another drive's state");
    }
    return std::make_unique<R>(sc, plant, *static_cast<const D*>(d.self), record_rows);
}

// The PMSM commissioning ([speed] identify): R, L and Phi measured by the
// firmware on the same plant before the run replace the drive model's.
void commission_speed_drive(Scenario* sc, MetricList* metrics)
{
    if (!sc->speed_gains.identify) {
        return;
    }
    const CommissionResult c = commission_pmsm(*sc);
    if (!c.ok) {
        throw std::runtime_error(sc->path + ": identification failed after " + std::to_string(c.duration_s) +
                                 " s: " + c.why);
    }
    sc->drive_model.R_ohm = c.R_ohm;
    sc->drive_model.L_H = c.L_H;
    sc->drive_model.L_q_H = c.L_H;
    sc->drive_model.K_Nm_per_A = c.Phi_Wb * static_cast<double>(sc->drive_model.n_p);
    metrics->emplace_back("id_R_ohm", c.R_ohm);
    metrics->emplace_back("id_L_H", c.L_H);
    metrics->emplace_back("id_Phi_Wb", c.Phi_Wb);
    metrics->emplace_back("id_R_err_pct", 100.0 * (c.R_ohm / sc->motor.R_ohm - 1.0));
    metrics->emplace_back("id_L_err_pct", 100.0 * (c.L_H / sc->motor.L_H - 1.0));
    metrics->emplace_back("id_Phi_err_pct", 100.0 * (c.Phi_Wb / sc->motor.Phi_Wb() - 1.0));
    metrics->emplace_back("id_time_s", c.duration_s);
}

const DriveRun kDriveRuns[] = {
    {"paper000", &probe_of<Paper000Recorder, paper000_drive_t>, nullptr},
    {"paper001", nullptr, &commission_speed_drive},
    {"paper002", &probe_of<Paper002Recorder, paper002_drive_t>, nullptr},
};

}  // namespace

const DriveRun* drive_run_find(const std::string& name)
{
    for (const DriveRun& r : kDriveRuns) {
        if (name == r.name) {
            return &r;
        }
    }
    return nullptr;
}

std::unique_ptr<RunRecorder> make_recorder(const Scenario& sc, const PmPlant& plant, const drive_t& d,
                                           bool record_rows)
{
    const DriveRun* r = drive_run_find(d.ops->name);
    if (r != nullptr && r->recorder != nullptr) {
        return r->recorder(sc, plant, d, record_rows);
    }
    if (d.ops->kind == DRIVE_KIND_SPEED) {
        return std::make_unique<SpeedRecorder>(sc, plant, d, record_rows);
    }
    throw ScenarioError(sc.path + ": drive.kind: \"" + d.ops->name +
                        "\" is a position drive without a probe of its own (sim/motorsim/drive_runs/)");
}

}  // namespace mcsim
