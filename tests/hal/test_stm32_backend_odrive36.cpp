// The STM32F405 backend's start-up and control path (hal/backends/stm32f405/
// stm32_backend.c) on fake peripherals with the ODrive v3.6 board table
// (boards/odrive36.c): a 2-phase stepper, winding a across TIM1's legs B
// and C (axis M0), winding b across TIM8's (axis M1). A thread answers as
// the chip would (ADC conversions end, bxCAN follows its initialisation
// request, TIM8 starts when TIM1's TRGO, its enable, rises while TIM8
// waits in trigger mode). Checked: both timers' registers, the legs A held
// off, the ADC sequences (winding a and the bus on ADC1, winding b on
// ADC2, one trigger), the duties of a command, the samples' currents with
// the board's scale, and the timers' synchronisation that fails: the fault
// state with both bridges off. The two DRV8301 on SPI3 (a fake that
// answers one frame late, fake_drv8301.h): their gain written and read
// back, the samples scaled with it, a read-back that differs and each SPI
// flag's timeout refusing the start, nFAULT (PD2) low at start refused and
// low while running the trip with both bridges off.
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "fake_drv8301.h"

extern "C" {
#include "boards/board.h"
#include "stm32_backend.h"
}

namespace {

struct Regs {
    rcc_regs_t rcc;
    flash_regs_t flash;
    tim_regs_t tim1, tim2, tim3, tim8, tim5;
    adc_common_regs_t adc_common;
    adc_regs_t adc[3];
    can_regs_t can1;
    iwdg_regs_t iwdg;
    gpio_regs_t gpio[5];
    exti_regs_t exti;
    syscfg_regs_t syscfg;
    spi_regs_t spi3;
};

struct FakeChip : Regs {
    stm32_periph_t hw;
    std::atomic<bool> stop{false};
    std::atomic<bool> tim8_trigger{true};  // false: TIM8 never sees TIM1's trigger
    std::atomic<bool> tim5_clock{true};    // false: TIM5 never answers its update
    // the two DRV8301 on SPI3, nCS PC13 (M0) and PC14 (M1)
    FakeDrv8301 drv{&spi3, &gpio[2], 13u, 14u};
    std::thread hardware;

    explicit FakeChip(uint32_t zero_code, FakeDrv8301::Mode spi_mode = FakeDrv8301::Mode::kOk)
    {
        std::memset(static_cast<void*>(static_cast<Regs*>(this)), 0, sizeof(Regs));
        drv.reset();
        drv.mode = spi_mode;
        gpio[3].IDR = 1u << 2;  // nFAULT (PD2) high: no fault
        hw = {&rcc,  &flash, &tim1, &tim2, &tim3, &adc_common, {&adc[0], &adc[1], &adc[2]}, &can1, &iwdg,
              {&gpio[0], &gpio[1], &gpio[2], &gpio[3], &gpio[4]}, &tim8, &tim5, &exti, &syscfg, &spi3};
        for (auto& a : adc) {
            a.JDR[0] = zero_code;
            a.JDR[1] = 1000;  // the bus on ADC1
        }
        hardware = std::thread([this] {
            while (!stop.load()) {
                for (auto& a : adc) {
                    if ((a.CR2 & ADC_CR2_JSWSTART) != 0u) a.SR = a.SR | ADC_SR_JEOC;
                }
                can1.MSR = (can1.MCR & CAN_MCR_INRQ) ? CAN_MSR_INAK : 0u;
                // TIM8 in trigger mode on ITR0 starts on TIM1's TRGO = its enable
                if (tim8_trigger.load() && (tim1.CR1 & TIM_CR1_CEN) != 0u &&
                    (tim1.CR2 & TIM_CR2_MMS_MASK) == TIM_CR2_MMS_ENABLE &&
                    (tim8.SMCR & (TIM_SMCR_SMS_MASK | TIM_SMCR_TS_MASK)) == TIM_SMCR_SMS_TRIGGER) {
                    tim8.CR1 = tim8.CR1 | TIM_CR1_CEN;
                }
                // an update event sets UIF (RM0090 18.4.5) when TIM5's clock runs
                if (tim5_clock.load() && (tim5.EGR & TIM_EGR_UG) != 0u) {
                    tim5.EGR = 0u;
                    tim5.SR = tim5.SR | TIM_SR_UIF;
                }
                drv.poll();
                std::this_thread::yield();
            }
        });
    }
    ~FakeChip()
    {
        stop = true;
        hardware.join();
    }
    void clocks_ok()
    {
        rcc.CR = RCC_CR_HSERDY | RCC_CR_PLLRDY;
        rcc.CFGR = RCC_CFGR_SWS_PLL;
    }
    bool moe1() const { return (tim1.BDTR & TIM_BDTR_MOE) != 0u; }
    bool moe8() const { return (tim8.BDTR & TIM_BDTR_MOE) != 0u; }
    // EN_GATE (PB12) an output with its pull-down; high once the last
    // write to port B's BSRR set it (the fake keeps the last write only)
    bool gate_output() const { return ((gpio[1].MODER >> 24) & 3u) == 1u && ((gpio[1].PUPDR >> 24) & 3u) == 2u; }
    bool gate_high() const { return (gpio[1].BSRR & (1u << 12)) != 0u; }
    bool gate_low() const { return gate_output() && !gate_high(); }
};

hal_command_t g_cmd;
void command_control(void*, const hal_sample_t*, hal_command_t* out) { *out = g_cmd; }

// the samples the callback was handed
std::vector<uint32_t> g_seen_status;
void recording_control(void*, const hal_sample_t* in, hal_command_t* out)
{
    g_seen_status.push_back(in->status);
    *out = hal_command_t{};
    out->n_phases = 2u;
}

}  // namespace

