/*
 * registry.c - the table of registered drives (registry.h) and the few
 * functions every drive shares through the interface (drive.h).
 */
#include "drives/registry.h"

const drive_ops_t *const drive_registry[] = {
    &paper000_drive_ops,
    &paper001_drive_ops,
    &paper002_drive_ops,
    &sensored_foc_drive_ops,
};
const size_t drive_registry_count = sizeof(drive_registry) / sizeof(drive_registry[0]);

static bool drive_name_eq(const char *a, const char *b)
{
    size_t k = 0;
    while (a[k] != '\0' && a[k] == b[k]) {
        ++k;
    }
    return a[k] == b[k];
}

const drive_ops_t *drive_find(const char *name)
{
    if (name == 0) {
        return 0;
    }
    for (size_t k = 0; k < drive_registry_count; ++k) {
        if (drive_name_eq(drive_registry[k]->name, name)) {
            return drive_registry[k];
        }
    }
    return 0;
}

bool drive_bind(drive_t *d, const drive_ops_t *ops, drive_storage_t *storage)
{
    if (ops == 0 || storage == 0 || ops->state_bytes > (uint32_t)sizeof(drive_storage_t)) {
        return false;
    }
    d->ops = ops;
    d->self = storage;
    return true;
}

const char *drive_refusal_name(drive_refusal_t r)
{
    switch (r) {
    case DRIVE_REFUSE_NONE: return "none";
    case DRIVE_REFUSE_UNSUPPORTED: return "unsupported";
    case DRIVE_REFUSE_STATE: return "state";
    case DRIVE_REFUSE_NO_FAULT: return "no fault";
    default: return "unknown";
    }
}
