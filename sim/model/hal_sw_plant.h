// hal_sw_plant.h - extras of the software-plant HAL backend (host tests and
// the simulator). The backend implements hal/include/hal/hal.h by stepping
// a simulated motor: each period it samples the currents through the
// sensor model, calls the registered control callback, passes the returned
// voltages through the amplifier model and integrates the plant over the
// period with those voltages held. Time is simulated: nothing waits on a
// clock, and hal_sw_plant_run() advances as fast as the host allows.
//
// Typical use:
//   hal_sw_plant_attach(&plant, &sensor, amp, 1e-4);
//   hal_start(my_callback, &my_ctx);
//   hal_sw_plant_run(n);  // n periods, synchronously
#ifndef HAL_SW_PLANT_H
#define HAL_SW_PLANT_H

#include <cstdint>

#include "hal/hal.h"
#include "model/amplifier.h"
#include "model/board_emulation.h"
#include "model/encoder.h"
#include "model/current_sensor.h"
#include "model/fault_injection.h"
#include "model/inverter.h"
#include "model/pm_plant.h"

// What happened in one period, in double precision (for logs and tests).
struct hal_sw_plant_period_t {
    std::uint32_t tick;               // period index since hal_start
    double t_s;                       // plant time at the start of the period (sampling instant)
    int n_phases;                     // the plant's: 2 (stepper) or 3 (PMSM; phase c below)
    double i_a_meas_A, i_b_meas_A;    // sensor output handed to the callback
    double v_a_cmd_V, v_b_cmd_V;      // callback output (0 after hal_safe_state)
    double v_a_V, v_b_V;              // amplifier output held over the period
    double i_c_meas_A, v_c_cmd_V, v_c_V;  // the third phase (0 with two)
    bool control_called;              // false once hal_safe_state() was called
};

// Called once per period after the control callback and before the plant is
// advanced, so the plant still shows the state at the sampling instant.
typedef void (*hal_sw_plant_monitor_fn)(void* ctx, const hal_sw_plant_period_t* period);

// Connects the backend to a plant and a sensor (not owned; they must outlive
// the run). ts_s is the control period: hal_control_rate_hz() = 1/ts_s.
// The amplifier clamps each output to +-amp.v_max_V: a winding's H-bridge
// (2 phases; the bus the drive sees is v_max) or a leg about the bus
// midpoint (3 phases; the bus is 2 v_max).
void hal_sw_plant_attach(mcsim::PmPlant* plant, mcsim::CurrentSensor* sensor,
                         const mcsim::Amplifier& amp, double ts_s);

// Disconnects the plant and resets the backend (callback, tick, monitor).
void hal_sw_plant_detach(void);

// The computation delay of a real drive, as a fraction d in [0, 1] of the
// sample (scenario key [run] compute_delay_samples): the voltage computed
// from the currents sampled at t_k acts from t_k + d Ts to t_(k+1) + d Ts,
// the previous one before (a DAC card writes its outputs when the
// computation ends; an MCU's PWM loads its shadow registers a whole period
// later: d = 1). 0 after attach. False (and no change) outside [0, 1].
bool hal_sw_plant_set_compute_delay(double fraction);

// A CAN bus behind hal_can_send/hal_can_receive (sim/can/socketcan.h,
// or a test's); nullptr, or none set since attach: no bus (both return
// false). Not owned; it must outlive the run.
struct hal_sw_plant_can_t {
    void* ctx;
    bool (*send)(void* ctx, const hal_can_frame_t* f);  // false: not taken
    bool (*receive)(void* ctx, hal_can_frame_t* f);     // false: nothing pending
};
void hal_sw_plant_set_can(const hal_sw_plant_can_t* bus);

// Optional observer of every period; pass nullptr to remove.
// Injected faults (sim/model/fault_injection.h) applied each period from
// now on; nullptr: none. The injector must outlive the run.
void hal_sw_plant_set_faults(mcsim::FaultInjector* faults);

void hal_sw_plant_set_monitor(hal_sw_plant_monitor_fn fn, void* ctx);

// A DAC/ADC board between the drive and the plant (motorsim --backend
// board-emulated, model/board_emulation.h): the currents and the bus the
// drive gets come through its sensors and A/D converters instead of the
// current sensor model, the voltages the plant gets through its D/A
// converters and amplifiers instead of the amplifier model. nullptr (or
// none set since attach): the sensor and amplifier models. Not owned.
void hal_sw_plant_set_board(mcsim::BoardEmulation* board);

// A PWM inverter's averaged nonlinearity (model/inverter.h: dead time and
// switching delays, device drops, minimum pulse) instead of the amplifier
// model: each leg's voltage from its command, the bus (the supply as the
// amplifier's, sags included) and the plant's current at the sampling
// instant, held over the period; 3 phases: three legs about the midpoint,
// 2 phases: an H-bridge per winding (Inverter::winding_voltage). nullptr
// (or none set since attach): the amplifier model, as today. A board
// (hal_sw_plant_set_board) takes precedence. Not owned.
// With params().pwm == kSwitched (after attach): the legs switched at the
// carrier instead (model/switched_pwm.h), the plant integrated over each
// switching segment, the currents sampled at the period's boundary (the
// middle of the zero vector V0); the period's record (v_a_V ...) then holds
// the averaged model's voltages for the command and the sampled currents.
// f_pwm times the period must be a whole number (the scenario checks it);
// else hal_start() and hal_sw_plant_run() refuse (false, 0; hal_last_error()).
void hal_sw_plant_set_inverter(const mcsim::Inverter* inverter);

// A position encoder (model/encoder.h): each sample then carries
// has_angle = true and its reading of the rotor's angle; nullptr: none.
void hal_sw_plant_set_encoder(mcsim::Encoder* encoder);

// Runs n periods synchronously and returns how many ran (0 if no plant is
// attached or hal_start() was not called). After hal_safe_state() the plant
// keeps running with 0 V on both phases (the amplifiers hold 0 V, the
// windings stay connected) and the callback is no longer called.
std::uint32_t hal_sw_plant_run(std::uint32_t n_periods);

// True after hal_safe_state() (until the next hal_start()).
bool hal_sw_plant_in_safe_state(void);

// The last period, valid after at least one hal_sw_plant_run() period.
const hal_sw_plant_period_t* hal_sw_plant_last_period(void);

#endif  // HAL_SW_PLANT_H
