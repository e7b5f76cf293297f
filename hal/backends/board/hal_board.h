/*
 * hal_board.h - the DAC/ADC board backend of hal/include/hal/hal.h on a
 * real card through Comedi (board_comedi.h): each control period reads the
 * phase currents (and the bus) on the A/D channels of the board's map,
 * converts them through the signal chain (board_chain.h) into the HAL's
 * sample, calls the registered control callback, and writes its phase
 * voltages through the chain on the D/A channels. hal_board_open() sets
 * every output to 0 V and measures the current sensors' offsets before
 * anything can run; an offset out of range refuses to start. The safe
 * state writes 0 V on every phase and stops calling back.
 *
 * Pacing is the caller's: hal_board_run_realtime() runs the periods in the
 * Linux real-time loop (rt_loop.h); a test steps hal_board_period() itself
 * (virtual time, e.g. in lock-step with a plant process).
 */
#ifndef HAL_BOARD_H
#define HAL_BOARD_H

#include <stdbool.h>
#include <stdint.h>

#include "board_chain.h"
#include "hal/hal.h"
#include "rt_loop.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Opens device for the map of cfg, 0 V out, calibrates over
 * calibration_samples reads. fs_hz is the control rate. False with why in
 * err (nothing driven). */
bool hal_board_open(const board_chain_config_t *cfg, const char *device, int calibration_samples, uint32_t fs_hz,
                    char *err, int err_len);

/* The calibrated chain (offsets), for reports. */
const board_chain_t *hal_board_chain(void);

/* One control period. False once in the safe state or after an I/O error
 * (then in the safe state, hal_last_error() says why). */
bool hal_board_period(void);

/* n_periods periods paced by the real-time loop. */
void hal_board_run_realtime(uint64_t n_periods, int priority, rt_loop_stats_t *st);

/* Safe state and close. */
void hal_board_close(void);

#ifdef __cplusplus
}
#endif

#endif /* HAL_BOARD_H */
