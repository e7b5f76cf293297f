/*
 * odrive36.c - the board table of the ODrive v3.6 (ODrive Robotics' open
 * two-axis board: STM32F405RG, two DRV8301 gate drivers with their
 * current amplifiers, low-side shunts on legs B and C of each axis), for
 * a 2-phase stepper: winding a across axis M0's legs B and C (TIM1),
 * winding b across axis M1's legs B and C (TIM8), the two timers counting
 * in phase (pwm_tim1.h, PWM_TWO_BRIDGES_TIM1_TIM8). Values from the ODrive
 * firmware's hardware configuration, github.com/odriverobotics/ODrive,
 * Firmware/Board/v3 (v3.5/v3.6 branch of Inc/main.h, board.cpp,
 * Inc/board.h, Src/adc.c, Src/main.c), and the v3.6 schematic:
 *   - 8 MHz crystal (Src/main.c SystemClock_Config: HSE, PLLM 4, PLLN 168,
 *     PLLP 2 -> 168 MHz; APB1 /4, APB2 /2, 5 wait states: clock.h's plan);
 *   - M0: TIM1 CH1-3 on PA8, PA9, PA10 (M0_AH/BH/CH), CH1N-3N on PB13,
 *     PB14, PB15 (M0_AL/BL/CL), AF1; M1: TIM8 CH1-3 on PC6, PC7, PC8
 *     (M1_AH/BH/CH), CH1N-3N on PA7, PB0, PB1 (M1_AL/BL/CL), AF3 (DS8626
 *     table 9); legs A (M0_AH/AL, M1_AH/AL) are not used: held low;
 *   - EN_GATE of both DRV8301 on PB12 (main.h EN_GATE_Pin; board.cpp: "EN
 *     pin (shared between both motors)"); their nFAULT, shared, on PD2
 *     (main.h nFAULT_Pin; board.cpp "nFAULT pin (shared between both
 *     motors)"), open drain, active low: read with the pull-up at start
 *     (low: the start refused) and at every control sample (low: the trip,
 *     both bridges off, the fault state);
 *   - both DRV8301 on SPI3 (board.cpp: m0_gate_driver, m1_gate_driver on
 *     spi3_arbiter), each its own chip select: M0 nCS PC13, M1 nCS PC14
 *     (main.h M0_nCS_Pin, M1_nCS_Pin); SCK PC10, MISO PC11, MOSI PC12, AF6
 *     (Src/spi.c HAL_SPI_MspInit: GPIO_AF6_SPI3; DS8626 table 9); mode 1
 *     (CPOL 0, CPHA 1), 16-bit words, APB1 / 16 = 2.625 MHz (Src/spi.c
 *     MX_SPI3_Init: the vendor's clock);
 *     EN_GATE high 10 ms before the first word (the vendor's
 *     Drv8301::init waits as long);
 *   - currents: M0_IB PC0 (ADC123_IN10), M0_IC PC1 (IN11), M1_IC PC2
 *     (IN12), M1_IB PC3 (IN13) (main.h; Src/adc.c's channel list); shunts
 *     500 uOhm (Inc/board.h SHUNT_RESISTANCE for v3.4 and later); the
 *     current i = (code - 2048) 3.3 V/4096 / gain / R_shunt, positive into
 *     the motor (Firmware/MotorControl/motor.cpp phase_current_from_adcval);
 *   - the DRV8301s' amplifier gain: 80 V/V (control register 2, GAIN = 11,
 *     SLOS719; the reset value is 10 V/V, the vendor writes 40), written
 *     over SPI3 and read back (drv8301.h): +-1.65 V / (80 x 0.5 mOhm) =
 *     +-41.25 A full scale, 20.1 mA a code. Paper 000's stepper runs at
 *     most 3 A (firmware/drives/paper000/boards/odrive36.toml [limits]
 *     i_max_A; the trip 4.5 A): 149 codes at 3 A, 223 at the trip, against
 *     19 and 28 at the reset gain; 40 V/V (+-82.5 A) would halve them for
 *     a range this motor never uses. The backend scales the samples with
 *     the gain read back from the chips (amp_gain is not used);
 *   - control register 1: over-current latch mode (OCP_MODE = 01: an
 *     over-current turns the FETs off and pulls nFAULT low, which stops
 *     the drive), V_DS threshold OC_ADJ_SET = 0, the lowest, 0.060 V
 *     (SLOS719's OC_ADJ_SET table): 24 A through the 2.5 mOhm
 *     docs/plant.md assumes for the 24 V board's NTMFS4935N, about 12 A
 *     scaled from the vendor's note that its 0.730 V is "approximately
 *     150A at 100degC" (drv8301.cpp, for motors of tens of amperes): above
 *     the stepper's 4.5 A trip, below the 41.25 A full scale; gate current
 *     1.7 A, six PWM inputs (GATE_CURRENT = 00, PWM_MODE = 0);
 *   - bus voltage on PA6 (VBUS_S, ADC12_IN6) through the divider
 *     VBUS_S_DIVIDER_RATIO 11 of the 24 V board (19 for the 48 V one:
 *     Inc/board.h);
 *   - CAN1 on PB8 (RX), PB9 (TX), AF9 (board.cpp gpios CAN_R, CAN_D);
 *   - dead time: TIM_1_8_DEADTIME_CLOCKS = 20 timer clocks at 168 MHz
 *     (main.h): 119 ns;
 *   - no MCU-driven LED (the board's LEDs are power indicators);
 *   - step/dir: the vendor's axis 0 takes STEP on GPIO1 and DIR on GPIO2
 *     (board.cpp: step_gpio_pin 1, dir_gpio_pin 2), PA0 and PA1 (board.cpp
 *     gpios[]); PA0's AF2 is TIM5_CH1 (board.cpp alternate_functions:
 *     GPIO1 GPIO_AF2_TIM5; DS8626 table 9): STEP clocks TIM5, DIR is EXTI
 *     line 1.
 * The vendor runs 24 kHz (TIM_1_8_PERIOD_CLOCKS 3500) with TIM8 a quarter
 * period behind TIM1 (board.cpp start_synchronised offsets); this image
 * runs the backend's 20 kHz with both timers in phase and the control
 * step at 10 kHz, the drive's Ts.
 */
