/*
 * pil_vectors.h - what a generated PIL vector file (tools/bench/pil_gen.cpp)
 * defines, for any drive of the registry: the drive's configuration as raw
 * words (loaded into a drive_config_storage_t, drives/registry.h) and, per
 * recorded period, the fields of the hal_sample_t the drive got and of the
 * hal_command_t it returned (hal/hal_types.h), as raw 32-bit words.
 *
 * A field that has the same value in every period is stored once
 * (pil_in_const / pil_out_const); the others are the columns of pil_rows,
 * in the order of the PIL_IN_* then PIL_OUT_* indices below, inputs first
 * (pil_in_varying / pil_out_varying: bit k set = field k is a column). So a
 * two-phase drive's rows hold i_a, i_b, v_a, v_b and a three-phase drive's
 * i_a, i_b, i_c (and v_bus, the angle if they vary), v_a, v_b, v_c, and the
 * image rebuilds every field whichever way it was stored. The sample's tick
 * is the period's index (pil_gen refuses a recording where it is not).
 * Beside them, the drive's signals after each step as one hash a period
 * (pil_signal_hash).
 */
#ifndef MCU_PIL_VECTORS_H
#define MCU_PIL_VECTORS_H

#include <stdint.h>

/* the recorded hal_sample_t fields, one word each (mc_t bits or integers) */
enum {
    PIL_IN_I_A = 0,   /* i_A[0] */
    PIL_IN_I_B = 1,   /* i_A[1] */
    PIL_IN_I_C = 2,   /* i_A[2] */
    PIL_IN_V_BUS = 3, /* v_bus_V */
    PIL_IN_ANGLE = 4, /* angle_rad */
    PIL_IN_META = 5,  /* n_phases | has_angle << 8 */
    PIL_IN_STATUS = 6,/* status */
    PIL_IN_FIELDS = 7
};
/* the recorded hal_command_t fields */
enum {
    PIL_OUT_V_A = 0,  /* v_V[0] */
    PIL_OUT_V_B = 1,  /* v_V[1] */
    PIL_OUT_V_C = 2,  /* v_V[2] */
    PIL_OUT_META = 3, /* n_phases */
    PIL_OUT_FIELDS = 4
};
#define PIL_META_HAS_ANGLE (1u << 8)

extern const char pil_source[];          /* scenario, drive, numeric type, periods */
extern const char pil_drive[];           /* the registry name the vectors were recorded from */
extern const uint32_t pil_control_hz;    /* the control rate of the recording (1 / Ts) */
extern const uint32_t pil_cfg_words[];   /* the drive's configuration, raw */
extern const uint32_t pil_cfg_bytes;     /* its size on the host (the drive's config_bytes) */
extern const uint32_t pil_n;             /* periods */
extern const uint32_t pil_in_varying, pil_out_varying; /* bit k: field k is a column of pil_rows */
extern const uint32_t pil_in_const[PIL_IN_FIELDS];     /* the value of each field that is not */
extern const uint32_t pil_out_const[PIL_OUT_FIELDS];
extern const uint32_t pil_row_words;     /* columns of pil_rows: popcount of both masks */
extern const uint32_t pil_rows[];        /* pil_n rows of pil_row_words words */

/* The drive's signals (drives/drive.h: signals, read_signals) after each
 * recorded step, the columns of its list: their count as recorded, and
 * per period one hash of their values' words (pil_signal_hash_of), which
 * the image compares with its own after the same step. */
extern const uint32_t pil_signal_count;
extern const uint32_t pil_signal_hash[]; /* pil_n hashes */

/* FNV-1a (32 bits) over the n words, each little-endian: the same on the
 * host and the target. */
static inline uint32_t pil_signal_hash_of(const uint32_t *w, uint32_t n)
{
    uint32_t h = 2166136261u;
    for (uint32_t k = 0; k < n; ++k) {
        for (uint32_t b = 0; b < 4u; ++b) {
            h ^= (w[k] >> (8u * b)) & 0xFFu;
            h *= 16777619u;
        }
    }
    return h;
}

#endif
