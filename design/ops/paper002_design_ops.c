/* paper002's design as an image runs it (design/ops/drive_design_ops.h). */
#include "design/paper002_design.h"
#include "design/ops/drive_design_ops.h"
#include "drives/paper002/generated/paper002_params.h"

static void defaults(void *input) { p002_design_defaults((p002_design_input_t *)input); }

static bool design(const void *input, void *cfg, char *err, size_t err_len)
{
    return p002_design((const p002_design_input_t *)input, (paper002_config_t *)cfg, err, err_len);
}

const drive_design_ops_t paper002_design_ops = {
    .name = "paper002",
    .params = &paper002_params,
    .input_bytes = (uint32_t)sizeof(p002_design_input_t),
    .config_bytes = (uint32_t)sizeof(paper002_config_t),
    .defaults = defaults,
    .design = design,
};
