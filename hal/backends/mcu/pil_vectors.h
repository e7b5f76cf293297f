/* pil_vectors.h - what a generated PIL vector file (tools/bench/pil_gen.cpp) defines. */
#ifndef MCU_PIL_VECTORS_H
#define MCU_PIL_VECTORS_H

#include <stdint.h>

extern const char pil_source[];
extern const uint32_t pil_cfg_words[];
extern const uint32_t pil_n;
extern const uint32_t pil_io[][4]; /* i_a, i_b, v_a, v_b as raw mc_t bits */

#endif
