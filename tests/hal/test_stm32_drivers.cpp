// The STM32F405 backend's peripheral drivers (hal/backends/stm32f405)
// against fake register blocks in RAM: the values written for the clock
// tree, a 20 kHz centre-aligned PWM with dead time, the ADC's injected
// trigger, CAN at 1 Mbit/s, the watchdog and the encoder's timer, each
// checked bit by bit against RM0090 by hand, and every timeout path (a flag
// that never comes ends in the fault code, nothing waits for ever); the
// encoder's counts, direction, the 16-bit counter's wrap, the index and its
// errors, and its angle against the simulator's encoder; the DRV8301 gate
// driver over SPI against a fake DRV8301 that answers one frame late
// (fake_drv8301.h).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <thread>

#include "fake_drv8301.h"
#include "model/encoder.h"

extern "C" {
#include "adc_inj.h"
#include "bxcan.h"
#include "clock.h"
#include "drv8301.h"
#include "encoder_tim.h"
#include "gpio.h"
#include "iwdg.h"
#include "pwm_tim1.h"
#include "step_dir.h"
#include "trajectory/step_shaper.h"
}

namespace {
template <class T>
T zeroed()
{
    T t;
    std::memset(static_cast<void*>(&t), 0, sizeof t);
    return t;
}
constexpr uint32_t kPolls = 1000;
}  // namespace

// 8 MHz crystal to 168 MHz: M = 4 (2 MHz into the PLL), N = 168 (VCO
// 336 MHz), P = 2, Q = 7 (48 MHz), 5 wait states, APB1 42 MHz (timers 84),
// APB2 84 MHz (timers 168).
TEST(Stm32Clock, PlanFor168MHzFromAn8MHzCrystal)
{
    clock_plan_t p;
    ASSERT_TRUE(clock_plan(8000000u, 168000000u, &p));
    EXPECT_EQ(p.pll_m, 4u);
    EXPECT_EQ(p.pll_n, 168u);
    EXPECT_EQ(p.pll_p, 2u);
    EXPECT_EQ(p.pll_q, 7u);
    EXPECT_EQ(p.flash_ws, 5u);
    EXPECT_EQ(p.apb1_hz, 42000000u);
    EXPECT_EQ(p.apb2_hz, 84000000u);
    EXPECT_EQ(p.apb1_timer_hz, 84000000u);
    EXPECT_EQ(p.apb2_timer_hz, 168000000u);
    EXPECT_FALSE(clock_plan(8000000u, 180000000u, &p)) << "beyond the F405's 168 MHz";
    EXPECT_FALSE(clock_plan(7000000u, 168000000u, &p)) << "7 MHz is no whole multiple of the 2 MHz PLL input";
}

// The registers of a start-up whose flags all come: PLLCFGR = M | N << 6 |
// (P/2 - 1) << 16 | PLLSRC_HSE | Q << 24, ACR = 5 WS + prefetch + caches,
// CFGR = PPRE2 /2 | PPRE1 /4 | SW = PLL.
TEST(Stm32Clock, StartUpWritesThePlan)
{
    clock_plan_t p;
    ASSERT_TRUE(clock_plan(8000000u, 168000000u, &p));
    auto rcc = zeroed<rcc_regs_t>();
    auto flash = zeroed<flash_regs_t>();
    rcc.CR = RCC_CR_HSERDY | RCC_CR_PLLRDY;  // the hardware's answers, already there
    rcc.CFGR = RCC_CFGR_SWS_PLL;
    ASSERT_EQ(clock_init(&rcc, &flash, &p, kPolls), STM32_OK);
    EXPECT_EQ(rcc.PLLCFGR, 0x07402A04u);
    EXPECT_EQ(flash.ACR, 0x705u);
    EXPECT_EQ(rcc.CFGR, 0x9402u | RCC_CFGR_SWS_PLL);
    EXPECT_TRUE(rcc.CR & RCC_CR_HSEON);
    EXPECT_TRUE(rcc.CR & RCC_CR_PLLON);
}

// Each flag that never comes: the fault code, the chip left on HSI.
TEST(Stm32Clock, EachTimeoutEndsInItsFault)
{
    clock_plan_t p;
    ASSERT_TRUE(clock_plan(8000000u, 168000000u, &p));
    {
        auto rcc = zeroed<rcc_regs_t>();
        auto flash = zeroed<flash_regs_t>();
        EXPECT_EQ(clock_init(&rcc, &flash, &p, kPolls), STM32_FAULT_HSE_TIMEOUT);
        EXPECT_FALSE(rcc.CR & RCC_CR_HSEON) << "crystal left on";
        EXPECT_EQ(rcc.CFGR & 3u, 0u) << "not on HSI";
    }
    {
        auto rcc = zeroed<rcc_regs_t>();
        auto flash = zeroed<flash_regs_t>();
        rcc.CR = RCC_CR_HSERDY;
        EXPECT_EQ(clock_init(&rcc, &flash, &p, kPolls), STM32_FAULT_PLL_TIMEOUT);
        EXPECT_FALSE(rcc.CR & RCC_CR_PLLON);
    }
    {
        auto rcc = zeroed<rcc_regs_t>();
        auto flash = zeroed<flash_regs_t>();
        rcc.CR = RCC_CR_HSERDY | RCC_CR_PLLRDY;
        EXPECT_EQ(clock_init(&rcc, &flash, &p, kPolls), STM32_FAULT_CLOCK_SWITCH);
        EXPECT_EQ(rcc.CFGR & 3u, 0u);
    }
}

// 20 kHz from the 168 MHz TIM1 clock: ARR = 168e6 / (2 * 20e3) = 4200;
// 10 kHz control: every 2nd conversion; 500 ns dead time = 84 clocks,
// DTG = 84 (first range); 1 us = 168 clocks: DTG = 0x80 | (84 - 64) =
// 0x94, exactly 168; 3 us = 504 clocks: (32 + 31) * 8 = 504, DTG = 0xDF.
TEST(Stm32Pwm, PlanFor20kHzAndTheDeadTimeEncoding)
{
    pwm_plan_t p;
    ASSERT_TRUE(pwm_plan(168000000u, 20000u, 10000u, 500u, &p));
    EXPECT_EQ(p.arr, 4200u);
    EXPECT_EQ(p.decimation, 2u);
    EXPECT_EQ(p.dtg, 84u);
    EXPECT_EQ(p.dead_ns, 500u);
    ASSERT_TRUE(pwm_plan(168000000u, 20000u, 10000u, 1000u, &p));
    EXPECT_EQ(p.dtg, 0x94u);
    EXPECT_EQ(p.dead_ns, 1000u);
    ASSERT_TRUE(pwm_plan(168000000u, 20000u, 10000u, 3000u, &p));
    EXPECT_EQ(p.dtg, 0xDFu);
    uint32_t dtg, actual;
    ASSERT_TRUE(pwm_dtg(129u, &dtg, &actual));
    EXPECT_EQ(actual, 130u) << "rounded up, never shorter";
    EXPECT_FALSE(pwm_dtg(1009u, &dtg, &actual));
    EXPECT_FALSE(pwm_plan(168000000u, 20000u, 7000u, 500u, &p)) << "7 kHz is no whole number of periods";
    EXPECT_FALSE(pwm_plan(168000000u, 20000u, 10000u, 10000u, &p)) << "10 us: beyond DTG";
    EXPECT_FALSE(pwm_plan(168000000u, 1000u, 1000u, 500u, &p)) << "ARR 84000 > 16 bits";
}

