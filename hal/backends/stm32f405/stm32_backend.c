/* stm32_backend.c - see stm32_backend.h. Backend state (one power stage
 * per chip) lives here; no algorithm state. */
#include "stm32_backend.h"

#include "adc_inj.h"
#include "boards/board.h"
#include "bxcan.h"
#include "clock.h"
#include "drv8301.h"
#include "encoder_tim.h"
#include "gpio.h"
#include "irq.h"
#include "iwdg.h"
#include "pwm_tim1.h"
#include "stm32f405_regs.h"
#include "math/mc_num.h" /* the sample's conversion to mc_t */

/* the chip's peripherals; host tests pass fake blocks to stm32_backend_init */
const stm32_periph_t stm32_hw = {
    .rcc = (rcc_regs_t *)STM32_RCC_BASE,
    .flash = (flash_regs_t *)STM32_FLASH_IF_BASE,
    .tim1 = (tim_regs_t *)STM32_TIM1_BASE,
    .tim2 = (tim_regs_t *)STM32_TIM2_BASE,
    .tim3 = (tim_regs_t *)STM32_TIM3_BASE,
    .adc_common = (adc_common_regs_t *)STM32_ADC_COMMON_BASE,
    .adc = {(adc_regs_t *)STM32_ADC1_BASE, (adc_regs_t *)STM32_ADC2_BASE, (adc_regs_t *)STM32_ADC3_BASE},
    .can1 = (can_regs_t *)STM32_CAN1_BASE,
    .iwdg = (iwdg_regs_t *)STM32_IWDG_BASE,
    .gpio = {(gpio_regs_t *)STM32_GPIO_BASE(0), (gpio_regs_t *)STM32_GPIO_BASE(1), (gpio_regs_t *)STM32_GPIO_BASE(2),
             (gpio_regs_t *)STM32_GPIO_BASE(3), (gpio_regs_t *)STM32_GPIO_BASE(4)},
    .tim8 = (tim_regs_t *)STM32_TIM8_BASE,
    .tim5 = (tim_regs_t *)STM32_TIM5_BASE,
    .exti = (exti_regs_t *)STM32_EXTI_BASE,
    .syscfg = (syscfg_regs_t *)STM32_SYSCFG_BASE,
    .spi3 = (spi_regs_t *)STM32_SPI3_BASE,
};

#define RCC (g.hw->rcc)
#define FLASH_IF (g.hw->flash)
#define TIM1 (g.hw->tim1)
#define TIM2 (g.hw->tim2)
#define TIM3 (g.hw->tim3)
#define TIM8 (g.hw->tim8)
#define TIM5 (g.hw->tim5)
#define EXTI (g.hw->exti)
#define ADC_COMMON (g.hw->adc_common)
#define CAN1 (g.hw->can1)
#define IWDG (g.hw->iwdg)
#define GPIO(port) (g.hw->gpio[(port)])
#define adc_of (g.hw->adc)
#define SPI3 (g.hw->spi3)

/* Polls of a ready flag before it counts as a timeout: at most 168 MHz and
 * a few cycles a poll, 200000 polls are over 2 ms, beyond every start-up
 * time of the datasheet (HSE 2 ms typ., PLL lock 0.1 ms, ADC 3 us, IWDG
 * register update 5 LSI periods = 0.2 ms); bxCAN's leaving initialisation
 * waits for 11 recessive bits (11 us at 1 Mbit/s). */
#ifndef STM32_TIMEOUT_POLLS
#define STM32_TIMEOUT_POLLS 200000u
#endif
/* (the host tests raise it: their fake hardware answers from another
 * thread, which a loaded machine may not schedule within 2 ms) */
/* Conversions averaged for the current sensors' zero: 256, 12 bits of
 * noise averaged to well under a code. */
#define STM32_ZERO_SAMPLES 256u
/* Share of the PWM period a duty may not exceed: the low-side switches
 * conduct at least 2 % (1 us at 20 kHz) around the sampling instant, so
 * that the shunt sees the phase current. */
#define STM32_DUTY_MAX 0.98f
/* LED blink: status every 0.5 s of steps; fault code: code flashes, pause. */
#define STM32_LED_BLINK_STEPS 5000u

