/*
 * main_qemu.c - the image's test under QEMU (-M netduinoplus2): the same
 * start-up code, vector table, backend control path and application as
 * main_board.c, on the QEMU board (boards/qemu_netduinoplus2.c). TIM2's
 * update interrupt at 10 kHz plays the ADC's part: it hands the backend
 * the next sample recorded on the host (the PIL vectors of
 * tools/bench/pil_gen.cpp for the image's drive, MC_DRIVE), and the command
 * the drive returns is compared with the host's, bit for bit
 * (hal/backends/mcu/pil_replay.h). Timed with SysTick as
 * the PIL tool times: the whole interrupt body (the backend around the
 * step included; the replay's decoding and comparison are not) and the
 * drive's step alone, called through the drive interface. Output by semihosting:
 *   "Q <isr cycles> ..." / "D <step cycles> ..." lines, then
 *   "STM32QEMU steps=.. mismatches=.. calib=.. boot=.." and PASS or FAIL.
 */
#include <string.h>

#include "app_drive.h"
#include "boards/board.h"
#include "mcu_rt.h"
#include "pil_replay.h"
#include "pil_vectors.h"
#include "stm32_backend.h"
#include "stm32f405_regs.h"

static app_drive_t app;

#ifdef MC_DESIGN_OPS
#include "design/ops/drive_design_ops.h"

/* The drive's design on the board from its parameters' defaults with the
 * pair's values over them, as the flashable image starts
 * (design/ops/drive_design_ops.h: the host's design code in double, the
 * Cortex-M4F's soft double and newlib's libm), compared byte for byte with
 * the configuration the host designs from the same parameters with the
 * same code (the vectors' pil_design_cfg_words, tools/bench/pil_gen.cpp
 * --board-scenario).
 * Static: the input and the configuration are a few kB. */
extern const drive_design_ops_t MC_DESIGN_OPS; /* the image's drive's (CMakeLists.txt) */
extern const drive_ops_t MC_DRIVE_OPS;          /* its drive (app_drive.c binds the same) */
extern const uint32_t pil_design_cfg_words[];
extern const app_param_value_t board_drive_values[]; /* the pair's values (CMakeLists.txt) */
extern const uint32_t board_drive_values_count;
extern const uint32_t pil_design_cfg_bytes;
static uint8_t design_input[2048] __attribute__((aligned(8)));
static volatile uint32_t systick_wraps; /* SysTick's interrupt, on during the design only */

void SysTick_Handler(void);
void SysTick_Handler(void) { systick_wraps = systick_wraps + 1u; }
static uint8_t design_cfg[2048] __attribute__((aligned(8)));

