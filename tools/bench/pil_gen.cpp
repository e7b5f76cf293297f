// pil_gen.cpp - records a processor-in-the-loop vector file from the host
// build, for any drive of the registry (firmware/drives/registry.h): runs a
// scenario with the drive in closed loop with the software plant, through
// the drive interface (drives/drive.h), and writes a C source
// (hal/backends/mcu/pil_vectors.h says what it defines) with
//   - the drive's configuration made on the host, as raw words (the layout
//     is the same on the Cortex-M targets: 4-byte fields, 32-bit enums,
//     checked by a _Static_assert on the size of <drive>_config_t in the
//     generated file and by the image against the drive's config_bytes),
//   - for every period: the fields of the hal_sample_t the drive got and of
//     the hal_command_t it returned, as raw words; a field that is the same
//     in every period is written once.
//   - after every period's step, the drive's signals (drives/drive.h: the
//     columns of its signal list, read_signals) as one hash of their bits
//     (pil_signal_hash_of, pil_vectors.h), their names in a comment.
// The bare-metal image (hal/backends/mcu/pil_image.c, built for the same
// drive with CMake MC_DRIVE) replays the samples through the drive's step
// and compares its commands with these bits, and its signals with these
// hashes.
//
// The configuration comes from the drive's host part (sim/host_drives/):
// the design motorsim runs for the scenario's drive ([drive] kind, or the
// drive whose table the scenario has: [trajectory], [speed], [paper002]).
// --drive defaults to the scenario's drive. --estimator NAME overrides the
// scenario's estimator of a drive that has several (flux|back_emf for a
// [speed] scenario, paper 001's drive; encoder|flux|hfi for a [paper002]
// one): the drive's host part checks which it takes (HostDrive::
// select_estimator) and names the one a configuration runs
// (HostDrive::estimator_name), written into the vectors' source line.
//
// Usage: mc_pil_gen [--drive NAME] [--estimator NAME] SCENARIO.toml OUT.c [MAX_SAMPLES]
//        mc_pil_gen --board-params [--drive NAME] [--estimator NAME] SCENARIO.toml OUT.c
//                   (an MCU board's values of the drive's parameters, see write_board_params)
#include <array>
#include <cinttypes>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "hal/hal.h"
#include "hal_sw_plant.h"
#include "host_drives/host_drive.h"
#include "model/encoder.h"
#include "model/fault_injection.h"
#include "scenario/rig.h"
#include "scenario/rig_hal.h"
#include "scenario/scenario.h"

extern "C" {
#include "drives/registry.h"
#if MC_HAS_PARAMS
#include "design/ops/drive_design_ops.h"
#endif
#include "pil_vectors.h"
}

