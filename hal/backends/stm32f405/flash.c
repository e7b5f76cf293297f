#include "flash.h"

#include <stddef.h>

#include "irq.h"

/* Register accesses: the chip's, or (host tests) a model of the flash
 * interface that answers them (tests/hal/test_stm32_flash.cpp). */
#ifdef STM32_FLASH_FAKE_IO
uint32_t stm32_flash_fake_read(const volatile uint32_t *reg);
void stm32_flash_fake_write(volatile uint32_t *reg, uint32_t v);
#define RD(r) stm32_flash_fake_read(&(r))
#define WR(r, v) stm32_flash_fake_write(&(r), (v))
#else
#define RD(r) (r)
#define WR(r, v) ((r) = (v))
#endif

/* The start and the wait run from SRAM (stm32f405.ld puts .ramfunc in
 * .data, copied at reset; long_call: SRAM is beyond a branch's reach from
 * flash): nothing is read from the flash while it is busy, so the wait
 * does not stall and refreshes the watchdog. */
#if defined(__arm__)
#define FLASH_RAMFUNC __attribute__((section(".ramfunc"), noinline, long_call))
#else
#define FLASH_RAMFUNC __attribute__((noinline))
#endif

/* Stores value at addr (the word to program, or FLASH_CR with STRT), then
 * polls BSY at most polls times, refreshing the watchdog at each: the
 * polls it took (>= 1), 0 if BSY was still set after the last. No call, no
 * constant from the flash. */
static FLASH_RAMFUNC uint32_t start_and_wait(volatile uint32_t *addr, uint32_t value, const volatile uint32_t *sr,
                                             volatile uint32_t *iwdg_kr, uint32_t polls)
{
    WR(*addr, value);
#if defined(__arm__)
    __asm__ volatile("dsb" ::: "memory"); /* the store reaches the interface before BSY is read */
#endif
    for (uint32_t k = 0; k < polls; ++k) {
        if (iwdg_kr != NULL) {
            WR(*iwdg_kr, IWDG_KEY_REFRESH);
        }
        if ((RD(*sr) & FLASH_SR_BSY) == 0u) {
            return k + 1u;
        }
    }
    return 0;
}

/* Waits for BSY to clear, from flash: before an operation, nothing started. */
static bool idle(const stm32_flash_t *f)
{
    for (uint32_t k = 0; k < f->hw.erase_polls; ++k) {
        if ((RD(f->hw.regs->SR) & FLASH_SR_BSY) == 0u) {
            return true;
        }
    }
    return false;
}

const char *stm32_flash_status_text(stm32_flash_status_t s)
{
    switch (s) {
    case STM32_FLASH_OK: return "ok";
    case STM32_FLASH_BRIDGE_ENABLED: return "flash: refused, the bridge is enabled (an erase stalls the control loop)";
    case STM32_FLASH_BAD_ARGS: return "flash: sector, offset or count outside the configuration sectors";
    case STM32_FLASH_BUSY_TIMEOUT: return "flash: BSY set before the operation did not clear";
    case STM32_FLASH_UNLOCK_FAILED: return "flash: FLASH_CR still locked after the key sequence";
    case STM32_FLASH_ERASE_TIMEOUT: return "flash: sector erase did not end (BSY)";
    case STM32_FLASH_PROGRAM_TIMEOUT: return "flash: word program did not end (BSY)";
    case STM32_FLASH_OPERR: return "flash: OPERR, operation error";
    case STM32_FLASH_WRPERR: return "flash: WRPERR, sector write-protected";
    case STM32_FLASH_PGAERR: return "flash: PGAERR, programming alignment error";
    case STM32_FLASH_PGPERR: return "flash: PGPERR, programming parallelism error";
    case STM32_FLASH_PGSERR: return "flash: PGSERR, programming sequence error";
    default: return "flash: unknown status";
    }
}

