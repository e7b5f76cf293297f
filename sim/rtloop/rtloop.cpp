// rtloop - the drive on the emulated DAC/ADC board in real time: each
// 100 us period of the Linux real-time loop (hal/backends/board/rt_loop.h)
// runs one period of the rig (the board's A/D, the scenario's drive, its
// D/A and amplifiers, the plant) and keeps to the wall clock; at the end
// JSON with the overruns, the wake-up jitter (mean, 99.9th percentile,
// max), the step time (mean, max) and whether real-time scheduling was
// granted. tools/bench/rtloop.py runs it.
//   usage: rtloop --scenario FILE [--seconds N] [--priority P]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "drives/registry.h"
#include "hal/hal.h"
#include "hal_sw_plant.h"
#include "model/board_emulation.h"
#include "motorsim/drive_glue.h"
#include "rt_loop.h"
#include "host_drives/host_drive.h"
#include "scenario/rig.h"
#include "scenario/scenario.h"

namespace {
bool one_period(void*) { return hal_sw_plant_run(1) == 1u && !hal_sw_plant_in_safe_state(); }
}  // namespace

int main(int argc, char** argv)
{
    double seconds = 10.0;
    int priority = 80;
    std::string scenario;  // required (tools/bench/rtloop.py gives the README's main scenario by default)
    for (int a = 1; a < argc; ++a) {
        const std::string s = argv[a];
        char* end = nullptr;
        if (s == "--seconds" && a + 1 < argc) {
            seconds = std::strtod(argv[++a], &end);
            if (end == argv[a] || *end != '\0') seconds = -1.0;
        } else if (s == "--scenario" && a + 1 < argc) {
            scenario = argv[++a];
        } else if (s == "--priority" && a + 1 < argc) {
            const long p = std::strtol(argv[++a], &end, 10);
            priority = (end == argv[a] || *end != '\0' || p < 1 || p > 99) ? -1 : static_cast<int>(p);
        } else {
            std::fprintf(stderr, "usage: rtloop --scenario FILE [--seconds N] [--priority 1-99]\n");
            return 2;
        }
    }
    if (scenario.empty() || !(seconds > 0.0) || seconds > 3600.0 || priority < 1 || priority > 99) {
        std::fprintf(stderr, "rtloop: --scenario is required, --seconds must be in (0, 3600], --priority in 1-99\n");
        return 2;
    }
    try {
        mcsim::Scenario sc = mcsim::load_scenario(scenario);
        static drive_storage_t storage;  // outlives the loop; a few kB: not on the stack
        static drive_config_storage_t drive_cfg;
        static drive_t active;
        active = mcsim::design_scenario_drive(sc, &storage, &drive_cfg);
        mcsim::Rig rig(sc);
        hal_sw_plant_attach(&rig.plant, &rig.sensor, rig.amp, sc.ts_s);
        mcsim::BoardEmulation board(sc.board, sc.seed);
        std::string why;
        if (!board.calibrate(&why)) throw std::runtime_error("board calibration: " + why);
        hal_sw_plant_set_board(&board);
        if (!hal_start(&mcsim::drive_control_callback, &active)) throw std::runtime_error(hal_last_error());
        rt_loop_config_t cfg{static_cast<std::uint32_t>(std::lround(sc.ts_s * 1e9)), priority};
        static rt_loop_stats_t st;
        const auto n = static_cast<std::uint64_t>(std::llround(seconds / sc.ts_s));
        rt_loop_run(&cfg, &one_period, nullptr, n, &st);
        if (!st.realtime || !st.locked) {
            std::fprintf(stderr, "rtloop: warning: %s: ran with the default scheduler, the jitter is not a real-time "
                                 "figure\n", st.why);
        }
        std::printf("{\"seconds\": %.3f, \"period_us\": %.1f, \"periods\": %llu, \"overruns\": %llu, "
                    "\"jitter_mean_us\": %.2f, \"jitter_p999_us\": %.1f, \"jitter_max_us\": %.1f, "
                    "\"step_time_mean_us\": %.2f, \"step_time_max_us\": %.1f, \"sched_fifo\": %s, \"mlockall\": %s, "
                    "\"scenario\": \"%s\", \"backend\": \"board-emulated\", \"drive_safe_state\": %s}\n",
                    seconds, cfg.period_ns / 1000.0, static_cast<unsigned long long>(st.periods),
                    static_cast<unsigned long long>(st.overruns), st.jitter_mean_us, st.jitter_p999_us, st.jitter_max_us,
                    st.step_mean_us, st.step_max_us, st.realtime ? "true" : "false", st.locked ? "true" : "false",
                    scenario.c_str(), hal_sw_plant_in_safe_state() ? "true" : "false");
        hal_sw_plant_detach();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rtloop: %s\n", e.what());
        return 1;
    }
    return 0;
}
