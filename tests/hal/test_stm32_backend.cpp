// The STM32F405 backend's start-up (hal/backends/stm32f405/stm32_backend.c)
// on fake peripherals with the VESC 6 board table: a small "hardware"
// thread answers like the chip would (ADC conversions end, bxCAN follows
// its initialisation request); each bad start-up condition ends in the
// fault state with the bridges off (TIM1 MOE = 0, the DRV8301's EN_GATE
// low) and its code: a crystal that does not start, a watchdog reset, a
// current sensor's zero out of range, the over-current break after a good
// start, the encoder's timer that does not answer; and hal_start() then
// refuses to run. The encoder's angle in the control sample, and withheld
// once the encoder erred.
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <string>
#include <thread>

extern "C" {
#include "boards/board.h"
#include "stm32_backend.h"
}

// the motor's encoder as a drive's parameters on the VESC 6 would give it
// (its encoder_counts, stm32_backend_configure before the start): 2048 lines
const bool kEncoderConfigured = stm32_backend_configure(board.can_node, board.dead_time_ns, 8192u) == STM32_OK;

namespace {

struct Regs {
    rcc_regs_t rcc;
    flash_regs_t flash;
    tim_regs_t tim1, tim2, tim3;
    adc_common_regs_t adc_common;
    adc_regs_t adc[3];
    can_regs_t can1;
    iwdg_regs_t iwdg;
    gpio_regs_t gpio[5];
};

struct FakeChip : Regs {
    stm32_periph_t hw;
    std::atomic<bool> stop{false};
    std::atomic<bool> tim3_clock{true};  // false: TIM3 never answers its update
    std::thread hardware;

