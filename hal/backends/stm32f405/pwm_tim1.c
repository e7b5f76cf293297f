#include "pwm_tim1.h"

bool pwm_dtg(uint32_t dead_ticks, uint32_t *dtg, uint32_t *actual)
{
    if (dead_ticks <= 127u) {
        *dtg = dead_ticks;
        *actual = dead_ticks;
        return true;
    }
    if (dead_ticks <= 2u * (64u + 63u)) {
        const uint32_t k = (dead_ticks + 1u) / 2u - 64u; /* round up */
        *dtg = 0x80u | k;
        *actual = 2u * (64u + k);
        return true;
    }
    if (dead_ticks <= 8u * (32u + 31u)) {
        const uint32_t k = (dead_ticks + 7u) / 8u - 32u;
        *dtg = 0xC0u | k;
        *actual = 8u * (32u + k);
        return true;
    }
    if (dead_ticks <= 16u * (32u + 31u)) {
        const uint32_t k = (dead_ticks + 15u) / 16u - 32u;
        *dtg = 0xE0u | k;
        *actual = 16u * (32u + k);
        return true;
    }
    return false;
}

bool pwm_plan(uint32_t f_tim_hz, uint32_t f_pwm_hz, uint32_t f_ctrl_hz, uint32_t dead_ns, pwm_plan_t *p)
{
    if (f_pwm_hz == 0u || f_ctrl_hz == 0u || (f_tim_hz % (2u * f_pwm_hz)) != 0u || (f_pwm_hz % f_ctrl_hz) != 0u) {
        return false;
    }
    const uint32_t arr = f_tim_hz / (2u * f_pwm_hz);
    const uint32_t periods = f_pwm_hz / f_ctrl_hz;
    if (arr < 2u || arr > 0xFFFFu || periods > 128u) {
        return false;
    }
    /* dead time in timer clocks, rounded up: never shorter than asked */
    const uint64_t ticks = ((uint64_t)dead_ns * f_tim_hz + 999999999u) / 1000000000u;
    uint32_t dtg, actual;
    if (ticks > 0xFFFFFFFFu || !pwm_dtg((uint32_t)ticks, &dtg, &actual)) {
        return false;
    }
    p->arr = arr;
    p->decimation = periods;
    p->dtg = dtg;
    p->dead_ns = (uint32_t)(((uint64_t)actual * 1000000000u) / f_tim_hz);
    p->f_pwm_hz = f_pwm_hz;
    return true;
}

void pwm_init(tim_regs_t *t, const pwm_plan_t *p, pwm_topology_t topo, bool break_enable, bool break_active_high)
{
    t->CR1 = 0;  /* stopped */
    t->BDTR = 0; /* MOE = 0 */
    t->PSC = 0;
    t->ARR = p->arr;
    t->RCR = 0u; /* an update (shadow registers loaded) at both ends */
    /* the channels driven: CH1-3, CH1-2, or CH2-3 (legs B and C) */
    const uint32_t ch_first = (topo == PWM_TWO_BRIDGES_TIM1_TIM8) ? 1u : 0u;
    const uint32_t ch_end = (topo == PWM_TWO_FULL_BRIDGES) ? 2u : 3u;
    uint32_t ccmr[2] = {0u, 0u};
    uint32_t ccer = 0u;
    for (uint32_t ch = ch_first; ch < ch_end; ++ch) {
        ccmr[ch / 2u] |= TIM_CCMR_OC_PWM1(ch) | TIM_CCMR_OC_PE(ch);
        ccer |= TIM_CCER_CCE(ch) | TIM_CCER_CCNE(ch);
        t->CCR[ch] = p->arr / 2u;
    }
    /* CH4 internal (no output enabled): OC4REF high from ARR - 1 up to the
     * top and back, the ADC's trigger through TRGO */
    ccmr[1] |= TIM_CCMR_OC_PWM2(3u) | TIM_CCMR_OC_PE(3u);
    t->CCR[3] = p->arr - 1u;
    t->CCMR1 = ccmr[0];
    t->CCMR2 = ccmr[1];
    t->CCER = ccer;
    t->CR2 = TIM_CR2_MMS_OC4REF;
    /* off-state selection: the outputs are driven to their inactive level
     * when MOE = 0 (OSSI) and while a channel is disabled (OSSR) */
    uint32_t bdtr = TIM_BDTR_OSSI | TIM_BDTR_OSSR | (p->dtg & TIM_BDTR_DTG_MASK);
    if (break_enable) {
        bdtr |= TIM_BDTR_BKE | (break_active_high ? TIM_BDTR_BKP : 0u);
    }
    t->BDTR = bdtr;
    t->CR1 = TIM_CR1_CMS_CENTER1 | TIM_CR1_ARPE;
    /* load ARR, CCRs now (UG), without an interrupt (URS) */
    t->CR1 |= TIM_CR1_URS;
    t->EGR = TIM_EGR_UG;
    t->SR = 0u;
    t->DIER = break_enable ? TIM_DIER_BIE : 0u;
}

