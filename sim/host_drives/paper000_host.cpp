// paper000_host.cpp - paper 000's position drive's host part: its tables
// are [trajectory] (the moves of eq. (70)), [design], [protection],
// [gains] and [bounds] (sim/scenarios/README.md), its design is
// design/paper000_design.h's from the scenario (paper000_host.h), its
// reference's peak demand is that of eq. (70)'s polynomial, and a replay
// tells it the applied voltage through paper000_drive_set_applied_voltage.
#include "host_drives/paper000_host.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "drives/paper000/generated/paper000_params.h"
#include "host_drives/host_drive.h"
#include "mc_convert.h"
#include "scenario/design_input.h"
#include "scenario/toml_view.h"
#include "trajectory/trajectory.h"

namespace mcsim {
namespace {

const char kName[] = "paper000";

struct GainField {
    const char* key;
    double drive_gain_override_t::*member;
};

struct BoundField {
    const char* key;
    double drive_design_input_t::*member;
};

// Keep in step with drive_gain_override_t; [gains] accepts exactly these
// names.
const GainField kGainFields[] = {
    {"emf_alpha_A_s2", &drive_gain_override_t::emf_alpha_A_s2},
    {"emf_lambda", &drive_gain_override_t::emf_lambda},
    {"emf_l_per_s", &drive_gain_override_t::emf_l_per_s},
    {"mech_alpha_rad_s3", &drive_gain_override_t::mech_alpha_rad_s3},
    {"mech_lambda", &drive_gain_override_t::mech_lambda},
    {"mech_l_per_s", &drive_gain_override_t::mech_l_per_s},
    {"cur_alpha_A_s2", &drive_gain_override_t::cur_alpha_A_s2},
    {"cur_lambda", &drive_gain_override_t::cur_lambda},
    {"k_surface_per_s", &drive_gain_override_t::k_surface_per_s},
    {"tw_lambda_m_rad_s3", &drive_gain_override_t::tw_lambda_m_rad_s3},
    {"tw_lambda_M_rad_s3", &drive_gain_override_t::tw_lambda_M_rad_s3},
    {"injection_filter_s", &drive_gain_override_t::injection_filter_s},
    {"blend_tau_s", &drive_gain_override_t::blend_tau_s},
    {"current_blend_tau_s", &drive_gain_override_t::current_blend_tau_s},
};

const BoundField kBoundFields[] = {
    {"bound_accel_rad_s2", &drive_design_input_t::bound_accel_rad_s2},
    {"bound_speed_rad_s", &drive_design_input_t::bound_speed_rad_s},
    {"bound_delta_omega_rad_s", &drive_design_input_t::bound_delta_omega_rad_s},
    {"bound_load_Nm", &drive_design_input_t::bound_load_Nm},
    {"bound_load_rate_Nm_s", &drive_design_input_t::bound_load_rate_Nm_s},
    {"bound_model_error_V", &drive_design_input_t::bound_model_error_V},
};

// Every double of drive_gain_override_t must be reachable from [gains]: a
// field added to the struct without a row here fails this check at compile
// time instead of being silently impossible to override.
static_assert(sizeof(kGainFields) / sizeof(kGainFields[0]) == sizeof(drive_gain_override_t) / sizeof(double),
              "kGainFields must list every field of drive_gain_override_t");

template <typename Table>
std::vector<std::string> keys_of(const Table& t)
{
    std::vector<std::string> k;
    for (const auto& f : t) {
        k.emplace_back(f.key);
    }
    return k;
}

const std::vector<std::string>& gain_override_keys()
{
    static const std::vector<std::string> k = keys_of(kGainFields);
    return k;
}

const std::vector<std::string>& design_bound_keys()
{
    static const std::vector<std::string> k = keys_of(kBoundFields);
    return k;
}

// The scenario runs this drive (its [design] and [protection] may also be
// in a scenario of another drive: parse_extra).
bool runs_here(const Scenario& sc) { return sc.drive_kind == kName; }

std::vector<std::string> p000_keys() { return {"segments"}; }

std::vector<std::string> segment_keys() { return {"t_start_s", "duration_s", "theta_to_rad"}; }
std::vector<std::string> design_keys()
{
    return {"load_feedforward", "identify_rl", "identify_k", "align_rotor", "gain_design", "control_law"};
}
std::vector<std::string> protection_keys() { return {"loss_of_sync"}; }

std::vector<std::pair<std::string, std::vector<std::string>>> p000_extra_keys()
{
    return {{"trajectory.segments", segment_keys()},
            {"design", design_keys()},
            {"protection", protection_keys()},
            {"gains", gain_override_keys()},
            {"bounds", design_bound_keys()}};
}

// [design] (optional): design switches that are neither gains nor bounds
void read_design(const View& v, Scenario* sc)
{
    v.only(design_keys());
    if (const auto b = v.boolean("load_feedforward")) {
        sc->load_feedforward = *b ? 1 : 0;
    }
    if (const auto b = v.boolean("identify_rl")) {
        sc->identify_rl = *b ? 1 : 0;
    }
    if (const auto b = v.boolean("align_rotor")) {
        sc->align_rotor = *b ? 1 : 0;
    }
    if (const auto b = v.boolean("identify_k")) {
        sc->identify_k = *b ? 1 : 0;
    }
    if (const auto g = v.string("gain_design")) {
        if (*g == "continuous") {
            sc->gain_design = 0;
        } else if (*g == "discrete") {
            sc->gain_design = 1;
        } else {
            v.fail("gain_design", "must be \"continuous\" or \"discrete\" (got \"" + *g + "\")");
        }
    }
    if (const auto g = v.string("control_law")) {
        if (*g == "twisting") {
            sc->control_law = 0;
        } else if (*g == "load_angle") {
            if (!runs_here(*sc)) {
                v.fail("control_law", "\"load_angle\" is the position drive's law ([trajectory]); the speed "
                                      "drives have their own");
            }
            sc->control_law = 1;
        } else {
            v.fail("control_law", "must be \"twisting\" or \"load_angle\" (got \"" + *g + "\")");
        }
    }
}

// [protection] (optional): reactions to faults
void read_protection(const View& v, Scenario* sc)
{
    v.only(protection_keys());
    if (const auto r = v.string("loss_of_sync")) {
        if (*r == "relock") {
            if (!runs_here(*sc)) {
                v.fail("loss_of_sync", "\"relock\" needs the position drive ([trajectory]); the speed drives "
                                       "have no re-lock");
            }
            sc->los_relock = 1;
        } else if (*r != "safe") {
            v.fail("loss_of_sync", "must be \"safe\" or \"relock\" (got \"" + *r + "\")");
        }
    }
}

// Design fields by name into *out, in the order of keys: each >= 0
// (zero_ok) or > 0.
void read_fields(const View& v, const std::vector<std::string>& keys, bool zero_ok,
                 std::vector<std::pair<std::string, double>>* out)
{
    v.only(keys);
    for (const std::string& k : keys) {
        if (const auto x = v.number(k)) {
            if (zero_ok) {
                ge(v, k, *x, 0.0);
            } else {
                gt(v, k, *x, 0.0);
            }
            out->emplace_back(k, *x);
        }
    }
}

// [gains]: design overrides by field name (0 = let drive_design derive it)
void read_gains(const View& v, Scenario* sc) { read_fields(v, gain_override_keys(), true, &sc->gains); }

// [bounds]: design bounds by field name
void read_bounds(const View& v, Scenario* sc) { read_fields(v, design_bound_keys(), false, &sc->bounds); }

// [design], [protection], [gains], [bounds], in every scenario (host_drive.h)
void p000_parse_extra(const View& root, Scenario* sc)
{
    const struct {
        const char* table;
        void (*read)(const View& v, Scenario* sc);
    } tables[] = {{"design", &read_design}, {"protection", &read_protection}, {"gains", &read_gains}, {"bounds", &read_bounds}};
    for (const auto& t : tables) {
        if (const auto v = root.table(t.table)) {
            t.read(*v, sc);
        }
    }
}

// [trajectory]: [[trajectory.segments]], and the open/closed-loop switch
// speed [limits] omega_lim_rad_s (optional for the other drives)
void p000_parse(const View* t, Scenario* sc)
{
    if (!(sc->omega_lim_rad_s > 0.0)) {  // read_limits refused a value <= 0
        fail(sc->path, "limits.omega_lim_rad_s", "missing required field");
    }
    if (t == nullptr) {
        fail(sc->path, "trajectory", "missing required table");
    }
    const View& v = *t;
    v.only(p000_keys());
    const auto segs = v.tables("segments");
    if (!segs || segs->empty()) {
        v.fail("segments", "missing required field (at least one [[trajectory.segments]])");
    }
    if (segs->size() > static_cast<std::size_t>(TRAJECTORY_MAX_SEGMENTS)) {
        v.fail("segments", "at most " + std::to_string(TRAJECTORY_MAX_SEGMENTS) + " segments (got " +
                               std::to_string(segs->size()) + ")");
    }
    double t_free = 0.0;
    for (const View& s : *segs) {
        s.only(segment_keys());
        Segment g;
        g.t_start_s = s.number_req("t_start_s");
        ge(s, "t_start_s", g.t_start_s, t_free);
        g.duration_s = s.number_req("duration_s");
        gt(s, "duration_s", g.duration_s, 0.0);
        g.theta_to_rad = s.number_req("theta_to_rad");
        t_free = g.t_start_s + g.duration_s;
        sc->segments.push_back(g);
    }
}

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

// The replay's applied voltage: the drive's own hook (a winding each)
void p000_set_applied_voltage(drive_t* d, const double* v_V, int /*n_phases*/)
{
    paper000_drive_set_applied_voltage(static_cast<paper000_drive_t*>(d->self), to_mc(v_V[0]), to_mc(v_V[1]));
}

}  // namespace

void make_design_input(const Scenario& sc, drive_design_input_t* in)
{
    *in = drive_design_input_t{};
    drive_design_defaults(in);
    shared_design_input(sc, in);
    in->v_max_V = sc.v_max_V;
    in->omega_lim_rad_s = sc.omega_lim_rad_s;
    in->los_relock = sc.los_relock;
    if (sc.i_open_loop_A > 0.0) {
        in->i_open_loop_A = sc.i_open_loop_A;
    }
    if (sc.load_feedforward >= 0) {
        in->load_feedforward = sc.load_feedforward;
    }
    if (sc.identify_rl >= 0) {
        in->identify_rl = sc.identify_rl;
    }
    if (sc.align_rotor >= 0) {
        in->align_rotor = sc.align_rotor;
    }
    if (sc.identify_k >= 0) {
        in->identify_k = sc.identify_k;
    }
    if (sc.gain_design >= 0) {
        in->gain_design = sc.gain_design == 1 ? DRIVE_GAIN_DISCRETE : DRIVE_GAIN_CONTINUOUS;
    }
    if (sc.control_law >= 0) {
        in->control_law = sc.control_law == 1 ? P000_LAW_LOAD_ANGLE : P000_LAW_TWISTING;
    }
    in->n_segments = static_cast<int>(sc.segments.size());
    for (std::size_t k = 0; k < sc.segments.size() && k < DRIVE_DESIGN_MAX_SEGMENTS; ++k) {
        in->segments[k].t_start_s = sc.segments[k].t_start_s;
        in->segments[k].duration_s = sc.segments[k].duration_s;
        in->segments[k].theta_to_rad = sc.segments[k].theta_to_rad;
    }
    for (const auto& kv : sc.bounds) {
        for (const BoundField& f : kBoundFields) {
            if (kv.first == f.key) {
                in->*(f.member) = kv.second;
            }
        }
    }
    for (const auto& kv : sc.gains) {
        for (const GainField& f : kGainFields) {
            if (kv.first == f.key) {
                in->override.*(f.member) = kv.second;
            }
        }
    }
}

void design_and_init_drive(Scenario& sc, paper000_drive_t* drive)
{
    drive_design_input_t in;
    make_design_input(sc, &in);
    init_drive_from(sc, in, drive);
}

void init_drive_from(Scenario& sc, const drive_design_input_t& in, paper000_drive_t* drive)
{
    if (sc.motor.type != MotorType::kStepper2) {
        throw ScenarioError(sc.path + ": motor.file: the paper-000 position drive ([trajectory]) runs two-phase "
                            "steppers (type = \"stepper2\"); a pmsm3 motor takes the speed drive ([speed])");
    }
    paper000_config_t cfg;
    std::memset(&cfg, 0, sizeof(cfg));
    char err[256] = {0};
    if (!drive_design(&in, &cfg, err, sizeof(err))) {
        throw ScenarioError(sc.path + ": design: " + (err[0] != '\0' ? err : "drive_design rejected the input"));
    }
    cfg.deadtime = deadtime_comp_config(sc);  // [inverter] (an MCU board; the rig's amplifiers have none)
    if (!paper000_drive_init(drive, &cfg)) {
        const char* why = paper000_config_problem(&cfg);
        throw ScenarioError(sc.path + ": design: the configuration derived from the motor file and the scenario is " +
                            "not usable: " +
                            (why != nullptr ? std::string(why) + " (a motor or limit value far outside what the "
                                                                 "design was written for?)"
                                            : std::string("trajectory: a segment of zero or too many samples, or "
                                                          "segments out of order")));
    }
    sc.pre_ticks = drive->align_ticks;
}

namespace {

void p000_design_input(const Scenario& sc, void* in)
{
    make_design_input(sc, static_cast<drive_design_input_t*>(in));
}

void p000_design_from_input(Scenario& sc, const void* in, drive_config_storage_t* out)
{
    auto d = std::make_unique<paper000_drive_t>();
    init_drive_from(sc, *static_cast<const drive_design_input_t*>(in), d.get());  // sets sc.pre_ticks
    out->paper000 = d->cfg;
}

}  // namespace

extern const HostDrive kPaper000Host;
const HostDrive kPaper000Host = {kName, "trajectory", false, &p000_parse, &p000_design, &p000_keys, &p000_extra_keys,
                                 &p000_parse_extra, nullptr, &p000_peak_demand, &p000_set_applied_voltage, nullptr,
                                 nullptr, nullptr, MC_HOST_PARAMS(paper000_params), sizeof(drive_design_input_t),
                                 &p000_design_input, &p000_design_from_input};

}  // namespace mcsim
