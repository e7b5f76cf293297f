// inverter.cpp - the averaged inverter leg (see inverter.h for the
// equations (1)-(3) and their sources).
#include "model/inverter.h"

#include <cmath>

namespace mcsim {

const char* InverterParams::problem() const
{
    if (!(f_pwm_Hz > 0.0) || !std::isfinite(f_pwm_Hz)) {
        return "f_pwm_Hz must be > 0";
    }
    const double vals[] = {dead_time_s, t_on_s, t_off_s, v_switch_V, r_switch_Ohm,
                           v_diode_V,   r_diode_Ohm, min_pulse_s, i_transition_A};
    for (double v : vals) {
        if (!(v >= 0.0) || !std::isfinite(v)) {
            return "times, drops, resistances and i_transition_A must be finite and >= 0";
        }
    }
    const double T = 1.0 / f_pwm_Hz;
    // Two dead times per period; a leg whose dead times (or shortest pulses)
    // fill half the period has no room left for a duty.
    if (2.0 * dead_time_s >= T || 2.0 * min_pulse_s >= T) {
        return "dead_time_s and min_pulse_s must each be shorter than half the PWM period";
    }
    if (std::fabs(error_time_s()) * 2.0 >= T) {
        return "dead_time_s + t_on_s - t_off_s must be shorter than half the PWM period";
    }
    return nullptr;
}

double Inverter::transition(double i_A) const
{
    if (p_.i_transition_A <= 0.0) {
        return (i_A > 0.0) ? 1.0 : ((i_A < 0.0) ? -1.0 : 0.0);
    }
    // g(x) of inverter.h: x/2 up to |x| = 1, then sgn(x)(1 - 1/(2|x|))
    const double x = i_A / p_.i_transition_A;
    const double ax = std::fabs(x);
    if (ax <= 1.0) {
        return 0.5 * x;
    }
    return std::copysign(1.0 - 0.5 / ax, x);
}

double Inverter::duty(double v_cmd_V, double v_dc_V) const
{
    if (!(v_cmd_V == v_cmd_V) || !(v_dc_V > 0.0)) {
        return 0.5;  // NaN command (or no bus): the leg at the midpoint, 0 V
    }
    double d = 0.5 + v_cmd_V / v_dc_V;
    d = d < 0.0 ? 0.0 : (d > 1.0 ? 1.0 : d);
    // (1): a pulse shorter than t_min is not produced (high pulse d T,
    // low pulse (1 - d) T)
    const double d_min = p_.min_pulse_s * p_.f_pwm_Hz;
    if (d_min > 0.0) {
        if (d < d_min) {
            d = 0.0;
        } else if (1.0 - d < d_min) {
            d = 1.0;
        }
    }
    return d;
}

double Inverter::leg_voltage(double v_cmd_V, double i_A, double v_dc_V) const
{
    if (!(v_dc_V > 0.0)) {
        return 0.0;  // no bus, no voltage
    }
    const double half = 0.5 * v_dc_V;
    // The ideal leg: the command clamped to the bus (model/amplifier.h), so
    // an inverter without errors gives the amplifier's voltage bit for bit.
    double v0 = (v_cmd_V == v_cmd_V) ? v_cmd_V : 0.0;
    v0 = v0 > half ? half : (v0 < -half ? -half : v0);
    const double d = duty(v_cmd_V, v_dc_V);
    if (d == 0.0) {
        v0 = -half;  // a rail: clamped, or a low pulse too short dropped by (1)
    } else if (d == 1.0) {
        v0 = half;
    }
    const bool switching = d > 0.0 && d < 1.0;
    const double s = transition(i_A);
    // (2): the dead-time (and delays') error, only on a switching leg
    double d_eff = d;
    if (switching) {
        d_eff = d - s * p_.error_time_s() * p_.f_pwm_Hz;
        d_eff = d_eff < 0.0 ? 0.0 : (d_eff > 1.0 ? 1.0 : d_eff);
    }
    double v = v0 + (d_eff - d) * v_dc_V;
    // (3): the conduction drops of the devices carrying i
    const bool drops = p_.v_switch_V != 0.0 || p_.r_switch_Ohm != 0.0 || p_.v_diode_V != 0.0 || p_.r_diode_Ohm != 0.0;
    if (drops) {
        double f_d;
        if (p_.synchronous) {
            // body diodes conduct in the two dead times of a switching period
            f_d = switching ? 2.0 * p_.dead_time_s * p_.f_pwm_Hz : 0.0;
        } else {
            // one-way switches: i > 0 in the upper switch while high and the
            // lower diode while low; i < 0 the other way round
            const double w = 0.5 * (1.0 + s);
            f_d = 1.0 - (w * d_eff + (1.0 - w) * (1.0 - d_eff));
        }
        const double f_s = 1.0 - f_d;
        v -= f_s * (s * p_.v_switch_V + p_.r_switch_Ohm * i_A) + f_d * (s * p_.v_diode_V + p_.r_diode_Ohm * i_A);
    }
    return v;
}

void Inverter::apply(int n, const double* v_cmd_V, const double* i_A, double v_dc_V, double* v_leg_V) const
{
    for (int k = 0; k < n; ++k) {
        v_leg_V[k] = leg_voltage(v_cmd_V[k], i_A[k], v_dc_V);
    }
}

double Inverter::winding_voltage(double v_cmd_V, double i_A, double v_dc_V) const
{
    // bipolar drive: legs at +-v/2 about the midpoint, the winding current
    // out of leg 1 and into leg 2
    const double h = 0.5 * ((v_cmd_V == v_cmd_V) ? v_cmd_V : 0.0);
    return leg_voltage(h, i_A, v_dc_V) - leg_voltage(-h, -i_A, v_dc_V);
}

void Inverter::phase_voltages(const double* v_leg_V, double* v_phase_V)
{
    const double v_n = (v_leg_V[0] + v_leg_V[1] + v_leg_V[2]) / 3.0;
    for (int k = 0; k < 3; ++k) {
        v_phase_V[k] = v_leg_V[k] - v_n;
    }
}

}  // namespace mcsim
