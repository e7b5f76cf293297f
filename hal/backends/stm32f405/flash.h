/*
 * flash.h - the STM32F405's flash interface (RM0090 ch. 3) as the
 * configuration store's flash (firmware/config/flash_if.h): the two 16 KB
 * sectors 1 and 2 (0x08004000, 0x08008000; RM0090 3.3 table 5) that the
 * image leaves free (stm32f405.ld: _config_sector_a, _config_sector_b),
 * erased a sector at a time (SER, SNB, STRT: RM0090 3.6.3) and programmed a
 * word at a time (PG, 32-bit parallelism: PSIZE x32, RM0090 3.6.2, 3.6.4),
 * the control register unlocked by its key sequence before (KEY1, KEY2:
 * RM0090 3.6.1) and locked again after. Every wait on BSY is bounded by a
 * poll count; every error flag of FLASH_SR (OPERR, WRPERR, PGAERR, PGPERR,
 * PGSERR: RM0090 3.9.4) is a failure named by its own code. While a bridge
 * timer's outputs are enabled (MOE of TIM1 or TIM8) every operation is
 * refused before a register is touched: an erase stalls every read of the
 * flash for its whole duration (RM0090 3.6.1: a read while BSY stalls the
 * bus), the control interrupt's code and vectors included, which would
 * leave the bridge on its last duties for a quarter of a second or more.
 * The wait runs from SRAM with interrupts masked and refreshes the
 * watchdog, so a 16 KB erase (DS8626: 500 ms at most) does not reset the
 * chip through its 10 ms watchdog. On the host the register accesses go to
 * a model of the interface (STM32_FLASH_FAKE_IO, tests/hal): QEMU's
 * netduinoplus2 has no flash interface.
 */
#ifndef STM32_FLASH_H
#define STM32_FLASH_H

#include <stdbool.h>
#include <stdint.h>

#include "config/flash_if.h"
#include "stm32f405_regs.h"

/* The store's sectors (RM0090 3.3 table 5: sectors 0-3 16 KB each from
 * 0x08000000). Sectors 1 and 2 rather than two 128 KB sectors at the end:
 * a 16 KB erase takes 250 ms typical, 500 ms at most at x32 against 1 s
 * and 2 s for 128 KB (DS8626 table "Flash memory programming"), and 32 KB
 * is kept from the images instead of 256 KB; the cost is sector 0 holding
 * only the vector table (the images, 52-54 KB on 2026-12-07 against the
 * issue's budget of 128 KB, start again at sector 3). The layout of the
 * VESC firmware, whose EEPROM emulation uses the same two sectors. */
#define STM32_FLASH_SECTOR_A 1u
#define STM32_FLASH_SECTOR_B 2u
#define STM32_FLASH_SECTOR_A_ADDR 0x08004000u
#define STM32_FLASH_SECTOR_B_ADDR 0x08008000u
#define STM32_FLASH_SECTOR_BYTES 16384u
#define STM32_FLASH_SECTOR_WORDS (STM32_FLASH_SECTOR_BYTES / 4u)

/* The bounds of the waits on BSY, in polls. A poll (from SRAM: read
 * FLASH_SR, test, refresh the watchdog, count, branch) takes at least 4
 * cycles, so at 168 MHz at most 42 polls a microsecond: each bound is at
 * least twice the datasheet's longest operation (DS8626, x32 parallelism:
 * a 16 KB sector erase 500 ms, a word 100 us), longer on a slower clock.
 * The wait before an operation (one still running: at most an erase) has
 * the erase's bound. */
#define STM32_FLASH_POLLS_PER_US 42u
#define STM32_FLASH_ERASE_POLLS (STM32_FLASH_POLLS_PER_US * 1000000u) /* >= 1 s */
#define STM32_FLASH_PROGRAM_POLLS (STM32_FLASH_POLLS_PER_US * 200u)   /* >= 200 us */

typedef enum {
    STM32_FLASH_OK = 0,
    STM32_FLASH_BRIDGE_ENABLED = 1,  /* refused: a bridge timer's outputs are on (MOE); nothing touched */
    STM32_FLASH_BAD_ARGS = 2,        /* a sector, offset or word count outside the store's sectors */
    STM32_FLASH_BUSY_TIMEOUT = 3,    /* BSY set before the operation, beyond the erase's bound */
    STM32_FLASH_UNLOCK_FAILED = 4,   /* FLASH_CR still locked after KEY1, KEY2 (a wrong key before: until reset) */
    STM32_FLASH_ERASE_TIMEOUT = 5,   /* BSY still set STM32_FLASH_ERASE_POLLS polls after STRT */
    STM32_FLASH_PROGRAM_TIMEOUT = 6, /* BSY still set STM32_FLASH_PROGRAM_POLLS polls after a word */
    STM32_FLASH_OPERR = 7,           /* FLASH_SR OPERR: operation error */
    STM32_FLASH_WRPERR = 8,          /* FLASH_SR WRPERR: the sector is write-protected (option bytes) */
    STM32_FLASH_PGAERR = 9,          /* FLASH_SR PGAERR: a write across a 128-bit row */
    STM32_FLASH_PGPERR = 10,         /* FLASH_SR PGPERR: access size other than PSIZE's */
    STM32_FLASH_PGSERR = 11          /* FLASH_SR PGSERR: programming sequence error */
} stm32_flash_status_t;

/* What the driver drives: the chip's (stm32_flash_chip) or fakes. */
typedef struct {
    flash_regs_t *regs;
    uint32_t *sector_base[FLASH_IF_SECTORS]; /* each store sector where it is mapped */
    uint8_t sector_number[FLASH_IF_SECTORS]; /* its SNB */
    uint32_t sector_words;
    const tim_regs_t *bridge[2];         /* the bridge timers (NULL: none): MOE set refuses */
    iwdg_regs_t *iwdg;                   /* refreshed at every poll (NULL: none running) */
    uint32_t erase_polls, program_polls; /* the waits' bounds (STM32_FLASH_*_POLLS) */
} stm32_flash_hw_t;

typedef struct {
    stm32_flash_hw_t hw;
    stm32_flash_status_t status; /* the last operation's */
    uint32_t sr;                 /* FLASH_SR when the last failure was found */
    uint32_t erases, words;      /* operations done */
    uint32_t erase_polls_max;    /* the longest waits seen, in polls: how near the bounds */
    uint32_t program_polls_max;
} stm32_flash_t;

/* The chip's: sectors 1 and 2 at the linker script's addresses, the
 * bounds above, the bridge timers and the watchdog given (NULL if none). */
void stm32_flash_chip(stm32_flash_hw_t *hw, const tim_regs_t *tim1, const tim_regs_t *tim8, iwdg_regs_t *iwdg);

void stm32_flash_init(stm32_flash_t *f, const stm32_flash_hw_t *hw);

/* The store's flash over this driver (ctx = f). */
flash_if_t stm32_flash_interface(stm32_flash_t *f);

/* Store sector 0 or 1 erased. */
flash_if_result_t stm32_flash_erase(stm32_flash_t *f, uint32_t sector);

/* words[0..n) programmed from word offset of store sector 0 or 1; stops
 * at the first word that fails. */
flash_if_result_t stm32_flash_program(stm32_flash_t *f, uint32_t sector, uint32_t offset, const uint32_t *words,
                                      uint32_t n);

/* True while a bridge timer's outputs are enabled (what refuses). */
bool stm32_flash_bridge_enabled(const stm32_flash_t *f);

/* A short English text for a status, never NULL. */
const char *stm32_flash_status_text(stm32_flash_status_t s);

#endif /* STM32_FLASH_H */