namespace {

// hal/backends/mcu/pil_vectors.h: PIL_IN_* and PIL_OUT_* fields
constexpr std::size_t kInFields = 7;   // i_a, i_b, i_c, v_bus, angle, meta, status
constexpr std::size_t kOutFields = 4;  // v_a, v_b, v_c, n_phases
constexpr std::uint32_t kMetaHasAngle = 1u << 8;

std::uint32_t bits(mc_t v)
{
    std::uint32_t u;
    static_assert(sizeof(mc_t) == 4, "mc_t must be 32 bits");
    std::memcpy(&u, &v, 4);
    return u;
}

struct Options {
    std::string drive;      // registry name; empty: the scenario's
    std::string estimator;  // one of the drive's estimators; empty: the scenario's
    std::string board_scenario;  // a board's scenario: its values over the design reference's defaults
};

// The scenario's own drive: its [drive] kind, or the drive its table chose.
std::string scenario_drive(const mcsim::Scenario& sc) { return sc.drive_kind; }

// The configuration of drive name for scenario sc, as motorsim designs it
// (its host part, sim/host_drives/); paper 000's design sets sc.pre_ticks
// (its rotor alignment before t = 0).
void design(const std::string& name, const Options& opt, mcsim::Scenario& sc, drive_config_storage_t* cfg)
{
    std::memset(cfg, 0, sizeof *cfg);
    const mcsim::HostDrive* host = mcsim::host_drive_find(name);
    if (host == nullptr) throw std::runtime_error("--drive " + name + ": no host part designs this drive");
    if (sc.drive_kind != name) {
        throw std::runtime_error(sc.path + ": --drive " + name + " needs a scenario of that drive ([" + host->table +
                                 "], or [drive] kind = \"" + name + "\"); this one's is " + sc.drive_kind);
    }
    if (!opt.estimator.empty()) {
        if (host->select_estimator == nullptr) throw std::runtime_error("--estimator: the " + name + " drive has one estimator");
        host->select_estimator(&sc, opt.estimator);
    }
    if (sc.speed_gains.identify) {  // [speed] identify = true (paper 001)
        // motorsim would replace the drive model by the commissioning's
        // R, L, Phi first; not reproduced here
        throw std::runtime_error(sc.path + ": [speed] identify = true is not supported by mc_pil_gen");
    }
    host->design(sc, cfg);
}

// ", estimator NAME" when the drive has several (its host part names the
// one cfg runs), else "".
std::string estimator_note(const std::string& name, const drive_config_storage_t& cfg)
{
    const mcsim::HostDrive* host = mcsim::host_drive_find(name);
    if (host == nullptr || host->estimator_name == nullptr) return "";
    return std::string(", estimator ") + host->estimator_name(&cfg);
}

void write_cfg_words(FILE* f, const drive_config_storage_t& cfg, std::uint32_t bytes, const char* name)
{
    const std::size_t nw = (bytes + 3u) / 4u;
    std::vector<std::uint32_t> w(nw, 0u);
    std::memcpy(w.data(), &cfg, bytes);
    std::fprintf(f, "const uint32_t %s[%zu] = {", name, nw);
    for (std::size_t i = 0; i < nw; ++i) std::fprintf(f, "%s0x%08" PRIx32 "u,", (i % 8) ? "" : "\n  ", w[i]);
    std::fprintf(f, "\n};\n");
}

#if MC_HAS_PARAMS
// A board's values of the drive's parameters (what --board-params writes):
// each parameter whose value in the scenario's design input differs from
// the table's default, as its id and 32 bits, checked to design what the
// scenario designs with its values rounded as the board holds them (a
// scenario that sets something no parameter carries, or a value outside a
// parameter's range, is refused naming it). *estimator_note: the design's.
std::vector<std::pair<std::uint16_t, std::uint32_t>> board_values(mcsim::Scenario& sc, const std::string& name,
                                                                  const std::string& estimator,
                                                                  std::string* estimator_note_out)
{
    const drive_design_ops_t* d = drive_design_ops_find(name.c_str());
    const mcsim::HostDrive* host = mcsim::host_drive_find(name);
    if (d == nullptr || host == nullptr || host->design_input == nullptr) {
        throw std::runtime_error("--drive " + name + ": a drive without user parameters (design/ops/)");
    }
    if (sc.drive_kind != name) {
        throw std::runtime_error(sc.path + ": --drive " + name + " needs a scenario of that drive; this one's is " +
                                 sc.drive_kind);
    }
    if (!estimator.empty()) {
        if (host->select_estimator == nullptr) throw std::runtime_error("--estimator: the " + name + " drive has one estimator");
        host->select_estimator(&sc, estimator);
    }
    const std::size_t nw = (d->input_bytes + sizeof(std::max_align_t) - 1) / sizeof(std::max_align_t);
    std::vector<std::max_align_t> in_sc(nw), in_def(nw), in_img(nw);
    host->design_input(sc, in_sc.data());
    param_error_t perr{};
    if (!drive_design_defaults_input(d, in_def.data(), &perr) || !drive_design_defaults_input(d, in_img.data(), &perr)) {
        throw std::runtime_error("the " + name + " drive's parameters' defaults: " + perr.text);
    }
    std::vector<std::pair<std::uint16_t, std::uint32_t>> values;
    const param_table_t* t = d->params;
    for (std::uint16_t k = 0; k < t->n_params; ++k) {
        const param_desc_t& pd = t->params[k];
        param_value_t v{}, v0{};
        if (!params_read(t, in_sc.data(), pd.id, &v, &perr) || !params_read(t, in_def.data(), pd.id, &v0, &perr)) {
            throw std::runtime_error(std::string("parameter ") + pd.name + ": " + perr.text);
        }
        if (!params_check_value(&pd, v, &perr)) {
            throw std::runtime_error(sc.path + ": the drive's parameter " + pd.name + " as the scenario sets it: " +
                                     perr.text);
        }
        if (pd.access == PARAM_RO) {
            // fixed by the image (a phase count, a sample time): the scenario must agree
            if (v.u32 != v0.u32) {
                throw std::runtime_error(sc.path + ": the drive's parameter " + pd.name +
                                         " is read-only and the scenario sets another value than the image's");
            }
            continue;
        }
        // the scenario's value as the board holds it, in both inputs
        if (!params_write(t, in_sc.data(), pd.id, v, false, &perr) ||
            !params_write(t, in_img.data(), pd.id, v, false, &perr)) {
            throw std::runtime_error(std::string("parameter ") + pd.name + ": " + perr.text);
        }
        if (v.u32 != v0.u32) values.emplace_back(pd.id, v.u32);
    }
    auto cfg_sc = std::make_unique<drive_config_storage_t>();
    auto cfg_img = std::make_unique<drive_config_storage_t>();
    std::memset(cfg_sc.get(), 0, sizeof *cfg_sc);
    std::memset(cfg_img.get(), 0, sizeof *cfg_img);
    char err[256] = {0};
    if (!d->design(in_sc.data(), cfg_sc.get(), err, sizeof err)) {
        throw std::runtime_error(sc.path + ": the scenario's parameters do not design: " + err);
    }
    if (!d->design(in_img.data(), cfg_img.get(), err, sizeof err)) {
        throw std::runtime_error(sc.path + ": the image's values do not design: " + err);
    }
    const auto* a = reinterpret_cast<const unsigned char*>(cfg_sc.get());
    const auto* b = reinterpret_cast<const unsigned char*>(cfg_img.get());
    for (std::uint32_t k = 0; k < d->config_bytes; ++k) {
        if (a[k] != b[k]) {
            throw std::runtime_error(sc.path + ": the scenario sets a design input no parameter of the " + name +
                                     " drive carries (its configuration differs at byte " + std::to_string(k) +
                                     "): give it a parameter (firmware/drives/" + name + "/params.toml) or leave it");
        }
    }
    if (estimator_note_out != nullptr) *estimator_note_out = estimator_note(name, *cfg_sc);
    return values;
}
#endif

// The reference an image that designs on the board compares its own design
// with (hal/backends/stm32f405/main_qemu.c): the drive's configuration
// designed here from its parameters' defaults (design/ops/), with a
// board's values over them (--board-scenario: what the flashable image of
// that board starts from), as pil_design_cfg_bytes and
// pil_design_cfg_words; nothing for a drive or a build without parameters
// (fixed point).
void write_design_reference(FILE* f, const std::string& name, const Options& opt)
{
#if MC_HAS_PARAMS
    const drive_design_ops_t* d = drive_design_ops_find(name.c_str());
    if (d == nullptr) return;
    std::vector<std::max_align_t> in((d->input_bytes + sizeof(std::max_align_t) - 1) / sizeof(std::max_align_t));
    auto cfg = std::make_unique<drive_config_storage_t>();
    std::memset(cfg.get(), 0, sizeof *cfg);
    param_error_t perr{};
    char err[256] = {0};
    if (!drive_design_defaults_input(d, in.data(), &perr)) {
        throw std::runtime_error("the " + name + " drive's parameters' defaults: " + perr.text);
    }
    if (!opt.board_scenario.empty()) {
        // the board's values over the defaults, as its flashable image starts
        mcsim::Scenario bsc = mcsim::load_scenario(opt.board_scenario);
        for (const auto& [id, u] : board_values(bsc, name, "", nullptr)) {
            param_value_t v{};
            v.u32 = u;
            if (!params_write(d->params, in.data(), id, v, false, &perr)) {
                throw std::runtime_error(opt.board_scenario + ": " + perr.text);
            }
        }
    }
    if (!d->design(in.data(), cfg.get(), err, sizeof err)) {
        throw std::runtime_error("the " + name + " drive's parameters do not design: " + std::string(err));
    }
    std::fprintf(f, "const uint32_t pil_design_cfg_bytes = %uu;\n", static_cast<unsigned>(d->config_bytes));
    write_cfg_words(f, *cfg, d->config_bytes, "pil_design_cfg_words");
#else
    (void)f;
    (void)name;
    (void)opt;
#endif
}

struct Rec {
    drive_t drive{};
    std::vector<std::array<std::uint32_t, kInFields>> in;
    std::vector<std::array<std::uint32_t, kOutFields>> out;
    std::vector<std::uint32_t> signal_hash;  // the drive's signals after each step
    std::uint32_t n_signals = 0;
    std::uint32_t max_samples = 0;
    bool faulted = false;
    std::string bad_sample;  // why a sample cannot be rebuilt on the target
};

void callback(void* ctx, const hal_sample_t* in, hal_command_t* out)
{
    Rec* r = static_cast<Rec*>(ctx);
    const std::size_t k = r->in.size();
    const bool ok = drive_step(&r->drive, in, out);
    if (k < r->max_samples) {
        if (in->tick != k && r->bad_sample.empty()) {
            r->bad_sample = "period " + std::to_string(k) + ": tick " + std::to_string(in->tick) +
                            " is not the period's index, as the image rebuilds it";
        }
        r->in.push_back({bits(in->i_A[0]), bits(in->i_A[1]), bits(in->i_A[2]), bits(in->v_bus_V), bits(in->angle_rad),
                         static_cast<std::uint32_t>(in->n_phases) | (in->has_angle ? kMetaHasAngle : 0u), in->status});
        r->out.push_back({bits(out->v_V[0]), bits(out->v_V[1]), bits(out->v_V[2]),
                          static_cast<std::uint32_t>(out->n_phases)});
        std::array<mc_t, DRIVE_SIGNALS_MAX> v{};
        std::array<std::uint32_t, DRIVE_SIGNALS_MAX> w{};
        drive_read_signals(&r->drive, v.data());
        for (std::uint32_t j = 0; j < r->n_signals; ++j) w[j] = bits(v[j]);
        r->signal_hash.push_back(pil_signal_hash_of(w.data(), r->n_signals));
    }
    if (!ok) {
        r->faulted = true;
        hal_safe_state();
    }
}

std::uint32_t sample_limit(const mcsim::Scenario& sc, const char* arg)
{
    std::uint32_t n = sc.n_ticks();
    if (arg != nullptr) {
        const unsigned long m = std::stoul(arg);
        if (m > 0 && m < n) n = static_cast<std::uint32_t>(m);
    }
    return n;
}

// Which fields vary over the rows (bit k), and each field's first value.
template <std::size_t N>
std::uint32_t varying(const std::vector<std::array<std::uint32_t, N>>& rows)
{
    std::uint32_t m = 0;
    for (const auto& r : rows) {
        for (std::size_t j = 0; j < N; ++j) {
            if (r[j] != rows[0][j]) m |= 1u << j;
        }
    }
    return m;
}

template <std::size_t N>
void write_consts(FILE* f, const char* name, const std::array<std::uint32_t, N>& first)
{
    std::fprintf(f, "const uint32_t %s[%zu] = {", name, N);
    for (std::size_t j = 0; j < N; ++j) std::fprintf(f, "0x%" PRIx32 "u,", first[j]);
    std::fprintf(f, "};\n");
}

int record(mcsim::Scenario& sc, const Options& opt, const char* out_c, const char* max_arg)
{
    const std::string name = opt.drive.empty() ? scenario_drive(sc) : opt.drive;
    const drive_ops_t* ops = drive_find(name.c_str());
    if (ops == nullptr) throw std::runtime_error("--drive " + name + ": not a drive of the registry");
    auto cfg = std::make_unique<drive_config_storage_t>();
    design(name, opt, sc, cfg.get());  // before the rig: paper000's alignment moves t = 0

    auto storage = std::make_unique<drive_storage_t>();
    Rec rec;
    if (!drive_bind(&rec.drive, ops, storage.get())) throw std::runtime_error(name + ": drive_bind failed");
    if (!drive_init(&rec.drive, cfg.get())) {
        const char* why = ops->config_problem != nullptr ? ops->config_problem(cfg.get()) : nullptr;
        throw std::runtime_error(sc.path + ": " + name + " refused its configuration" +
                                 (why != nullptr ? std::string(": ") + why : std::string()));
    }
    rec.max_samples = sample_limit(sc, max_arg);
    const drive_signal_t* signals = drive_signals(&rec.drive, &rec.n_signals);
    if (rec.n_signals > DRIVE_SIGNALS_MAX) throw std::runtime_error(name + ": more signals than DRIVE_SIGNALS_MAX");

    // the bench as motorsim builds it (rig, delay, encoder, injected faults)
    mcsim::Rig rig(sc);
    mcsim::attach_rig(rig, sc);  // plant, sensor, amplifier or [inverter], delay: as motorsim
    std::unique_ptr<mcsim::Encoder> encoder;
    if (sc.encoder.present()) {
        encoder = std::make_unique<mcsim::Encoder>(sc.encoder, sc.seed);
        hal_sw_plant_set_encoder(encoder.get());
    }
    mcsim::FaultInjector injector(sc.faults, sc.seed);
    if (sc.faults.any()) hal_sw_plant_set_faults(&injector);
    if (!hal_start(&callback, &rec)) {
        hal_sw_plant_detach();
        throw std::runtime_error(std::string("hal_start: ") + hal_last_error());
    }
    hal_sw_plant_run(rec.max_samples);
    hal_safe_state();
    hal_sw_plant_detach();
    if (!rec.bad_sample.empty()) throw std::runtime_error(rec.bad_sample);
    const std::size_t n = rec.in.size();
    if (n == 0) throw std::runtime_error("no period recorded");

    const std::uint32_t in_var = varying(rec.in);
    const std::uint32_t out_var = varying(rec.out);
    const int words = __builtin_popcount(in_var) + __builtin_popcount(out_var);
    const std::string note = estimator_note(name, *cfg);
    FILE* f = std::fopen(out_c, "w");
    if (!f) throw std::runtime_error(std::string("cannot write ") + out_c);
    std::fprintf(f, "/* Generated by tools/bench/pil_gen.cpp (--drive %s) from %s: do not edit. */\n", name.c_str(),
                 sc.path.c_str());
    std::fprintf(f, "#include <stdint.h>\n#include \"drives/%s/%s_drive.h\"\n#include \"pil_vectors.h\"\n\n",
                 name.c_str(), name.c_str());
    std::fprintf(f, "_Static_assert(sizeof(%s_config_t) == %u, \"%s_config_t layout differs from the host's\");\n",
                 name.c_str(), static_cast<unsigned>(ops->config_bytes), name.c_str());
    std::fprintf(f, "_Static_assert(MC_FIXED == %d, \"vectors were made for the other numeric type\");\n\n",
                 (int)MC_FIXED);
    std::fprintf(f, "const char pil_source[] = \"%s (%s%s, %s, %zu periods%s)\";\n", sc.stem.c_str(), name.c_str(),
                 note.c_str(), MC_FIXED ? "fixed Q14.17" : "float32", n, rec.faulted ? ", drive FAULT" : "");
    std::fprintf(f, "const char pil_drive[] = \"%s\";\n", name.c_str());
    std::fprintf(f, "const uint32_t pil_control_hz = %luu;\n", std::lround(1.0 / sc.ts_s));
    std::fprintf(f, "const uint32_t pil_cfg_bytes = %uu;\n", static_cast<unsigned>(ops->config_bytes));
    write_cfg_words(f, *cfg, ops->config_bytes, "pil_cfg_words");
    write_design_reference(f, name, opt);
    std::fprintf(f, "const uint32_t pil_n = %zuu;\n", n);
    std::fprintf(f, "const uint32_t pil_in_varying = 0x%" PRIx32 "u, pil_out_varying = 0x%" PRIx32 "u;\n", in_var,
                 out_var);
    write_consts(f, "pil_in_const", rec.in[0]);
    write_consts(f, "pil_out_const", rec.out[0]);
    std::fprintf(f, "const uint32_t pil_row_words = %du;\n", words);
    std::fprintf(f, "const uint32_t pil_rows[%zu] = {\n", n * static_cast<std::size_t>(words > 0 ? words : 1));
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = 0; j < kInFields; ++j) {
            if ((in_var >> j) & 1u) std::fprintf(f, "0x%" PRIx32 "u,", rec.in[i][j]);
        }
        for (std::size_t j = 0; j < kOutFields; ++j) {
            if ((out_var >> j) & 1u) std::fprintf(f, "0x%" PRIx32 "u,", rec.out[i][j]);
        }
        std::fputc('\n', f);
    }
    if (words == 0) std::fprintf(f, "0u\n");
    std::fprintf(f, "};\n");
    std::fprintf(f, "/* the drive's signals, hashed in this order:");
    for (std::uint32_t j = 0; j < rec.n_signals; ++j) std::fprintf(f, "%s %s", j ? "," : "", signals[j].name);
    std::fprintf(f, " */\nconst uint32_t pil_signal_count = %uu;\n", static_cast<unsigned>(rec.n_signals));
    std::fprintf(f, "const uint32_t pil_signal_hash[%zu] = {", n);
    for (std::size_t i = 0; i < n; ++i) std::fprintf(f, "%s0x%08" PRIx32 "u,", (i % 8) ? "" : "\n  ", rec.signal_hash[i]);
    std::fprintf(f, "\n};\n");
    if (std::fclose(f) != 0) throw std::runtime_error(std::string("cannot write ") + out_c);
    std::fprintf(stderr, "mc_pil_gen: %zu periods of %s (%s%s, %s)%s, %d words a period -> %s\n", n, sc.stem.c_str(),
                 name.c_str(), note.c_str(), MC_FIXED ? "fixed" : "float", rec.faulted ? " [drive faulted]" : "",
                 words, out_c);
    return 0;
}

