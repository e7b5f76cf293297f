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
 *
 * Two timers (the ODrive v3.6's two axes, boards/odrive36.c): TIM1 and
 * TIM8 each drive two legs, B and C (CH2/CH2N, CH3/CH3N), a winding
 * across them: a full bridge per timer, leg B at duty d and leg C at
 * 1 - d, v = (2 d - 1) v_bus (PWM_TWO_BRIDGES_TIM1_TIM8). Both count the
 * same 168 MHz APB2 timer clock with the same ARR; TIM8 is TIM1's slave
 * (RM0090 17.3.15, "Timer synchronization", and 17.3.20, "Starting 2
 * timers synchronously"): TIM1's TRGO is first its enable (MMS = 001),
 * TIM8 in trigger mode on ITR0 (= TIM1's TRGO for TIM8, RM0090 table 86:
 * SMCR SMS = 110, TS = 000), so setting TIM1's CEN starts TIM8 in the same
 * timer clock up to the trigger's resynchronisation (a timer clock or two,
 * 6-12 ns of the 50 us period); from then the two count in phase, their
 * triangles' tops together, and TIM1's TRGO becomes OC4REF, the one ADC
 * trigger for both windings' currents.
 */
#ifndef STM32_PWM_TIM1_H
#define STM32_PWM_TIM1_H

#include <stdbool.h>
#include <stdint.h>

#include "stm32_status.h"
#include "stm32f405_regs.h"

typedef enum {
    PWM_THREE_HALF_BRIDGES = 0, /* CH1-3 and CH1N-3N, dead time by TIM1 */
    PWM_TWO_FULL_BRIDGES = 1,   /* CH1/CH1N bridge A, CH2/CH2N bridge B, bipolar */
    PWM_TWO_BRIDGES_TIM1_TIM8 = 2 /* legs B, C of TIM1 (winding a) and of TIM8 (winding b), in phase */
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

/* PWM_TWO_BRIDGES_TIM1_TIM8's second timer: configured as pwm_init does
 * its legs B and C (stopped, MOE = 0, no break: TIM8's break input is not
 * used), and as TIM1's slave in trigger mode on ITR0 (SMCR SMS = 110,
 * TS = 000), its counter at 0. */
void pwm_init_slave(tim_regs_t *slave, const pwm_plan_t *p);

/* Starts master and slave in phase: master's TRGO = its enable (CR2 MMS =
 * 001), both counters at 0, master's CEN; waits at most timeout_polls
 * polls for the slave's CEN (set by the trigger, RM0090 17.4.1), then
 * master's TRGO = OC4REF (the ADC trigger) and the slave's slave mode off
 * (it counts on). STM32_FAULT_PWM_SYNC if the slave did not start (both
 * stopped again). */
stm32_status_t pwm_start_synchronised(tim_regs_t *master, tim_regs_t *slave, uint32_t timeout_polls);

/* A winding across legs B and C (CH2, CH3) of t: leg B at duty d_b, leg C
 * at 1 - d_b, d_b clamped to [0, 1]. */
void pwm_set_bridge_bc(tim_regs_t *t, const pwm_plan_t *p, float d_b);

/* Duty cycles in [0, 1] of the output channels (3, or 2), clamped. */
void pwm_set_duty(tim_regs_t *t, const pwm_plan_t *p, const float *duty, uint32_t n);

/* Main output enable: MOE = 1 (outputs follow the PWM) or 0 (idle state:
 * every switch off). */
void pwm_outputs(tim_regs_t *t, bool on);

#endif /* STM32_PWM_TIM1_H */
