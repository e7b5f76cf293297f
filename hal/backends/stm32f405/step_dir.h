/*
 * step_dir.h - a step/dir input (the convention of stepper drivers: a
 * pulse on STEP moves the target one step, the level of DIR says which
 * way) counted by a timer: TIM5 (32 bits) in external clock mode 1 (RM0090
 * 18.3.3: SMCR SMS = 111, TS = 101, TI1FP1), so each rising edge of STEP on
 * CH1 (through the input filter, CCMR1 CC1S = 01, IC1F) clocks the counter
 * by one in the direction of CR1's DIR bit, which DIR's edges set: the
 * DIR pin's EXTI line interrupts on both edges (RM0090 12.3: RTSR, FTSR)
 * and step_dir_direction() copies its level into CR1.DIR (writable in
 * edge-aligned mode, 18.4.1). Every step is counted by the hardware, at
 * any step rate the filter passes and whatever the CPU is doing: an
 * interrupt comes only at a change of direction (one a step would cost
 * the control interrupt its time at high step rates; the vendor firmware
 * of the ODrive takes an interrupt per step). The one window: a step
 * within the DIR interrupt's latency after a change of direction (about
 * 0.1-0.2 us at 168 MHz, the interrupt at the highest priority) counts
 * the old way; step/dir senders keep DIR set up well before the next STEP
 * edge (e.g. 650 ns in TI's DRV8825 datasheet, tSU(DIR)).
 * CNT read as a signed 32-bit count is the position in steps since start
 * (the signed count wraps after 2^31 steps: 6 hours of a 100 kHz step
 * train in one direction).
 */
#ifndef STM32_STEP_DIR_H
#define STM32_STEP_DIR_H

#include <stdbool.h>
#include <stdint.h>

#include "stm32_status.h"
#include "stm32f405_regs.h"

typedef struct {
    uint8_t filter;       /* IC1F, 0..15: the STEP input's digital filter (RM0090 18.4.7) */
    bool dir_invert;      /* true: DIR high counts down (else DIR high counts up) */
    uint8_t dir_line;     /* the DIR pin's EXTI line (its pin number), 0..15 */
    uint8_t dir_port;     /* its port, 0 = A (SYSCFG_EXTICR) */
} step_dir_config_t;

typedef struct {
    step_dir_config_t cfg;
    stm32_status_t status;
    uint32_t direction_changes;   /* DIR edges seen */
} step_dir_t;

/* STM32_OK or STM32_FAULT_STEP_DIR_CONFIG (filter > 15, line > 15, port >
 * 4: what the registers cannot hold). */
stm32_status_t step_dir_check(const step_dir_config_t *c);

/* Configures t as the step counter (stopped, then its update to load PSC
 * and ARR, waiting at most timeout_polls polls for UIF: else
 * STM32_FAULT_STEP_DIR_TIMEOUT), the DIR line's EXTI on both edges
 * (syscfg's EXTICR selects the port), the count at 0 and its direction
 * from dir_level, the DIR pin's level now; then starts the counter. */
stm32_status_t step_dir_init(step_dir_t *s, tim_regs_t *t, exti_regs_t *exti, syscfg_regs_t *syscfg,
                             const step_dir_config_t *cfg, bool dir_level, uint32_t timeout_polls);

/* The DIR line's interrupt: clears its pending bit, sets the counting
 * direction from the DIR pin's level dir_level. */
void step_dir_direction(step_dir_t *s, tim_regs_t *t, exti_regs_t *exti, bool dir_level);

/* The steps counted since start, signed. */
int32_t step_dir_count(const tim_regs_t *t);

#endif /* STM32_STEP_DIR_H */