// A good start: the PWM of both axes, the legs A held off, the ADCs, CAN;
// then hal_start runs both timers in phase and enables the gate drivers.
TEST(Stm32BackendOdrive36, TwoTimersTwoWindingsOneTrigger)
{
    FakeChip chip(2048);
    chip.clocks_ok();
    ASSERT_TRUE(stm32_backend_init(&chip.hw)) << hal_last_error();
    EXPECT_TRUE(chip.rcc.APB2ENR & RCC_APB2ENR_TIM8EN);
    EXPECT_EQ(chip.tim1.CCER, 0x0550u) << "TIM1: legs B and C";
    EXPECT_EQ(chip.tim8.CCER, 0x0550u) << "TIM8: legs B and C";
    EXPECT_EQ(chip.tim8.SMCR, 0x06u) << "TIM8 waits for TIM1 (trigger mode, ITR0)";
    EXPECT_EQ(chip.tim1.BDTR & 0xFFu, 20u) << "dead time: 20 clocks (ODrive main.h)";
    EXPECT_FALSE(chip.moe1());
    EXPECT_FALSE(chip.moe8());
    // EN_GATE high since the DRV8301s' configuration (their SPI and
    // amplifiers need it); every switch still off: MOE = 0 on both timers
    EXPECT_TRUE(chip.gate_output());
    EXPECT_TRUE(chip.gate_high());
    // PA9, PA10 (TIM1 CH2, CH3) AF1; PB14, PB15 (CH2N, CH3N) AF1
    EXPECT_EQ((chip.gpio[0].MODER >> 18) & 0xFu, 0xAu);
    EXPECT_EQ((chip.gpio[0].AFR[1] >> 4) & 0xFFu, 0x11u);
    EXPECT_EQ((chip.gpio[1].AFR[1] >> 24) & 0xFFu, 0x11u);
    // PC7, PC8 (TIM8 CH2, CH3) AF3; PB0, PB1 (CH2N, CH3N) AF3
    EXPECT_EQ((chip.gpio[2].MODER >> 14) & 0xFu, 0xAu);
    EXPECT_EQ((chip.gpio[2].AFR[0] >> 28) & 0xFu, 0x3u);
    EXPECT_EQ(chip.gpio[2].AFR[1] & 0xFu, 0x3u);
    EXPECT_EQ(chip.gpio[1].AFR[0] & 0xFFu, 0x33u);
    // legs A: PA8, PB13 (M0_AH, M0_AL), PC6, PA7 (M1_AH, M1_AL) outputs, low
    EXPECT_EQ((chip.gpio[0].MODER >> 16) & 3u, 1u);
    EXPECT_EQ((chip.gpio[1].MODER >> 26) & 3u, 1u);
    EXPECT_EQ((chip.gpio[2].MODER >> 12) & 3u, 1u);
    EXPECT_EQ((chip.gpio[0].MODER >> 14) & 3u, 1u);
    EXPECT_EQ((chip.gpio[0].PUPDR >> 14) & 0xFu, 0xAu) << "PA7, PA8 pulled down";
    // ADC1: winding a (IN10, M0_IB) then the bus (IN6, VBUS_S); ADC2:
    // winding b (IN13, M1_IB); both on TIM1's TRGO
    EXPECT_EQ(chip.adc[0].JSQR, (1u << 20) | (10u << 10) | (6u << 15));
    EXPECT_EQ(chip.adc[1].JSQR, 13u << 15);
    EXPECT_EQ(chip.adc[0].CR2 & ADC_JEXTSEL_MASK, ADC_CR2_JEXTSEL(ADC_JEXTSEL_TIM1_TRGO));
    EXPECT_EQ(chip.adc[1].CR2 & ADC_JEXTSEL_MASK, ADC_CR2_JEXTSEL(ADC_JEXTSEL_TIM1_TRGO));
    EXPECT_EQ(chip.adc[2].CR2, 0u) << "ADC3 unused";
    // run: both timers counting, in phase, both bridges on, the gate drivers enabled
    ASSERT_TRUE(hal_start(&command_control, nullptr)) << hal_last_error();
    EXPECT_TRUE(chip.tim1.CR1 & TIM_CR1_CEN);
    EXPECT_TRUE(chip.tim8.CR1 & TIM_CR1_CEN);
    EXPECT_EQ(chip.tim1.CR2 & TIM_CR2_MMS_MASK, TIM_CR2_MMS_OC4REF) << "TRGO: the ADC trigger again";
    EXPECT_EQ(chip.tim8.SMCR, 0u);
    EXPECT_TRUE(chip.moe1());
    EXPECT_TRUE(chip.moe8());
    EXPECT_TRUE(chip.gate_high());
    // a sample: +100 codes on winding a, -50 on winding b, the bus at 1000
    // codes: 3.3/4096/(80 x 0.0005) = 0.02014 A a code (the gain read back
    // from the DRV8301s), 11 x 3.3/4096 V a code
    chip.adc[0].JDR[0] = 2148u;
    chip.adc[1].JDR[0] = 1998u;
    hal_sample_t in;
    stm32_backend_sample(&in);
    EXPECT_EQ(in.n_phases, 2u);
    EXPECT_EQ(in.status, 0u);
    EXPECT_NEAR(static_cast<float>(in.i_A[0]), 2.0142f, 0.0001f);
    EXPECT_NEAR(static_cast<float>(in.i_A[1]), -1.0071f, 0.0001f);
    EXPECT_NEAR(static_cast<float>(in.v_bus_V), 8.862f, 0.001f);
    // the command: +v_bus/4 on winding a -> leg B 0.625, leg C 0.375;
    // -v_bus on winding b -> leg B clamped at 0.02, leg C 0.98
    in.v_bus_V = static_cast<mc_t>(20.0f);
    g_cmd = hal_command_t{};
    g_cmd.n_phases = 2u;
    g_cmd.v_V[0] = static_cast<mc_t>(5.0f);
    g_cmd.v_V[1] = static_cast<mc_t>(-20.0f);
    stm32_backend_control(&in);
    EXPECT_EQ(chip.tim1.CCR[1], 2625u);
    EXPECT_EQ(chip.tim1.CCR[2], 1575u);
    EXPECT_EQ(chip.tim8.CCR[1], 84u);
    EXPECT_EQ(chip.tim8.CCR[2], 4116u);
    EXPECT_EQ(chip.tim1.CCR[0], 0u) << "leg A untouched";
    // the fault state turns both bridges off
    hal_safe_state();
    EXPECT_FALSE(chip.moe1());
    EXPECT_FALSE(chip.moe8());
}

