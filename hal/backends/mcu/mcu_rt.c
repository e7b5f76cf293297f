/* mcu_rt.c - start-up, vector table, semihosting for the qemu test images. */
#include "mcu_rt.h"

extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _estack;

static int semihost(int op, const void *arg)
{
    register int r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

void mcu_puts(const char *s) { (void)semihost(0x04, s); }

void mcu_put_u32(uint32_t v)
{
    char buf[12];
    int i = 11;
    buf[i] = '\0';
    do {
        buf[--i] = (char)('0' + (v % 10u));
        v /= 10u;
    } while (v != 0u);
    mcu_puts(&buf[i]);
}

void mcu_put_i32(int32_t v)
{
    if (v < 0) {
        mcu_puts("-");
        mcu_put_u32(0u - (uint32_t)v);
    } else {
        mcu_put_u32((uint32_t)v);
    }
}

void mcu_put_hex32(uint32_t v)
{
    char buf[9];
    for (int i = 7; i >= 0; --i) {
        const uint32_t d = v & 0xFu;
        buf[i] = (char)((d < 10u) ? ('0' + d) : ('a' + d - 10u));
        v >>= 4;
    }
    buf[8] = '\0';
    mcu_puts(buf);
}

void mcu_put_kv(const char *key, uint32_t v)
{
    mcu_puts(" ");
    mcu_puts(key);
    mcu_puts("=");
    mcu_put_u32(v);
}

void mcu_exit(int code)
{
    /* ADP_Stopped_ApplicationExit -> qemu exit status 0, RunTimeErrorUnknown -> 1 */
    for (;;) {
        (void)semihost(0x18, (const void *)(uintptr_t)((code == 0) ? 0x20026u : 0x20023u));
    }
}

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
