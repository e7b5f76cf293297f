/*
 * pwm_tim1.h - TIM1 as the power stage's PWM (RM0090 ch. 17): centre-
 * aligned, one period = 2 ARR timer clocks, complementary outputs with a
 * dead time: three half-bridges (CH1-3 and CH1N-3N, a 3-phase PMSM), or two
 * full H-bridges driven bipolar, each by one complementary pair (CH1/CH1N
 * the two legs of bridge A, CH2/CH2N of bridge B: the 2-phase stepper of
 * paper 000; winding voltage (2 d - 1) v_bus); the break input as the
 * hardware over-current trip (outputs to their idle state by hardware, no
 * software in the path). CH4 is internal: PWM mode 2 with CCR4 = ARR - 1,
 * so OC4REF rises one timer clock before the top of every count, where
 * every low-side switch conducts, and TRGO = OC4REF starts the ADC's
 * injected conversions (adc_inj.h) there, once a PWM period (the control
 * step takes every n-th: n = f_pwm / f_ctrl). (An update-event trigger with
 * the repetition counter would come at the top or at the bottom depending
 * on how the counter was started, RM0090 17.3.3; OC4REF does not.)
 */
#ifndef STM32_PWM_TIM1_H
#define STM32_PWM_TIM1_H

#include <stdbool.h>
#include <stdint.h>

#include "stm32_status.h"
#include "stm32f405_regs.h"

typedef enum {
    PWM_THREE_HALF_BRIDGES = 0, /* CH1-3 and CH1N-3N, dead time by TIM1 */
    PWM_TWO_FULL_BRIDGES = 1    /* CH1/CH1N bridge A, CH2/CH2N bridge B, bipolar */
} pwm_topology_t;

typedef struct {
    uint32_t arr;            /* f_tim / (2 f_pwm) */
    uint32_t decimation;     /* f_pwm / f_ctrl: conversions per control step */
    uint32_t dtg;            /* BDTR.DTG: the shortest dead time not below the asked one */
    uint32_t dead_ns;        /* the dead time DTG gives */
    uint32_t f_pwm_hz;
} pwm_plan_t;

/* False if f_pwm does not divide f_tim into a whole ARR (16 bits),
 * f_ctrl does not divide f_pwm into a whole number of periods (at most
 * 128), or the dead time is beyond DTG's largest (1008 timer clocks). */
bool pwm_plan(uint32_t f_tim_hz, uint32_t f_pwm_hz, uint32_t f_ctrl_hz, uint32_t dead_ns, pwm_plan_t *p);

/* BDTR.DTG for at least dead_ticks timer clocks (RM0090 17.4.18: DTG[7:5]
 * = 0xx: DTG; 10x: (64 + DTG[5:0]) 2; 110: (32 + DTG[4:0]) 8; 111: (32 +
 * DTG[4:0]) 16); *actual the clocks it gives. False beyond 1008. */
bool pwm_dtg(uint32_t dead_ticks, uint32_t *dtg, uint32_t *actual);

/* Configures TIM1 stopped, outputs disabled (MOE = 0): mode, channels,
 * dead time, break (enabled: BKE, polarity), CH4 and TRGO, duties 50 %. */
void pwm_init(tim_regs_t *t, const pwm_plan_t *p, pwm_topology_t topo, bool break_enable, bool break_active_high);

/* Starts the counter (from 0, counting up: the first update is at the top). */
void pwm_start(tim_regs_t *t);

/* Duty cycles in [0, 1] of the output channels (3, or 2), clamped. */
void pwm_set_duty(tim_regs_t *t, const pwm_plan_t *p, const float *duty, uint32_t n);

/* Main output enable: MOE = 1 (outputs follow the PWM) or 0 (idle state:
 * every switch off). */
void pwm_outputs(tim_regs_t *t, bool on);

#endif /* STM32_PWM_TIM1_H */
