#include "trajectory/speed_poly.h"

bool speed_poly_init(speed_poly_t *p, uint32_t t0_tick, uint32_t t1_tick, mc_t w0_rad_s, mc_t w1_rad_s, int32_t fs_hz)
{
    p->t0_tick = t0_tick;
    p->t1_tick = t1_tick;
    p->w0_rad_s = w0_rad_s;
    p->w1_rad_s = w1_rad_s;
    p->fs_hz = fs_hz;
    return t1_tick > t0_tick && fs_hz > 0 && (t1_tick - t0_tick) < (uint32_t)INT32_MAX;
}

void speed_poly_eval(const speed_poly_t *p, uint32_t tick, mc_t *w_rad_s, mc_t *dw_rad_s2)
{
    if (tick <= p->t0_tick || tick >= p->t1_tick) {
        *w_rad_s = (tick <= p->t0_tick) ? p->w0_rad_s : p->w1_rad_s;
        *dw_rad_s2 = MC_ZERO;
        return;
    }
    const int32_t n = (int32_t)(p->t1_tick - p->t0_tick);
    const mc_t x = mc_ratio_i((int32_t)(tick - p->t0_tick), n);
    const mc_t dw = mc_sub(p->w1_rad_s, p->w0_rad_s);
    const mc_t x2 = mc_mul(x, x);
    /* 10 x^3 - 15 x^4 + 6 x^5 = x^3 (10 - x (15 - 6 x)); its derivative 30 x^2 (1 - x)^2 */
    const mc_t poly = mc_mul(mc_mul(x2, x), mc_sub(MC_C(10.0), mc_mul(x, mc_sub(MC_C(15.0), mc_mul_i(x, 6)))));
    const mc_t one_x = mc_sub(MC_ONE, x);
    const mc_t dpoly = mc_mul_i(mc_mul(x2, mc_mul(one_x, one_x)), 30);
    *w_rad_s = mc_mac(p->w0_rad_s, dw, poly);
    /* dw/dt = dw dpoly / T, T = n / fs */
    *dw_rad_s2 = mc_div(mc_mul_i(mc_mul(dw, dpoly), p->fs_hz), mc_from_i(n));
}
