/* paper001's design as an image runs it (design/ops/drive_design_ops.h). */
#include "design/paper001_design.h"
#include "design/ops/drive_design_ops.h"
#include "drives/paper001/generated/paper001_params.h"

static void defaults(void *input) { p001_design_defaults((p001_design_input_t *)input); }

static bool design(const void *input, void *cfg, char *err, size_t err_len)
{
    p001_design_report_t rep;
    return p001_design((const p001_design_input_t *)input, (paper001_config_t *)cfg, &rep, err, err_len);
}

const drive_design_ops_t paper001_design_ops = {
    .name = "paper001",
    .params = &paper001_params,
    .input_bytes = (uint32_t)sizeof(p001_design_input_t),
    .config_bytes = (uint32_t)sizeof(paper001_config_t),
    .defaults = defaults,
    .design = design,
};
