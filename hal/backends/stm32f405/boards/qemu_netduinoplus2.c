/*
 * qemu_netduinoplus2.c - the board table of QEMU's netduinoplus2 machine
 * (an STM32F405 model) for the image's test under QEMU: what QEMU 7.2
 * models of this SoC is the core, flash and SRAM/CCM, SysTick, TIM2-5,
 * USART, SYSCFG, EXTI; RCC, TIM1, triggered ADC conversions, bxCAN and
 * the IWDG are not (README.md). So: no crystal (the reset clock), the
 * control interrupt from TIM2, no ADC (the test feeds recorded samples),
 * no CAN, no watchdog, no power stage, no gate driver: QEMU maps SPI3
 * (its stm32f2xx-spi) with nothing on the bus (every word reads back 0)
 * and the GPIO ports unimplemented (reads 0), so a DRV8301's configuration
 * would read back 0x000 and its nFAULT (PD2) read low: gate_drivers 0 and
 * gate_fault_enable false (the zero of the fields left out below) skip
 * both, as the ADC is skipped. Everything else is the real image's code:
 * start-up, vector table, the backend's control path.
 */
#include "boards/board.h"

#define NO_PIN {0xFFu, 0u, 0u}
/* the stm32_qemu_hse image asks for the VESC 6's 8 MHz crystal: QEMU's RCC
 * never reports it ready, so the start-up must end in fault 1 */
#ifndef QEMU_BOARD_HSE_HZ
#define QEMU_BOARD_HSE_HZ 0u
#endif

const board_t board = {
    .name = "QEMU netduinoplus2 (STM32F405 model)",
    .hse_hz = QEMU_BOARD_HSE_HZ,
    .sysclk_hz = (QEMU_BOARD_HSE_HZ != 0u) ? 168000000u : 16000000u,
    .topology = PWM_THREE_HALF_BRIDGES,
    .n_phases = 3u,
    .pwm_hz = 20000u,
    .control_hz = 10000u,
    .dead_time_ns = 500u,
    .pwm_pins = {NO_PIN, NO_PIN, NO_PIN, NO_PIN, NO_PIN, NO_PIN},
    .pwm_pins_2 = {NO_PIN, NO_PIN, NO_PIN, NO_PIN, NO_PIN, NO_PIN},
    .pins_held_low = {NO_PIN, NO_PIN, NO_PIN, NO_PIN},
    .break_enable = false,
    .break_pin = NO_PIN,
    .has_gate_enable = false,
    .gate_enable = NO_PIN,
    .led_status = NO_PIN,
    .led_fault = NO_PIN,
    .control = BOARD_CONTROL_TIM2,
    /* QEMU 7.2's STM32F4 timer model counts at 1 GHz whatever the RCC says
     * (hw/arm/stm32f405_soc.c sets its clock-frequency); measured: 100 us
     * between updates with this value (tools/bench/stm32_qemu.py) */
    .control_timer_hz = 1000000000u,
    .analog_pins = {NO_PIN, NO_PIN, NO_PIN, NO_PIN},
    .adc_vref_V = 3.3f,
    .shunt_ohm = 1.0f,
    .amp_gain = 1.0f,
    .current_sign = 1.0f,
    .vbus_divider = 1.0f,
    .can_enable = false,
    .can_rx = NO_PIN,
    .can_tx = NO_PIN,
    .watchdog_us = 0u,
    /* QEMU's timer model counts its clock only (no encoder or capture
     * mode): the recorded sample brings the angle */
    .encoder_port = false,
    .encoder_a = NO_PIN,
    .encoder_b = NO_PIN,
    .encoder_index = NO_PIN,
};
