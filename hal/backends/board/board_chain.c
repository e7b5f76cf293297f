#include "board_chain.h"

#include <math.h>
#include <stdio.h>

static bool fail(char *err, int n, const char *key, const char *why)
{
    if (err != NULL && n > 0) {
        (void)snprintf(err, (size_t)n, "%s: %s", key, why);
    }
    return false;
}

bool board_chain_check(const board_chain_config_t *c, char *err, int n)
{
    char why[160];
    if (c->n_phases != 2 && c->n_phases != 3) return fail(err, n, "board.current_channels", "2 or 3 phases");
    if (c->ai_channels < 1 || c->ai_channels > BOARD_MAX_CHANNELS)
        return fail(err, n, "board.ai_channels", "must be 1-64");
    if (c->ao_channels < 1 || c->ao_channels > BOARD_MAX_CHANNELS)
        return fail(err, n, "board.ao_channels", "must be 1-64");
    bool ai_used[BOARD_MAX_CHANNELS] = {false};
    bool ao_used[BOARD_MAX_CHANNELS] = {false};
    for (int k = 0; k < c->n_phases; ++k) {
        const int a = c->current_ai[k], o = c->voltage_ao[k];
        if (a < 0 || a >= c->ai_channels) {
            (void)snprintf(why, sizeof why, "channel %d of phase %c is not one of the card's %d A/D channels", a,
                           'a' + k, c->ai_channels);
            return fail(err, n, "board.current_channels", why);
        }
        if (ai_used[a]) {
            (void)snprintf(why, sizeof why, "A/D channel %d carries two signals", a);
            return fail(err, n, "board.current_channels", why);
        }
        ai_used[a] = true;
        if (o < 0 || o >= c->ao_channels) {
            (void)snprintf(why, sizeof why, "channel %d of phase %c is not one of the card's %d D/A channels", o,
                           'a' + k, c->ao_channels);
            return fail(err, n, "board.voltage_channels", why);
        }
        if (ao_used[o]) {
            (void)snprintf(why, sizeof why, "D/A channel %d carries two signals", o);
            return fail(err, n, "board.voltage_channels", why);
        }
        ao_used[o] = true;
    }
    if (c->vbus_ai >= 0) {
        if (c->vbus_ai >= c->ai_channels) {
            (void)snprintf(why, sizeof why, "channel %d is not one of the card's %d A/D channels", c->vbus_ai,
                           c->ai_channels);
            return fail(err, n, "board.vbus_channel", why);
        }
        if (ai_used[c->vbus_ai]) {
            (void)snprintf(why, sizeof why, "A/D channel %d already carries a phase current", c->vbus_ai);
            return fail(err, n, "board.vbus_channel", why);
        }
    }
    if (c->adc_bits < 1 || c->adc_bits > 24) return fail(err, n, "board.adc_bits", "must be 1-24");
    if (c->dac_bits < 1 || c->dac_bits > 24) return fail(err, n, "board.dac_bits", "must be 1-24");
    if (!(c->adc_range_V > 0.0) || !isfinite(c->adc_range_V)) return fail(err, n, "board.adc_range_V", "must be > 0");
    if (!(c->dac_range_V > 0.0) || !isfinite(c->dac_range_V)) return fail(err, n, "board.dac_range_V", "must be > 0");
    if (!(c->sensor_V_per_A > 0.0) || !isfinite(c->sensor_V_per_A))
        return fail(err, n, "board.sensor_V_per_A", "must be > 0 (a gain of 0 measures nothing)");
    if (!(c->amplifier_V_per_V > 0.0) || !isfinite(c->amplifier_V_per_V))
        return fail(err, n, "board.amplifier_V_per_V", "must be > 0 (a gain of 0 drives nothing)");
    if (c->vbus_ai >= 0 && (!(c->vbus_V_per_V > 0.0) || !isfinite(c->vbus_V_per_V)))
        return fail(err, n, "board.vbus_V_per_V", "must be > 0");
    if (!(c->supply_V > 0.0)) return fail(err, n, "supply.v_max_V", "must be > 0");
    if (c->dac_range_V * c->amplifier_V_per_V < c->supply_V * (1.0 - 1e-9)) {
        (void)snprintf(why, sizeof why,
                       "the D/A range %.4g V times the amplifier's %.4g V/V gives %.4g V, less than the %.4g V supply",
                       c->dac_range_V, c->amplifier_V_per_V, c->dac_range_V * c->amplifier_V_per_V, c->supply_V);
        return fail(err, n, "board.dac_range_V", why);
    }
    if (c->vbus_ai >= 0 && c->adc_range_V * c->vbus_V_per_V < c->supply_V) {
        (void)snprintf(why, sizeof why, "the A/D range %.4g V through the divider holds %.4g V, less than the %.4g V supply",
                       c->adc_range_V, c->adc_range_V * c->vbus_V_per_V, c->supply_V);
        return fail(err, n, "board.vbus_V_per_V", why);
    }
    if (!(c->offset_max_V > 0.0) || c->offset_max_V >= c->adc_range_V)
        return fail(err, n, "board.offset_max_V", "must be > 0 and below the A/D range");
    return true;
}