// Three half-bridges: CR1 = centre-aligned 1 | ARPE | URS, PWM mode 1 with
// preload on CH1-3, CH4 internal in PWM mode 2 at ARR - 1 (0x7800 in
// CCMR2's high byte with preload), CCER = CCxE | CCxNE, BDTR = OSSI | OSSR |
// DTG | BKE | BKP and MOE off until asked, TRGO = OC4REF, the break
// interrupt.
TEST(Stm32Pwm, ThreeHalfBridgesRegisters)
{
    pwm_plan_t p;
    ASSERT_TRUE(pwm_plan(168000000u, 20000u, 10000u, 500u, &p));
    auto t = zeroed<tim_regs_t>();
    pwm_init(&t, &p, PWM_THREE_HALF_BRIDGES, true, true);
    EXPECT_EQ(t.CR1, 0xA4u);
    EXPECT_EQ(t.CR2, 0x70u);
    EXPECT_EQ(t.ARR, 4200u);
    EXPECT_EQ(t.RCR, 0u);
    EXPECT_EQ(t.CCMR1, 0x6868u);
    EXPECT_EQ(t.CCMR2, 0x7868u);
    EXPECT_EQ(t.CCR[3], 4199u);
    EXPECT_EQ(t.CCER, 0x0555u);
    EXPECT_EQ(t.BDTR, 0x3C00u | 84u);
    EXPECT_EQ(t.DIER, TIM_DIER_BIE);
    EXPECT_EQ(t.CCR[0], 2100u);
    EXPECT_EQ(t.EGR, TIM_EGR_UG);
    pwm_outputs(&t, true);
    EXPECT_TRUE(t.BDTR & TIM_BDTR_MOE);
    pwm_start(&t);
    EXPECT_TRUE(t.CR1 & TIM_CR1_CEN);
    const float d[3] = {0.25f, 1.5f, -0.1f};
    pwm_set_duty(&t, &p, d, 3);
    EXPECT_EQ(t.CCR[0], 1050u);
    EXPECT_EQ(t.CCR[1], 4200u) << "clamped to 1";
    EXPECT_EQ(t.CCR[2], 0u) << "clamped to 0";
    pwm_outputs(&t, false);
    EXPECT_FALSE(t.BDTR & TIM_BDTR_MOE);
}

// Two full bridges, bipolar: CH1/CH1N and CH2/CH2N (each pair the two legs
// of one bridge) with the dead time, CH4 the trigger, no break when the
// board has none.
TEST(Stm32Pwm, TwoFullBridgesRegisters)
{
    pwm_plan_t p;
    ASSERT_TRUE(pwm_plan(168000000u, 20000u, 10000u, 500u, &p));
    auto t = zeroed<tim_regs_t>();
    pwm_init(&t, &p, PWM_TWO_FULL_BRIDGES, false, false);
    EXPECT_EQ(t.CCMR1, 0x6868u);
    EXPECT_EQ(t.CCMR2, 0x7800u);
    EXPECT_EQ(t.CCER, 0x0055u);
    EXPECT_EQ(t.BDTR, 0x0C00u | 84u);
    EXPECT_EQ(t.DIER, 0u);
}

// Two timers' legs B and C (the ODrive v3.6's PWM_TWO_BRIDGES_TIM1_TIM8):
// CH2/CH2N and CH3/CH3N driven, CH1 (leg A) left disabled, CH4 TIM1's ADC
// trigger (TRGO = OC4REF); TIM8 the same legs, no break, its own TRGO
// unused, TIM1's slave in trigger mode on ITR0 (SMCR TS = 000, SMS = 110,
// RM0090 17.4.3); the dead time of 20 clocks at 168 MHz (DTG = 20).
TEST(Stm32Pwm, TwoTimersLegsBAndCRegisters)
{
    pwm_plan_t p;
    ASSERT_TRUE(pwm_plan(168000000u, 20000u, 10000u, 119u, &p));
    EXPECT_EQ(p.dtg, 20u);
    EXPECT_EQ(p.dead_ns, 119u);
    auto t1 = zeroed<tim_regs_t>();
    auto t8 = zeroed<tim_regs_t>();
    pwm_init(&t1, &p, PWM_TWO_BRIDGES_TIM1_TIM8, false, false);
    EXPECT_EQ(t1.CCMR1, 0x6800u) << "CH2 PWM mode 1 with preload, CH1 unused";
    EXPECT_EQ(t1.CCMR2, 0x7868u) << "CH3 PWM mode 1, CH4 PWM mode 2";
    EXPECT_EQ(t1.CCER, 0x0550u) << "CC2E, CC2NE, CC3E, CC3NE";
    EXPECT_EQ(t1.CR2, 0x70u);
    EXPECT_EQ(t1.CCR[1], 2100u);
    EXPECT_EQ(t1.CCR[2], 2100u);
    EXPECT_EQ(t1.CCR[0], 0u);
    EXPECT_EQ(t1.BDTR, 0x0C00u | 20u);
    EXPECT_EQ(t1.CR1, 0xA4u);
    pwm_init_slave(&t8, &p);
    EXPECT_EQ(t8.CCER, 0x0550u);
    EXPECT_EQ(t8.CR2, 0u);
    EXPECT_EQ(t8.SMCR, 0x06u) << "TS = ITR0 (TIM1's TRGO), SMS = trigger mode";
    EXPECT_EQ(t8.BDTR, 0x0C00u | 20u) << "no break";
    EXPECT_EQ(t8.DIER, 0u);
    EXPECT_EQ(t8.CR1 & TIM_CR1_CEN, 0u) << "stopped until TIM1 starts it";
    // a winding across legs B and C: leg B at d, leg C at 1 - d
    pwm_set_bridge_bc(&t8, &p, 0.75f);
    EXPECT_EQ(t8.CCR[1], 3150u);
    EXPECT_EQ(t8.CCR[2], 1050u);
    pwm_set_bridge_bc(&t8, &p, 1.5f);
    EXPECT_EQ(t8.CCR[1], 4200u) << "clamped to 1";
    EXPECT_EQ(t8.CCR[2], 0u);
    pwm_set_bridge_bc(&t8, &p, NAN);
    EXPECT_EQ(t8.CCR[1], 0u) << "not a number: 0";
    EXPECT_EQ(t8.CCR[2], 4200u);
}

