/*
 * irq.h - interrupts masked around a short section the control interrupt
 * must not enter (the flash's waits, whose vectors and handlers sit in the
 * flash; the bridges' outputs switched from the main loop), the caller's
 * mask restored after (PRIMASK: ARMv7-M ARM B1.4.3, CPSID I). On the host
 * (the drivers' tests) nothing is masked.
 */
#ifndef STM32_IRQ_H
#define STM32_IRQ_H

#include <stdint.h>

/* Masks interrupts; returns the PRIMASK before, for irq_restore. */
static inline uint32_t irq_mask(void)
{
#if defined(__arm__)
    uint32_t primask;
    __asm__ volatile("mrs %0, primask\n cpsid i" : "=r"(primask)::"memory");
    return primask;
#else
    return 0u;
#endif
}

/* PRIMASK back to what irq_mask returned. */
static inline void irq_restore(uint32_t primask)
{
#if defined(__arm__)
    __asm__ volatile("msr primask, %0" ::"r"(primask) : "memory");
#else
    (void)primask;
#endif
}

#endif /* STM32_IRQ_H */
