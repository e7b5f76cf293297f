/*
 * paper001_probe.c - paper 001's own PIL probe (hal/backends/mcu/pil_probe.h):
 * the parts of paper001_drive_step timed on their own, linked into the
 * generic PIL image (hal/backends/mcu/pil_image.c) when it is built for
 * this drive (CMake MC_DRIVE=paper001). It reads the drive's state, which
 * only a file about this drive may do: it lives with the bench tools, not
 * in hal/.
 *
 * Parts of the step, on their own (estimator FLUX, periods that start and
 * end in closed loop): before the step the probe copies the flux observer,
 * the I&I speed/load observer and the IDA-PBC states; after it, it runs the
 * same calls the step made on those copies, with the step's inputs (the
 * alpha-beta currents, the new rho_hat, the drive's i_d/i_q, estimates and
 * reference), each between two SysTick reads:
 *   flux    flux_observer_step (12)-(14)        (a library call in the step)
 *   ii      speed_load_observer_step (15)-(16)  (a library call in the step)
 *   ida     ida_pbc_step (11)                   (inline in the step)
 *   frames  mc_rot_fwd of i and mc_rot_inv of v at the advanced output
 *           angle (flux_speed_output_rot; inline in the step)
 * each through a noipa wrapper that takes its arguments in one struct, so
 * that the timed sequence (pointer, bl) is the same for every part and for
 * an empty wrapper timed in the same period, which tools/bench/pil.py
 * subtracts. A part's count is thus its body plus loading its arguments
 * (and, for the library calls, the call itself), as in the step.
 * It then checks that the copies end bit for bit where the drive's states
 * did (the flux observer told the voltage held over the last sample first, as the step's measure is,
 * I&I, IDA-PBC, i_d/i_q) and, in the periods where the supervisor did not
 * limit the command (part_outputs_checked), that IDA-PBC's (v_d, v_q) plus
 * the bumpless offset and its rotation are the command and voltage the step
 * recorded; a difference counts in part_mismatches (and fails the image).
 *
 * Output: " estimator=<0 flux|1 back_emf>" on the first PIL line;
 *   P <period> <flux> <ii> <flux/ii empty> <ida> <ida empty> <frames> <frames empty>
 * per such period (SysTick ticks); " part_mismatches=<m> part_first=<i>
 * part_outputs_checked=<n>" on the last PIL line.
 */
#include <string.h>

#include "control/ida_pbc.h"
#include "drives/paper001/paper001_drive.h"
#include "estimators/flux_observer.h"
#include "estimators/speed_load_observer.h"
#include "mcu_rt.h"
#include "pil_common.h"
#include "pil_probe.h"

/* the parts' states before the step, replayed after it */
static flux_observer_t flux_copy;
static speed_load_observer_t speed_copy;
static ida_pbc_t ctrl_copy;
/* what the step started from */
static bool part;
static mc_t blend_d, blend_q; /* the bumpless offset the supervisor adds to this step's command */
static mc_ab_t u_held_before; /* the voltage the step's flux observer integrates (the drive's x.u_held_ab_V) */
static uint32_t part_mismatches, part_outputs_checked;
static uint32_t part_first = 0xFFFFFFFFu;
static pil_line_t line;

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
    mc_rot_inv(flux_speed_output_rot(&a->c->est, a->rho, a->w_hat), a->v_d, a->v_q, &a->v.alpha, &a->v.beta);
}
__attribute__((noipa)) static void pil_frames_empty(pil_frames_args_t *a) { (void)a; }

static pil_obs_args_t obs_args;
static pil_ida_args_t ida_args;
static pil_frames_args_t frames_args;

void pil_probe_header(const void *cfg_v)
{
    const paper001_config_t *cfg = (const paper001_config_t *)cfg_v;
    mcu_put_kv("estimator", (uint32_t)cfg->estimator);
}

