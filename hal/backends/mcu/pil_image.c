/*
 * pil_image.c - the processor-in-the-loop image of any drive of the
 * registry (drives/registry.h): the drive's control step on the emulated
 * core over a sequence recorded on the host (tools/bench/pil_gen.cpp).
 *
 * The drive is the one the build was configured with (CMake MC_DRIVE; the
 * generated pil_drive.h names it and its operations, checked against the
 * registry at configure time): the image binds it to a drive_storage_t, loads the host-designed configuration
 * (raw words into a drive_config_storage_t) and initialises it through the
 * interface. For every recorded period the sample goes, as a backend hands
 * it to its control callback (hal.h: zeroed command, its phase count set),
 * into the drive's step between two SysTick reads, and every field of the
 * command is compared bit for bit with what the host build of the same
 * numeric type returned, and so are its signals (drives/drive.h: the
 * columns of its signal list, read after the step outside the timed
 * region) against the host's hash of them (pil_vectors.h: pil_signal_hash).
 * After the step, timed apart: the drive's CAN node
 * at the default rates (comm/can_node.h, through the interface: its
 * telemetry step and the transmit queue drained). The drive's own probe
 * (pil_probe.h) may time parts of the step around it.
 *
 * Output (semihosting), parsed by tools/bench/pil.py:
 *   PIL source=<...> drive=<name> n=<N> cfg_bytes=<..> state_bytes=<ops->state_bytes> [probe keys]
 *   T <ticks> ...    per-period SysTick ticks of the step, 32 per line
 *   C <ticks> ...    the CAN node's step after it, the same periods
 *   S <digits>       the supervisor state after each step (drive_status_t.state:
 *                    0 identify, 1 open loop, 2 closed loop, 3 fault), 64 per line
 *   [probe lines]
 *   PIL calib=<ticks of an empty timed region> mismatches=<m> first=<i>
 *       signals=<n> signal_mismatches=<m> signal_first=<i> [probe keys]
 *       stack_used=<bytes below the stack top touched by the whole run>
 *       stack_main=<depth of main's frame at the step call, about> fixed=<0|1>
 *   PIL PASS | PIL FAIL
 * A failure before the run (the drive not in the registry, vectors of
 * another drive or size, a configuration the drive refuses) prints why and
 * PIL FAIL, and exits 1.
 */
#include <string.h>

#include "comm/can_node.h"
#include "drives/registry.h"
#include "hal/hal.h"
#include "mcu_rt.h"
#include "pil_common.h"
#include "pil_drive.h"
#include "pil_probe.h"
#include "pil_replay.h"
#include "pil_vectors.h"

static drive_storage_t storage;
static drive_config_storage_t cfg;
static drive_t drive;
static can_node_t can_node;
static pil_line_t line;
static mc_t signal_values[DRIVE_SIGNALS_MAX];
static uint32_t signal_words[DRIVE_SIGNALS_MAX];
static uint32_t n_signals, signal_mismatches, signal_first = 0xFFFFFFFFu;

static int fail(const char *why)
{
    mcu_puts("PIL ");
    mcu_puts(why);
    mcu_puts("\nPIL FAIL\n");
    return 1;
}

static void put_ticks(char tag, const uint32_t *v, uint32_t n)
{
    pil_line_char(&line, tag);
    for (uint32_t j = 0; j < n; ++j) {
        pil_line_char(&line, ' ');
        pil_line_u32(&line, v[j]);
    }
    pil_line_char(&line, '\n');
    pil_line_flush(&line);
}

/* The signals' check lives in functions of its own, its state static,
 * and its count's check comes after the calibration: the compiler
 * schedules the calibration's empty timed region with main's code around
 * it, and that figure is subtracted from every step's (with the check in
 * main the M4F's calibration fell from 12 to 6 ticks, every step's count
 * rose by one instruction that the step did not have). */

/* the drive's signals after period i's step against the host's hash,
 * outside the timed region */
__attribute__((noinline)) static void check_signals(uint32_t i)
{
    drive_read_signals(&drive, signal_values);
    for (uint32_t k = 0; k < n_signals; ++k) {
        signal_words[k] = to_bits(signal_values[k]);
    }
    if (pil_signal_hash_of(signal_words, n_signals) != pil_signal_hash[i]) {
        if (signal_mismatches == 0u) {
            signal_first = i;
        }
        ++signal_mismatches;
    }
}

__attribute__((noinline)) static void report_signals(void)
{
    mcu_put_kv("signals", n_signals);
    mcu_put_kv("signal_mismatches", signal_mismatches);
    mcu_put_kv("signal_first", signal_first);
}

__attribute__((noinline)) static bool signals_ok(void) { return signal_mismatches == 0u; }

/* the drive's signal list is the one the vectors were recorded with */
__attribute__((noinline)) static bool signals_recorded(void)
{
    (void)drive_signals(&drive, &n_signals);
    return n_signals == pil_signal_count && n_signals <= DRIVE_SIGNALS_MAX;
}

