// hal_sw_plant.cpp - software-plant backend of hal.h (see hal_sw_plant.h).
#include "hal_sw_plant.h"

#include <cmath>
#include <optional>

#include "mc_convert.h"
#include "model/switched_pwm.h"

namespace {

struct Backend {
    mcsim::PmPlant* plant = nullptr;
    mcsim::CurrentSensor* sensor = nullptr;
    mcsim::Amplifier amp;
    double ts_s = 1e-4;
    hal_control_fn control = nullptr;
    void* control_ctx = nullptr;
    hal_sw_plant_monitor_fn monitor = nullptr;
    void* monitor_ctx = nullptr;
    bool started = false;
    bool safe = false;
    std::uint32_t tick = 0;
    double t_start_s = 0.0;  // plant time at hal_start
    double delay = 0.0;      // computation delay, fraction of a sample
    double v_prev[3] = {0.0, 0.0, 0.0};  // voltage applied over the last sample
    mcsim::FaultInjector* faults = nullptr;  // injected faults, or none
    const hal_sw_plant_can_t* can = nullptr;  // CAN bus, or none
    mcsim::BoardEmulation* board = nullptr;   // DAC/ADC board, or none
    mcsim::Encoder* encoder = nullptr;        // position encoder, or none
    const mcsim::Inverter* inverter = nullptr;  // PWM inverter, or the amplifier
    // its legs switched at the carrier ([inverter] pwm = "switched"), with
    // the duties of the last period's command; none: the averaged inverter
    std::optional<mcsim::SwitchedPwm> pwm;
    double d_prev[mcsim::SwitchedPwm::kMaxLegs] = {0.5, 0.5, 0.5, 0.5};
    bool pwm_ratio_bad = false;  // switched with f_pwm Ts not whole: run refuses
    bool amp_output = true;  // neither a board nor an inverter: the amplifier model (one test a period)
    hal_sw_plant_period_t last{};
    const char* error = "";
};

// One backend per process, like the one power stage of a real board.
Backend g_hal;

}  // namespace

void hal_sw_plant_attach(mcsim::PmPlant* plant, mcsim::CurrentSensor* sensor,
                         const mcsim::Amplifier& amp, double ts_s)
{
    g_hal = Backend{};
    g_hal.plant = plant;
    g_hal.sensor = sensor;
    g_hal.amp = amp;
    g_hal.ts_s = ts_s;
}

void hal_sw_plant_detach(void) { g_hal = Backend{}; }

bool hal_sw_plant_set_compute_delay(double fraction)
{
    if (!(fraction >= 0.0 && fraction <= 1.0)) {
        g_hal.error = "hal_sw_plant_set_compute_delay: the fraction must be in [0, 1]";
        return false;
    }
    g_hal.delay = fraction;
    return true;
}

void hal_sw_plant_set_faults(mcsim::FaultInjector* faults) { g_hal.faults = faults; }

void hal_sw_plant_set_can(const hal_sw_plant_can_t* bus) { g_hal.can = bus; }

void hal_sw_plant_set_board(mcsim::BoardEmulation* board)
{
    g_hal.board = board;
    g_hal.amp_output = g_hal.board == nullptr && g_hal.inverter == nullptr;
}

void hal_sw_plant_set_encoder(mcsim::Encoder* encoder) { g_hal.encoder = encoder; }

void hal_sw_plant_set_inverter(const mcsim::Inverter* inverter)
{
    g_hal.inverter = inverter;
    g_hal.amp_output = g_hal.board == nullptr && g_hal.inverter == nullptr;
    g_hal.pwm.reset();
    g_hal.pwm_ratio_bad = false;
    if (inverter != nullptr && inverter->params().pwm == mcsim::PwmModel::kSwitched && g_hal.plant != nullptr) {
        if (mcsim::SwitchedPwm::carrier_periods(inverter->params().f_pwm_Hz, g_hal.ts_s) == 0) {
            g_hal.pwm_ratio_bad = true;
            g_hal.error = "hal_sw_plant_set_inverter: switched PWM needs a whole number of carrier periods per control period";
            return;
        }
        const int legs = mcsim::PlantLoad(*g_hal.plant).legs();
        g_hal.pwm.emplace(inverter->params(), legs, g_hal.ts_s);
        // before the first command the legs at 0 V, as v_prev
        const double zero[3] = {0.0, 0.0, 0.0};
        const double v_bus = g_hal.plant->n_phases() == 3 ? 2.0 * g_hal.amp.v_max_V : g_hal.amp.v_max_V;
        (void)mcsim::SwitchedPwm::leg_duties(*inverter, g_hal.plant->n_phases(), zero, v_bus, g_hal.d_prev);
    }
}