// Both timers started together: at the moment TIM1's CEN is set, TIM1's
// TRGO is its enable (MMS = 001) and TIM8 waits in trigger mode, both
// counters at 0 (a thread plays TIM8's trigger input: it starts TIM8 when
// it sees TIM1 enabled, and notes what it saw then); after TIM8 runs,
// TIM1's TRGO is OC4REF again (the ADC trigger) and TIM8's slave mode off.
// A TIM8 that never starts: STM32_FAULT_PWM_SYNC, TIM1 stopped again.
TEST(Stm32Pwm, SynchronisedStartAndItsTimeout)
{
    pwm_plan_t p;
    ASSERT_TRUE(pwm_plan(168000000u, 20000u, 10000u, 119u, &p));
    auto t1 = zeroed<tim_regs_t>();
    auto t8 = zeroed<tim_regs_t>();
    pwm_init(&t1, &p, PWM_TWO_BRIDGES_TIM1_TIM8, false, false);
    pwm_init_slave(&t8, &p);
    t1.CNT = 17u;
    t8.CNT = 99u;
    std::atomic<bool> seen{false};
    std::atomic<uint32_t> mms{0}, smcr{0}, cnt1{1}, cnt8{1};
    std::thread trigger([&] {
        for (long k = 0; k < 2000000000L && !seen.load(); ++k) {
            if ((t1.CR1 & TIM_CR1_CEN) != 0u) {
                mms = t1.CR2 & TIM_CR2_MMS_MASK;
                smcr = t8.SMCR;
                cnt1 = t1.CNT;
                cnt8 = t8.CNT;
                if ((t8.SMCR & TIM_SMCR_SMS_MASK) == TIM_SMCR_SMS_TRIGGER) t8.CR1 = t8.CR1 | TIM_CR1_CEN;
                seen = true;
            }
            std::this_thread::yield();
        }
    });
    const stm32_status_t st = pwm_start_synchronised(&t1, &t8, 2000000000u);
    trigger.join();
    EXPECT_EQ(st, STM32_OK);
    EXPECT_EQ(mms.load(), TIM_CR2_MMS_ENABLE);
    EXPECT_EQ(smcr.load(), 0x06u);
    EXPECT_EQ(cnt1.load(), 0u);
    EXPECT_EQ(cnt8.load(), 0u);
    EXPECT_EQ(t1.CR2 & TIM_CR2_MMS_MASK, TIM_CR2_MMS_OC4REF) << "TRGO back to the ADC trigger";
    EXPECT_EQ(t8.SMCR, 0u);
    EXPECT_TRUE(t1.CR1 & TIM_CR1_CEN);
    EXPECT_TRUE(t8.CR1 & TIM_CR1_CEN);
    // the timeout: TIM8 never starts
    auto u1 = zeroed<tim_regs_t>();
    auto u8 = zeroed<tim_regs_t>();
    pwm_init(&u1, &p, PWM_TWO_BRIDGES_TIM1_TIM8, false, false);
    pwm_init_slave(&u8, &p);
    EXPECT_EQ(pwm_start_synchronised(&u1, &u8, kPolls), STM32_FAULT_PWM_SYNC);
    EXPECT_EQ(u1.CR1 & TIM_CR1_CEN, 0u) << "TIM1 stopped again";
    EXPECT_EQ(u1.CR2 & TIM_CR2_MMS_MASK, TIM_CR2_MMS_OC4REF);
}

// Current on IN10 and the bus on IN13 (the VESC 6's PC0 and PC3): SCAN and
// JEOCIE, 15-cycle sampling of both (SMPR1 bits 0-2 and 9-11), JSQR = JL
// 1 | IN10 in JSQ3 | IN13 in JSQ4, JEXTSEL = TIM1 TRGO, rising edge, ADON;
// ADCCLK = APB2 / 4.
TEST(Stm32Adc, InjectedSequenceOnTim1Trgo)
{
    auto c = zeroed<adc_common_regs_t>();
    auto a = zeroed<adc_regs_t>();
    const adc_sequence_t seq = {2, {10, 13, 0, 0}};
    adc_inj_init(&c, &a, &seq, true, true);
    EXPECT_EQ(c.CCR, 0x10000u);
    EXPECT_EQ(a.CR1, 0x180u);
    EXPECT_EQ(a.SMPR1, 0x201u);
    EXPECT_EQ(a.SMPR2, 0u);
    EXPECT_EQ(a.JSQR, 0x16A800u);
    EXPECT_EQ(a.CR2, 0x110001u);
    a.JDR[0] = 2047;
    a.JDR[1] = 1234;
    uint16_t codes[2];
    adc_inj_read(&a, codes, 2);
    EXPECT_EQ(codes[0], 2047);
    EXPECT_EQ(codes[1], 1234);
}

// The start-up zero: within tolerance passes, outside fails with
// ADC_OFFSET, a conversion that never ends with ADC_TIMEOUT.
TEST(Stm32Adc, SensorZeroAndItsFaults)
{
    uint32_t zero[2];
    {
        auto a = zeroed<adc_regs_t>();
        a.SR = ADC_SR_JEOC;
        a.JDR[0] = 2060;
        a.JDR[1] = 2030;
        EXPECT_EQ(adc_inj_zero(&a, 2, 1, 2048, 100, kPolls, zero), STM32_OK);
        EXPECT_EQ(zero[0], 2060u);
        EXPECT_TRUE(a.CR2 & ADC_CR2_JSWSTART);
    }
    {
        auto a = zeroed<adc_regs_t>();
        a.SR = ADC_SR_JEOC;
        a.JDR[0] = 2048;
        a.JDR[1] = 2600;
        EXPECT_EQ(adc_inj_zero(&a, 2, 1, 2048, 100, kPolls, zero), STM32_FAULT_ADC_OFFSET);
    }
    {
        auto a = zeroed<adc_regs_t>();
        EXPECT_EQ(adc_inj_zero(&a, 2, 4, 2048, 100, kPolls, zero), STM32_FAULT_ADC_TIMEOUT);
    }
}

// 1 Mbit/s from APB1 = 42 MHz: 42 = 3 x 14 quanta, BS1 = 11, BS2 = 2,
// sample point 12/14 = 85.7 % (the nearest to 87.5 % any exact setting
// gives), SJW 2: BTR = BRP 2 | TS1 10 << 16 | TS2 1 << 20 | SJW 1 << 24.
// 500 kbit/s: 42 = 6 x 14 again; 84 MHz (APB2 by mistake) finds 1 Mbit/s
// with other numbers; 1 Mbit/s from 7 MHz has no setting (7 quanta < 8).
TEST(Stm32Can, BitTimingFor1MbitFromApb1)
{
    bxcan_timing_t t;
    ASSERT_TRUE(bxcan_timing(42000000u, 1000000u, BXCAN_SAMPLE_PERMILLE, &t));
    EXPECT_EQ(t.brp, 3u);
    EXPECT_EQ(t.tq, 14u);
    EXPECT_EQ(t.bs1, 11u);
    EXPECT_EQ(t.bs2, 2u);
    EXPECT_EQ(t.sample_permille, 857u);
    EXPECT_EQ(t.btr, 0x011A0002u);
    EXPECT_EQ(42000000u / (t.brp * t.tq), 1000000u);
    ASSERT_TRUE(bxcan_timing(42000000u, 500000u, BXCAN_SAMPLE_PERMILLE, &t));
    EXPECT_EQ(t.brp * t.tq * 500000u, 42000000u);
    EXPECT_FALSE(bxcan_timing(7000000u, 1000000u, BXCAN_SAMPLE_PERMILLE, &t)) << "7 quanta at most: fewer than 8";
}

