#include "iwdg.h"

bool iwdg_plan(uint32_t lsi_hz, uint32_t timeout_us, uint32_t *pr, uint32_t *rlr)
{
    for (uint32_t p = 0; p <= 6u; ++p) {
        const uint64_t div = 4ull << p;
        const uint64_t counts = ((uint64_t)timeout_us * lsi_hz) / (div * 1000000ull);
        if (counts >= 1u && counts <= 4096u) {
            *pr = p;
            *rlr = (uint32_t)counts - 1u;
            return true;
        }
    }
    return false;
}

stm32_status_t iwdg_start(iwdg_regs_t *w, uint32_t pr, uint32_t rlr, uint32_t timeout_polls)
{
    w->KR = IWDG_KEY_ENABLE;
    w->KR = IWDG_KEY_UNLOCK;
    w->PR = pr;
    w->RLR = rlr;
    for (uint32_t k = 0; k < timeout_polls; ++k) {
        if ((w->SR & (IWDG_SR_PVU | IWDG_SR_RVU)) == 0u) {
            w->KR = IWDG_KEY_REFRESH;
            return STM32_OK;
        }
    }
    return STM32_FAULT_IWDG_TIMEOUT;
}