void pwm_start(tim_regs_t *t)
{
    t->CNT = 0u;
    t->CR1 |= TIM_CR1_CEN;
}

void pwm_init_slave(tim_regs_t *slave, const pwm_plan_t *p)
{
    pwm_init(slave, p, PWM_TWO_BRIDGES_TIM1_TIM8, false, false);
    slave->CR2 = 0u; /* its own TRGO unused */
    slave->SMCR = TIM_SMCR_TS(TIM_SMCR_TS_ITR0) | TIM_SMCR_SMS_TRIGGER;
    slave->CNT = 0u;
}

stm32_status_t pwm_start_synchronised(tim_regs_t *master, tim_regs_t *slave, uint32_t timeout_polls)
{
    master->CR2 = (master->CR2 & ~TIM_CR2_MMS_MASK) | TIM_CR2_MMS_ENABLE;
    slave->CNT = 0u;
    master->CNT = 0u;
    master->CR1 |= TIM_CR1_CEN;
    for (uint32_t k = 0; k < timeout_polls; ++k) {
        if ((slave->CR1 & TIM_CR1_CEN) != 0u) {
            master->CR2 = (master->CR2 & ~TIM_CR2_MMS_MASK) | TIM_CR2_MMS_OC4REF;
            slave->SMCR &= ~(TIM_SMCR_SMS_MASK | TIM_SMCR_TS_MASK);
            return STM32_OK;
        }
    }
    master->CR1 &= ~TIM_CR1_CEN;
    master->CR2 = (master->CR2 & ~TIM_CR2_MMS_MASK) | TIM_CR2_MMS_OC4REF;
    return STM32_FAULT_PWM_SYNC;
}

void pwm_set_bridge_bc(tim_regs_t *t, const pwm_plan_t *p, float d_b)
{
    float d = (d_b > 1.0f) ? 1.0f : ((d_b < 0.0f || d_b != d_b) ? 0.0f : d_b);
    t->CCR[1] = (uint32_t)(d * (float)p->arr + 0.5f);
    t->CCR[2] = p->arr - t->CCR[1];
}

void pwm_set_duty(tim_regs_t *t, const pwm_plan_t *p, const float *duty, uint32_t n)
{
    for (uint32_t ch = 0; ch < n && ch < 4u; ++ch) {
        float d = duty[ch];
        d = (d > 1.0f) ? 1.0f : ((d < 0.0f || d != d) ? 0.0f : d);
        t->CCR[ch] = (uint32_t)(d * (float)p->arr + 0.5f);
    }
}

void pwm_outputs(tim_regs_t *t, bool on)
{
    if (on) {
        t->BDTR |= TIM_BDTR_MOE;
    } else {
        t->BDTR &= ~TIM_BDTR_MOE;
    }
}
