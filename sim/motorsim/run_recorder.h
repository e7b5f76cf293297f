// run_recorder.h - the one recorder of motorsim. What every run's log
// shares is here: one preallocated row per period (allocated and touched
// before the loop, so the loop neither allocates nor faults pages in), the
// run's watch (divergence, the drive's first fault: run_watch.h), the
// software plant's monitor callback, the metrics' common tail and the one
// CSV writer (outputs.h). What a drive's log holds is its probe: a subclass
// that names its columns, fills one row per period from the plant and the
// drive, and computes its metrics. Speed drives share one probe
// (speed_recorder.h, through the drive interface); a drive with telemetry
// of its own brings its probe in sim/motorsim/drive_runs/ and one line in
// recorders/recorder_registry.cpp (make_recorder below).
#ifndef MCSIM_MOTORSIM_RUN_RECORDER_H
#define MCSIM_MOTORSIM_RUN_RECORDER_H

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

extern "C" {
#include "drives/drive.h"
}
#include "hal_sw_plant.h"
#include "model/pm_plant.h"
#include "motorsim/metrics.h"
#include "motorsim/run_watch.h"
#include "scenario/scenario.h"

namespace mcsim {

// An angle [rad] into [-pi, pi): the probes' angle errors.
inline double wrap_pi(double x)
{
    constexpr double kPi = 3.14159265358979323846;
    x = std::fmod(x + kPi, 2.0 * kPi);
    if (x < 0.0) {
        x += 2.0 * kPi;
    }
    return x - kPi;
}

class RunRecorder {
public:
    virtual ~RunRecorder() = default;
    RunRecorder(const RunRecorder&) = delete;
    RunRecorder& operator=(const RunRecorder&) = delete;

    // hal_sw_plant_monitor_fn; ctx is the RunRecorder.
    static void monitor(void* ctx, const hal_sw_plant_period_t* p);

    // Final metrics (the probe's, then the run's tail); wall_loop_s is the
    // wall time of the simulation loop. The names are the same before the
    // run (motorsim checks [expect] against them).
    virtual MetricList metrics(double wall_loop_s) const = 0;
    const RunWatch& watch() const { return watch_; }

    // Scores against the drive's own reference instead of the scenario's:
    // a drive commanded over CAN goes where it is told.
    void score_against_drive_reference(bool on) { drive_ref_ = on; }

    // The log as a CSV file (outputs.h: written whole or not at all).
    void write_csv(const std::string& path) const;
    std::size_t rows() const { return rows_.empty() ? 0 : static_cast<std::size_t>(n_); }
    const double* data() const { return rows_.data(); }

protected:
    // columns: n_columns names (static storage); record_rows = false: no
    // per-sample log (metrics only), the metrics are the same.
    RunRecorder(const Scenario& sc, const PmPlant& plant, const char* const* columns, int n_columns,
                bool record_rows);

    // One period of the probe: its row (nullptr without a log) and its
    // metrics' accumulators. Returns the drive's fault code after its step
    // (0: none), for the watch. index() is this period's row.
    virtual std::int64_t on_period(const hal_sw_plant_period_t& p, double* row) = 0;

    // The tail every run's metrics end with: n_samples, seed, [substeps,]
    // sim_time_s, wall_time_s, realtime_factor.
    void append_run_tail(MetricList* m, double wall_loop_s, bool with_substeps) const;

    std::uint64_t index() const { return n_; }      // rows recorded before this period
    std::uint64_t n_max() const { return n_max_; }  // the scenario's periods
    double* row_at(std::uint64_t k);                // an earlier row (nullptr without a log)
    bool drive_ref() const { return drive_ref_; }

    const Scenario& sc_;
    const PmPlant& plant_;

private:
    void record(const hal_sw_plant_period_t& p);

    const char* const* columns_;
    int n_columns_;
    std::uint64_t n_max_;
    std::uint64_t n_ = 0;
    std::vector<double> rows_;
    bool drive_ref_ = false;
    RunWatch watch_;
};

// The recorder of the drive d ([drive] kind, or the drive a paper's table
// chose): a drive's own probe from drive_runs/registry.cpp, else
// the speed probe for a speed drive. Throws ScenarioError for a drive with
// neither.
std::unique_ptr<RunRecorder> make_recorder(const Scenario& sc, const PmPlant& plant, const drive_t& d,
                                           bool record_rows);

}  // namespace mcsim

#endif  // MCSIM_MOTORSIM_RUN_RECORDER_H
