/*
 * hal.h - the one hardware interface the drive runs on.
 *
 * Modelled on NuttX's FOC lower half: the control code registers one
 * callback that the backend calls at the PWM rate (10 kHz) with the phase
 * current samples; the callback returns the phase voltages the backend
 * applies until the next call. Backends are chosen at link time (exactly
 * one of hal/backends/<name> is linked): the software plant (host tests and
 * simulator), a dSpace-like DAC/ADC board, an MCU drive. The data of one
 * period (2 or 3 phase currents, bus voltage, optional position sensor,
 * status; phase voltages back) is in hal_types.h, which the control code
 * reads; nothing in firmware/ includes this header or knows which backend
 * it runs on. All values are SI (A, V, s) in the firmware numeric type mc_t.
 */
#ifndef HAL_HAL_H
#define HAL_HAL_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal_types.h"
#include "math/mc_type.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Called once per period; must fill *out. Runs in interrupt context on MCUs. */
typedef void (*hal_control_fn)(void *ctx, const hal_sample_t *in, hal_command_t *out);

/* Period of the control interrupt, in Hz (10000 for every backend here). */
uint32_t hal_control_rate_hz(void);

/* Registers the callback and enables the power stage. Returns false and
 * sets hal_last_error() if the backend cannot start. */
bool hal_start(hal_control_fn fn, void *ctx);

/* Puts the power stage in its safe state (all phases at 0 V / outputs off)
 * and stops calling the callback. Safe to call from the callback. */
void hal_safe_state(void);

/* Time since hal_start in microseconds (wraps after 71 minutes). */
uint32_t hal_time_us(void);

/* CAN, optional (a backend without a bus returns false from both). Both
 * are non-blocking and may be called from the control callback.
 * hal_can_send: false when there is no bus or no room to transmit (the
 * frame was not taken: keep it and try again later).
 * hal_can_receive: false when nothing is pending, else the oldest frame. */
bool hal_can_send(const hal_can_frame_t *f);
bool hal_can_receive(hal_can_frame_t *f);

/* Human-readable reason of the last failure, never NULL. */
const char *hal_last_error(void);

#ifdef __cplusplus
}
#endif

#endif /* HAL_HAL_H */
