/*
 * speed_poly.h - paper 002's speed reference: w_d holds w_0 until t_0,
 * moves to w_1 by the C^2 quintic w_0 + (w_1 - w_0)(10 x^3 - 15 x^4 +
 * 6 x^5), x = (t - t_0)/(t_1 - t_0), and holds w_1 after t_1 (zero
 * acceleration and jerk at both ends; the reference set: 0 until
 * 0.2 s, to 100 rad/s at 0.4 s). Returns w_d and dw_d/dt (SOSMC and HTSMC
 * take both). Times are sample ticks, exact in both builds.
 * Fixed point (Q14.17, +-16384): dw_d/dt is formed as (w_1 - w_0) dpoly fs
 * before the division by the ramp's length, so it saturates once
 * |w_1 - w_0| 1.875 fs passes 16384 (0.87 rad/s at 10 kHz): in Q14.17 this
 * block serves no real ramp. Paper 002's drive is float only (its EKF,
 * docs/paper002.md), so no build uses it so; SpeedPoly's test is float
 * only for that reason.
 */
#ifndef TRAJECTORY_SPEED_POLY_H
#define TRAJECTORY_SPEED_POLY_H

#include <stdbool.h>
#include <stdint.h>

#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    uint32_t t0_tick, t1_tick;  /* t0 < t1 */
    mc_t w0_rad_s, w1_rad_s;
    int32_t fs_hz;
} speed_poly_t;

bool speed_poly_init(speed_poly_t *p, uint32_t t0_tick, uint32_t t1_tick, mc_t w0_rad_s, mc_t w1_rad_s, int32_t fs_hz);

void speed_poly_eval(const speed_poly_t *p, uint32_t tick, mc_t *w_rad_s, mc_t *dw_rad_s2);

#ifdef __cplusplus
}
#endif

#endif /* TRAJECTORY_SPEED_POLY_H */