void pil_probe_before(const void *self, const void *cfg_v, const hal_sample_t *in, uint32_t k)
{
    const paper001_drive_t *drive = (const paper001_drive_t *)self;
    const paper001_config_t *cfg = (const paper001_config_t *)cfg_v;
    (void)in;
    (void)k;
    part = cfg->estimator == OPEN_START_FLUX && drive->sup.state == SUP_STATE_CLOSED_LOOP;
    blend_d = drive->sup.blend_V[0];
    blend_q = drive->sup.blend_V[1];
    u_held_before = drive->x.u_held_ab_V;
    if (part) {
        memcpy(&flux_copy, &drive->est_state.flux_speed.flux, sizeof flux_copy);
        memcpy(&speed_copy, &drive->est_state.flux_speed.speed, sizeof speed_copy);
        flux_observer_hold(&flux_copy, u_held_before); /* as the step's measure begins */
        memcpy(&ctrl_copy, &drive->ctrl, sizeof ctrl_copy);
    }
}

void pil_probe_after(const void *self, const void *cfg_v, const hal_sample_t *in, const hal_command_t *out, uint32_t i)
{
    const paper001_drive_t *drive = (const paper001_drive_t *)self;
    const paper001_config_t *cfg = (const paper001_config_t *)cfg_v;
    (void)out;
    if (!part || drive->sup.state != SUP_STATE_CLOSED_LOOP) {
        return;
    }
    /* the parts of this step, replayed on the copies */
    mc_t i_zero;
    const mc_ab_t i_ab = phase_adapter_currents(in, &i_zero);
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
    ida_args.c = &cfg->ctrl;
    ida_args.i_d = drive->last.i_d_A;
    ida_args.i_q = drive->last.i_q_A;
    ida_args.w_hat = speed_copy.omega_rad_s;
    ida_args.tau_hat = speed_copy.load_Nm;
    ida_args.w_ref = drive->x.ref.omega_rad_s;
    ida_args.a_ref = drive->x.ref.accel_rad_s2;
    PIL_TIME(t_ida0, pil_ida_empty(&ida_args));
    PIL_TIME(t_ida, pil_ida(&ida_args));
    /* the command as supervisor_blend makes it (no switch in a closed-loop
     * period) */
    mc_t v_d = ida_args.v_d;
    mc_t v_q = ida_args.v_q;
    if (mc_ne(blend_d, MC_ZERO) || mc_ne(blend_q, MC_ZERO)) {
        v_d = mc_add(v_d, blend_d);
        v_q = mc_add(v_q, blend_q);
    }
    frames_args.c = cfg;
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
    bool same = memcmp(&flux_copy, &drive->est_state.flux_speed.flux, sizeof flux_copy) == 0 &&
                memcmp(&speed_copy, &drive->est_state.flux_speed.speed, sizeof speed_copy) == 0 &&
                memcmp(&ctrl_copy, &drive->ctrl, sizeof ctrl_copy) == 0 && to_bits(i_d) == to_bits(drive->last.i_d_A) &&
                to_bits(i_q) == to_bits(drive->last.i_q_A);
    if (!drive->sup.sat_prev) {
        /* not limited: the command the supervisor recorded is IDA-PBC's
         * (v_d, v_q) plus the offset, the held voltage its rotation to
         * alpha-beta */
        ++part_outputs_checked;
        same = same && to_bits(v_d) == to_bits(drive->sup.v_prev_V[0]) &&
               to_bits(v_q) == to_bits(drive->sup.v_prev_V[1]) &&
               to_bits(v_ab.alpha) == to_bits(drive->last.v_ab_V.alpha) &&
               to_bits(v_ab.beta) == to_bits(drive->last.v_ab_V.beta);
    }
    if (!same) {
        if (part_mismatches == 0u) {
            part_first = i;
        }
        ++part_mismatches;
    }
    const uint32_t v[8] = {i, t_flux, t_ii, t_obs0, t_ida, t_ida0, t_frames, t_frames0};
    pil_line_char(&line, 'P');
    for (uint32_t j = 0; j < 8u; ++j) {
        pil_line_char(&line, ' ');
        pil_line_u32(&line, v[j]);
    }
    pil_line_char(&line, '\n');
    pil_line_flush(&line);
}

bool pil_probe_report(void)
{
    mcu_put_kv("part_mismatches", part_mismatches);
    mcu_put_kv("part_first", part_first);
    mcu_put_kv("part_outputs_checked", part_outputs_checked);
    return part_mismatches == 0u;
}