// Init: a controller that never acknowledges initialisation, or never
// leaves it (no bus: 11 recessive bits never seen), times out; the filter
// takes node 5's command ids, standard data frames only.
TEST(Stm32Can, InitFilterAndTimeouts)
{
    bxcan_timing_t t;
    ASSERT_TRUE(bxcan_timing(42000000u, 1000000u, BXCAN_SAMPLE_PERMILLE, &t));
    auto c = zeroed<can_regs_t>();
    EXPECT_EQ(bxcan_init(&c, &t, 5, kPolls), STM32_FAULT_CAN_TIMEOUT) << "INAK never set";
    c = zeroed<can_regs_t>();
    c.MSR = CAN_MSR_INAK;  // stays in initialisation
    EXPECT_EQ(bxcan_init(&c, &t, 5, kPolls), STM32_FAULT_CAN_TIMEOUT);
    EXPECT_EQ(c.BTR, 0x011A0002u);
    EXPECT_EQ(c.FILTER[0].FR1, 0x205u << 21);
    EXPECT_EQ(c.FILTER[0].FR2, (0x70Fu << 21) | 0x6u);
    EXPECT_EQ(c.FA1R & 1u, 1u);
    EXPECT_EQ(c.FS1R & 1u, 1u);
    EXPECT_EQ(c.FMR & CAN_FMR_FINIT, 0u);
    EXPECT_TRUE(c.MCR & CAN_MCR_ABOM);
}

TEST(Stm32Can, SendAndReceive)
{
    auto c = zeroed<can_regs_t>();
    hal_can_frame_t f{0x115, 8, {1, 2, 3, 4, 5, 6, 7, 8}};
    EXPECT_FALSE(bxcan_send(&c, &f)) << "three busy mailboxes";
    c.TSR = CAN_TSR_TME(1);
    ASSERT_TRUE(bxcan_send(&c, &f));
    EXPECT_EQ(c.TX[1].TIR, (0x115u << 21) | CAN_TIR_TXRQ);
    EXPECT_EQ(c.TX[1].TDTR, 8u);
    EXPECT_EQ(c.TX[1].TDLR, 0x04030201u);
    EXPECT_EQ(c.TX[1].TDHR, 0x08070605u);
    hal_can_frame_t r{};
    EXPECT_FALSE(bxcan_receive(&c, &r));
    c.RF0R = 1;
    c.RX[0].RIR = 0x235u << 21;
    c.RX[0].RDTR = 1;
    c.RX[0].RDLR = 0xAB;
    ASSERT_TRUE(bxcan_receive(&c, &r));
    EXPECT_EQ(r.id, 0x235u);
    EXPECT_EQ(r.dlc, 1u);
    EXPECT_EQ(r.data[0], 0xAB);
    EXPECT_EQ(c.RF0R, CAN_RFR_RFOM);
    c.RF0R = 1;
    c.RX[0].RIR = (0x235u << 21) | CAN_RIR_RTR;
    ASSERT_TRUE(bxcan_receive(&c, &r));
    EXPECT_EQ(r.id, 0xFFFFFFFFu) << "a remote frame reaches no node";
}

// 10 ms at 32 kHz: /4, 80 counts (RLR 79); 1 s: /8, 4000 (RLR 3999); the
// registers that never update time out.
TEST(Stm32Iwdg, PlanStartAndTimeout)
{
    uint32_t pr, rlr;
    ASSERT_TRUE(iwdg_plan(IWDG_LSI_NOMINAL_HZ, 10000u, &pr, &rlr));
    EXPECT_EQ(pr, 0u);
    EXPECT_EQ(rlr, 79u);
    ASSERT_TRUE(iwdg_plan(IWDG_LSI_NOMINAL_HZ, 1000000u, &pr, &rlr));
    EXPECT_EQ(pr, 1u);
    EXPECT_EQ(rlr, 3999u);
    EXPECT_FALSE(iwdg_plan(IWDG_LSI_NOMINAL_HZ, 60000000u, &pr, &rlr));
    auto w = zeroed<iwdg_regs_t>();
    EXPECT_EQ(iwdg_start(&w, 0, 79, kPolls), STM32_OK);
    EXPECT_EQ(w.PR, 0u);
    EXPECT_EQ(w.RLR, 79u);
    EXPECT_EQ(w.KR, IWDG_KEY_REFRESH);
    w = zeroed<iwdg_regs_t>();
    w.SR = IWDG_SR_RVU;
    EXPECT_EQ(iwdg_start(&w, 0, 79, kPolls), STM32_FAULT_IWDG_TIMEOUT);
}

// PA8 as TIM1_CH1 (AF1): MODER bits 16-17 = 2, AFRH bits 0-3 = 1.
TEST(Stm32Gpio, AlternateFunction)
{
    auto g = zeroed<gpio_regs_t>();
    gpio_config(&g, 8, GPIO_AF, 1, GPIO_NO_PULL);
    EXPECT_EQ(g.MODER, 2u << 16);
    EXPECT_EQ(g.AFR[1], 1u);
    EXPECT_EQ(g.AFR[0], 0u);
    gpio_write(&g, 8, false);
    EXPECT_EQ(g.BSRR, 1u << 24);
}

namespace {
// 2048 lines (8192 counts a turn), the index at count 100, 4 counts of
// tolerance; one timer clock's filter; 1000 counts a read at most
encoder_config_t enc_cfg(bool index)
{
    encoder_config_t c{};
    c.counts_per_turn = 8192u;
    c.filter = 1u;
    c.invert = false;
    c.start_count = 0u;
    c.max_step_counts = 1000u;
    c.index = index;
    c.index_count = 100u;
    c.index_tolerance = 4u;
    return c;
}
constexpr double kTwoPi = 6.283185307179586476925286766559;
// encoder_init on a fake TIM3 whose "hardware" (a thread) answers the
// update the driver asks for (EGR UG) with its flag (SR UIF), as a timer
// whose clock runs does; the driver clears SR first, so a flag already
// there would not do. Polls enough for a loaded host to schedule the thread.
stm32_status_t init_answered(encoder_t* e, tim_regs_t* t, const encoder_config_t& c)
{
    std::atomic<bool> stop{false};
    std::thread hw([&] {
        while (!stop.load()) {
            if ((t->EGR & TIM_EGR_UG) != 0u) {
                t->SR = t->SR | TIM_SR_UIF;
            }
            std::this_thread::yield();
        }
    });
    const stm32_status_t st = encoder_init(e, t, &c, 1000000000u);
    stop = true;
    hw.join();
    return st;
}
tim_regs_t started(encoder_t* e, const encoder_config_t& c)
{
    auto t = zeroed<tim_regs_t>();
    EXPECT_EQ(init_answered(e, &t, c), STM32_OK);
    return t;
}
}  // namespace

