// paper002_recorder.h - paper 002's probe of the one recorder
// (motorsim/run_recorder.h): per-sample log and metrics of a paper-002 run
// (section 5's study): the true plant against the drive's reference and
// its EKF, one preallocated row per period.
//
// Metrics (keys checked by tests/sim, tools/tables/paper002_table.py and checks
// outside them):
//   speed_rmse_rad_s              RMSE of w_d - w over [0, 1] s (the whole
//                                 run if shorter), w the plant's speed
//   speed_rmse_after_50ms_rad_s   the same over [0.05, 1] s (the start from
//                                 w(0) = 5 rad/s left out)
//   speed_err_max_rad_s           max |w_d - w| over the run
//   omega_est_rmse_rad_s          RMSE of the EKF's w_hat - w
//   M0_est_rmse_Nm                RMSE of the EKF's M0_hat against the true
//                                 lumped disturbance (load + LuGre friction)
//   voltage_hf_rms_V              the RMS of the applied d-q voltages'
//                                 spectrum above 1 kHz over the run's second
//                                 half (steady state of the reference: the
//                                 hold at w1), mean removed, Hann window
//                                 (power-corrected): chattering shows here
//   voltage_rms_V                 the RMS of the same signals, for scale
//   ekf_p_min_eig                 the smallest eigenvalue of the EKF's P
//                                 after any sample (SPD: > 0)
//   ekf_p_asym_max                the largest |P_ij - P_ji| after any sample
//   ekf_spd_ok                    1 if every correction found S positive
//                                 definite and P stayed SPD, else 0
//   theta_est_err_max_rad, position_drift_max_rad, hfi_on_fraction,
//   hfi_current_ripple_rms_A, hfi_voltage_rms_V   angle source 2 (HF
//                                 injection) only: max |theta_hat - theta|
//                                 of the EKF from 50 ms on, max |theta - theta(0)| (the
//                                 rotor's excursion from its start), both
//                                 mechanical; the share of samples with the
//                                 injection on, and while on the RMS of half
//                                 the true alpha-beta current's change per
//                                 sample (the triangle's amplitude) and of
//                                 the injected voltage
//   hfi_start_polarity            with [paper002] hfi_find_angle only: the
//                                 start's polarity test, +1 kept, -1 flipped
//                                 by pi, 0 undecided (the drive refused)
//   hfi_start_polarity_diff_A     the test's i_pos - i_neg (A)
//   hfi_start_lock_amp            the lock's mean (H1) amplitude over its
//                                 last quarter: 1 locked on the d axis,
//                                 L_d/L_q across it (below (1 + L_d/L_q)/2
//                                 the drive refused: fault 12)
//   max_abs_current_A, voltage_saturated_fraction, fault, ...
#ifndef MCSIM_MOTORSIM_DRIVE_RUNS_PAPER002_RECORDER_H
#define MCSIM_MOTORSIM_DRIVE_RUNS_PAPER002_RECORDER_H

#include <cstdint>
#include <vector>

#include "drives/paper002/paper002_drive.h"
#include "hal_sw_plant.h"
#include "model/pm_plant.h"
#include "motorsim/run_recorder.h"
#include "scenario/scenario.h"

namespace mcsim {

enum P002Column : int {
    kP2T,
    kP2OmegaD,
    kP2Omega,
    kP2OmegaEst,
    kP2Theta,
    kP2ThetaEst,
    kP2ThetaMeas,
    kP2M0,
    kP2M0Est,
    kP2Md,
    kP2Id,
    kP2Iq,
    kP2IdMeas,
    kP2IqMeas,
    kP2IdEst,
    kP2IqEst,
    kP2IdRef,
    kP2IqRef,
    kP2Ud,
    kP2Uq,
    kP2Va,
    kP2Vb,
    kP2Vc,
    kP2Mode,
    kP2Sat,
    kP2Fault,
    kP2NumColumns
};
extern const char* const kPaper002ColumnNames[kP2NumColumns];

// The frequency above which the applied voltage's content counts as
// chattering [Hz] (the figure), and where the steady state starts
// as a fraction of the run.
constexpr double kP002HfCutoff_Hz = 1000.0;
constexpr double kP002SteadyFrom = 0.5;

class Paper002Recorder : public RunRecorder {
public:
    Paper002Recorder(const Scenario& sc, const PmPlant& plant, const paper002_drive_t& drive, bool record_rows);
    MetricList metrics(double wall_loop_s) const override;

private:
    std::int64_t on_period(const hal_sw_plant_period_t& p, double* row) override;

    const paper002_drive_t& drive_;
    std::vector<double> ud_, uq_;  // the steady-state window, for the spectrum

    std::uint64_t n_rmse_ = 0, n_rmse50_ = 0, n_sat_ = 0;
    double ss_ = 0.0, ss50_ = 0.0, err_max_ = 0.0, est_ss_ = 0.0, m0_ss_ = 0.0, i_max_ = 0.0, th_ss_ = 0.0, thm_ss_ = 0.0;
    double p_min_eig_ = 1e300, p_asym_ = 0.0;
    bool spd_ok_ = true;
    // the HF injection's metrics (angle source 2 only; metrics() lists them then)
    double th_err_max_ = 0.0, drift_max_ = 0.0, theta0_ = 0.0, hfi_ripple_ss_ = 0.0, hfi_u_ss_ = 0.0;
    double prev_ia_ = 0.0, prev_ib_ = 0.0;
    std::uint64_t n_hfi_on_ = 0;
    std::int64_t fault_ = 0;
};

}  // namespace mcsim

#endif  // MCSIM_MOTORSIM_DRIVE_RUNS_PAPER002_RECORDER_H
