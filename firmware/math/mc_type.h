/*
 * mc_type.h - the firmware's numeric type alone: mc_t and MC_FIXED, with
 * none of its operations. float32 by default; with MC_FIXED_POINT=1 a
 * Q14.17 value in an int32_t (mc_num_fixed.h documents the format), and in
 * the strict check build (MC_STRICT_TYPES=1, C only) that int32_t wrapped
 * in a one-member struct so that no C operator applies to it. Headers that
 * only carry values across an interface (hal/include/hal/hal_types.h)
 * include this; code that computes includes math/mc_num.h, which includes
 * it too.
 */
#ifndef MC_TYPE_H
#define MC_TYPE_H

#include <stdint.h>

#if defined(MC_FIXED_POINT) && MC_FIXED_POINT
#if defined(MC_STRICT_TYPES) && MC_STRICT_TYPES
typedef struct {
    int32_t raw;
} mc_t;
#else
typedef int32_t mc_t;
#endif
#define MC_FIXED 1
#else
typedef float mc_t;
#define MC_FIXED 0
#endif

#endif /* MC_TYPE_H */
