/*
 * stm32_backend.h - the STM32F405 backend of hal/include/hal/hal.h: the
 * start-up of the board (boards/board.h) and the control interrupt.
 *
 * stm32_backend_init() reads why the chip was reset, sets the clocks, the
 * pins, the PWM with its outputs off, the ADC, measures the current
 * sensors' zero with the bridges off (after the gate drivers' configuration
 * over SPI, drv8301.h, on a board that has it: their amplifiers' gain, read
 * back; nFAULT checked), starts the encoder (the board's port,
 * when the drive's configuration gives its counts per turn), CAN and the
 * watchdog. Any
 * failure ends in the fault state: bridges off (TIM1 MOE = 0, the gate
 * driver disabled), the fault code kept and blinked on the fault LED.
 * Then hal_start() enables the outputs and the control interrupt: at each
 * end of conversion the sample (currents, bus voltage, status bits) goes to
 * the registered callback and its phase voltages to the PWM duties;
 * the watchdog is refreshed by the step, overruns are counted and reported
 * in the next sample's status.
 */
#ifndef STM32_BACKEND_H
#define STM32_BACKEND_H

#include <stdbool.h>
#include <stdint.h>

#include "encoder_tim.h"
#include "hal/hal.h"
#include "stm32_status.h"
#include "step_dir.h"
#include "stm32f405_regs.h"

/* The peripherals the backend drives: the chip's (stm32_hw), or fake
 * blocks in a host test. */
typedef struct {
    rcc_regs_t *rcc;
    flash_regs_t *flash;
    tim_regs_t *tim1, *tim2, *tim3;
    adc_common_regs_t *adc_common;
    adc_regs_t *adc[3];
    can_regs_t *can1;
    iwdg_regs_t *iwdg;
    gpio_regs_t *gpio[5]; /* ports A-E */
    tim_regs_t *tim8;     /* the second bridge timer (PWM_TWO_BRIDGES_TIM1_TIM8) */
    tim_regs_t *tim5;     /* the step/dir input's counter (step_dir.h) */
    exti_regs_t *exti;    /* the DIR pin's line */
    syscfg_regs_t *syscfg;
    spi_regs_t *spi3; /* the gate drivers' SPI (drv8301.h) */
} stm32_periph_t;

extern const stm32_periph_t stm32_hw;

/* Start-up of the board on hw; false (and the fault state) on any failure. */
bool stm32_backend_init(const stm32_periph_t *hw);

/* What the image's parameters set in the backend (config/board_params.h
 * and the drive's encoder_counts): the node's CAN id (the receive
 * filter), the bridges' dead time, the encoder port's counts a turn (0:
 * not read). Before stm32_backend_init: what it starts with (never
 * called: the board's table, no encoder). After: each part that changed
 * applied at once (the dead time's DTG, the encoder counted again from
 * zero, the filter), for the control interrupt to call while the drive is
 * disabled. STM32_OK, or why not: STM32_FAULT_PWM_PLAN (a dead time the
 * timer cannot make), STM32_FAULT_ENCODER_CONFIG (counts the encoder
 * cannot run, or a board without the port), STM32_FAULT_CAN_TIMING (a
 * node above 15); a refusal is not the fault state. */
stm32_status_t stm32_backend_configure(uint8_t can_node, uint32_t dead_time_ns, uint32_t encoder_counts);

/* pause: the bridges' outputs off (MOE = 0: every switch off, the gate
 * drivers kept configured) while the control interrupt goes on, as a
 * flash write needs (flash.h: refused while MOE is set); !pause: back on,
 * unless a fault or hal_safe_state stopped them meanwhile (then false).
 * Callable from the main loop (interrupts masked around the change). */
bool stm32_backend_pause(bool pause);

/* TIM1's break: what its interrupt does (the hardware already turned the
 * outputs off): the fault state with STM32_FAULT_OVERCURRENT_BREAK. */
void stm32_backend_break(void);

/* The fault state: bridges off, code kept; callable from any context.
 * Does not return when called from a handler of a CPU fault (it blinks). */
void stm32_backend_fault(stm32_status_t why);

/* The code of the fault state, STM32_OK if none. */
stm32_status_t stm32_backend_status(void);

/* The body of the control interrupt: sample in, callback, PWM out.
 * Called by the board's interrupt (ADC or TIM2) with the sample it read. */
void stm32_backend_control(hal_sample_t *in);

/* The sample of one control period as the board's converters and
 * sensors give it (the ADC interrupt's part before the callback): the
 * phase currents and the bus from the injected conversions, the trip and
 * converter status, and with the board's encoder running its angle
 * (has_angle; withheld once the encoder latched an error, whose code
 * stm32_backend_encoder() keeps and hal_last_error() names). With the
 * gate drivers' nFAULT watched (board_t.gate_fault_enable) and low while
 * running: the bridges off at once, HAL_STATUS_PWM_TRIP in the sample, and
 * the fault state STM32_FAULT_GATE_DRIVER_NFAULT once stm32_backend_control
 * has handed the drive that sample. */
void stm32_backend_sample(hal_sample_t *in);

/* The encoder's state (encoder_tim.h), or NULL if the image runs none. */
const encoder_t *stm32_backend_encoder(void);

/* The step/dir input's count of steps (step_dir.h); false if the board
 * runs none. */
bool stm32_backend_step_count(int32_t *count);

/* The DIR line's interrupt body (EXTI0-4 handlers call it). */
void stm32_backend_dir_edge(void);

/* Counters for telemetry and tests. */
uint32_t stm32_backend_overruns(void);
uint32_t stm32_backend_steps(void);

/* Idle work of the main loop: the LEDs (status blinks at 1 Hz while
 * running; the fault LED blinks the fault code). */
void stm32_backend_idle(void);

#endif /* STM32_BACKEND_H */