// --board-params: the image's values of the drive's parameters for an MCU
// board (hal/backends/stm32f405/app_params.h), written to the drive's own
// folder (firmware/drives/<drive>/boards/<board>[_<variant>]_params.c):
// each parameter whose value in the scenario's design input differs from
// the table's default, as its id and 32 bits (board_drive_values[]). The
// board designs from them (the table's defaults, these over them) with the
// host's code; refused here, naming it, when the scenario sets a value
// outside a parameter's range or sets something of the design input no
// parameter carries (the design from the values differs from the one from
// the scenario with its parameters rounded as the board holds them).
int write_board_params(mcsim::Scenario& sc, const Options& opt, const char* given_path, const char* out_c)
{
#if MC_HAS_PARAMS
    const std::string name = opt.drive.empty() ? scenario_drive(sc) : opt.drive;
    std::string note;
    const auto values = board_values(sc, name, opt.estimator, &note);
    const param_table_t* t = drive_design_ops_find(name.c_str())->params;
    const std::string tmp = std::string(out_c) + ".tmp";
    FILE* f = std::fopen(tmp.c_str(), "w");
    if (!f) throw std::runtime_error(std::string("cannot write ") + tmp);
    std::fprintf(f, "/* Generated by tools/bench/pil_gen.cpp --board-params from %s: do not edit\n", given_path);
    std::fprintf(f, " * (ctest mcu.board_params_current regenerates it and compares). The %s drive's\n",
                 name.c_str());
    std::fprintf(f, " * parameters whose value for this board differs from the table's default\n");
    std::fprintf(f, " * (firmware/drives/%s/params.toml, docs/parameters.md): the base the\n", name.c_str());
    std::fprintf(f, " * board designs from and \"defaults\" restores (app_params.h). */\n");
    std::fprintf(f, "#include <stdint.h>\n#include \"app_params.h\"\n\n");
    std::fprintf(f, "_Static_assert(MC_FIXED == 0, \"the parameters are the float images'\");\n\n");
    std::fprintf(f, "const char board_drive_values_source[] = \"%s (%s%s)\";\n", given_path, name.c_str(),
                 note.c_str());
    std::fprintf(f, "const uint32_t board_drive_values_count = %zuu;\n", values.size());
    std::fprintf(f, "const app_param_value_t board_drive_values[%zu] = {\n", values.empty() ? 1 : values.size());
    for (const auto& [id, u] : values) {
        const param_desc_t* pd = params_find(t, id, nullptr);
        param_value_t v{};
        v.u32 = u;
        std::string shown;
        char buf[64];
        switch (pd->type) {
        case PARAM_F32: std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(v.f32)); break;
        case PARAM_I32: std::snprintf(buf, sizeof buf, "%" PRId32, v.i32); break;
        case PARAM_ENUM:
            std::snprintf(buf, sizeof buf, "%s", v.i32 >= 0 && v.i32 < pd->n_names ? pd->names[v.i32] : "?");
            break;
        default: std::snprintf(buf, sizeof buf, "%" PRIu32, v.u32); break;
        }
        std::fprintf(f, "    {0x%04xu, 0x%08" PRIx32 "u}, /* %s = %s%s%s */\n", id, u, pd->name, buf,
                     pd->unit[0] != '\0' ? " " : "", pd->unit);
    }
    if (values.empty()) std::fprintf(f, "    {0u, 0u}, /* none: the defaults */\n");
    std::fprintf(f, "};\n");
    if (std::fclose(f) != 0 || std::rename(tmp.c_str(), out_c) != 0) {
        throw std::runtime_error(std::string("cannot write ") + out_c);
    }
    return 0;