static void check_design_on_board(void)
{
    const drive_design_ops_t *d = &MC_DESIGN_OPS;
    param_error_t perr;
    char err[96] = {0};
    mcu_puts("STM32QEMU design ");
    mcu_puts(d->name);
    if (d->input_bytes > sizeof design_input || d->config_bytes > sizeof design_cfg ||
        d->config_bytes != pil_design_cfg_bytes) {
        mcu_puts(": sizes do not fit\nSTM32QEMU FAIL\n");
        mcu_exit(1);
    }
    memset(design_cfg, 0, sizeof design_cfg);
    /* timed across SysTick's wraps (24 bits: 0.1 s at 168 MHz): its
     * interrupt counts them while the design runs */
    systick_wraps = 0u;
    SYST_CVR = 0u;
    SYST_CSR = 7u;
    const uint32_t c0 = SYST_CVR;
    bool ok = drive_design_defaults_input(d, design_input, &perr);
    /* the board's values over the defaults, as the flashable image starts
     * (firmware/drives/<drive>/boards/<board>[_<variant>]_params.c) */
    for (uint32_t k = 0; ok && k < board_drive_values_count; ++k) {
        const param_value_t v = {.u32 = board_drive_values[k].value};
        ok = params_write(d->params, design_input, board_drive_values[k].id, v, false, &perr);
    }
    ok = ok && d->design(design_input, design_cfg, err, sizeof err);
    const uint32_t c1 = SYST_CVR;
    SYST_CSR = 5u;
    /* ticks = wraps * 2^24 + c0 - c1 (counting down from c0 after the reload) */
    const uint64_t ticks = (uint64_t)systick_wraps * 0x01000000u + c0 - c1;
    if (!ok) {
        mcu_puts(" refused: ");
        mcu_puts(err);
        mcu_puts("\nSTM32QEMU FAIL\n");
        mcu_exit(1);
    }
    uint32_t differ = 0u, first = 0xFFFFFFFFu;
    const uint8_t *host = (const uint8_t *)pil_design_cfg_words;
    for (uint32_t k = 0; k < d->config_bytes; ++k) {
        if (design_cfg[k] != host[k]) {
            if (differ == 0u) first = k;
            differ += 1u;
        }
    }
    /* the drive initialised from it, as the flashable image's control
     * interrupt does when it takes a new configuration (app_params.c):
     * timed alone (well within SysTick's 24 bits) */
    drive_t probe;
    uint32_t init_ticks = 0u;
    if (drive_bind(&probe, &MC_DRIVE_OPS, &app.storage)) {
        SYST_CVR = 0u;
        const uint32_t i0 = SYST_CVR;
        const bool init_ok = drive_init(&probe, design_cfg);
        const uint32_t i1 = SYST_CVR;
        /* cppcheck-suppress duplicateValueTernary ; SYST_CVR is a hardware counter: two reads differ */
        init_ticks = init_ok ? ((i0 - i1) & 0x00FFFFFFu) : 0u;
    }
    mcu_put_kv("design_init_ticks", init_ticks);
    mcu_put_kv("design_bytes", d->config_bytes);
    mcu_put_kv("design_differ", differ);
    mcu_put_kv("design_first", first);
    mcu_put_kv("design_ticks_hi", (uint32_t)(ticks >> 32));
    mcu_put_kv("design_ticks", (uint32_t)ticks);
    mcu_puts("\n");
    if (differ != 0u) {
        mcu_puts("STM32QEMU the configuration designed on the board differs from the host's\nSTM32QEMU FAIL\n");
        mcu_exit(1);
    }
}
#endif

static volatile uint32_t next;       /* the next recorded period */
static hal_sample_t next_in;         /* its sample, decoded from the vectors */
static volatile uint32_t mismatches;
static volatile uint32_t first_mismatch = 0xFFFFFFFFu;
static volatile bool done;
static uint32_t isr_cycles[32], step_cycles[32];
static uint32_t line_fill; /* periods in isr_cycles, step_cycles */
static uint32_t last_entry, period_min = 0xFFFFFFFFu, period_max;
static uint32_t period_sum, period_n; /* the mean period: the timer's rate, whatever one entry's latency */

/* the recorded output of period k, checked against what the drive returned */
static hal_command_t last_out;
static void checking_control(void *ctx, const hal_sample_t *in, hal_command_t *out)
{
    app_drive_control(ctx, in, out);
    last_out = *out;
}

static void put_line(char tag, const uint32_t *v, uint32_t n)
{
    char t[3] = {tag, 0, 0};
    mcu_puts(t);
    for (uint32_t j = 0; j < n; ++j) {
        mcu_puts(" ");
        mcu_put_u32(v[j]);
    }
    mcu_puts("\n");
}

void TIM2_IRQHandler(void)
{
    const uint32_t t0 = SYST_CVR;
    ((tim_regs_t *)STM32_TIM2_BASE)->SR = 0u;
    const uint32_t k = next;
    /* the interrupt's period in SysTick ticks (after the first) */
    if (k > 0u) {
        const uint32_t p = (last_entry - t0) & 0x00FFFFFFu;
        period_min = p < period_min ? p : period_min;
        period_max = p > period_max ? p : period_max;
        period_sum += p;
        period_n += 1u;
    }
    last_entry = t0;
    if (k >= pil_n) {
        done = true;
        return;
    }
    /* the sample decoded after the last interrupt's timed part (a board's
     * ADC hands it over ready) */
    hal_sample_t in = next_in;
    stm32_backend_control(&in); /* the backend sets the tick (its own count, = k) */
    next = k + 1u;
    const uint32_t t1 = SYST_CVR;
    /* not timed: the comparison with the host's command and the next sample */
    if (!pil_command_matches(k, &last_out)) {
        if (mismatches == 0u) first_mismatch = k;
        mismatches = mismatches + 1u;
    }
    if (k + 1u < pil_n) {
        pil_sample(k + 1u, &next_in);
    }
    isr_cycles[line_fill] = (t0 - t1) & 0x00FFFFFFu;
    step_cycles[line_fill] = app.step_cycles;
    line_fill += 1u;
    if (line_fill == 32u || k + 1u == pil_n) {
        put_line('Q', isr_cycles, line_fill);
        put_line('D', step_cycles, line_fill);
        line_fill = 0u;
    }
}