// TIM8 that does not start on TIM1's trigger: hal_start refuses, the fault
// state (code 19), both bridges off, the gate drivers disabled.
TEST(Stm32BackendOdrive36, TimersThatDoNotSynchroniseAreAFaultWithBridgesOff)
{
    FakeChip chip(2048);
    chip.tim8_trigger = false;
    chip.clocks_ok();
    ASSERT_TRUE(stm32_backend_init(&chip.hw)) << hal_last_error();
    EXPECT_FALSE(hal_start(&command_control, nullptr));
    EXPECT_EQ(stm32_backend_status(), STM32_FAULT_PWM_SYNC);
    EXPECT_EQ(std::string(hal_last_error()), "PWM: TIM8 did not start on TIM1's trigger");
    EXPECT_FALSE(chip.moe1());
    EXPECT_FALSE(chip.moe8());
    EXPECT_TRUE(chip.gate_low());
    EXPECT_EQ(chip.tim1.CR1 & TIM_CR1_CEN, 0u);
}

// A current sensor's zero out of range (with the bridges off): the fault.
TEST(Stm32BackendOdrive36, CurrentSensorZeroOutOfRangeIsAFaultWithBridgesOff)
{
    FakeChip chip(1800);
    chip.clocks_ok();
    EXPECT_FALSE(stm32_backend_init(&chip.hw));
    EXPECT_EQ(stm32_backend_status(), STM32_FAULT_ADC_OFFSET);
    EXPECT_FALSE(chip.moe1());
    EXPECT_FALSE(chip.moe8());
    EXPECT_TRUE(chip.gate_low());
}

