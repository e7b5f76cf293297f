/*
 * pil_replay.h - the recorded periods of a PIL vector file (pil_vectors.h)
 * back as the HAL's structs (hal/hal_types.h): the sample of period k as a
 * backend hands it to its control callback, and the check of a command
 * against the one the host build returned, every field bit for bit. Used
 * by the PIL image (pil_image.c) and the STM32F405 QEMU image
 * (stm32f405/main_qemu.c); any drive.
 */
#ifndef PIL_REPLAY_H
#define PIL_REPLAY_H

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "hal/hal_types.h"
#include "pil_vectors.h"

/* the n fields of one side of period k: a column of the row where its
 * bit of varying is set, else its constant */
static inline void pil_fields(uint32_t k, uint32_t first_col, uint32_t varying, const uint32_t *constant, uint32_t n,
                              uint32_t *f)
{
    const uint32_t *row = &pil_rows[k * pil_row_words];
    uint32_t col = first_col;
    for (uint32_t j = 0; j < n; ++j) {
        f[j] = ((varying >> j) & 1u) ? row[col++] : constant[j];
    }
}

static inline uint32_t pil_popcount(uint32_t m)
{
    uint32_t n = 0u;
    for (; m != 0u; m &= m - 1u) {
        ++n;
    }
    return n;
}

/* the sample of period k (tick = k) */
static inline void pil_sample(uint32_t k, hal_sample_t *in)
{
    uint32_t f[PIL_IN_FIELDS];
    pil_fields(k, 0u, pil_in_varying, pil_in_const, PIL_IN_FIELDS, f);
    memset(in, 0, sizeof *in);
    in->tick = k;
    memcpy(&in->i_A[0], &f[PIL_IN_I_A], sizeof in->i_A[0]);
    memcpy(&in->i_A[1], &f[PIL_IN_I_B], sizeof in->i_A[1]);
    memcpy(&in->i_A[2], &f[PIL_IN_I_C], sizeof in->i_A[2]);
    memcpy(&in->v_bus_V, &f[PIL_IN_V_BUS], sizeof in->v_bus_V);
    memcpy(&in->angle_rad, &f[PIL_IN_ANGLE], sizeof in->angle_rad);
    in->n_phases = (uint8_t)(f[PIL_IN_META] & 0xFFu);
    in->has_angle = (f[PIL_IN_META] & PIL_META_HAS_ANGLE) != 0u;
    in->status = f[PIL_IN_STATUS];
}

/* out equals the command the host returned in period k, bit for bit */
static inline bool pil_command_matches(uint32_t k, const hal_command_t *out)
{
    uint32_t f[PIL_OUT_FIELDS];
    pil_fields(k, pil_popcount(pil_in_varying), pil_out_varying, pil_out_const, PIL_OUT_FIELDS, f);
    uint32_t v[3];
    memcpy(v, out->v_V, sizeof v);
    return v[0] == f[PIL_OUT_V_A] && v[1] == f[PIL_OUT_V_B] && v[2] == f[PIL_OUT_V_C] &&
           (uint32_t)out->n_phases == f[PIL_OUT_META];
}

#endif /* PIL_REPLAY_H */