static struct {
    const stm32_periph_t *hw;
    hal_control_fn fn;
    void *ctx;
    bool running;
    bool started;     /* hal_start succeeded: the control interrupt runs from then on, whatever happens */
    bool app_stopped; /* hal_safe_state: the application asked for no more callbacks */
    volatile stm32_status_t fault;
    const char *error;
    uint32_t tick;
    uint32_t steps;
    uint32_t overruns;
    uint32_t conversions;       /* ADC1 JEOC interrupts */
    uint32_t status_next;       /* HAL_STATUS_* bits for the next sample */
    uint32_t zero[3];
    float amps_per_code, volts_per_code;
    pwm_plan_t pwm;
    clock_plan_t clocks;
    bool watchdog;
    bool encoder_on;            /* the board's encoder runs (encoder_tim.h) */
    bool step_dir_on;           /* the board's step/dir input runs (step_dir.h) */
    bool gate_fault_on;         /* the gate drivers' nFAULT is watched at every sample */
    stm32_status_t fault_pending; /* the fault state after this sample's callback */
    float amp_gain;             /* the amplifiers' gain: the board's, or read back from the gate drivers */
    drv8301_bus_t drv;          /* the gate drivers' SPI and its last error (drv8301.h) */
    step_dir_t sd;
    encoder_t enc;
    hal_can_frame_t can_rx[16];
    uint32_t can_rx_head, can_rx_count, can_rx_dropped;
    /* what the drive's parameters set (stm32_backend_configure) */
    bool configured;
    uint8_t can_node;
    uint32_t dead_time_ns, encoder_counts;
    uint32_t apb2_timer_hz;     /* TIM1's clock (the dead time's ticks) */
    bool initialised;           /* stm32_backend_init succeeded */
    bool paused;                /* stm32_backend_pause: the bridges' outputs held off */
} g = {.hw = &stm32_hw};

stm32_status_t stm32_backend_status(void) { return g.fault; }
uint32_t stm32_backend_overruns(void) { return g.overruns; }
uint32_t stm32_backend_steps(void) { return g.steps; }

/* the board's second bridge timer (two timers' legs B and C) */
static bool two_timers(void) { return board.topology == PWM_TWO_BRIDGES_TIM1_TIM8; }

static void bridges_off(void)
{
    pwm_outputs(TIM1, false);
    if (two_timers()) pwm_outputs(TIM8, false);
    if (board.has_gate_enable) {
        gpio_write(GPIO(board.gate_enable.port), board.gate_enable.pin, false);
    }
}

void stm32_backend_fault(stm32_status_t why)
{
    bridges_off();
    if (g.fault == STM32_OK) {
        g.fault = why;
        g.error = stm32_status_text(why);
    }
    if (g.running) {
        /* at run time the drive hears of it at its next sample (a trip:
         * DRIVE_FAULT_HW_TRIP), whatever the cause */
        g.status_next |= HAL_STATUS_PWM_TRIP;
    }
    g.running = false;
    if (board.led_fault.port != 0xFFu) {
        gpio_write(GPIO(board.led_fault.port), board.led_fault.pin, true);
    }
}

static bool fail(stm32_status_t why)
{
    stm32_backend_fault(why);
    return false;
}

static void pin_af(gpio_pin_t p, gpio_pull_t pull)
{
    if (p.port != 0xFFu) gpio_config(GPIO(p.port), p.pin, GPIO_AF, p.af, pull);
}

/* a busy wait of at least n core cycles (each pass takes more than 4) */
static void spin(uint32_t n)
{
    for (volatile uint32_t k = 0; k < n / 4u; ++k) {
    }
}

static bool gate_fault_asserted(void)
{
    return (GPIO(board.gate_fault.port)->IDR & (1u << board.gate_fault.pin)) == 0u;
}

/* The gate drivers (drv8301.h) on SPI3, with EN_GATE high: their SPI and
 * amplifiers run only then (SLOS719: EN_GATE low shuts the DRV8301 down
 * and its registers return to their reset values); every switch stays
 * off meanwhile (MOE = 0: the PWM outputs at their idle level, low). Each
 * one's control registers written and read back; the amplifiers' gain the
 * one read back. Then nFAULT: low refuses the start. */
