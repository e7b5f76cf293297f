/*
 * iwdg.h - the independent watchdog (RM0090 ch. 19), clocked by the LSI
 * RC oscillator (32 kHz nominal, 17-47 kHz over parts and temperature):
 * once started nothing stops it; the control step refreshes it, so a
 * control interrupt that stops coming resets the chip, and the next
 * start-up reads the reset flag and stays in its fault state.
 */
#ifndef STM32_IWDG_H
#define STM32_IWDG_H

#include <stdbool.h>
#include <stdint.h>

#include "stm32_status.h"
#include "stm32f405_regs.h"

#define IWDG_LSI_NOMINAL_HZ 32000u

/* Prescaler code (0: /4 .. 6: /256) and reload (<= 4095) for timeout_us
 * at lsi_hz, the smallest prescaler that fits; false if none does. */
bool iwdg_plan(uint32_t lsi_hz, uint32_t timeout_us, uint32_t *pr, uint32_t *rlr);

/* Starts it: enable key, unlock, PR and RLR, wait for both to load (at
 * most timeout_polls polls), refresh. */
stm32_status_t iwdg_start(iwdg_regs_t *w, uint32_t pr, uint32_t rlr, uint32_t timeout_polls);

static inline void iwdg_refresh(iwdg_regs_t *w) { w->KR = IWDG_KEY_REFRESH; }

#endif /* STM32_IWDG_H */
