// recorder.h - per-sample log and metrics of a closed-loop run. One
// Recorder::on_period() per control period (installed as the sw_plant
// backend's monitor): it reads the true plant state at the sampling instant
// and the drive's telemetry of the same sample, appends one preallocated row
// (unless built without a log) and updates the metrics. No allocation and no
// I/O per sample.
#ifndef MCSIM_MOTORSIM_RECORDER_H
#define MCSIM_MOTORSIM_RECORDER_H

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "drives/paper000/paper000_drive.h"
#include "hal_sw_plant.h"
#include "model/reference.h"
#include "model/pm_plant.h"
#include "motorsim/run_watch.h"
#include "scenario/scenario.h"

namespace mcsim {

// CSV columns, in file order (names in kColumnNames).
enum Column : int {
    kColT,
    kColMode,
    kColThetaRef,
    kColOmegaRef,
    kColAccelRef,
    kColTheta,
    kColThetaEst,
    kColOmega,
    kColOmegaEst,
    kColAccel,
    kColAccelEst,
    kColLoadTrue,
    kColLoadEst,
    kColIa,
    kColIb,
    kColIaMeas,
    kColIbMeas,
    kColIf,
    kColIg,
    kColIfHat,
    kColIgHat,
    kColDf,
    kColDg,
    kColDfHat,
    kColDgHat,
    kColVa,
    kColVb,
    kColVf,
    kColVg,
    kColDeltaThetaEst,
    kColJumpCount,
    kColDeltaTheta,
    kColIfRef,
    kColIgRef,
    kColFault,
    kNumColumns
};

extern const char* const kColumnNames[kNumColumns];

using Row = std::array<double, kNumColumns>;

// One metric: an integer or a real (NaN allowed, written as null in JSON).
using MetricValue = std::variant<std::int64_t, double>;
using MetricList = std::vector<std::pair<std::string, MetricValue>>;

class Recorder {
public:
    // record_rows = false: metrics only, no per-sample log (data() is empty);
    // the metrics are the same either way.
    Recorder(const Scenario& sc, const PmPlant& plant, const paper000_drive_t& drive, const Reference& ref,
             bool record_rows = true);

    // hal_sw_plant_monitor_fn; ctx is the Recorder.
    static void monitor(void* ctx, const hal_sw_plant_period_t* p);

    // The rows recorded so far (the log is sized for the scenario's n_ticks).
    const Row* data() const { return rows_.data(); }
    std::size_t size() const { return rows_.empty() ? 0 : static_cast<std::size_t>(n_); }

    // Final metrics; wall_loop_s is the wall time of the simulation loop.
    MetricList metrics(double wall_loop_s) const;
    const RunWatch& watch() const { return watch_; }

    // Scores the tracking against the drive's own reference instead of the
    // scenario's: a drive commanded over CAN moves where it is told, not
    // where the scenario's [trajectory] says.
    void score_against_drive_reference(bool on) { drive_ref_ = on; }

private:
    void on_period(const hal_sw_plant_period_t& p);

    bool drive_ref_ = false;
    double drive_theta_ref_last_ = 0.0;

    const Scenario& sc_;
    const PmPlant& plant_;
    const paper000_drive_t& drive_;
    const Reference& ref_;
    double n_p_;
    double K_over_L_;           // true plant, for d_f, d_g of eq. (23)
    double inv_L_drive_;        // drive model, for d_hat = e_hat / L
    double omega_lim_rad_s_;
    std::uint64_t n_max_;       // periods scored: the scenario's n_ticks
    std::vector<Row> rows_;     // n_max_ rows, or none (metrics only)

    // metric accumulators
    bool offset_known_ = false;
    double offset_rad_ = 0.0;          // equilibrium found by the alignment (absolute plant angle)
    double align_residual_rad_ = 0.0;  // rotor minus that equilibrium at t = 0
    std::uint64_t n_pre_ = 0;          // samples before t = 0 (alignment)
    std::uint64_t n_ = 0, n_closed_ = 0, n_mode_closed_ = 0, n_peak_ = 0, n_vsat_ = 0;
    double theta_track_max_ = 0.0, theta_est_max_ = 0.0, current_obs_max_ = 0.0, omega_est_peak_max_ = 0.0;
    double omega_est_max_ = 0.0, theta_track_ss_ = 0.0, theta_est_ss_ = 0.0, omega_est_ss_ = 0.0;
    double max_abs_current_ = 0.0, max_abs_voltage_ = 0.0, ref_mismatch_max_ = 0.0;
    double theta_track_max_all_ = 0.0;
    std::int64_t mode_switches_ = 0;
    int last_mode_ = -1;
    std::int64_t fault_ = 0;
    RunWatch watch_;
    double first_switch_t_ = -1.0;
    // [load] changes: the next one not yet complete, the end of the last
    // complete one (-1: none yet), the tracking error from kLoadSettleS after it
    std::size_t load_next_ = 0;
    double load_done_t_ = -1.0;
    double theta_track_load_settled_max_ = NAN;
};

}  // namespace mcsim

#endif  // MCSIM_MOTORSIM_RECORDER_H
