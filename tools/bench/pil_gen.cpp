// pil_gen.cpp - records a processor-in-the-loop vector file from the host
// build: runs a scenario with a drive in closed loop with the software
// plant, and writes a C source with
//   - the drive's configuration made on the host, as raw words (the layout
//     is the same on the Cortex-M targets: 4-byte fields, 32-bit enums,
//     checked by a _Static_assert on sizeof in the generated file),
//   - for every period: what the drive got and what it returned, as raw
//     mc_t bits.
// Two drives (--drive):
//   paper000  paper000_config_t from drive_design() (default scenario
//             sim/scenarios/paper000_ideal.toml); per period the two phase
//             currents and the two voltages: pil_io[n][4] = ia, ib, va, vb.
//             The image is hal/backends/mcu/pil_main.c.
//   paper001  paper001_config_t from p001_design() ([speed] scenarios, e.g.
//             sim/scenarios/paper001_benchmark.toml), as motorsim makes it
//             (design_and_init_speed_drive); per period the three phase
//             currents, the bus voltage and the three phase voltages:
//             pil_io[n][7] = ia, ib, ic, vbus, va, vb, vc. The image is
//             hal/backends/mcu/pil_paper001_main.c. --estimator flux|back_emf
//             overrides the scenario's [speed] estimator.
//   default: paper001 for a [speed] scenario, paper000 otherwise.
// The bare-metal image replays the inputs through the drive's init/step and
// compares its outputs with these bits.
// Usage: mc_pil_gen [--drive paper000|paper001] [--estimator flux|back_emf]
//                   SCENARIO.toml OUT.c [MAX_SAMPLES]
//        mc_pil_gen --board-config SCENARIO.toml OUT.c   (an MCU board's drive
//                   configuration only, see write_board_config)
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "drives/paper000/paper000_drive.h"
#include "drives/paper001/paper001_drive.h"
#include "hal/hal.h"
#include "hal_sw_plant.h"
#include "scenario/rig.h"
#include "model/amplifier.h"
#include "model/current_sensor.h"
#include "model/pm_plant.h"
#include "scenario/design_input.h"
#include "scenario/scenario.h"