// The step/dir input (GPIO1 = PA0 STEP on TIM5_CH1 AF2, GPIO2 = PA1 DIR on
// EXTI line 1): TIM5 counting STEP's rising edges (external clock mode 1),
// DIR's line on both edges, its interrupt enabled by hal_start; a DIR
// edge turns the count's direction from the pin's level; the count is
// what stm32_backend_step_count gives the application.
TEST(Stm32BackendOdrive36, StepDirInputCountsOnTim5)
{
    FakeChip chip(2048);
    chip.clocks_ok();
    chip.gpio[0].IDR = 1u << 1;  // DIR high at start: counting up
    ASSERT_TRUE(stm32_backend_init(&chip.hw)) << hal_last_error();
    EXPECT_TRUE(chip.rcc.APB1ENR & RCC_APB1ENR_TIM5EN);
    EXPECT_TRUE(chip.rcc.APB2ENR & RCC_APB2ENR_SYSCFGEN);
    EXPECT_EQ(chip.tim5.SMCR, 0x57u);
    EXPECT_EQ(chip.tim5.CCMR1, 0x31u) << "TI1, 8 samples at 84 MHz";
    EXPECT_EQ(chip.tim5.CR1, TIM_CR1_CEN);
    EXPECT_EQ((chip.gpio[0].MODER >> 0) & 0xFu, 0x2u) << "PA0 alternate function, PA1 input";
    EXPECT_EQ(chip.gpio[0].AFR[0] & 0xFu, 0x2u) << "AF2: TIM5_CH1";
    EXPECT_EQ(chip.syscfg.EXTICR[0] & 0xF0u, 0u) << "line 1 on port A";
    EXPECT_EQ(chip.exti.IMR, 2u);
    EXPECT_EQ(chip.exti.RTSR & chip.exti.FTSR, 2u);
    int32_t count = -1;
    chip.tim5.CNT = 40u;  // 40 steps counted
    ASSERT_TRUE(stm32_backend_step_count(&count));
    EXPECT_EQ(count, 40);
    chip.gpio[0].IDR = 0u;  // DIR low: its edge's interrupt
    stm32_backend_dir_edge();
    EXPECT_TRUE(chip.tim5.CR1 & TIM_CR1_DIR) << "counting down";
    EXPECT_EQ(chip.exti.PR, 2u);
    chip.tim5.CNT = 0xFFFFFFF6u;
    ASSERT_TRUE(stm32_backend_step_count(&count));
    EXPECT_EQ(count, -10);
}

// TIM5 that does not answer its update: the start-up's fault (21), bridges off.
TEST(Stm32BackendOdrive36, StepCounterThatDoesNotAnswerIsAFaultWithBridgesOff)
{
    FakeChip chip(2048);
    chip.tim5_clock = false;
    chip.clocks_ok();
    EXPECT_FALSE(stm32_backend_init(&chip.hw));
    EXPECT_EQ(stm32_backend_status(), STM32_FAULT_STEP_DIR_TIMEOUT);
    EXPECT_EQ(std::string(hal_last_error()), "step/dir input: its timer did not answer the update");
    EXPECT_FALSE(chip.moe1());
    EXPECT_FALSE(chip.moe8());
    EXPECT_TRUE(chip.gate_low());
    int32_t count = 0;
    EXPECT_FALSE(stm32_backend_step_count(&count));
}