#else
    (void)sc;
    (void)opt;
    (void)given_path;
    (void)out_c;
    throw std::runtime_error("--board-params: the parameters are the float build's (this one is fixed point)");
#endif
}

}  // namespace

int main(int argc, char** argv)
{
    const char* usage =
        "usage: %s [--drive NAME] [--estimator NAME] [--board-scenario BOARD.toml] SCENARIO.toml OUT.c [MAX_SAMPLES]\n"
        "       %s --board-params [--drive NAME] [--estimator NAME] SCENARIO.toml OUT.c\n"
        "--estimator: one of the drive's estimators (default: the scenario's)\n"
        "--board-scenario: the design reference (pil_design_cfg_words) with that board's values\n"
        "--drive: a drive of the registry (default: the scenario's):";
    Options opt;
    bool board = false;
    std::vector<const char*> pos;
    for (int a = 1; a < argc; ++a) {
        const std::string s = argv[a];
        if ((s == "--drive" || s == "--estimator") && a + 1 < argc) {
            (s == "--drive" ? opt.drive : opt.estimator) = argv[++a];
        } else if (s == "--board-scenario" && a + 1 < argc) {
            opt.board_scenario = argv[++a];
        } else if (s == "--board-params") {
            board = true;
        } else if (s.rfind("--", 0) == 0) {
            pos.clear();
            break;
        } else {
            pos.push_back(argv[a]);
        }
    }
    const bool bad_drive = !opt.drive.empty() && drive_find(opt.drive.c_str()) == nullptr;
    if (pos.size() < 2 || pos.size() > (board ? 2u : 3u) || bad_drive) {
        if (bad_drive) std::fprintf(stderr, "error: --drive %s: not a drive of the registry\n", opt.drive.c_str());
        std::fprintf(stderr, usage, argv[0], argv[0]);
        for (std::size_t k = 0; k < drive_registry_count; ++k) std::fprintf(stderr, " %s", drive_registry[k]->name);
        std::fprintf(stderr, "\n");
        return 2;
    }
    try {
        mcsim::Scenario sc = mcsim::load_scenario(pos[0]);
        if (board) return write_board_params(sc, opt, pos[0], pos[1]);
        return record(sc, opt, pos[1], pos.size() > 2 ? pos[2] : nullptr);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
}
