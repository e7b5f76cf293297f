/* pil_vectors.h - what a generated PIL vector file (tools/bench/pil_gen.cpp) defines. */
#ifndef MCU_PIL_VECTORS_H
#define MCU_PIL_VECTORS_H

#include <stdint.h>

/* words per period of the paper-001 vectors (mc_pil_gen --drive paper001) */
#define PIL_P001_IO_WORDS 7

extern const char pil_source[];
extern const uint32_t pil_cfg_words[];
extern const uint32_t pil_n;
#if defined(MC_PIL_DRIVE_PAPER001) && MC_PIL_DRIVE_PAPER001
/* paper001_drive_t (pil_paper001_main.c): i_a, i_b, i_c, v_bus, v_a, v_b, v_c
 * as raw mc_t bits; every sample has n_phases = pil_n_phases */
extern const uint32_t pil_n_phases;
extern const uint32_t pil_io[][PIL_P001_IO_WORDS];
#else
extern const uint32_t pil_io[][4]; /* paper000_drive_t (pil_main.c): i_a, i_b, v_a, v_b as raw mc_t bits */
#endif

#endif
