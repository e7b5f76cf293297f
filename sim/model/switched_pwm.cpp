// switched_pwm.cpp - the legs switched at the carrier (see switched_pwm.h).
#include "model/switched_pwm.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "model/pm_plant.h"

namespace mcsim {

int PlantLoad::legs() const { return plant_.n_phases() == 3 ? 3 : 4; }

void PlantLoad::leg_currents(double* i_A) const
{
    if (plant_.n_phases() == 3) {
        plant_.phase_currents(i_A);
        return;
    }
    double w[2];
    plant_.phase_currents(w);
    i_A[0] = w[0];
    i_A[1] = -w[0];
    i_A[2] = w[1];
    i_A[3] = -w[1];
}

void PlantLoad::step(const double* v_leg_V, double dt_s)
{
    if (plant_.n_phases() == 3) {
        plant_.step_phases(v_leg_V, dt_s);  // the star point: the plant's Clarke
        return;
    }
    const double w[2] = {v_leg_V[0] - v_leg_V[1], v_leg_V[2] - v_leg_V[3]};
    plant_.step_phases(w, dt_s);
}

int SwitchedPwm::carrier_periods(double f_pwm_Hz, double ts_s)
{
    const double r = f_pwm_Hz * ts_s;
    if (!std::isfinite(r) || !(r > 0.5) || r > kMaxCarrierPeriods + 0.5) {
        return 0;
    }
    const double n = std::round(r);
    return std::fabs(r - n) <= kRatioTolerance * n ? static_cast<int>(n) : 0;
}

double SwitchedPwm::node_voltage(const InverterParams& p, Node s, double i_A, double v_dc_V, bool free_high)
{
    if (!(v_dc_V > 0.0)) {
        return 0.0;  // no bus, no voltage (as Inverter::leg_voltage)
    }
    const double half = 0.5 * v_dc_V;
    const double sg = (i_A > 0.0) ? 1.0 : ((i_A < 0.0) ? -1.0 : 0.0);
    const double switch_drop = sg * p.v_switch_V + p.r_switch_Ohm * i_A;
    const double diode_drop = sg * p.v_diode_V + p.r_diode_Ohm * i_A;
    if (s == Node::kFree) {
        if (sg == 0.0) {
            // no current to commutate: the state of the edge that opened
            // the interval, the command delayed by the interval's start
            // (the averaged model's sgn(0) = 0: no error)
            return free_high ? half : -half;
        }
        if (p.error_time_s() > 0.0) {
            // both switches off: the diode of the current's direction, the
            // low one for i > 0 (the current leaves through the leg)
            return (sg > 0.0 ? -half : half) - diode_drop;
        }
        // both on (t_off > t_dead + t_on): the current's switch, the high
        // one for i > 0
        return (sg > 0.0 ? half : -half) - switch_drop;
    }
    const bool high = s == Node::kHigh;
    const double v = high ? half : -half;
    if (p.synchronous) {
        return v - switch_drop;  // the channel conducts both ways
    }
    // one-way switches: the high switch carries i > 0, the low one i < 0;
    // the opposite diode the other direction (i = 0: no drop either way)
    const bool by_switch = high ? sg > 0.0 : sg < 0.0;
    return v - (by_switch ? switch_drop : diode_drop);
}

int SwitchedPwm::leg_duties(const Inverter& inv, int n_phases, const double* v_cmd_V, double v_dc_V, double* d)
{
    if (n_phases == 3) {
        for (int k = 0; k < 3; ++k) {
            d[k] = inv.duty(v_cmd_V[k], v_dc_V);
        }
        return 3;
    }
    // each winding's H-bridge driven bipolar, as Inverter::winding_voltage
    for (std::size_t w = 0; w < 2; ++w) {
        const double h = 0.5 * ((v_cmd_V[w] == v_cmd_V[w]) ? v_cmd_V[w] : 0.0);
        d[2 * w] = inv.duty(h, v_dc_V);
        d[2 * w + 1] = inv.duty(-h, v_dc_V);
    }
    return 4;
}

SwitchedPwm::SwitchedPwm(const InverterParams& p, int n_legs, double ts_s)
    : p_(p),
      n_legs_(std::clamp(n_legs, 1, kMaxLegs)),
      n_(std::max(carrier_periods(p.f_pwm_Hz, ts_s), 1)),
      ts_(ts_s),
      T_(ts_s / static_cast<double>(n_)),
      lo_(std::min(p.t_off_s, p.dead_time_s + p.t_on_s)),
      hi_(std::max(p.t_off_s, p.dead_time_s + p.t_on_s))
{
    // per leg two events an edge and two edges a carrier period, plus the
    // edges of a command change (at the period's start and at the delay's
    // instant) and those carried over: reserved once so that the loop does
    // not allocate (a reserve, not a limit)
    events_.reserve(static_cast<std::size_t>(n_legs_) * (4u * static_cast<std::size_t>(n_) + 8u));
    carried_.reserve(static_cast<std::size_t>(n_legs_) * 8u);
}

void SwitchedPwm::add_edge(int leg, double t_e, bool high)
{
    events_.push_back(Event{t_e + lo_, leg, +1, high});
    events_.push_back(Event{t_e + hi_, leg, -1, high});
    legs_[leg].cmd_high = high;
}

void SwitchedPwm::add_piece(int leg, double t0, double t1, double d)
{
    // the commanded state at t0, then the carrier's edges in (t0, t1)
    const bool rail = !(d > 0.0 && d < 1.0);
    int k0 = static_cast<int>(std::floor(t0 / T_));
    k0 = std::clamp(k0, 0, n_ - 1);
    const double up = 0.5 * (1.0 - d) * T_;  // rising edge from the carrier period's start
    const double down = 0.5 * (1.0 + d) * T_;
    bool s0;
    if (rail) {
        s0 = d >= 1.0;
    } else {
        const double base = static_cast<double>(k0) * T_;
        s0 = base + up <= t0 && t0 < base + down;
    }
    if (s0 != legs_[leg].cmd_high) {
        add_edge(leg, t0, s0);  // the command's change itself switches the leg
    }
    if (rail) {
        return;
    }
    for (int k = k0; k < n_; ++k) {
        const double base = static_cast<double>(k) * T_;
        if (base >= t1) {
            break;
        }
        const double tr = base + up;
        const double tf = base + down;
        if (tr > t0 && tr < t1) {
            add_edge(leg, tr, true);
        }
        if (tf > t0 && tf < t1) {
            add_edge(leg, tf, false);
        }
    }
}

double SwitchedPwm::slew_time(double i_A, bool old_high) const
{
    const double t_f = hi_ - lo_;
    if (!(p_.i_transition_A > 0.0) || !(p_.error_time_s() > 0.0) || !(t_f > 0.0)) {
        return 0.0;  // no capacitance, or no interval with both switches off
    }
    // only a current that leaves toward the other rail slews the node; the
    // other direction holds it at the outgoing rail through the diode
    const bool away = old_high ? i_A > 0.0 : i_A < 0.0;
    if (!away) {
        return 0.0;
    }
    const double x = std::fabs(i_A) / p_.i_transition_A;
    return (x >= 1.0) ? t_f / (2.0 * x) : t_f * (1.0 - 0.5 * x);
}

SwitchedPwm::Node SwitchedPwm::node(int leg) const
{
    const Leg& l = legs_[leg];
    if (l.free > 0) {
        return Node::kFree;
    }
    return l.settled_high ? Node::kHigh : Node::kLow;
}

void SwitchedPwm::run_period(PwmLoad& load, const double* d_prev, const double* d_new, double t_switch_s,
                             double v_dc_V)
{
    events_.clear();
    events_.insert(events_.end(), carried_.begin(), carried_.end());
    carried_.clear();
    const double t_sw = std::clamp(t_switch_s, 0.0, ts_);
    for (int k = 0; k < n_legs_; ++k) {
        if (t_sw > 0.0) {
            add_piece(k, 0.0, t_sw, d_prev[k]);
        }
        if (t_sw < ts_) {
            add_piece(k, t_sw, ts_, d_new[k]);
        }
    }
    // Insertion sort by time, stable: a leg's free interval opens before it
    // closes at the same instant, the carried events before this period's.
    // A few dozen events, nearly sorted leg by leg.
    for (std::size_t a = 1; a < events_.size(); ++a) {
        const Event e = events_[a];
        std::size_t b = a;
        while (b > 0 && events_[b - 1].t_s > e.t_s) {
            events_[b] = events_[b - 1];
            --b;
        }
        events_[b] = e;
    }
    double i[kMaxLegs] = {0.0, 0.0, 0.0, 0.0};
    double v[kMaxLegs] = {0.0, 0.0, 0.0, 0.0};
    double t = 0.0;
    auto segment = [&](double dt) {
        load.leg_currents(i);
        const double half = 0.5 * v_dc_V;
        for (int k = 0; k < n_legs_; ++k) {
            const Leg& l = legs_[k];
            // a slewing node: at the outgoing rail, no device conducting
            v[k] = (l.slew_end_s > t) ? (l.slew_high ? half : -half)
                                       : node_voltage(p_, node(k), i[k], v_dc_V, l.free_high);
        }
        load.step(v, dt);
        ++segments_;
    };
    // steps to t_end, split where a node's slew ends
    auto advance = [&](double t_end) {
        while (t_end > t) {
            double next = t_end;
            for (int k = 0; k < n_legs_; ++k) {
                if (legs_[k].slew_end_s > t && legs_[k].slew_end_s < next) {
                    next = legs_[k].slew_end_s;
                }
            }
            segment(next - t);
            t = next;
        }
    };
    segments_ = 0;
    std::size_t a = 0;
    for (; a < events_.size() && events_[a].t_s < ts_; ++a) {
        const Event& e = events_[a];
        advance(e.t_s);
        Leg& l = legs_[e.leg];
        const bool opening = e.delta > 0 && l.free == 0;
        l.free += e.delta;
        if (e.delta < 0) {
            l.settled_high = e.high;
            if (l.free == 0) {
                l.slew_end_s = -1.0;  // the incoming switch clamps the node
            }
        } else {
            l.free_high = e.high;
        }
        if (opening && v_dc_V > 0.0) {
            load.leg_currents(i);
            const double t_a = slew_time(i[e.leg], l.settled_high);
            if (t_a > 0.0) {
                l.slew_end_s = e.t_s + t_a;
                l.slew_high = l.settled_high;
            }
        }
    }
    advance(ts_);
    for (; a < events_.size(); ++a) {
        Event e = events_[a];
        e.t_s -= ts_;
        carried_.push_back(e);
    }
    for (int k = 0; k < n_legs_; ++k) {
        Leg& l = legs_[k];
        l.slew_end_s = (l.slew_end_s > ts_) ? l.slew_end_s - ts_ : -1.0;
    }
}

}  // namespace mcsim
