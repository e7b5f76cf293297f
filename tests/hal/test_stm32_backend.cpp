// The STM32F405 backend's start-up (hal/backends/stm32f405/stm32_backend.c)
// on fake peripherals with the VESC 6 board table: a small "hardware"
// thread answers like the chip would (ADC conversions end, bxCAN follows
// its initialisation request); each bad start-up condition ends in the
// fault state with the bridges off (TIM1 MOE = 0, the DRV8301's EN_GATE
// low) and its code: a crystal that does not start, a watchdog reset, a
// current sensor's zero out of range, the over-current break after a good
// start; and hal_start() then refuses to run.
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <string>
#include <thread>

extern "C" {
#include "boards/board.h"
#include "stm32_backend.h"
}

namespace {

struct Regs {
    rcc_regs_t rcc;
    flash_regs_t flash;
    tim_regs_t tim1, tim2;
    adc_common_regs_t adc_common;
    adc_regs_t adc[3];
    can_regs_t can1;
    iwdg_regs_t iwdg;
    gpio_regs_t gpio[5];
};

struct FakeChip : Regs {
    stm32_periph_t hw;
    std::atomic<bool> stop{false};
    std::thread hardware;

    explicit FakeChip(uint32_t zero_code)
    {
        std::memset(static_cast<void*>(static_cast<Regs*>(this)), 0, sizeof(Regs));
        hw = {&rcc, &flash, &tim1, &tim2, &adc_common, {&adc[0], &adc[1], &adc[2]}, &can1, &iwdg,
              {&gpio[0], &gpio[1], &gpio[2], &gpio[3], &gpio[4]}};
        for (auto& a : adc) {
            a.JDR[0] = zero_code;
            a.JDR[1] = 2000;  // the bus on ADC1
        }
        hardware = std::thread([this] {
            while (!stop.load()) {
                for (auto& a : adc) {
                    if ((a.CR2 & ADC_CR2_JSWSTART) != 0u) a.SR = a.SR | ADC_SR_JEOC;
                }
                can1.MSR = (can1.MCR & CAN_MCR_INRQ) ? CAN_MSR_INAK : 0u;
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
    bool moe() const { return (tim1.BDTR & TIM_BDTR_MOE) != 0u; }
    // EN_GATE (PB5) driven low: its BSRR reset bit was written, never its set bit since
    bool gate_low() const { return (gpio[1].MODER & (3u << 10)) == (1u << 10); }
};

void dummy_control(void*, const hal_sample_t*, hal_command_t*) {}

}  // namespace

TEST(Stm32Backend, CrystalThatDoesNotStartIsAFaultWithBridgesOff)
{
    FakeChip chip(2048);
    EXPECT_FALSE(stm32_backend_init(&chip.hw));
    EXPECT_EQ(stm32_backend_status(), STM32_FAULT_HSE_TIMEOUT);
    EXPECT_EQ(std::string(hal_last_error()), "HSE crystal did not start");
    EXPECT_FALSE(chip.moe());
    EXPECT_FALSE(hal_start(&dummy_control, nullptr)) << "a faulted backend must not start";
}

TEST(Stm32Backend, WatchdogResetIsAFaultWithBridgesOff)
{
    FakeChip chip(2048);
    chip.clocks_ok();
    chip.rcc.CSR = RCC_CSR_IWDGRSTF;
    EXPECT_FALSE(stm32_backend_init(&chip.hw));
    EXPECT_EQ(stm32_backend_status(), STM32_FAULT_WATCHDOG_RESET);
    EXPECT_TRUE(chip.rcc.CSR & RCC_CSR_RMVF) << "the reset flags are cleared for the next start";
    EXPECT_FALSE(chip.moe());
    EXPECT_TRUE(chip.gate_low());
    EXPECT_TRUE(chip.tim1.BDTR & TIM_BDTR_BKE) << "the PWM was set up, outputs off";
}

TEST(Stm32Backend, CurrentSensorZeroOutOfRangeIsAFaultWithBridgesOff)
{
    FakeChip chip(2600);  // 552 codes off mid-scale: 44 A on the VESC 6
    chip.clocks_ok();
    EXPECT_FALSE(stm32_backend_init(&chip.hw));
    EXPECT_EQ(stm32_backend_status(), STM32_FAULT_ADC_OFFSET);
    EXPECT_FALSE(chip.moe());
    EXPECT_TRUE(chip.gate_low());
}

TEST(Stm32Backend, GoodStartThenOvercurrentBreak)
{
    FakeChip chip(2050);
    chip.clocks_ok();
    ASSERT_TRUE(stm32_backend_init(&chip.hw)) << hal_last_error();
    EXPECT_EQ(stm32_backend_status(), STM32_OK);
    // 168 MHz from the crystal, the watchdog started, CAN in normal mode
    EXPECT_EQ(chip.rcc.PLLCFGR, 0x07402A04u);
    EXPECT_EQ(chip.iwdg.KR, IWDG_KEY_REFRESH);
    EXPECT_EQ(chip.iwdg.RLR, 79u);
    EXPECT_EQ(chip.can1.BTR, 0x011A0002u);
    // ADC1 converts phase a (IN10) then the bus (IN13) on TIM1's trigger
    EXPECT_EQ(chip.adc[0].JSQR, 0x16A800u);
    EXPECT_EQ(chip.adc[0].CR2 & ADC_JEXTSEL_MASK, ADC_CR2_JEXTSEL(ADC_JEXTSEL_TIM1_TRGO));
    // the break: bridges off by hardware, the fault recorded
    chip.tim1.BDTR |= TIM_BDTR_MOE;  // as if running
    chip.tim1.SR = TIM_SR_BIF;
    stm32_backend_break();
    EXPECT_EQ(stm32_backend_status(), STM32_FAULT_OVERCURRENT_BREAK);
    EXPECT_FALSE(chip.moe());
    EXPECT_EQ(chip.tim1.SR & TIM_SR_BIF, 0u);
    EXPECT_FALSE(hal_start(&dummy_control, nullptr));
    EXPECT_EQ(std::string(hal_last_error()), "over-current: TIM1 break input");
}
