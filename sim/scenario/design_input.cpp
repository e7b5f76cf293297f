#include "scenario/design_input.h"

#include <algorithm>
#include <iterator>
#include <cmath>
#include <cstring>

namespace mcsim {
namespace {

struct GainField {
    const char* key;
    double drive_gain_override_t::*member;
};

struct BoundField {
    const char* key;
    double drive_design_input_t::*member;
};

// Keep in step with drive_gain_override_t; the scenario parser accepts
// exactly these names.
const GainField kGainFields[] = {
    {"emf_alpha_A_s2", &drive_gain_override_t::emf_alpha_A_s2},
    {"emf_lambda", &drive_gain_override_t::emf_lambda},
    {"emf_l_per_s", &drive_gain_override_t::emf_l_per_s},
    {"mech_alpha_rad_s3", &drive_gain_override_t::mech_alpha_rad_s3},
    {"mech_lambda", &drive_gain_override_t::mech_lambda},
    {"mech_l_per_s", &drive_gain_override_t::mech_l_per_s},
    {"cur_alpha_A_s2", &drive_gain_override_t::cur_alpha_A_s2},
    {"cur_lambda", &drive_gain_override_t::cur_lambda},
    {"k_surface_per_s", &drive_gain_override_t::k_surface_per_s},
    {"tw_lambda_m_rad_s3", &drive_gain_override_t::tw_lambda_m_rad_s3},
    {"tw_lambda_M_rad_s3", &drive_gain_override_t::tw_lambda_M_rad_s3},
    {"injection_filter_s", &drive_gain_override_t::injection_filter_s},
    {"blend_tau_s", &drive_gain_override_t::blend_tau_s},
    {"current_blend_tau_s", &drive_gain_override_t::current_blend_tau_s},
};

const BoundField kBoundFields[] = {
    {"bound_accel_rad_s2", &drive_design_input_t::bound_accel_rad_s2},
    {"bound_speed_rad_s", &drive_design_input_t::bound_speed_rad_s},
    {"bound_delta_omega_rad_s", &drive_design_input_t::bound_delta_omega_rad_s},
    {"bound_load_Nm", &drive_design_input_t::bound_load_Nm},
    {"bound_load_rate_Nm_s", &drive_design_input_t::bound_load_rate_Nm_s},
    {"bound_model_error_V", &drive_design_input_t::bound_model_error_V},
};

// Every double of drive_gain_override_t must be reachable from [gains]: a
// field added to the struct without a row here fails this check at compile
// time instead of being silently impossible to override.
static_assert(sizeof(kGainFields) / sizeof(kGainFields[0]) == sizeof(drive_gain_override_t) / sizeof(double),
              "kGainFields must list every field of drive_gain_override_t");

template <typename Table>
std::vector<std::string> keys_of(const Table& t)
{
    std::vector<std::string> k;
    for (const auto& f : t) {
        k.emplace_back(f.key);
    }
    return k;
}

// The one design input for the motor (design/motor_design.h), the same
// for every design.
motor_design_input_t to_design_motor(const MotorParams& m)
{
    motor_design_input_t d;
    d.L_H = m.L_H;
    d.R_ohm = m.R_ohm;
    d.K_Nm_per_A = m.K_Nm_per_A;
    d.J_kgm2 = m.J_kgm2;
    d.fv_Nms_per_rad = m.fv_Nms_per_rad;
    d.n_p = m.n_p;
    d.coulomb_Nm = m.coulomb_Nm;
    d.n_phases = m.n_phases();
    d.L_q_H = m.L_q();
    return d;
}

}  // namespace

const std::vector<std::string>& gain_override_keys()
{
    static const std::vector<std::string> k = keys_of(kGainFields);
    return k;
}

const std::vector<std::string>& design_bound_keys()
{
    static const std::vector<std::string> k = keys_of(kBoundFields);
    return k;
}

// The ADC's rail for the fault monitor: its largest code is full scale
// minus one LSB; 1.5 LSB below full scale catches it without catching the
// code below. 0 (no check) without an ADC.
double adc_rail_A(const SensorParams& p)
{
    if (p.adc_bits <= 0) {
        return 0.0;
    }
    const double lsb = 2.0 * p.adc_full_scale_A / std::ldexp(1.0, p.adc_bits);
    return p.adc_full_scale_A - 1.5 * lsb;
}

void make_design_input(const Scenario& sc, drive_design_input_t* in)
{
    *in = drive_design_input_t{};
    drive_design_defaults(in);
    in->motor = to_design_motor(sc.drive_model);
    in->ts_s = sc.ts_s;
    in->v_max_V = sc.v_max_V;
    in->i_max_A = sc.i_max_A;
    in->i_trip_A = sc.i_trip_A;
    in->i_trip_samples = sc.i_trip_samples;
    in->omega_lim_rad_s = sc.omega_lim_rad_s;
    in->los_relock = sc.los_relock;
    if (sc.i_open_loop_A > 0.0) {
        in->i_open_loop_A = sc.i_open_loop_A;
    }
    if (sc.load_feedforward >= 0) {
        in->load_feedforward = sc.load_feedforward;
    }
    if (sc.identify_rl >= 0) {
        in->identify_rl = sc.identify_rl;
    }
    if (sc.align_rotor >= 0) {
        in->align_rotor = sc.align_rotor;
    }
    if (sc.identify_k >= 0) {
        in->identify_k = sc.identify_k;
    }
    in->i_rail_A = adc_rail_A(sc.sensor);
    in->compute_delay_samples = sc.compute_delay_samples;  // the board's, known to its drive
    if (sc.gain_design >= 0) {
        in->gain_design = sc.gain_design == 1 ? DRIVE_GAIN_DISCRETE : DRIVE_GAIN_CONTINUOUS;
    }
    if (sc.control_law >= 0) {
        in->control_law = sc.control_law == 1 ? P000_LAW_LOAD_ANGLE : P000_LAW_TWISTING;
    }
    in->n_segments = static_cast<int>(sc.segments.size());
    for (std::size_t k = 0; k < sc.segments.size() && k < DRIVE_DESIGN_MAX_SEGMENTS; ++k) {
        in->segments[k].t_start_s = sc.segments[k].t_start_s;
        in->segments[k].duration_s = sc.segments[k].duration_s;
        in->segments[k].theta_to_rad = sc.segments[k].theta_to_rad;
    }
    for (const auto& kv : sc.bounds) {
        for (const BoundField& f : kBoundFields) {
            if (kv.first == f.key) {
                in->*(f.member) = kv.second;
            }
        }
    }
    for (const auto& kv : sc.gains) {
        for (const GainField& f : kGainFields) {
            if (kv.first == f.key) {
                in->override.*(f.member) = kv.second;
            }
        }
    }
}

void design_and_init_drive(Scenario& sc, paper000_drive_t* drive)
{
    if (sc.motor.type != MotorType::kStepper2) {
        throw ScenarioError(sc.path + ": motor.file: the paper-000 position drive ([trajectory]) runs two-phase "
                            "steppers (type = \"stepper2\"); a pmsm3 motor takes the speed drive ([speed])");
    }
    drive_design_input_t in;
    make_design_input(sc, &in);
    paper000_config_t cfg;
    std::memset(&cfg, 0, sizeof(cfg));
    char err[256] = {0};
    if (!drive_design(&in, &cfg, err, sizeof(err))) {
        throw ScenarioError(sc.path + ": design: " + (err[0] != '\0' ? err : "drive_design rejected the input"));
    }
    if (!paper000_drive_init(drive, &cfg)) {
        const char* why = paper000_config_problem(&cfg);
        throw ScenarioError(sc.path + ": design: the configuration derived from the motor file and the scenario is " +
                            "not usable: " +
                            (why != nullptr ? std::string(why) + " (a motor or limit value far outside what the "
                                                                 "design was written for?)"
                                            : std::string("trajectory: a segment of zero or too many samples, or "
                                                          "segments out of order")));
    }
    sc.pre_ticks = drive->align_ticks;
}

void make_speed_design_input(const Scenario& sc, p001_design_input_t* in)
{
    *in = p001_design_input_t{};
    p001_design_defaults(in);
    in->motor = to_design_motor(sc.drive_model);
    in->ts_s = sc.ts_s;
    in->i_max_A = sc.i_max_A;
    in->i_trip_A = sc.i_trip_A;
    in->i_trip_samples = sc.i_trip_samples;
    in->i_open_loop_A = sc.i_open_loop_A;
    in->gamma = sc.speed_gains.gamma;
    in->a1 = sc.speed_gains.a1;
    in->a2 = sc.speed_gains.a2;
    in->r_ohm = sc.speed_gains.r_ohm;
    in->blend_tau_s = sc.speed_gains.blend_tau_s;
    in->handover_sweep_rad = sc.speed_gains.handover_sweep_rad;
    in->fit_det_min = sc.speed_gains.fit_det_min;
    in->estimator = sc.speed_gains.estimator;
    in->compute_delay_samples = sc.compute_delay_samples;  // the board's, known to its drive
    in->i_rail_A = adc_rail_A(sc.sensor);
    in->omega_lim_rad_s = sc.omega_lim_rad_s;
    if (sc.speed_gains.probe_s >= 0.0) {
        in->probe_s = sc.speed_gains.probe_s;
    }
    in->n_points = sc.speed_points.size();
    for (std::size_t k = 0; k < sc.speed_points.size() && k < SPEED_PROFILE_MAX_POINTS; ++k) {
        in->t_s[k] = sc.speed_points[k].first;
        in->omega_rad_s[k] = sc.speed_points[k].second;
    }
}

void design_and_init_speed_drive(const Scenario& sc, paper001_drive_t* drive, p001_design_report_t* rep)
{
    p001_design_input_t in;
    make_speed_design_input(sc, &in);
    paper001_config_t cfg;
    std::memset(&cfg, 0, sizeof(cfg));
    char err[256] = {0};
    if (!p001_design(&in, &cfg, rep, err, sizeof(err))) {
        throw ScenarioError(sc.path + ": design: " + (err[0] != '\0' ? err : "p001_design rejected the input"));
    }
    if (!paper001_drive_init(drive, &cfg)) {
        throw ScenarioError(sc.path + ": design: paper001_drive_init rejected the derived configuration");
    }
}

void make_paper002_design_input(const Scenario& sc, p002_design_input_t* in)
{
    p002_design_defaults(in);
    in->motor = to_design_motor(sc.drive_model);
    in->ts_s = sc.ts_s;
    in->i_max_A = sc.i_max_A;
    in->i_trip_A = sc.i_trip_A;
    in->i_trip_samples = sc.i_trip_samples;
    in->i_rail_A = adc_rail_A(sc.sensor);
    switch (sc.sensor.noise) {
    case NoiseKind::kGaussian: in->sigma_i_A = sc.sensor.noise_A; break;
    case NoiseKind::kUniform: in->sigma_i_A = sc.sensor.noise_A / std::sqrt(3.0); break;
    default: in->sigma_i_A = 0.0; break;
    }
    in->encoder_counts = static_cast<long>(sc.encoder.counts_per_turn);
    in->sigma_theta_rad = sc.encoder.noise_rad;
    in->controller = sc.ipmsm.controller;
    in->compensate = sc.ipmsm.compensate;
    in->t0_s = sc.ipmsm.t0_s;
    in->t1_s = sc.ipmsm.t1_s;
    in->w0_rad_s = sc.ipmsm.omega_start_rad_s;
    in->w1_rad_s = sc.ipmsm.omega_final_rad_s;
    in->angle_source = sc.ipmsm.estimator;
    in->theta0_rad = sc.theta0_rad;  // the sensorless variant's aligned start (paper002_drive.h)
    in->compute_delay_samples = sc.compute_delay_samples;  // the board's, known to its drive
    std::copy(std::begin(sc.ipmsm.ekf_q), std::end(sc.ipmsm.ekf_q), in->ekf_q);
    std::copy(std::begin(sc.ipmsm.ekf_r), std::end(sc.ipmsm.ekf_r), in->ekf_r);
}

void design_and_init_paper002_drive(const Scenario& sc, paper002_drive_t* drive)
{
    p002_design_input_t in;
    make_paper002_design_input(sc, &in);
    paper002_config_t cfg;
    std::memset(&cfg, 0, sizeof(cfg));
    char err[256] = {0};
    if (!p002_design(&in, &cfg, err, sizeof(err))) {
        throw ScenarioError(sc.path + ": design: " + (err[0] != '\0' ? err : "p002_design rejected the input"));
    }
    if (!paper002_drive_init(drive, &cfg)) {
        throw ScenarioError(sc.path + ": design: paper002_drive_init rejected the derived configuration");
    }
}

}  // namespace mcsim
