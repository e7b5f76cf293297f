/* estimator_registry.c - see estimator_registry.h. */
#include "estimators/estimator_registry.h"

const estimator_ops_t *const estimator_registry[] = {
    &encoder_angle_ops, &flux_angle_ops, &hfi_angle_ops, &flux_speed_ops, &emf_speed_ops,
};
const size_t estimator_registry_count = sizeof(estimator_registry) / sizeof(estimator_registry[0]);

const estimator_ops_t *estimator_find(estimator_family_t family, uint32_t id)
{
    for (size_t k = 0; k < estimator_registry_count; ++k) {
        const estimator_ops_t *e = estimator_registry[k];
        if (e->family == family && e->id == id && e->state_bytes <= sizeof(estimator_storage_t)) {
            return e;
        }
    }
    return 0;
}
