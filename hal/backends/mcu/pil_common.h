/*
 * pil_common.h - what both PIL images (pil_main.c for paper 000's drive,
 * pil_paper001_main.c for paper 001's) need besides their drive: the
 * bit-exact view of an mc_t as the host recorded it, and the stack
 * high-water mark (the free RAM painted with a pattern before the run).
 * Included once per image; _ebss and _estack come from the linker script
 * (mps2.ld).
 */
#ifndef PIL_COMMON_H
#define PIL_COMMON_H

#include <stdint.h>
#include <string.h>

#include "math/mc_num.h"

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
__attribute__((noinline)) static void paint_stack(void)
{
    volatile uint32_t *p = &_ebss;
    uint32_t here;
    const volatile uint32_t *stop = (const volatile uint32_t *)((uintptr_t)&here - 256u);
    while (p < stop) {
        *p++ = 0xDEADBEEFu;
    }
}

static uint32_t stack_used(void)
{
    const uint32_t *p = &_ebss;
    /* cppcheck-suppress comparePointers ; linker symbols: _ebss and _estack bound the stack's RAM (mps2.ld) */
    while (p < &_estack && *p == 0xDEADBEEFu) {
        ++p;
    }
    return (uint32_t)((uintptr_t)&_estack - (uintptr_t)p);
}

#endif /* PIL_COMMON_H */