    explicit FakeChip(uint32_t zero_code)
    {
        std::memset(static_cast<void*>(static_cast<Regs*>(this)), 0, sizeof(Regs));
        hw = {&rcc, &flash, &tim1, &tim2, &tim3, &adc_common, {&adc[0], &adc[1], &adc[2]}, &can1, &iwdg,
              {&gpio[0], &gpio[1], &gpio[2], &gpio[3], &gpio[4]}, nullptr, nullptr, nullptr, nullptr, nullptr};
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
                // an update event sets UIF (RM0090 18.4.5) when the timer's clock runs
                if (tim3_clock.load() && (tim3.EGR & TIM_EGR_UG) != 0u) {
                    tim3.EGR = 0u;
                    tim3.SR = tim3.SR | TIM_SR_UIF;
                }
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
    ASSERT_TRUE(kEncoderConfigured);
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

// The VESC 6's encoder port (TIM3, PC6/PC7 AF2) started with the counts per
// turn of the drive's configuration, in encoder mode 3; each control sample
// then carries the angle: a quarter turn at count 2048 of 8192.
TEST(Stm32Backend, EncoderStartsAndItsAngleReachesTheSample)
{
    FakeChip chip(2048);
    chip.clocks_ok();
    ASSERT_TRUE(stm32_backend_init(&chip.hw)) << hal_last_error();
    EXPECT_TRUE(chip.rcc.APB1ENR & RCC_APB1ENR_TIM3EN);
    EXPECT_EQ(chip.tim3.SMCR, 3u);
    EXPECT_EQ(chip.tim3.CR1 & TIM_CR1_CEN, TIM_CR1_CEN);
    EXPECT_EQ((chip.gpio[2].MODER >> 12) & 0xFu, 0xAu) << "PC6, PC7 alternate function";
    EXPECT_EQ(chip.gpio[2].AFR[0] >> 24, 0x22u) << "AF2: TIM3_CH1, TIM3_CH2";
    ASSERT_NE(stm32_backend_encoder(), nullptr);
    EXPECT_EQ(stm32_backend_encoder()->cfg.max_step_counts, 2733u) << "8192 x 3334 rev/s / 10 kHz, up, + 1";
    chip.tim3.CNT = 2048u;
    hal_sample_t in;
    stm32_backend_sample(&in);
    EXPECT_TRUE(in.has_angle);
    EXPECT_FLOAT_EQ(static_cast<float>(in.angle_rad), 1.5707964f);
    EXPECT_EQ(in.n_phases, 3u);
}

// The encoder's timer that never answers its update (its clock not
// running): the start-up's fault, bridges off, nothing starts.
TEST(Stm32Backend, EncoderTimerThatDoesNotAnswerIsAFaultWithBridgesOff)
{
    FakeChip chip(2048);
    chip.tim3_clock = false;
    chip.clocks_ok();
    EXPECT_FALSE(stm32_backend_init(&chip.hw));
    EXPECT_EQ(stm32_backend_status(), STM32_FAULT_ENCODER_TIMEOUT);
    EXPECT_EQ(std::string(hal_last_error()), "encoder: its timer did not answer the update");
    EXPECT_FALSE(chip.moe());
    EXPECT_TRUE(chip.gate_low());
    EXPECT_FALSE(hal_start(&dummy_control, nullptr));
}

// A count that jumps beyond the board's fastest motor: the sample comes
// without the angle (a drive that reads it refuses the sample: its
// BAD_INPUT, the safe state), the encoder's error kept and named; the
// backend itself runs on (a sensorless drive does not need the encoder).
TEST(Stm32Backend, EncoderErrorWithholdsTheAngle)
{
    FakeChip chip(2048);
    chip.clocks_ok();
    ASSERT_TRUE(stm32_backend_init(&chip.hw)) << hal_last_error();
    hal_sample_t in;
    chip.tim3.CNT = 2000u;
    stm32_backend_sample(&in);
    EXPECT_TRUE(in.has_angle);
    chip.tim3.CNT = 2000u + 2734u;
    stm32_backend_sample(&in);
    EXPECT_FALSE(in.has_angle);
    EXPECT_EQ(stm32_backend_encoder()->status, STM32_FAULT_ENCODER_STEP);
    EXPECT_EQ(std::string(hal_last_error()), "encoder: count moved faster than any motor on the board");
    EXPECT_EQ(stm32_backend_status(), STM32_OK);
    chip.tim3.CNT = 2000u;
    stm32_backend_sample(&in);
    EXPECT_FALSE(in.has_angle) << "latched";
}

// The TIM1 break at run time (the bridges' over-current comparator): the
// next sample carries the trip to the drive, then the backend's fault
// state, the bridges off; the control interrupt goes on with the
// application called (its drive holds FAULT, its CAN node reports it) and
// no duty written, the watchdog fed (no reset 10 ms later that would lose
// the cause and restart the bridges); after hal_safe_state the application
// is no longer called, the watchdog still fed.
namespace {
struct Seen {
    int calls = 0;
    uint32_t status = 0;
};
void recording_control(void* ctx, const hal_sample_t* in, hal_command_t* out)
{
    auto* s = static_cast<Seen*>(ctx);
    s->calls += 1;
    s->status |= in->status;
    out->v_V[0] = 3.0f;  // a command the backend must not apply once in fault
}
}  // namespace

TEST(Stm32Backend, BreakAtRunTimeReachesTheDriveAndTheBoardStaysSafeAndAlive)
{
    FakeChip chip(2048);
    chip.clocks_ok();
    ASSERT_TRUE(stm32_backend_init(&chip.hw)) << hal_last_error();
    Seen seen;
    ASSERT_TRUE(hal_start(&recording_control, &seen)) << hal_last_error();
    hal_sample_t in{};
    stm32_backend_control(&in);
    ASSERT_EQ(seen.calls, 1);
    EXPECT_EQ(seen.status & HAL_STATUS_PWM_TRIP, 0u);
    // the comparator trips: the hardware clears MOE, the interrupt comes
    chip.tim1.BDTR &= ~TIM_BDTR_MOE;
    chip.tim1.SR = TIM_SR_BIF;
    stm32_backend_break();
    EXPECT_TRUE(chip.gate_low());
    in = hal_sample_t{};
    stm32_backend_control(&in);
    EXPECT_EQ(seen.calls, 2);
    EXPECT_NE(seen.status & HAL_STATUS_PWM_TRIP, 0u) << "the drive saw the trip";
    EXPECT_EQ(stm32_backend_status(), STM32_FAULT_OVERCURRENT_BREAK);
    const uint32_t ccr[3] = {chip.tim1.CCR[0], chip.tim1.CCR[1], chip.tim1.CCR[2]};
    for (int k = 0; k < 3; ++k) {
        chip.iwdg.KR = 0u;
        in = hal_sample_t{};
        stm32_backend_control(&in);
        EXPECT_EQ(chip.iwdg.KR, IWDG_KEY_REFRESH) << "the watchdog fed in the fault state";
    }
    EXPECT_EQ(seen.calls, 5) << "the application still runs";
    EXPECT_EQ(chip.tim1.CCR[0], ccr[0]);
    EXPECT_EQ(chip.tim1.CCR[1], ccr[1]);
    EXPECT_EQ(chip.tim1.CCR[2], ccr[2]);
    EXPECT_FALSE(chip.moe());
    hal_safe_state();
    chip.iwdg.KR = 0u;
    stm32_backend_control(&in);
    EXPECT_EQ(seen.calls, 5) << "stopped by the application";
    EXPECT_EQ(chip.iwdg.KR, IWDG_KEY_REFRESH);
}
