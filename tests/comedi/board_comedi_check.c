/*
 * board_comedi_check.c - the Comedi driver of the board backend
 * (hal/backends/board/board_comedi.h) against a real kernel's comedi_test
 * (run in the VM fixture by ctest hal.comedi_roundtrip, label comedi):
 * comedi_test's single-sample analog inputs return what was last written
 * to the analog output of the same channel, so every conversion
 * round-trips through the kernel: 8 channels each way, 16 bits, the +-10 V
 * range found; each value written comes back as the same code and within
 * one step in volts; values beyond the range are clamped to its ends; a
 * missing device and a channel the card lacks are refused with their
 * names. Exit 0 when all hold.
 *   usage: board_comedi_check [/dev/comedi0]
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "board_comedi.h"

static int fails;

static void check(int ok, const char *what)
{
    printf("%s %s\n", ok ? "ok  " : "FAIL", what);
    if (!ok) ++fails;
}

int main(int argc, char **argv)
{
    const char *path = argc > 1 ? argv[1] : "/dev/comedi0";
    int ch[8];
    for (int k = 0; k < 8; ++k) ch[k] = k;
    char err[256] = "";
    board_comedi_t *c = board_comedi_open(path, 10.0, ch, 8, ch, 8, err, sizeof err);
    if (c == NULL) {
        printf("FAIL open %s: %s\n", path, err);
        return 1;
    }
    board_comedi_info_t info;
    board_comedi_info(c, &info);
    printf("card: driver %s, board %s; AI subdevice %d (%d channels, maxdata %u, %.3f..%.3f V, %s); "
           "AO subdevice %d (%d channels, maxdata %u, %.3f..%.3f V, %s)\n",
           info.driver, info.board, info.ai_subdevice, info.ai_channels, info.ai_maxdata, info.ai_min_V, info.ai_max_V,
           info.ai_calibrated ? "calibration" : "range table", info.ao_subdevice, info.ao_channels, info.ao_maxdata,
           info.ao_min_V, info.ao_max_V, info.ao_calibrated ? "calibration" : "range table");
    check(info.ai_channels >= 8 && info.ao_channels >= 8, "8 channels each way");
    check(info.ai_maxdata == 65535u && info.ao_maxdata == 65535u, "16-bit converters");
    check(fabs(info.ai_min_V + 10.0) < 1e-6 && fabs(info.ai_max_V - 10.0) < 1e-6 && fabs(info.ao_max_V - 10.0) < 1e-6,
          "the +-10 V range selected both ways");
    const double step = 20.0 / 65535.0;
    const double values[] = {-10.0, -7.5, -0.001, 0.0, 0.00015, 3.3, 9.9999, 12.0, -12.0};
    int n = 0, same_code = 0, within = 0;
    double worst = 0.0;
    for (int k = 0; k < 8; ++k) {
        for (size_t j = 0; j < sizeof values / sizeof values[0]; ++j) {
            uint32_t cw = 0, cr = 0;
            double vr = 0.0;
            if (!board_comedi_write(c, k, values[j], &cw) || !board_comedi_read(c, k, &vr, &cr)) {
                printf("FAIL channel %d: %s\n", k, board_comedi_error(c));
                ++fails;
                continue;
            }
            const double want = values[j] > 10.0 ? 10.0 : (values[j] < -10.0 ? -10.0 : values[j]);
            ++n;
            same_code += cw == cr;
            within += fabs(vr - want) <= step;
            worst = fmax(worst, fabs(vr - want));
            if (values[j] > 10.0) check(cw == 65535u, "12 V written as the top code 65535 (clamped)");
            if (values[j] < -10.0) check(cw == 0u, "-12 V written as code 0 (clamped)");
        }
    }
    char line[160];
    snprintf(line, sizeof line, "%d conversions through the kernel: %d the same code back, %d within one step "
                                "(%.3g V; worst %.3g V)", n, same_code, within, step, worst);
    check(n == 72 && same_code == n && within == n, line);
    board_comedi_close(c);
    /* refusals, named */
    err[0] = '\0';
    board_comedi_t *bad = board_comedi_open("/dev/comedi_none", 10.0, ch, 1, ch, 1, err, sizeof err);
    check(bad == NULL && strstr(err, "/dev/comedi_none: cannot open") != NULL, err);
    const int far[1] = {99};
    err[0] = '\0';
    bad = board_comedi_open(path, 10.0, far, 1, ch, 1, err, sizeof err);
    check(bad == NULL && strstr(err, "A/D channel 99 is not one of the card's") != NULL, err);
    printf("board_comedi_check: %s\n", fails ? "FAILED" : "all checks passed");
    return fails ? 1 : 0;
}