// Encoder interface mode 3 (RM0090 18.3.12): SMCR SMS = 011; CCMR1 CC1S =
// CC2S = 01 (IC1 on TI1, IC2 on TI2) with IC1F = IC2F = 1: 0x1111; the
// index on CH3 (CCMR2 CC3S = 01, IC3F = 1: 0x11; CCER CC3E, bit 8, rising:
// CC3P = 0); the count over 16 bits (ARR 0xFFFF, PSC 0); an update (UG)
// answered (UIF), then the counter on (CEN). Inverted: CCER CC1P (bit 1).
TEST(Stm32Encoder, RegistersOfEncoderModeAndTheIndexCapture)
{
    encoder_t e;
    auto t = started(&e, enc_cfg(true));
    EXPECT_EQ(t.SMCR, 3u);
    EXPECT_EQ(t.CCMR1, 0x1111u);
    EXPECT_EQ(t.CCMR2, 0x11u);
    EXPECT_EQ(t.CCER, 0x100u);
    EXPECT_EQ(t.ARR, 0xFFFFu);
    EXPECT_EQ(t.PSC, 0u);
    EXPECT_EQ(t.EGR, TIM_EGR_UG);
    EXPECT_EQ(t.CR1, TIM_CR1_CEN);
    EXPECT_EQ(t.SR & TIM_SR_UIF, 0u) << "the update's flag cleared";
    EXPECT_EQ(t.DIER, 0u) << "no interrupt: the control step reads it";
    auto c = enc_cfg(false);
    c.invert = true;
    c.filter = 15u;
    t = started(&e, c);
    EXPECT_EQ(t.CCER, 0x2u) << "CC1P: TI1 inverted, the count the other way; no capture without the index";
    EXPECT_EQ(t.CCMR1, 0xF1F1u);
    EXPECT_EQ(t.CCMR2, 0u);
}

// Counts and direction: +100, then back by 150 through zero (CNT wraps to
// 65486): the unwrapped count -50, the last step's sign the direction.
// Then 100 reads of +2000 (200,000 counts: the 16-bit counter wraps three
// times, 24 turns and 3392 counts) and back: every count kept.
TEST(Stm32Encoder, CountsDirectionAndTheWrapOfTheCounter)
{
    encoder_t e;
    auto c = enc_cfg(false);
    c.max_step_counts = 2000u;
    auto t = started(&e, c);
    float a = 99.0f;
    t.CNT = 100u;
    ASSERT_TRUE(encoder_read(&e, &t, &a));
    EXPECT_EQ(encoder_count(&e), 100);
    EXPECT_GT(e.last_step, 0) << "forward";
    EXPECT_FLOAT_EQ(a, static_cast<float>(100.0 * kTwoPi / 8192.0));
    t.CNT = 65486u;  // 100 - 150 modulo 2^16
    ASSERT_TRUE(encoder_read(&e, &t, &a));
    EXPECT_EQ(encoder_count(&e), -50);
    EXPECT_EQ(e.last_step, -150) << "backward";
    EXPECT_EQ(e.turns, -1);
    EXPECT_EQ(e.pos, 8142u);
    EXPECT_FLOAT_EQ(a, static_cast<float>(-50.0 * kTwoPi / 8192.0));
    int64_t want = -50;
    uint32_t cnt = 65486u;
    for (int k = 0; k < 100; ++k) {
        cnt = (cnt + 2000u) & 0xFFFFu;
        want += 2000;
        t.CNT = cnt;
        ASSERT_TRUE(encoder_read(&e, &t, &a));
        ASSERT_EQ(encoder_count(&e), want) << "read " << k;
    }
    EXPECT_EQ(encoder_count(&e), 199950);
    EXPECT_EQ(e.turns, 24);
    EXPECT_EQ(e.pos, 3342u);
    for (int k = 0; k < 100; ++k) {
        cnt = (cnt - 2000u) & 0xFFFFu;
        t.CNT = cnt;
        ASSERT_TRUE(encoder_read(&e, &t, &a));
    }
    EXPECT_EQ(encoder_count(&e), -50);
    EXPECT_LT(e.last_step, 0);
}

// The angle as paper 002's drive reads it in the simulator
// (sim/model/encoder.h, no noise): the count the rotor has passed times
// 2 pi / n, wrapped into [-pi, pi); for 8192 and 1000 counts a turn, over
// three turns both ways, within two float roundings of the simulator's
// (modulo 2 pi: at half a turn the simulator's double may wrap to +pi
// where this gives -pi, the same angle).
TEST(Stm32Encoder, AngleAsTheSimulatorsEncoderGivesIt)
{
    for (uint32_t n : {8192u, 1000u}) {
        mcsim::EncoderParams p;
        p.counts_per_turn = n;
        mcsim::Encoder sim(p, 1u);
        for (int k = -3000; k <= 3000; ++k) {
            const double theta = k * (3.0 * kTwoPi / 3000.0) + 1e-9;
            const double step = kTwoPi / n;
            const int64_t count = static_cast<int64_t>(std::floor(theta / step));
            const uint32_t pos = static_cast<uint32_t>(((count % n) + n) % n);
            const float mine = encoder_angle_of(pos, n);
            const float theirs = static_cast<float>(sim.measure(theta));
            double d = static_cast<double>(mine) - static_cast<double>(theirs);
            d -= kTwoPi * std::round(d / kTwoPi);
            ASSERT_NEAR(d, 0.0, 2.0 * 4.8e-7) << "n " << n << " theta " << theta << ": " << mine << " " << theirs;
            ASSERT_GE(mine, -static_cast<float>(M_PI));
            ASSERT_LT(mine, static_cast<float>(M_PI));
        }
    }
}

// The index (captured on CH3): the first, at count 250 while the count says
// 250, moves the zero so that it sits at 100 (-150 counts); the next turn's
// at the same place passes; one 10 counts off (beyond 4) is an error: the
// angle withheld from then on. The capture's flags are cleared each time.
TEST(Stm32Encoder, IndexFixesTheZeroThenChecksEveryTurn)
{
    encoder_t e;
    auto t = started(&e, enc_cfg(true));
    float a = 0.0f;
    t.CNT = 300u;
    t.CCR[2] = 250u;
    t.SR = TIM_SR_CCIF(2u) | TIM_SR_CCOF(2u);
    ASSERT_TRUE(encoder_read(&e, &t, &a));
    EXPECT_TRUE(e.referenced);
    EXPECT_EQ(e.index_correction, -150);
    EXPECT_EQ(encoder_count(&e), 150) << "300 counts on, the index (at 250) now at 100";
    EXPECT_EQ(t.SR & (TIM_SR_CCIF(2u) | TIM_SR_CCOF(2u)), 0u);
    EXPECT_FLOAT_EQ(a, static_cast<float>(150.0 * kTwoPi / 8192.0));
    // a turn on in steps of 1000 counts, the index at 250 + 8192 modulo 2^16
    uint32_t cnt = 300u;
    for (int k = 0; k < 9; ++k) {
        cnt += 1000u;
        t.CNT = cnt;
        if (k == 8) {
            t.CCR[2] = 250u + 8192u;
            t.SR = TIM_SR_CCIF(2u);
        }
        ASSERT_TRUE(encoder_read(&e, &t, &a)) << k;
    }
    EXPECT_EQ(e.index_seen, 2u);
    EXPECT_EQ(e.status, STM32_OK);
    // the next turn's 2 counts early: within the tolerance
    for (int k = 0; k < 8; ++k) {
        cnt += 1000u;
        t.CNT = cnt & 0xFFFFu;
        if (k == 7) {
            t.CCR[2] = (250u + 2u * 8192u - 2u) & 0xFFFFu;
            t.SR = TIM_SR_CCIF(2u);
        }
        ASSERT_TRUE(encoder_read(&e, &t, &a)) << k;
    }
    EXPECT_EQ(e.index_seen, 3u);
    // the next turn's index 10 counts late: counts were lost
    cnt += 1000u * 8u;
    for (int k = 0; k < 8; ++k) {
        t.CNT = (cnt - 1000u * (7u - k)) & 0xFFFFu;
        ASSERT_TRUE(encoder_read(&e, &t, &a)) << k;
    }
    t.CNT = (cnt + 1000u) & 0xFFFFu;
    t.CCR[2] = (250u + 3u * 8192u + 10u) & 0xFFFFu;
    t.SR = TIM_SR_CCIF(2u);
    EXPECT_FALSE(encoder_read(&e, &t, &a));
    EXPECT_EQ(e.status, STM32_FAULT_ENCODER_INDEX);
    EXPECT_FALSE(encoder_read(&e, &t, &a)) << "latched";
}

