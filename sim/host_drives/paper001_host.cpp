// paper001_host.cpp - paper 001's speed drive's host part: its table is
// [speed] (its keys: sim/scenarios/README.md), its design is
// design/paper001_design.h's from the scenario (paper001_host.h), and
// --estimator chooses paper 001's flux and I&I observers (flux) or paper
// 000's back-EMF chain (back_emf).
#include "host_drives/paper001_host.h"

#include <cstring>
#include <memory>
#include <stdexcept>

#include "drives/paper001/generated/paper001_params.h"
#include "host_drives/host_drive.h"
#include "scenario/design_input.h"
#include "scenario/toml_view.h"

namespace mcsim {
namespace {

std::vector<std::string> p001_keys()
{
    return {
        "profile_rpm", "gamma", "a1", "a2", "r_ohm", "handover_sweep_rad", "fit_det_min", "blend_tau_s",
        "probe_s", "identify", "track_resistance", "estimator"
    };
}

// [speed]: the speed drive's reference and design choices
void p001_parse(const View* v, Scenario* sc)
{
    if (v == nullptr) {
        throw ScenarioError(sc->path + ": speed: missing required table (profile_rpm, the speed reference)");
    }
    v->only(p001_keys());
    read_speed_profile(*v, sc);
    auto opt = [&](const char* k, double* dst) {
        if (const auto x = v->number(k)) {
            gt(*v, k, *x, 0.0);
            *dst = *x;
        }
    };
    opt("gamma", &sc->speed_gains.gamma);
    opt("a1", &sc->speed_gains.a1);
    opt("a2", &sc->speed_gains.a2);
    opt("r_ohm", &sc->speed_gains.r_ohm);
    opt("handover_sweep_rad", &sc->speed_gains.handover_sweep_rad);
    opt("fit_det_min", &sc->speed_gains.fit_det_min);
    opt("blend_tau_s", &sc->speed_gains.blend_tau_s);
    if (const auto e = v->string("estimator")) {
        if (*e == "flux") {
            sc->speed_gains.estimator = 0;
        } else if (*e == "back_emf") {
            sc->speed_gains.estimator = 1;
        } else {
            v->fail("estimator", "must be \"flux\" (paper 001) or \"back_emf\" (paper 000) (got \"" + *e + "\")");
        }
    }
    if (const auto b = v->boolean("identify")) {
        sc->speed_gains.identify = *b;
    }
    if (const auto b = v->boolean("track_resistance")) {
        sc->speed_gains.track_resistance = *b;
    }
    if (const auto x = v->number("probe_s")) {
        ge(*v, "probe_s", *x, 0.0);
        if (*x > 10.0) {
            v->fail("probe_s", "must be <= 10 s (got " + fmt_num(*x) + ")");
        }
        sc->speed_gains.probe_s = *x;
    }
}

// cppcheck-suppress constParameterCallback ; HostDrive.design may set sc.pre_ticks (paper 000's does)
void p001_design(Scenario& sc, drive_config_storage_t* out)
{
    auto d = std::make_unique<paper001_drive_t>();
    p001_design_report_t rep{};
    design_and_init_speed_drive(sc, d.get(), &rep);
    out->paper001 = d->cfg;
}

void p001_design_input(const Scenario& sc, void* in)
{
    make_speed_design_input(sc, static_cast<p001_design_input_t*>(in));
}

// cppcheck-suppress constParameterCallback ; HostDrive.design_from_input may set sc.pre_ticks (paper 000's does)
void p001_design_from_input(Scenario& sc, const void* in, drive_config_storage_t* out)
{
    auto d = std::make_unique<paper001_drive_t>();
    p001_design_report_t rep{};
    init_speed_drive_from(sc, *static_cast<const p001_design_input_t*>(in), d.get(), &rep);
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

const char* p001_estimator_name(const drive_config_storage_t* cfg)
{
    return cfg->paper001.estimator == OPEN_START_BACK_EMF ? "back_emf" : "flux";
}

}  // namespace

void make_speed_design_input(const Scenario& sc, p001_design_input_t* in)
{
    *in = p001_design_input_t{};
    p001_design_defaults(in);
    shared_design_input(sc, in);
    in->i_open_loop_A = sc.i_open_loop_A;
    in->gamma = sc.speed_gains.gamma;
    in->a1 = sc.speed_gains.a1;
    in->a2 = sc.speed_gains.a2;
    in->r_ohm = sc.speed_gains.r_ohm;
    in->blend_tau_s = sc.speed_gains.blend_tau_s;
    in->handover_sweep_rad = sc.speed_gains.handover_sweep_rad;
    in->fit_det_min = sc.speed_gains.fit_det_min;
    in->estimator = sc.speed_gains.estimator;
    in->track_resistance = sc.speed_gains.track_resistance;
    in->omega_lim_rad_s = sc.omega_lim_rad_s;
    if (sc.speed_gains.probe_s >= 0.0) {
        in->probe_s = sc.speed_gains.probe_s;
    }
    speed_points_design_input(sc, in);
}

void design_and_init_speed_drive(const Scenario& sc, paper001_drive_t* drive, p001_design_report_t* rep)
{
    p001_design_input_t in;
    make_speed_design_input(sc, &in);
    init_speed_drive_from(sc, in, drive, rep);
}

void init_speed_drive_from(const Scenario& sc, const p001_design_input_t& in, paper001_drive_t* drive,
                           p001_design_report_t* rep)
{
    paper001_config_t cfg;
    std::memset(&cfg, 0, sizeof(cfg));
    char err[256] = {0};
    if (!p001_design(&in, &cfg, rep, err, sizeof(err))) {
        throw ScenarioError(sc.path + ": design: " + (err[0] != '\0' ? err : "p001_design rejected the input"));
    }
    cfg.deadtime = deadtime_comp_config(sc);  // [inverter]: the board's dead-time compensation
    if (!paper001_drive_init(drive, &cfg)) {
        throw ScenarioError(sc.path + ": design: paper001_drive_init rejected the derived configuration");
    }
}

namespace {

// [speed] identify = true: the PMSM commissioning before the design
// (HostDrive::pmsm_identification; motorsim/commission.h runs it): R, L and
// Phi measured by the firmware on the same plant replace the drive model's.
bool p001_identification(const Scenario& sc, pmsm_id_config_t* cfg, double* duration_s)
{
    if (!sc.speed_gains.identify) {
        return false;
    }
    p001_design_input_t in;
    make_speed_design_input(sc, &in);
    char err[256] = {0};
    if (!p001_identification_design(&in, cfg, duration_s, err, sizeof(err))) {
        throw ScenarioError(sc.path + ": identification design: " + err);
    }
    return true;
}

}  // namespace

extern const HostDrive kPaper001Host;
const HostDrive kPaper001Host = {"paper001", "speed", false, &p001_parse, &p001_design, &p001_keys, nullptr, nullptr,
                                 &p001_select_estimator, nullptr, nullptr, &p001_estimator_name, nullptr,
                                 &p001_identification, MC_HOST_PARAMS(paper001_params), sizeof(p001_design_input_t),
                                 &p001_design_input, &p001_design_from_input};

}  // namespace mcsim
