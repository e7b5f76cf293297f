/*
 * pil_paper001_main.c - processor-in-the-loop image of the paper-001 speed
 * drive (drives/paper001/paper001_drive.h): paper001_drive_step on the emulated core
 * over a recorded input sequence (tools/bench/pil_gen.cpp --drive paper001),
 * like pil_main.c does for paper 000's paper000_drive_step.
 *
 * For every period: the recorded phase currents and bus voltage go, as a
 * hal_sample_t, into the drive's control callback (the hal_control_fn a
 * backend calls), the call is timed with SysTick, and the three phase
 * voltages are compared bit for bit with those the host build of the same
 * numeric type returned.
 *
 * Parts of the step, on their own (estimator FLUX, periods that start and
 * end in closed loop): before the step the image copies the flux observer,
 * the I&I speed/load observer and the IDA-PBC states; after it, it runs the
 * same calls the step made on those copies, with the step's inputs (the
 * alpha-beta currents, the new rho_hat, the drive's i_d/i_q, estimates and
 * reference), each between two SysTick reads:
 *   flux    flux_observer_step (12)-(14)        (a library call in the step)
 *   ii      speed_load_observer_step (15)-(16)  (a library call in the step)
 *   ida     ida_pbc_step (11)                   (inline in the step)
 *   frames  mc_rot_fwd of i and mc_rot_inv of v at the advanced output
 *           angle (paper001_output_rot; inline in the step)
 * each through a noipa wrapper that takes its arguments in one struct, so
 * that the timed sequence (pointer, bl) is the same for every part and for
 * an empty wrapper timed in the same period, which tools/bench/pil.py
 * subtracts. A part's count is thus its body plus loading its arguments
 * (and, for the library calls, the call itself), as in the step.
 * It then checks that the copies end bit for bit where the drive's states
 * did (flux observer after flux_observer_hold of the voltage the step held,
 * I&I, IDA-PBC, i_d/i_q) and, in the periods where the supervisor did not
 * limit the command (part_outputs_checked), that IDA-PBC's (v_d, v_q) plus
 * the bumpless offset and its rotation are the command and voltage the step
 * recorded; a difference counts in part_mismatches.
 *
 * Output (semihosting), parsed by tools/bench/pil.py:
 *   PIL source=<...> n=<N> cfg_bytes=<..> state_bytes=<sizeof(paper001_drive_t)> estimator=<0|1>
 *   T <ticks> <ticks> ...         per-period SysTick ticks of the step, 32 per line
 *   S <digits>                    supervisor state after each step, 64 per line
 *                                 (0 identify, 1 open loop, 2 closed loop, 3 fault)
 *   P <period> <flux> <ii> <flux/ii empty> <ida> <ida empty> <frames> <frames empty>
 *                                 ticks of the parts (see above)
 *   PIL calib=<ticks of an empty timed region>
 *       mismatches=<m> first=<i> part_mismatches=<m> part_first=<i> part_outputs_checked=<n>
 *       stack_used=<bytes> stack_main=<bytes>
 *   PIL PASS | PIL FAIL
 */
#include <string.h>

#include "control/ida_pbc.h"
#include "drives/paper001/paper001_drive.h"
#include "estimators/flux_observer.h"
#include "estimators/speed_load_observer.h"
#include "hal/hal.h"
#include "mcu_rt.h"
#include "pil_common.h"
#include "pil_vectors.h"

static paper001_drive_t drive;
/* the parts' states before the step, replayed after it */
static flux_observer_t flux_copy;
static speed_load_observer_t speed_copy;
static ida_pbc_t ctrl_copy;

/* The control callback of hal.h (hal_control_fn), as an MCU backend calls
 * it from its end-of-conversion interrupt: the drive's step, and the safe
 * state on a fault (here: nothing to switch off). */
static void drive_callback(void *ctx, const hal_sample_t *in, hal_command_t *out)
{
    (void)paper001_drive_step((paper001_drive_t *)ctx, in, out);
}
static hal_control_fn const control = drive_callback;

/* The inline parts, out of line (noipa: no constant propagation into them,
 * no removal of the empty ones), and empty twins for the call overhead.
 * Arguments and results go through one struct, so that the timed call is
 * the same two instructions (pointer, bl) for a part and its empty twin, and
 * the part's count includes loading its inputs and storing its outputs, as
 * the inline code in the step does from and to the drive's state. */
