/* sensored_foc's design as an image runs it (design/ops/drive_design_ops.h). */
#include "design/sensored_foc_design.h"
#include "design/ops/drive_design_ops.h"
#include "drives/sensored_foc/generated/sensored_foc_params.h"

static void defaults(void *input) { sfoc_design_defaults((sfoc_design_input_t *)input); }

static bool design(const void *input, void *cfg, char *err, size_t err_len)
{
    return sfoc_design((const sfoc_design_input_t *)input, (sensored_foc_config_t *)cfg, err, err_len);
}

const drive_design_ops_t sensored_foc_design_ops = {
    .name = "sensored_foc",
    .params = &sensored_foc_params,
    .input_bytes = (uint32_t)sizeof(sfoc_design_input_t),
    .config_bytes = (uint32_t)sizeof(sensored_foc_config_t),
    .defaults = defaults,
    .design = design,
};
