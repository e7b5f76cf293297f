/*
 * startup_stm32f405.c - reset and the vector table of the STM32F405
 * (RM0090 table 61: 16 core exceptions, 82 interrupts). The reset handler
 * copies .data from flash, clears .bss, turns the FPU on (CPACR CP10/CP11
 * full access: the drive is float on the M4F's FPU) and calls main().
 * Every interrupt without a handler of its own goes to the backend's
 * fault state: bridges off, the fault code kept (stm32_backend.h).
 */
#include <stdint.h>

#include "stm32_backend.h"
#include "stm32f405_regs.h"

extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _estack;
int main(void);

void Reset_Handler(void);
void Default_Handler(void);

void Reset_Handler(void)
{
    const uint32_t *src = &_sidata;
    /* cppcheck-suppress comparePointers ; linker symbols: _sdata and _edata bound one section (stm32f405.ld) */
    for (uint32_t *dst = &_sdata; dst < &_edata;) {
        *dst++ = *src++;
    }
    /* cppcheck-suppress comparePointers ; linker symbols: _sbss and _ebss bound one section (stm32f405.ld) */
    for (uint32_t *dst = &_sbss; dst < &_ebss;) {
        *dst++ = 0u;
    }
    SCB_CPACR |= 0xFu << 20;
    __asm__ volatile("dsb\n isb" ::: "memory");
    (void)main();
    stm32_backend_fault(STM32_FAULT_UNEXPECTED_IRQ);
}

void Default_Handler(void) { stm32_backend_fault(STM32_FAULT_UNEXPECTED_IRQ); }

#define WEAK_HANDLER(name) void name(void) __attribute__((weak, alias("Default_Handler")))
WEAK_HANDLER(NMI_Handler);
WEAK_HANDLER(HardFault_Handler);
WEAK_HANDLER(MemManage_Handler);
WEAK_HANDLER(BusFault_Handler);
WEAK_HANDLER(UsageFault_Handler);
WEAK_HANDLER(SVC_Handler);
WEAK_HANDLER(DebugMon_Handler);
WEAK_HANDLER(PendSV_Handler);
WEAK_HANDLER(SysTick_Handler);
WEAK_HANDLER(ADC_IRQHandler);
WEAK_HANDLER(CAN1_TX_IRQHandler);
WEAK_HANDLER(CAN1_RX0_IRQHandler);
WEAK_HANDLER(CAN1_SCE_IRQHandler);
WEAK_HANDLER(TIM1_BRK_TIM9_IRQHandler);
WEAK_HANDLER(TIM2_IRQHandler);
WEAK_HANDLER(EXTI0_IRQHandler);
WEAK_HANDLER(EXTI1_IRQHandler);
WEAK_HANDLER(EXTI2_IRQHandler);
WEAK_HANDLER(EXTI3_IRQHandler);
WEAK_HANDLER(EXTI4_IRQHandler);

typedef void (*vector_t)(void);

/* every entry Default_Handler first (no NULL vector), then the ones used */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Woverride-init"
__attribute__((section(".isr_vector"), used)) const vector_t stm32_vectors[16 + STM32F405_N_IRQ] = {
    [2 ... 16 + STM32F405_N_IRQ - 1] = Default_Handler,
    [0] = (vector_t)(uintptr_t)&_estack,
    [1] = Reset_Handler,
    [2] = NMI_Handler,
    [3] = HardFault_Handler,
    [4] = MemManage_Handler,
    [5] = BusFault_Handler,
    [6] = UsageFault_Handler,
    [11] = SVC_Handler,
    [12] = DebugMon_Handler,
    [14] = PendSV_Handler,
    [15] = SysTick_Handler,
    [16 + IRQ_ADC] = ADC_IRQHandler,
    [16 + IRQ_CAN1_TX] = CAN1_TX_IRQHandler,
    [16 + IRQ_CAN1_RX0] = CAN1_RX0_IRQHandler,
    [16 + IRQ_CAN1_SCE] = CAN1_SCE_IRQHandler,
    [16 + IRQ_TIM1_BRK_TIM9] = TIM1_BRK_TIM9_IRQHandler,
    [16 + IRQ_TIM2] = TIM2_IRQHandler,
    [16 + IRQ_EXTI0] = EXTI0_IRQHandler,
    [16 + IRQ_EXTI0 + 1] = EXTI1_IRQHandler,
    [16 + IRQ_EXTI0 + 2] = EXTI2_IRQHandler,
    [16 + IRQ_EXTI0 + 3] = EXTI3_IRQHandler,
    [16 + IRQ_EXTI0 + 4] = EXTI4_IRQHandler,
};
#pragma GCC diagnostic pop
