/*
 * registry.h - the drives this firmware holds. A drive is registered by
 * its header's include here, one member in each storage union below and
 * its line in drive_registry (registry.c), nothing else; its folder
 * (drives/<name>/) is compiled by the glob of firmware/CMakeLists.txt. Programs find a drive here by name
 * (drive_find) and hold it as a drive_t (drives/drive.h); none names a
 * drive itself. Every build compiles every registered drive (there is no
 * option to leave one out); a bare-metal image runs the one drive chosen
 * when it is configured (CMake MC_DRIVE, checked against this registry by
 * cmake/mc_drive.cmake), never by editing a program. Both bare-metal
 * images (the PIL image, hal/backends/mcu/pil_drive.h.in; the STM32F405
 * image, app_drive.c) bind that drive's operations directly rather than
 * through drive_find, so the linker's --gc-sections drops the others.
 */
#ifndef DRIVES_REGISTRY_H
#define DRIVES_REGISTRY_H

#include <stddef.h>

#include "drives/drive.h"
#include "drives/paper000/paper000_drive.h"
#include "drives/paper001/paper001_drive.h"
#include "drives/paper002/paper002_drive.h"
#include "drives/sensored_foc/sensored_foc_drive.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Static storage for any registered drive: an image holds one of these
 * and points drive_t.self at it. */
typedef union {
    paper000_drive_t paper000;
    paper001_drive_t paper001;
    paper002_drive_t paper002;
    sensored_foc_drive_t sensored_foc;
} drive_storage_t;

/* Static storage for any registered drive's configuration. */
typedef union {
    paper000_config_t paper000;
    paper001_config_t paper001;
    paper002_config_t paper002;
    sensored_foc_config_t sensored_foc;
} drive_config_storage_t;

/* The registered drives, in the order of their DBC DriveKind (tools/can/drive.dbc). */
extern const drive_ops_t *const drive_registry[];
extern const size_t drive_registry_count;

/* The drive named name ("paper000"), or NULL. */
const drive_ops_t *drive_find(const char *name);

/* drive_t over storage for ops: false (d untouched) if ops is NULL or its
 * state does not fit drive_storage_t. */
bool drive_bind(drive_t *d, const drive_ops_t *ops, drive_storage_t *storage);

#ifdef __cplusplus
}
#endif

#endif /* DRIVES_REGISTRY_H */
