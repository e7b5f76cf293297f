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

#include "estimators/encoder_angle.h"
#include "estimators/estimator.h"
#include "estimators/flux_angle.h"
#include "estimators/hfi_angle.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Static storage for any registered estimator. */
typedef union {
    encoder_angle_t encoder;
    flux_angle_t flux;
    hfi_angle_t hfi;
} estimator_storage_t;

extern const estimator_ops_t *const estimator_registry[];
extern const size_t estimator_registry_count;

/* The estimator of that family and number whose state fits
 * estimator_storage_t, or NULL. */
const estimator_ops_t *estimator_find(estimator_family_t family, uint32_t id);

#ifdef __cplusplus
}
#endif

#endif /* ESTIMATORS_ESTIMATOR_REGISTRY_H */