// A count that moved more than the fastest motor can between two reads
// (noise on A or B, or a step the 16-bit difference cannot tell): an
// error, latched; exactly the limit passes.
TEST(Stm32Encoder, StepBeyondTheFastestMotorIsAnError)
{
    encoder_t e;
    auto t = started(&e, enc_cfg(false));
    float a = 0.0f;
    t.CNT = 1000u;
    ASSERT_TRUE(encoder_read(&e, &t, &a));
    t.CNT = 0u;
    ASSERT_TRUE(encoder_read(&e, &t, &a));
    t.CNT = (0u - 1001u) & 0xFFFFu;
    EXPECT_FALSE(encoder_read(&e, &t, &a));
    EXPECT_EQ(e.status, STM32_FAULT_ENCODER_STEP);
    t.CNT = 0u;
    EXPECT_FALSE(encoder_read(&e, &t, &a)) << "latched";
}

// Every configuration the timer cannot run, and the update that never
// comes (no clock): the counter is not started, nothing is read.
TEST(Stm32Encoder, ConfigurationErrorsAndTheTimeout)
{
    encoder_t e;
    const encoder_config_t good = enc_cfg(true);
    auto bad = [&](auto edit) {
        encoder_config_t c = good;
        edit(c);
        auto t = zeroed<tim_regs_t>();
        return init_answered(&e, &t, c);
    };
    EXPECT_EQ(bad([](encoder_config_t& c) { c.counts_per_turn = 3u; }), STM32_FAULT_ENCODER_CONFIG);
    EXPECT_EQ(bad([](encoder_config_t& c) { c.counts_per_turn = (1u << 24) + 1u; }), STM32_FAULT_ENCODER_CONFIG);
    EXPECT_EQ(bad([](encoder_config_t& c) { c.filter = 16u; }), STM32_FAULT_ENCODER_CONFIG);
    EXPECT_EQ(bad([](encoder_config_t& c) { c.start_count = 8192u; }), STM32_FAULT_ENCODER_CONFIG);
    EXPECT_EQ(bad([](encoder_config_t& c) { c.max_step_counts = 0u; }), STM32_FAULT_ENCODER_CONFIG);
    EXPECT_EQ(bad([](encoder_config_t& c) { c.max_step_counts = ENCODER_STEP_MAX + 1u; }), STM32_FAULT_ENCODER_CONFIG);
    EXPECT_EQ(bad([](encoder_config_t& c) { c.index_count = 8192u; }), STM32_FAULT_ENCODER_CONFIG);
    EXPECT_EQ(bad([](encoder_config_t& c) { c.index_tolerance = 4096u; }), STM32_FAULT_ENCODER_CONFIG);
    EXPECT_EQ(bad([](encoder_config_t& c) { c.index = false; c.index_count = 9000u; }), STM32_OK)
        << "the index's place matters only with the index";
    auto t = zeroed<tim_regs_t>();  // UIF never comes
    EXPECT_EQ(encoder_init(&e, &t, &good, kPolls), STM32_FAULT_ENCODER_TIMEOUT);
    EXPECT_EQ(t.CR1 & TIM_CR1_CEN, 0u) << "not started";
    float a = 0.0f;
    EXPECT_FALSE(encoder_read(&e, &t, &a));
}

// ---- the step/dir input (step_dir.h) ----

namespace {
// What TIM5 does in external clock mode 1 with STEP on TI1 (RM0090 18.3.3):
// each rising edge of STEP clocks the counter one way, CR1.DIR's
// (up when 0), the 32-bit counter wrapping; nothing counts while the
// counter is stopped or in another slave mode.
void step_pulses(tim_regs_t& t, uint32_t n)
{
    if ((t.CR1 & TIM_CR1_CEN) == 0u || (t.SMCR & 0x77u) != 0x57u) return;
    for (uint32_t k = 0; k < n; ++k) t.CNT = (t.CR1 & TIM_CR1_DIR) ? t.CNT - 1u : t.CNT + 1u;
}
// step_dir_init on a fake TIM5 whose "hardware" (a thread) answers the
// update (EGR UG) with its flag (SR UIF), as init_answered does the encoder's
stm32_status_t step_dir_answered(step_dir_t* s, tim_regs_t* t, exti_regs_t* e, syscfg_regs_t* sc,
                                 const step_dir_config_t& c, bool dir_level)
{
    std::atomic<bool> stop{false};
    std::thread hw([&] {
        while (!stop.load()) {
            if ((t->EGR & TIM_EGR_UG) != 0u) {
                t->EGR = 0u;
                t->SR = t->SR | TIM_SR_UIF;
            }
            std::this_thread::yield();
        }
    });
    const stm32_status_t st = step_dir_init(s, t, e, sc, &c, dir_level, 2000000000u);
    stop = true;
    hw.join();
    return st;
}
step_dir_config_t odrive_step_dir()
{
    // the ODrive v3.6's GPIO1 (PA0: TIM5_CH1, AF2) step and GPIO2 (PA1) dir
    // (ODrive firmware board.cpp: axis 0 step_gpio_pin 1, dir_gpio_pin 2)
    step_dir_config_t c;
    c.filter = 3u;
    c.dir_invert = false;
    c.dir_line = 1u;
    c.dir_port = 0u;
    return c;
}
}  // namespace

// The registers (RM0090 18.4): STEP on TI1 through the filter (CCMR1 CC1S
// = 01, IC1F), TS = TI1FP1 and SMS = external clock mode 1 (SMCR 0x57), all
// 32 bits (ARR), the update's wait answered; DIR's line 1 on port A (SYSCFG
// EXTICR1 bits 4-7 = 0), both edges, unmasked; the counter running from 0
// counting up (DIR high).
TEST(Stm32StepDir, RegistersOfExternalClockModeAndTheDirectionLine)
{
    auto t = zeroed<tim_regs_t>();
    auto e = zeroed<exti_regs_t>();
    auto sc = zeroed<syscfg_regs_t>();
    sc.EXTICR[0] = 0xFFF0u;  // line 1 was port P (0xF): the driver selects A
    t.CNT = 1234u;
    step_dir_t s;
    const step_dir_config_t c = odrive_step_dir();
    ASSERT_EQ(step_dir_answered(&s, &t, &e, &sc, c, true), STM32_OK);
    EXPECT_EQ(t.CCMR1, 0x31u);
    EXPECT_EQ(t.SMCR, 0x57u);
    EXPECT_EQ(t.ARR, 0xFFFFFFFFu);
    EXPECT_EQ(t.PSC, 0u);
    EXPECT_EQ(t.CCER, 0u) << "rising edges, the capture itself not used";
    EXPECT_EQ(t.CR1, TIM_CR1_CEN) << "counting up, edge-aligned";
    EXPECT_EQ(t.CNT, 0u);
    EXPECT_EQ(sc.EXTICR[0], 0xFF00u);
    EXPECT_EQ(e.RTSR, 2u);
    EXPECT_EQ(e.FTSR, 2u);
    EXPECT_EQ(e.IMR, 2u);
    EXPECT_EQ(e.PR, 2u) << "a stale edge cleared";
}