static stm32_status_t gate_drivers_init(uint32_t apb1_hz, uint32_t core_hz)
{
    drv8301_chip_t chips[2];
    uint32_t n = 0u; /* the chips configured: board.gate_drivers, at most 2 */
    g.drv.error[0] = '\0';
    if (board.gate_fault_enable) {
        RCC->AHB1ENR |= RCC_AHB1ENR_GPIO(board.gate_fault.port);
        gpio_config(GPIO(board.gate_fault.port), board.gate_fault.pin, GPIO_INPUT, 0, GPIO_PULL_UP);
    }
    if (board.gate_drivers > 0u) {
        uint32_t br = 0u;
        if (!drv8301_spi_divider(apb1_hz, board.spi_max_hz, &br)) return STM32_FAULT_GATE_DRIVER_CONFIG;
        RCC->APB1ENR |= RCC_APB1ENR_SPI3EN;
        for (uint32_t k = 0; k < 3u; ++k) pin_af(board.spi_pins[k], GPIO_NO_PULL);
        /* nCS high at least 1 us between words (a poll takes a cycle or more) */
        drv8301_bus_init(&g.drv, SPI3, br, STM32_TIMEOUT_POLLS, core_hz / 1000000u);
        for (; n < board.gate_drivers && n < 2u; ++n) {
            const gpio_pin_t cs = board.gate_driver_cs[n];
            RCC->AHB1ENR |= RCC_AHB1ENR_GPIO(cs.port);
            chips[n] = (drv8301_chip_t){GPIO(cs.port), cs.pin, board.gate_driver_name[n]};
            drv8301_chip_init(&chips[n]);
        }
    }
    if (board.has_gate_enable) {
        gpio_write(GPIO(board.gate_enable.port), board.gate_enable.pin, true);
        spin((uint32_t)((uint64_t)core_hz * board.gate_driver_settle_us / 1000000u));
    }
    for (uint32_t k = 0; k < board.gate_drivers && k < 2u; ++k) {
        uint16_t ctrl2 = 0u;
        if (!drv8301_configure(&g.drv, &chips[k], board.gate_driver_ctrl1, board.gate_driver_ctrl2, &ctrl2)) {
            return g.drv.status;
        }
        /* the gain the amplifiers run with: the one read back (each chip
         * read back what was written, so all the same) */
        g.amp_gain = (float)DRV8301_GAIN_VV(DRV8301_CTRL2_GAIN_OF(ctrl2));
    }
    if (board.gate_fault_enable && gate_fault_asserted()) {
        if (board.gate_drivers == 0u || !drv8301_fault_report(&g.drv, chips, n, "gate driver: nFAULT low at start")) {
            g.drv.error[0] = '\0';
        }
        return STM32_FAULT_GATE_DRIVER_NFAULT;
    }
    return STM32_OK;
}

/* The board's encoder port (TIM3, encoder_tim.h) started, or started
 * again, at counts a turn: its count from zero. */
static stm32_status_t encoder_start(uint32_t counts)
{
    g.encoder_on = false;
    RCC->APB1ENR |= RCC_APB1ENR_TIM3EN;
    pin_af(board.encoder_a, GPIO_PULL_UP);
    pin_af(board.encoder_b, GPIO_PULL_UP);
    if (board.encoder_index_enable) pin_af(board.encoder_index, GPIO_PULL_DOWN);
    /* the largest count change between two control samples at the
     * board's fastest motor, rounded up, one count of margin */
    const uint64_t step = ((uint64_t)counts * board.encoder_max_rev_s + board.control_hz - 1u) / board.control_hz + 1u;
    const encoder_config_t ec = {
        .counts_per_turn = counts,
        .filter = board.encoder_filter,
        .invert = false,
        .start_count = 0u,
        .max_step_counts = step > ENCODER_STEP_MAX ? ENCODER_STEP_MAX + 1u : (uint32_t)step,
        .index = board.encoder_index_enable,
        .index_count = board.encoder_index_count,
        .index_tolerance = board.encoder_index_tolerance,
    };
    const stm32_status_t st = encoder_init(&g.enc, TIM3, &ec, STM32_TIMEOUT_POLLS);
    g.encoder_on = st == STM32_OK;
    return st;
}

