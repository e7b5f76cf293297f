#include "board_comedi.h"

#include <comedilib.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    int range;                 /* range index */
    comedi_range rng;          /* its limits */
    lsampl_t maxdata;
    bool has_poly;
    comedi_polynomial_t poly;  /* the calibration's conversion */
} channel_t;

struct board_comedi {
    comedi_t *dev;
    int ai_subd, ao_subd;
    channel_t ai[BOARD_COMEDI_MAX_CH], ao[BOARD_COMEDI_MAX_CH];
    bool ai_used[BOARD_COMEDI_MAX_CH], ao_used[BOARD_COMEDI_MAX_CH];
    comedi_calibration_t *softcal;
    char err[256];
};

static void set_err(char *err, int n, const char *fmt, const char *a, int b, const char *c)
{
    if (err != NULL && n > 0) (void)snprintf(err, (size_t)n, fmt, a, b, c);
}

/* the range of a channel that holds +-range_V and its conversion */
static bool setup_channel(board_comedi_t *c, int subd, int ch, double range_V, enum comedi_conversion_direction dir_in,
                          channel_t *out)
{
    const int r = comedi_find_range(c->dev, (unsigned)subd, (unsigned)ch, UNIT_volt, -range_V, range_V);
    if (r < 0) return false;
    const comedi_range *rng = comedi_get_range(c->dev, (unsigned)subd, (unsigned)ch, (unsigned)r);
    if (rng == NULL) return false;
    out->range = r;
    out->rng = *rng;
    out->maxdata = comedi_get_maxdata(c->dev, (unsigned)subd, (unsigned)ch);
    out->has_poly = false;
    const int flags = comedi_get_subdevice_flags(c->dev, (unsigned)subd);
    if (flags >= 0 && (flags & SDF_SOFT_CALIBRATED) != 0) {
        if (c->softcal != NULL &&
            comedi_get_softcal_converter((unsigned)subd, (unsigned)ch, (unsigned)r, dir_in, c->softcal, &out->poly) == 0) {
            out->has_poly = true;
        }
    } else if (comedi_get_hardcal_converter(c->dev, (unsigned)subd, (unsigned)ch, (unsigned)r, dir_in, &out->poly) == 0) {
        out->has_poly = true;
    }
    return true;
}

board_comedi_t *board_comedi_open(const char *path, double range_V, const int *ai, int n_ai, const int *ao, int n_ao,
                                  char *err, int err_len)
{
    comedi_set_global_oor_behavior(COMEDI_OOR_NUMBER);
    comedi_t *dev = comedi_open(path);
    if (dev == NULL) {
        set_err(err, err_len, "%s: cannot open the Comedi device (%d: %s)", path, comedi_errno(),
                comedi_strerror(comedi_errno()));
        return NULL;
    }
    board_comedi_t *c = (board_comedi_t *)calloc(1, sizeof *c);
    if (c == NULL) {
        comedi_close(dev);
        set_err(err, err_len, "%s: out of memory%.0d%s", path, 0, "");
        return NULL;
    }
    c->dev = dev;
    c->ai_subd = comedi_find_subdevice_by_type(dev, COMEDI_SUBD_AI, 0);
    c->ao_subd = comedi_find_subdevice_by_type(dev, COMEDI_SUBD_AO, 0);
    if (c->ai_subd < 0 || c->ao_subd < 0) {
        set_err(err, err_len, "%s: the card has no%.0d %s subdevice", path, 0,
                c->ai_subd < 0 ? "analog input" : "analog output");
        board_comedi_close(c);
        return NULL;
    }
    if ((comedi_get_subdevice_flags(dev, (unsigned)c->ai_subd) & SDF_SOFT_CALIBRATED) != 0 ||
        (comedi_get_subdevice_flags(dev, (unsigned)c->ao_subd) & SDF_SOFT_CALIBRATED) != 0) {
        char *cal = comedi_get_default_calibration_path(dev);
        if (cal != NULL) {
            c->softcal = comedi_parse_calibration_file(cal);
            free(cal);
        }
    }
    const int n_ai_card = comedi_get_n_channels(dev, (unsigned)c->ai_subd);
    const int n_ao_card = comedi_get_n_channels(dev, (unsigned)c->ao_subd);
    for (int k = 0; k < n_ai; ++k) {
        if (ai[k] < 0 || ai[k] >= n_ai_card || ai[k] >= BOARD_COMEDI_MAX_CH) {
            set_err(err, err_len, "%s: A/D channel %d is not one of the card's%s", path, ai[k], " analog inputs");
            board_comedi_close(c);
            return NULL;
        }
        if (!setup_channel(c, c->ai_subd, ai[k], range_V, COMEDI_TO_PHYSICAL, &c->ai[ai[k]])) {
            set_err(err, err_len, "%s: A/D channel %d has no range holding the board's%s", path, ai[k], " +-range");
            board_comedi_close(c);
            return NULL;
        }
        c->ai_used[ai[k]] = true;
    }
    for (int k = 0; k < n_ao; ++k) {
        if (ao[k] < 0 || ao[k] >= n_ao_card || ao[k] >= BOARD_COMEDI_MAX_CH) {
            set_err(err, err_len, "%s: D/A channel %d is not one of the card's%s", path, ao[k], " analog outputs");
            board_comedi_close(c);
            return NULL;
        }
        if (!setup_channel(c, c->ao_subd, ao[k], range_V, COMEDI_FROM_PHYSICAL, &c->ao[ao[k]])) {
            set_err(err, err_len, "%s: D/A channel %d has no range holding the board's%s", path, ao[k], " +-range");
            board_comedi_close(c);
            return NULL;
        }
        c->ao_used[ao[k]] = true;
    }
    return c;
}

