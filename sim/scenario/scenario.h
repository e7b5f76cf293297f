// scenario.h - the simulator's scenario files (TOML, format documented in
// sim/scenarios/README.md): plant, sensor, supply, load, trajectory and the
// optional design overrides of the drive. load_scenario() validates the
// whole file (and the motor file it references) before anything runs, and
// reports the first problem as one line naming the file and the key.
#ifndef MCSIM_SCENARIO_SCENARIO_H
#define MCSIM_SCENARIO_SCENARIO_H

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "model/current_sensor.h"
#include "model/fault_injection.h"
#include "model/inverter.h"
#include "model/board_emulation.h"
#include "model/encoder.h"
#include "model/load_profile.h"
#include "model/motor_params.h"
#include "model/reference.h"
#include "model/pm_plant.h"

namespace mcsim {

// what() is "FILE: KEY: reason" (or "FILE: reason" / "FILE:LINE:COL: reason"
// for errors not tied to a key); callers prefix "error: ". It is one line:
// control characters that a key, a value or a path of the file brings into
// it (a quoted key "a\nb", a NUL) are written as \n, \r, \xNN.
class ScenarioError : public std::runtime_error {
public:
    explicit ScenarioError(const std::string& what) : std::runtime_error(one_line(what)) {}
    explicit ScenarioError(const char* what) : ScenarioError(std::string(what)) {}

private:
    static std::string one_line(const std::string& s)
    {
        static const char kHex[] = "0123456789ABCDEF";
        std::string out;
        out.reserve(s.size());
        for (const char ch : s) {
            const auto c = static_cast<unsigned char>(ch);
            if (c == '\n') {
                out += "\\n";
            } else if (c == '\r') {
                out += "\\r";
            } else if ((c < 0x20 && c != '\t') || c == 0x7F) {
                out += "\\x";
                out += kHex[c >> 4];
                out += kHex[c & 0xF];
            } else {
                out += ch;
            }
        }
        return out;
    }
};

constexpr double kRpmToRadS = 3.14159265358979323846 / 30.0;

// RK4 sub-steps per control sample when [run] substeps is not given.
constexpr int kDefaultSubsteps = PmPlant::kDefaultSubsteps;
// [run] substeps is at most this; a motor that needs more is refused.
constexpr int kMaxSubsteps = 1000;
// The plant's RK4 sub-step h must keep h * (fastest rate of the motor) at or
// below this (RK4's real-axis stability limit is 2.78; 1 keeps it accurate).
constexpr double kRk4StepTimesRateMax = 1.0;

// One [expect] entry: the run fails (motorsim exit 4) if the metric is
// above max, below min, or not a number.
struct Expectation {
    std::string metric;
    bool has_max = false, has_min = false;
    double max = 0.0, min = 0.0;
};

struct Scenario {
    std::string path;         // as given by the user
    std::string stem;         // file name without extension: output names
    std::string description;

    // [run]
    double duration_s = 0.0;
    double ts_s = 0.0;
    std::uint64_t seed = 1;
    int substeps = kDefaultSubsteps;
    bool substeps_given = false;  // [run] substeps was in the file
    double theta0_rad = 0.0;  // initial rotor angle; the drive assumes 0
    double omega0_rad_s = 0.0;  // initial rotor speed (a drive's table may set it: [paper002] omega0_rad_s)
    // computation delay of the drive, fraction of Ts in [0, 1]: its voltage
    // acts that much after the currents were sampled (hal_sw_plant.h)
    double compute_delay_samples = 0.0;

    // [motor] (plant) and [drive_model] (what the drive is designed for)
    std::string motor_file;   // resolved path of the motor file
    MotorParams motor;
    MotorParams drive_model;

    // [supply], [limits]
    double v_max_V = 0.0;
    double i_max_A = 0.0;
    double i_trip_A = 0.0;
    double omega_lim_rad_s = 0.0;
    double i_open_loop_A = 0.0;  // 0 = the design default (i_max_A)
    int i_trip_samples = 1;      // [limits] i_trip_samples: consecutive samples beyond i_trip_A that trip
    int los_relock = 0;          // [protection] loss_of_sync = "relock"

    // [design]: switches of drive_design_input_t; -1 = the design default.
    // ([design], [protection], [trajectory], [gains] and [bounds] are read
    // by paper 000's host part, sim/host_drives/paper000_host.cpp.)
    int load_feedforward = -1;
    int identify_rl = -1; // [design] identify_rl; -1: design default
    int align_rotor = -1; // [design] align_rotor; -1: design default
    int identify_k = -1;  // [design] identify_k; -1: design default

    // Samples the drive runs before t = 0 (the position drive's rotor
    // alignment, paper000_drive_t.align_ticks): set by whoever designs the drive,
    // before the Rig is built. The run starts at t = -pre_ticks * ts_s;
    // duration_s counts from t = 0.
    std::uint32_t pre_ticks = 0;
    int gain_design = -1; // [design] gain_design: 0 continuous, 1 discrete; -1: design default
    int control_law = -1; // [design] control_law: 0 twisting, 1 load_angle; -1: design default

