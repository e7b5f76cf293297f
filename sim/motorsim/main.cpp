// motorsim - closed-loop simulation of a drive of the registry on the
// software plant: scenario in, CSV log + metrics (+ PNG plot) out. The
// drive is the scenario's [drive] kind, or the drive whose table the
// scenario has ([trajectory]: paper 000, [speed]: paper 001, [paper002]);
// it is designed by its host part (sim/host_drives/), run through the drive
// interface (firmware/drives/drive.h) and recorded by the one recorder with
// its scoring and the drive's signals (run_recorder.h). Nothing here names a
// drive.
//
//   motorsim --scenario FILE [--out DIR] [--metrics-out FILE.json]
//            [--seed N] [--no-plot] [--no-csv] [--quiet]
//            [--can IFACE [--can-node N]] [--realtime]
//
// With --can the drive is a node on a SocketCAN interface (docs/can.md):
// it sends the telemetry of tools/can/drive.dbc and obeys its commands
// (motorsim/can_glue.h). --realtime paces the loop to the wall clock
// (else it runs as fast as it can).
//
// Outputs (kOutputModes below, also in --help):
//   --out DIR given        CSV + metrics JSON + PNG into DIR
//   only --metrics-out     the metrics JSON alone: no per-sample log is even
//                          recorded (the fast mode for many variants)
//   neither                as --out out
//
// Each 100 us period the sw_plant HAL backend samples the currents through
// the sensor model, calls the drive (drive_glue.cpp), clamps the voltages in
// the amplifier model and integrates the plant with them held. Everything is
// validated before the run and nothing is written before the run is over.
// Exit status (kExitStatus below, also in --help and the README): 0 ok,
// 1 run or I/O failure, 2 bad command line or scenario, 3 the drive latched
// a fault, 4 a metric missed its [expect] bound, 5 the plant diverged.
// A run that fails still writes its outputs: it is the one a user most
// wants to look at.
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>

#include <unistd.h>

#include <CLI/CLI.hpp>

#include "drives/registry.h"
#include "host_drives/host_drive.h"
#include "motorsim/commission.h"
#include "motorsim/run_recorder.h"
#include "motorsim/run_watch.h"
#include "hal/hal.h"
#include "hal_sw_plant.h"
#include "scenario/rig.h"
#include "scenario/rig_hal.h"
#include "model/amplifier.h"
#include "model/current_sensor.h"
#include "model/pm_plant.h"
#include "motorsim/drive_glue.h"
#include "motorsim/can_glue.h"
#include "motorsim/param_glue.h"
#include "can/socketcan.h"
#include "motorsim/outputs.h"
#include "motorsim_config.h"
#include "mc_version.h"
#include "scenario/scenario.h"

namespace fs = std::filesystem;

namespace {

// 4e6 samples = 400 s at 10 kHz, ~1.1 GB of log (metrics-only runs keep no log).
constexpr std::uint32_t kMaxLoggedSamples = 4000000;

constexpr const char* kOutputModes =
    "Outputs:\n"
    "  --out DIR given       DIR/<stem>.csv, DIR/<stem>_metrics.json (or --metrics-out) and\n"
    "                        DIR/<stem>.png; --no-plot: no PNG, --no-csv: no CSV and no PNG\n"
    "  only --metrics-out    the metrics JSON alone: no CSV, no PNG, no per-sample log at all\n"
    "                        (fastest; the metrics are the same as in a full run)\n"
    "  neither               as --out out\n"
    "The metrics are also printed on stdout unless --quiet. Nothing is written\n"
    "before the run is over, and each file appears whole or not at all; a run that\n"
    "fails (status 3-5) still writes its outputs and says why on stderr.\n";

// One place for the exit statuses (--help, the README, tests).
enum ExitStatus : int {
    kExitOk = 0,
    kExitRunError = 1,
    kExitBadInput = 2,
    kExitFault = 3,
    kExitExpect = 4,
    kExitDiverged = 5,
};
constexpr const char* kExitStatusHelp =
    "Exit status:\n"
    "  0  ok\n"
    "  1  run or I/O failure (nothing or not everything written)\n"
    "  2  bad command line or scenario (nothing written)\n"
    "  3  the drive latched a fault (code, name and time on stderr)\n"
    "  4  a metric missed its bound in the scenario's [expect] table\n"
    "  5  the plant diverged: a non-finite state, or a current or speed beyond\n"
    "     what the supply allows (the integration step is too large for the motor)\n"
    "When several apply, the first of 5, 3, 4 is returned; all are printed.";

struct Options {
    // (ordered by size: clang-analyzer's padding check)
    std::int64_t seed = 0;
    double theta0_rad = 0.0;
    double delay_samples = 0.0;
    std::string scenario;
    std::string out_dir = "out";
    std::string metrics_out;
    std::string estimator;  // empty: the scenario's
    std::string can_iface;  // empty: no CAN
    std::string flash_image;  // empty: none
    unsigned can_node = 0;
    bool out_given = false;
    bool metrics_out_given = false;
    bool seed_given = false;
    bool theta0_given = false;
    bool delay_given = false;
    bool no_expect = false;
    bool no_plot = false;
    bool no_csv = false;
    bool quiet = false;
    bool can_given = false;
    bool flash_given = false;
    bool realtime = false;
    std::string backend = "plant";
};

// Refuses output paths that cannot work before anything runs; creates nothing.
void check_output_dir(const std::string& dir, const char* what)
{
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
        throw std::invalid_argument(std::string(what) + ": '" + dir + "' exists and is not a directory");
    }
}

