/* paper000's design as an image runs it (design/ops/drive_design_ops.h). */
#include "design/paper000_design.h"
#include "design/ops/drive_design_ops.h"
#include "drives/paper000/generated/paper000_params.h"

static void defaults(void *input) { drive_design_defaults((drive_design_input_t *)input); }

static bool design(const void *input, void *cfg, char *err, size_t err_len)
{
    return drive_design((const drive_design_input_t *)input, (paper000_config_t *)cfg, err, err_len);
}

const drive_design_ops_t paper000_design_ops = {
    .name = "paper000",
    .params = &paper000_params,
    .input_bytes = (uint32_t)sizeof(drive_design_input_t),
    .config_bytes = (uint32_t)sizeof(paper000_config_t),
    .defaults = defaults,
    .design = design,
};