void hal_sw_plant_set_monitor(hal_sw_plant_monitor_fn fn, void* ctx)
{
    g_hal.monitor = fn;
    g_hal.monitor_ctx = ctx;
}

bool hal_sw_plant_in_safe_state(void) { return g_hal.safe; }

const hal_sw_plant_period_t* hal_sw_plant_last_period(void) { return &g_hal.last; }

std::uint32_t hal_sw_plant_run(std::uint32_t n_periods)
{
    if (g_hal.plant == nullptr || g_hal.sensor == nullptr || !g_hal.started) {
        g_hal.error = "hal_sw_plant_run: no plant attached or hal_start not called";
        return 0;
    }
    if (g_hal.pwm_ratio_bad) {
        return 0;  // hal_last_error() says why (set_inverter)
    }
    mcsim::PmPlant& plant = *g_hal.plant;
    hal_sw_plant_period_t& p = g_hal.last;
    for (std::uint32_t period = 0; period < n_periods; ++period) {
        p.tick = g_hal.tick;
        // Time from the tick count, not an accumulated sum.
        p.t_s = g_hal.t_start_s + static_cast<double>(g_hal.tick) * g_hal.ts_s;
        const int n_ph = plant.n_phases();
        double i_true[3] = {0.0, 0.0, 0.0};
        double i_meas[3] = {0.0, 0.0, 0.0};
        mcsim::FaultInjector* const fi = g_hal.faults;
        if (fi != nullptr) {
            plant.set_locked(fi->rotor_locked(p.t_s, g_hal.ts_s));
            plant.set_open_winding(fi->open_phase(p.t_s, g_hal.ts_s));
        }
        plant.phase_currents(i_true);
        const double v_supply = fi != nullptr ? fi->v_max_V(p.t_s, g_hal.amp.v_max_V) : g_hal.amp.v_max_V;
        // The simulated supply is stiff: an H-bridge swings +-v_bus, a leg
        // +-v_bus/2 about the midpoint.
        const double v_bus_true = n_ph == 3 ? 2.0 * v_supply : v_supply;
        double v_bus_meas = v_bus_true;
        double i_sensed[3] = {i_true[0], i_true[1], i_true[2]};
        if (fi != nullptr) {
            fi->analog(p.t_s, g_hal.ts_s, n_ph, i_sensed);
        }
        if (g_hal.board != nullptr) {
            g_hal.board->measure(n_ph, i_sensed, v_bus_true, i_meas, &v_bus_meas);
        } else {
            g_hal.sensor->measure_phases(n_ph, i_sensed, i_meas);
        }
        if (fi != nullptr) {
            fi->digital(p.t_s, g_hal.ts_s, n_ph, i_meas);
        }
        p.n_phases = n_ph;
        p.i_a_meas_A = i_meas[0];
        p.i_b_meas_A = i_meas[1];
        p.i_c_meas_A = i_meas[2];

        double v_cmd[3] = {0.0, 0.0, 0.0};
        p.control_called = !g_hal.safe && g_hal.control != nullptr;
        if (p.control_called) {
            // Zeroed first: fields a later version adds read as "absent".
            hal_sample_t in{};
            in.tick = g_hal.tick;
            in.n_phases = static_cast<std::uint8_t>(n_ph);
            for (int k = 0; k < n_ph; ++k) {
                // not to_mc: a NaN sample (an injected fault) reaches the
                // float drive as NaN, whose fault monitor must catch it
                in.i_A[k] = mc_from_double(i_meas[k]);
            }
            in.v_bus_V = mcsim::to_mc(v_bus_meas);
            in.has_angle = g_hal.encoder != nullptr;
            in.angle_rad = in.has_angle ? mcsim::to_mc(g_hal.encoder->measure(plant.theta_rad())) : mcsim::to_mc(0.0);
            in.status = (fi != nullptr && fi->overrun(p.t_s, g_hal.ts_s)) ? HAL_STATUS_OVERRUN : 0u;
            hal_command_t out{};
            out.n_phases = static_cast<std::uint8_t>(n_ph);
            g_hal.control(g_hal.control_ctx, &in, &out);
            // The callback may have called hal_safe_state(): 0 V from now on.
            // A command of another phase count than the plant's is not applied.
            if (!g_hal.safe && out.n_phases == n_ph) {
                for (int k = 0; k < n_ph; ++k) {
                    v_cmd[k] = mcsim::to_double(out.v_V[k]);
                }
            }
        }
        double v_app[3] = {0.0, 0.0, 0.0};
        mcsim::Amplifier amp = g_hal.amp;
        amp.v_max_V = v_supply;
        if (g_hal.amp_output) {
            for (int k = 0; k < n_ph; ++k) {
                v_app[k] = amp.apply(v_cmd[k]);
            }
        } else if (g_hal.board != nullptr) {
            g_hal.board->apply(n_ph, v_cmd, v_supply, v_app);
        } else {
            // the inverter, with the leg currents at the sampling instant
            // held over the period (switched: the period's record only)
            if (n_ph == 3) {
                g_hal.inverter->apply(3, v_cmd, i_true, v_bus_true, v_app);
            } else {
                for (int k = 0; k < n_ph; ++k) {
                    v_app[k] = g_hal.inverter->winding_voltage(v_cmd[k], i_true[k], v_bus_true);
                }
            }
        }
        p.v_a_cmd_V = v_cmd[0];
        p.v_b_cmd_V = v_cmd[1];
        p.v_c_cmd_V = v_cmd[2];
        p.v_a_V = v_app[0];
        p.v_b_V = v_app[1];
        p.v_c_V = v_app[2];

        if (g_hal.monitor != nullptr) {
            g_hal.monitor(g_hal.monitor_ctx, &p);
        }
        // The voltage computed from this sample's currents acts d Ts later
        // (d = compute_delay); until then the last one holds. d = 0 is one
        // step, exactly as without a delay.
        if (g_hal.pwm && g_hal.board == nullptr) {
            // the legs switched at the carrier: the last command's duties
            // before d Ts, this one's after (model/switched_pwm.h)
            double d_new[mcsim::SwitchedPwm::kMaxLegs];
            const int legs = mcsim::SwitchedPwm::leg_duties(*g_hal.inverter, n_ph, v_cmd, v_bus_true, d_new);
            mcsim::PlantLoad load(plant);
            g_hal.pwm->run_period(load, g_hal.d_prev, d_new, g_hal.delay * g_hal.ts_s, v_bus_true);
            for (int k = 0; k < legs; ++k) {
                g_hal.d_prev[k] = d_new[k];
            }
        } else if (g_hal.delay > 0.0) {
            plant.step_phases(g_hal.v_prev, g_hal.delay * g_hal.ts_s);
            if (g_hal.delay < 1.0) {
                plant.step_phases(v_app, (1.0 - g_hal.delay) * g_hal.ts_s);
            }
        } else {
            plant.step_phases(v_app, g_hal.ts_s);
        }
        for (int k = 0; k < 3; ++k) {
            g_hal.v_prev[k] = v_app[k];
        }
        ++g_hal.tick;
    }
    return n_periods;
}