// Percentage on stderr for long runs: in place on a terminal, else every 25%.
class Progress {
public:
    Progress(bool enabled, std::uint32_t total) : enabled_(enabled), tty_(::isatty(2) != 0), total_(total) {}

    void update(std::uint32_t done, double wall_s)
    {
        if (!enabled_ || total_ == 0) {
            return;
        }
        const double frac = static_cast<double>(done) / static_cast<double>(total_);
        if (!active_) {
            // Only runs expected to take more than ~2 s of wall time report.
            if (frac <= 0.0 || wall_s / frac < 2.0) {
                return;
            }
            active_ = true;
        }
        const int pct = static_cast<int>(100.0 * frac);
        if (tty_) {
            if (pct != last_pct_) {
                std::fprintf(stderr, "\rmotorsim: %3d%%", pct);
                std::fflush(stderr);
            }
        } else if (pct / 25 != last_pct_ / 25) {
            std::fprintf(stderr, "motorsim: %d%%\n", pct / 25 * 25);
        }
        last_pct_ = pct;
    }

    void finish()
    {
        if (active_ && tty_) {
            std::fputc('\n', stderr);
        }
    }

private:
    bool enabled_;
    bool tty_;
    std::uint32_t total_;
    bool active_ = false;
    int last_pct_ = 0;
};

// Runs the HAL backend for n_total periods with a progress line; returns
// the wall time of the loop.
// With realtime, the loop runs in 1 ms chunks and sleeps until the wall
// clock has caught up with the simulated time (ts_s per period).
double run_loop(std::uint32_t n_total, bool quiet, const mcsim::RunWatch& watch, bool realtime, double ts_s)
{
    const std::uint32_t rt_chunk = std::max<std::uint32_t>(1, static_cast<std::uint32_t>(std::lround(1e-3 / ts_s)));
    const std::uint32_t chunk = realtime ? rt_chunk : std::max<std::uint32_t>(1, n_total / 100);
    Progress progress(!quiet && !realtime, n_total);
    const auto t0 = std::chrono::steady_clock::now();
    double wall_s = 0.0;
    for (std::uint32_t done = 0; done < n_total;) {
        const std::uint32_t n = std::min(chunk, n_total - done);
        hal_sw_plant_run(n);
        done += n;
        if (watch.diverged()) {
            break;  // the rest would be NaN; the outputs end where physics did
        }
        if (realtime) {
            std::this_thread::sleep_until(t0 + std::chrono::duration<double>(static_cast<double>(done) * ts_s));
        }
        wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        progress.update(done, wall_s);
    }
    progress.finish();
    return wall_s;
}

