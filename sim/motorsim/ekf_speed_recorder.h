// ekf_speed_recorder.h - the "ekf_speed" scoring of the one recorder
// (motorsim/run_recorder.h): per-sample log and metrics of a speed drive
// that runs its own reference and estimates a lumped disturbance (paper
// 002's section 5 study): the true plant against the drive's reference and
// estimates (its status), one preallocated row per period. Where a metric
// needs a drive's quantity beyond its status it asks for the signal by
// name (drives/drive.h) and is left out when the drive has none: the
// angle it was given (theta_meas_rad), its EKF's covariance (ekf_P_ij, the
// lower triangle; ekf_P_asym, ekf_spd_ok) and settings (angle_source,
// ekf_q_*, ekf_r_*), an HF injection's state (hfi_on, hfi_u_alpha_V,
// hfi_u_beta_V) and its start's figures (hfi_start_*).
//
// Columns (then the drive's signals): t_s, mode, fault, saturated, the
// drive's reference omega_d_rad_s, the true omega_rad_s and the estimate,
// the true mechanical angle theta_rad (wrapped) and the estimate, the true
// lumped disturbance M0_Nm (load + LuGre friction) and the estimate, the
// true d-q currents i_d_A, i_q_A on the true electrical angle, the applied
// phase voltages v_a_V, v_b_V, v_c_V.
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
//   theta_meas_rmse_rad           RMSE of the angle the EKF was given
//                                 (signal theta_meas_rad)
//   angle_source, ekf_q_*, ekf_r_*  the drive's settings of those names
//   ekf_p_min_eig                 the smallest eigenvalue of the EKF's P
//                                 after any sample (SPD: > 0), from its
//                                 lower triangle (signals ekf_P_ij)
//   ekf_p_asym_max                the largest |P_ij - P_ji| after any
//                                 sample (signal ekf_P_asym)
//   ekf_spd_ok                    1 if every correction found S positive
//                                 definite and P stayed SPD, else 0
//   theta_est_err_max_rad, position_drift_max_rad, hfi_on_fraction,
//   hfi_current_ripple_rms_A, hfi_voltage_rms_V   with an HF injection
//                                 (signal hfi_on: paper 002's angle source
//                                 2) only: max |theta_hat - theta|
//                                 of the EKF from 50 ms on, max |theta - theta(0)| (the
//                                 rotor's excursion from its start), both
//                                 mechanical; the share of samples with the
//                                 injection on, and while on the RMS of half
//                                 the true alpha-beta current's change per
//                                 sample (the triangle's amplitude) and of
//                                 the injected voltage
//   hfi_start_polarity            with the injection's own start (signal
//                                 hfi_start_polarity: [paper002] hfi_find_angle) only: the
//                                 start's polarity test, +1 kept, -1 flipped
//                                 by pi, 0 undecided (the drive refused)
//   hfi_start_polarity_diff_A     the test's i_pos - i_neg (A)
//   hfi_start_lock_amp            the lock's mean (H1) amplitude over its
//                                 last quarter: 1 locked on the d axis,
//                                 L_d/L_q across it (below (1 + L_d/L_q)/2
//                                 the drive refused: fault 12)
//   max_abs_current_A, voltage_saturated_fraction, fault, ...
#ifndef MCSIM_MOTORSIM_EKF_SPEED_RECORDER_H
#define MCSIM_MOTORSIM_EKF_SPEED_RECORDER_H

#include <cstdint>
#include <vector>

#include "hal_sw_plant.h"
#include "model/pm_plant.h"
#include "motorsim/run_recorder.h"
#include "scenario/scenario.h"

namespace mcsim {

enum EkfSpeedColumn : int {
    kEsT,
    kEsMode,
    kEsFault,
    kEsSat,
    kEsOmegaD,
    kEsOmega,
    kEsOmegaEst,
    kEsTheta,
    kEsThetaEst,
    kEsM0,
    kEsM0Est,
    kEsId,
    kEsIq,
    kEsVa,
    kEsVb,
    kEsVc,
    kEsNumColumns
};
extern const char* const kEkfSpeedColumnNames[kEsNumColumns];

// The EKF's states (the covariance's signals ekf_P_ij, i >= j).
constexpr int kEkfStates = 5;

// The frequency above which the applied voltage's content counts as
// chattering [Hz] (the figure), and where the steady state starts
// as a fraction of the run.
constexpr double kEsHfCutoff_Hz = 1000.0;
constexpr double kEsSteadyFrom = 0.5;

class EkfSpeedRecorder : public RunRecorder {
public:
    EkfSpeedRecorder(const Scenario& sc, const PmPlant& plant, const drive_t& drive, bool record_rows);
    MetricList metrics(double wall_loop_s) const override;

private:
    std::int64_t on_period(const hal_sw_plant_period_t& p, double* row) override;
    void score_injection(double t, double th, double th_err);
    void score_covariance();

    std::vector<double> ud_, uq_;  // the steady-state window, for the spectrum
    // the drive's signals the metrics need (-1: it has none)
    int sig_theta_meas_, sig_p_asym_, sig_spd_ok_, sig_hfi_on_, sig_hfi_ua_, sig_hfi_ub_;
    int sig_p_[kEkfStates][kEkfStates];  // ekf_P_ij, i >= j
    bool has_p_ = false;                 // all of them

    std::uint64_t n_rmse_ = 0, n_rmse50_ = 0, n_sat_ = 0;
    double ss_ = 0.0, ss50_ = 0.0, err_max_ = 0.0, est_ss_ = 0.0, m0_ss_ = 0.0, i_max_ = 0.0, th_ss_ = 0.0,
           thm_ss_ = 0.0;
    double p_min_eig_ = 1e300, p_asym_ = 0.0;
    bool spd_ok_ = true;
    // the HF injection's metrics (a drive with signal hfi_on only; metrics() lists them then)
    double th_err_max_ = 0.0, drift_max_ = 0.0, theta0_ = 0.0, hfi_ripple_ss_ = 0.0, hfi_u_ss_ = 0.0;
    double prev_ia_ = 0.0, prev_ib_ = 0.0;
    std::uint64_t n_hfi_on_ = 0;
    std::int64_t fault_ = 0;
};

}  // namespace mcsim

#endif  // MCSIM_MOTORSIM_EKF_SPEED_RECORDER_H