void stm32_flash_init(stm32_flash_t *f, const stm32_flash_hw_t *hw)
{
    *f = (stm32_flash_t){.hw = *hw, .status = STM32_FLASH_OK};
}

bool stm32_flash_bridge_enabled(const stm32_flash_t *f)
{
    for (uint32_t i = 0; i < 2u; ++i) {
        if (f->hw.bridge[i] != NULL && (RD(f->hw.bridge[i]->BDTR) & TIM_BDTR_MOE) != 0u) {
            return true;
        }
    }
    return false;
}

static flash_if_result_t done(stm32_flash_t *f, stm32_flash_status_t s)
{
    f->status = s;
    if (s == STM32_FLASH_OK) {
        return FLASH_IF_OK;
    }
    return s == STM32_FLASH_BRIDGE_ENABLED ? FLASH_IF_REFUSED : FLASH_IF_FAILED;
}

/* FLASH_CR locked again (PG, SER, SNB cleared with it) */
static void lock(stm32_flash_t *f) { WR(f->hw.regs->CR, FLASH_CR_LOCK); }

/* The error flags after an operation, each named (the first of them in
 * this order if several); the flags are cleared for the next one. */
static stm32_flash_status_t errors(stm32_flash_t *f)
{
    const uint32_t sr = RD(f->hw.regs->SR);
    if ((sr & FLASH_SR_ERRORS) == 0u) {
        return STM32_FLASH_OK;
    }
    f->sr = sr;
    WR(f->hw.regs->SR, sr & (FLASH_SR_ERRORS | FLASH_SR_EOP));
    if (sr & FLASH_SR_WRPERR) return STM32_FLASH_WRPERR;
    if (sr & FLASH_SR_PGAERR) return STM32_FLASH_PGAERR;
    if (sr & FLASH_SR_PGPERR) return STM32_FLASH_PGPERR;
    if (sr & FLASH_SR_PGSERR) return STM32_FLASH_PGSERR;
    return STM32_FLASH_OPERR;
}

/* The start of every operation (RM0090 3.6.1, 3.6.3, 3.6.4): refused with
 * a bridge enabled; no operation running (bounded); FLASH_CR unlocked by
 * the keys and checked; error flags of earlier operations cleared (after
 * a reset under a debugger PGSERR and PGPERR can be found set). */
static stm32_flash_status_t begin(stm32_flash_t *f)
{
    if (stm32_flash_bridge_enabled(f)) {
        return STM32_FLASH_BRIDGE_ENABLED;
    }
    flash_regs_t *r = f->hw.regs;
    if (!idle(f)) {
        f->sr = RD(r->SR);
        return STM32_FLASH_BUSY_TIMEOUT;
    }
    if ((RD(r->CR) & FLASH_CR_LOCK) != 0u) {
        WR(r->KEYR, FLASH_KEY1);
        WR(r->KEYR, FLASH_KEY2);
        if ((RD(r->CR) & FLASH_CR_LOCK) != 0u) {
            return STM32_FLASH_UNLOCK_FAILED;
        }
    }
    WR(r->SR, FLASH_SR_ERRORS | FLASH_SR_EOP);
    return STM32_FLASH_OK;
}

flash_if_result_t stm32_flash_erase(stm32_flash_t *f, uint32_t sector)
{
    if (sector >= FLASH_IF_SECTORS) {
        return done(f, STM32_FLASH_BAD_ARGS);
    }
    const stm32_flash_status_t b = begin(f);
    if (b != STM32_FLASH_OK) {
        return done(f, b);
    }
    flash_regs_t *r = f->hw.regs;
    const uint32_t cr = FLASH_CR_PSIZE_X32 | FLASH_CR_SER | FLASH_CR_SNB(f->hw.sector_number[sector]);
    WR(r->CR, cr);
    const uint32_t primask = irq_mask();
    const uint32_t polls = start_and_wait(&r->CR, cr | FLASH_CR_STRT, &r->SR,
                                          f->hw.iwdg != NULL ? &f->hw.iwdg->KR : NULL, f->hw.erase_polls);
    irq_restore(primask);
    if (polls == 0u) {
        /* FLASH_CR left as it is: a write to it while BSY is set stalls
         * the bus until BSY clears (RM0090 3.6.1) */
        f->sr = RD(r->SR);
        return done(f, STM32_FLASH_ERASE_TIMEOUT);
    }
    f->erase_polls_max = polls > f->erase_polls_max ? polls : f->erase_polls_max;
    const stm32_flash_status_t e = errors(f);
    lock(f);
    if (e == STM32_FLASH_OK) {
        f->erases++;
    }
    return done(f, e);
}

