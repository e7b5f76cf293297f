/*
 * pil_common.h - what the PIL image (pil_image.c) and a drive's PIL probe
 * (pil_probe.h) share besides the drive: the bit-exact view of an mc_t as
 * the host recorded it, the stack high-water mark (the free RAM painted
 * with a pattern before the run), a timed region and a line buffer written
 * with one semihosting call. Included once per translation unit; _ebss and
 * _estack come from the linker script (mps2.ld).
 */
#ifndef PIL_COMMON_H
#define PIL_COMMON_H

#include <stdint.h>
#include <string.h>

#include "math/mc_num.h"
#include "mcu_rt.h"

extern uint32_t _ebss, _estack;

static inline mc_t from_bits(uint32_t u)
{
    mc_t v;
    memcpy(&v, &u, sizeof v);
    return v;
}

static inline uint32_t to_bits(mc_t v)
{
    uint32_t u;
    memcpy(&u, &v, sizeof u);
    return u;
}

/* fill the free stack with a pattern to measure the high-water mark */
__attribute__((noinline, unused)) static void paint_stack(void)
{
    volatile uint32_t *p = &_ebss;
    uint32_t here;
    const volatile uint32_t *stop = (const volatile uint32_t *)((uintptr_t)&here - 256u);
    while (p < stop) {
        *p++ = 0xDEADBEEFu;
    }
}

static inline uint32_t stack_used(void)
{
    const uint32_t *p = &_ebss;
    /* cppcheck-suppress comparePointers ; linker symbols: _ebss and _estack bound the stack's RAM (mps2.ld) */
    while (p < &_estack && *p == 0xDEADBEEFu) {
        ++p;
    }
    return (uint32_t)((uintptr_t)&_estack - (uintptr_t)p);
}

/* t_out = SysTick ticks of call; the empty asm keep the argument stores
 * before and the result use after the timed region (the compiler may not
 * move memory accesses across them) */
#define PIL_TIME(t_out, call)                                                                                          \
    do {                                                                                                               \
        __asm__ volatile("" ::: "memory");                                                                             \
        const uint32_t t0_ = mcu_systick_now();                                                                        \
        call;                                                                                                          \
        const uint32_t t1_ = mcu_systick_now();                                                                        \
        __asm__ volatile("" ::: "memory");                                                                             \
        (t_out) = mcu_systick_elapsed(t0_, t1_);                                                                       \
    } while (0)

/* a line built in a buffer, written with one semihosting call */
typedef struct {
    char buf[400];
    uint32_t len;
} pil_line_t;

static inline void pil_line_char(pil_line_t *l, char ch)
{
    if (l->len + 1u < sizeof l->buf) {
        l->buf[l->len++] = ch;
    }
}

static inline void pil_line_u32(pil_line_t *l, uint32_t v)
{
    char tmp[10];
    uint32_t k = 0u;
    do {
        tmp[k++] = (char)('0' + (char)(v % 10u));
        v /= 10u;
    } while (v != 0u);
    while (k > 0u) {
        pil_line_char(l, tmp[--k]);
    }
}

static inline void pil_line_flush(pil_line_t *l)
{
    l->buf[l->len] = '\0';
    mcu_puts(l->buf);
    l->len = 0u;
}

#endif /* PIL_COMMON_H */