namespace {

struct Rec {
    paper000_drive_t* drive = nullptr;
    std::vector<std::uint32_t> io;  // ia, ib, va, vb per period
    std::uint32_t max_samples = 0;
    bool faulted = false;
};

std::uint32_t bits(mc_t v)
{
    std::uint32_t u;
    static_assert(sizeof(mc_t) == 4, "mc_t must be 32 bits");
    std::memcpy(&u, &v, 4);
    return u;
}

void callback(void* ctx, const hal_sample_t* in, hal_command_t* out)
{
    Rec* r = static_cast<Rec*>(ctx);
    const bool ok = paper000_drive_step(r->drive, in, out);
    if (r->io.size() / 4 < r->max_samples) {
        r->io.insert(r->io.end(), {bits(in->i_A[0]), bits(in->i_A[1]), bits(out->v_V[0]), bits(out->v_V[1])});
    }
    if (!ok) {
        r->faulted = true;
        hal_safe_state();
    }
}

// paper 001: the image rebuilds each sample from the recorded currents and
// bus voltage with tick = period, n_phases = pil_n_phases, no angle sensor,
// status 0; anything else the software plant sent is refused here.
constexpr std::size_t kP001Words = 7;  // ia, ib, ic, vbus, va, vb, vc

struct Rec001 {
    paper001_drive_t* drive = nullptr;
    std::vector<std::uint32_t> io;
    std::uint32_t max_samples = 0;
    std::uint8_t n_phases = 0;
    bool faulted = false;
    std::string bad_sample;  // why a sample cannot be rebuilt on the target
};

void callback001(void* ctx, const hal_sample_t* in, hal_command_t* out)
{
    Rec001* r = static_cast<Rec001*>(ctx);
    const std::size_t k = r->io.size() / kP001Words;
    const bool ok = paper001_drive_step(r->drive, in, out);
    if (k < r->max_samples) {
        if (r->bad_sample.empty()) {
            if (k == 0) r->n_phases = in->n_phases;
            if (in->tick != k || in->n_phases != r->n_phases || in->has_angle || in->status != 0u) {
                r->bad_sample = "period " + std::to_string(k) + ": tick/n_phases/has_angle/status not as the image "
                                "rebuilds them";
            }
        }
        r->io.insert(r->io.end(), {bits(in->i_A[0]), bits(in->i_A[1]), bits(in->i_A[2]), bits(in->v_bus_V),
                                   bits(out->v_V[0]), bits(out->v_V[1]), bits(out->v_V[2])});
    }
    if (!ok) {
        r->faulted = true;
        hal_safe_state();
    }
}

template <typename Cfg>
void write_cfg_words(FILE* f, const Cfg& cfg, const char* name = "pil_cfg_words")
{
    const std::size_t nw = (sizeof(Cfg) + 3) / 4;
    std::vector<std::uint32_t> w(nw, 0u);
    std::memcpy(w.data(), &cfg, sizeof(Cfg));
    std::fprintf(f, "const uint32_t %s[%zu] = {", name, nw);
    for (std::size_t i = 0; i < nw; ++i) std::fprintf(f, "%s0x%08" PRIx32 "u,", (i % 8) ? "" : "\n  ", w[i]);
    std::fprintf(f, "\n};\n");
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

int record_paper000(const mcsim::Scenario& sc_in, const char* out_c, const char* max_arg)
{
    mcsim::Scenario sc = sc_in;  // the design sets its pre_ticks (alignment)
    auto drive = std::make_unique<paper000_drive_t>();
    mcsim::design_and_init_drive(sc, drive.get());
    const paper000_config_t cfg = drive->cfg;  // what paper000_drive_init got

    mcsim::Rig rig(sc);
    mcsim::PmPlant& plant = rig.plant;
    mcsim::CurrentSensor& sensor = rig.sensor;
    const mcsim::Amplifier& amp = rig.amp;

    Rec rec;
    rec.drive = drive.get();
    rec.max_samples = sample_limit(sc, max_arg);
    hal_sw_plant_attach(&plant, &sensor, amp, sc.ts_s);
    (void)hal_sw_plant_set_compute_delay(sc.compute_delay_samples);  // the board's, as motorsim; validated at load
    if (!hal_start(&callback, &rec)) {
        throw std::runtime_error(std::string("hal_start: ") + hal_last_error());
    }
    hal_sw_plant_run(rec.max_samples);
    hal_sw_plant_detach();
    const std::size_t n = rec.io.size() / 4;
    if (n == 0) throw std::runtime_error("no period recorded");

    FILE* f = std::fopen(out_c, "w");
    if (!f) throw std::runtime_error(std::string("cannot write ") + out_c);
    std::fprintf(f, "/* Generated by tools/bench/pil_gen.cpp from %s: do not edit. */\n", sc.path.c_str());
    std::fprintf(f, "#include <stdint.h>\n#include \"drives/paper000/paper000_drive.h\"\n#include \"pil_vectors.h\"\n\n");
    std::fprintf(f, "_Static_assert(sizeof(paper000_config_t) == %zu, \"paper000_config_t layout differs from the host's\");\n",
                 sizeof(paper000_config_t));
    std::fprintf(f, "_Static_assert(MC_FIXED == %d, \"vectors were made for the other numeric type\");\n\n",
                 (int)MC_FIXED);
    std::fprintf(f, "const char pil_source[] = \"%s (%s, %zu periods%s)\";\n", sc.stem.c_str(),
                 MC_FIXED ? "fixed Q14.17" : "float32", n, rec.faulted ? ", drive FAULT" : "");
    write_cfg_words(f, cfg);
    std::fprintf(f, "const uint32_t pil_n = %zuu;\nconst uint32_t pil_io[%zu][4] = {\n", n, n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t* p = &rec.io[4 * i];
        std::fprintf(f, "{0x%" PRIx32 "u,0x%" PRIx32 "u,0x%" PRIx32 "u,0x%" PRIx32 "u},\n", p[0], p[1], p[2], p[3]);
    }
    std::fprintf(f, "};\n");
    std::fclose(f);
    std::fprintf(stderr, "mc_pil_gen: %zu periods of %s (%s)%s -> %s\n", n, sc.stem.c_str(),
                 MC_FIXED ? "fixed" : "float", rec.faulted ? " [drive faulted]" : "", out_c);
    return 0;
}

int record_paper001(const mcsim::Scenario& sc, const char* out_c, const char* max_arg)
{
    if (sc.speed_gains.identify) {
        // motorsim would replace the drive model by the commissioning's
        // R, L, Phi first; not reproduced here
        throw std::runtime_error(sc.path + ": [speed] identify = true is not supported by mc_pil_gen");
    }
    auto drive = std::make_unique<paper001_drive_t>();
    p001_design_report_t rep{};
    mcsim::design_and_init_speed_drive(sc, drive.get(), &rep);
    const paper001_config_t cfg = drive->cfg;  // what paper001_drive_init got

    mcsim::Rig rig(sc);
    hal_sw_plant_attach(&rig.plant, &rig.sensor, rig.amp, sc.ts_s);
    Rec001 rec;
    rec.drive = drive.get();
    rec.max_samples = sample_limit(sc, max_arg);
    if (!hal_start(&callback001, &rec)) {
        throw std::runtime_error(std::string("hal_start: ") + hal_last_error());
    }
    hal_sw_plant_run(rec.max_samples);
    hal_safe_state();
    hal_sw_plant_detach();
    if (!rec.bad_sample.empty()) throw std::runtime_error(rec.bad_sample);
    const std::size_t n = rec.io.size() / kP001Words;
    if (n == 0) throw std::runtime_error("no period recorded");
    const char* est = (cfg.estimator == P001_ESTIMATOR_BACK_EMF) ? "back_emf" : "flux";

    FILE* f = std::fopen(out_c, "w");
    if (!f) throw std::runtime_error(std::string("cannot write ") + out_c);
    std::fprintf(f, "/* Generated by tools/bench/pil_gen.cpp (--drive paper001) from %s: do not edit. */\n",
                 sc.path.c_str());
    std::fprintf(f, "#include <stdint.h>\n#include \"drives/paper001/paper001_drive.h\"\n#include \"pil_vectors.h\"\n\n");
    std::fprintf(f,
                 "_Static_assert(sizeof(paper001_config_t) == %zu, \"paper001_config_t layout differs from the "
                 "host's\");\n",
                 sizeof(paper001_config_t));
    std::fprintf(f, "_Static_assert(MC_FIXED == %d, \"vectors were made for the other numeric type\");\n",
                 (int)MC_FIXED);
    std::fprintf(f, "_Static_assert(PIL_P001_IO_WORDS == %zu, \"row layout differs from pil_vectors.h\");\n\n",
                 kP001Words);
    std::fprintf(f, "const char pil_source[] = \"%s (paper001, estimator %s, %s, %zu periods%s)\";\n",
                 sc.stem.c_str(), est, MC_FIXED ? "fixed Q14.17" : "float32", n, rec.faulted ? ", drive FAULT" : "");
    write_cfg_words(f, cfg);
    std::fprintf(f, "const uint32_t pil_n_phases = %uu;\n", static_cast<unsigned>(rec.n_phases));
    std::fprintf(f, "const uint32_t pil_n = %zuu;\nconst uint32_t pil_io[%zu][PIL_P001_IO_WORDS] = {\n", n, n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t* p = &rec.io[kP001Words * i];
        std::fprintf(f, "{0x%" PRIx32 "u,0x%" PRIx32 "u,0x%" PRIx32 "u,0x%" PRIx32 "u,0x%" PRIx32 "u,0x%" PRIx32
                     "u,0x%" PRIx32 "u},\n",
                     p[0], p[1], p[2], p[3], p[4], p[5], p[6]);
    }
    std::fprintf(f, "};\n");
    std::fclose(f);
    std::fprintf(stderr, "mc_pil_gen: %zu periods of %s (paper001, estimator %s, %s)%s -> %s\n", n, sc.stem.c_str(),
                 est, MC_FIXED ? "fixed" : "float", rec.faulted ? " [drive faulted]" : "", out_c);
    return 0;
}

// --board-config: only the paper-001 drive's configuration, as the words
// of board_drive_cfg_words[] for an MCU image's board
// (hal/backends/stm32f405/boards/board.h). The scenario path is written as
// given (relative to the repository, so that the file does not depend on
// where the repository is).
int write_board_config(const mcsim::Scenario& sc, const char* given_path, const char* out_c)
{
    if (sc.speed_gains.identify) {
        throw std::runtime_error(sc.path + ": [speed] identify = true is not supported for a board configuration");
    }
    auto drive = std::make_unique<paper001_drive_t>();
    p001_design_report_t rep{};
    mcsim::design_and_init_speed_drive(sc, drive.get(), &rep);
    const paper001_config_t cfg = drive->cfg;
    const std::string tmp = std::string(out_c) + ".tmp";
    FILE* f = std::fopen(tmp.c_str(), "w");
    if (!f) throw std::runtime_error(std::string("cannot write ") + tmp);
    std::fprintf(f, "/* Generated by tools/bench/pil_gen.cpp --board-config from %s: do not edit\n", given_path);
    std::fprintf(f, " * (ctest mcu.board_config_current regenerates it and compares). */\n");
    std::fprintf(f, "#include <stdint.h>\n#include \"boards/board.h\"\n#include \"drives/paper001/paper001_drive.h\"\n\n");
    std::fprintf(f,
                 "_Static_assert(sizeof(paper001_config_t) == %zu, \"paper001_config_t layout differs from the "
                 "host's\");\n",
                 sizeof(paper001_config_t));
    std::fprintf(f, "_Static_assert(MC_FIXED == %d, \"made for the other numeric type\");\n\n", (int)MC_FIXED);
    std::fprintf(f, "const char board_drive_cfg_source[] = \"%s (paper001, estimator %s, %s)\";\n", given_path,
                 cfg.estimator == P001_ESTIMATOR_BACK_EMF ? "back_emf" : "flux", MC_FIXED ? "fixed Q14.17" : "float32");
    write_cfg_words(f, cfg, "board_drive_cfg_words");
    if (std::fclose(f) != 0 || std::rename(tmp.c_str(), out_c) != 0) {
        throw std::runtime_error(std::string("cannot write ") + out_c);
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv)
{
    const char* usage =
        "usage: %s [--drive paper000|paper001] [--estimator flux|back_emf] SCENARIO.toml OUT.c [MAX_SAMPLES]\n";
    std::string drive_opt, est_opt;
    std::vector<const char*> pos;
    if (argc == 4 && std::string(argv[1]) == "--board-config") {
        try {
            const mcsim::Scenario sc = mcsim::load_scenario(argv[2]);
            if (!sc.speed_drive) throw std::runtime_error(std::string(argv[2]) + ": a board configuration needs a [speed] scenario");
            return write_board_config(sc, argv[2], argv[3]);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "error: %s\n", e.what());
            return 1;
        }
    }
    for (int a = 1; a < argc; ++a) {
        const std::string s = argv[a];
        if ((s == "--drive" || s == "--estimator") && a + 1 < argc) {
            (s == "--drive" ? drive_opt : est_opt) = argv[++a];
        } else if (s.rfind("--", 0) == 0) {
            std::fprintf(stderr, usage, argv[0]);
            return 2;
        } else {
            pos.push_back(argv[a]);
        }
    }
    if (pos.size() < 2 || pos.size() > 3 || (!drive_opt.empty() && drive_opt != "paper000" && drive_opt != "paper001") ||
        (!est_opt.empty() && est_opt != "flux" && est_opt != "back_emf")) {
        std::fprintf(stderr, usage, argv[0]);
        return 2;
    }
    try {
        mcsim::Scenario sc = mcsim::load_scenario(pos[0]);
        const std::string drive = drive_opt.empty() ? (sc.speed_drive ? "paper001" : "paper000") : drive_opt;
        const char* max_arg = pos.size() > 2 ? pos[2] : nullptr;
        if (drive == "paper001") {
            if (!sc.speed_drive) throw std::runtime_error(sc.path + ": --drive paper001 needs a [speed] scenario");
            if (!est_opt.empty()) sc.speed_gains.estimator = (est_opt == "back_emf") ? 1 : 0;
            return record_paper001(sc, pos[1], max_arg);
        }
        if (!est_opt.empty()) throw std::runtime_error("--estimator applies to --drive paper001 only");
        return record_paper000(sc, pos[1], max_arg);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
}