// Pulses on the fake timer: counted in DIR's direction, DIR's edges turn
// the count (the line's pending bit cleared), the signed count through 0,
// an inverted DIR, and the 32-bit counter's wrap read as a signed count.
TEST(Stm32StepDir, PulsesAndDirectionBecomeTheCount)
{
    auto t = zeroed<tim_regs_t>();
    auto e = zeroed<exti_regs_t>();
    auto sc = zeroed<syscfg_regs_t>();
    step_dir_t s;
    const step_dir_config_t c = odrive_step_dir();
    ASSERT_EQ(step_dir_answered(&s, &t, &e, &sc, c, true), STM32_OK);
    step_pulses(t, 100);
    EXPECT_EQ(step_dir_count(&t), 100);
    e.PR = 0u;
    step_dir_direction(&s, &t, &e, false);  // DIR low
    EXPECT_EQ(e.PR, 2u) << "the line's pending bit cleared";
    step_pulses(t, 250);
    EXPECT_EQ(step_dir_count(&t), -150);
    step_dir_direction(&s, &t, &e, true);
    step_pulses(t, 150);
    EXPECT_EQ(step_dir_count(&t), 0);
    EXPECT_EQ(s.direction_changes, 2u);
    // inverted: DIR high counts down
    auto u = zeroed<tim_regs_t>();
    step_dir_config_t ci = c;
    ci.dir_invert = true;
    ASSERT_EQ(step_dir_answered(&s, &u, &e, &sc, ci, true), STM32_OK);
    step_pulses(u, 3);
    EXPECT_EQ(step_dir_count(&u), -3);
    EXPECT_EQ(u.CNT, 0xFFFFFFFDu) << "the counter wrapped below 0";
}

// Every error: a filter, line or port the registers cannot hold (nothing
// written), and the update that never comes (the timer's clock not
// running): its timeout.
TEST(Stm32StepDir, ConfigurationErrorsAndTheTimeout)
{
    auto t = zeroed<tim_regs_t>();
    auto e = zeroed<exti_regs_t>();
    auto sc = zeroed<syscfg_regs_t>();
    step_dir_t s;
    step_dir_config_t c = odrive_step_dir();
    c.filter = 16u;
    EXPECT_EQ(step_dir_init(&s, &t, &e, &sc, &c, true, kPolls), STM32_FAULT_STEP_DIR_CONFIG);
    c = odrive_step_dir();
    c.dir_line = 16u;
    EXPECT_EQ(step_dir_init(&s, &t, &e, &sc, &c, true, kPolls), STM32_FAULT_STEP_DIR_CONFIG);
    c = odrive_step_dir();
    c.dir_port = 5u;
    EXPECT_EQ(step_dir_init(&s, &t, &e, &sc, &c, true, kPolls), STM32_FAULT_STEP_DIR_CONFIG);
    EXPECT_EQ(t.SMCR, 0u) << "nothing written";
    c = odrive_step_dir();
    EXPECT_EQ(step_dir_init(&s, &t, &e, &sc, &c, true, kPolls), STM32_FAULT_STEP_DIR_TIMEOUT);
    EXPECT_EQ(s.status, STM32_FAULT_STEP_DIR_TIMEOUT);
    EXPECT_EQ(t.CR1 & TIM_CR1_CEN, 0u) << "not started";
    EXPECT_EQ(e.IMR, 0u);
}

// Pulses generated on the fake timer become the position target: a step
// train counted by TIM5 and shaped (trajectory/step_shaper.h) offers moves
// to count x step angle; a burst faster than the design allows (the
// ODrive's configuration: w_max 20 rad/s, a_max 40 rad/s^2; 1/16
// microsteps) is counted as excess and still ends at the count.
TEST(Stm32StepDir, PulsesOnTheTimerBecomeThePositionTarget)
{
    auto t = zeroed<tim_regs_t>();
    auto e = zeroed<exti_regs_t>();
    auto sc = zeroed<syscfg_regs_t>();
    step_dir_t sd;
    const step_dir_config_t c = odrive_step_dir();
    ASSERT_EQ(step_dir_answered(&sd, &t, &e, &sc, c, true), STM32_OK);
    const float phi = 6.2831853f / 3200.0f;
    step_shaper_config_t sc_cfg;
    sc_cfg.step_angle_rad = phi;
    sc_cfg.speed_max_rad_s = 20.0f;
    sc_cfg.accel_max_rad_s2 = 40.0f;
    sc_cfg.fs_hz = 10000;
    step_shaper_t sh;
    ASSERT_TRUE(step_shaper_init(&sh, &sc_cfg, step_dir_count(&t)));
    step_shaper_move_t m;
    // 8 steps in one sample (80,000 steps/s): one move offered to 8 phi
    step_pulses(t, 8);
    step_shaper_step(&sh, step_dir_count(&t), 0.0f, &m);
    ASSERT_TRUE(m.move);
    EXPECT_FLOAT_EQ(m.theta_to_rad, 8 * phi);
    EXPECT_EQ(sh.excess_steps, 6u) << "8 steps, 2 of credit (the bucket)";
    step_shaper_answer(&sh, true);
    // the direction turned: 20 back, in the next sample, while the move runs
    step_dir_direction(&sd, &t, &e, false);
    step_pulses(t, 20);
    step_shaper_step(&sh, step_dir_count(&t), 8 * phi, &m);
    ASSERT_TRUE(m.move);
    EXPECT_FLOAT_EQ(m.theta_to_rad, -12 * phi);
    EXPECT_EQ(sh.excess_steps, 6u + 20u) << "0.47 steps of credit: none whole";
    step_shaper_answer(&sh, false);  // the drive still moving: offered again
    EXPECT_EQ(step_shaper_backlog(&sh), -20);
}

// ---- the DRV8301 over SPI (drv8301.h) ----