bool stm32_backend_init(const stm32_periph_t *hw)
{
    g.hw = hw;
    g.fault = STM32_OK;
    g.running = false;
    g.started = false;
    g.app_stopped = false;
    g.error = "";
    g.encoder_on = false;
    g.step_dir_on = false;
    g.gate_fault_on = false;
    g.fault_pending = STM32_OK;
    g.amp_gain = board.amp_gain;
    g.initialised = false;
    g.paused = false;
    if (!g.configured) {
        g.can_node = board.can_node; /* no parameters: the board's table, no encoder */
        g.dead_time_ns = board.dead_time_ns;
        g.encoder_counts = 0u;
    }
    /* 1. why the last reset: a watchdog reset stays a fault until power is cycled */
    const bool wd_reset = (RCC->CSR & RCC_CSR_IWDGRSTF) != 0u;
    RCC->CSR |= RCC_CSR_RMVF;
    /* 2. clocks */
    uint32_t apb1 = 16000000u, apb2_timer = 16000000u;
    if (board.hse_hz != 0u) {
        if (!clock_plan(board.hse_hz, board.sysclk_hz, &g.clocks)) return fail(STM32_FAULT_CLOCK_PLAN);
        const stm32_status_t st = clock_init(RCC, FLASH_IF, &g.clocks, STM32_TIMEOUT_POLLS);
        if (st != STM32_OK) return fail(st);
        apb1 = g.clocks.apb1_hz;
        apb2_timer = g.clocks.apb2_timer_hz;
    }
    g.apb2_timer_hz = apb2_timer;
    RCC->AHB1ENR |= RCC_AHB1ENR_GPIO(0) | RCC_AHB1ENR_GPIO(1) | RCC_AHB1ENR_GPIO(2);
    RCC->APB2ENR |= RCC_APB2ENR_TIM1EN | RCC_APB2ENR_ADC1EN | RCC_APB2ENR_ADC2EN | RCC_APB2ENR_ADC3EN;
    RCC->APB1ENR |= RCC_APB1ENR_CAN1EN | RCC_APB1ENR_TIM2EN;
    /* 3. outputs off first: LEDs, gate driver disabled, PWM configured with MOE = 0 */
    if (board.led_status.port != 0xFFu)
        gpio_config(GPIO(board.led_status.port), board.led_status.pin, GPIO_OUTPUT, 0, GPIO_NO_PULL);
    if (board.led_fault.port != 0xFFu)
        gpio_config(GPIO(board.led_fault.port), board.led_fault.pin, GPIO_OUTPUT, 0, GPIO_NO_PULL);
    if (board.has_gate_enable) {
        gpio_write(GPIO(board.gate_enable.port), board.gate_enable.pin, false);
        gpio_config(GPIO(board.gate_enable.port), board.gate_enable.pin, GPIO_OUTPUT, 0, GPIO_PULL_DOWN);
    }
    if (!pwm_plan(apb2_timer, board.pwm_hz, board.pwm_hz >= board.control_hz ? board.control_hz : board.pwm_hz,
                  g.dead_time_ns, &g.pwm)) {
        return fail(STM32_FAULT_PWM_PLAN);
    }
    pwm_init(TIM1, &g.pwm, board.topology, board.break_enable, board.break_active_high);
    if (two_timers()) {
        RCC->APB2ENR |= RCC_APB2ENR_TIM8EN;
        pwm_init_slave(TIM8, &g.pwm);
    }
    for (uint32_t k = 0; k < 6u; ++k) pin_af(board.pwm_pins[k], GPIO_NO_PULL);
    for (uint32_t k = 0; k < 6u; ++k) pin_af(board.pwm_pins_2[k], GPIO_NO_PULL);
    /* the legs no winding uses: both switches held off (their gate
     * driver's inputs low) */
    for (uint32_t k = 0; k < 4u; ++k) {
        const gpio_pin_t p = board.pins_held_low[k];
        if (p.port != 0xFFu) {
            gpio_write(GPIO(p.port), p.pin, false);
            gpio_config(GPIO(p.port), p.pin, GPIO_OUTPUT, 0, GPIO_PULL_DOWN);
        }
    }
    if (board.break_enable) pin_af(board.break_pin, board.break_active_high ? GPIO_PULL_DOWN : GPIO_PULL_UP);
    if (wd_reset) return fail(STM32_FAULT_WATCHDOG_RESET);
    /* 3b. the gate drivers configured over SPI, before the currents' zero
     * (measured at the gain they run with) */
    if (board.gate_drivers > 0u || board.gate_fault_enable) {
        const stm32_status_t st = gate_drivers_init(apb1, board.hse_hz != 0u ? board.sysclk_hz : 16000000u);
        if (st != STM32_OK) {
            stm32_backend_fault(st);
            if (g.drv.error[0] != '\0') g.error = g.drv.error; /* the chip, register, values or flag */
            return false;
        }
        g.gate_fault_on = board.gate_fault_enable;
    }
    /* 4. the ADCs: the currents' zero with the bridges off, then the trigger */
    g.amps_per_code = board.current_sign * board.adc_vref_V / 4096.0f / (g.amp_gain * board.shunt_ohm);
    g.volts_per_code = board.adc_vref_V / 4096.0f * board.vbus_divider;
    if (board.control == BOARD_CONTROL_ADC) {
        for (uint32_t k = 0; k < 4u; ++k) {
            const gpio_pin_t p = board.analog_pins[k];
            if (p.port != 0xFFu) gpio_config(GPIO(p.port), p.pin, GPIO_ANALOG, 0, GPIO_NO_PULL);
        }
        for (uint32_t k = 0; k < board.n_phases; ++k) {
            const adc_sequence_t seq = {1u, {board.current_channel[k], 0, 0, 0}};
            adc_inj_init(ADC_COMMON, adc_of[k], &seq, false, false);
            uint32_t zero = 0;
            const stm32_status_t st = adc_inj_zero(adc_of[k], 1u, STM32_ZERO_SAMPLES, board.zero_nominal_code,
                                                   board.zero_tolerance_code, STM32_TIMEOUT_POLLS, &zero);
            if (st != STM32_OK) return fail(st);
            g.zero[k] = zero;
        }
        for (uint32_t k = 0; k < board.n_phases; ++k) {
            /* ADC1 also converts the bus after phase a, and interrupts */
            const adc_sequence_t seq = (k == 0u) ? (adc_sequence_t){2u, {board.current_channel[0], board.vbus_channel, 0, 0}}
                                                 : (adc_sequence_t){1u, {board.current_channel[k], 0, 0, 0}};
            adc_inj_init(ADC_COMMON, adc_of[k], &seq, true, k == 0u);
        }
    }
    /* 5. the encoder, when the board has its port and the drive's
     * parameters give its counts per turn */
    if (board.encoder_port && g.encoder_counts > 0u) {
        const stm32_status_t st = encoder_start(g.encoder_counts);
        if (st != STM32_OK) return fail(st);
    }
    /* 5b. the step/dir input: STEP on TIM5_CH1, DIR's line 0-4 (each its
     * own interrupt; lines 5-15 share theirs: not taken) */
    if (board.step_dir_enable) {
        if (board.dir_pin.port == 0xFFu || board.dir_pin.pin > 4u || board.step_pin.port == 0xFFu) {
            return fail(STM32_FAULT_STEP_DIR_CONFIG);
        }
        RCC->APB1ENR |= RCC_APB1ENR_TIM5EN;
        RCC->APB2ENR |= RCC_APB2ENR_SYSCFGEN;
        pin_af(board.step_pin, GPIO_PULL_DOWN);
        gpio_config(GPIO(board.dir_pin.port), board.dir_pin.pin, GPIO_INPUT, 0, GPIO_PULL_DOWN);
        const step_dir_config_t sc = {
            .filter = board.step_filter,
            .dir_invert = board.dir_invert,
            .dir_line = board.dir_pin.pin,
            .dir_port = board.dir_pin.port,
        };
        const bool level = (GPIO(board.dir_pin.port)->IDR & (1u << board.dir_pin.pin)) != 0u;
        const stm32_status_t st = step_dir_init(&g.sd, TIM5, EXTI, g.hw->syscfg, &sc, level, STM32_TIMEOUT_POLLS);
        if (st != STM32_OK) return fail(st);
        g.step_dir_on = true;
    }
    /* 6. CAN */
    if (board.can_enable) {
        bxcan_timing_t t;
        if (!bxcan_timing(apb1, board.can_bitrate, BXCAN_SAMPLE_PERMILLE, &t)) return fail(STM32_FAULT_CAN_TIMING);
        pin_af(board.can_rx, GPIO_PULL_UP);
        pin_af(board.can_tx, GPIO_NO_PULL);
        const stm32_status_t st = bxcan_init(CAN1, &t, g.can_node, STM32_TIMEOUT_POLLS);
        if (st != STM32_OK) return fail(st);
    }
    /* 7. the watchdog, last: from here the control step must come */
    if (board.watchdog_us != 0u) {
        uint32_t pr, rlr;
        if (!iwdg_plan(IWDG_LSI_NOMINAL_HZ, board.watchdog_us, &pr, &rlr)) return fail(STM32_FAULT_IWDG_TIMEOUT);
        const stm32_status_t st = iwdg_start(IWDG, pr, rlr, STM32_TIMEOUT_POLLS);
        if (st != STM32_OK) return fail(st);
        g.watchdog = true;
    }
    g.initialised = true;
    return true;
}