int main(void)
{
    paint_stack();
    mcu_puts("PIL source=");
    mcu_puts(pil_source);
    mcu_puts(" drive=");
    mcu_puts(PIL_DRIVE_NAME);
    const drive_ops_t *ops = PIL_DRIVE_OPS;
    if (!drive_bind(&drive, ops, &storage)) {
        return fail("the drive of this build (MC_DRIVE) does not fit drive_storage_t");
    }
    if (strcmp(pil_drive, PIL_DRIVE_NAME) != 0) {
        mcu_puts("\nPIL the vectors were recorded from drive ");
        mcu_puts(pil_drive);
        return fail("(mc_pil_gen --drive), not this build's MC_DRIVE");
    }
    if (pil_cfg_bytes != ops->config_bytes || pil_cfg_bytes > (uint32_t)sizeof cfg) {
        return fail("the recorded configuration's size is not the drive's config_bytes (a layout differs)");
    }
    memcpy(&cfg, pil_cfg_words, pil_cfg_bytes);
    mcu_put_kv("n", pil_n);
    mcu_put_kv("cfg_bytes", ops->config_bytes);
    mcu_put_kv("state_bytes", ops->state_bytes);
    pil_probe_header(&cfg);
    mcu_puts("\n");
    if (!drive_init(&drive, &cfg)) {
        mcu_puts("PIL drive_init rejected the recorded config: ");
        const char *why = (ops->config_problem != 0) ? ops->config_problem(&cfg) : 0;
        return fail(why != 0 ? why : "(no reason given)");
    }

    /* the drive's CAN node at the default rates (comm/can_node.h) */
    {
        can_tx_config_t tc;
        can_tx_defaults(&tc, 0u, (int32_t)pil_control_hz);
        if (!can_node_init(&can_node, &tc)) {
            return fail("can_node_init refused node 0 at the control rate");
        }
    }

    /* calibration: the same timed region around nothing */
    uint32_t calib = 0xFFFFFFFFu;
    for (int k = 0; k < 8; ++k) {
        uint32_t dt;
        PIL_TIME(dt, (void)0);
        calib = (dt < calib) ? dt : calib;
    }

    if (!signals_recorded()) {
        return fail("the drive lists another number of signals than the vectors were recorded with");
    }
    void *const self = drive.self;
    uint32_t mismatches = 0u;
    uint32_t first = 0xFFFFFFFFu;
    uint32_t col = 0u;
    uint32_t step_ticks[32], can_ticks[32];
    char states[65];
    uint32_t n_states = 0u;
    for (uint32_t i = 0; i < pil_n; ++i) {
        /* the sample and the command as a backend hands them to its
         * control callback (hal_types.h) */
        hal_sample_t in;
        pil_sample(i, &in);
        hal_command_t out;
        memset(&out, 0, sizeof out);
        out.n_phases = in.n_phases;
        pil_probe_before(self, &cfg, &in, i);
        uint32_t dt;
#if PIL_STEP_VIA_INTERFACE
        PIL_TIME(dt, (void)drive_step(&drive, &in, &out));
#else
        PIL_TIME(dt, (void)pil_drive_step_direct(self, &in, &out));
#endif
        if (!pil_command_matches(i, &out)) {
            if (mismatches == 0u) {
                first = i;
            }
            ++mismatches;
        }
        pil_probe_after(self, &cfg, &in, &out, i);
        check_signals(i);
        uint32_t dc;
        __asm__ volatile("" ::: "memory");
        const uint32_t c0 = mcu_systick_now();
        can_node_step_drive(&can_node, &drive, i, MC_ZERO, MC_ZERO);
        can_frame_t frame;
        while (can_node_peek(&can_node, &frame)) {
            can_node_pop(&can_node);
        }
        const uint32_t c1 = mcu_systick_now();
        __asm__ volatile("" ::: "memory");
        dc = mcu_systick_elapsed(c0, c1);

        drive_status_t st;
        drive_status(&drive, &st);
        states[n_states++] = (char)('0' + (char)(st.state % 10u));
        if (n_states == 64u || i + 1u == pil_n) {
            states[n_states] = '\0';
            mcu_puts("S ");
            mcu_puts(states);
            mcu_puts("\n");
            n_states = 0u;
        }
        step_ticks[col] = dt;
        can_ticks[col] = dc;
        if (++col == 32u || i + 1u == pil_n) {
            put_ticks('T', step_ticks, col);
            put_ticks('C', can_ticks, col);
            col = 0u;
        }
    }
    mcu_puts("PIL");
    mcu_put_kv("calib", calib);
    mcu_put_kv("mismatches", mismatches);
    mcu_put_kv("first", first);
    report_signals();
    const bool probe_ok = pil_probe_report();
    mcu_put_kv("stack_used", stack_used());
    uint32_t here = 0u;
    __asm__ volatile("" : "+r"(here));
    mcu_put_kv("stack_main", (uint32_t)((uintptr_t)&_estack - (uintptr_t)&here));
    mcu_put_kv("fixed", (uint32_t)MC_FIXED);
    mcu_put_kv("step_via_interface", (uint32_t)PIL_STEP_VIA_INTERFACE);
    const bool pass = mismatches == 0u && signals_ok() && probe_ok;
    mcu_puts(pass ? "\nPIL PASS\n" : "\nPIL FAIL\n");
    return pass ? 0 : 1;
}
