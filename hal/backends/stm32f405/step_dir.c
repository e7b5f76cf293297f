#include "step_dir.h"

stm32_status_t step_dir_check(const step_dir_config_t *c)
{
    return (c->filter <= 15u && c->dir_line <= 15u && c->dir_port <= 4u) ? STM32_OK : STM32_FAULT_STEP_DIR_CONFIG;
}

static void set_direction(tim_regs_t *t, const step_dir_config_t *c, bool dir_level)
{
    /* DIR high counts up (CR1.DIR = 0), low down; inverted by dir_invert */
    const bool up = dir_level != c->dir_invert;
    if (up) {
        t->CR1 &= ~TIM_CR1_DIR;
    } else {
        t->CR1 |= TIM_CR1_DIR;
    }
}

stm32_status_t step_dir_init(step_dir_t *s, tim_regs_t *t, exti_regs_t *exti, syscfg_regs_t *syscfg,
                             const step_dir_config_t *cfg, bool dir_level, uint32_t timeout_polls)
{
    s->cfg = *cfg;
    s->direction_changes = 0u;
    s->status = step_dir_check(cfg);
    if (s->status != STM32_OK) {
        return s->status;
    }
    /* stopped, edge-aligned, channels off (CC1S writable only with CC1E = 0) */
    t->CR1 = 0u;
    t->SMCR = 0u;
    t->CCER = 0u;
    t->DIER = 0u;
    /* STEP on TI1 through its filter, rising edges (CC1P = 0, CC1NP = 0) */
    t->CCMR1 = TIM_CCMR_CC_IN_TI(0u) | TIM_CCMR_IC_F(0u, cfg->filter);
    t->CCMR2 = 0u;
    t->PSC = 0u;
    t->ARR = 0xFFFFFFFFu; /* TIM5's whole 32 bits */
    t->SMCR = TIM_SMCR_TS(TIM_SMCR_TS_TI1FP1) | TIM_SMCR_SMS_EXT_CLOCK1;
    /* the update loads PSC and ARR and clears the counter; with URS = 0 it
     * sets UIF (RM0090 18.4.5, 18.4.6) */
    t->SR = 0u;
    t->EGR = TIM_EGR_UG;
    bool answered = false;
    for (uint32_t k = 0; k < timeout_polls; ++k) {
        if ((t->SR & TIM_SR_UIF) != 0u) {
            answered = true;
            break;
        }
    }
    if (!answered) {
        s->status = STM32_FAULT_STEP_DIR_TIMEOUT;
        return s->status;
    }
    t->SR = 0u;
    t->CNT = 0u;
    /* DIR's line: port select (4 bits a line, RM0090 9.2.3), both edges, unmasked */
    const uint32_t line = cfg->dir_line, r = line / 4u, sh = 4u * (line % 4u);
    syscfg->EXTICR[r] = (syscfg->EXTICR[r] & ~(0xFu << sh)) | ((uint32_t)cfg->dir_port << sh);
    exti->RTSR |= 1u << line;
    exti->FTSR |= 1u << line;
    exti->PR = 1u << line; /* a stale edge cleared (write 1 to clear) */
    exti->IMR |= 1u << line;
    set_direction(t, cfg, dir_level);
    t->CR1 |= TIM_CR1_CEN;
    return STM32_OK;
}

void step_dir_direction(step_dir_t *s, tim_regs_t *t, exti_regs_t *exti, bool dir_level)
{
    exti->PR = 1u << s->cfg.dir_line;
    set_direction(t, &s->cfg, dir_level);
    s->direction_changes += 1u;
}

int32_t step_dir_count(const tim_regs_t *t) { return (int32_t)t->CNT; }