#include "boards/board.h"
#include "drv8301.h"

/* two full bridges: a 2-phase stepper (boards/odrive36.cmake says the same
 * to the configure-time check of a drive's needs) */
#define ODRIVE36_PHASES 2
#ifdef MC_BOARD_PHASES
_Static_assert(MC_BOARD_PHASES == ODRIVE36_PHASES, "boards/odrive36.cmake and boards/odrive36.c disagree on the phase count");
#endif

#define PIN(port, pin, af) {(port), (pin), (af)}
#define NO_PIN {0xFFu, 0u, 0u}
enum { PA = 0, PB = 1, PC = 2, PD = 3 };
/* DS8626 table 9: TIM1 on AF1, TIM8 on AF3, CAN1 on AF9 */
#define AF_TIM1 1u
#define AF_TIM8 3u
#define AF_CAN1 9u
#define AF_SPI3 6u

const board_t board = {
    .name = "ODrive v3.6 (STM32F405RG, two DRV8301)",
    .hse_hz = 8000000u,
    .sysclk_hz = 168000000u,
    .topology = PWM_TWO_BRIDGES_TIM1_TIM8,
    .n_phases = (uint8_t)ODRIVE36_PHASES,
    .pwm_hz = 20000u,
    .control_hz = 10000u,
    /* 20 clocks of 168 MHz (main.h TIM_1_8_DEADTIME_CLOCKS): pwm_plan
     * rounds 119 ns up to 20 clocks */
    .dead_time_ns = 119u,
    /* winding a: M0 leg B (CH2/CH2N), leg C (CH3/CH3N) */
    .pwm_pins = {PIN(PA, 9, AF_TIM1), PIN(PA, 10, AF_TIM1), PIN(PB, 14, AF_TIM1), PIN(PB, 15, AF_TIM1), NO_PIN, NO_PIN},
    /* winding b: M1 leg B (CH2/CH2N), leg C (CH3/CH3N) */
    .pwm_pins_2 = {PIN(PC, 7, AF_TIM8), PIN(PC, 8, AF_TIM8), PIN(PB, 0, AF_TIM8), PIN(PB, 1, AF_TIM8), NO_PIN, NO_PIN},
    /* legs A of both axes: M0_AH, M0_AL, M1_AH, M1_AL */
    .pins_held_low = {PIN(PA, 8, 0), PIN(PB, 13, 0), PIN(PC, 6, 0), PIN(PA, 7, 0)},
    /* no timer break input is wired on the ODrive (the DRV8301s' nFAULT
     * goes to PD2, a GPIO, read at each control sample below) */
    .break_enable = false,
    .break_active_high = false,
    .break_pin = NO_PIN,
    .has_gate_enable = true,
    .gate_enable = PIN(PB, 12, 0),
    /* both DRV8301 on SPI3: M0's amplifier measures winding a, M1's b */
    .gate_drivers = 2u,
    .gate_driver_cs = {PIN(PC, 13, 0), PIN(PC, 14, 0)},
    .gate_driver_name = {"M0 (nCS PC13)", "M1 (nCS PC14)"},
    .spi_pins = {PIN(PC, 10, AF_SPI3), PIN(PC, 11, AF_SPI3), PIN(PC, 12, AF_SPI3)},
    .spi_max_hz = 2625000u,
    .gate_driver_ctrl1 = (uint16_t)(DRV8301_CTRL1_OCP_LATCH | DRV8301_CTRL1_OC_ADJ(0u)),
    .gate_driver_ctrl2 = (uint16_t)DRV8301_CTRL2_GAIN(DRV8301_GAIN_80),
    .gate_driver_settle_us = 10000u,
    .gate_fault_enable = true,
    .gate_fault = PIN(PD, 2, 0),
    .led_status = NO_PIN,
    .led_fault = NO_PIN,
    .control = BOARD_CONTROL_ADC,
    /* winding a on ADC1: M0_IB (IN10), then the bus (IN6); winding b on
     * ADC2: M1_IB (IN13); one trigger, TIM1's TRGO (adc_inj.h) */
    .current_channel = {10u, 13u, 0u},
    .vbus_channel = 6u,
    .analog_pins = {PIN(PC, 0, 0), PIN(PC, 3, 0), PIN(PA, 6, 0), NO_PIN},
    .adc_vref_V = 3.3f,
    .shunt_ohm = 0.0005f,
    /* amp_gain: not used, the gain read back from the DRV8301s (80 V/V,
     * gate_driver_ctrl2 above) */
    .amp_gain = 0.0f,
    /* leg B's current into the motor is winding current: the vendor's
     * sign (motor.cpp), +1 */
    .current_sign = 1.0f,
    .vbus_divider = 11.0f,
    /* zero at mid-scale 2048 +- 150 codes (as the VESC 6; 150 codes are
     * 3.0 A at 80 V/V, a current that cannot flow with the bridges off,
     * and 1.5 mV at the amplifiers' inputs: whether the DRV8301s' offset
     * stays inside it is for the board to show) */
    .zero_nominal_code = 2048u,
    .zero_tolerance_code = 150u,
    .can_enable = true,
    .can_rx = PIN(PB, 8, AF_CAN1),
    .can_tx = PIN(PB, 9, AF_CAN1),
    .can_bitrate = 1000000u,
    .can_node = 0u,
    /* 10 ms: 100 control periods, as the VESC 6 */
    .watchdog_us = 10000u,
    .encoder_port = false,
    .encoder_a = NO_PIN,
    .encoder_b = NO_PIN,
    .encoder_index = NO_PIN,
    .step_dir_enable = true,
    .step_pin = PIN(PA, 0, 2u),
    .dir_pin = PIN(PA, 1, 0),
    /* IC1F = 3: 8 samples at TIM5's 84 MHz (RM0090 18.4.7): a STEP pulse
     * under 95 ns is rejected (step/dir senders hold STEP high 1 us or
     * more) */
    .step_filter = 3u,
    .dir_invert = false,
    /* 1/16 microsteps of a 200-step motor (paper 000's stepper: 50 pole
     * pairs, 200 full steps a turn): 2 pi / 3200 rad a step; set it for
     * your motor and your sender's microstepping */
    .step_angle_rad = 6.28318530718f / 3200.0f,
    /* the move limits of paper 000's configuration for this board
     * (firmware/drives/paper000/boards/odrive36.toml [bounds]: 20 rad/s,
     * 40 rad/s^2, which design/paper000_design.c makes its
     * move_speed_max_rad_s, move_accel_max_rad_s2): no faster */
    .step_speed_max_rad_s = 20.0f,
    .step_accel_max_rad_s2 = 40.0f,
};