void board_chain_init(board_chain_t *b, const board_chain_config_t *cfg)
{
    b->cfg = *cfg;
    for (int k = 0; k < BOARD_MAX_PHASES; ++k) b->offset_V[k] = 0.0;
    b->calibrated = false;
}

static double maxdata(int bits) { return (double)((1u << (unsigned)bits) - 1u); }

double board_code_to_volts(uint32_t code, int bits, double range_V)
{
    return -range_V + (double)code * (2.0 * range_V) / maxdata(bits);
}

uint32_t board_volts_to_code(double v, int bits, double range_V)
{
    const double m = maxdata(bits);
    double c = (v + range_V) * m / (2.0 * range_V);
    if (!(c > 0.0)) c = 0.0; /* NaN too */
    if (c > m) c = m;
    return (uint32_t)floor(c + 0.5);
}

double board_current_from_V(const board_chain_t *b, int k, double v_adc)
{
    return (v_adc - b->offset_V[k]) / b->cfg.sensor_V_per_A;
}

double board_vbus_from_V(const board_chain_t *b, double v_adc)
{
    return (b->cfg.vbus_ai < 0) ? b->cfg.supply_V : v_adc * b->cfg.vbus_V_per_V;
}

double board_current_A(const board_chain_t *b, int k, uint32_t code)
{
    return board_current_from_V(b, k, board_code_to_volts(code, b->cfg.adc_bits, b->cfg.adc_range_V));
}

double board_vbus_V(const board_chain_t *b, uint32_t code)
{
    return board_vbus_from_V(b, board_code_to_volts(code, b->cfg.adc_bits, b->cfg.adc_range_V));
}

uint32_t board_voltage_code(const board_chain_t *b, double v, bool *clamped)
{
    return board_volts_to_code(board_dac_V(b, v, clamped), b->cfg.dac_bits, b->cfg.dac_range_V);
}

double board_dac_V(const board_chain_t *b, double v, bool *clamped)
{
    const board_chain_config_t *c = &b->cfg;
    bool cl = false;
    if (!isfinite(v)) {
        v = 0.0;
        cl = true;
    }
    if (v > c->supply_V) { v = c->supply_V; cl = true; }
    if (v < -c->supply_V) { v = -c->supply_V; cl = true; }
    double u = v / c->amplifier_V_per_V;
    if (u > c->dac_range_V) { u = c->dac_range_V; cl = true; }
    if (u < -c->dac_range_V) { u = -c->dac_range_V; cl = true; }
    if (clamped != NULL) *clamped = cl;
    return u;
}

bool board_chain_calibrate(board_chain_t *b, const double *sum_V, int n, char *err, int err_len)
{
    if (n < 1) return fail(err, err_len, "board.calibration_samples", "must be >= 1");
    for (int k = 0; k < b->cfg.n_phases; ++k) {
        const double off = sum_V[k] / (double)n;
        if (!(fabs(off) <= b->cfg.offset_max_V)) {
            char why[160];
            (void)snprintf(why, sizeof why,
                           "phase %c's current sensor reads %.4g V with the outputs at zero, beyond +-%.4g V: "
                           "not starting (a sensor fault, or a current flowing)",
                           'a' + k, off, b->cfg.offset_max_V);
            b->calibrated = false;
            return fail(err, err_len, "board.offset_max_V", why);
        }
        b->offset_V[k] = off;
    }
    b->calibrated = true;
    return true;
}