// Warns (stderr, the run goes on) where the reference asks more than the
// supply and the current limit can give: a motor turning at w needs K_e w
// of back-EMF plus R i within the voltage the drive has, and an
// acceleration a needs J a / K_t of current (plus the load) within i_max.
// The reference's peak speed and acceleration are the drive's host part's
// (its peak_demand), else those of the speed profile's corners.
void warn_feasibility(const mcsim::Scenario& sc, const mcsim::HostDrive& host)
{
    const mcsim::MotorParams& m = sc.motor;
    const double Ke = m.K_Nm_per_A;
    const double Kt = m.torque_scale() * Ke;
    double w_pk = 0.0, a_pk = 0.0;
    if (host.peak_demand != nullptr) {
        host.peak_demand(sc, &w_pk, &a_pk);
    } else {  // the speed profile's corners ([speed] or the drive's table)
        for (std::size_t k = 0; k < sc.speed_points.size(); ++k) {
            w_pk = std::max(w_pk, std::fabs(sc.speed_points[k].second));
            if (k + 1 < sc.speed_points.size()) {
                const double dt = sc.speed_points[k + 1].first - sc.speed_points[k].first;
                a_pk = std::max(a_pk, std::fabs(sc.speed_points[k + 1].second - sc.speed_points[k].second) / dt);
            }
        }
    }
    double load_pk = m.coulomb_Nm + m.fv_Nms_per_rad * w_pk;
    double lmax = 0.0;
    for (const auto& l : sc.load) {
        lmax = std::max(lmax, std::fabs(l.torque_Nm));
    }
    load_pk += lmax;
    const double v_need = Ke * w_pk;
    const double i_need = (m.J_kgm2 * a_pk + load_pk) / Kt;
    if (v_need > sc.v_max_V) {
        std::fprintf(stderr,
                     "warning: %s: the reference's peak speed %.4g rad/s needs %.4g V of back-EMF alone, more than the "
                     "%.4g V the drive has: the drive cannot follow it\n",
                     sc.path.c_str(), w_pk, v_need, sc.v_max_V);
    }
    if (i_need > sc.i_max_A) {
        std::fprintf(stderr,
                     "warning: %s: the reference's peak acceleration %.4g rad/s^2 (J a = %.4g N m) plus %.4g N m of "
                     "friction at its peak speed and load needs %.4g A, more than [limits] i_max_A = %.4g A: the "
                     "drive cannot follow it\n",
                     sc.path.c_str(), a_pk, m.J_kgm2 * a_pk, load_pk, i_need, sc.i_max_A);
    }
}

std::string num6(double v)
{
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", v);
    return b;
}

// The exit status of a finished run and its reasons on stderr.
int verdict(const mcsim::Scenario& sc, const mcsim::MetricList& metrics, const mcsim::RunWatch& w)
{
    int status = kExitOk;
    auto set = [&status](int s) {
        // precedence 5, 3, 4
        auto rank = [](int x) { return x == kExitDiverged ? 3 : x == kExitFault ? 2 : x == kExitExpect ? 1 : 0; };
        if (rank(s) > rank(status)) {
            status = s;
        }
    };
    if (w.diverged()) {
        std::fprintf(stderr,
                     "motorsim: FAILED: the plant left its physical envelope at t = %.4f s: %s (an integration "
                     "step too large for the motor, see [run] substeps, or an external torque beyond the motor's); "
                     "the run stopped there\n",
                     w.diverged_t_s(), w.diverged_what().c_str());
        set(kExitDiverged);
    }
    if (w.faulted()) {
        const auto f = static_cast<drive_fault_t>(w.fault());
        std::fprintf(stderr, "motorsim: FAILED: drive fault %lld (%s) at t = %.4f s", static_cast<long long>(w.fault()),
                     drive_fault_name(f), w.fault_t_s());
        if (f == DRIVE_FAULT_OVERCURRENT) {
            std::fprintf(stderr, ": measured phase current %.4g A beyond [limits] i_trip_A = %.4g A",
                         w.fault_i_meas_A(), sc.i_trip_A);
            if (sc.i_trip_samples > 1) {
                std::fprintf(stderr, " (the last of %d consecutive samples, [limits] i_trip_samples)",
                             sc.i_trip_samples);
            }
        }
        std::fprintf(stderr, "; the drive held 0 V from then on\n");
        double first_t = -1.0, events = 0.0, relocks = 0.0, first = 0.0;
        for (const auto& kv : metrics) {
            const double x = std::holds_alternative<double>(kv.second) ? std::get<double>(kv.second)
                                                                       : static_cast<double>(std::get<std::int64_t>(kv.second));
            if (kv.first == "fault_first_t_s") first_t = x;
            if (kv.first == "fault_events") events = x;
            if (kv.first == "relocks") relocks = x;
            if (kv.first == "fault_first") first = x;
        }
        if (events > 1.0 || relocks > 0.0) {
            std::fprintf(stderr,
                         "motorsim: the first fault was %s at t = %.4f s; %.0f fault events, %.0f re-locks before the "
                         "safe state\n",
                         drive_fault_name(static_cast<drive_fault_t>(static_cast<int>(first))), first_t, events, relocks);
        }
        set(kExitFault);
    }
    for (const mcsim::Expectation& e : sc.expect) {
        double x = NAN;
        for (const auto& kv : metrics) {
            if (kv.first == e.metric) {
                x = std::holds_alternative<double>(kv.second) ? std::get<double>(kv.second)
                                                              : static_cast<double>(std::get<std::int64_t>(kv.second));
            }
        }
        const bool bad = !std::isfinite(x) || (e.has_max && x > e.max) || (e.has_min && x < e.min);
        if (bad) {
            std::string bound;
            if (!std::isfinite(x)) {
                bound = "not a number (the run never measured it)";
            } else if (e.has_max && x > e.max) {
                bound = "> max " + num6(e.max);
            } else {
                bound = "< min " + num6(e.min);
            }
            std::fprintf(stderr, "motorsim: FAILED: %s: expect.%s: %s %s\n", sc.path.c_str(), e.metric.c_str(),
                         std::isfinite(x) ? num6(x).c_str() : "null", bound.c_str());
            set(kExitExpect);
        }
    }
    return status;
}

