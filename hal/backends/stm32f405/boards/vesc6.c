/*
 * vesc6.c - the board table of the VESC 6 (Benjamin Vedder's open
 * hardware ESC: STM32F405RG, DRV8301 gate driver with its current
 * amplifiers, three low-side phase shunts; the values below are from its
 * published schematic and the hardware configuration hw_60.h of the VESC
 * firmware, github.com/vedderb/bldc and vedderb/bldc-hardware):
 *   - 8 MHz crystal; TIM1 CH1-3 on PA8, PA9, PA10 and CH1N-3N on PB13,
 *     PB14, PB15 (AF1); DRV8301 EN_GATE on PB5; LEDs green PB0, red PB1;
 *   - phase currents on PC0, PC1, PC2 (ADC123_IN10, IN11, IN12): 0.5 mOhm
 *     shunts, amplifier gain 20, 3.3 V reference, zero at mid-scale;
 *   - bus voltage on PC3 (ADC123_IN13) through 39 kOhm / 2.2 kOhm;
 *   - CAN1 on PB8 (RX), PB9 (TX), AF9;
 *   - the Hall/encoder port: hw_60.h's "Hall/encoder pins" HW_HALL_ENC_PIN1-3
 *     PC6, PC7, PC8 on HW_ENC_TIM TIM3 (its encoder driver counts A and B on
 *     TIM3 and takes the index on PC8); the alternate function AF2 is
 *     TIM3_CH1, CH2, CH3 on PC6, PC7, PC8 (DS8626 table 9, alternate
 *     function mapping): A on CH1, B on CH2, the index captured on CH3.
 * The VESC 6 routes no comparator to a TIM1 break pin (the DRV8301 limits
 * the current cycle by cycle itself): the break input is enabled on PA6
 * (TIM1_BKIN, AF1), active low with the pull-up, for a board that wires
 * the DRV8301's nOCTW to it; leave it unconnected and it never fires.
 * Dead time 500 ns (the DRV8301's own minimum is 50 ns; 500 ns covers
 * the VESC 6's MOSFETs' turn-off). 20 kHz PWM, control at 10 kHz.
 * The drive is the image's (MC_DRIVE), designed on the board from its
 * parameters: their values for this board,
 * firmware/drives/<drive>/boards/vesc6[_<variant>]_params.c, come from the
 * scenario beside it; over CAN they change and are saved (app_params.h).
 */
#include "boards/board.h"

/* three half-bridges: a 3-phase motor (boards/vesc6.cmake says the same
 * to the configure-time check of a drive's needs) */
#define VESC6_PHASES 3
#ifdef MC_BOARD_PHASES
_Static_assert(MC_BOARD_PHASES == VESC6_PHASES, "boards/vesc6.cmake and boards/vesc6.c disagree on the phase count");
#endif

#define PIN(port, pin, af) {(port), (pin), (af)}
#define NO_PIN {0xFFu, 0u, 0u}
enum { PA = 0, PB = 1, PC = 2 };

const board_t board = {
    .name = "VESC 6 (STM32F405RG, DRV8301)",
    .hse_hz = 8000000u,
    .sysclk_hz = 168000000u,
    .topology = PWM_THREE_HALF_BRIDGES,
    .n_phases = (uint8_t)VESC6_PHASES,
    .pwm_hz = 20000u,
    .control_hz = 10000u,
    .dead_time_ns = 500u,
    .pwm_pins = {PIN(PA, 8, 1), PIN(PA, 9, 1), PIN(PA, 10, 1), PIN(PB, 13, 1), PIN(PB, 14, 1), PIN(PB, 15, 1)},
    .pwm_pins_2 = {NO_PIN, NO_PIN, NO_PIN, NO_PIN, NO_PIN, NO_PIN},
    .pins_held_low = {NO_PIN, NO_PIN, NO_PIN, NO_PIN},
    .break_enable = true,
    .break_active_high = false,
    .break_pin = PIN(PA, 6, 1),
    .has_gate_enable = true,
    .gate_enable = PIN(PB, 5, 0),
    .led_status = PIN(PB, 0, 0),
    .led_fault = PIN(PB, 1, 0),
    .control = BOARD_CONTROL_ADC,
    .current_channel = {10u, 11u, 12u},
    .vbus_channel = 13u,
    .analog_pins = {PIN(PC, 0, 0), PIN(PC, 1, 0), PIN(PC, 2, 0), PIN(PC, 3, 0)},
    .adc_vref_V = 3.3f,
    .shunt_ohm = 0.0005f,
    .amp_gain = 20.0f,
    /* the DRV8301's amplifiers: a current out of the phase (into the low
     * side) lowers the output */
    .current_sign = -1.0f,
    .vbus_divider = (39000.0f + 2200.0f) / 2200.0f,
    /* zero at mid-scale 2048 +- 150 codes (+-0.12 V: the amplifiers'
     * offset after the DRV8301's DC calibration is a few mV; 150 codes is
     * 12 A here, a current that should not be flowing with the bridges off) */
    .zero_nominal_code = 2048u,
    .zero_tolerance_code = 150u,
    .can_enable = true,
    .can_rx = PIN(PB, 8, 9),
    .can_tx = PIN(PB, 9, 9),
    .can_bitrate = 1000000u,
    .can_node = 0u,
    /* 10 ms: 100 control periods; LSI at its 47 kHz worst case makes it 6.8 ms */
    .watchdog_us = 10000u,
    .encoder_port = true,
    .encoder_a = PIN(PC, 6, 2),
    .encoder_b = PIN(PC, 7, 2),
    .encoder_index = PIN(PC, 8, 2),
    /* ICxF = 1: two samples at TIM3's 84 MHz (RM0090 18.4.7): a pulse
     * under 24 ns is rejected; at the fastest motor below and 8192 counts a
     * turn an edge comes every 36 ns, still counted */
    .encoder_filter = 1u,
    /* the index off by default: wire it to PC8 and set where it is */
    .encoder_index_enable = false,
    .encoder_index_count = 0u,
    .encoder_index_tolerance = 4u,
    /* hw_60.h's HW_LIM_ERPM, 200,000 electrical rpm: a motor with one pole
     * pair or more turns at most 3,334 rev/s on this board */
    .encoder_max_rev_s = 3334u,
};
