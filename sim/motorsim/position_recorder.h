// position_recorder.h - the "position" scoring of the one recorder
// (motorsim/run_recorder.h): the per-sample log and metrics of a position
// drive's run against the scenario's [trajectory] (paper 000's section 5).
// One on_period() per control period: the true plant state at the sampling
// instant, the drive's status of the same sample (its reference, its
// estimates, its mode) and, where a metric needs them, its signals by name
// (drives/drive.h): the current observer's i_f_est_A, i_g_est_A, the model
// it ended with (model_R_ohm, model_L_H, model_K_V_s, k_id_state) and its
// relocks; a metric whose signal the drive lacks is left out (relocks then
// the status's count). One preallocated row (unless built without a log);
// no allocation and no I/O per sample.
//
// Columns (then the drive's signals): t_s, mode, the drive's reference
// theta_ref_rad, omega_ref_rad_s, accel_ref_rad_s2, the true theta_rad
// (from the equilibrium the alignment found), its estimate, the true
// omega, acceleration and load torque with their estimates, the true
// phase currents i_a_A, i_b_A and the sensor's i_a_meas_A, i_b_meas_A, the
// true currents i_f_A, i_g_A and back-EMFs e_f_V, e_g_V in the frame at the
// drive's reference angle n_p theta_ref (paper 000 eqs. (6), (23): what
// its (f-g) observer estimates), the applied phase voltages, the true load
// angle delta_theta_rad = theta - theta_ref, fault.
#ifndef MCSIM_MOTORSIM_POSITION_RECORDER_H
#define MCSIM_MOTORSIM_POSITION_RECORDER_H

#include <cmath>
#include <cstdint>
#include <vector>

#include "hal_sw_plant.h"
#include "model/pm_plant.h"
#include "model/reference.h"
#include "motorsim/run_recorder.h"
#include "scenario/scenario.h"

namespace mcsim {

// CSV columns, in file order (names in kPositionColumnNames).
enum PositionColumn : int {
    kPoT,
    kPoMode,
    kPoThetaRef,
    kPoOmegaRef,
    kPoAccelRef,
    kPoTheta,
    kPoThetaEst,
    kPoOmega,
    kPoOmegaEst,
    kPoAccel,
    kPoAccelEst,
    kPoLoad,
    kPoLoadEst,
    kPoIa,
    kPoIb,
    kPoIaMeas,
    kPoIbMeas,
    kPoIf,
    kPoIg,
    kPoEf,
    kPoEg,
    kPoVa,
    kPoVb,
    kPoDeltaTheta,
    kPoFault,
    kPoNumColumns
};

extern const char* const kPositionColumnNames[kPoNumColumns];

class PositionRecorder : public RunRecorder {
public:
    PositionRecorder(const Scenario& sc, const PmPlant& plant, const drive_t& drive, bool record_rows);
    MetricList metrics(double wall_loop_s) const override;

private:
    // The true plant and the drive's view of one period.
    struct Sample {
        double theta, omega, i_a, i_b;  // true (theta from the alignment's equilibrium)
        double theta_ref;               // the drive's reference
        double i_f, i_g, e_f, e_g;      // true, in the frame at n_p theta_ref
        double dtheta;                  // true theta - theta_ref
        double theta_est, omega_est;    // the drive's estimates
        bool has_obs;                   // the drive shows its current observer:
        double i_f_hat, i_g_hat;        // its currents (0 without)
    };

    std::int64_t on_period(const hal_sw_plant_period_t& p, double* r) override;
    void find_offset();
    Sample sample(const drive_status_t& tl) const;
    void write_row(const hal_sw_plant_period_t& p, const drive_status_t& tl, const Sample& q, double* r) const;
    // the metrics' accumulators of a period from t = 0
    void score(const hal_sw_plant_period_t& p, const drive_status_t& tl, const Sample& q);

    double drive_theta_ref_last_ = 0.0;

    const Reference ref_;  // the scenario's [trajectory], from 0 rad
    double n_p_;
    double K_;  // true plant, for e_f, e_g of eq. (23)
    double omega_lim_rad_s_;
    int sig_if_est_, sig_ig_est_;  // the drive's current observer (-1: none)

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

#endif  // MCSIM_MOTORSIM_POSITION_RECORDER_H