int run(const Options& opt)
{
    // ---- everything that can be wrong with the input, before any output --
    mcsim::Scenario sc = mcsim::load_scenario(opt.scenario);
    if (opt.seed_given) {
        sc.seed = static_cast<std::uint64_t>(opt.seed);
    }
    if (opt.delay_given) {
        if (!(opt.delay_samples >= 0.0 && opt.delay_samples <= 1.0)) {
            throw std::invalid_argument("--compute-delay-samples: must be in [0, 1] (got " + num6(opt.delay_samples) + ")");
        }
        sc.compute_delay_samples = opt.delay_samples;
    }
    if (opt.theta0_given) {
        if (!std::isfinite(opt.theta0_rad)) {
            throw std::invalid_argument("--theta0-rad: must be finite");
        }
        sc.theta0_rad = opt.theta0_rad;
    }
    // The drive of the scenario, in both registries (the firmware's and
    // the host parts': sim/host_drives/)
    const mcsim::HostDrive* host = mcsim::host_drive_find(sc.drive_kind);
    const drive_ops_t* ops = drive_find(sc.drive_kind.c_str());
    if (host == nullptr || ops == nullptr) {
        throw mcsim::ScenarioError(sc.path + ": drive.kind: \"" + sc.drive_kind + "\" is not in this build");
    }
    if (!opt.estimator.empty()) {
        if (host->select_estimator == nullptr) {
            throw std::invalid_argument("--estimator: the " + sc.drive_kind + " drive has one estimator");
        }
        host->select_estimator(&sc, opt.estimator);
    }
    if (opt.out_given && opt.out_dir.empty()) {
        throw std::invalid_argument("--out: empty path");
    }
    if (opt.metrics_out_given && opt.metrics_out.empty()) {
        throw std::invalid_argument("--metrics-out: empty path");
    }
    // Metrics only: --metrics-out without --out. Else DIR gets the CSV (no
    // --no-csv), the PNG (drawn from the CSV; no --no-plot) and, without
    // --metrics-out, the metrics JSON.
    const bool metrics_only = !opt.out_given && !opt.metrics_out.empty();
    const bool write_csv = !metrics_only && !opt.no_csv;
    const bool write_png = write_csv && !opt.no_plot;
    if (write_csv || opt.metrics_out.empty()) {
        check_output_dir(opt.out_dir, "--out");
    }
    const std::string csv_path = (fs::path(opt.out_dir) / (sc.stem + ".csv")).string();
    const std::string png_path = (fs::path(opt.out_dir) / (sc.stem + ".png")).string();
    const std::string json_path =
        opt.metrics_out.empty() ? (fs::path(opt.out_dir) / (sc.stem + "_metrics.json")).string() : opt.metrics_out;
    {
        std::error_code ec;
        if (!opt.metrics_out.empty() && fs::is_directory(json_path, ec)) {
            throw std::invalid_argument("--metrics-out: '" + json_path + "' is a directory");
        }
    }
    if (json_path != "-" && fs::path(json_path).has_parent_path()) {
        check_output_dir(fs::path(json_path).parent_path().string(), "--metrics-out");
    }

    // The CAN interface, opened (and so checked) before the run.
    if (opt.realtime && opt.can_iface.empty() && !opt.quiet) {
        std::fprintf(stderr, "motorsim: --realtime without --can: the run is paced to the wall clock\n");
    }
    std::unique_ptr<mcsim::SocketCan> can;
    if (opt.can_given && opt.can_iface.empty()) {
        throw std::invalid_argument("--can: empty interface name");
    }
    if (!opt.can_iface.empty()) {
        can = std::make_unique<mcsim::SocketCan>(opt.can_iface, opt.can_node);
    }

    // The whole log stays in memory until the run is over (no file I/O in
    // the loop): ~300 bytes per sample. Refuse runs that would not fit.
    if (write_csv && sc.n_ticks() > kMaxLoggedSamples) {
        throw std::invalid_argument(sc.path + ": run.duration_s: " + std::to_string(sc.n_ticks()) +
                                    " samples exceed the in-memory log limit of " +
                                    std::to_string(kMaxLoggedSamples) + " (" +
                                    std::to_string(static_cast<int>(kMaxLoggedSamples * sc.ts_s)) +
                                    " s at this Ts_s) of a run with a CSV; run it without one (--no-csv, or "
                                    "--metrics-out without --out), which keeps no log");
    }

    if (opt.no_expect) {
        sc.expect.clear();
    }

    // A commissioning run before the design (its host part's, when the
    // scenario asks for it: paper 001's [speed] identify measures R, L and
    // Phi on the same plant; motorsim/commission.h), then the design by the
    // drive's host part, which also says what the run starts with: the
    // samples before t = 0 (paper 000's rotor alignment, sc.pre_ticks),
    // which the rig's start time and the run's length take from it.
    mcsim::MetricList commission_metrics;
    mcsim::commission_drive(*host, &sc, &commission_metrics);
    // With --flash-image or on CAN the drive's user parameters (as a board
    // has them: motorsim/param_glue.h): the design from the scenario's
    // design input with the image's saved record over it.
    if (opt.flash_given && opt.flash_image.empty()) {
        throw std::invalid_argument("--flash-image: empty path");
    }
    if (opt.flash_given && host->params == nullptr) {
        throw std::invalid_argument("--flash-image: the " + sc.drive_kind +
                                    " drive has no user parameters in this build (the float build serves them)");
    }
    std::unique_ptr<mcsim::ParamGlue> params;
    if (host->params != nullptr && (opt.flash_given || can)) {
        params = std::make_unique<mcsim::ParamGlue>(sc, *host, opt.flash_image);
    }
    // a few kB: heap, not stack
    auto storage = std::make_unique<drive_storage_t>();
    auto cfg = std::make_unique<drive_config_storage_t>();
    drive_t drive = params ? params->start(storage.get(), cfg.get())
                           : mcsim::design_scenario_drive(sc, storage.get(), cfg.get());
    if (params && !opt.quiet) {
        std::fprintf(stderr, "motorsim: parameters: %s\n", params->summary().c_str());
    }
    if (sc.pre_ticks > 0 && write_csv && sc.n_ticks() > kMaxLoggedSamples) {
        throw std::invalid_argument(sc.path + ": run.duration_s: with the rotor alignment, " +
                                    std::to_string(sc.n_ticks()) + " samples exceed the in-memory log limit of " +
                                    std::to_string(kMaxLoggedSamples) +
                                    "; run it without a CSV (--no-csv, or --metrics-out without --out)");
    }
    mcsim::Rig rig(sc);
    mcsim::PmPlant& plant = rig.plant;
    // plant, sensor, amplifier or [inverter], delay (scenario/rig_hal.h)
    mcsim::attach_rig(rig, sc);
    // --backend board-emulated: the DAC/ADC board between drive and plant,
    // its sensors calibrated with the outputs at zero before the drive
    // starts (a sensor out of range: nothing runs, nothing is written)
    std::unique_ptr<mcsim::BoardEmulation> board;
    if (opt.backend == "board-emulated") {
        if (sc.inverter_given) {
            hal_sw_plant_detach();
            throw mcsim::ScenarioError(sc.path + ": inverter: --backend board-emulated drives the plant through the "
                                                 "DAC board's amplifiers, not an MCU board's inverter: remove "
                                                 "[inverter] or run the sw-plant backend");
        }
        board = std::make_unique<mcsim::BoardEmulation>(sc.board, sc.seed);
        std::string why;
        if (!board->calibrate(&why)) {
            hal_sw_plant_detach();
            throw std::runtime_error(sc.path + ": board calibration refused to start: " + why);
        }
        hal_sw_plant_set_board(board.get());
    }
    // [encoder]: the samples carry its reading (the drives of papers 000
    // and 001 are sensorless and do not read it)
    std::unique_ptr<mcsim::Encoder> encoder;
    if (sc.encoder.present()) {
        encoder = std::make_unique<mcsim::Encoder>(sc.encoder, sc.seed);
        hal_sw_plant_set_encoder(encoder.get());
    }
    mcsim::FaultInjector injector(sc.faults, sc.seed);
    if (sc.faults.any()) {
        hal_sw_plant_set_faults(&injector);
    }

    // The log: the one recorder with the drive's scoring and its signals
    // (motorsim/run_recorder.h)
    const std::unique_ptr<mcsim::RunRecorder> rec = mcsim::make_recorder(sc, plant, drive, /*record_rows=*/write_csv);
    hal_sw_plant_set_monitor(&mcsim::RunRecorder::monitor, rec.get());
    // The reference against the supply and the current limit: a warning
    // with the numbers, once the drive has accepted the scenario (a refused
    // scenario gets its one error line and nothing else).
    warn_feasibility(sc, *host);
    // On CAN the callback is the drive's node (motorsim/can_glue.h); else
    // the drive alone (drive_glue.h).
    std::unique_ptr<mcsim::CanDriveContext> can_ctx;
    bool started = false;
    if (can) {
        can_ctx = std::make_unique<mcsim::CanDriveContext>();
        can_ctx->drive = drive;
        can_ctx->ts_s = sc.ts_s;
        can_ctx->t_start_s = sc.t_start_s();
        can_ctx->log = opt.quiet ? nullptr : stderr;
        mcsim::can_glue_init(can_ctx.get(), opt.can_node, hal_control_rate_hz());
        if (params) {
            can_ctx->params = params.get();
            can_node_set_params(&can_ctx->node, &mcsim::ParamGlue::answer, params.get());
        }
        rec->score_against_drive_reference(true);  // the ekf_speed scoring always does
        hal_sw_plant_set_can(can->bus());
        started = hal_start(&mcsim::can_drive_control_callback, can_ctx.get());
    } else {
        started = hal_start(&mcsim::drive_control_callback, &drive);
    }
    if (!started) {
        throw std::runtime_error(std::string("hal_start: ") + hal_last_error());
    }

    // ---- the loop: plant + drive + metrics only --------------------------
    // [expect] names must be metrics of this drive: checked before the run
    {
        const mcsim::MetricList names = rec->metrics(0.0);
        for (const mcsim::Expectation& e : sc.expect) {
            bool known = false;
            std::string all;
            for (const auto& kv : names) {
                known = known || kv.first == e.metric;
                all += (all.empty() ? "" : ", ") + kv.first;
            }
            if (!known) {
                throw mcsim::ScenarioError(sc.path + ": expect." + e.metric + ": not a metric of the " +
                                           sc.drive_kind + " drive (its metrics: " + all + ")");
            }
        }
    }
    const mcsim::RunWatch& watch = rec->watch();
    if (can && !opt.quiet) {
        std::fprintf(stderr, "motorsim: on CAN %s as node %u (%s), %s\n", can->iface().c_str(), opt.can_node,
                     ops->title, opt.realtime ? "in real time" : "as fast as it runs");
    }
    const double wall_s = run_loop(sc.n_ticks(), opt.quiet, watch, opt.realtime, sc.ts_s);

    hal_safe_state();
    hal_sw_plant_detach();
    mcsim::MetricList metrics = rec->metrics(wall_s);
    if (board) {
        // the calibration against the emulated sensors' true offsets, and
        // the A/D converter's step
        const board_chain_t& ch = board->chain();
        double err_max = 0.0;
        for (int k = 0; k < ch.cfg.n_phases; ++k) {
            err_max = std::max(err_max, std::fabs(ch.offset_V[k] - sc.board.sensor_offset_V[k]));
        }
        metrics.emplace_back("board_offset_error_max_V", err_max);
        metrics.emplace_back("board_adc_step_V", 2.0 * ch.cfg.adc_range_V / (std::ldexp(1.0, ch.cfg.adc_bits) - 1.0));
    }
    if (can_ctx) {
        const can_node_t& nd = can_ctx->node;
        metrics.emplace_back("can_frames_sent", static_cast<std::int64_t>(can->sent()));
        metrics.emplace_back("can_frames_dropped", static_cast<std::int64_t>(nd.tx.dropped));
        metrics.emplace_back("can_commands_accepted", static_cast<std::int64_t>(nd.accepted));
        metrics.emplace_back("can_commands_refused", static_cast<std::int64_t>(nd.rejected));
    }
    metrics.insert(metrics.end(), commission_metrics.begin(), commission_metrics.end());

    // ---- outputs ----------------------------------------------------------
    if (write_csv) {
        fs::create_directories(opt.out_dir);
    }
    if (json_path != "-" && fs::path(json_path).has_parent_path()) {
        fs::create_directories(fs::path(json_path).parent_path());
    }
    if (write_csv) {
        rec->write_csv(csv_path);
    }
    mcsim::write_metrics_json_atomic(json_path, metrics);
    if (!opt.quiet && json_path != "-") {
        mcsim::print_metrics(stdout, metrics);
        std::fflush(stdout);
        if (write_csv) {
            std::fprintf(stderr, "motorsim: wrote %s, %s\n", csv_path.c_str(), json_path.c_str());
        } else {
            std::fprintf(stderr, "motorsim: wrote %s\n", json_path.c_str());
        }
    }
    if (write_png) {
        const char* env_py = std::getenv("MC_PYTHON");
        const std::string python = (env_py != nullptr && env_py[0] != '\0') ? env_py : MOTORSIM_PYTHON;
        const std::string why = mcsim::run_plot(python, MOTORSIM_PLOT_SCRIPT, csv_path, png_path);
        if (!why.empty()) {
            std::fprintf(stderr, "warning: plot skipped: %s\n", why.c_str());
        } else if (!opt.quiet) {
            std::fprintf(stderr, "motorsim: wrote %s\n", png_path.c_str());
        }
    }
    return verdict(sc, metrics, watch);
}

}  // namespace

