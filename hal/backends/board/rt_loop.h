/*
 * rt_loop.h - a periodic real-time loop for Linux (the board backend's
 * clock at 10 kHz): SCHED_FIFO, memory locked, absolute deadlines with
 * clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME), so that a late wake-up
 * does not shift the following ones. Counts overruns (a step that ends
 * after the next deadline: the loop then skips to the next deadline still
 * ahead), records the step time and the wake-up jitter (the lateness of
 * each wake-up against its deadline: a histogram in 1 us bins, its
 * maximum). Without permission for real-time scheduling or locking it
 * says so in the stats and runs anyway with the default scheduler.
 */
#ifndef BOARD_RT_LOOP_H
#define BOARD_RT_LOOP_H

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define RT_LOOP_HIST_US 2000 /* jitter histogram: 1 us bins to 2 ms, then one overflow bin */

typedef struct {
    uint32_t period_ns;      /* 100000 at 10 kHz */
    int priority;            /* SCHED_FIFO priority, 1-99 (80: above most IRQ threads' default 50) */
} rt_loop_config_t;

typedef struct {
    uint64_t periods, overruns;
    double step_mean_us, step_max_us;
    double jitter_mean_us, jitter_max_us, jitter_p999_us;
    uint32_t hist[RT_LOOP_HIST_US + 1];
    bool realtime;           /* SCHED_FIFO granted */
    bool locked;             /* mlockall granted */
    char why[160];           /* what was not granted, and why */
} rt_loop_stats_t;

/* One period's work; false stops the loop. */
typedef bool (*rt_loop_step_fn)(void *ctx);

/* Runs step every period for n_periods (or until it returns false). */
void rt_loop_run(const rt_loop_config_t *cfg, rt_loop_step_fn step, void *ctx, uint64_t n_periods, rt_loop_stats_t *st);

#ifdef __cplusplus
}
#endif

#endif /* BOARD_RT_LOOP_H */
