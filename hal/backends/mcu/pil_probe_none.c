/*
 * pil_probe_none.c - the PIL probe of a drive that has none of its own
 * (pil_probe.h): nothing to add to the generic measurements.
 */
#include "pil_probe.h"

void pil_probe_header(const void *cfg) { (void)cfg; }

void pil_probe_before(const void *self, const void *cfg, const hal_sample_t *in, uint32_t k)
{
    (void)self;
    (void)cfg;
    (void)in;
    (void)k;
}

void pil_probe_after(const void *self, const void *cfg, const hal_sample_t *in, const hal_command_t *out, uint32_t k)
{
    (void)self;
    (void)cfg;
    (void)in;
    (void)out;
    (void)k;
}

bool pil_probe_report(void) { return true; }
