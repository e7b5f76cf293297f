// sensored_foc_host.cpp - the sensored FOC drive's host part: its scenario
// table [sensored_foc] and its design from the scenario.
//
//   [drive]
//   kind = "sensored_foc"
//   [sensored_foc]
//   profile_rpm = [[t_s, rpm], ...]   the speed reference's corners (required)
//   current_bw_hz, speed_bw_hz, observer_bw_hz, load_bw_hz, position_bw_hz
//                                     the loops' bandwidths (optional;
//                                     design/sensored_foc_design.h: defaults
//                                     500, 20, 50, 5, 5 Hz)
//
// The drive reads the scenario's [encoder] (required), the motor (a pmsm3),
// [supply] v_bus_V, [limits] and [run] compute_delay_samples.
#include <cstdio>
#include <string>

#include "host_drives/host_drive.h"
#include "scenario/design_input.h"
#include "scenario/toml_view.h"

extern "C" {
#include "design/sensored_foc_design.h"
#include "drives/sensored_foc/generated/sensored_foc_params.h"
}

namespace mcsim {
namespace {

const char* const kBandwidths[] = {"current_bw_hz", "speed_bw_hz", "observer_bw_hz", "load_bw_hz", "position_bw_hz"};

std::vector<std::string> sfoc_keys()
{
    std::vector<std::string> k = {"profile_rpm"};
    for (const char* b : kBandwidths) {
        k.emplace_back(b);
    }
    return k;
}

void sfoc_parse(const View* t, Scenario* sc)
{
    if (t == nullptr) {
        throw ScenarioError(sc->path + ": sensored_foc: missing required table (profile_rpm, its speed reference)");
    }
    t->only(sfoc_keys());
    read_speed_profile(*t, sc);
    for (const char* b : kBandwidths) {
        if (const auto x = t->number(b)) {
            gt(*t, b, *x, 0.0);
            sc->drive_params.emplace_back(b, *x);
        }
    }
    if (sc->motor.type != MotorType::kPmsm3) {
        throw ScenarioError(sc->path + ": motor.file: the sensored FOC drive runs a three-phase PMSM (type = \"pmsm3\")");
    }
    if (!sc->encoder.present()) {
        throw ScenarioError(sc->path + ": encoder: missing required table: the sensored FOC drive reads an encoder");
    }
}

void sfoc_design_input(const Scenario& sc, void* vin)
{
    auto* in = static_cast<sfoc_design_input_t*>(vin);
    *in = sfoc_design_input_t{};
    sfoc_design_defaults(in);
    shared_design_input(sc, in);
    in->v_bus_V = 2.0 * sc.v_max_V;  // three legs: v_max_V = v_bus / 2 ([supply])
    for (const auto& [k, v] : sc.drive_params) {
        if (k == "current_bw_hz") in->current_bw_hz = v;
        if (k == "speed_bw_hz") in->speed_bw_hz = v;
        if (k == "observer_bw_hz") in->observer_bw_hz = v;
        if (k == "load_bw_hz") in->load_bw_hz = v;
        if (k == "position_bw_hz") in->position_bw_hz = v;
    }
    speed_points_design_input(sc, in);
}

// cppcheck-suppress constParameterCallback ; HostDrive.design_from_input may set sc.pre_ticks (paper 000's does)
void sfoc_design_from_input(Scenario& sc, const void* in, drive_config_storage_t* out)
{
    char err[256];
    if (!sfoc_design(static_cast<const sfoc_design_input_t*>(in), &out->sensored_foc, err, sizeof err)) {
        throw ScenarioError(sc.path + ": design: sensored_foc: " + err);
    }
    out->sensored_foc.deadtime = deadtime_comp_config(sc);  // [inverter]: the board's dead-time compensation
}

// cppcheck-suppress constParameterCallback ; HostDrive.design may set sc.pre_ticks (paper 000's does)
void sfoc_design_from(Scenario& sc, drive_config_storage_t* out)
{
    sfoc_design_input_t in{};
    sfoc_design_input(sc, &in);
    sfoc_design_from_input(sc, &in, out);
}

}  // namespace

extern const HostDrive kSensoredFocHost;
const HostDrive kSensoredFocHost = {"sensored_foc", "sensored_foc", true, &sfoc_parse, &sfoc_design_from, &sfoc_keys,
                                    nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr,
                                    MC_HOST_PARAMS(sensored_foc_params), sizeof(sfoc_design_input_t),
                                    &sfoc_design_input, &sfoc_design_from_input};

}  // namespace mcsim
