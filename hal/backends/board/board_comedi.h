/*
 * board_comedi.h - a real DAC/ADC card through Comedi (libcomedi, the
 * Linux DAQ standard) for the board backend: opens the device, finds its
 * analog input and output subdevices, checks the channels the board's map
 * uses exist, selects on each the range that holds +-range_V, and converts
 * between the card's codes and volts with the card's own calibration
 * (a software calibration file for cards flagged SDF_SOFT_CALIBRATED, the
 * hardware calibration's polynomial otherwise) or, where the card has
 * none (comedi_test), its range table. Single-sample reads and writes
 * (comedi_data_read/write): one control period's worth at a time.
 * Functions return false and keep an error string naming what failed.
 */
#ifndef BOARD_COMEDI_H
#define BOARD_COMEDI_H

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define BOARD_COMEDI_MAX_CH 32

typedef struct board_comedi board_comedi_t;

/* Opens path (e.g. /dev/comedi0) for the A/D channels ai[0..n_ai-1] and
 * the D/A channels ao[0..n_ao-1], each on a range holding +-range_V.
 * NULL on failure, with why in err. */
board_comedi_t *board_comedi_open(const char *path, double range_V, const int *ai, int n_ai, const int *ao, int n_ao,
                                  char *err, int err_len);
void board_comedi_close(board_comedi_t *c);

/* A/D channel ch in volts (and its code). */
bool board_comedi_read(board_comedi_t *c, int ch, double *v, uint32_t *code);
/* D/A channel ch to v volts, clamped to its range (the code written). */
bool board_comedi_write(board_comedi_t *c, int ch, double v, uint32_t *code);

/* What was found, for reports: subdevices, channel counts, maxdata, the
 * range of a channel, whether a calibration (not the range table)
 * converts. */
typedef struct {
    int ai_subdevice, ao_subdevice;
    int ai_channels, ao_channels;
    uint32_t ai_maxdata, ao_maxdata;
    double ai_min_V, ai_max_V, ao_min_V, ao_max_V;
    bool ai_calibrated, ao_calibrated;
    char driver[32], board[32];
} board_comedi_info_t;
void board_comedi_info(const board_comedi_t *c, board_comedi_info_t *info);

const char *board_comedi_error(const board_comedi_t *c);

#ifdef __cplusplus
}
#endif

#endif /* BOARD_COMEDI_H */
