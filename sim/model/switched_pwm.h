// switched_pwm.h - the inverter's legs switched at the PWM carrier (issue
// 30, [inverter] pwm = "switched"): instead of the averaged voltage of
// model/inverter.h held over a control period, each leg's voltage is
// piecewise constant, +-V_dc/2 about the bus midpoint, as centre-aligned PWM
// switches it, and the plant is integrated over each piece. For checking
// the averaged model and the current ripple the ADC sees; the averaged
// model stays the default (it is an order of magnitude cheaper).
//
// Carrier and sampling instant. An up-down counter, one carrier period T =
// 1/f_pwm per count up and down, the control period Ts a whole number n of
// carrier periods (like this project's TIM1 image, pwm_plan() in
// hal/backends/stm32f405/pwm_tim1.c, which refuses any other ratio). The
// currents are sampled in the middle of the zero vector in which every
// low-side switch conducts (V0, "000"), at the counter's turning point: the
// VESC's firmware triggers the ADC at both turning points and its control
// runs on the V0 one (vedderb/bldc motor/mcpwm_foc.c: TIM1 centre-aligned,
// TRGO on update, the ADC interrupt returns on is_v7 unless
// foc_sample_v0_v7), the ODrive's on the update event with the counter
// turning to count up, "we just sampled in SVM vector 0, i.e. real current"
// (odriverobotics/ODrive Firmware/MotorControl/low_level.cpp,
// pwm_trig_adc_cb), this project's image one timer clock before the top,
// where every low-side switch conducts (pwm_tim1.h: CH4 in PWM mode 2,
// CCR4 = ARR - 1). The few timer clocks between the turning point and the
// conversion (6-24 ns of a 50 us period) are neglected. So a control period
// starts and ends in the middle of V0, and within carrier period k (from
// t_k = k T) a leg of duty d is commanded
//
//   high for  t_k + (1 - d) T/2 <= t < t_k + (1 + d) T/2,  low otherwise,
//
// its pulse d T centred in the carrier period (d from the averaged model's
// (1), Inverter::duty(), minimum pulse included; d = 0 and d = 1 are rails:
// no edges). The currents the drive gets are the plant's at the period's
// boundary, ripple included. (At that instant the ideal ripple is zero: each
// half carrier period delivers the commanded volt-seconds, so the current
// there is the fundamental's, which is why the boards sample there; dead
// time and a command changing within the period break that symmetry.)
//
// Each commanded edge at t_e (either direction): the outgoing switch stops
// conducting at t_e + t_off, the incoming one starts at t_e + t_dead + t_on
// (the timer's dead time delays the incoming gate). Between the two the leg
// is "free": with t_dead + t_on > t_off both switches are off and the
// current decides through a diode, i > 0 (out of the leg) the low diode
// (-V_dc/2), i < 0 the high one (+V_dc/2); with t_off > t_dead + t_on both
// conduct for that time (a shoot-through this model does not resolve) and
// the current's switch decides, i > 0 the high side. The sign is the leg's
// current at the segment's start (i = 0: nothing commutates the node, taken
// to follow the command from the interval's start on, i.e. no error: the
// averaged model's sgn(0) = 0). Free intervals of edges closer than
// |t_dead + t_on - t_off| merge (a pulse shorter than the dead time is not
// produced, the averaged model's clamp of d_eff). Over a carrier period at a
// constant current this gives exactly the averaged model's (2) with the hard
// sign (i_transition_A = 0).
//
// The node capacitance (i_transition_A > 0, both switches off in the free
// interval, t_f = t_dead + t_on - t_off > 0): when the current leaves the
// node toward the other rail (i > 0 after the high switch turned off, i < 0
// after the low one), it does not jump there; the current slews the node
// across the bus at i/C, C = i_transition_A t_f / V_dc (docs/plant.md, the
// transition near zero current: i_transition_A is the current whose ramp
// just fills the free interval). With x = |i|/i_transition_A at the
// interval's opening, the ramp's volt-seconds are those of the node held at
// the outgoing rail for
//     t_a = t_f / (2 x)      (x >= 1: the ramp ends within t_f), or
//     t_a = t_f (1 - x/2)    (x < 1: the incoming switch clamps it),
// then at the diode's rail; the leg is stepped so (a step of equal area in
// place of the ramp, a few hundred nanoseconds). Over a carrier period at a
// constant current that is the averaged model's (2) with g(x) exactly
// (ctest sim.switched_pwm.Leg.CarrierPeriodMeanIsTheAveragedLegWithTheTransition);
// with it the switched and the averaged models share the soft zero
// crossing, which the drives' compensation assumes. During the slew no
// device conducts: no drops. With the current's ripple the zero crossing is
// smoothed further (a current changing sign within the period).
//
// The devices' drops of (3) per segment, on whichever device conducts, with
// the hard sign s = sgn(i): high or low with MOSFETs driven complementary
// (synchronous) the channel, -(s V_s0 + r_s i); with one-way switches (IGBTs)
// the switch for its direction of current and the opposite diode otherwise,
// -(s V_d0 + r_d i); free (dead) the diode; free (overlap) the current's
// switch. (The synchronous diode conducts the free intervals here, the
// averaged model's f_d = 2 t_dead f_pwm assumes two whole dead times: they
// differ with t_on != t_off and for a pulse shorter than the dead time,
// whose two free intervals merge into one.)
//
// The compute delay (hal_sw_plant_set_compute_delay, fraction D): the legs
// compare the carrier with the previous command's duty before D Ts and with
// the new one after (a compare value written at once; D = 1, the MCU's
// shadow registers loaded at the next period, switches at the boundary in
// V0 where nothing switches). The plant is stepped (RK4, PmPlant::step_phases)
// over each segment between the legs' sorted events, the legs' voltages held;
// a star-connected motor's star point floats at the legs' mean (the plant's
// Clarke removes it, as for the averaged model); a stepper's winding is an
// H-bridge of two legs on the same carrier, at +v/2 and -v/2 (duties d and
// 1 - d, both centred: boards/odrive36.c's legs B and C).
#ifndef MCSIM_MODEL_SWITCHED_PWM_H
#define MCSIM_MODEL_SWITCHED_PWM_H

