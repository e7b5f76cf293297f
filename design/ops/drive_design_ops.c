#include "design/ops/drive_design_ops.h"

#include <string.h>

bool drive_design_defaults_input(const drive_design_ops_t *d, void *input, param_error_t *err)
{
    memset(input, 0, d->input_bytes);
    d->defaults(input);
    return params_set_defaults(d->params, input, err);
}
