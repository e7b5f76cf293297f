// run_recorder.h - the one recorder of motorsim. What every run's log
// shares is here: one preallocated row per period (allocated and touched
// before the loop, so the loop neither allocates nor faults pages in), the
// run's watch (divergence, the drive's first fault: run_watch.h), the
// software plant's monitor callback, the drive's signals (drive_signals.h:
// what it shows beyond drive_status_t, read after every step and written
// as the log's last columns, under their names), the metrics' common tail
// and the one CSV writer (outputs.h). How a run is scored is a subclass (a
// scoring) that names its columns (the time, the plant's truth, the
// reference it scores against, the drive's status it needs), fills them
// each period and computes the metrics, asking for a drive's signal by
// name where a metric needs one: "position" (position_recorder.h),
// "speed" (speed_recorder.h), "ekf_speed" (ekf_speed_recorder.h). A drive's
// host part names its scoring (HostDrive::scoring), else its kind does
// (make_recorder below). No scoring names a drive.
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
#include "motorsim/drive_signals.h"
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

    // Final metrics (the scoring's, then the run's tail); wall_loop_s is the
    // wall time of the simulation loop. The names are the same before the
    // run (motorsim checks [expect] against them).
    virtual MetricList metrics(double wall_loop_s) const = 0;
    const RunWatch& watch() const { return watch_; }

    // Scores against the drive's own reference instead of the scenario's:
    // a drive commanded over CAN goes where it is told.
    void score_against_drive_reference(bool on) { drive_ref_ = on; }

    // The log as a CSV file (outputs.h: written whole or not at all): the
    // scoring's columns, then the drive's signals (not its settings).
    void write_csv(const std::string& path) const;
    std::size_t rows() const { return rows_.empty() ? 0 : static_cast<std::size_t>(n_); }
    const double* data() const { return rows_.data(); }
    const std::vector<const char*>& columns() const { return columns_; }

protected:
    // columns: the scoring's n_columns names (static storage), which no
    // signal of the drive may have (std::logic_error naming both);
    // record_rows = false: no per-sample log (metrics only), the metrics
    // are the same.
    RunRecorder(const Scenario& sc, const PmPlant& plant, const drive_t& drive, const char* const* columns,
                int n_columns, bool record_rows);

    // One period of the scoring: its columns of the row (nullptr without a
    // log) and its metrics' accumulators; the drive's signals are read
    // (signals().value). Returns the drive's fault code after its step (0:
    // none), for the watch. index() is this period's row.
    virtual std::int64_t on_period(const hal_sw_plant_period_t& p, double* row) = 0;

    const drive_t& drive() const { return drive_; }
    const DriveSignals& signals() const { return signals_; }

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

    const drive_t drive_;
    DriveSignals signals_;
    std::vector<int> signal_columns_;  // the signals written, in the drive's order
    std::vector<const char*> columns_;  // the scoring's, then those signals'
    int n_own_;                         // the scoring's columns
    std::uint64_t n_max_;
    std::uint64_t n_ = 0;
    std::vector<double> rows_;
    bool drive_ref_ = false;
    RunWatch watch_;
};

// The recorder of the drive d ([drive] kind, or the drive a paper's table
// chose), after its init: the scoring its host part names
// (HostDrive::scoring), else "position" for a position drive and "speed"
// for a speed drive. Throws std::logic_error for a scoring that does not
// exist.
std::unique_ptr<RunRecorder> make_recorder(const Scenario& sc, const PmPlant& plant, const drive_t& d,
                                           bool record_rows);

}  // namespace mcsim

#endif  // MCSIM_MOTORSIM_RUN_RECORDER_H
