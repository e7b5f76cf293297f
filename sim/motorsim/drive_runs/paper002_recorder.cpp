#include "motorsim/drive_runs/paper002_recorder.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "mc_convert.h"
#include "model/spectrum.h"

namespace mcsim {
namespace {
// the metric windows of paper002_recorder.h: RMSE over [0, 1] s, and from
// 50 ms
constexpr double kRmseEnd_s = 1.0;
constexpr double kRmseSkip_s = 0.05;
}  // namespace

const char* const kPaper002ColumnNames[kP2NumColumns] = {
    "t_s",        "omega_d_rad_s", "omega_rad_s", "omega_est_rad_s", "theta_rad", "theta_est_rad", "theta_meas_rad",
    "M0_Nm",      "M0_est_Nm",     "M_d_Nm",      "i_d_A",           "i_q_A",     "i_d_meas_A", "i_q_meas_A", "i_d_est_A",
    "i_q_est_A",  "i_d_ref_A",     "i_q_ref_A",   "u_d_V",           "u_q_V",     "v_a_V",
    "v_b_V",      "v_c_V",         "mode",        "saturated",   "fault"};

Paper002Recorder::Paper002Recorder(const Scenario& sc, const PmPlant& plant, const paper002_drive_t& drive,
                                   bool record_rows)
    : RunRecorder(sc, plant, kPaper002ColumnNames, kP2NumColumns, record_rows), drive_(drive)
{
    const std::size_t n_win = static_cast<std::size_t>(static_cast<double>(n_max()) * (1.0 - kP002SteadyFrom)) + 1;
    ud_.reserve(n_win);
    uq_.reserve(n_win);
}

std::int64_t Paper002Recorder::on_period(const hal_sw_plant_period_t& p, double* r)
{
    const auto& l = drive_.last;
    const double t = p.t_s;
    const double w_d = to_double(l.w_d_rad_s);
    const double w = plant_.omega_rad_s();
    const double err = w_d - w;
    if (t < kRmseEnd_s - 1e-12) {
        ss_ += err * err;
        n_rmse_ += 1;
        if (t >= kRmseSkip_s - 1e-12) {
            ss50_ += err * err;
            n_rmse50_ += 1;
        }
    }
    err_max_ = std::max(err_max_, std::fabs(err));
    const double w_hat = to_double(l.w_hat_rad_s);
    est_ss_ += (w_hat - w) * (w_hat - w);
    // the EKF's angle and the angle it was given (the encoder's or the flux
    // observer's), against the rotor's, mechanical
    const double th = plant_.theta_rad();
    const double th_err = wrap_pi(to_double(l.theta_hat_rad) - th);
    const double thm_err = wrap_pi(to_double(l.theta_meas_rad) - th);
    th_ss_ += th_err * th_err;
    thm_ss_ += thm_err * thm_err;
    if (drive_.cfg.angle_source == P002_ANGLE_HFI) {
        // the HF injection (angle source 2): the EKF's largest angle error
        // from 50 ms (the first correction of the start left out),
        // the rotor's largest excursion from its start (mechanical), the
        // injection's voltage and its current ripple (half the change of
        // the true alpha-beta current from one sample to the next, the
        // triangle's amplitude) while it is on
        if (index() == 0) {
            theta0_ = th;
        }
        if (t >= kRmseSkip_s - 1e-12) {
            th_err_max_ = std::max(th_err_max_, std::fabs(th_err));
        }
        drift_max_ = std::max(drift_max_, std::fabs(wrap_pi(th - theta0_)));
        const double ia = plant_.i_a_A(), ib = plant_.i_b_A();
        if (drive_.est_state.hfi.hfi.on) {
            n_hfi_on_ += 1;
            hfi_ripple_ss_ += 0.25 * ((ia - prev_ia_) * (ia - prev_ia_) + (ib - prev_ib_) * (ib - prev_ib_));
            const double ua = to_double(drive_.est_state.hfi.hfi.u_h_V.alpha), ub = to_double(drive_.est_state.hfi.hfi.u_h_V.beta);
            hfi_u_ss_ += ua * ua + ub * ub;
        }
        prev_ia_ = ia;
        prev_ib_ = ib;
    }
    // the lumped disturbance the EKF estimates: everything that brakes the
    // rotor besides the viscous d w of its model (load, LuGre friction)
    const double M0 = plant_.load_torque_Nm();
    const double M0_hat = to_double(l.M0_hat_Nm);
    m0_ss_ += (M0_hat - M0) * (M0_hat - M0);
    // the true d-q currents on the true electrical angle
    const double c = plant_.cos_elec(), s = plant_.sin_elec();
    const double i_d = c * plant_.i_a_A() + s * plant_.i_b_A();
    const double i_q = -s * plant_.i_a_A() + c * plant_.i_b_A();
    double i_ph[3] = {0.0, 0.0, 0.0};
    plant_.phase_currents(i_ph);
    for (int k = 0; k < plant_.n_phases(); ++k) {
        i_max_ = std::max(i_max_, std::fabs(i_ph[k]));
    }
    if (l.saturated) {
        n_sat_ += 1;
    }
    const double u_d = to_double(l.u_d_V), u_q = to_double(l.u_q_V);
    if (static_cast<double>(index()) >= kP002SteadyFrom * static_cast<double>(n_max())) {
        ud_.push_back(u_d);
        uq_.push_back(u_q);
    }
    // the EKF's covariance: symmetric, positive definite
    Eigen::Matrix<double, EKF_N, EKF_N> P;
    for (int i = 0; i < EKF_N; ++i) {
        for (int j = 0; j < EKF_N; ++j) {
            P(i, j) = to_double(drive_.ekf.P[i][j]);
        }
    }
    p_asym_ = std::max(p_asym_, (P - P.transpose()).cwiseAbs().maxCoeff());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, EKF_N, EKF_N>> eig(P, Eigen::EigenvaluesOnly);
    const double e_min = eig.eigenvalues().minCoeff();
    p_min_eig_ = std::min(p_min_eig_, e_min);
    spd_ok_ = spd_ok_ && drive_.ekf.spd_ok && e_min > 0.0;
    if (drive_.sup.fault != DRIVE_FAULT_NONE) {
        fault_ = static_cast<std::int64_t>(drive_.sup.fault);
    }
    if (r != nullptr) {
        r[kP2T] = t;
        r[kP2OmegaD] = w_d;
        r[kP2Omega] = w;
        r[kP2OmegaEst] = w_hat;
        r[kP2Theta] = wrap_pi(plant_.theta_rad());
        r[kP2ThetaEst] = to_double(l.theta_hat_rad);
        r[kP2ThetaMeas] = to_double(l.theta_meas_rad);
        r[kP2M0] = M0;
        r[kP2M0Est] = M0_hat;
        r[kP2Md] = to_double(l.M_d_Nm);
        r[kP2Id] = i_d;
        r[kP2Iq] = i_q;
        // the drive's measured currents, in the frame of the angle it runs on
        r[kP2IdMeas] = to_double(l.i_d_A);
        r[kP2IqMeas] = to_double(l.i_q_A);
        r[kP2IdEst] = to_double(l.i_d_hat_A);
        r[kP2IqEst] = to_double(l.i_q_hat_A);
        r[kP2IdRef] = to_double(l.i_dd_A);
        r[kP2IqRef] = to_double(l.i_qd_A);
        r[kP2Ud] = u_d;
        r[kP2Uq] = u_q;
        r[kP2Va] = p.v_a_V;
        r[kP2Vb] = p.v_b_V;
        r[kP2Vc] = p.v_c_V;
        // drive_mode_t's numbers (plot_run.py reads them): closed loop from
        // the first sample (the encoder gives the angle), 2 in the safe state
        r[kP2Mode] = drive_.sup.fault != DRIVE_FAULT_NONE ? 2.0 : 1.0;
        r[kP2Sat] = l.saturated ? 1.0 : 0.0;
        r[kP2Fault] = static_cast<double>(drive_.sup.fault);
    }
    return fault_;
}

MetricList Paper002Recorder::metrics(double wall_loop_s) const
{
    const std::uint64_t n_rec = index();  // every period recorded
    const double n = static_cast<double>(n_rec);
    auto rms = [](double ss, std::uint64_t k) { return k > 0 ? std::sqrt(ss / static_cast<double>(k)) : NAN; };
    const double hf_d = hf_rms(ud_, sc_.ts_s, kP002HfCutoff_Hz), hf_q = hf_rms(uq_, sc_.ts_s, kP002HfCutoff_Hz);
    double u_ss = 0.0;
    for (std::size_t k = 0; k < ud_.size(); ++k) {
        u_ss += ud_[k] * ud_[k] + uq_[k] * uq_[k];
    }
    MetricList m;
    m.emplace_back("speed_rmse_rad_s", rms(ss_, n_rmse_));
    m.emplace_back("speed_rmse_after_50ms_rad_s", rms(ss50_, n_rmse50_));
    m.emplace_back("speed_err_max_rad_s", err_max_);
    m.emplace_back("omega_est_rmse_rad_s", rms(est_ss_, n_rec));
    m.emplace_back("M0_est_rmse_Nm", rms(m0_ss_, n_rec));
    m.emplace_back("theta_est_rmse_rad", rms(th_ss_, n_rec));
    m.emplace_back("theta_meas_rmse_rad", rms(thm_ss_, n_rec));
    m.emplace_back("angle_source", static_cast<std::int64_t>(drive_.cfg.angle_source));
    if (drive_.cfg.angle_source == P002_ANGLE_HFI) {
        m.emplace_back("theta_est_err_max_rad", th_err_max_);
        m.emplace_back("position_drift_max_rad", drift_max_);
        m.emplace_back("hfi_on_fraction", n > 0 ? static_cast<double>(n_hfi_on_) / n : 0.0);
        m.emplace_back("hfi_current_ripple_rms_A", rms(hfi_ripple_ss_, n_hfi_on_));
        m.emplace_back("hfi_voltage_rms_V", rms(hfi_u_ss_, n_hfi_on_));
        if (drive_.cfg.hfi_find_angle) {
            // the start's polarity test: +1 kept, -1 flipped, 0 undecided (or not reached)
            m.emplace_back("hfi_start_polarity", static_cast<std::int64_t>(drive_.est_state.hfi.polarity));
            // its difference of the two peaks (A; 0 until it is done)
            m.emplace_back("hfi_start_polarity_diff_A", to_double(drive_.est_state.hfi.magpol.diff_A));
            // the lock's mean (H1) amplitude over its last quarter (1 on the
            // d axis, L_d/L_q across it; below (1 + L_d/L_q)/2 refused)
            m.emplace_back("hfi_start_lock_amp", to_double(drive_.est_state.hfi.lock_amp));
        }
    }
    m.emplace_back("voltage_hf_rms_V", std::sqrt(hf_d * hf_d + hf_q * hf_q));
    m.emplace_back("voltage_rms_V", ud_.empty() ? 0.0 : std::sqrt(u_ss / static_cast<double>(ud_.size())));
    m.emplace_back("ekf_p_min_eig", p_min_eig_);
    m.emplace_back("ekf_p_asym_max", p_asym_);
    m.emplace_back("ekf_spd_ok", static_cast<std::int64_t>(spd_ok_ ? 1 : 0));
    // the EKF's Q and R diagonals it ran with (the design's or [paper002]
    // ekf_q, ekf_r), per sample
    static const char* const kQ[EKF_N] = {"ekf_q_id", "ekf_q_iq", "ekf_q_theta", "ekf_q_omega", "ekf_q_M0"};
    static const char* const kR[EKF_M] = {"ekf_r_id", "ekf_r_iq", "ekf_r_theta"};
    for (int i = 0; i < EKF_N; ++i) {
        m.emplace_back(kQ[i], static_cast<double>(drive_.cfg.ekf.q[i]));
    }
    for (int i = 0; i < EKF_M; ++i) {
        m.emplace_back(kR[i], static_cast<double>(drive_.cfg.ekf.r[i]));
    }
    m.emplace_back("voltage_saturated_fraction", n > 0 ? static_cast<double>(n_sat_) / n : 0.0);
    m.emplace_back("max_abs_current_A", i_max_);
    m.emplace_back("i_max_A", sc_.i_max_A);
    m.emplace_back("final_omega_rad_s", plant_.omega_rad_s());
    m.emplace_back("fault", fault_);
    append_run_tail(&m, wall_loop_s, false);
    return m;
}

}  // namespace mcsim