typedef struct {
    flux_observer_t *o;
    speed_load_observer_t *so;
    mc_rot_t rho;
    mc_ab_t i;
} pil_obs_args_t;
/* the library calls as the step makes them: arguments loaded, then bl */
__attribute__((noipa)) static void pil_flux(pil_obs_args_t *a) { flux_observer_step(a->o, a->i); }
__attribute__((noipa)) static void pil_ii(pil_obs_args_t *a) { speed_load_observer_step(a->so, a->rho, a->i); }
__attribute__((noipa)) static void pil_obs_empty(pil_obs_args_t *a) { (void)a; }

typedef struct {
    ida_pbc_t *s;
    const ida_pbc_config_t *c;
    mc_t i_d, i_q, w_hat, tau_hat, w_ref, a_ref;
    mc_t v_d, v_q;
} pil_ida_args_t;
__attribute__((noipa)) static void pil_ida(pil_ida_args_t *a)
{
    ida_pbc_step(a->s, a->c, a->i_d, a->i_q, a->w_hat, a->tau_hat, a->w_ref, a->a_ref, &a->v_d, &a->v_q);
}
__attribute__((noipa)) static void pil_ida_empty(pil_ida_args_t *a) { (void)a; }

typedef struct {
    const paper001_config_t *c;
    mc_rot_t rho;
    mc_t w_hat;
    mc_ab_t i;
    mc_t v_d, v_q;
    mc_t i_d, i_q;
    mc_ab_t v;
} pil_frames_args_t;
__attribute__((noipa)) static void pil_frames(pil_frames_args_t *a)
{
    mc_rot_fwd(a->rho, a->i.alpha, a->i.beta, &a->i_d, &a->i_q);
    mc_rot_inv(paper001_output_rot(a->c, a->rho, a->w_hat), a->v_d, a->v_q, &a->v.alpha, &a->v.beta);
}
__attribute__((noipa)) static void pil_frames_empty(pil_frames_args_t *a) { (void)a; }


/* a line built in a buffer, written with one semihosting call */
static char line[400];
static uint32_t line_len;
static void line_char(char ch)
{
    if (line_len + 1u < sizeof line) {
        line[line_len++] = ch;
    }
}
static void line_u32(uint32_t v)
{
    char tmp[10];
    uint32_t k = 0u;
    do {
        tmp[k++] = (char)('0' + (char)(v % 10u));
        v /= 10u;
    } while (v != 0u);
    while (k > 0u) {
        line_char(tmp[--k]);
    }
}
static void line_flush(void)
{
    line[line_len] = '\0';
    mcu_puts(line);
    line_len = 0u;
}

#define PIL_TIME(t_out, call)                                                                                          \
    do {                                                                                                               \
        __asm__ volatile("" ::: "memory");                                                                             \
        const uint32_t t0_ = mcu_systick_now();                                                                        \
        call;                                                                                                          \
        const uint32_t t1_ = mcu_systick_now();                                                                        \
        __asm__ volatile("" ::: "memory");                                                                             \
        (t_out) = mcu_systick_elapsed(t0_, t1_);                                                                       \
    } while (0)

static uint32_t min_u32(uint32_t a, uint32_t b) { return (a < b) ? a : b; }

