/*
 * board.h - what differs between boards with an STM32F405: one constant
 * table per board (boards/<name>.c), chosen at link time. Pins, the
 * current and bus-voltage signal chains, the power stage (topology, PWM
 * frequency, dead time, break input), CAN, the watchdog. The node id and
 * the dead time here are the defaults of the board's parameters
 * (firmware/config/board_params.toml, checked against this table); the
 * drive's configuration is designed on the board from the drive's
 * parameters (app_params.h).
 */
#ifndef STM32_BOARD_H
#define STM32_BOARD_H

#include <stdbool.h>
#include <stdint.h>

#include "gpio.h"
#include "pwm_tim1.h"

typedef enum {
    BOARD_CONTROL_ADC = 0, /* the control step on ADC1's end of injected conversions (TIM1 TRGO) */
    BOARD_CONTROL_TIM2 = 1 /* on TIM2's update (QEMU: no TIM1, no triggered ADC modelled) */
} board_control_source_t;

typedef struct {
    const char *name;
    /* clocks: hse_hz 0 runs on the internal 16 MHz oscillator (QEMU) */
    uint32_t hse_hz, sysclk_hz;
    /* power stage */
    pwm_topology_t topology;
    uint8_t n_phases;                 /* 3 (three half-bridges) or 2 (two full bridges) */
    uint32_t pwm_hz, control_hz, dead_time_ns;
    gpio_pin_t pwm_pins[6];           /* CH1-3 then CH1N-3N (3 phases), or CH1-4 (2 phases),
                                       * or TIM1's CH2, CH3, CH2N, CH3N (PWM_TWO_BRIDGES_TIM1_TIM8) */
    gpio_pin_t pwm_pins_2[6];         /* PWM_TWO_BRIDGES_TIM1_TIM8: TIM8's CH2, CH3, CH2N, CH3N; else none */
    gpio_pin_t pins_held_low[4];      /* gate inputs of legs no winding uses: outputs held low (switches off) */
    bool break_enable, break_active_high;
    gpio_pin_t break_pin;
    bool has_gate_enable;
    gpio_pin_t gate_enable;           /* the gate driver's enable, high = on */
    /* gate drivers configured over SPI3 (drv8301.h): 0 none (the
     * amplifiers at the fixed amp_gain below); else each on its chip
     * select, all with the same control registers, written at start-up
     * with EN_GATE high and read back (a difference refuses the start);
     * the amplifiers' gain is then the GAIN field read back from them, and
     * amp_gain is not used */
    uint8_t gate_drivers;             /* 0..2 */
    gpio_pin_t gate_driver_cs[2];     /* their chip selects, active low */
    const char *gate_driver_name[2];  /* in the error texts */
    gpio_pin_t spi_pins[3];           /* SPI3's SCK, MISO, MOSI (AF6) */
    uint32_t spi_max_hz;              /* the SPI clock at most this (APB1 / 2..256) */
    uint16_t gate_driver_ctrl1, gate_driver_ctrl2; /* the control registers' 11 data bits */
    uint32_t gate_driver_settle_us;   /* from EN_GATE high to the first frame */
    /* the gate drivers' nFAULT (active low, open drain, pulled up): low at
     * start refuses it; low at a control sample is the trip (the sample's
     * HAL_STATUS_PWM_TRIP, then the fault state) */
    bool gate_fault_enable;
    gpio_pin_t gate_fault;
    gpio_pin_t led_status, led_fault;
    /* currents: phase k on ADC(k+1), channel current_channel[k]; the bus on
     * ADC1 after phase a */
    board_control_source_t control;
    uint32_t control_timer_hz;        /* BOARD_CONTROL_TIM2: TIM2's input clock */
    uint8_t current_channel[3];
    uint8_t vbus_channel;
    gpio_pin_t analog_pins[4];
    float adc_vref_V;                 /* full scale of the 12-bit converter */
    float shunt_ohm, amp_gain;        /* i = (code - zero) vref/4096 / (gain R) * current_sign; the
                                       * gain amp_gain, or the gate drivers' (gate_drivers > 0) */
    float current_sign;
    float vbus_divider;               /* (R1 + R2)/R2 */
    uint32_t zero_nominal_code, zero_tolerance_code;
    /* CAN */
    bool can_enable;
    gpio_pin_t can_rx, can_tx;
    uint32_t can_bitrate;
    uint8_t can_node;
    /* watchdog: 0 = none */
    uint32_t watchdog_us;
    /* an incremental encoder's port on TIM3 (encoder_tim.h; the one
     * encoder timer this backend drives): A on CH1, B on CH2, the index on
     * CH3 (captured). Run when the board has the port and the image's
     * drive's parameters give counts per turn (encoder_counts > 0,
     * stm32_backend_configure); each control sample then carries its
     * angle (has_angle, angle_rad). */
    bool encoder_port;
    gpio_pin_t encoder_a, encoder_b, encoder_index;
    uint8_t encoder_filter;           /* ICxF, 0..15 */
    bool encoder_index_enable;        /* an encoder with an index wired to encoder_index */
    uint32_t encoder_index_count;     /* where the index is, counts from the rotor's angle zero */
    uint32_t encoder_index_tolerance; /* counts a later index may be off */
    uint32_t encoder_max_rev_s;       /* no motor on the board turns faster: a larger step is an error */
    /* a step/dir input (step_dir.h) on TIM5: STEP on TIM5_CH1, DIR a pin
     * of EXTI lines 0-4 (their own interrupts). Run when the image's
     * drive is a position drive: the step count times step_angle_rad is
     * its target (trajectory/step_shaper.h), within the move limits below,
     * which must not exceed the drive configuration's (its design's w_max,
     * a_max: the drive refuses faster moves). */
    bool step_dir_enable;
    gpio_pin_t step_pin, dir_pin;
    uint8_t step_filter;              /* IC1F, 0..15 */
    bool dir_invert;                  /* DIR high counts down */
    float step_angle_rad;             /* the target's move a step: the motor's step over the sender's microsteps */
    float step_speed_max_rad_s, step_accel_max_rad_s2;
} board_t;

extern const board_t board;

#endif /* STM32_BOARD_H */
