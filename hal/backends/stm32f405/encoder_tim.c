#include "encoder_tim.h"

/* 2 pi as the float the angle is computed in */
#define ENCODER_TWO_PI 6.28318530717958647692f

static uint32_t mod_u(int64_t v, uint32_t m)
{
    const int64_t r = v % (int64_t)m;
    return (uint32_t)(r < 0 ? r + (int64_t)m : r);
}

/* v modulo m as the nearest signed value, (-m/2, m/2] */
static int32_t mod_signed(int64_t v, uint32_t m)
{
    const uint32_t r = mod_u(v, m);
    return (2u * r > m) ? (int32_t)r - (int32_t)m : (int32_t)r;
}

stm32_status_t encoder_check(const encoder_config_t *c)
{
    const bool ok = c->counts_per_turn >= 4u && c->counts_per_turn <= (1u << 24) && c->filter <= 15u &&
                    c->start_count < c->counts_per_turn && c->max_step_counts >= 1u &&
                    c->max_step_counts <= ENCODER_STEP_MAX &&
                    (!c->index || (c->index_count < c->counts_per_turn && 2u * c->index_tolerance < c->counts_per_turn));
    return ok ? STM32_OK : STM32_FAULT_ENCODER_CONFIG;
}

stm32_status_t encoder_init(encoder_t *e, tim_regs_t *t, const encoder_config_t *cfg, uint32_t timeout_polls)
{
    e->cfg = *cfg;
    e->turns = 0;
    e->pos = 0u;
    e->last_step = 0;
    e->referenced = false;
    e->index_correction = 0;
    e->index_seen = 0u;
    e->last_cnt = 0u;
    e->status = encoder_check(cfg);
    if (e->status != STM32_OK) {
        return e->status;
    }
    e->pos = cfg->start_count;
    /* stopped, channels off: CCxS is writable only with CCxE = 0 (RM0090 18.4.7) */
    t->CR1 = 0u;
    t->SMCR = 0u;
    t->CCER = 0u;
    t->DIER = 0u;
    /* A on TI1, B on TI2, each through its filter; the index on TI3 */
    t->CCMR1 = TIM_CCMR_CC_IN_TI(0u) | TIM_CCMR_IC_F(0u, cfg->filter) | TIM_CCMR_CC_IN_TI(1u) |
               TIM_CCMR_IC_F(1u, cfg->filter);
    t->CCMR2 = cfg->index ? (TIM_CCMR_CC_IN_TI(2u) | TIM_CCMR_IC_F(2u, cfg->filter)) : 0u;
    /* CC1P inverts TI1 and with it the count's direction; the index's
     * capture on its rising edge (CC3P = 0), enabled (CC3E) */
    t->CCER = (cfg->invert ? TIM_CCER_CCP(0u) : 0u) | (cfg->index ? TIM_CCER_CCE(2u) : 0u);
    t->PSC = 0u;
    t->ARR = 0xFFFFu;
    t->SMCR = TIM_SMCR_SMS_ENCODER3;
    /* the update loads PSC and ARR and clears the counter; with URS = 0 it
     * sets UIF (RM0090 18.4.5, 18.4.6): a timer whose clock runs answers */
    t->SR = 0u;
    t->EGR = TIM_EGR_UG;
    bool updated = false;
    for (uint32_t k = 0; k < timeout_polls && !updated; ++k) {
        updated = (t->SR & TIM_SR_UIF) != 0u;
    }
    if (!updated) {
        e->status = STM32_FAULT_ENCODER_TIMEOUT;
        return e->status;
    }
    t->SR = 0u;
    e->last_cnt = (uint16_t)(t->CNT & 0xFFFFu);
    t->CR1 = TIM_CR1_CEN;
    return STM32_OK;
}

int64_t encoder_count(const encoder_t *e) { return (int64_t)e->turns * (int64_t)e->cfg.counts_per_turn + e->pos; }

float encoder_angle_of(uint32_t pos, uint32_t counts_per_turn)
{
    /* the count into [-n/2, n/2) (exact in integers), then one product */
    const int32_t s = (2u * pos >= counts_per_turn) ? (int32_t)pos - (int32_t)counts_per_turn : (int32_t)pos;
    return (float)s * (ENCODER_TWO_PI / (float)counts_per_turn);
}

/* the unwrapped count moved by d: turns and the count into the turn */
static void encoder_move(encoder_t *e, int64_t d)
{
    const uint32_t n = e->cfg.counts_per_turn;
    const int64_t u = (int64_t)e->pos + d;
    const uint32_t pos = mod_u(u, n);
    e->turns += (int32_t)((u - (int64_t)pos) / (int64_t)n);
    e->pos = pos;
}

bool encoder_read(encoder_t *e, tim_regs_t *t, float *angle_rad)
{
    if (e->status != STM32_OK) {
        return false;
    }
    const uint16_t cnt = (uint16_t)(t->CNT & 0xFFFFu);
    const int32_t step = (int16_t)(uint16_t)(cnt - e->last_cnt); /* the 16-bit counter's wrap undone */
    if ((uint32_t)(step < 0 ? -step : step) > e->cfg.max_step_counts) {
        e->status = STM32_FAULT_ENCODER_STEP;
        return false;
    }
    e->last_cnt = cnt;
    e->last_step = step;
    encoder_move(e, step);
    if (e->cfg.index && (t->SR & TIM_SR_CCIF(2u)) != 0u) {
        /* the count at the index (read before the flags are cleared: a
         * capture between the two is taken at the next read) */
        const uint16_t c = (uint16_t)(t->CCR[2] & 0xFFFFu);
        t->SR &= ~(TIM_SR_CCIF(2u) | TIM_SR_CCOF(2u));
        e->index_seen += 1u;
        /* where the unwrapped count stood at the pulse: now, less what the
         * counter moved since (within this read's step) */
        const int64_t at = (int64_t)e->pos - (int16_t)(uint16_t)(cnt - c);
        const int32_t off = mod_signed(at - (int64_t)e->cfg.index_count, e->cfg.counts_per_turn);
        if (!e->referenced) {
            encoder_move(e, -(int64_t)off);
            e->index_correction = -off;
            e->referenced = true;
        } else if ((uint32_t)(off < 0 ? -off : off) > e->cfg.index_tolerance) {
            e->status = STM32_FAULT_ENCODER_INDEX;
            return false;
        }
    }
    *angle_rad = encoder_angle_of(e->pos, e->cfg.counts_per_turn);
    return true;
}
