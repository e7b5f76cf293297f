// fuzz_scenario.cpp - libFuzzer target: arbitrary bytes as a scenario file
// and as a motor file (sim/scenario/scenario.h). Built with
// -fsanitize=fuzzer,address,undefined by the MC_FUZZ build of
// scripts/fuzz.sh; docs/testing.md, "Static analysis and fuzzing".
//
// The contract checked: load_scenario() and load_motor_file() either return
// or throw mcsim::ScenarioError whose message is one line (motorsim prints
// it as "error: FILE: KEY: reason", exit status 2). Any other exception
// escapes and aborts (so does a crash, a leak, undefined behaviour or a
// hang: libFuzzer and the sanitizers report those).
//
// Motor files: a scenario names its motor file relative to itself. Each
// input is written to WORK/in/fuzz.toml, and every motor file of the
// repository (sim/motors, tests/sim/{bad_scenarios,failing_runs}/motors) is
// copied once to WORK/in/motors/ and WORK/motors/, so "motors/NAME.toml"
// (the form of the seed corpus, tests/fuzz/corpus) and "../motors/NAME.toml"
// (the form of sim/scenarios) both resolve. WORK is $MC_FUZZ_WORKDIR (made
// by scripts/fuzz.sh), or else a fresh directory under the system's
// temporary directory, removed at exit.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

#include "scenario/scenario.h"

namespace {

namespace fs = std::filesystem;

std::string g_input;  // WORK/in/fuzz.toml
fs::path g_owned;     // WORK when this process made it (removed at exit)

[[noreturn]] void die(const std::string& why)
{
    std::fprintf(stderr, "fuzz_scenario: %s\n", why.c_str());
    std::abort();
}

void copy_motor_files(const fs::path& from, const fs::path& to)
{
    std::error_code ec;
    for (const fs::directory_entry& e : fs::directory_iterator(from, ec)) {
        if (e.path().extension() == ".toml") {
            fs::copy_file(e.path(), to / e.path().filename(), fs::copy_options::overwrite_existing, ec);
            if (ec) {
                die("cannot copy " + e.path().string() + ": " + ec.message());
            }
        }
    }
    if (ec) {
        die("cannot list " + from.string() + ": " + ec.message());
    }
}

void remove_owned() { std::error_code ec; fs::remove_all(g_owned, ec); }

// The message motorsim prints: one line, not empty.
void check_message(const char* what)
{
    const std::string m(what);
    if (m.empty() || m.find_first_of("\n\r") != std::string::npos) {
        die("ScenarioError message is not one line: \"" + m + "\"");
    }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/)
{
    fs::path work;
    if (const char* w = std::getenv("MC_FUZZ_WORKDIR"); w != nullptr && *w != '\0') {
        work = w;
    } else {
        std::string tmpl = (fs::temp_directory_path() / "mc_fuzz_XXXXXX").string();
        if (::mkdtemp(tmpl.data()) == nullptr) {
            die("mkdtemp failed");
        }
        work = tmpl;
        g_owned = work;
        std::atexit(remove_owned);
    }
    const fs::path in = work / "in";
    std::error_code ec;
    fs::create_directories(in / "motors", ec);
    fs::create_directories(work / "motors", ec);
    if (ec) {
        die("cannot create " + in.string() + ": " + ec.message());
    }
    const fs::path src(MC_SOURCE_DIR);
    for (const char* d : {"sim/motors", "tests/sim/bad_scenarios/motors", "tests/sim/failing_runs/motors"}) {
        copy_motor_files(src / d, in / "motors");
        copy_motor_files(src / d, work / "motors");
    }
    g_input = (in / "fuzz.toml").string();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    std::FILE* f = std::fopen(g_input.c_str(), "wb");
    if (f == nullptr) {
        die("cannot write " + g_input);
    }
    const bool written = size == 0 || std::fwrite(data, 1, size, f) == size;
    if (std::fclose(f) != 0 || !written) {
        die("cannot write " + g_input);
    }
    try {
        const mcsim::Scenario sc = mcsim::load_scenario(g_input);
        (void)sc.n_ticks();
    } catch (const mcsim::ScenarioError& e) {
        check_message(e.what());
    }
    try {
        (void)mcsim::load_motor_file(g_input);
    } catch (const mcsim::ScenarioError& e) {
        check_message(e.what());
    }
    return 0;
}
