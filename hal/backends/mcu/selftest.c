/*
 * selftest.c - trivial bare-metal image: checks a few mc_* identities on the
 * target (either numeric type) and times a dummy "step" with SysTick.
 * Prints "SELFTEST PASS" and exits 0, or "SELFTEST FAIL ..." and exits 1.
 */
#include "math/mc_num.h"
#include "mcu_rt.h"

static volatile mc_t sink;

/* a dummy control step: a rotation, an atan2 and a square root */
__attribute__((noinline)) static mc_t dummy_step(mc_t x, mc_t y)
{
    mc_t s;
    mc_t c;
    mc_sincos(x, &s, &c);
    const mc_t u = mc_sub(mc_mul(c, y), mc_mul(s, x));
    return mc_add(mc_atan2(u, y), mc_sqrt(mc_abs(u)));
}

int main(void)
{
    uint32_t fails = 0;
    const mc_t tol = MC_C(2e-5);
    for (int32_t k = -400; k <= 400; ++k) {
        const mc_t x = mc_ratio_i(k, 128); /* -3.125 .. 3.125 rad */
        mc_t s;
        mc_t c;
        mc_sincos(x, &s, &c);
        /* atan2(sin x, cos x) == x, sin^2 + cos^2 == 1, sqrt(x^2) == |x| */
        if (mc_gt(mc_abs(mc_sub(mc_atan2(s, c), x)), tol)) {
            ++fails;
        }
        if (mc_gt(mc_abs(mc_sub(mc_add(mc_mul(s, s), mc_mul(c, c)), MC_ONE)), tol)) {
            ++fails;
        }
        if (mc_gt(mc_abs(mc_sub(mc_sqrt(mc_mul(x, x)), mc_abs(x))), tol)) {
            ++fails;
        }
        if (mc_gt(mc_abs(mc_sub(mc_wrap_pi(mc_add(x, MC_C(6.283185307179586 * 3.0))), x)), tol)) {
            ++fails;
        }
    }
    uint32_t tmin = 0xFFFFFFFFu;
    uint32_t tmax = 0u;
    for (int32_t k = 0; k < 100; ++k) {
        const mc_t x = mc_ratio_i(k, 16);
        const uint32_t t0 = mcu_systick_now();
        sink = dummy_step(x, MC_C(0.5));
        const uint32_t t1 = mcu_systick_now();
        const uint32_t dt = mcu_systick_elapsed(t0, t1);
        tmin = (dt < tmin) ? dt : tmin;
        tmax = (dt > tmax) ? dt : tmax;
    }
    mcu_puts("selftest:");
    mcu_put_kv("fixed", (uint32_t)MC_FIXED);
    mcu_put_kv("dummy_step_ticks_min", tmin);
    mcu_put_kv("dummy_step_ticks_max", tmax);
    mcu_put_kv("fails", fails);
    mcu_puts((fails == 0u) ? "\nSELFTEST PASS\n" : "\nSELFTEST FAIL\n");
    return (fails == 0u) ? 0 : 1;
}
