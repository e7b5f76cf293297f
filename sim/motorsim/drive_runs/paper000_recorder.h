// paper000_recorder.h - paper 000's probe of the one recorder
// (motorsim/run_recorder.h): the per-sample log and metrics of a
// position-drive run. One on_period() per control period: the true plant
// state at the sampling instant and the drive's telemetry of the same
// sample (paper000_telemetry_t: the (f-g) frame's currents, disturbances
// and the jump count), one preallocated row (unless built without a log),
// the metrics. No allocation and no I/O per sample.
#ifndef MCSIM_MOTORSIM_DRIVE_RUNS_PAPER000_RECORDER_H
#define MCSIM_MOTORSIM_DRIVE_RUNS_PAPER000_RECORDER_H

#include <cmath>
#include <cstdint>
#include <vector>

#include "drives/paper000/paper000_drive.h"
#include "hal_sw_plant.h"
#include "model/reference.h"
#include "model/pm_plant.h"
#include "motorsim/run_recorder.h"
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

class Paper000Recorder : public RunRecorder {
public:
    Paper000Recorder(const Scenario& sc, const PmPlant& plant, const paper000_drive_t& drive, bool record_rows);
    MetricList metrics(double wall_loop_s) const override;

private:
    std::int64_t on_period(const hal_sw_plant_period_t& p, double* r) override;

    double drive_theta_ref_last_ = 0.0;

    const paper000_drive_t& drive_;
    const Reference ref_;       // the scenario's [trajectory], from 0 rad
    double n_p_;
    double K_over_L_;           // true plant, for d_f, d_g of eq. (23)
    double inv_L_drive_;        // drive model, for d_hat = e_hat / L
    double omega_lim_rad_s_;

    // metric accumulators
    bool offset_known_ = false;
    double offset_rad_ = 0.0;          // equilibrium found by the alignment (absolute plant angle)
    double align_residual_rad_ = 0.0;  // rotor minus that equilibrium at t = 0
    std::uint64_t n_pre_ = 0;          // samples before t = 0 (alignment)
    std::uint64_t n_closed_ = 0, n_mode_closed_ = 0, n_peak_ = 0, n_vsat_ = 0;
    double theta_track_max_ = 0.0, theta_est_max_ = 0.0, current_obs_max_ = 0.0, omega_est_peak_max_ = 0.0;
    double omega_est_max_ = 0.0, theta_track_ss_ = 0.0, theta_est_ss_ = 0.0, omega_est_ss_ = 0.0;
    double max_abs_current_ = 0.0, max_abs_voltage_ = 0.0, ref_mismatch_max_ = 0.0;
    double theta_track_max_all_ = 0.0;
    std::int64_t mode_switches_ = 0;
    int last_mode_ = -1;
    std::int64_t fault_ = 0;
    double first_switch_t_ = -1.0;
    // [load] changes: the next one not yet complete, the end of the last
    // complete one (-1: none yet), the tracking error from kLoadSettleS after it
    std::size_t load_next_ = 0;
    double load_done_t_ = -1.0;
    double theta_track_load_settled_max_ = NAN;
};

}  // namespace mcsim

#endif  // MCSIM_MOTORSIM_DRIVE_RUNS_PAPER000_RECORDER_H
