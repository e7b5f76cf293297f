/*
 * pil_main.c - processor-in-the-loop image: the drive's control step on the
 * emulated core, over a recorded input sequence (tools/bench/pil_gen.cpp).
 *
 * For every period: the recorded phase currents go, as a hal_sample_t,
 * into the drive's control callback (the hal_control_fn a backend calls),
 * the call is timed with SysTick, and the two voltages are compared bit for bit
 * with those the host build of the same numeric type returned. Output
 * (semihosting), parsed by tools/bench/pil.py:
 *   PIL source=<...> n=<N> cfg_bytes=<..> state_bytes=<sizeof(paper000_drive_t)>
 *   T <ticks> <ticks> ...         per-period SysTick ticks, 32 per line
 *   PIL calib=<ticks of an empty timed region> mismatches=<m> first=<i>
 *       stack_used=<bytes below the stack top touched by the whole run>
 *       stack_main=<depth of main's frame at the paper000_drive_step call, about>
 *   PIL PASS | PIL FAIL
 */
#include <string.h>

#include "comm/can_node.h"
#include "drives/registry.h"
#include "drives/paper000/paper000_drive.h"
#include "hal/hal.h"
#include "mcu_rt.h"
#include "pil_common.h"
#include "pil_vectors.h"

static paper000_drive_t drive;
static drive_t handle = {&paper000_drive_ops, &drive}; /* the CAN node's view of it */
static can_node_t can_node;

/* The control callback of hal.h (hal_control_fn), as an MCU backend calls
 * it from its end-of-conversion interrupt: the drive's step, and the safe
 * state on a fault (here: nothing to switch off). */
static void drive_callback(void *ctx, const hal_sample_t *in, hal_command_t *out)
{
    (void)paper000_drive_step((paper000_drive_t *)ctx, in, out);
}
static hal_control_fn const control = drive_callback;


int main(void)
{
    paint_stack();
    paper000_config_t cfg;
    memcpy(&cfg, pil_cfg_words, sizeof cfg);
    mcu_puts("PIL source=");
    mcu_puts(pil_source);
    mcu_put_kv("n", pil_n);
    mcu_put_kv("cfg_bytes", (uint32_t)sizeof(paper000_config_t));
    mcu_put_kv("state_bytes", (uint32_t)sizeof(paper000_drive_t));
    mcu_puts("\n");
    if (!paper000_drive_init(&drive, &cfg)) {
        mcu_puts("PIL paper000_drive_init rejected the recorded config\nPIL FAIL\n");
        return 1;
    }

    /* the drive's CAN node at the default rates (comm/can_node.h): its
     * telemetry step and the transmit queue drained, timed apart from the
     * control step ("C" lines) */
    {
        can_tx_config_t tc;
        can_tx_defaults(&tc, 0u, (int32_t)cfg.model.fs_hz);
        can_node_init(&can_node, &tc);
    }

    /* calibration: the same timed region around nothing */
    uint32_t calib = 0xFFFFFFFFu;
    for (int k = 0; k < 8; ++k) {
        __asm__ volatile("" ::: "memory");
        const uint32_t t0 = mcu_systick_now();
        __asm__ volatile("" ::: "memory");
        const uint32_t t1 = mcu_systick_now();
        const uint32_t dt = mcu_systick_elapsed(t0, t1);
        calib = (dt < calib) ? dt : calib;
    }

    uint32_t mismatches = 0u;
    uint32_t first = 0xFFFFFFFFu;
    uint32_t col = 0u;
    uint32_t can_times[32];
    for (uint32_t i = 0; i < pil_n; ++i) {
        /* the sample a backend hands to its control callback (hal_types.h) */
        hal_sample_t in;
        memset(&in, 0, sizeof in);
        in.tick = i;
        in.n_phases = 2u;
        in.i_A[0] = from_bits(pil_io[i][0]);
        in.i_A[1] = from_bits(pil_io[i][1]);
        hal_command_t out;
        /* keep the argument stores before and the result use after the
         * timed region: the compiler may not move them across the asm */
        __asm__ volatile("" ::: "memory");
        const uint32_t t0 = mcu_systick_now();
        control(&drive, &in, &out);
        const uint32_t t1 = mcu_systick_now();
        __asm__ volatile("" ::: "memory");
        const mc_t va = out.v_V[0];
        const mc_t vb = out.v_V[1];
        if (to_bits(va) != pil_io[i][2] || to_bits(vb) != pil_io[i][3]) {
            if (mismatches == 0u) {
                first = i;
            }
            ++mismatches;
        }
        __asm__ volatile("" ::: "memory");
        const uint32_t c0 = mcu_systick_now();
        can_node_step_drive(&can_node, &handle, i, MC_ZERO, MC_ZERO);
        can_frame_t frame;
        while (can_node_peek(&can_node, &frame)) {
            can_node_pop(&can_node);
        }
        const uint32_t c1 = mcu_systick_now();
        __asm__ volatile("" ::: "memory");
        can_times[col] = mcu_systick_elapsed(c0, c1);
        if (col == 0u) {
            mcu_puts("T");
        }
        mcu_puts(" ");
        mcu_put_u32(mcu_systick_elapsed(t0, t1));
        if (++col == 32u || i + 1u == pil_n) {
            mcu_puts("\nC");
            for (uint32_t j = 0; j < col; ++j) {
                mcu_puts(" ");
                mcu_put_u32(can_times[j]);
            }
            mcu_puts("\n");
            col = 0u;
        }
    }
    mcu_puts("PIL");
    mcu_put_kv("calib", calib);
    mcu_put_kv("mismatches", mismatches);
    mcu_put_kv("first", first);
    mcu_put_kv("stack_used", stack_used());
    uint32_t here = 0u;
    __asm__ volatile("" : "+r"(here));
    mcu_put_kv("stack_main", (uint32_t)((uintptr_t)&_estack - (uintptr_t)&here));
    mcu_put_kv("fixed", (uint32_t)MC_FIXED);
    mcu_puts((mismatches == 0u) ? "\nPIL PASS\n" : "\nPIL FAIL\n");
    return (mismatches == 0u) ? 0 : 1;
}
