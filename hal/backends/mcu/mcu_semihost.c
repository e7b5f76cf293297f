/* mcu_semihost.c - text and exit through ARM semihosting (QEMU's
 * -semihosting-config; mcu_rt.h): shared by every bare-metal image (the
 * mps2 runtime, the STM32F405 image under QEMU). */
#include "mcu_rt.h"

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