int main(void)
{
    paint_stack();
    paper001_config_t cfg;
    memcpy(&cfg, pil_cfg_words, sizeof cfg);
    mcu_puts("PIL source=");
    mcu_puts(pil_source);
    mcu_put_kv("n", pil_n);
    mcu_put_kv("cfg_bytes", (uint32_t)sizeof(paper001_config_t));
    mcu_put_kv("state_bytes", (uint32_t)sizeof(paper001_drive_t));
    mcu_put_kv("estimator", (uint32_t)cfg.estimator);
    mcu_puts("\n");
    if (!paper001_drive_init(&drive, &cfg)) {
        mcu_puts("PIL paper001_drive_init rejected the recorded config\nPIL FAIL\n");
        return 1;
    }

    /* calibration: the same timed region around nothing */
    uint32_t calib = 0xFFFFFFFFu;
    for (int k = 0; k < 8; ++k) {
        uint32_t dt;
        PIL_TIME(dt, (void)0);
        calib = min_u32(calib, dt);
    }
    static pil_obs_args_t obs_args;
    static pil_ida_args_t ida_args;
    static pil_frames_args_t frames_args;

    uint32_t mismatches = 0u, part_mismatches = 0u, part_outputs_checked = 0u;
    uint32_t first = 0xFFFFFFFFu, part_first = 0xFFFFFFFFu;
    uint32_t ticks[32];
    uint32_t col = 0u;
    char states[65];
    uint32_t n_states = 0u;
    for (uint32_t i = 0; i < pil_n; ++i) {
        /* the sample a backend hands to its control callback (hal_types.h) */
        hal_sample_t in;
        memset(&in, 0, sizeof in);
        in.tick = i;
        in.n_phases = (uint8_t)pil_n_phases;
        in.i_A[0] = from_bits(pil_io[i][0]);
        in.i_A[1] = from_bits(pil_io[i][1]);
        in.i_A[2] = from_bits(pil_io[i][2]);
        in.v_bus_V = from_bits(pil_io[i][3]);
        hal_command_t out;
        memset(&out, 0, sizeof out);
        const bool part = cfg.estimator == P001_ESTIMATOR_FLUX && drive.sup.state == SUP_STATE_CLOSED_LOOP;
        /* the bumpless offset the supervisor adds to this step's command */
        const mc_t blend_d = drive.sup.blend_V[0];
        const mc_t blend_q = drive.sup.blend_V[1];
        /* the voltage held over the last sample (the delay's v[k-1]) */
        const mc_ab_t v_ab_before = drive.last.v_ab_V;
        if (part) {
            memcpy(&flux_copy, &drive.flux, sizeof flux_copy);
            memcpy(&speed_copy, &drive.speed, sizeof speed_copy);
            memcpy(&ctrl_copy, &drive.ctrl, sizeof ctrl_copy);
        }
        /* keep the argument stores before and the result use after the
         * timed region: the compiler may not move them across the asm */
        __asm__ volatile("" ::: "memory");
        const uint32_t t0 = mcu_systick_now();
        control(&drive, &in, &out);
        const uint32_t t1 = mcu_systick_now();
        __asm__ volatile("" ::: "memory");
        const uint32_t dt = mcu_systick_elapsed(t0, t1);
        if (to_bits(out.v_V[0]) != pil_io[i][4] || to_bits(out.v_V[1]) != pil_io[i][5] ||
            to_bits(out.v_V[2]) != pil_io[i][6]) {
            if (mismatches == 0u) {
                first = i;
            }
            ++mismatches;
        }

        if (part && drive.sup.state == SUP_STATE_CLOSED_LOOP) {
            /* the parts of this step, replayed on the copies */
            mc_t i_zero;
            const mc_ab_t i_ab = phase_adapter_currents(&in, &i_zero);
            uint32_t t_obs0, t_flux, t_ii, t_ida, t_ida0, t_frames, t_frames0;
            obs_args.o = &flux_copy;
            obs_args.so = &speed_copy;
            obs_args.i = i_ab;
            PIL_TIME(t_obs0, pil_obs_empty(&obs_args));
            PIL_TIME(t_flux, pil_flux(&obs_args));
            const mc_rot_t rho = flux_copy.unit;
            obs_args.rho = rho;
            PIL_TIME(t_ii, pil_ii(&obs_args));
            ida_args.s = &ctrl_copy;
            ida_args.c = &cfg.ctrl;
            ida_args.i_d = drive.last.i_d_A;
            ida_args.i_q = drive.last.i_q_A;
            ida_args.w_hat = speed_copy.omega_rad_s;
            ida_args.tau_hat = speed_copy.load_Nm;
            ida_args.w_ref = drive.ref.omega_rad_s;
            ida_args.a_ref = drive.ref.accel_rad_s2;
            PIL_TIME(t_ida0, pil_ida_empty(&ida_args));
            PIL_TIME(t_ida, pil_ida(&ida_args));
            /* the command as supervisor_blend makes it (no switch in a
             * closed-loop period) */
            mc_t v_d = ida_args.v_d;
            mc_t v_q = ida_args.v_q;
            if (mc_ne(blend_d, MC_ZERO) || mc_ne(blend_q, MC_ZERO)) {
                v_d = mc_add(v_d, blend_d);
                v_q = mc_add(v_q, blend_q);
            }
            frames_args.c = &cfg;
            frames_args.rho = rho;
            frames_args.w_hat = speed_copy.omega_rad_s;
            frames_args.i = i_ab;
            frames_args.v_d = v_d;
            frames_args.v_q = v_q;
            PIL_TIME(t_frames0, pil_frames_empty(&frames_args));
            PIL_TIME(t_frames, pil_frames(&frames_args));
            const mc_t i_d = frames_args.i_d;
            const mc_t i_q = frames_args.i_q;
            const mc_ab_t v_ab = frames_args.v;
            flux_observer_hold(&flux_copy, paper001_applied_mean(&cfg, drive.last.v_ab_V, v_ab_before));
            bool same = memcmp(&flux_copy, &drive.flux, sizeof flux_copy) == 0 &&
                        memcmp(&speed_copy, &drive.speed, sizeof speed_copy) == 0 &&
                        memcmp(&ctrl_copy, &drive.ctrl, sizeof ctrl_copy) == 0 &&
                        to_bits(i_d) == to_bits(drive.last.i_d_A) && to_bits(i_q) == to_bits(drive.last.i_q_A);
            if (!drive.sup.sat_prev) {
                /* not limited: the command the supervisor recorded is
                 * IDA-PBC's (v_d, v_q) plus the offset, the held voltage its
                 * rotation to alpha-beta */
                ++part_outputs_checked;
                same = same && to_bits(v_d) == to_bits(drive.sup.v_prev_V[0]) &&
                       to_bits(v_q) == to_bits(drive.sup.v_prev_V[1]) &&
                       to_bits(v_ab.alpha) == to_bits(drive.last.v_ab_V.alpha) &&
                       to_bits(v_ab.beta) == to_bits(drive.last.v_ab_V.beta);
            }
            if (!same) {
                if (part_mismatches == 0u) {
                    part_first = i;
                }
                ++part_mismatches;
            }
            line_char('P');
            line_char(' ');
            line_u32(i);
            line_char(' ');
            line_u32(t_flux);
            line_char(' ');
            line_u32(t_ii);
            line_char(' ');
            line_u32(t_obs0);
            line_char(' ');
            line_u32(t_ida);
            line_char(' ');
            line_u32(t_ida0);
            line_char(' ');
            line_u32(t_frames);
            line_char(' ');
            line_u32(t_frames0);
            line_char('\n');
            line_flush();
        }

        states[n_states++] = (char)('0' + (char)drive.sup.state);
        if (n_states == 64u || i + 1u == pil_n) {
            states[n_states] = '\0';
            mcu_puts("S ");
            mcu_puts(states);
            mcu_puts("\n");
            n_states = 0u;
        }
        ticks[col++] = dt;
        if (col == 32u || i + 1u == pil_n) {
            line_char('T');
            for (uint32_t k = 0; k < col; ++k) {
                line_char(' ');
                line_u32(ticks[k]);
            }
            line_char('\n');
            line_flush();
            col = 0u;
        }
    }
    mcu_puts("PIL");
    mcu_put_kv("calib", calib);
    mcu_put_kv("mismatches", mismatches);
    mcu_put_kv("first", first);
    mcu_put_kv("part_mismatches", part_mismatches);
    mcu_put_kv("part_first", part_first);
    mcu_put_kv("part_outputs_checked", part_outputs_checked);
    mcu_put_kv("stack_used", stack_used());
    uint32_t here = 0u;
    __asm__ volatile("" : "+r"(here));
    mcu_put_kv("stack_main", (uint32_t)((uintptr_t)&_estack - (uintptr_t)&here));
    mcu_put_kv("fixed", (uint32_t)MC_FIXED);
    const bool pass = mismatches == 0u && part_mismatches == 0u;
    mcu_puts(pass ? "\nPIL PASS\n" : "\nPIL FAIL\n");
    return pass ? 0 : 1;
}
