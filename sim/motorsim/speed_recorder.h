// speed_recorder.h - the "speed" scoring of the one recorder
// (run_recorder.h): per-sample log and metrics of a speed-drive run
// against the scenario's speed profile (paper 001's benchmark, section
// 5.1): the true plant against the reference and the drive's estimates,
// one preallocated row per period. Any speed drive: it reads the drive
// through its operations (drives/drive.h: status and flight recorder).
//
// Columns (then the drive's signals, e.g. its d-q currents i_d_meas_A,
// i_q_meas_A, i_q_ref_A): t_s, mode, the reference omega_ref_rad_s (the
// scenario's, or the drive's over CAN), the true omega_rad_s and the
// estimate, the true electrical angle theta_e_rad, the estimate and the
// error (wrapped), the true load torque load_Nm (load + friction) and the
// estimate, the true phase currents i_a_A, i_b_A, i_c_A, the command
// v_alpha_V, v_beta_V, the applied phase voltages v_a_V, v_b_V, v_c_V, the
// estimator's estimate_quality (drive_status_t: 1 when consistent),
// estimate_valid, fault.
//
// Metrics (keys checked by tests/sim and by checks outside them):
//   speed_err_settled_max_rpm   max |w - w*| where w* is constant, from 0.5 s
//                               after each reference corner or load change
//                               until the next one
//   speed_err_settled_moving_max_rpm   the same, only where w* != 0
//   speed_err_ramp_max_rpm      max |w - w*| on the ramps, from 0.5 s after
//                               their start
//   speed_err_rms_rpm, speed_err_max_rpm   over the whole run
//   load_est_err_settled_nm     max |tau_hat - tau_L| in the settled windows
//                               (tau_L: what brakes the rotor besides the
//                               motor torque: load, friction)
//   lock_time_s                 first sample of a 50 ms run of samples with
//                               the drive's estimate valid and the electrical
//                               angle error < 5 degrees (NaN: never)
//   theta_est_max_deg_e         max electrical angle error once the lock is
//                               established (lock_time_s + 50 ms) to the end
//   max_abs_current_A           largest true phase current
#ifndef MCSIM_MOTORSIM_SPEED_RECORDER_H
#define MCSIM_MOTORSIM_SPEED_RECORDER_H

#include <cstdint>
#include <vector>

#include "drives/drive.h"
#include "hal_sw_plant.h"
#include "model/pm_plant.h"
#include "motorsim/run_recorder.h"
#include "scenario/scenario.h"

namespace mcsim {

enum SpeedColumn : int {
    kSpT,
    kSpMode,
    kSpOmegaRef,
    kSpOmega,
    kSpOmegaEst,
    kSpThetaE,
    kSpThetaEEst,
    kSpThetaErrE,
    kSpLoad,
    kSpLoadEst,
    kSpIa,
    kSpIb,
    kSpIc,
    kSpValpha,
    kSpVbeta,
    kSpVa,
    kSpVb,
    kSpVc,
    kSpQuality,
    kSpValid,
    kSpFault,
    kSpNumColumns
};
extern const char* const kSpeedColumnNames[kSpNumColumns];

class SpeedRecorder : public RunRecorder {
public:
    SpeedRecorder(const Scenario& sc, const PmPlant& plant, const drive_t& drive, bool record_rows);
    MetricList metrics(double wall_loop_s) const override;

    // reference speed of the scenario at t (double, independent of the drive's)
    double omega_ref(double t_s, double* slope) const;

private:
    std::int64_t on_period(const hal_sw_plant_period_t& p, double* row) override;
    void score_speed_error(double t, double w_ref, double slope, double err_rpm, double load_err);
    void score_lock(double t, bool valid, double th_err);

    std::vector<double> events_;  // reference corners and load changes, sorted

    std::uint64_t n_closed_ = 0, lock_run_ = 0;
    double settled_max_ = 0.0, settled_moving_max_ = 0.0, ramp_max_ = 0.0, err_max_ = 0.0, err_ss_ = 0.0;
    double load_settled_max_ = 0.0, theta_max_deg_ = 0.0, i_max_ = 0.0, v_max_ = 0.0;
    double lock_t_ = -1.0, lock_run_start_ = 0.0, first_closed_t_ = -1.0;
    std::int64_t fault_ = 0;
};

}  // namespace mcsim

#endif  // MCSIM_MOTORSIM_SPEED_RECORDER_H
