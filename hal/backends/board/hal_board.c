#include "hal_board.h"

#include <stdio.h>
#include <string.h>

#include "board_comedi.h"
#include "math/mc_convert.h"

/* One card per process, like one power stage per board. */
static struct {
    board_comedi_t *card;
    board_chain_t chain;
    uint32_t fs_hz;
    hal_control_fn fn;
    void *ctx;
    bool started, safe;
    uint32_t tick;
    char error[256];
} g;

static void zero_outputs(void)
{
    for (int k = 0; k < g.chain.cfg.n_phases; ++k) {
        (void)board_comedi_write(g.card, g.chain.cfg.voltage_ao[k], 0.0, NULL);
    }
}

bool hal_board_open(const board_chain_config_t *cfg, const char *device, int calibration_samples, uint32_t fs_hz,
                    char *err, int err_len)
{
    memset(&g, 0, sizeof g);
    if (!board_chain_check(cfg, err, err_len)) return false;
    board_chain_init(&g.chain, cfg);
    g.fs_hz = fs_hz;
    int ai[BOARD_MAX_PHASES + 1], ao[BOARD_MAX_PHASES];
    int n_ai = 0;
    for (int k = 0; k < cfg->n_phases; ++k) {
        ai[n_ai++] = cfg->current_ai[k];
        ao[k] = cfg->voltage_ao[k];
    }
    if (cfg->vbus_ai >= 0) ai[n_ai++] = cfg->vbus_ai;
    g.card = board_comedi_open(device, cfg->adc_range_V, ai, n_ai, ao, cfg->n_phases, err, err_len);
    if (g.card == NULL) return false;
    zero_outputs();
    /* the sensors' offsets with the outputs at zero */
    double sum[BOARD_MAX_PHASES] = {0.0, 0.0, 0.0};
    for (int s = 0; s < calibration_samples; ++s) {
        for (int k = 0; k < cfg->n_phases; ++k) {
            double v = 0.0;
            if (!board_comedi_read(g.card, cfg->current_ai[k], &v, NULL)) {
                (void)snprintf(err, (size_t)err_len, "%s: calibration: %s", device, board_comedi_error(g.card));
                hal_board_close();
                return false;
            }
            sum[k] += v;
        }
    }
    if (!board_chain_calibrate(&g.chain, sum, calibration_samples, err, err_len)) {
        hal_board_close();
        return false;
    }
    return true;
}

const board_chain_t *hal_board_chain(void) { return &g.chain; }

static bool io_fail(void)
{
    (void)snprintf(g.error, sizeof g.error, "%s", board_comedi_error(g.card));
    hal_safe_state();
    return false;
}

bool hal_board_period(void)
{
    if (!g.started || g.safe || g.card == NULL) return false;
    const board_chain_config_t *c = &g.chain.cfg;
    hal_sample_t in;
    memset(&in, 0, sizeof in);
    in.tick = g.tick;
    in.n_phases = (uint8_t)c->n_phases;
    for (int k = 0; k < c->n_phases; ++k) {
        double v = 0.0;
        if (!board_comedi_read(g.card, c->current_ai[k], &v, NULL)) return io_fail();
        in.i_A[k] = mc_from_double(board_current_from_V(&g.chain, k, v));
    }
    double vb = 0.0;
    if (c->vbus_ai >= 0 && !board_comedi_read(g.card, c->vbus_ai, &vb, NULL)) return io_fail();
    in.v_bus_V = mc_from_double(board_vbus_from_V(&g.chain, vb));
    hal_command_t out;
    memset(&out, 0, sizeof out);
    out.n_phases = in.n_phases;
    g.fn(g.ctx, &in, &out);
    if (g.safe) return false; /* the callback put the stage in its safe state */
    for (int k = 0; k < c->n_phases; ++k) {
        const double u = board_dac_V(&g.chain, mc_to_double(out.v_V[k]), NULL);
        if (!board_comedi_write(g.card, c->voltage_ao[k], u, NULL)) return io_fail();
    }
    g.tick += 1u;
    return true;
}

static bool rt_step(void *ctx)
{
    (void)ctx;
    return hal_board_period();
}

void hal_board_run_realtime(uint64_t n_periods, int priority, rt_loop_stats_t *st)
{
    rt_loop_config_t cfg = {1000000000u / g.fs_hz, priority};
    rt_loop_run(&cfg, &rt_step, NULL, n_periods, st);
}

void hal_board_close(void)
{
    if (g.card != NULL) {
        zero_outputs();
        board_comedi_close(g.card);
        g.card = NULL;
    }
    g.started = false;
}

/* ---- hal.h ---- */

uint32_t hal_control_rate_hz(void) { return g.fs_hz; }

bool hal_start(hal_control_fn fn, void *ctx)
{
    if (g.card == NULL || !g.chain.calibrated) {
        (void)snprintf(g.error, sizeof g.error, "hal_start: the board is not open and calibrated (hal_board_open)");
        return false;
    }
    if (fn == NULL) {
        (void)snprintf(g.error, sizeof g.error, "hal_start: control callback is NULL");
        return false;
    }
    g.fn = fn;
    g.ctx = ctx;
    g.tick = 0;
    g.started = true;
    g.safe = false;
    return true;
}

void hal_safe_state(void)
{
    g.safe = true;
    if (g.card != NULL) zero_outputs();
}

uint32_t hal_time_us(void) { return g.fs_hz ? (uint32_t)((uint64_t)g.tick * 1000000u / g.fs_hz) : 0u; }

const char *hal_last_error(void) { return g.error; }

bool hal_can_send(const hal_can_frame_t *f)
{
    (void)f;
    return false; /* no bus on this backend */
}

bool hal_can_receive(hal_can_frame_t *f)
{
    (void)f;
    return false;
}
