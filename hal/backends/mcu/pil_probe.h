/*
 * pil_probe.h - a drive's own measurements in the PIL image (pil_image.c),
 * beside the generic ones (the whole step, the CAN node, the state, the
 * stack): e.g. the parts of its step replayed on copies of their states.
 * The image calls these hooks for whichever drive it runs; the build
 * (CMakeLists.txt) links the drive's probe, tools/bench/pil_probes/<drive>_probe.c,
 * when there is one, else pil_probe_none.c (no hooks do anything). A probe
 * runs outside the timed step and may not change the drive's state; it
 * prints its own lines (tools/bench/pil.py reads them per drive).
 */
#ifndef PIL_PROBE_H
#define PIL_PROBE_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal_types.h"

/* after the first "PIL source=..." keys: its own " key=value" pairs; cfg is
 * the drive's configuration as the image loaded it */
void pil_probe_header(const void *cfg);
/* before the timed step of period k: self is the drive's state */
void pil_probe_before(const void *self, const void *cfg, const hal_sample_t *in, uint32_t k);
/* after it: the sample and the command of the step */
void pil_probe_after(const void *self, const void *cfg, const hal_sample_t *in, const hal_command_t *out,
                     uint32_t k);
/* at the end, on the last "PIL ..." line: its own keys; false when a check
 * of its own failed (the image then fails) */
bool pil_probe_report(void);

#endif /* PIL_PROBE_H */
