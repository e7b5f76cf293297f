#define _GNU_SOURCE
#include "rt_loop.h"

#include <errno.h>
#include <sched.h>
#include <stdio.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>

static int64_t ns_of(const struct timespec *t) { return (int64_t)t->tv_sec * 1000000000 + t->tv_nsec; }

static struct timespec ts_of(int64_t ns)
{
    struct timespec t;
    t.tv_sec = (time_t)(ns / 1000000000);
    t.tv_nsec = (long)(ns % 1000000000);
    return t;
}

static int64_t now_ns(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return ns_of(&t);
}

void rt_loop_run(const rt_loop_config_t *cfg, rt_loop_step_fn step, void *ctx, uint64_t n_periods, rt_loop_stats_t *st)
{
    memset(st, 0, sizeof *st);
    struct sched_param sp;
    memset(&sp, 0, sizeof sp);
    sp.sched_priority = cfg->priority;
    st->realtime = sched_setscheduler(0, SCHED_FIFO, &sp) == 0;
    const int e_sched = errno;
    st->locked = mlockall(MCL_CURRENT | MCL_FUTURE) == 0;
    const int e_lock = errno;
    if (!st->realtime || !st->locked) {
        (void)snprintf(st->why, sizeof st->why, "%s%s%s%s (needs root, CAP_SYS_NICE/CAP_IPC_LOCK or rtprio/memlock limits)",
                       st->realtime ? "" : "no SCHED_FIFO: ", st->realtime ? "" : strerror(e_sched),
                       st->locked ? "" : "; memory not locked: ", st->locked ? "" : strerror(e_lock));
    }
    const int64_t period = (int64_t)cfg->period_ns;
    int64_t deadline = now_ns() + period;
    double step_sum = 0.0, jit_sum = 0.0;
    for (uint64_t k = 0; k < n_periods; ++k) {
        const struct timespec d = ts_of(deadline);
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &d, NULL) == EINTR) {
        }
        const int64_t woke = now_ns();
        const bool go = step(ctx);
        const int64_t done = now_ns();
        const double jitter_us = (double)(woke - deadline) / 1000.0;
        const double step_us = (double)(done - woke) / 1000.0;
        st->periods += 1u;
        step_sum += step_us;
        jit_sum += jitter_us;
        if (step_us > st->step_max_us) st->step_max_us = step_us;
        if (jitter_us > st->jitter_max_us) st->jitter_max_us = jitter_us;
        const int bin = jitter_us < 0.0 ? 0 : (jitter_us >= RT_LOOP_HIST_US ? RT_LOOP_HIST_US : (int)jitter_us);
        st->hist[bin] += 1u;
        deadline += period;
        if (done > deadline) {
            /* the next deadline already passed: an overrun; skip to the
             * first one still ahead */
            st->overruns += 1u;
            while (deadline <= done) deadline += period;
        }
        if (!go) break;
    }
    if (st->periods > 0u) {
        st->step_mean_us = step_sum / (double)st->periods;
        st->jitter_mean_us = jit_sum / (double)st->periods;
        const uint64_t want = st->periods - st->periods / 1000u; /* 99.9 % of the periods at or below */
        uint64_t seen = 0;
        for (int b = 0; b <= RT_LOOP_HIST_US; ++b) {
            seen += st->hist[b];
            if (seen >= want) {
                st->jitter_p999_us = (double)b + 1.0; /* the bin's upper edge */
                break;
            }
        }
    }
    if (st->locked) (void)munlockall();
}
