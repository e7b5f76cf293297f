/* Every drive's design ops by name (design/ops/drive_design_ops.h), for the
 * host's programs; an image takes its own drive's ops by symbol instead,
 * so that it links that drive's design alone. A drive adds its line. */
#include <string.h>

#include "design/ops/drive_design_ops.h"

extern const drive_design_ops_t paper000_design_ops;
extern const drive_design_ops_t paper001_design_ops;
extern const drive_design_ops_t paper002_design_ops;
extern const drive_design_ops_t sensored_foc_design_ops;

static const drive_design_ops_t *const all_designs[] = {
    &paper000_design_ops,
    &paper001_design_ops,
    &paper002_design_ops,
    &sensored_foc_design_ops,
};

const drive_design_ops_t *drive_design_ops_find(const char *name)
{
    for (size_t k = 0; k < sizeof all_designs / sizeof all_designs[0]; ++k) {
        if (strcmp(all_designs[k]->name, name) == 0) return all_designs[k];
    }
    return NULL;
}
