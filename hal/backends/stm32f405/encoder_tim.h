/*
 * encoder_tim.h - an incremental (quadrature) encoder on a general-purpose
 * timer in encoder interface mode (RM0090 18.3.12): A on TI1, B on TI2,
 * both edges of both counted (SMS = 011, "encoder mode 3": four counts a
 * line, TIMx_SMCR, RM0090 18.4.3), each input mapped on its own pin
 * (CC1S = CC2S = 01, TIMx_CCMR1, RM0090 18.4.7) through the digital filter
 * ICxF, the count direction swapped by CC1P (TIMx_CCER, RM0090 18.4.9).
 * The counter runs over the whole 16 bits (ARR = 0xFFFF, RM0090 18.4.12;
 * TIM3 and TIM4 are 16-bit), and each read turns the signed 16-bit change
 * of CNT (RM0090 18.4.10) since the last read into an unwrapped count: a
 * whole number of turns and the count into the turn, [0, counts_per_turn),
 * so that no count of the timer's wrap is lost and a turn need not be a
 * power of two. The optional index (the encoder's once-a-turn pulse) is
 * captured in hardware on CH3 (IC3 on TI3, CC3S = 01, TIMx_CCMR2, RM0090
 * 18.4.8; rising edge; CCR3 holds the count at the pulse, CC3IF in TIMx_SR
 * says one came, RM0090 18.4.5 and 18.3.5, and reading CCR3 clears it):
 * no interrupt, no latency between the edge and the count it fixes.
 *
 * The angle is the rotor's mechanical angle in [-pi, pi), as paper 002's
 * drive reads hal_sample_t.angle_rad and as the simulator's encoder gives
 * it (sim/model/encoder.h: the count the rotor has passed, floor, times
 * 2 pi / counts_per_turn, wrapped into [-pi, pi)). Its zero: the count at
 * start-up is taken as the angle start_count (the rotor at a known angle
 * when the drive starts, e.g. aligned before; paper 002's sensorless
 * variant assumes the same of its flux observer); with the index, the
 * first index moves the zero so that the index sits at index_count (the
 * correction kept), and every later one must come within index_tolerance
 * counts of it.
 *
 * Errors, latched (the angle is then withheld: a drive that reads it gets
 * samples without has_angle, its BAD_INPUT): a configuration the timer
 * cannot run, a timer that does not answer its update (no clock: the
 * start-up's bounded wait), a change between two reads beyond
 * max_step_counts (a speed no motor on the board reaches: noise on A or B,
 * or counts the unwrap could not tell apart), an index away from where
 * the count puts it (counts lost or gained).
 */
#ifndef STM32_ENCODER_TIM_H
#define STM32_ENCODER_TIM_H

#include <stdbool.h>
#include <stdint.h>

#include "stm32_status.h"
#include "stm32f405_regs.h"

/* The unwrap's limit: a change of CNT between two reads is told from the
 * 16-bit difference only while it stays within +-32767 counts. */
#define ENCODER_STEP_MAX 32767u

typedef struct {
    uint32_t counts_per_turn;  /* quadrature counts a mechanical turn (4 x lines), 4 .. 2^24 */
    uint32_t filter;           /* ICxF of A, B and the index, 0..15 (RM0090 18.4.7) */
    bool invert;               /* count the other way (CC1P = 1) */
    uint32_t start_count;      /* the angle at start-up, in counts, < counts_per_turn */
    uint32_t max_step_counts;  /* the largest change between two reads, 1..ENCODER_STEP_MAX */
    bool index;                /* the index captured on CH3 */
    uint32_t index_count;      /* where the index is, counts from the angle's zero, < counts_per_turn */
    uint32_t index_tolerance;  /* counts a later index may be off, < counts_per_turn / 2 */
} encoder_config_t;

typedef struct {
    encoder_config_t cfg;
    stm32_status_t status;     /* STM32_OK, or the latched error */
    uint16_t last_cnt;         /* CNT at the last read */
    int32_t turns;             /* whole turns since the start (the unwrapped count's high part) */
    uint32_t pos;              /* counts into the turn, [0, counts_per_turn) */
    int32_t last_step;         /* the last read's change: its sign is the direction */
    bool referenced;           /* an index has fixed the zero */
    int32_t index_correction;  /* counts the first index moved the zero by */
    uint32_t index_seen;       /* indexes captured */
} encoder_t;

/* STM32_OK if cfg is a configuration the timer can run, else
 * STM32_FAULT_ENCODER_CONFIG. */
stm32_status_t encoder_check(const encoder_config_t *cfg);

/* Sets the timer up (stopped first): encoder mode 3, the inputs, ARR =
 * 0xFFFF, the index's capture; an update (UG) loads it and clears the
 * counter, and its flag (UIF, RM0090 18.4.5/18.4.6) must come within
 * timeout_polls polls (STM32_FAULT_ENCODER_TIMEOUT: the timer's clock does
 * not run); then the counter starts. e holds the state; e->status the
 * result. */
stm32_status_t encoder_init(encoder_t *e, tim_regs_t *t, const encoder_config_t *cfg, uint32_t timeout_polls);

/* One read (once a control period): the count's change since the last
 * read, the index if one was captured. True with *angle_rad the
 * mechanical angle in [-pi, pi); false once an error is latched
 * (e->status). */
bool encoder_read(encoder_t *e, tim_regs_t *t, float *angle_rad);

/* The unwrapped count: turns * counts_per_turn + pos. */
int64_t encoder_count(const encoder_t *e);

/* The angle of a count into the turn, [-pi, pi). */
float encoder_angle_of(uint32_t pos, uint32_t counts_per_turn);

#endif /* STM32_ENCODER_TIM_H */
