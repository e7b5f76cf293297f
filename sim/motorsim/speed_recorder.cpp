#include "motorsim/speed_recorder.h"

#include <algorithm>
#include <cmath>

#include "mc_convert.h"

namespace mcsim {
namespace {
constexpr double kRadSToRpm = 30.0 / 3.14159265358979323846;
constexpr double kPi = 3.14159265358979323846;
// the metric definitions of speed_recorder.h
constexpr double kSettleAfter_s = 0.5;
constexpr double kLockTol_rad = 5.0 * kPi / 180.0;
constexpr double kLockHold_s = 0.05;
}  // namespace

const char* const kSpeedColumnNames[kSpNumColumns] = {
    "t_s",         "mode",        "omega_ref_rad_s", "omega_rad_s", "omega_est_rad_s", "theta_e_rad",
    "theta_e_est_rad", "theta_e_err_rad", "load_Nm", "load_est_Nm", "i_a_A",       "i_b_A",
    "i_c_A",       "v_alpha_V",   "v_beta_V",        "v_a_V",       "v_b_V",           "v_c_V",
    "estimate_quality", "estimate_valid", "fault"};

SpeedRecorder::SpeedRecorder(const Scenario& sc, const PmPlant& plant, const drive_t& drive, bool record_rows)
    : RunRecorder(sc, plant, drive, kSpeedColumnNames, kSpNumColumns, record_rows)
{
    for (const auto& p : sc.speed_points) {
        events_.push_back(p.first);
    }
    for (const LoadStep& s : sc.load) {
        events_.push_back(s.t_s);
        if (s.ramp_s > 0.0) {
            events_.push_back(s.t_s + s.ramp_s);
        }
    }
    std::sort(events_.begin(), events_.end());
}

double SpeedRecorder::omega_ref(double t_s, double* slope) const
{
    const auto& p = sc_.speed_points;
    *slope = 0.0;
    if (t_s <= p.front().first) {
        return p.front().second;
    }
    for (std::size_t k = 0; k + 1 < p.size(); ++k) {
        if (t_s < p[k + 1].first) {
            *slope = (p[k + 1].second - p[k].second) / (p[k + 1].first - p[k].first);
            return p[k].second + *slope * (t_s - p[k].first);
        }
    }
    return p.back().second;
}

std::int64_t SpeedRecorder::on_period(const hal_sw_plant_period_t& p, double* r)
{
    drive_status_t tm;
    drive_status(&drive(), &tm);
    const double t = p.t_s;
    double slope = 0.0;
    double w_ref = omega_ref(t, &slope);
    if (drive_ref()) {
        w_ref = to_double(tm.omega_ref_rad_s);
        slope = to_double(tm.accel_ref_rad_s2);
    }
    const double w = plant_.omega_rad_s();
    const double err_rpm = std::fabs(w - w_ref) * kRadSToRpm;
    const double th_e = wrap_pi(static_cast<double>(plant_.motor().n_p) * plant_.theta_rad());
    const double th_e_est = to_double(tm.theta_e_est_rad);
    const double th_err = wrap_pi(th_e_est - th_e);
    const double load = plant_.load_torque_Nm() + plant_.motor().fv_Nms_per_rad * w;
    const double load_est = to_double(tm.load_est_Nm);
    const bool valid = tm.estimate_valid && p.control_called;

    score_speed_error(t, w_ref, slope, err_rpm, std::fabs(load_est - load));
    score_lock(t, valid, th_err);
    double i_ph[3] = {0.0, 0.0, 0.0};
    plant_.phase_currents(i_ph);
    for (int k = 0; k < plant_.n_phases(); ++k) {
        i_max_ = std::max(i_max_, std::fabs(i_ph[k]));
    }
    v_max_ = std::max({v_max_, std::fabs(p.v_a_V), std::fabs(p.v_b_V), std::fabs(p.v_c_V)});
    if (tm.state == SUP_STATE_CLOSED_LOOP) {
        n_closed_ += 1;
        if (first_closed_t_ < 0.0) {
            first_closed_t_ = t;
        }
    }
    if (tm.fault_code != DRIVE_FAULT_NONE) {
        fault_ = static_cast<std::int64_t>(tm.fault_code);
    }
    if (r != nullptr) {  // in kSpeedColumnNames' order
        const double row[kSpNumColumns] = {t,
                                           static_cast<double>(tm.mode),
                                           w_ref,
                                           w,
                                           to_double(tm.omega_est_rad_s),
                                           th_e,
                                           th_e_est,
                                           th_err,
                                           load,
                                           load_est,
                                           i_ph[0],
                                           i_ph[1],
                                           i_ph[2],
                                           to_double(tm.v_alpha_V),
                                           to_double(tm.v_beta_V),
                                           p.v_a_V,
                                           p.v_b_V,
                                           p.v_c_V,
                                           to_double(tm.estimate_quality),
                                           valid ? 1.0 : 0.0,
                                           static_cast<double>(tm.fault_code)};
        std::copy(row, row + kSpNumColumns, r);
    }
    return static_cast<std::int64_t>(tm.fault_code);
}

// The speed error err_rpm at t against w_ref (its slope), the load
// estimate's error load_err: the settled windows (from kSettleAfter_s after
// each corner or load change), the ramps (from kSettleAfter_s after their
// start), the whole run.
void SpeedRecorder::score_speed_error(double t, double w_ref, double slope, double err_rpm, double load_err)
{
    // time since the last corner or load change, and the segment type
    const auto it = std::upper_bound(events_.begin(), events_.end(), t + 1e-12);
    const double since = (it == events_.begin()) ? t : t - *(it - 1);
    const bool settled_time = since >= kSettleAfter_s - 1e-12;
    err_max_ = std::max(err_max_, err_rpm);
    err_ss_ += err_rpm * err_rpm;
    if (settled_time) {
        if (slope == 0.0) {
            settled_max_ = std::max(settled_max_, err_rpm);
            if (w_ref != 0.0) {
                settled_moving_max_ = std::max(settled_moving_max_, err_rpm);
            }
            load_settled_max_ = std::max(load_settled_max_, load_err);
        }
    }
    // ramps: from 0.5 s after the start of the ramp (corners only)
    if (slope != 0.0) {
        double ramp_start = 0.0;
        for (const auto& c : sc_.speed_points) {
            if (c.first <= t) {
                ramp_start = c.first;
            }
        }
        if (t - ramp_start >= kSettleAfter_s - 1e-12) {
            ramp_max_ = std::max(ramp_max_, err_rpm);
        }
    }
}

// The lock (a run of kLockHold_s with the estimate valid and the angle
// error below kLockTol_rad) and the angle error after it.
void SpeedRecorder::score_lock(double t, bool valid, double th_err)
{
    if (lock_t_ < 0.0) {
        if (valid && std::fabs(th_err) < kLockTol_rad) {
            if (lock_run_ == 0) {
                lock_run_start_ = t;
            }
            lock_run_ += 1;
            if (static_cast<double>(lock_run_) * sc_.ts_s >= kLockHold_s - 1e-12) {
                lock_t_ = lock_run_start_;
            }
        } else {
            lock_run_ = 0;
        }
    } else {
        theta_max_deg_ = std::max(theta_max_deg_, std::fabs(th_err) * 180.0 / kPi);
    }
}

MetricList SpeedRecorder::metrics(double wall_loop_s) const
{
    const std::uint64_t n_rec = index();  // every period recorded
    const bool locked = lock_t_ >= 0.0;
    MetricList m;
    m.emplace_back("speed_err_settled_max_rpm", settled_max_);
    m.emplace_back("speed_err_settled_moving_max_rpm", settled_moving_max_);
    m.emplace_back("speed_err_ramp_max_rpm", ramp_max_);
    m.emplace_back("speed_err_rms_rpm", n_rec > 0 ? std::sqrt(err_ss_ / static_cast<double>(n_rec)) : NAN);
    m.emplace_back("speed_err_max_rpm", err_max_);
    m.emplace_back("load_est_err_settled_nm", load_settled_max_);
    m.emplace_back("lock_time_s", locked ? lock_t_ : NAN);
    m.emplace_back("theta_est_max_deg_e", locked ? theta_max_deg_ : NAN);
    m.emplace_back("first_closed_loop_t_s", first_closed_t_);
    m.emplace_back("closed_loop_fraction", n_rec > 0 ? static_cast<double>(n_closed_) / static_cast<double>(n_rec) : 0.0);
    m.emplace_back("max_abs_current_A", i_max_);
    m.emplace_back("max_abs_voltage_V", v_max_);
    m.emplace_back("i_max_A", sc_.i_max_A);
    m.emplace_back("final_omega_rad_s", plant_.omega_rad_s());
    m.emplace_back("fault", fault_);
    const flight_recorder_t* fr = drive_recorder(&drive());
    if (fr != nullptr) {
        m.emplace_back("fault_first", static_cast<std::int64_t>(fr->fault));
        m.emplace_back("fault_first_t_s", fr->frozen ? static_cast<double>(fr->fault_tick) * sc_.ts_s : -1.0);
        m.emplace_back("fault_events", static_cast<std::int64_t>(fr->events));
    } else {  // a drive without a flight recorder: its latched fault only
        m.emplace_back("fault_first", fault_);
        m.emplace_back("fault_first_t_s", -1.0);
        m.emplace_back("fault_events", static_cast<std::int64_t>(fault_ != 0 ? 1 : 0));
    }
    m.emplace_back("relocks", static_cast<std::int64_t>(0));  // the speed drive has no re-lock
    append_run_tail(&m, wall_loop_s, false);
    return m;
}

}  // namespace mcsim