void board_comedi_close(board_comedi_t *c)
{
    if (c == NULL) return;
    if (c->softcal != NULL) comedi_cleanup_calibration(c->softcal);
    if (c->dev != NULL) comedi_close(c->dev);
    free(c);
}

bool board_comedi_read(board_comedi_t *c, int ch, double *v, uint32_t *code)
{
    if (ch < 0 || ch >= BOARD_COMEDI_MAX_CH || !c->ai_used[ch]) {
        (void)snprintf(c->err, sizeof c->err, "A/D channel %d was not opened", ch);
        return false;
    }
    const channel_t *k = &c->ai[ch];
    lsampl_t d = 0;
    if (comedi_data_read(c->dev, (unsigned)c->ai_subd, (unsigned)ch, (unsigned)k->range, AREF_GROUND, &d) < 0) {
        (void)snprintf(c->err, sizeof c->err, "A/D channel %d: %s", ch, comedi_strerror(comedi_errno()));
        return false;
    }
    comedi_range rng = k->rng;
    *v = k->has_poly ? comedi_to_physical(d, &k->poly) : comedi_to_phys(d, &rng, k->maxdata);
    if (code != NULL) *code = d;
    return true;
}

bool board_comedi_write(board_comedi_t *c, int ch, double v, uint32_t *code)
{
    if (ch < 0 || ch >= BOARD_COMEDI_MAX_CH || !c->ao_used[ch]) {
        (void)snprintf(c->err, sizeof c->err, "D/A channel %d was not opened", ch);
        return false;
    }
    const channel_t *k = &c->ao[ch];
    /* clamp at the converter's range before conversion */
    if (!(v == v)) v = 0.0;
    if (v > k->rng.max) v = k->rng.max;
    if (v < k->rng.min) v = k->rng.min;
    comedi_range rng = k->rng;
    lsampl_t d = k->has_poly ? comedi_from_physical(v, &k->poly) : comedi_from_phys(v, &rng, k->maxdata);
    if (d > k->maxdata) d = k->maxdata;
    if (comedi_data_write(c->dev, (unsigned)c->ao_subd, (unsigned)ch, (unsigned)k->range, AREF_GROUND, d) < 0) {
        (void)snprintf(c->err, sizeof c->err, "D/A channel %d: %s", ch, comedi_strerror(comedi_errno()));
        return false;
    }
    if (code != NULL) *code = d;
    return true;
}

void board_comedi_info(const board_comedi_t *c, board_comedi_info_t *info)
{
    memset(info, 0, sizeof *info);
    info->ai_subdevice = c->ai_subd;
    info->ao_subdevice = c->ao_subd;
    info->ai_channels = comedi_get_n_channels(c->dev, (unsigned)c->ai_subd);
    info->ao_channels = comedi_get_n_channels(c->dev, (unsigned)c->ao_subd);
    for (int ch = 0; ch < BOARD_COMEDI_MAX_CH; ++ch) {
        if (c->ai_used[ch] && info->ai_maxdata == 0u) {
            info->ai_maxdata = c->ai[ch].maxdata;
            info->ai_min_V = c->ai[ch].rng.min;
            info->ai_max_V = c->ai[ch].rng.max;
            info->ai_calibrated = c->ai[ch].has_poly;
        }
        if (c->ao_used[ch] && info->ao_maxdata == 0u) {
            info->ao_maxdata = c->ao[ch].maxdata;
            info->ao_min_V = c->ao[ch].rng.min;
            info->ao_max_V = c->ao[ch].rng.max;
            info->ao_calibrated = c->ao[ch].has_poly;
        }
    }
    const char *d = comedi_get_driver_name(c->dev);
    const char *b = comedi_get_board_name(c->dev);
    (void)snprintf(info->driver, sizeof info->driver, "%s", d != NULL ? d : "?");
    (void)snprintf(info->board, sizeof info->board, "%s", b != NULL ? b : "?");
}

const char *board_comedi_error(const board_comedi_t *c) { return c->err; }