stm32_status_t stm32_backend_configure(uint8_t can_node, uint32_t dead_time_ns, uint32_t encoder_counts)
{
    if (can_node > 15u) return STM32_FAULT_CAN_TIMING;
    if (encoder_counts > 0u && !board.encoder_port) return STM32_FAULT_ENCODER_CONFIG;
    if (!g.initialised) {
        /* before the start: what stm32_backend_init sets up */
        g.configured = true;
        g.can_node = can_node;
        g.dead_time_ns = dead_time_ns;
        g.encoder_counts = encoder_counts;
        return STM32_OK;
    }
    /* at run time, each part only when it changes: the dead time's ticks
     * (DTG: RM0090 17.4.18, writable while LOCK = 0, as pwm_init leaves
     * it; taken at the next edge), the encoder counted again from zero,
     * the receive filter */
    if (dead_time_ns != g.dead_time_ns) {
        pwm_plan_t p;
        if (!pwm_plan(g.apb2_timer_hz, board.pwm_hz, board.pwm_hz >= board.control_hz ? board.control_hz : board.pwm_hz,
                      dead_time_ns, &p) ||
            p.arr != g.pwm.arr) {
            return STM32_FAULT_PWM_PLAN;
        }
        g.pwm = p;
        TIM1->BDTR = (TIM1->BDTR & ~TIM_BDTR_DTG_MASK) | (p.dtg & TIM_BDTR_DTG_MASK);
        if (two_timers()) TIM8->BDTR = (TIM8->BDTR & ~TIM_BDTR_DTG_MASK) | (p.dtg & TIM_BDTR_DTG_MASK);
        g.dead_time_ns = dead_time_ns;
    }
    if (encoder_counts != g.encoder_counts || (encoder_counts > 0u && !g.encoder_on)) {
        g.encoder_counts = encoder_counts;
        g.encoder_on = false;
        if (encoder_counts > 0u) {
            const stm32_status_t st = encoder_start(encoder_counts);
            if (st != STM32_OK) return st;
        }
    }
    if (can_node != g.can_node && board.can_enable) {
        bxcan_node_filter(CAN1, can_node);
    }
    g.can_node = can_node;
    return STM32_OK;
}