#include <vector>

#include "model/inverter.h"

namespace mcsim {

class PmPlant;

// What the legs drive: the currents out of the legs at a segment's start,
// and a step with the legs' voltages held.
class PwmLoad {
public:
    virtual ~PwmLoad() = default;
    virtual void leg_currents(double* i_A) const = 0;
    virtual void step(const double* v_leg_V, double dt_s) = 0;
};

// The plant behind the legs: three legs of a star-connected PMSM (leg k
// drives phase k), or a stepper's two H-bridges (legs 0 and 1 winding a,
// its current out of leg 0 and into leg 1; legs 2 and 3 winding b).
class PlantLoad final : public PwmLoad {
public:
    explicit PlantLoad(PmPlant& plant) : plant_(plant) {}
    // 3 or 4
    int legs() const;
    void leg_currents(double* i_A) const override;
    void step(const double* v_leg_V, double dt_s) override;

private:
    PmPlant& plant_;
};

class SwitchedPwm {
public:
    static constexpr int kMaxLegs = 4;  // a stepper's two H-bridges
    // At most this many carrier periods per control period: pwm_plan()'s
    // limit (pwm_tim1.h), the firmware's bound on the ADC decimation.
    static constexpr int kMaxCarrierPeriods = 128;
    // f_pwm Ts may differ from a whole number by this fraction of it and
    // still count as whole: Ts and f_pwm are decimal numbers whose product
    // is off by a few ulps in double (1e-16); a real mismatch is at least
    // one timer clock in a period of thousands (1e-4).
    static constexpr double kRatioTolerance = 1e-9;

    // The number n of carrier periods in a control period ts_s, if f_pwm ts
    // is a whole number in [1, kMaxCarrierPeriods]; else 0.
    static int carrier_periods(double f_pwm_Hz, double ts_s);

    // A leg's state over a segment: its commanded state settled, or free
    // (between the outgoing switch's turn-off and the incoming one's turn-on).
    enum class Node : unsigned char { kLow, kHigh, kFree };

    // The leg's voltage about the midpoint in state s carrying i_A out of
    // the leg on a bus of v_dc_V, the drops included (see above); free_high:
    // free with no current, the state the opening edge commands.
    static double node_voltage(const InverterParams& p, Node s, double i_A, double v_dc_V, bool free_high);

    // The legs' duties for the drive's commands on a bus of v_dc_V (three
    // legs of n_phases = 3, four of 2: each winding's legs at +v/2 and -v/2);
    // returns the number of legs.
    static int leg_duties(const Inverter& inv, int n_phases, const double* v_cmd_V, double v_dc_V, double* d);

    // n_legs legs (1 to kMaxLegs) switching at p.f_pwm_Hz within control
    // periods of ts_s; carrier_periods(p.f_pwm_Hz, ts_s) must be > 0.
    SwitchedPwm(const InverterParams& p, int n_legs, double ts_s);

    // One control period: leg k at duty d_prev[k] before t_switch_s (from
    // the period's start, in [0, ts]) and d_new[k] from then on; the load
    // stepped over every segment between the legs' events. The legs' state
    // (edges whose dead time runs into the next period) carries over.
    void run_period(PwmLoad& load, const double* d_prev, const double* d_new, double t_switch_s, double v_dc_V);

    // Segments the last period was stepped in (the cost: one plant step each).
    int segments_last_period() const { return segments_; }
    int carrier_periods() const { return n_; }
    int legs() const { return n_legs_; }

private:
    struct Event {
        double t_s;      // from the period's start
        int leg;
        int delta;       // +1: a free interval opens; -1: one closes
        bool high;       // the commanded state it settles to (delta = -1)
    };
    struct Leg {
        bool cmd_high = false;  // the commanded state at the last edge
        bool settled_high = false;
        bool free_high = false;  // the state the last edge to open a free interval commands
        int free = 0;           // free intervals open
        // the node still slewing on its capacitance from the outgoing
        // switch's rail (slew_high) until slew_end_s (< 0: not slewing)
        double slew_end_s = -1.0;
        bool slew_high = false;
    };
    // The node capacitance's commutation at a free interval's opening
    // (see above): the equivalent time the node stays at the outgoing
    // rail, for a leg current i_A.
    double slew_time(double i_A, bool old_high) const;
    void add_piece(int leg, double t0, double t1, double d);
    void add_edge(int leg, double t_e, bool high);
    Node node(int leg) const;

    InverterParams p_;
    int n_legs_;
    int n_;        // carrier periods per control period
    double ts_;
    double T_;     // carrier period
    double lo_;    // a free interval from t_e + lo_ ...
    double hi_;    // ... to t_e + hi_
    Leg legs_[kMaxLegs];
    std::vector<Event> events_;   // this period's, sorted
    std::vector<Event> carried_;  // past the period's end, for the next
    int segments_ = 0;
};

}  // namespace mcsim

#endif  // MCSIM_MODEL_SWITCHED_PWM_H
