#include "adc_inj.h"

void adc_inj_init(adc_common_regs_t *common, adc_regs_t *adc, const adc_sequence_t *seq, bool trigger, bool irq)
{
    common->CCR = ADC_CCR_ADCPRE_DIV4;
    adc->CR2 = 0u;
    adc->CR1 = ADC_CR1_SCAN | (irq ? ADC_CR1_JEOCIE : 0u);
    /* sampling time of every channel used */
    uint32_t smpr1 = 0u, smpr2 = 0u;
    for (uint32_t k = 0; k < seq->n; ++k) {
        const uint32_t ch = seq->channel[k];
        if (ch >= 10u) {
            smpr1 |= ADC_SMP_15_CYCLES << (3u * (ch - 10u));
        } else {
            smpr2 |= ADC_SMP_15_CYCLES << (3u * ch);
        }
    }
    adc->SMPR1 = smpr1;
    adc->SMPR2 = smpr2;
    /* JSQR: a sequence of n uses JSQ(5-n)..JSQ4, results in JDR1..n (RM0090 13.13.12) */
    uint32_t jsqr = (uint32_t)(seq->n - 1u) << 20;
    for (uint32_t k = 0; k < seq->n; ++k) {
        const uint32_t slot = 4u - seq->n + k; /* 0-based JSQ index */
        jsqr |= (uint32_t)(seq->channel[k] & 0x1Fu) << (5u * slot);
    }
    adc->JSQR = jsqr;
    adc->SR = 0u;
    adc->CR2 = ADC_CR2_ADON | (trigger ? (ADC_CR2_JEXTSEL(ADC_JEXTSEL_TIM1_TRGO) | ADC_CR2_JEXTEN_RISING) : 0u);
}

void adc_inj_read(const adc_regs_t *adc, uint16_t *codes, uint32_t n)
{
    for (uint32_t k = 0; k < n && k < 4u; ++k) {
        codes[k] = (uint16_t)(adc->JDR[k] & 0xFFFFu);
    }
}

stm32_status_t adc_inj_convert(adc_regs_t *adc, uint16_t *codes, uint32_t n, uint32_t timeout_polls)
{
    /* JEOC is clear here: cleared after each read, and at init */
    adc->CR2 |= ADC_CR2_JSWSTART;
    for (uint32_t k = 0; k < timeout_polls; ++k) {
        if ((adc->SR & ADC_SR_JEOC) != 0u) {
            adc_inj_read(adc, codes, n);
            adc->SR &= ~ADC_SR_JEOC;
            return STM32_OK;
        }
    }
    return STM32_FAULT_ADC_TIMEOUT;
}

stm32_status_t adc_inj_zero(adc_regs_t *adc, uint32_t n, uint32_t n_samples, uint32_t nominal, uint32_t tolerance,
                            uint32_t timeout_polls, uint32_t *zero)
{
    uint32_t sum[4] = {0u, 0u, 0u, 0u};
    if (n == 0u || n > 4u || n_samples == 0u) {
        return STM32_FAULT_ADC_OFFSET;
    }
    for (uint32_t s = 0; s < n_samples; ++s) {
        uint16_t c[4];
        const stm32_status_t st = adc_inj_convert(adc, c, n, timeout_polls);
        if (st != STM32_OK) {
            return st;
        }
        for (uint32_t k = 0; k < n; ++k) {
            sum[k] += c[k];
        }
    }
    stm32_status_t st = STM32_OK;
    for (uint32_t k = 0; k < n; ++k) {
        zero[k] = (sum[k] + n_samples / 2u) / n_samples;
        const uint32_t dev = (zero[k] > nominal) ? zero[k] - nominal : nominal - zero[k];
        if (dev > tolerance) {
            st = STM32_FAULT_ADC_OFFSET;
        }
    }
    return st;
}