bool stm32_backend_pause(bool pause)
{
    const uint32_t primask = irq_mask();
    bool ok = true;
    if (pause) {
        pwm_outputs(TIM1, false);
        if (two_timers()) pwm_outputs(TIM8, false);
        g.paused = g.started;
    } else if (g.paused) {
        /* outputs back on only while nothing stopped them meanwhile (a
         * fault, the application's safe state) */
        ok = g.running && !g.app_stopped && g.fault == STM32_OK;
        if (ok) {
            pwm_outputs(TIM1, true);
            if (two_timers()) pwm_outputs(TIM8, true);
        }
        g.paused = false;
    }
    irq_restore(primask);
    return ok;
}

static void nvic_enable(uint32_t irq, uint8_t prio)
{
#if defined(__arm__)
    NVIC_IPR8(irq) = prio;
    NVIC_ISER(irq / 32u) = 1u << (irq % 32u);
#else
    /* a host test of the backend on fake peripherals: no NVIC */
    (void)irq;
    (void)prio;
#endif
}

/* ---- hal.h ---- */

uint32_t hal_control_rate_hz(void) { return board.control_hz; }

bool hal_start(hal_control_fn fn, void *ctx)
{
    if (g.fault != STM32_OK) {
        g.error = stm32_status_text(g.fault);
        return false;
    }
    if (fn == 0) {
        g.error = "hal_start: control callback is NULL";
        return false;
    }
    g.fn = fn;
    g.ctx = ctx;
    g.tick = 0;
    g.running = true;
    g.app_stopped = false;
    /* the break first (highest priority), the control step, CAN below it */
    if (board.break_enable) nvic_enable(IRQ_TIM1_BRK_TIM9, 0x00u);
    if (board.control == BOARD_CONTROL_ADC) {
        nvic_enable(IRQ_ADC, 0x10u);
        if (board.has_gate_enable) gpio_write(GPIO(board.gate_enable.port), board.gate_enable.pin, true);
        pwm_outputs(TIM1, true);
        if (two_timers()) {
            pwm_outputs(TIM8, true);
            const stm32_status_t st = pwm_start_synchronised(TIM1, TIM8, STM32_TIMEOUT_POLLS);
            if (st != STM32_OK) {
                stm32_backend_fault(st);
                g.error = stm32_status_text(st);
                return false;
            }
        } else {
            pwm_start(TIM1);
        }
        g.started = true;
    } else {
        /* TIM2 update at control_hz */
        g.started = true;
        TIM2->PSC = 0u;
        TIM2->ARR = board.control_timer_hz / board.control_hz - 1u;
        TIM2->DIER = TIM_DIER_UIE;
        TIM2->CR1 = TIM_CR1_CEN;
        nvic_enable(IRQ_TIM2, 0x10u);
    }
    if (g.step_dir_on) {
        /* the direction before the next step: above everything but the break */
        nvic_enable(IRQ_EXTI0 + board.dir_pin.pin, 0x00u);
    }
    if (board.can_enable) {
        CAN1->IER = CAN_IER_FMPIE0 | CAN_IER_BOFIE | CAN_IER_ERRIE;
        nvic_enable(IRQ_CAN1_RX0, 0x20u);
        nvic_enable(IRQ_CAN1_SCE, 0x20u);
    }
    return true;
}

void hal_safe_state(void)
{
    bridges_off();
    g.running = false;
    g.app_stopped = true;
}

uint32_t hal_time_us(void) { return (uint32_t)((uint64_t)g.tick * 1000000u / board.control_hz); }

const char *hal_last_error(void) { return g.error != 0 ? g.error : ""; }

bool hal_can_send(const hal_can_frame_t *f) { return board.can_enable && f != 0 && bxcan_send(CAN1, f); }

bool hal_can_receive(hal_can_frame_t *f)
{
    bool got = false;
    stm32_irq_disable();
    if (g.can_rx_count > 0u && f != 0) {
        *f = g.can_rx[g.can_rx_head];
        g.can_rx_head = (g.can_rx_head + 1u) & 15u;
        g.can_rx_count -= 1u;
        got = true;
    }
    stm32_irq_enable();
    return got;
}

/* ---- the control step ---- */

