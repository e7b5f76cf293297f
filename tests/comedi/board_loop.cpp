// board_loop.cpp - a closed-loop paper-000 run through a real kernel's
// Comedi card (comedi_test in the VM fixture; ctest hal.comedi_closed_loop,
// label comedi). Two processes in lock-step (virtual time: the VM is not
// real time), a token on a pipe each way per control period:
//   the drive process: the board backend of the HAL (hal_board.h) with the
//     paper-000 drive as its control callback: it opens the card,
//     calibrates the Hall sensors' offsets with the outputs at zero, and
//     each period reads the phase currents on A/D channels 2, 3 through the
//     board chain, runs the drive, writes the phase voltages through the
//     chain on D/A channels 0, 1 (hal_board_period: stepped here, paced by
//     the real-time loop on a real rig, sim/board_drive);
//   the plant process: reads D/A 0, 1 back on A/D 0, 1 (comedi_test loops
//     each analog output back to the input of the same channel), drives
//     the plant through the amplifiers' gain and the supply's clamp for one
//     period, writes the Hall sensors' volts (gain, offset) of the new
//     currents on D/A 2, 3, and sends the true angle with its token.
// Prints JSON (samples, calibrated offsets, tracking) and exits 0 if the
// move finishes and tracks: no fault, the tracking error while the loop is
// closed and the final error within the scenario's thresholds.
//   usage: board_loop SCENARIO.toml [/dev/comedi0]
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include "board_chain.h"
#include "board_comedi.h"
#include "hal_board.h"
#include "motorsim/drive_glue.h"
#include "drives/paper000/paper000_drive.h"
#include "mc_convert.h"
#include "host_drives/paper000_host.h"
#include "scenario/rig.h"
#include "scenario/scenario.h"

namespace {

// comedi_test: the drive's voltages out on 0, 1 (back in on 0, 1), the
// currents out (by the plant) on 2, 3 (back in on 2, 3)
constexpr int kVoltageCh[2] = {0, 1};
constexpr int kCurrentCh[2] = {2, 3};
// the Hall sensors' offsets the plant side puts on its outputs (2 % and
// 1.5 % of the +-10 V range): the drive's calibration must find them
constexpr double kTrueOffsetV[2] = {0.2, -0.15};

bool write_all(int fd, const void* p, std::size_t n) { return ::write(fd, p, n) == static_cast<ssize_t>(n); }
bool read_all(int fd, void* p, std::size_t n) { return ::read(fd, p, n) == static_cast<ssize_t>(n); }

[[noreturn]] void die(const std::string& why)
{
    std::fprintf(stderr, "board_loop: %s\n", why.c_str());
    std::exit(1);
}

// the plant process: until the drive closes its pipe
int plant_process(mcsim::Scenario sc, const board_chain_config_t& chain, const char* dev, int from_drive,
                  int to_drive)
{
    char err[256];
    const int ai[2] = {kVoltageCh[0], kVoltageCh[1]};
    const int ao[2] = {kCurrentCh[0], kCurrentCh[1]};
    board_comedi_t* card = board_comedi_open(dev, chain.adc_range_V, ai, 2, ao, 2, err, sizeof err);
    if (card == nullptr) die(std::string("plant: ") + err);
    mcsim::Rig rig(sc);
    for (;;) {
        double i[3] = {0.0, 0.0, 0.0};
        rig.plant.phase_currents(i);
        for (int k = 0; k < 2; ++k) {
            if (!board_comedi_write(card, kCurrentCh[k], i[k] * chain.sensor_V_per_A + kTrueOffsetV[k], nullptr)) {
                die(std::string("plant: ") + board_comedi_error(card));
            }
        }
        const double theta = rig.plant.theta_rad();
        if (!write_all(to_drive, &theta, sizeof theta)) break;
        char go = 0;
        if (!read_all(from_drive, &go, 1)) break;
        double v[3] = {0.0, 0.0, 0.0};
        for (int k = 0; k < 2; ++k) {
            double u = 0.0;
            if (!board_comedi_read(card, kVoltageCh[k], &u, nullptr)) die(std::string("plant: ") + board_comedi_error(card));
            v[k] = std::fmax(-sc.v_max_V, std::fmin(sc.v_max_V, u * chain.amplifier_V_per_V));
        }
        rig.plant.step_phases(v, sc.ts_s);
    }
    board_comedi_close(card);
    return 0;
}

}  // namespace