int main(void)
{
    SYST_RVR = 0x00FFFFFFu;
    SYST_CVR = 0u;
    SYST_CSR = 5u;
    /* calibration: the timed region around nothing */
    uint32_t calib = 0xFFFFFFFFu;
    for (int j = 0; j < 8; ++j) {
        __asm__ volatile("" ::: "memory");
        const uint32_t a = SYST_CVR;
        __asm__ volatile("" ::: "memory");
        const uint32_t b = SYST_CVR;
        const uint32_t d = (a - b) & 0x00FFFFFFu;
        calib = d < calib ? d : calib;
    }
    /* 1000 instructions timed: SysTick ticks per instruction under -icount */
    __asm__ volatile("" ::: "memory");
    const uint32_t n0 = SYST_CVR;
    __asm__ volatile(".rept 1000\n nop\n .endr" ::: "memory");
    const uint32_t n1 = SYST_CVR;
    const uint32_t nop1000 = ((n0 - n1) & 0x00FFFFFFu) - calib;
    mcu_puts("STM32QEMU board=");
    mcu_puts(board.name);
    mcu_puts(" drive=");
    mcu_puts(app_drive_name());
    mcu_puts(" source=");
    mcu_puts(pil_source);
    mcu_puts("\n");
    if (strcmp(pil_drive, app_drive_name()) != 0) {
        mcu_puts("STM32QEMU the vectors were recorded from drive ");
        mcu_puts(pil_drive);
        mcu_puts(", not this image's (MC_DRIVE)\nSTM32QEMU FAIL\n");
        mcu_exit(1);
    }
#ifdef MC_DESIGN_OPS
    check_design_on_board();
#endif
    if (!stm32_backend_init(&stm32_hw)) {
        mcu_puts("STM32QEMU init failed: ");
        mcu_puts(hal_last_error());
        mcu_put_kv("fault", (uint32_t)stm32_backend_status());
        mcu_puts("\nSTM32QEMU FAIL\n");
        mcu_exit(1);
    }
    pil_sample(0u, &next_in);
    if (!app_drive_init(&app, pil_cfg_words, pil_cfg_bytes, pil_control_hz, 0u, false) || !hal_start(&checking_control, &app)) {
        mcu_puts("STM32QEMU drive or hal_start failed\nSTM32QEMU FAIL\n");
        mcu_exit(1);
    }
    while (!done) {
        __asm__ volatile("wfi");
    }
    mcu_puts("STM32QEMU");
    mcu_put_kv("steps", stm32_backend_steps());
    mcu_put_kv("periods", pil_n);
    mcu_put_kv("mismatches", mismatches);
    mcu_put_kv("first", first_mismatch);
    mcu_put_kv("overruns", stm32_backend_overruns());
    mcu_put_kv("calib", calib);
    mcu_put_kv("nop1000", nop1000);
    mcu_put_kv("period_min", period_min);
    mcu_put_kv("period_max", period_max);
    mcu_put_kv("period_sum", period_sum);
    mcu_put_kv("period_n", period_n);
    const bool ok = mismatches == 0u && stm32_backend_steps() == pil_n;
    mcu_puts(ok ? "\nSTM32QEMU PASS\n" : "\nSTM32QEMU FAIL\n");
    mcu_exit(ok ? 0 : 1);
}