void stm32_backend_control(hal_sample_t *in)
{
    in->tick = g.tick;
    in->status |= g.status_next;
    g.status_next = 0u;
    if (!g.started) {
        return;
    }
    /* After a fault at run time the bridges stay off and no duty is
     * written, but the interrupt goes on: the application still runs (its
     * drive saw the trip and holds FAULT, its CAN node reports it and
     * takes commands) unless it stopped itself (hal_safe_state), and the
     * watchdog is fed, so the board does not reset out of the fault state
     * 10 ms later and lose its cause (hal/backends/stm32f405/README.md). */
    if (g.app_stopped) {
        if (g.watchdog) iwdg_refresh(IWDG);
        return;
    }
    hal_command_t out;
    out.n_phases = board.n_phases;
    for (uint32_t k = 0; k < HAL_MAX_PHASES; ++k) out.v_V[k] = MC_ZERO;
    g.fn(g.ctx, in, &out);
    if (g.fault_pending != STM32_OK) {
        /* the sample told the drive (its trip bit); now the fault state */
        stm32_backend_fault(g.fault_pending);
        g.fault_pending = STM32_OK;
    }
    if (g.running && board.control == BOARD_CONTROL_ADC) {
        /* phase voltages to duties: a leg about the bus midpoint (3 phases),
         * or a winding across a full bridge driven in opposition (2) */
        const float vbus = (float)in->v_bus_V;
        /* a leg about the bus midpoint: d = 1/2 + v/v_bus (3 phases); a
         * bipolar full bridge: v = (2 d - 1) v_bus, d = 1/2 + v/(2 v_bus) */
        const float gain = (board.n_phases == 3u) ? 1.0f : 0.5f;
        float duty[3] = {0.5f, 0.5f, 0.5f};
        for (uint32_t k = 0; k < board.n_phases && k < 3u; ++k) {
            if (vbus > 1.0f) duty[k] = 0.5f + gain * (float)out.v_V[k] / vbus;
            duty[k] = duty[k] > STM32_DUTY_MAX ? STM32_DUTY_MAX : duty[k];
            /* two legs a winding: leg C at 1 - d, its low side too */
            if (two_timers() && duty[k] < 1.0f - STM32_DUTY_MAX) duty[k] = 1.0f - STM32_DUTY_MAX;
        }
        if (two_timers()) {
            /* winding a across TIM1's legs B, C; winding b across TIM8's */
            pwm_set_bridge_bc(TIM1, &g.pwm, duty[0]);
            pwm_set_bridge_bc(TIM8, &g.pwm, duty[1]);
        } else {
            pwm_set_duty(TIM1, &g.pwm, duty, board.n_phases);
        }
    }
    if (g.watchdog) iwdg_refresh(IWDG);
    g.tick += 1u;
    g.steps += 1u;
}

const encoder_t *stm32_backend_encoder(void) { return g.encoder_on ? &g.enc : 0; }

bool stm32_backend_step_count(int32_t *count)
{
    if (!g.step_dir_on) return false;
    *count = step_dir_count(TIM5);
    return true;
}

void stm32_backend_dir_edge(void)
{
    if (!g.step_dir_on) {
        EXTI->PR = 0x1Fu;
        return;
    }
    const bool level = (GPIO(board.dir_pin.port)->IDR & (1u << board.dir_pin.pin)) != 0u;
    step_dir_direction(&g.sd, TIM5, EXTI, level);
}

void EXTI0_IRQHandler(void) { stm32_backend_dir_edge(); }
void EXTI1_IRQHandler(void) { stm32_backend_dir_edge(); }
void EXTI2_IRQHandler(void) { stm32_backend_dir_edge(); }
void EXTI3_IRQHandler(void) { stm32_backend_dir_edge(); }
void EXTI4_IRQHandler(void) { stm32_backend_dir_edge(); }