    // A speed drive's reference (profile_rpm of [speed] or [sensored_foc]),
    // and [speed]'s choices (the paper-001 speed drive)
    std::vector<std::pair<double, double>> speed_points;  // (t [s], w [rad/s]) corners
    struct {
        double gamma = 0.0, a1 = 0.0, a2 = 0.0, r_ohm = 0.0;  // 0: the design's default
        double handover_sweep_rad = 0.0, fit_det_min = 0.0, blend_tau_s = 0.0;
        double probe_s = -1.0;  // start-up probe [s]; 0: none; < 0: the design's default
        bool identify = false;  // commissioning run (R, L, Phi) before the run
        bool track_resistance = false;  // R of the flux observer tracked on line
        int estimator = 0;      // paper001_config_t.estimator: 0 flux (paper 001), 1 back_emf (paper 000)
    } speed_gains;

    // [paper002] (paper 002's cascaded speed drive of an IPMSM on an
    // encoder): the controller, disturbance compensation, the reference
    // w_d (w0 until t0, a C^2 polynomial to w1 on [t0, t1], held) and the
    // plant's initial speed w(0)
    struct {
        int controller = 0;        // p002_controller_t: 0 sosmc, 1 htsmc
        bool compensate = true;    // disturbance compensation (DC)
        double t0_s = 0.2, t1_s = 0.4, omega_final_rad_s = 100.0;
        double omega0_rad_s = 0.0; // the plant's w(0) (the EKF starts at 0)
        double omega_start_rad_s = 0.0; // the reference before t0_s (its polynomial's w0)
        int estimator = 0;         // p002_angle_source_t: 0 the encoder, 1 paper 001's flux observer, 2 HF injection + flux observer
        bool iron_model = false;      // estimator 1, 2: the active flux with the motor's saturation ([motor] i_sat_A)
        bool hfi_find_angle = false;  // estimator 2: the start angle unknown, found by the drive (lock, polarity test)
        double ekf_q[5] = {0, 0, 0, 0, 0};  // the EKF's Q diagonal per sample (all 0: the design's)
        double ekf_r[3] = {0, 0, 0};        // its R diagonal (all 0: the design's)
    } ipmsm;

    // The drive: [drive] kind, or the drive whose table the scenario has
    // ([trajectory], [speed], [paper002]); a name of the host registry
    // (sim/host_drives/host_drive.h) and of the firmware's. drive_table is
    // the table its keys are in; a host part that parses its own table
    // puts them into speed_points and drive_params.
    std::string drive_kind;
    std::string drive_table;
    std::vector<std::pair<std::string, double>> drive_params;  // (key, value) of [<kind>], in file order

    std::vector<Expectation> expect;  // [expect], in file order

    SensorParams sensor;
    std::vector<LoadStep> load;
    FaultInjection faults;  // [faults]: none unless given
    BoardParams board;      // [board]: defaults (DS1104-like) unless given
    EncoderParams encoder;  // [encoder]: none unless given
    bool board_given = false;
    // [inverter]: the PWM inverter of an MCU board (model/inverter.h)
    // instead of the amplifier model; absent: the amplifier (today's plant)
    InverterParams inverter;
    bool inverter_given = false;
    std::string inverter_file;         // resolved path of [inverter] file, or ""
    bool inverter_compensation = true; // [inverter] compensation: the drive's dead-time compensation on
    double compensation_dead_time_s = -1.0; // [inverter] compensation_dead_time_s: the drive's belief; < 0: the plant's
    std::vector<Segment> segments;  // [[trajectory.segments]]

    // [gains] and [bounds]: (field name, value) in file order; names are
    // fields of drive_gain_override_t and drive_design_input_t.
    std::vector<std::pair<std::string, double>> gains;
    std::vector<std::pair<std::string, double>> bounds;

    // Samples of the whole run: pre_ticks, then round(duration_s / ts_s).
    std::uint32_t n_ticks() const;
    // Time of the run's first sample: -pre_ticks * ts_s.
    double t_start_s() const { return -static_cast<double>(pre_ticks) * ts_s; }
};

// Throws ScenarioError on any problem.
Scenario load_scenario(const std::string& path);

// Every table's keys as the parser knows them, (table, keys): its own
// tables, "top" (the top level), "motor_file" (sim/motors/*.toml), and each
// drive's tables from its host part (HostDrive keys and extra_keys). What
// sim/scenarios/README.md documents is checked against it (ctest
// docs.scenario_keys).
std::vector<std::pair<std::string, std::vector<std::string>>> scenario_keys();

// Reads a motor file on its own (keys as in sim/motors/*.toml).
MotorParams load_motor_file(const std::string& path);

}  // namespace mcsim

#endif  // MCSIM_SCENARIO_SCENARIO_H
