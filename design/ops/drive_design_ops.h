/*
 * drive_design_ops.h - a drive's design as an image runs it: its user
 * parameters' table over its design input (config/params.h), the input's
 * and the configuration's sizes, the design's own defaults for the fields
 * no parameter sets, and the design itself (design/<drive>_design.h, the
 * host's code, in double). An image that designs on the board (a float
 * one: hal/backends/stm32f405) takes its drive's <drive>_design_ops by
 * name (MC_DESIGN_OPS), so only that drive's design is linked. One file
 * per drive in design/ops/. No allocation; the caller owns the input and
 * the configuration.
 */
#ifndef DESIGN_OPS_DRIVE_DESIGN_OPS_H
#define DESIGN_OPS_DRIVE_DESIGN_OPS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "config/params.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    const char *name;            /* the drive's registry name (drives/registry.h) */
    const param_table_t *params; /* its parameters over the design input */
    uint32_t input_bytes;        /* sizeof the design input */
    uint32_t config_bytes;       /* sizeof the drive's configuration (drive_ops_t.config_bytes) */
    /* the design's defaults into input (the fields no parameter sets) */
    void (*defaults)(void *input);
    /* the configuration from input; false with a reason in err */
    bool (*design)(const void *input, void *cfg, char *err, size_t err_len);
} drive_design_ops_t;

/* The design input of the table's defaults: the design's own defaults,
 * then every parameter's (params_set_defaults). */
bool drive_design_defaults_input(const drive_design_ops_t *d, void *input, param_error_t *err);

/* The ops of the drive of that name (design/ops/design_ops_registry.c),
 * or NULL: for the host's programs. */
const drive_design_ops_t *drive_design_ops_find(const char *name);

/* Each drive's are <drive>_design_ops (design/ops/<drive>_design_ops.c);
 * an image declares its own (MC_DESIGN_OPS), the registry all of them. */

#ifdef __cplusplus
}
#endif

#endif /* DESIGN_OPS_DRIVE_DESIGN_OPS_H */
