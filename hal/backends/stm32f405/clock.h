/*
 * clock.h - the STM32F405's clock tree from an external crystal through
 * the main PLL (RM0090 6.2, 6.3.2): SYSCLK and the bus clocks a board
 * asks for, the flash wait states they need, and the start-up that sets
 * them with every wait on a ready flag bounded. A crystal that does not
 * start, a PLL that does not lock or a switch that does not happen leaves
 * the chip on its internal 16 MHz oscillator and returns the fault.
 */
#ifndef STM32_CLOCK_H
#define STM32_CLOCK_H

#include <stdbool.h>
#include <stdint.h>

#include "stm32_status.h"
#include "stm32f405_regs.h"

/* The PLL's input after /M: 2 MHz, the value RM0090 6.3.2 recommends
 * (least jitter); its VCO must stay in [100, 432] MHz. */
#define CLOCK_PLL_IN_HZ 2000000u
#define CLOCK_VCO_MIN_HZ 100000000u
#define CLOCK_VCO_MAX_HZ 432000000u
/* USB OTG FS, SDIO and RNG need 48 MHz from /Q (RM0090 6.2). */
#define CLOCK_48MHZ 48000000u
/* One flash wait state per 30 MHz of HCLK at 2.7-3.6 V (RM0090 table 10). */
#define CLOCK_HZ_PER_WAIT_STATE 30000000u
#define CLOCK_SYSCLK_MAX_HZ 168000000u
#define CLOCK_APB1_MAX_HZ 42000000u
#define CLOCK_APB2_MAX_HZ 84000000u

typedef struct {
    uint32_t hse_hz, sysclk_hz;
    uint32_t pll_m, pll_n, pll_p, pll_q;
    uint32_t flash_ws;
    uint32_t apb1_hz, apb2_hz;
    uint32_t apb1_timer_hz, apb2_timer_hz; /* x2 when the APB prescaler is not 1 (RM0090 6.2) */
} clock_plan_t;

/* SYSCLK = sysclk_hz from an hse_hz crystal with AHB /1, APB1 /4, APB2 /2
 * (42 and 84 MHz at 168 MHz: the buses' maxima); false if no M, N, P, Q
 * gives it exactly within the PLL's ranges. */
bool clock_plan(uint32_t hse_hz, uint32_t sysclk_hz, clock_plan_t *p);

/* Runs the plan: HSE on, PLL, flash latency before the switch, SYSCLK to
 * the PLL. Each wait polls its flag at most timeout_polls times. */
stm32_status_t clock_init(rcc_regs_t *rcc, flash_regs_t *flash, const clock_plan_t *p, uint32_t timeout_polls);

#endif /* STM32_CLOCK_H */