void stm32_backend_sample(hal_sample_t *in)
{
    adc_regs_t *a1 = adc_of[0];
    uint32_t status = 0u;
    if ((a1->SR & ADC_SR_OVR) != 0u) status |= HAL_STATUS_ADC_FAULT;
    uint16_t c0[2] = {0u, 0u}, c1 = 0u, c2 = 0u;
    adc_inj_read(a1, c0, 2u);
    a1->SR = 0u;
    adc_inj_read(adc_of[1], &c1, 1u);
    adc_of[1]->SR = 0u;
    if (board.n_phases == 3u) {
        adc_inj_read(adc_of[2], &c2, 1u);
        adc_of[2]->SR = 0u;
    }
    *in = (hal_sample_t){0};
    in->n_phases = board.n_phases;
    in->i_A[0] = (mc_t)(((float)c0[0] - (float)g.zero[0]) * g.amps_per_code);
    in->i_A[1] = (mc_t)(((float)c1 - (float)g.zero[1]) * g.amps_per_code);
    if (board.n_phases == 3u) in->i_A[2] = (mc_t)(((float)c2 - (float)g.zero[2]) * g.amps_per_code);
    in->v_bus_V = (mc_t)((float)c0[1] * g.volts_per_code);
    in->status = status;
    if ((TIM1->SR & TIM_SR_BIF) != 0u) in->status |= HAL_STATUS_PWM_TRIP;
    if (g.gate_fault_on && g.running && gate_fault_asserted()) {
        /* the gate drivers' fault: every switch off at once; this sample
         * carries the trip to the drive (DRIVE_FAULT_HW_TRIP), then the
         * fault state (stm32_backend_control) */
        in->status |= HAL_STATUS_PWM_TRIP;
        bridges_off();
        g.fault_pending = STM32_FAULT_GATE_DRIVER_NFAULT;
    }
    if (g.encoder_on) {
        /* the count a few microseconds after the currents' sampling
         * instant (the conversions' 2.6 us and the interrupt's entry) */
        float angle = 0.0f;
        if (encoder_read(&g.enc, TIM3, &angle)) {
            in->has_angle = true;
            in->angle_rad = (mc_t)angle;
        } else {
            /* withheld: a drive that reads the angle refuses the sample
             * (its BAD_INPUT, the safe state); the code is kept */
            g.error = stm32_status_text(g.enc.status);
        }
    }
}

void ADC_IRQHandler(void)
{
    const uint32_t t0 = SYST_CVR;
    /* a conversion every PWM period; the control step takes every
     * decimation-th (f_pwm / f_ctrl) */
    g.conversions += 1u;
    if ((g.conversions % g.pwm.decimation) != 0u) {
        for (uint32_t k = 0; k < board.n_phases; ++k) adc_of[k]->SR = 0u;
        return;
    }
    hal_sample_t in;
    stm32_backend_sample(&in);
    stm32_backend_control(&in);
    /* the step longer than a control period (SysTick at SYSCLK, free-running
     * 24-bit down counter: main starts it) */
    const uint32_t took = (t0 - SYST_CVR) & 0x00FFFFFFu;
    /* cppcheck-suppress unsignedLessThanZero ; SYST_CVR is a hardware counter: two reads differ */
    if (took > board.sysclk_hz / board.control_hz) {
        g.overruns += 1u;
        g.status_next |= HAL_STATUS_OVERRUN;
    }
}

void TIM1_BRK_TIM9_IRQHandler(void) { stm32_backend_break(); }

void stm32_backend_break(void)
{
    /* the hardware already forced the outputs off (MOE = 0); the gate
     * enable too, now */
    TIM1->SR &= ~TIM_SR_BIF;
    TIM1->DIER &= ~TIM_DIER_BIE;
    g.status_next |= HAL_STATUS_PWM_TRIP;
    bridges_off();
    if (g.running) {
        /* the next sample carries the trip to the drive (DRIVE_FAULT_HW_TRIP),
         * then the fault state (stm32_backend_control), as the gate
         * drivers' nFAULT does */
        g.fault_pending = STM32_FAULT_OVERCURRENT_BREAK;
    } else {
        stm32_backend_fault(STM32_FAULT_OVERCURRENT_BREAK);
    }
}

void CAN1_RX0_IRQHandler(void)
{
    hal_can_frame_t f;
    while (bxcan_receive(CAN1, &f)) {
        if (g.can_rx_count >= 16u) {
            g.can_rx_dropped += 1u;
            continue;
        }
        g.can_rx[(g.can_rx_head + g.can_rx_count) & 15u] = f;
        g.can_rx_count += 1u;
    }
}

void CAN1_SCE_IRQHandler(void)
{
    /* errors and bus-off: automatic recovery (ABOM); clear the interrupt */
    CAN1->MSR = 1u << 2; /* ERRI */
}

void stm32_backend_idle(void)
{
    const stm32_status_t f = g.fault;
    if (f == STM32_OK) {
        const uint32_t phase = g.steps / STM32_LED_BLINK_STEPS;
        if (board.led_status.port != 0xFFu) {
            gpio_write(GPIO(board.led_status.port), board.led_status.pin, (phase & 1u) != 0u);
        }
        return;
    }
    /* the fault code: that many flashes of 0.2 s, then 1 s dark */
    if (board.led_fault.port == 0xFFu) {
        return;
    }
    const uint32_t hz = (board.hse_hz != 0u) ? board.sysclk_hz : 16000000u;
    gpio_regs_t *led = GPIO(board.led_fault.port);
    for (uint32_t k = 0; k < (uint32_t)f; ++k) {
        gpio_write(led, board.led_fault.pin, true);
        spin(hz / 5u);
        gpio_write(led, board.led_fault.pin, false);
        spin(hz / 5u);
    }
    spin(hz);
}
