// board_drive - the drive of a scenario on a real DAC/ADC card through
// Comedi (docs/board.md): the card opened with the scenario's [board] map
// and signal chain, the outputs at 0 V, the current sensors' offsets
// calibrated (out of range: nothing is driven), then the drive's control
// step at the scenario's rate in the Linux real-time loop for --seconds,
// or until Ctrl-C; 0 V on every output at the end. Prints JSON: the
// loop's overruns, jitter and step time, the calibrated offsets, the
// drive's fault. Exit 0; 1 on a start-up failure, a drive fault or an I/O
// error; 2 on bad input.
//   usage: board_drive --scenario FILE [--device /dev/comedi0] [--seconds S] [--priority P]
#include <csignal>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "drives/registry.h"
#include "hal_board.h"
#include "motorsim/drive_glue.h"
#include "host_drives/host_drive.h"
#include "scenario/scenario.h"

namespace {
volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

}  // namespace

int main(int argc, char** argv)
{
    std::string scenario, device = "/dev/comedi0";
    double seconds = 10.0;
    long priority = 80;
    for (int a = 1; a < argc; ++a) {
        const std::string s = argv[a];
        char* end = nullptr;
        if (s == "--scenario" && a + 1 < argc) {
            scenario = argv[++a];
        } else if (s == "--device" && a + 1 < argc) {
            device = argv[++a];
        } else if (s == "--seconds" && a + 1 < argc) {
            seconds = std::strtod(argv[++a], &end);
            if (end == argv[a] || *end != '\0') seconds = -1.0;
        } else if (s == "--priority" && a + 1 < argc) {
            priority = std::strtol(argv[++a], &end, 10);
            if (end == argv[a] || *end != '\0') priority = -1;
        } else {
            std::fprintf(stderr, "usage: board_drive --scenario FILE [--device /dev/comedi0] [--seconds S] [--priority 1-99]\n");
            return 2;
        }
    }
    if (scenario.empty() || !(seconds > 0.0) || seconds > 86400.0 || priority < 1 || priority > 99) {
        std::fprintf(stderr, "board_drive: --scenario is required, --seconds in (0, 86400], --priority in 1-99\n");
        return 2;
    }
    mcsim::Scenario sc;
    auto storage = std::make_unique<drive_storage_t>();  // a few kB: heap, not stack
    auto cfg = std::make_unique<drive_config_storage_t>();
    drive_t drive{};
    try {
        sc = mcsim::load_scenario(scenario);
        drive = mcsim::design_scenario_drive(sc, storage.get(), cfg.get());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "board_drive: %s\n", e.what());
        return 2;
    }
    char err[256];
    const auto fs = static_cast<std::uint32_t>(std::lround(1.0 / sc.ts_s));
    if (!hal_board_open(&sc.board.chain, device.c_str(), sc.board.calibration_samples, fs, err, sizeof err)) {
        std::fprintf(stderr, "board_drive: %s: not starting, nothing driven\n", err);
        return 1;
    }
    const bool started = hal_start(&mcsim::drive_control_callback, &drive);
    if (!started) {
        std::fprintf(stderr, "board_drive: %s\n", hal_last_error());
        hal_board_close();
        return 1;
    }
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    const auto n_total = static_cast<std::uint64_t>(std::llround(seconds * fs));
    rt_loop_stats_t st{}, chunk{};
    std::uint64_t done = 0;
    while (done < n_total && !g_stop) {
        const std::uint64_t n = std::min<std::uint64_t>(fs, n_total - done);  // a second at a time: Ctrl-C is seen
        hal_board_run_realtime(n, static_cast<int>(priority), &chunk);
        st.periods += chunk.periods;
        st.overruns += chunk.overruns;
        st.jitter_max_us = std::fmax(st.jitter_max_us, chunk.jitter_max_us);
        st.jitter_p999_us = std::fmax(st.jitter_p999_us, chunk.jitter_p999_us);
        st.step_max_us = std::fmax(st.step_max_us, chunk.step_max_us);
        st.realtime = chunk.realtime;
        done += chunk.periods;
        if (chunk.periods < n) break;  // the safe state or an I/O error
    }
    const board_chain_t& ch = *hal_board_chain();
    drive_status_t status{};
    drive_status(&drive, &status);
    const int fault = static_cast<int>(status.fault_code);
    const std::string io_error = hal_last_error();
    hal_board_close();
    std::printf("{\"device\": \"%s\", \"periods\": %llu, \"overruns\": %llu, \"jitter_p999_us_max\": %.1f, "
                "\"jitter_max_us\": %.1f, \"step_time_max_us\": %.1f, \"sched_fifo\": %s, \"offsets_V\": [%.5f, %.5f, %.5f], "
                "\"fault\": %d, \"io_error\": \"%s\", \"stopped_by_signal\": %s}\n",
                device.c_str(), static_cast<unsigned long long>(st.periods),
                static_cast<unsigned long long>(st.overruns), st.jitter_p999_us, st.jitter_max_us, st.step_max_us,
                st.realtime ? "true" : "false", ch.offset_V[0], ch.offset_V[1], ch.offset_V[2], fault,
                io_error.c_str(), g_stop ? "true" : "false");
    if (fault != 0 || !io_error.empty()) {
        std::fprintf(stderr, "board_drive: FAILED: %s\n", fault != 0 ? "the drive latched a fault" : io_error.c_str());
        return 1;
    }
    return 0;
}