// Outside its try blocks only the CLI11 set-up can throw (bad_alloc, or a
// duplicate option: a programming error every test run would show):
// std::terminate with the exception's message is the right end for those.
// NOLINTNEXTLINE(bugprone-exception-escape)
int main(int argc, char** argv)
{
    CLI::App app{"motorsim: closed-loop simulation of a drive of the registry on a model motor (the scenario's [drive] "
                 "kind, or the drive whose table it has; the drives: see --help's footer)",
                 "motorsim"};
    Options opt;
    app.set_version_flag("--version", std::string("motorsim ") + MOTORSIM_VERSION +
                                          " (sensorless_drive; firmware " + MC_VERSION_STRING + ", " +
                                          (MC_FIXED ? "fixed point Q14.17" : "float") + ")");
    app.add_option("--scenario", opt.scenario, "scenario TOML file (format: sim/scenarios/README.md)")
        ->required()
        ->type_name("FILE");
    CLI::Option* out_opt =
        app.add_option("--out", opt.out_dir,
                       "output directory for <stem>.csv, <stem>_metrics.json, <stem>.png (default: out, "
                       "unless --metrics-out is given alone: then metrics only)")
            ->type_name("DIR");
    CLI::Option* metrics_out_opt = app.add_option("--metrics-out", opt.metrics_out,
                   "metrics JSON path (default DIR/<stem>_metrics.json); without --out, the only output")
        ->type_name("FILE.json");
    // Signed so that "-3" is an error rather than a wrapped 2^64 - 3.
    CLI::Option* seed_opt = app.add_option("--seed", opt.seed, "noise seed >= 0, overrides [run] seed")
                                ->type_name("N")
                                ->check(CLI::Validator(
                                    [](std::string& v) {
                                        if (!v.empty() && v[0] == '-') {
                                            return "must be >= 0 (got " + v + ")";
                                        }
                                        errno = 0;
                                        char* end = nullptr;
                                        (void)std::strtoll(v.c_str(), &end, 10);
                                        if (errno == ERANGE) {
                                            return "must be at most 9223372036854775807 (got " + v + ")";
                                        }
                                        return std::string();
                                    },
                                    ">= 0"));
    CLI::Option* theta0_opt =
        app.add_option("--theta0-rad", opt.theta0_rad, "initial rotor angle [rad, mechanical], overrides [run] theta0_rad")
            ->type_name("RAD");
    CLI::Option* delay_opt = app.add_option("--compute-delay-samples", opt.delay_samples,
                                            "computation delay in samples [0, 1], overrides [run] compute_delay_samples")
                                 ->type_name("D");
    app.add_option("--estimator", opt.estimator,
                   "the drive's estimator, overrides its table's: paper 001's speed drive flux (its flux and I&I "
                   "observers) or back_emf (paper 000's back-EMF chain); paper 002's drive encoder, flux (paper "
                   "001's flux observer, sensorless) or hfi (HF injection at low speed, the flux observer at "
                   "speed); a drive with one estimator refuses it")
        ->check(CLI::IsMember({"flux", "back_emf", "encoder", "hfi"}))
        ->type_name("NAME");
    app.add_flag("--no-expect", opt.no_expect,
                 "do not judge the metrics against the scenario's [expect] table (for variants: another "
                 "estimator, seed or angle); a fault or a diverged plant still fails the run");
    CLI::Option* can_opt = app.add_option("--can", opt.can_iface,
                   "run the drive as a node on SocketCAN interface IFACE (can0, vcan0): telemetry and commands "
                   "of tools/can/drive.dbc (docs/can.md)")
        ->type_name("IFACE");
    app.add_option("--can-node", opt.can_node, "node id 0-15 on the bus (default 0), added to the DBC's ids")
        ->type_name("N")
        ->check(CLI::Range(0u, 15u))
        ->needs(can_opt);
    CLI::Option* flash_opt = app.add_option("--flash-image", opt.flash_image,
                   "keep the drive's parameters in PATH, a flash image of the board's store (two 16 KB sectors; "
                   "created erased if absent): at start the newest saved record goes over the scenario's design "
                   "input, and on CAN a ParamRequest save writes to it (docs/parameters.md)")
        ->type_name("PATH");
    app.add_option("--backend", opt.backend,
                   "plant (default: the drive on the plant's sensor and amplifier models) or board-emulated (through "
                   "an emulated DAC/ADC board, [board] of the scenario: Hall sensors, 16-bit converters, linear "
                   "amplifiers, the sensors' offsets calibrated at start-up)")
        ->check(CLI::IsMember({"plant", "board-emulated"}))
        ->type_name("NAME");
    app.add_flag("--realtime", opt.realtime, "pace the simulation to the wall clock (default: as fast as it runs)");
    app.add_flag("--no-plot", opt.no_plot, "do not write the PNG plot");
    app.add_flag("--no-csv", opt.no_csv, "do not record or write the CSV log (and so no PNG either)");
    app.add_flag("--quiet", opt.quiet, "print nothing but warnings and errors");
    std::string footer = std::string(kOutputModes) + "\n" + kExitStatusHelp + "\nDrive fault codes (metrics key \"fault\"):";
    for (int f = 0; f < DRIVE_FAULT_COUNT; ++f) {
        footer += "\n  " + std::to_string(f) + "  " + drive_fault_name(static_cast<drive_fault_t>(f));
    }
    footer += "\nDrives (firmware/drives/registry.c; [drive] kind = \"NAME\", or the drive whose table the scenario has):";
    for (std::size_t k = 0; k < drive_registry_count; ++k) {
        const mcsim::HostDrive* h = mcsim::host_drive_find(drive_registry[k]->name);
        footer += std::string("\n  ") + drive_registry[k]->name + "  [" + (h != nullptr ? h->table : "-") + "]  " +
                  drive_registry[k]->title;
    }
    app.footer(footer);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "error: %s (see motorsim --help)\n", e.what());
        return 2;
    }
    opt.seed_given = seed_opt->count() > 0;
    opt.theta0_given = theta0_opt->count() > 0;
    opt.delay_given = delay_opt->count() > 0;
    opt.out_given = out_opt->count() > 0;
    opt.metrics_out_given = metrics_out_opt->count() > 0;
    opt.can_given = can_opt->count() > 0;
    opt.flash_given = flash_opt->count() > 0;

    mcsim::install_output_signal_handlers();
    try {
        return run(opt);
    } catch (const mcsim::ScenarioError& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    } catch (const std::invalid_argument& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
}
