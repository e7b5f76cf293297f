/*
 * mcu_rt.h - the bare-metal run time of the Cortex-M test images (qemu
 * mps2-an386 = Cortex-M4F, mps2-an385 = Cortex-M3): start-up, semihosting
 * console and exit, SysTick as an instruction/cycle counter. Integer only,
 * no libc: the fixed-point M3 image must contain no floating-point code.
 */
#ifndef MCU_RT_H
#define MCU_RT_H

#include <stdint.h>

/* SysTick: a 24-bit down counter at the core clock (enabled by the start-up
 * code with reload 0xFFFFFF). mcu_ticks() is monotonic modulo 2^24. */
#define MCU_SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define MCU_SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define MCU_SYST_CVR (*(volatile uint32_t *)0xE000E018u)
static inline uint32_t mcu_systick_now(void) { return MCU_SYST_CVR; }
/* elapsed ticks between two mcu_systick_now() readings (down counter) */
static inline uint32_t mcu_systick_elapsed(uint32_t t0, uint32_t t1) { return (t0 - t1) & 0x00FFFFFFu; }

void mcu_puts(const char *s);             /* semihosting SYS_WRITE0 */
void mcu_put_u32(uint32_t v);             /* decimal */
void mcu_put_i32(int32_t v);              /* decimal */
void mcu_put_hex32(uint32_t v);           /* 8 hex digits */
void mcu_put_kv(const char *key, uint32_t v); /* " key=v" */
void mcu_exit(int code) __attribute__((noreturn)); /* 0 -> qemu exits 0, else 1 */

int main(void);

#endif /* MCU_RT_H */
