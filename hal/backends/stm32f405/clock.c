#include "clock.h"

bool clock_plan(uint32_t hse_hz, uint32_t sysclk_hz, clock_plan_t *p)
{
    if (hse_hz < 4000000u || hse_hz > 26000000u || (hse_hz % CLOCK_PLL_IN_HZ) != 0u ||
        sysclk_hz > CLOCK_SYSCLK_MAX_HZ || sysclk_hz == 0u) {
        return false;
    }
    p->hse_hz = hse_hz;
    p->sysclk_hz = sysclk_hz;
    p->pll_m = hse_hz / CLOCK_PLL_IN_HZ;
    /* the smallest P (2, 4, 6, 8) that puts the VCO in range and makes Q whole */
    bool found = false;
    for (uint32_t pp = 2u; pp <= 8u && !found; pp += 2u) {
        const uint64_t vco = (uint64_t)sysclk_hz * pp;
        if (vco < CLOCK_VCO_MIN_HZ || vco > CLOCK_VCO_MAX_HZ || (vco % CLOCK_PLL_IN_HZ) != 0u ||
            (vco % CLOCK_48MHZ) != 0u) {
            continue;
        }
        p->pll_p = pp;
        p->pll_n = (uint32_t)(vco / CLOCK_PLL_IN_HZ);
        p->pll_q = (uint32_t)(vco / CLOCK_48MHZ);
        found = p->pll_n >= 50u && p->pll_n <= 432u && p->pll_q >= 2u && p->pll_q <= 15u;
    }
    if (!found) {
        return false;
    }
    p->flash_ws = (sysclk_hz - 1u) / CLOCK_HZ_PER_WAIT_STATE;
    p->apb1_hz = sysclk_hz / 4u;
    p->apb2_hz = sysclk_hz / 2u;
    p->apb1_timer_hz = 2u * p->apb1_hz;
    p->apb2_timer_hz = 2u * p->apb2_hz;
    return p->apb1_hz <= CLOCK_APB1_MAX_HZ && p->apb2_hz <= CLOCK_APB2_MAX_HZ;
}

/* polls (*reg & mask) == want at most n times */
static bool wait_for(const volatile uint32_t *reg, uint32_t mask, uint32_t want, uint32_t n)
{
    for (uint32_t k = 0; k < n; ++k) {
        if ((*reg & mask) == want) {
            return true;
        }
    }
    return false;
}

/* back on the internal oscillator, PLL and crystal off */
static stm32_status_t clock_fail(rcc_regs_t *rcc, stm32_status_t why)
{
    rcc->CFGR &= ~3u; /* SW = HSI */
    rcc->CR &= ~(RCC_CR_PLLON | RCC_CR_HSEON);
    return why;
}

stm32_status_t clock_init(rcc_regs_t *rcc, flash_regs_t *flash, const clock_plan_t *p, uint32_t timeout_polls)
{
    rcc->CR |= RCC_CR_HSEON;
    if (!wait_for(&rcc->CR, RCC_CR_HSERDY, RCC_CR_HSERDY, timeout_polls)) {
        return clock_fail(rcc, STM32_FAULT_HSE_TIMEOUT);
    }
    rcc->CR &= ~RCC_CR_PLLON;
    rcc->PLLCFGR = RCC_PLLCFGR_M(p->pll_m) | RCC_PLLCFGR_N(p->pll_n) | RCC_PLLCFGR_P(p->pll_p) | RCC_PLLCFGR_SRC_HSE |
                   RCC_PLLCFGR_Q(p->pll_q);
    rcc->CR |= RCC_CR_PLLON;
    if (!wait_for(&rcc->CR, RCC_CR_PLLRDY, RCC_CR_PLLRDY, timeout_polls)) {
        return clock_fail(rcc, STM32_FAULT_PLL_TIMEOUT);
    }
    /* wait states before the faster clock (RM0090 3.5.1), and read back */
    flash->ACR = FLASH_ACR_LATENCY(p->flash_ws) | FLASH_ACR_PRFTEN | FLASH_ACR_ICEN | FLASH_ACR_DCEN;
    if (!wait_for(&flash->ACR, FLASH_ACR_LATENCY_MASK, p->flash_ws, timeout_polls)) {
        return clock_fail(rcc, STM32_FAULT_CLOCK_SWITCH);
    }
    rcc->CFGR = (rcc->CFGR & ~0xFFF3u) | RCC_CFGR_PPRE1_DIV4 | RCC_CFGR_PPRE2_DIV2 | RCC_CFGR_SW_PLL;
    if (!wait_for(&rcc->CFGR, RCC_CFGR_SWS_MASK, RCC_CFGR_SWS_PLL, timeout_polls)) {
        return clock_fail(rcc, STM32_FAULT_CLOCK_SWITCH);
    }
    return STM32_OK;
}
