/*
 * flash_if.h - the flash the configuration store (config/config_store.h)
 * writes to, as a table of three operations over a driver's own context:
 * erase a sector (every bit back to 1), program words into a sector (a
 * word's bits can only go from 1 to 0 until the next erase, NOR flash's
 * rule), and read in place (each sector is mapped at a base address the
 * store reads like memory). The sectors are the store's: it owns them
 * whole and never asks for any other. A driver may refuse an operation
 * (the STM32F405's while the bridge is enabled: an erase stalls every read
 * of the flash, the control interrupt's included, hal/backends/stm32f405/
 * flash.h) or fail it (an error flag, a wait that did not end); its error
 * text then says which. The host tests give the store a simulated flash
 * that can stop at any point of an operation (tests/firmware/sim_flash.h).
 * Nothing allocates; the store keeps no pointer into the driver beyond
 * this table.
 */
#ifndef CONFIG_FLASH_IF_H
#define CONFIG_FLASH_IF_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The store's sectors: two, written in turn (ping-pong). */
#define FLASH_IF_SECTORS 2u

/* The word every bit of an erased word reads as. */
#define FLASH_IF_ERASED 0xFFFFFFFFu

/* What an operation did. */
typedef enum {
    FLASH_IF_OK = 0,      /* done (the caller still reads back what it wrote) */
    FLASH_IF_REFUSED = 1, /* not started, the flash unchanged: not allowed now (the bridge is enabled) */
    FLASH_IF_FAILED = 2   /* started and failed, or a wait did not end: the sector's content unknown */
} flash_if_result_t;

typedef struct flash_if {
    void *ctx;             /* the driver's state, handed to every operation */
    uint32_t sector_words; /* the words of each sector (the F405's sectors 1 and 2: 4096) */
    /* each sector read in place: sector_words words at base[s], 4-byte aligned */
    const uint32_t *base[FLASH_IF_SECTORS];
    /* every word of sector s to FLASH_IF_ERASED */
    flash_if_result_t (*erase)(void *ctx, uint32_t sector);
    /* words[0..n) into sector s from word offset: each target word erased
     * before (the store checks it), so only 1 -> 0 bit changes are asked */
    flash_if_result_t (*program)(void *ctx, uint32_t sector, uint32_t offset, const uint32_t *words, uint32_t n);
    /* the last failure or refusal in a few words, never NULL ("" if none) */
    const char *(*error)(void *ctx);
} flash_if_t;

#ifdef __cplusplus
}
#endif

#endif /* CONFIG_FLASH_IF_H */
