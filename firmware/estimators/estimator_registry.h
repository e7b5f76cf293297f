/*
 * estimator_registry.h - the estimators this firmware holds
 * (estimators/estimator.h). An estimator is registered by its header's
 * include here, one member of the storage union and its line in
 * estimator_registry (estimator_registry.c), nothing else; a drive finds
 * the one its configuration names by family and number (estimator_find)
 * and keeps its state in an estimator_storage_t of its own state.
 */
#ifndef ESTIMATORS_ESTIMATOR_REGISTRY_H
#define ESTIMATORS_ESTIMATOR_REGISTRY_H

#include <stddef.h>

#include "estimators/emf_speed.h"
#include "estimators/encoder_angle.h"
#include "estimators/estimator.h"
#include "estimators/flux_angle.h"
#include "estimators/flux_speed.h"
#include "estimators/hfi_angle.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Static storage for any registered estimator. */
typedef union {
    encoder_angle_t encoder;
    flux_angle_t flux;
    hfi_angle_t hfi;
    flux_speed_t flux_speed;
    emf_speed_t emf_speed;
} estimator_storage_t;

/* The open-start family's members (estimators/open_start.h), one line
 * each: X(prefix), where the header defines prefix_ops and the sample's
 * operations in line (prefix_measure_op, prefix_open_loop_op,
 * prefix_hold_op). A drive of the family
 * instantiates its step once per line, so that the sample runs the
 * estimator without a call (paper001_drive.c); its configuration's number
 * picks the instantiation at init. */
#define OPEN_START_ESTIMATORS(X) X(flux_speed) X(emf_speed)

extern const estimator_ops_t *const estimator_registry[];
extern const size_t estimator_registry_count;

/* The estimator of that family and number whose state fits
 * estimator_storage_t, or NULL. */
const estimator_ops_t *estimator_find(estimator_family_t family, uint32_t id);

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_ESTIMATOR_REGISTRY_H */
