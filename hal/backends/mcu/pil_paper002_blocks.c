/*
 * pil_paper002_blocks.c - the cost of paper 002's control step on the
 * emulated core, before its drive exists: per sample the EKF's correction
 * and prediction (estimators/ekf_ipmsm.h), SOSMC (control/sosmc.h), MTPA
 * with the torque inversion (control/mtpa.h) and the inversion-based
 * current control (control/ibcc.h), in that order, on the reference
 * motor, 2000 samples of a speed reference rising to 100 rad/s with the
 * measurements made up from the EKF's own estimate plus a deterministic
 * dither (the cost does not depend on the values: no data-dependent loops
 * but tanh's halvings and the MTPA limit, both exercised). Timed as the
 * PIL tool times (SysTick, -icount; tools/bench/pil.py --drive
 * paper002-blocks converts to instructions): "B <ticks>..." lines, then
 * "P002 calib=.. n=..".
 */
#include "control/ibcc.h"
#include "control/mtpa.h"
#include "control/sosmc.h"
#include "estimators/ekf_ipmsm.h"
#include "mcu_rt.h"

#define N_SAMPLES 2000

static ekf_ipmsm_t ekf;
static sosmc_t smc;
static ibcc_t cc;

int main(void)
{
    ekf_ipmsm_config_t ec = {0};
    ec.R_ohm = MC_C(0.3);
    ec.Ld_H = MC_C(3e-3);
    ec.Lq_H = MC_C(9e-3);
    ec.psi_Wb = MC_C(0.04);
    ec.p = 4;
    ec.J_kgm2 = MC_C(1e-3);
    ec.d_Nms = MC_C(5e-4);
    ec.ts_s = MC_C(1e-4);
    const mc_t q[5] = {MC_C(1e-4), MC_C(1e-4), MC_C(1e-12), MC_C(1e-3), MC_C(1e-5)};
    for (int i = 0; i < 5; ++i) {
        ec.q[i] = q[i];
        ec.p0[i] = MC_C(1e-3);
    }
    ec.r[0] = ec.r[1] = MC_C(2.5e-5);
    ec.r[2] = MC_C(1e-8);
    const sosmc_config_t sc = {MC_C(1e-3), MC_C(5e-4), MC_C(200.0), MC_C(1e4), MC_C(1e4), MC_C(50.0), MC_C(5.0),
                               true, MC_C(1e-4)};
    const mtpa_config_t mc = {MC_C(3e-3), MC_C(9e-3), MC_C(0.04), 4, MC_C(20.0)};
    /* lambda and the references' filter as design/paper002_design.c sets them:
     * lambda Ts = 0.2, ref_alpha = 1 - exp(-0.3 lambda Ts) = 0.058 */
    const ibcc_config_t ic = {MC_C(0.3), MC_C(3e-3), MC_C(9e-3), MC_C(0.04), 4, MC_C(2000.0), 10000, MC_C(0.058)};
    if (!ekf_ipmsm_init(&ekf, &ec) || !sosmc_init(&smc, &sc) || !ibcc_init(&cc, &ic)) {
        mcu_puts("P002 FAIL init\n");
        mcu_exit(1);
    }
    uint32_t calib = 0xFFFFFFFFu;
    for (int k = 0; k < 8; ++k) {
        __asm__ volatile("" ::: "memory");
        const uint32_t t0 = mcu_systick_now();
        __asm__ volatile("" ::: "memory");
        const uint32_t t1 = mcu_systick_now();
        const uint32_t d = mcu_systick_elapsed(t0, t1);
        calib = d < calib ? d : calib;
    }
    uint32_t col = 0;
    mc_t ud = MC_ZERO, uq = MC_ZERO;
    for (int32_t k = 0; k < N_SAMPLES; ++k) {
        /* made-up measurements: the estimate plus a dither of a few mA / urad */
        const mc_t dith = mc_mul(MC_C(1e-3), mc_from_i((k * 7919) % 11 - 5));
        const mc_t y_id = mc_add(ekf.x[EKF_ID], dith);
        const mc_t y_iq = mc_sub(ekf.x[EKF_IQ], dith);
        const mc_t y_th = mc_add(ekf.x[EKF_THETA], mc_mul(dith, MC_C(0.01)));
        const mc_t w_d = mc_mul_i(MC_C(0.05), k); /* 0 -> 100 rad/s over the run */
        __asm__ volatile("" ::: "memory");
        const uint32_t t0 = mcu_systick_now();
        (void)ekf_ipmsm_correct(&ekf, y_id, y_iq, y_th);
        const mc_t M = sosmc_step(&smc, &sc, w_d, MC_C(500.0), ekf.x[EKF_OMEGA], ekf_ipmsm_accel(&ekf), ekf.x[EKF_M0]);
        mtpa_out_t ref;
        mtpa_step(&mc, M, &ref);
        ibcc_step(&cc, &ic, ref.i_d_A, ref.i_q_A, ekf.x[EKF_ID], ekf.x[EKF_IQ], ekf.x[EKF_OMEGA], MC_C(24.0), &ud, &uq);
        ekf_ipmsm_predict(&ekf, ud, uq);
        const uint32_t t1 = mcu_systick_now();
        __asm__ volatile("" ::: "memory");
        if (col == 0u) mcu_puts("B");
        mcu_puts(" ");
        mcu_put_u32(mcu_systick_elapsed(t0, t1));
        if (++col == 32u || k + 1 == N_SAMPLES) {
            mcu_puts("\n");
            col = 0u;
        }
    }
    mcu_puts("P002");
    mcu_put_kv("calib", calib);
    mcu_put_kv("n", N_SAMPLES);
    mcu_puts("\nP002 PASS\n");
    mcu_exit(0);
}
