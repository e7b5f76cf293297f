// paper002_host.cpp - paper 002's IPMSM speed drive's host part: its table
// is [paper002] (its keys: sim/scenarios/README.md), its design is
// design/paper002_design.h's from the scenario, --estimator chooses the
// encoder (the paper) or paper 001's flux observer (sensorless), and its
// reference is a C^2 polynomial from w0 to w1.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <memory>
#include <stdexcept>

#include "design/paper002_design.h"
#include "drives/paper002/generated/paper002_params.h"
#include "host_drives/host_drive.h"
#include "scenario/design_input.h"
#include "scenario/toml_view.h"

namespace mcsim {
namespace {

std::vector<std::string> p002_keys()
{
    return {
        "controller", "compensation", "t0_s", "t1_s", "omega_final_rad_s", "omega_start_rad_s",
        "omega0_rad_s", "estimator", "ekf_q", "ekf_r", "hfi_find_angle", "iron_model"
    };
}

// [paper002]: paper 002's drive (sim/scenarios/README.md)
void p002_parse(const View* v, Scenario* sc)
{
    if (v == nullptr) {
        throw ScenarioError(sc->path + ": paper002: missing required table (paper 002's reference and design choices)");
    }
    v->only(p002_keys());
    // the EKF's Q and R diagonals instead of the design's: positive
    // definite, so every entry > 0
    const auto positive = [](double x) { return x > 0.0; };
    if (const auto q = v->numbers("ekf_q", std::size(sc->ipmsm.ekf_q), positive, "must be > 0 (Q positive definite)")) {
        std::copy(q->begin(), q->end(), sc->ipmsm.ekf_q);
    }
    if (const auto r = v->numbers("ekf_r", std::size(sc->ipmsm.ekf_r), positive, "must be > 0 (R positive definite)")) {
        std::copy(r->begin(), r->end(), sc->ipmsm.ekf_r);
    }
    if (const auto e = v->string("estimator")) {
        if (*e == "encoder") {
            sc->ipmsm.estimator = 0;
        } else if (*e == "flux") {
            sc->ipmsm.estimator = 1;
        } else if (*e == "hfi") {
            sc->ipmsm.estimator = 2;
        } else {
            v->fail("estimator", "must be \"encoder\", \"flux\" or \"hfi\" (got \"" + *e + "\")");
        }
    }
    if (const auto b = v->boolean("hfi_find_angle")) {
        sc->ipmsm.hfi_find_angle = *b;
    }
    if (const auto b = v->boolean("iron_model")) {
        sc->ipmsm.iron_model = *b;
    }
    if (const auto c = v->string("controller")) {
        if (*c == "sosmc") {
            sc->ipmsm.controller = 0;
        } else if (*c == "htsmc") {
            sc->ipmsm.controller = 1;
        } else {
            v->fail("controller", "must be \"sosmc\" or \"htsmc\" (got \"" + *c + "\")");
        }
    }
    if (const auto b = v->boolean("compensation")) {
        sc->ipmsm.compensate = *b;
    }
    sc->ipmsm.t0_s = v->number("t0_s").value_or(sc->ipmsm.t0_s);
    ge(*v, "t0_s", sc->ipmsm.t0_s, 0.0);
    sc->ipmsm.t1_s = v->number("t1_s").value_or(sc->ipmsm.t1_s);
    if (!(sc->ipmsm.t1_s >= sc->ipmsm.t0_s + sc->ts_s)) {
        v->fail("t1_s", "must be at least Ts_s after t0_s (got " + fmt_num(sc->ipmsm.t1_s) + ")");
    }
    sc->ipmsm.omega_final_rad_s = v->number("omega_final_rad_s").value_or(sc->ipmsm.omega_final_rad_s);
    sc->ipmsm.omega_start_rad_s = v->number("omega_start_rad_s").value_or(0.0);
    sc->ipmsm.omega0_rad_s = v->number("omega0_rad_s").value_or(0.0);
    sc->omega0_rad_s = sc->ipmsm.omega0_rad_s;
    if (sc->motor.type != MotorType::kPmsm3) {
        throw ScenarioError(sc->path + ": motor.file: paper 002's drive needs a pmsm3 motor (this one is a stepper2)");
    }
    if (sc->ipmsm.hfi_find_angle && sc->ipmsm.estimator != 2) {
        v->fail("hfi_find_angle", "needs estimator = \"hfi\" (the start angle is found by the HF injection)");
    }
    if (sc->ipmsm.iron_model && !(sc->motor.i_sat_A > 0.0)) {
        v->fail("iron_model", "needs the motor's saturation, [motor] i_sat_A > 0 (the iron the drive is told)");
    }
    if (sc->ipmsm.estimator == 0 && !sc->encoder.present()) {
        throw ScenarioError(sc->path + ": encoder: missing required table: paper 002's drive reads an encoder (or set "
                            "paper002.estimator = \"flux\" or \"hfi\")");
    }
}

// The design input from the scenario: the drive model, limits, sensor
// noise (a uniform half-width a as its sigma a/sqrt(3)), encoder and
// reference. The fixed-point build's design refuses it.
void make_paper002_design_input(const Scenario& sc, p002_design_input_t* in)
{
    p002_design_defaults(in);
    shared_design_input(sc, in);
    switch (sc.sensor.noise) {
    case NoiseKind::kGaussian: in->sigma_i_A = sc.sensor.noise_A; break;
    case NoiseKind::kUniform: in->sigma_i_A = sc.sensor.noise_A / std::sqrt(3.0); break;
    default: in->sigma_i_A = 0.0; break;
    }
    in->encoder_counts = static_cast<long>(sc.encoder.counts_per_turn);
    in->sigma_theta_rad = sc.encoder.noise_rad;
    in->controller = sc.ipmsm.controller;
    in->compensate = sc.ipmsm.compensate;
    in->t0_s = sc.ipmsm.t0_s;
    in->t1_s = sc.ipmsm.t1_s;
    in->w0_rad_s = sc.ipmsm.omega_start_rad_s;
    in->w1_rad_s = sc.ipmsm.omega_final_rad_s;
    in->angle_source = sc.ipmsm.estimator;
    in->theta0_rad = sc.theta0_rad;  // the sensorless variant's aligned start (paper002_drive.h)
    in->hfi_find_angle = sc.ipmsm.hfi_find_angle;  // or the start angle found (the injection, the polarity test)
    if (sc.ipmsm.iron_model) {
        // the iron as the plant's [motor] has it: the commissioning's map
        in->iron_i_sat_A = sc.motor.i_sat_A;
        in->iron_i_bias_A = sc.motor.i_sat_bias_A;
    }
    std::copy(std::begin(sc.ipmsm.ekf_q), std::end(sc.ipmsm.ekf_q), in->ekf_q);
    std::copy(std::begin(sc.ipmsm.ekf_r), std::end(sc.ipmsm.ekf_r), in->ekf_r);
}

void init_paper002_drive_from(const Scenario& sc, const p002_design_input_t& in, paper002_drive_t* drive);

void design_and_init_paper002_drive(const Scenario& sc, paper002_drive_t* drive)
{
    p002_design_input_t in;
    make_paper002_design_input(sc, &in);
    init_paper002_drive_from(sc, in, drive);
}

void init_paper002_drive_from(const Scenario& sc, const p002_design_input_t& in, paper002_drive_t* drive)
{
    paper002_config_t cfg;
    std::memset(&cfg, 0, sizeof(cfg));
    char err[256] = {0};
    if (!p002_design(&in, &cfg, err, sizeof(err))) {
        throw ScenarioError(sc.path + ": design: " + (err[0] != '\0' ? err : "p002_design rejected the input"));
    }
    cfg.deadtime = deadtime_comp_config(sc);  // [inverter]: the board's dead-time compensation
    if (!paper002_drive_init(drive, &cfg)) {
        throw ScenarioError(sc.path + ": design: paper002_drive_init rejected the derived configuration");
    }
}

// cppcheck-suppress constParameterCallback ; HostDrive.design may set sc.pre_ticks (paper 000's does)
void p002_design(Scenario& sc, drive_config_storage_t* out)
{
    auto d = std::make_unique<paper002_drive_t>();
    design_and_init_paper002_drive(sc, d.get());
    out->paper002 = d->cfg;
}

void p002_design_input(const Scenario& sc, void* in)
{
    make_paper002_design_input(sc, static_cast<p002_design_input_t*>(in));
}

// cppcheck-suppress constParameterCallback ; HostDrive.design_from_input may set sc.pre_ticks (paper 000's does)
void p002_design_from_input(Scenario& sc, const void* in, drive_config_storage_t* out)
{
    auto d = std::make_unique<paper002_drive_t>();
    init_paper002_drive_from(sc, *static_cast<const p002_design_input_t*>(in), d.get());
    out->paper002 = d->cfg;
}

void p002_select_estimator(Scenario* sc, const std::string& name)
{
    if (name == "encoder" || name == "flux" || name == "hfi") {
        sc->ipmsm.estimator = (name == "hfi") ? 2 : ((name == "flux") ? 1 : 0);
        return;
    }
    throw std::invalid_argument("--estimator: " + name + ": paper 002's drive takes encoder, flux or hfi");
}

const char* p002_estimator_name(const drive_config_storage_t* cfg)
{
    const int a = cfg->paper002.angle_source;
    return a == P002_ANGLE_HFI ? "hfi" : (a == P002_ANGLE_FLUX ? "flux" : "encoder");
}

// The C^2 polynomial's peak acceleration is 1.875 (w1 - w0)/(t1 - t0).
void p002_peak_demand(const Scenario& sc, double* w_pk, double* a_pk)
{
    *w_pk = std::max(std::fabs(sc.ipmsm.omega_start_rad_s), std::fabs(sc.ipmsm.omega_final_rad_s));
    *a_pk = 1.875 * std::fabs(sc.ipmsm.omega_final_rad_s - sc.ipmsm.omega_start_rad_s) / (sc.ipmsm.t1_s - sc.ipmsm.t0_s);
}

}  // namespace

extern const HostDrive kPaper002Host;
const HostDrive kPaper002Host = {"paper002", "paper002", false, &p002_parse, &p002_design, &p002_keys, nullptr, nullptr,
                                 &p002_select_estimator, &p002_peak_demand, nullptr, &p002_estimator_name,
                                 "ekf_speed", nullptr, MC_HOST_PARAMS(paper002_params), sizeof(p002_design_input_t),
                                 &p002_design_input, &p002_design_from_input};

}  // namespace mcsim