flash_if_result_t stm32_flash_program(stm32_flash_t *f, uint32_t sector, uint32_t offset, const uint32_t *words,
                                      uint32_t n)
{
    if (sector >= FLASH_IF_SECTORS || words == NULL || offset > f->hw.sector_words || n > f->hw.sector_words - offset) {
        return done(f, STM32_FLASH_BAD_ARGS);
    }
    const stm32_flash_status_t b = begin(f);
    if (b != STM32_FLASH_OK) {
        return done(f, b);
    }
    flash_regs_t *r = f->hw.regs;
    WR(r->CR, FLASH_CR_PSIZE_X32 | FLASH_CR_PG);
    volatile uint32_t *dst = f->hw.sector_base[sector] + offset;
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t primask = irq_mask();
        const uint32_t polls =
            start_and_wait(&dst[i], words[i], &r->SR, f->hw.iwdg != NULL ? &f->hw.iwdg->KR : NULL, f->hw.program_polls);
        irq_restore(primask);
        if (polls == 0u) {
            f->sr = RD(r->SR);
            return done(f, STM32_FLASH_PROGRAM_TIMEOUT); /* FLASH_CR left: as after the erase's */
        }
        f->program_polls_max = polls > f->program_polls_max ? polls : f->program_polls_max;
        const stm32_flash_status_t e = errors(f);
        if (e != STM32_FLASH_OK) {
            lock(f);
            return done(f, e);
        }
        f->words++;
    }
    lock(f);
    return done(f, STM32_FLASH_OK);
}

static flash_if_result_t if_erase(void *ctx, uint32_t sector) { return stm32_flash_erase(ctx, sector); }
static flash_if_result_t if_program(void *ctx, uint32_t sector, uint32_t offset, const uint32_t *words, uint32_t n)
{
    return stm32_flash_program(ctx, sector, offset, words, n);
}
static const char *if_error(void *ctx)
{
    const stm32_flash_t *f = ctx;
    return f->status == STM32_FLASH_OK ? "" : stm32_flash_status_text(f->status);
}

flash_if_t stm32_flash_interface(stm32_flash_t *f)
{
    flash_if_t i = {.ctx = f,
                    .sector_words = f->hw.sector_words,
                    .base = {f->hw.sector_base[0], f->hw.sector_base[1]},
                    .erase = if_erase,
                    .program = if_program,
                    .error = if_error};
    return i;
}

#if defined(__arm__)
/* stm32f405.ld: the two sectors the image leaves free */
extern uint32_t _config_sector_a[], _config_sector_b[];

void stm32_flash_chip(stm32_flash_hw_t *hw, const tim_regs_t *tim1, const tim_regs_t *tim8, iwdg_regs_t *iwdg)
{
    *hw = (stm32_flash_hw_t){.regs = (flash_regs_t *)STM32_FLASH_IF_BASE,
                             .sector_base = {_config_sector_a, _config_sector_b},
                             .sector_number = {STM32_FLASH_SECTOR_A, STM32_FLASH_SECTOR_B},
                             .sector_words = STM32_FLASH_SECTOR_WORDS,
                             .bridge = {tim1, tim8},
                             .iwdg = iwdg,
                             .erase_polls = STM32_FLASH_ERASE_POLLS,
                             .program_polls = STM32_FLASH_PROGRAM_POLLS};
}
#endif