extern "C" {

uint32_t hal_control_rate_hz(void)
{
    return static_cast<uint32_t>(std::lround(1.0 / g_hal.ts_s));
}

bool hal_start(hal_control_fn fn, void* ctx)
{
    if (g_hal.plant == nullptr || g_hal.sensor == nullptr) {
        g_hal.error = "hal_start: no plant attached (call hal_sw_plant_attach first)";
        return false;
    }
    if (fn == nullptr) {
        g_hal.error = "hal_start: control callback is NULL";
        return false;
    }
    if (g_hal.pwm_ratio_bad) {
        return false;  // hal_last_error() says why (set_inverter)
    }
    g_hal.control = fn;
    g_hal.control_ctx = ctx;
    g_hal.started = true;
    g_hal.safe = false;
    g_hal.tick = 0;
    g_hal.t_start_s = g_hal.plant->time_s();
    return true;
}

void hal_safe_state(void) { g_hal.safe = true; }

uint32_t hal_time_us(void)
{
    // Wraps like the 32-bit microsecond counter of a real board.
    const double us = static_cast<double>(g_hal.tick) * g_hal.ts_s * 1e6;
    return static_cast<uint32_t>(static_cast<std::uint64_t>(std::llround(us)));
}

const char* hal_last_error(void) { return g_hal.error; }

bool hal_can_send(const hal_can_frame_t* f)
{
    return g_hal.can != nullptr && f != nullptr && g_hal.can->send(g_hal.can->ctx, f);
}

bool hal_can_receive(hal_can_frame_t* f)
{
    return g_hal.can != nullptr && f != nullptr && g_hal.can->receive(g_hal.can->ctx, f);
}

}  // extern "C"