int main(int argc, char** argv)
{
    if (argc < 2 || argc > 3) {
        std::fprintf(stderr, "usage: board_loop SCENARIO.toml [/dev/comedi0]\n");
        return 2;
    }
    const char* dev = argc > 2 ? argv[2] : "/dev/comedi0";
    mcsim::Scenario sc;
    auto drive = std::make_unique<paper000_drive_t>();
    try {
        sc = mcsim::load_scenario(argv[1]);
        if (sc.drive_kind != "paper000" || sc.motor.n_phases() != 2) throw std::runtime_error("a paper-000 (stepper) scenario");
        mcsim::design_and_init_drive(sc, drive.get());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "board_loop: %s\n", e.what());
        return 2;
    }
    board_chain_config_t cfg = sc.board.chain;
    cfg.current_ai[0] = kCurrentCh[0];
    cfg.current_ai[1] = kCurrentCh[1];
    cfg.voltage_ao[0] = kVoltageCh[0];
    cfg.voltage_ao[1] = kVoltageCh[1];
    cfg.vbus_ai = -1;
    char err[256];
    if (!board_chain_check(&cfg, err, sizeof err)) die(err);
    int p2d[2], d2p[2];
    if (::pipe(p2d) != 0 || ::pipe(d2p) != 0) die("pipe");
    const pid_t pid = ::fork();
    if (pid < 0) die("fork");
    if (pid == 0) {
        ::close(p2d[0]);
        ::close(d2p[1]);
        std::_Exit(plant_process(sc, cfg, dev, d2p[0], p2d[1]));
    }
    ::close(p2d[1]);
    ::close(d2p[0]);
    const int from_plant = p2d[0], to_plant = d2p[1];
    // the plant has written its sensors' volts at rest: open and calibrate
    double theta = 0.0;
    const char go = 1;
    if (!read_all(from_plant, &theta, sizeof theta)) die("the plant process stopped");
    const auto fs = static_cast<std::uint32_t>(std::lround(1.0 / sc.ts_s));
    if (!hal_board_open(&cfg, dev, sc.board.calibration_samples, fs, err, sizeof err)) die(err);
    drive_t active{&paper000_drive_ops, drive.get()};
    if (!hal_start(&mcsim::drive_control_callback, &active)) die(hal_last_error());
    const board_chain_t& chain = *hal_board_chain();
    const int n_cal = sc.board.calibration_samples;

    // the run: one period of the board backend per token
    const std::uint32_t n = sc.n_ticks();
    double track_max = 0.0;
    std::uint32_t closed = 0;
    bool faulted = false;
    for (std::uint32_t t = 0; t < n; ++t) {
        if (t > 0 && !read_all(from_plant, &theta, sizeof theta)) die("the plant process stopped");
        if (!hal_board_period()) faulted = true;
        paper000_telemetry_t tl;
        paper000_drive_get_telemetry(drive.get(), &tl);
        faulted = faulted || tl.fault != DRIVE_FAULT_NONE;
        if (tl.mode == DRIVE_MODE_CLOSED_LOOP) {
            ++closed;
            track_max = std::fmax(track_max, std::fabs(theta - mcsim::to_double(tl.theta_ref_rad)));
        }
        if (!write_all(to_plant, &go, 1)) die("the plant process stopped");
    }
    if (!read_all(from_plant, &theta, sizeof theta)) die("the plant process stopped");
    ::close(to_plant);
    ::close(from_plant);
    int status = 0;
    ::waitpid(pid, &status, 0);
    const double offset_a = chain.offset_V[0], offset_b = chain.offset_V[1];
    hal_board_close();
    const double theta_end = sc.segments.empty() ? 0.0 : sc.segments.back().theta_to_rad;
    const double final_err = std::fabs(theta - theta_end);
    const bool ok = !faulted && closed > 0 && track_max < 0.02 && final_err < 0.02;
    std::printf("{\"samples\": %u, \"calibration_samples\": %d, \"offset_a_V\": %.6f, \"offset_b_V\": %.6f, "
                "\"offset_true_V\": [%.3f, %.3f], \"closed_loop_samples\": %u, \"theta_track_max_rad\": %.6f, "
                "\"final_theta_rad\": %.6f, \"final_theta_err_rad\": %.6f, \"fault\": %s, \"pass\": %s}\n",
                n, n_cal, offset_a, offset_b, kTrueOffsetV[0], kTrueOffsetV[1], closed, track_max,
                theta, final_err, faulted ? "true" : "false", ok ? "true" : "false");
    return ok ? 0 : 1;
}