namespace {
// SPI3 and port C with the ODrive v3.6's two DRV8301 (nCS PC13, PC14)
// behind them; a thread plays the fake chips. The polls of a flag: enough
// for a loaded host to schedule the thread (a timeout takes a fraction of
// a second).
constexpr uint32_t kSpiPolls = 50000000u;
struct Drv8301Bench {
    spi_regs_t spi = zeroed<spi_regs_t>();
    gpio_regs_t port = zeroed<gpio_regs_t>();
    FakeDrv8301 fake{&spi, &port, 13u, 14u};
    drv8301_bus_t bus{};
    drv8301_chip_t m0{&port, 13u, "M0 (nCS PC13)"};
    drv8301_chip_t m1{&port, 14u, "M1 (nCS PC14)"};
    std::atomic<bool> stop{false};
    std::thread hw;
    explicit Drv8301Bench(FakeDrv8301::Mode mode = FakeDrv8301::Mode::kOk)
    {
        fake.mode = mode;
        drv8301_bus_init(&bus, &spi, 3u, kSpiPolls, 10u);
        drv8301_chip_init(&m0);
        drv8301_chip_init(&m1);
        hw = std::thread([this] {
            while (!stop.load()) {
                fake.poll();
                std::this_thread::yield();
            }
        });
    }
    // the thread stopped, the last chip-select writes taken
    void halt()
    {
        if (!stop.exchange(true)) hw.join();
        fake.poll();
    }
    ~Drv8301Bench() { halt(); }
};
const uint16_t kCtrl1 = static_cast<uint16_t>(DRV8301_CTRL1_OCP_LATCH | DRV8301_CTRL1_OC_ADJ(0u));
const uint16_t kCtrl2 = static_cast<uint16_t>(DRV8301_CTRL2_GAIN(DRV8301_GAIN_80));
}  // namespace

// The SPI master (RM0090 28.5.1): mode 1 (CPOL 0, CPHA 1), master, 16-bit
// frames, MSB first, software slave select (SSM, SSI), APB1's 42 MHz / 16 =
// 2.625 MHz (BR = 011), enabled; a chip select an output, high, low speed.
TEST(Stm32Drv8301, SpiRegistersTheDividerAndTheChipSelect)
{
    uint32_t br = 99u;
    ASSERT_TRUE(drv8301_spi_divider(42000000u, 2625000u, &br));
    EXPECT_EQ(br, 3u);
    ASSERT_TRUE(drv8301_spi_divider(42000000u, 10000000u, &br));
    EXPECT_EQ(br, 2u) << "42 MHz / 8 = 5.25 MHz";
    EXPECT_FALSE(drv8301_spi_divider(42000000u, 100000u, &br)) << "/256 is 164 kHz";
    auto spi = zeroed<spi_regs_t>();
    drv8301_bus_t bus{};
    drv8301_bus_init(&bus, &spi, 3u, kPolls, 0u);
    EXPECT_EQ(spi.CR1, 0x0B5Du) << "DFF, SSM, SSI, SPE, BR 011, MSTR, CPHA";
    EXPECT_EQ(spi.CR2, 0u);
    auto port = zeroed<gpio_regs_t>();
    port.OSPEEDR = 0xFFFFFFFFu;
    const drv8301_chip_t c{&port, 13u, "M0"};
    drv8301_chip_init(&c);
    EXPECT_EQ((port.MODER >> 26) & 3u, 1u) << "PC13 an output";
    EXPECT_EQ((port.OSPEEDR >> 26) & 3u, 0u) << "low speed (DS8626: PC13-15 at most 2 MHz)";
    EXPECT_EQ(port.BSRR, 1u << 13) << "high: not selected";
}

// Both control registers written (control register 2's GAIN = 11: 80 V/V),
// then read back: each read twice on the wire, the chip answering one
// frame late; the gain read back is what the backend scales with. A status
// register read: FAULT and FETHB_OC.
TEST(Stm32Drv8301, ControlRegistersWrittenThenReadBack)
{
    Drv8301Bench b;
    uint16_t ctrl2 = 0u;
    ASSERT_TRUE(drv8301_configure(&b.bus, &b.m1, kCtrl1, kCtrl2, &ctrl2)) << b.bus.error;
    EXPECT_EQ(ctrl2, 0x00Cu);
    EXPECT_EQ(DRV8301_GAIN_VV(DRV8301_CTRL2_GAIN_OF(ctrl2)), 80u);
    EXPECT_EQ(b.bus.status, STM32_OK);
    EXPECT_STREQ(b.bus.error, "");
    EXPECT_EQ(b.fake.reg(1, DRV8301_REG_CTRL1), 0x010u);
    EXPECT_EQ(b.fake.reg(1, DRV8301_REG_CTRL2), 0x00Cu);
    EXPECT_EQ(b.fake.reg(0, DRV8301_REG_CTRL2), 0u) << "M0 not selected";
    // write 0x02 <- 0x010, write 0x03 <- 0x00C, read 0x02 twice, read 0x03 twice
    const std::vector<uint16_t> want{0x1010u, 0x180Cu, 0x9000u, 0x9000u, 0x9800u, 0x9800u};
    EXPECT_EQ(b.fake.words_to(1), want);
    EXPECT_TRUE(b.fake.words_to(0).empty());
    b.fake.set_reg(0, DRV8301_REG_STATUS1, 0x408u);
    uint16_t s1 = 0u;
    ASSERT_TRUE(drv8301_read(&b.bus, &b.m0, DRV8301_REG_STATUS1, &s1)) << b.bus.error;
    EXPECT_EQ(s1, 0x408u);
    EXPECT_TRUE(s1 & DRV8301_STATUS1_FAULT);
    b.halt();
    EXPECT_EQ(b.fake.selected(), -1) << "nCS high after the last frame";
}

// A chip that does not keep control register 2 (its read-back 0x000, the
// reset value): refused, the text naming the chip, the register, the value
// written and the value read.
TEST(Stm32Drv8301, ReadBackThatDiffersIsRefusedWithTheValues)
{
    Drv8301Bench b;
    b.fake.drop_writes_chip = 0;
    b.fake.drop_writes_addr = static_cast<int>(DRV8301_REG_CTRL2);
    uint16_t ctrl2 = 0xFFFFu;
    EXPECT_FALSE(drv8301_configure(&b.bus, &b.m0, kCtrl1, kCtrl2, &ctrl2));
    EXPECT_EQ(b.bus.status, STM32_FAULT_GATE_DRIVER_CONFIG);
    EXPECT_STREQ(b.bus.error, "DRV8301 M0 (nCS PC13): control register 2 written 0x00C, read back 0x000");
    EXPECT_EQ(ctrl2, 0xFFFFu) << "no gain handed out";
}

// Each of the SPI's flags that never comes: an error naming it, the chip
// select left high, nothing waits for ever.
TEST(Stm32Drv8301, EachSpiFlagTimeoutIsAnErrorNamingIt)
{
    const struct {
        FakeDrv8301::Mode mode;
        const char* text;
    } cases[] = {
        {FakeDrv8301::Mode::kNoTxe, "DRV8301 M0 (nCS PC13): SPI TXE (transmit buffer empty) timed out (frame 0x1010)"},
        {FakeDrv8301::Mode::kNoRxne, "DRV8301 M0 (nCS PC13): SPI RXNE (word received) timed out (frame 0x1010)"},
        {FakeDrv8301::Mode::kBusyStuck, "DRV8301 M0 (nCS PC13): SPI BSY (bus busy) timed out (frame 0x1010)"},
    };
    for (const auto& c : cases) {
        Drv8301Bench b(c.mode);
        uint16_t ctrl2 = 0u;
        EXPECT_FALSE(drv8301_configure(&b.bus, &b.m0, kCtrl1, kCtrl2, &ctrl2));
        EXPECT_EQ(b.bus.status, STM32_FAULT_GATE_DRIVER_SPI);
        EXPECT_STREQ(b.bus.error, c.text);
        b.halt();
        EXPECT_EQ(b.fake.selected(), -1) << c.text;
    }
}
