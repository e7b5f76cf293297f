// inverter.h - the averaged nonlinearity of a voltage-source inverter leg
// (issue 30): dead time and switching delays, the switches' and diodes'
// conduction drops, a minimum pulse width, on a DC link of V_dc; and the
// phase voltages of a star-connected motor with an isolated neutral. Paper
// 000's linear amplifiers keep model/amplifier.h; this is the MCU boards'
// power stage (VESC 6: three MOSFET half bridges on a DRV8301).
//
// Averaged over one PWM period T = 1/f_pwm, one leg whose current i flows
// out of the leg into the motor (i > 0), with the voltage about the bus
// midpoint:
//
//   d     = clamp(1/2 + v_cmd/V_dc, 0, 1)                    commanded duty
//   d     = 0 if d < t_min f_pwm, 1 if 1 - d < t_min f_pwm    minimum pulse (1)
//   d_eff = clamp(d - g(i/i_tr) (t_dead + t_on - t_off) f_pwm, 0, 1)   (2)
//           (only while the leg switches, 0 < d < 1: a leg held at a rail
//           has no edges, so no dead time)
//   v     = (d_eff - 1/2) V_dc - f_s (s V_s0 + r_s i) - f_d (s V_d0 + r_d i)  (3)
//
// (2) is the classic dead-time error: over each period the leg's pulse is
// shortened (i > 0) or lengthened (i < 0) by the dead time plus the turn-on
// delay of the incoming switch minus the turn-off delay of the outgoing one,
// i.e. V_dc (t_dead + t_on - t_off) f_pwm of average voltage against the
// sign of the current (T. Sukegawa, K. Kamiyama, K. Mizuno, T. Matsui,
// T. Okuyama, "Fully digital, vector-controlled PWM VSI-fed ac drives with
// an inverter dead-time compensation strategy", IEEE Trans. Ind. Appl.
// 27(3), 1991, pp. 552-559; J.-W. Choi, S.-K. Sul, "Inverter output voltage
// synthesis using novel dead time compensation", IEEE Trans. Power
// Electron. 11(2), 1996, pp. 221-227, which adds the device drops of (3)).
//
// The transition near zero current, g: with a hard sgn(i) the error would
// jump by 2 V_dc t f_pwm as the current crosses zero; a real leg does not,
// because the node's capacitance (the two devices' output capacitances,
// charge Q_node = 2 Q_oss(V_dc)) must be swung by the load current itself
// during the dead time. Worked out for a constant current over the dead
// time (the derivation is in docs/plant.md, "Inverter"): with
// i_tr = Q_node / t_dead, the current that swings the node across the whole
// bus in exactly one dead time,
//
//   g(x) = x / 2                      for |x| <= 1,
//   g(x) = sgn(x) (1 - 1/(2 |x|))     for |x| >  1,
//
// continuous with a continuous slope (1/2 at |x| = 1), g -> sgn as |x| grows
// (0.95 at |x| = 10). The same linear-then-saturating shape is what the
// current ripple produces when it makes the current change sign within the
// period (|i| below about half the peak-to-peak ripple), so i_tr may be set
// to the larger of 2 Q_oss / t_dead and half the ripple (docs/plant.md).
// i_transition_A = 0 is the hard sgn(i) (with sgn(0) = 0).
//
// (3), the conduction drops (Choi and Sul 1996): a device carrying i drops
// sgn(i) V0 + r i against the current. With s = g(i/i_tr) standing for
// sgn(i) (so the drops also vanish at zero current) and w = (1 + s)/2 the
// weight of the i > 0 case, the switches conduct the fraction
//   f_s = w d_eff + (1 - w)(1 - d_eff)   and the diodes f_d = 1 - f_s
// for switches that conduct one way only (IGBTs: the freewheeling current
// flows through the opposite diode); for MOSFETs driven complementary
// (synchronous rectification, the VESC's) the channel conducts both ways
// and the body diode only in the two dead times of a switching period:
//   f_d = 2 t_dead f_pwm (0 while the leg is held at a rail), f_s = 1 - f_d.
//
// Star connection, isolated neutral: the star point floats at the legs'
// mean, v_n = (v_a + v_b + v_c)/3, so the phase voltages are the legs' minus
// that common mode, v_x - v_n (model/pm_plant.h's Clarke removes it the same
// way). The ideal inverter (every time, drop and i_tr zero; f_pwm any) is
// the amplifier model: the command clamped to +-V_dc/2.
#ifndef MCSIM_MODEL_INVERTER_H
#define MCSIM_MODEL_INVERTER_H

