/*
 * adc_inj.h - the phase currents and the bus voltage by injected
 * conversions (RM0090 13.3.6), started by TIM1's TRGO (pwm_tim1.h) at the
 * top of the PWM count, so that every sample sees the low-side shunts
 * conducting. ADC1, ADC2 and ADC3 run one injected sequence each (up to
 * four channels, results in JDR1..n), all on the same trigger: the
 * currents of different phases are converted at the same instant. ADC1's
 * end of sequence (JEOC) interrupts; its sequence is the longest, so the
 * others are done by then. Also the start-up measurement of the current
 * sensors' zero with the bridges off (software-started, bounded waits).
 */
#ifndef STM32_ADC_INJ_H
#define STM32_ADC_INJ_H

#include <stdbool.h>
#include <stdint.h>

#include "stm32_status.h"
#include "stm32f405_regs.h"

/* ADCCLK = APB2 / 4 = 21 MHz at 168 MHz (at most 36 MHz); 15 cycles of
 * sampling (SMP = 1) and 12 of conversion: 1.29 us a conversion, so a
 * sequence of two ends 2.6 us after the trigger. 15 cycles charge the
 * 4 pF sample capacitor to 12 bits from the amplifiers' low output
 * impedance (RM0090 13.4). */
#define ADC_SMP_15_CYCLES 1u

typedef struct {
    uint8_t n;          /* conversions, 1..4 */
    uint8_t channel[4]; /* ADC_INx channel numbers, 0..18 */
} adc_sequence_t;

/* Configures adc for seq, triggered by TIM1 TRGO (trigger) or by software
 * only; the JEOC interrupt if irq. Leaves it on (ADON). */
void adc_inj_init(adc_common_regs_t *common, adc_regs_t *adc, const adc_sequence_t *seq, bool trigger, bool irq);

/* The sequence's results (12-bit codes). */
void adc_inj_read(const adc_regs_t *adc, uint16_t *codes, uint32_t n);

/* One software-started sequence: JSWSTART, wait JEOC at most
 * timeout_polls times, read, clear. */
stm32_status_t adc_inj_convert(adc_regs_t *adc, uint16_t *codes, uint32_t n, uint32_t timeout_polls);

/* The zero of each of the n current channels (index in the sequence):
 * the mean of n_samples conversions with the bridges off, in codes,
 * checked against nominal +- tolerance; STM32_FAULT_ADC_OFFSET if one is
 * outside (a broken amplifier, a shorted shunt, a current flowing). */
stm32_status_t adc_inj_zero(adc_regs_t *adc, uint32_t n, uint32_t n_samples, uint32_t nominal, uint32_t tolerance,
                            uint32_t timeout_polls, uint32_t *zero);

#endif /* STM32_ADC_INJ_H */