// The two DRV8301 on SPI3 (M0 nCS PC13, M1 nCS PC14; SCK, MISO, MOSI on
// PC10-12, AF6): each one's control registers written (1: over-current
// latch, V_DS 0.060 V; 2: GAIN = 11, 80 V/V), then read back (each read
// twice: the answer comes one frame late), with EN_GATE high and both
// bridges off; nFAULT (PD2) an input with its pull-up. The samples' scale
// is the gain read back: a chip that reads back 40 V/V (the vendor's)
// would double every current.
TEST(Stm32BackendOdrive36, GateDriversGainWrittenAndReadBack)
{
    FakeChip chip(2048);
    chip.clocks_ok();
    ASSERT_TRUE(stm32_backend_init(&chip.hw)) << hal_last_error();
    EXPECT_TRUE(chip.rcc.APB1ENR & RCC_APB1ENR_SPI3EN);
    EXPECT_EQ(chip.spi3.CR1, 0x0B5Du) << "mode 1, master, 16 bits, APB1 / 16 = 2.625 MHz, enabled";
    EXPECT_EQ((chip.gpio[2].MODER >> 20) & 0x3Fu, 0x2Au) << "PC10-PC12 alternate function";
    EXPECT_EQ((chip.gpio[2].AFR[1] >> 8) & 0xFFFu, 0x666u) << "AF6: SPI3";
    EXPECT_EQ((chip.gpio[2].MODER >> 26) & 0xFu, 0x5u) << "PC13, PC14 outputs (nCS)";
    EXPECT_TRUE(chip.rcc.AHB1ENR & RCC_AHB1ENR_GPIO(3)) << "port D clocked";
    EXPECT_EQ((chip.gpio[3].MODER >> 4) & 3u, 0u) << "PD2 an input";
    EXPECT_EQ((chip.gpio[3].PUPDR >> 4) & 3u, 1u) << "PD2 pulled up";
    const std::vector<uint16_t> want{0x1010u, 0x180Cu, 0x9000u, 0x9000u, 0x9800u, 0x9800u};
    EXPECT_EQ(chip.drv.words_to(0), want) << "M0";
    EXPECT_EQ(chip.drv.words_to(1), want) << "M1";
    for (int k = 0; k < 2; ++k) {
        EXPECT_EQ(chip.drv.reg(k, DRV8301_REG_CTRL1), 0x010u);
        EXPECT_EQ(chip.drv.reg(k, DRV8301_REG_CTRL2), 0x00Cu);
    }
    EXPECT_FALSE(chip.moe1());
    EXPECT_FALSE(chip.moe8());
    // the zero measured at this gain; one code is 20.1 mA
    chip.adc[0].JDR[0] = 2049u;
    hal_sample_t in;
    stm32_backend_sample(&in);
    EXPECT_NEAR(static_cast<float>(in.i_A[0]), 3.3f / 4096.0f / (80.0f * 0.0005f), 1e-6f);
}

// M1 does not keep control register 2 (reads back its reset value): the
// start refused (fault 23), the text naming the chip, the register, the
// value written and the value read; both bridges off, EN_GATE low.
TEST(Stm32BackendOdrive36, GateDriverReadBackThatDiffersRefusesTheStart)
{
    FakeChip chip(2048);
    chip.drv.drop_writes_chip = 1;
    chip.drv.drop_writes_addr = static_cast<int>(DRV8301_REG_CTRL2);
    chip.clocks_ok();
    EXPECT_FALSE(stm32_backend_init(&chip.hw));
    EXPECT_EQ(stm32_backend_status(), STM32_FAULT_GATE_DRIVER_CONFIG);
    EXPECT_EQ(std::string(hal_last_error()), "DRV8301 M1 (nCS PC14): control register 2 written 0x00C, read back 0x000");
    EXPECT_FALSE(chip.moe1());
    EXPECT_FALSE(chip.moe8());
    EXPECT_TRUE(chip.gate_low());
    EXPECT_FALSE(hal_start(&command_control, nullptr));
    EXPECT_EQ(chip.adc[0].CR2, 0u) << "no current sampled at an unknown gain";
}

// Each SPI flag that never comes (TXE, RXNE, BSY): the start refused
// (fault 22) with a text naming the flag, the bridges off, EN_GATE low.
TEST(Stm32BackendOdrive36, GateDriverSpiFlagTimeoutsRefuseTheStart)
{
    const struct {
        FakeDrv8301::Mode mode;
        const char* flag;
    } cases[] = {
        {FakeDrv8301::Mode::kNoTxe, "TXE (transmit buffer empty)"},
        {FakeDrv8301::Mode::kNoRxne, "RXNE (word received)"},
        {FakeDrv8301::Mode::kBusyStuck, "BSY (bus busy)"},
    };
    for (const auto& c : cases) {
        FakeChip chip(2048, c.mode);
        chip.clocks_ok();
        EXPECT_FALSE(stm32_backend_init(&chip.hw)) << c.flag;
        EXPECT_EQ(stm32_backend_status(), STM32_FAULT_GATE_DRIVER_SPI) << c.flag;
        EXPECT_EQ(std::string(hal_last_error()),
                  std::string("DRV8301 M0 (nCS PC13): SPI ") + c.flag + " timed out (frame 0x1010)");
        EXPECT_FALSE(chip.moe1());
        EXPECT_FALSE(chip.moe8());
        EXPECT_TRUE(chip.gate_low()) << c.flag;
        EXPECT_FALSE(hal_start(&command_control, nullptr));
    }
}