namespace mcsim {

// How the software plant's backend applies the inverter ([inverter] pwm):
// the averaged leg voltages of this file, held over each control period
// (the default), or the legs switched at the carrier with the plant
// integrated over each switching segment (model/switched_pwm.h).
enum class PwmModel { kAveraged, kSwitched };

struct InverterParams {
    double f_pwm_Hz = 20e3;       // carrier (switching) frequency
    double dead_time_s = 0.0;     // both switches off between the two states of a leg
    double t_on_s = 0.0;          // turn-on delay of a switch (adds to the dead time)
    double t_off_s = 0.0;         // turn-off delay of a switch (subtracts from it)
    double v_switch_V = 0.0;      // switch's constant drop (IGBT V_CE0; 0 for a MOSFET)
    double r_switch_Ohm = 0.0;    // switch's slope resistance (a MOSFET's R_DS(on))
    double v_diode_V = 0.0;       // freewheeling (body) diode's constant drop
    double r_diode_Ohm = 0.0;     // its slope resistance
    double min_pulse_s = 0.0;     // pulses shorter than this are not produced
    double i_transition_A = 0.0;  // i_tr of g above; 0: hard sgn(i)
    // true: MOSFETs driven complementary (the channel conducts both ways);
    // false: one-way switches (IGBTs) with freewheeling diodes.
    bool synchronous = true;
    PwmModel pwm = PwmModel::kAveraged;  // not used by Inverter itself

    // The effective error time t_dead + t_on - t_off [s].
    double error_time_s() const { return dead_time_s + t_on_s - t_off_s; }
    // nullptr if the parameters describe a leg, else the first problem
    // (a negative time or drop, a dead time or minimum pulse that fills a
    // period, f_pwm <= 0).
    const char* problem() const;
};

class Inverter {
public:
    explicit Inverter(const InverterParams& p) : p_(p) {}

    // Duty of a leg commanded v_cmd_V about the midpoint: (1) with the
    // clamp; a NaN command is 0 V (d = 1/2), as in model/amplifier.h.
    double duty(double v_cmd_V, double v_dc_V) const;
    // g(i / i_tr) in [-1, 1] (the transition above).
    double transition(double i_A) const;
    // The averaged voltage of one leg about the bus midpoint, (1)-(3), for
    // its command and the current out of it.
    double leg_voltage(double v_cmd_V, double i_A, double v_dc_V) const;
    // n legs at once (3 for a PMSM's bridge): v_leg_V[k] = leg_voltage(...).
    void apply(int n, const double* v_cmd_V, const double* i_A, double v_dc_V, double* v_leg_V) const;
    // One winding between two legs driven bipolar (a stepper's H-bridge):
    // the legs at +-v_cmd/2, the winding current out of the first and into
    // the second; the winding voltage v_1 - v_2 (v_cmd clamped to +-V_dc).
    double winding_voltage(double v_cmd_V, double i_A, double v_dc_V) const;
    // Star with isolated neutral: v_phase = v_leg - (v_a + v_b + v_c)/3.
    static void phase_voltages(const double* v_leg_V, double* v_phase_V);

    const InverterParams& params() const { return p_; }

private:
    InverterParams p_;
};

}  // namespace mcsim

#endif  // MCSIM_MODEL_INVERTER_H
