#include "motorsim/ekf_speed_recorder.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Eigenvalues>

#include "mc_convert.h"
#include "model/spectrum.h"

namespace mcsim {
namespace {
// the metric windows of ekf_speed_recorder.h: RMSE over [0, 1] s, and from
// 50 ms
constexpr double kRmseEnd_s = 1.0;
constexpr double kRmseSkip_s = 0.05;
}  // namespace

const char* const kEkfSpeedColumnNames[kEsNumColumns] = {
    "t_s",           "mode",  "fault",     "saturated", "omega_d_rad_s", "omega_rad_s", "omega_est_rad_s", "theta_rad",
    "theta_est_rad", "M0_Nm", "M0_est_Nm", "i_d_A",     "i_q_A",         "v_a_V",       "v_b_V",           "v_c_V"};

EkfSpeedRecorder::EkfSpeedRecorder(const Scenario& sc, const PmPlant& plant, const drive_t& drive, bool record_rows)
    : RunRecorder(sc, plant, drive, kEkfSpeedColumnNames, kEsNumColumns, record_rows),
      sig_theta_meas_(signals().find("theta_meas_rad")),
      sig_p_asym_(signals().find("ekf_P_asym")),
      sig_spd_ok_(signals().find("ekf_spd_ok")),
      sig_hfi_on_(signals().find("hfi_on")),
      sig_hfi_ua_(signals().find("hfi_u_alpha_V")),
      sig_hfi_ub_(signals().find("hfi_u_beta_V"))
{
    const std::size_t n_win = static_cast<std::size_t>(static_cast<double>(n_max()) * (1.0 - kEsSteadyFrom)) + 1;
    ud_.reserve(n_win);
    uq_.reserve(n_win);
    has_p_ = true;
    for (int i = 0; i < kEkfStates; ++i) {
        for (int j = 0; j < kEkfStates; ++j) {
            const std::string name = "ekf_P_" + std::to_string(std::max(i, j)) + std::to_string(std::min(i, j));
            sig_p_[i][j] = signals().find(name.c_str());
            has_p_ = has_p_ && sig_p_[i][j] >= 0;
        }
    }
    if (sig_hfi_on_ >= 0 && (sig_hfi_ua_ < 0 || sig_hfi_ub_ < 0)) {
        sig_hfi_on_ = -1;  // an injection's metrics need its voltage too
    }
}

std::int64_t EkfSpeedRecorder::on_period(const hal_sw_plant_period_t& p, double* r)
{
    drive_status_t l;
    drive_status(&drive(), &l);
    const double t = p.t_s;
    const double w_d = to_double(l.omega_ref_rad_s);
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
    const double w_hat = to_double(l.omega_est_rad_s);
    est_ss_ += (w_hat - w) * (w_hat - w);
    // the estimated angle and the angle the estimator was given (the
    // encoder's or the flux observer's), against the rotor's, mechanical
    const double th = plant_.theta_rad();
    const double th_hat = to_double(l.theta_est_rad);
    const double th_err = wrap_pi(th_hat - th);
    th_ss_ += th_err * th_err;
    if (sig_theta_meas_ >= 0) {
        const double thm_err = wrap_pi(signals().value(sig_theta_meas_) - th);
        thm_ss_ += thm_err * thm_err;
    }
    if (sig_hfi_on_ >= 0) {
        score_injection(t, th, th_err);
    }
    // the lumped disturbance the drive estimates: everything that brakes
    // the rotor besides the viscous d w of its model (load, LuGre friction)
    const double M0 = plant_.load_torque_Nm();
    const double M0_hat = to_double(l.load_est_Nm);
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
    // the command in the drive's (estimated) d-q frame
    const double u_d = to_double(l.v1_V), u_q = to_double(l.v2_V);
    if (static_cast<double>(index()) >= kEsSteadyFrom * static_cast<double>(n_max())) {
        ud_.push_back(u_d);
        uq_.push_back(u_q);
    }
    if (has_p_) {
        score_covariance();
    }
    if (sig_p_asym_ >= 0) {
        p_asym_ = std::max(p_asym_, signals().value(sig_p_asym_));
    }
    if (l.fault_code != DRIVE_FAULT_NONE) {
        fault_ = static_cast<std::int64_t>(l.fault_code);
    }
    if (r != nullptr) {  // in kEkfSpeedColumnNames' order
        const double row[kEsNumColumns] = {t,
                                           static_cast<double>(l.mode),
                                           static_cast<double>(l.fault_code),
                                           l.saturated ? 1.0 : 0.0,
                                           w_d,
                                           w,
                                           w_hat,
                                           wrap_pi(plant_.theta_rad()),
                                           th_hat,
                                           M0,
                                           M0_hat,
                                           i_d,
                                           i_q,
                                           p.v_a_V,
                                           p.v_b_V,
                                           p.v_c_V};
        std::copy(row, row + kEsNumColumns, r);
    }
    return fault_;
}

// The HF injection: the largest angle error from 50 ms (the first
// correction of the start left out), the rotor's largest excursion from its
// start (mechanical), the injection's voltage and its current ripple (half
// the change of the true alpha-beta current from one sample to the next,
// the triangle's amplitude) while it is on.
void EkfSpeedRecorder::score_injection(double t, double th, double th_err)
{
    if (index() == 0) {
        theta0_ = th;
    }
    if (t >= kRmseSkip_s - 1e-12) {
        th_err_max_ = std::max(th_err_max_, std::fabs(th_err));
    }
    drift_max_ = std::max(drift_max_, std::fabs(wrap_pi(th - theta0_)));
    const double ia = plant_.i_a_A(), ib = plant_.i_b_A();
    if (signals().value(sig_hfi_on_) != 0.0) {
        n_hfi_on_ += 1;
        hfi_ripple_ss_ += 0.25 * ((ia - prev_ia_) * (ia - prev_ia_) + (ib - prev_ib_) * (ib - prev_ib_));
        const double ua = signals().value(sig_hfi_ua_), ub = signals().value(sig_hfi_ub_);
        hfi_u_ss_ += ua * ua + ub * ub;
    }
    prev_ia_ = ia;
    prev_ib_ = ib;
}

// The EKF's covariance: symmetric, positive definite (the eigen solver
// reads the lower triangle, which the drive lists).
void EkfSpeedRecorder::score_covariance()
{
    Eigen::Matrix<double, kEkfStates, kEkfStates> P;
    for (int i = 0; i < kEkfStates; ++i) {
        for (int j = 0; j < kEkfStates; ++j) {
            P(i, j) = signals().value(sig_p_[i][j]);
        }
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, kEkfStates, kEkfStates>> eig(P, Eigen::EigenvaluesOnly);
    const double e_min = eig.eigenvalues().minCoeff();
    p_min_eig_ = std::min(p_min_eig_, e_min);
    spd_ok_ = spd_ok_ && (sig_spd_ok_ < 0 || signals().value(sig_spd_ok_) != 0.0) && e_min > 0.0;
}

MetricList EkfSpeedRecorder::metrics(double wall_loop_s) const
{
    const std::uint64_t n_rec = index();  // every period recorded
    const double n = static_cast<double>(n_rec);
    auto rms = [](double ss, std::uint64_t k) { return k > 0 ? std::sqrt(ss / static_cast<double>(k)) : NAN; };
    const double hf_d = hf_rms(ud_, sc_.ts_s, kEsHfCutoff_Hz), hf_q = hf_rms(uq_, sc_.ts_s, kEsHfCutoff_Hz);
    double u_ss = 0.0;
    for (std::size_t k = 0; k < ud_.size(); ++k) {
        u_ss += ud_[k] * ud_[k] + uq_[k] * uq_[k];
    }
    const DriveSignals& sg = signals();
    MetricList m;
    m.emplace_back("speed_rmse_rad_s", rms(ss_, n_rmse_));
    m.emplace_back("speed_rmse_after_50ms_rad_s", rms(ss50_, n_rmse50_));
    m.emplace_back("speed_err_max_rad_s", err_max_);
    m.emplace_back("omega_est_rmse_rad_s", rms(est_ss_, n_rec));
    m.emplace_back("M0_est_rmse_Nm", rms(m0_ss_, n_rec));
    m.emplace_back("theta_est_rmse_rad", rms(th_ss_, n_rec));
    if (sig_theta_meas_ >= 0) {
        m.emplace_back("theta_meas_rmse_rad", rms(thm_ss_, n_rec));
    }
    sg.append_metric(&m, "angle_source", "angle_source");
    if (sig_hfi_on_ >= 0) {
        m.emplace_back("theta_est_err_max_rad", th_err_max_);
        m.emplace_back("position_drift_max_rad", drift_max_);
        m.emplace_back("hfi_on_fraction", n > 0 ? static_cast<double>(n_hfi_on_) / n : 0.0);
        m.emplace_back("hfi_current_ripple_rms_A", rms(hfi_ripple_ss_, n_hfi_on_));
        m.emplace_back("hfi_voltage_rms_V", rms(hfi_u_ss_, n_hfi_on_));
        // the start's polarity test: +1 kept, -1 flipped, 0 undecided (or
        // not reached); its difference of the two peaks (A; 0 until it is
        // done); the lock's mean (H1) amplitude over its last quarter (1 on
        // the d axis, L_d/L_q across it; below (1 + L_d/L_q)/2 refused)
        sg.append_metric(&m, "hfi_start_polarity", "hfi_start_polarity");
        sg.append_metric(&m, "hfi_start_polarity_diff_A", "hfi_start_polarity_diff_A");
        sg.append_metric(&m, "hfi_start_lock_amp", "hfi_start_lock_amp");
    }
    m.emplace_back("voltage_hf_rms_V", std::sqrt(hf_d * hf_d + hf_q * hf_q));
    m.emplace_back("voltage_rms_V", ud_.empty() ? 0.0 : std::sqrt(u_ss / static_cast<double>(ud_.size())));
    if (has_p_) {
        m.emplace_back("ekf_p_min_eig", p_min_eig_);
    }
    if (sig_p_asym_ >= 0) {
        m.emplace_back("ekf_p_asym_max", p_asym_);
    }
    if (has_p_) {
        m.emplace_back("ekf_spd_ok", static_cast<std::int64_t>(spd_ok_ ? 1 : 0));
    }
    // the EKF's Q and R diagonals it ran with (the design's or [paper002]
    // ekf_q, ekf_r), per sample
    for (const char* k :
         {"ekf_q_id", "ekf_q_iq", "ekf_q_theta", "ekf_q_omega", "ekf_q_M0", "ekf_r_id", "ekf_r_iq", "ekf_r_theta"}) {
        sg.append_metric(&m, k, k);
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