// nFAULT (PD2) low at start, after the configuration: refused (fault 24),
// the text with both chips' status registers (M0: FAULT and FETHB_OC),
// bridges off, EN_GATE low.
TEST(Stm32BackendOdrive36, NFaultLowAtStartRefusesTheStart)
{
    FakeChip chip(2048);
    chip.gpio[3].IDR = 0u;
    chip.drv.set_reg(0, DRV8301_REG_STATUS1, 0x408u);
    chip.drv.set_reg(1, DRV8301_REG_STATUS2, 0x001u);
    chip.clocks_ok();
    EXPECT_FALSE(stm32_backend_init(&chip.hw));
    EXPECT_EQ(stm32_backend_status(), STM32_FAULT_GATE_DRIVER_NFAULT);
    EXPECT_EQ(std::string(hal_last_error()),
              "gate driver: nFAULT low at start; M0 (nCS PC13) status 1 0x408, 2 0x000; "
              "M1 (nCS PC14) status 1 0x000, 2 0x001");
    EXPECT_FALSE(chip.moe1());
    EXPECT_FALSE(chip.moe8());
    EXPECT_TRUE(chip.gate_low());
    EXPECT_FALSE(hal_start(&command_control, nullptr));
}

// nFAULT going low while running: the sample turns both bridges off at
// once (MOE = 0 on TIM1 and TIM8, EN_GATE low) and carries the trip
// (HAL_STATUS_PWM_TRIP: the drive's DRIVE_FAULT_HW_TRIP, its safe state);
// the drive is handed that sample, then the fault state (24): no more
// duties, the application still called (stm32_backend_control), hal_start
// refused.
TEST(Stm32BackendOdrive36, NFaultWhileRunningTripsWithBridgesOff)
{
    FakeChip chip(2048);
    chip.clocks_ok();
    ASSERT_TRUE(stm32_backend_init(&chip.hw)) << hal_last_error();
    g_seen_status.clear();
    ASSERT_TRUE(hal_start(&recording_control, nullptr)) << hal_last_error();
    hal_sample_t in;
    stm32_backend_sample(&in);
    stm32_backend_control(&in);
    ASSERT_EQ(g_seen_status.size(), 1u);
    EXPECT_EQ(g_seen_status[0], 0u);
    EXPECT_TRUE(chip.moe1());
    chip.gpio[3].IDR = 0u;  // nFAULT low
    stm32_backend_sample(&in);
    EXPECT_TRUE(in.status & HAL_STATUS_PWM_TRIP);
    EXPECT_FALSE(chip.moe1()) << "off before the callback";
    EXPECT_FALSE(chip.moe8());
    EXPECT_TRUE(chip.gate_low());
    chip.tim1.CCR[1] = 1234u;
    stm32_backend_control(&in);
    ASSERT_EQ(g_seen_status.size(), 2u) << "the drive is handed the trip";
    EXPECT_TRUE(g_seen_status[1] & HAL_STATUS_PWM_TRIP);
    EXPECT_EQ(stm32_backend_status(), STM32_FAULT_GATE_DRIVER_NFAULT);
    EXPECT_EQ(std::string(hal_last_error()), "gate driver: nFAULT asserted");
    EXPECT_EQ(chip.tim1.CCR[1], 1234u) << "no duties written after the trip";
    stm32_backend_sample(&in);
    stm32_backend_control(&in);
    EXPECT_EQ(g_seen_status.size(), 3u) << "the fault state: the application still called (its drive in FAULT, "
                                           "its CAN node alive)";
    EXPECT_EQ(chip.tim1.CCR[1], 1234u) << "and no duties written";
    EXPECT_FALSE(chip.moe1());
    EXPECT_TRUE(chip.gate_low());
    EXPECT_FALSE(hal_start(&command_control, nullptr));
}
