/* mcu_rt.c - start-up and vector table of the mps2 qemu test images (their text output: mcu_semihost.c). */
#include "mcu_rt.h"

extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _estack;

void Reset_Handler(void);
void Fault_Handler(void);
void Default_Handler(void);

void Reset_Handler(void)
{
    uint32_t *src = &_sidata;
    /* cppcheck-suppress comparePointers ; linker symbols: _sdata and _edata bound one section (mps2.ld) */
    for (uint32_t *dst = &_sdata; dst < &_edata;) {
        *dst++ = *src++;
    }
    /* cppcheck-suppress comparePointers ; linker symbols: _sbss and _ebss bound one section (mps2.ld) */
    for (uint32_t *dst = &_sbss; dst < &_ebss;) {
        *dst++ = 0u;
    }
#if defined(__ARM_FP)
    /* enable CP10/CP11 (the FPU) */
    *(volatile uint32_t *)0xE000ED88u |= (0xFu << 20);
    __asm__ volatile("dsb\n\tisb" ::: "memory");
#endif
    MCU_SYST_RVR = 0x00FFFFFFu;
    MCU_SYST_CVR = 0u;
    MCU_SYST_CSR = 0x5u; /* enable, core clock, no interrupt */
    mcu_exit(main());
}

void Fault_Handler(void)
{
    mcu_puts("\nMCU FAULT\n");
    mcu_exit(2);
}

void Default_Handler(void)
{
    mcu_puts("\nMCU UNEXPECTED IRQ\n");
    mcu_exit(3);
}

__attribute__((section(".isr_vector"), used)) void (*const mcu_vectors[16])(void) = {
    (void (*)(void))(uintptr_t)&_estack,
    Reset_Handler,
    Default_Handler, /* NMI */
    Fault_Handler,   /* HardFault */
    Fault_Handler,   /* MemManage */
    Fault_Handler,   /* BusFault */
    Fault_Handler,   /* UsageFault */
    0, 0, 0, 0,
    Default_Handler, /* SVC */
    Default_Handler, /* DebugMon */
    0,
    Default_Handler, /* PendSV */
    Default_Handler, /* SysTick */
};
