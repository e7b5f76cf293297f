#include "motorsim/drive_runs/paper000_recorder.h"

#include <algorithm>
#include <cmath>

#include "mc_convert.h"

namespace mcsim {

namespace {
// The time a load change is given before the tracking error counts in
// theta_track_load_settled_max_rad: 100 ms, the recovery time the load-step
// requirement of the paper-000 issue states ("back within 0.02 rad in
// 100 ms").
constexpr double kLoadSettleS = 0.1;
}  // namespace

const char* const kColumnNames[kNumColumns] = {
    "t_s",       "mode",        "theta_ref", "omega_ref",       "accel_ref",  "theta",     "theta_est",
    "omega",     "omega_est",   "accel",     "accel_est",       "load_true_Nm", "load_est_Nm", "i_a",
    "i_b",       "i_a_meas",    "i_b_meas",  "i_f",             "i_g",        "i_f_hat",   "i_g_hat",
    "d_f",       "d_g",         "d_f_hat",   "d_g_hat",         "v_a",        "v_b",       "v_f",
    "v_g",       "delta_theta_est", "jump_count", "delta_theta", "i_f_ref",   "i_g_ref",   "fault",
};

Paper000Recorder::Paper000Recorder(const Scenario& sc, const PmPlant& plant, const paper000_drive_t& drive,
                                   bool record_rows)
    : RunRecorder(sc, plant, kColumnNames, kNumColumns, record_rows),
      drive_(drive),
      ref_(sc.segments, 0.0),
      n_p_(static_cast<double>(plant.motor().n_p)),
      K_over_L_(plant.motor().K_Nm_per_A / plant.motor().L_H),
      inv_L_drive_(1.0 / sc.drive_model.L_H),
      omega_lim_rad_s_(sc.omega_lim_rad_s)
{
}

std::int64_t Paper000Recorder::on_period(const hal_sw_plant_period_t& p, double* r)
{
    paper000_telemetry_t tl;
    paper000_drive_get_telemetry(&drive_, &tl);
    const PmPlant::State& x = plant_.state();
    // Before t = 0 the drive aligns the rotor (sc.pre_ticks); from t = 0 on,
    // angles are relative to the equilibrium it found: the nearest multiple
    // of the tooth pitch to where the rotor then rests (the drive's 0; a
    // sensorless stepper cannot know which of its n_p equilibria it is on).
    const bool before_start = p.t_s < -0.5 * sc_.ts_s;
    if (!before_start && !offset_known_) {
        offset_known_ = true;
        if (sc_.pre_ticks > 0) {
            const double pitch = 2.0 * 3.14159265358979323846 / n_p_;
            const double th0 = ref_.eval(0.0).theta_rad;
            offset_rad_ = std::round((x[PmPlant::kTheta] - th0) / pitch) * pitch;
            align_residual_rad_ = x[PmPlant::kTheta] - offset_rad_ - th0;
            for (std::uint64_t k = 0; k < index(); ++k) {
                double* earlier = row_at(k);
                if (earlier == nullptr) {
                    break;  // no log
                }
                earlier[kColTheta] -= offset_rad_;
                earlier[kColDeltaTheta] -= offset_rad_;
            }
        }
    }
    const double theta = x[PmPlant::kTheta] - offset_rad_;
    const double omega = x[PmPlant::kOmega];
    const double i_a = x[PmPlant::kIa];
    const double i_b = x[PmPlant::kIb];

    const double theta_ref = to_double(tl.theta_ref_rad);
    // True currents in the drive's (f-g) frame, eq. (6), so that they compare
    // one to one with the observer's i_f_hat, i_g_hat.
    const double er = n_p_ * theta_ref;
    const double sr = std::sin(er);
    const double cr = std::cos(er);
    const double i_f = cr * i_a + sr * i_b;
    const double i_g = -sr * i_a + cr * i_b;
    // True back-EMF disturbances, eq. (23), with dtheta = theta - theta_r;
    // sin/cos(n_p dtheta) by angle subtraction from the plant's cached
    // sin/cos(n_p theta).
    const double dtheta = theta - theta_ref;
    const double se = plant_.sin_elec();
    const double ce = plant_.cos_elec();
    const double d_f = K_over_L_ * omega * (se * cr - ce * sr);
    const double d_g = -K_over_L_ * omega * (ce * cr + se * sr);

    const double theta_est = to_double(tl.theta_est_rad);
    const double omega_est = to_double(tl.omega_est_rad_s);
    const double i_f_hat = to_double(tl.i_f_hat_A);
    const double i_g_hat = to_double(tl.i_g_hat_A);

    if (r != nullptr) {
        r[kColT] = p.t_s;
        r[kColMode] = static_cast<double>(tl.mode);
        r[kColThetaRef] = theta_ref;
        r[kColOmegaRef] = to_double(tl.omega_ref_rad_s);
        r[kColAccelRef] = to_double(tl.accel_ref_rad_s2);
        r[kColTheta] = theta;
        r[kColThetaEst] = theta_est;
        r[kColOmega] = omega;
        r[kColOmegaEst] = omega_est;
        r[kColAccel] = plant_.accel_rad_s2();
        r[kColAccelEst] = to_double(tl.accel_est_rad_s2);
        r[kColLoadTrue] = plant_.load_torque_Nm();
        r[kColLoadEst] = to_double(tl.load_est_Nm);
        r[kColIa] = i_a;
        r[kColIb] = i_b;
        r[kColIaMeas] = p.i_a_meas_A;
        r[kColIbMeas] = p.i_b_meas_A;
        r[kColIf] = i_f;
        r[kColIg] = i_g;
        r[kColIfHat] = i_f_hat;
        r[kColIgHat] = i_g_hat;
        r[kColDf] = d_f;
        r[kColDg] = d_g;
        r[kColDfHat] = to_double(tl.e_f_hat_V) * inv_L_drive_;
        r[kColDgHat] = to_double(tl.e_g_hat_V) * inv_L_drive_;
        r[kColVa] = p.v_a_V;
        r[kColVb] = p.v_b_V;
        r[kColVf] = to_double(tl.v_f_V);
        r[kColVg] = to_double(tl.v_g_V);
        r[kColDeltaThetaEst] = to_double(tl.delta_theta_est_rad);
        r[kColJumpCount] = static_cast<double>(tl.jump_count);
        r[kColDeltaTheta] = dtheta;
        r[kColIfRef] = to_double(tl.i_f_ref_A);
        r[kColIgRef] = to_double(tl.i_g_ref_A);
        r[kColFault] = static_cast<double>(tl.fault);
    }

    // --- metrics: scored against the scenario's own reference -----------
    // The alignment before t = 0 counts for the current, voltage and fault
    // only: the reference holds then, and the rotor is being moved onto it.
    max_abs_current_ = std::max(max_abs_current_, std::max(std::fabs(i_a), std::fabs(i_b)));
    max_abs_voltage_ = std::max(max_abs_voltage_, std::max(std::fabs(p.v_a_V), std::fabs(p.v_b_V)));
    if (tl.fault != DRIVE_FAULT_NONE) {
        fault_ = static_cast<std::int64_t>(tl.fault);
    }
    if (before_start) {
        ++n_pre_;
        return static_cast<std::int64_t>(tl.fault);
    }
    RefPoint ref = ref_.eval(p.t_s);
    if (drive_ref()) {
        ref.theta_rad = theta_ref;
        ref.omega_rad_s = to_double(tl.omega_ref_rad_s);
    }
    drive_theta_ref_last_ = theta_ref;
    const double track = std::fabs(theta - ref.theta_rad);
    const double est = std::fabs(theta - theta_est);
    const double w_err = std::fabs(omega - omega_est);
    theta_track_max_all_ = std::max(theta_track_max_all_, track);
    ref_mismatch_max_ = std::max(ref_mismatch_max_, std::fabs(theta_ref - ref.theta_rad));
    if (std::max(std::fabs(p.v_a_cmd_V), std::fabs(p.v_b_cmd_V)) >= sc_.v_max_V) {
        ++n_vsat_;
    }
    const int mode = static_cast<int>(tl.mode);
    if (mode == DRIVE_MODE_CLOSED_LOOP) {
        ++n_mode_closed_;
        if (first_switch_t_ < 0.0) {
            first_switch_t_ = p.t_s;
        }
    }
    if (last_mode_ >= 0 && mode != last_mode_) {
        ++mode_switches_;
    }
    last_mode_ = mode;
    // [load] changes complete by now (a step at t_s, a ramp at t_s + ramp_s);
    // settled: kLoadSettleS after the last one, and the next not begun
    while (load_next_ < sc_.load.size() && sc_.load[load_next_].t_s + sc_.load[load_next_].ramp_s <= p.t_s) {
        load_done_t_ = sc_.load[load_next_].t_s + sc_.load[load_next_].ramp_s;
        ++load_next_;
    }
    const bool load_settled = load_done_t_ >= 0.0 && p.t_s - load_done_t_ >= kLoadSettleS &&
                              (load_next_ >= sc_.load.size() || sc_.load[load_next_].t_s > p.t_s);
    // after a load change, every sample counts, open loop too: the rotor
    // must be back on the reference whatever the drive's mode
    if (load_settled) {
        // fmax: the first one replaces the NaN of "no such sample"
        theta_track_load_settled_max_ = std::fmax(theta_track_load_settled_max_, track);
    }
    // "Closed loop" by the reference speed, as in section 5.4, so that the
    // open/closed switch transients count against the drive.
    if (std::fabs(ref.omega_rad_s) >= omega_lim_rad_s_) {
        ++n_closed_;
        theta_track_max_ = std::max(theta_track_max_, track);
        theta_est_max_ = std::max(theta_est_max_, est);
        current_obs_max_ = std::max(current_obs_max_, std::max(std::fabs(i_f - i_f_hat), std::fabs(i_g - i_g_hat)));
        omega_est_max_ = std::max(omega_est_max_, w_err);
        theta_track_ss_ += track * track;
        theta_est_ss_ += est * est;
        omega_est_ss_ += w_err * w_err;
        if (std::fabs(ref.omega_rad_s) >= 15.0) {
            ++n_peak_;
            omega_est_peak_max_ = std::max(omega_est_peak_max_, w_err);
        }
    }
    // NaN anywhere must not read as a perfect run: max() ignores NaN.
    if (!std::isfinite(theta) || !std::isfinite(theta_est) || !std::isfinite(i_f_hat)) {
        theta_track_max_ = theta_est_max_ = current_obs_max_ = theta_track_load_settled_max_ = NAN;
    }
    return static_cast<std::int64_t>(tl.fault);
}

MetricList Paper000Recorder::metrics(double wall_loop_s) const
{
    const double nc = static_cast<double>(n_closed_);
    const double n_run = static_cast<double>(index() - n_pre_);  // samples from t = 0
    auto rms = [nc](double ss) { return nc > 0.0 ? std::sqrt(ss / nc) : 0.0; };
    MetricList m;
    m.emplace_back("theta_track_max_rad", theta_track_max_);
    m.emplace_back("theta_track_rms_rad", rms(theta_track_ss_));
    m.emplace_back("theta_est_max_rad", theta_est_max_);
    m.emplace_back("theta_est_rms_rad", rms(theta_est_ss_));
    m.emplace_back("current_obs_max_a", current_obs_max_);
    m.emplace_back("omega_est_peak_max_rad_s", n_peak_ > 0 ? omega_est_peak_max_ : NAN);
    m.emplace_back("omega_est_max_rad_s", omega_est_max_);
    m.emplace_back("omega_est_rms_rad_s", rms(omega_est_ss_));
    const double theta_end = drive_ref() ? drive_theta_ref_last_ : ref_.final_theta_rad();
    m.emplace_back("final_theta_err_rad", std::fabs(plant_.theta_rad() - offset_rad_ - theta_end));
    m.emplace_back("final_theta_rad", plant_.theta_rad() - offset_rad_);
    {
        paper000_telemetry_t tl;
        paper000_drive_get_telemetry(&drive_, &tl);
        m.emplace_back("model_R_ohm", to_double(tl.R_model_ohm));
        m.emplace_back("model_L_H", to_double(tl.L_model_H));
        m.emplace_back("model_K_V_s", to_double(tl.K_model_V_s));
        m.emplace_back("k_id_state", static_cast<std::int64_t>(tl.k_id_state));
    }
    m.emplace_back("align_offset_rad", offset_rad_);
    m.emplace_back("align_residual_rad", align_residual_rad_);
    m.emplace_back("align_time_s", static_cast<double>(sc_.pre_ticks) * sc_.ts_s);
    m.emplace_back("closed_loop_fraction", n_run > 0 ? nc / n_run : 0.0);
    m.emplace_back("drive_closed_loop_fraction", n_run > 0 ? static_cast<double>(n_mode_closed_) / n_run : 0.0);
    m.emplace_back("first_closed_loop_t_s", first_switch_t_);
    m.emplace_back("mode_switches", mode_switches_);
    m.emplace_back("theta_track_max_all_rad", theta_track_max_all_);
    m.emplace_back("theta_track_load_settled_max_rad", theta_track_load_settled_max_);
    m.emplace_back("ref_mismatch_max_rad", ref_mismatch_max_);
    m.emplace_back("max_abs_current_A", max_abs_current_);
    m.emplace_back("max_abs_voltage_V", max_abs_voltage_);
    m.emplace_back("voltage_saturated_fraction", n_run > 0 ? static_cast<double>(n_vsat_) / n_run : 0.0);
    m.emplace_back("fault", fault_);
    // the flight recorder's first fault (a recovered one included) and the
    // count of faults and re-locks (firmware/supervisor/flight_recorder.h)
    const flight_recorder_t* fr = paper000_drive_flight_recorder(&drive_);
    m.emplace_back("fault_first", static_cast<std::int64_t>(fr->fault));
    m.emplace_back("fault_first_t_s",
                   fr->frozen ? sc_.t_start_s() + static_cast<double>(fr->fault_tick) * sc_.ts_s : -1.0);
    m.emplace_back("fault_events", static_cast<std::int64_t>(fr->events));
    m.emplace_back("relocks", static_cast<std::int64_t>(drive_.relocks));
    append_run_tail(&m, wall_loop_s, true);
    return m;
}

}  // namespace mcsim
