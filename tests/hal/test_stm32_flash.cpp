// The STM32F405's flash driver (hal/backends/stm32f405/flash.c) against a
// model of the flash interface (RM0090 3.6, 3.9): the driver's register
// accesses go through stm32_flash_fake_read/write (STM32_FLASH_FAKE_IO),
// which keep the order of the writes and answer as the chip does: FLASH_CR
// locked until KEY1 then KEY2 (a wrong key locks it until reset), the
// error flags of FLASH_SR cleared by writing 1, BSY set for a few reads
// after an erase's STRT or a word's write, a word written without PG
// setting PGSERR, a program only clearing bits, a write to FLASH_CR while
// BSY is set counted (on the chip it stalls the bus). QEMU's netduinoplus2
// has no flash interface: this is where the driver is checked.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <utility>
#include <vector>

extern "C" {
#include "config/config_store.h"
#include "flash.h"
}

namespace {

constexpr uint32_t kWords = 64;  // a small sector: the store compacts often

struct FakeFlash {
    flash_regs_t regs{};
    tim_regs_t tim1{}, tim8{};
    iwdg_regs_t iwdg{};
    std::vector<uint32_t> mem[2] = {std::vector<uint32_t>(kWords, 0u), std::vector<uint32_t>(kWords, 0u)};
    // the chip's state
    uint32_t sr = 0, cr = FLASH_CR_LOCK;
    int key_stage = 0;
    bool keys_ignored = false;  // the key sequence does not unlock (a wrong key earlier)
    uint32_t busy_reads = 0;    // SR reads left with BSY set
    uint32_t op_busy = 3;       // BSY reads after each operation starts
    bool busy_forever = false;
    uint32_t inject = 0;  // error flags the next operations set (and then do nothing)
    // what the driver did
    std::vector<std::pair<std::string, uint32_t>> writes;
    uint32_t sr_reads = 0, refreshes = 0, cr_writes_while_busy = 0, nor_violations = 0;

    bool busy() const { return busy_forever || busy_reads > 0; }
    void start_op()
    {
        busy_reads = op_busy;
        sr |= inject;
    }
    int sector_of(const volatile uint32_t* p, uint32_t* off) const
    {
        for (int s = 0; s < 2; ++s) {
            const uint32_t* b = mem[s].data();
            if (p >= b && p < b + kWords) {
                *off = static_cast<uint32_t>(p - b);
                return s;
            }
        }
        return -1;
    }

    uint32_t read(const volatile uint32_t* r)
    {
        if (r == &regs.SR) {
            ++sr_reads;
            if (busy_forever) return sr | FLASH_SR_BSY;
            if (busy_reads > 0) {
                --busy_reads;
                return sr | FLASH_SR_BSY;
            }
            return sr;
        }
        if (r == &regs.CR) return cr;
        return *r;
    }

    void write(volatile uint32_t* r, uint32_t v)
    {
        uint32_t off = 0;
        const int s = sector_of(r, &off);
        if (r == &regs.KEYR) {
            writes.emplace_back("KEYR", v);
            if (keys_ignored) return;
            if (key_stage == 0 && v == FLASH_KEY1) {
                key_stage = 1;
            } else if (key_stage == 1 && v == FLASH_KEY2) {
                key_stage = 0;
                cr &= ~FLASH_CR_LOCK;
            } else {
                keys_ignored = true;  // locked until reset
            }
        } else if (r == &regs.SR) {
            writes.emplace_back("SR", v);
            sr &= ~(v & (FLASH_SR_ERRORS | FLASH_SR_EOP));
        } else if (r == &regs.CR) {
            writes.emplace_back("CR", v);
            if (busy()) ++cr_writes_while_busy;
            if (cr & FLASH_CR_LOCK) return;  // ignored while locked
            cr = v;
            if ((v & FLASH_CR_STRT) && (v & FLASH_CR_SER)) {
                start_op();
                const uint32_t snb = (v >> 3) & 0xFu;
                if (inject == 0 && (snb == 1 || snb == 2)) mem[snb - 1].assign(kWords, FLASH_IF_ERASED);
                cr &= ~FLASH_CR_STRT;
            }
        } else if (r == &iwdg.KR) {
            if (v == IWDG_KEY_REFRESH) ++refreshes;
        } else if (s >= 0) {
            writes.emplace_back("word " + std::to_string(s) + ":" + std::to_string(off), v);
            if ((cr & FLASH_CR_LOCK) || !(cr & FLASH_CR_PG)) {
                sr |= FLASH_SR_PGSERR;
                return;
            }
            if ((cr & (3u << 8)) != FLASH_CR_PSIZE_X32) {
                sr |= FLASH_SR_PGPERR;
                return;
            }
            start_op();
            if (inject != 0) return;
            if (v & ~mem[s][off]) ++nor_violations;
            mem[s][off] &= v;
        } else {
            *r = v;
        }
    }
};

FakeFlash* g_fake = nullptr;

stm32_flash_hw_t fake_hw(FakeFlash& k)
{
    stm32_flash_hw_t hw{};
    hw.regs = &k.regs;
    hw.sector_base[0] = k.mem[0].data();
    hw.sector_base[1] = k.mem[1].data();
    hw.sector_number[0] = STM32_FLASH_SECTOR_A;
    hw.sector_number[1] = STM32_FLASH_SECTOR_B;
    hw.sector_words = kWords;
    hw.bridge[0] = &k.tim1;
    hw.bridge[1] = &k.tim8;
    hw.iwdg = &k.iwdg;
    hw.erase_polls = 100;
    hw.program_polls = 10;
    return hw;
}

class Stm32Flash : public ::testing::Test {
protected:
    void SetUp() override
    {
        g_fake = &k;
        const stm32_flash_hw_t hw = fake_hw(k);
        stm32_flash_init(&f, &hw);
    }
    void TearDown() override { g_fake = nullptr; }
    using Log = std::vector<std::pair<std::string, uint32_t>>;
    FakeFlash k;
    stm32_flash_t f{};
};

}  // namespace

extern "C" uint32_t stm32_flash_fake_read(const volatile uint32_t* reg) { return g_fake->read(reg); }
extern "C" void stm32_flash_fake_write(volatile uint32_t* reg, uint32_t v) { g_fake->write(reg, v); }

// RM0090 3.6.1, 3.6.3: KEY1, KEY2; the old error flags cleared; PSIZE x32
// (bits 8-9 = 10), SER, SNB = 1 (store sector 0) or 2 (store sector 1);
// STRT; BSY waited for with the watchdog refreshed at each poll; locked.
TEST_F(Stm32Flash, EraseFollowsTheReferenceManual)
{
    k.mem[1].assign(kWords, 0x12345678u);
    ASSERT_EQ(stm32_flash_erase(&f, 0), FLASH_IF_OK) << stm32_flash_status_text(f.status);
    const Log want = {{"KEYR", 0x45670123u}, {"KEYR", 0xCDEF89ABu}, {"SR", 0xF3u},
                      {"CR", 0x20Au},        {"CR", 0x1020Au},      {"CR", 0x80000000u}};
    EXPECT_EQ(k.writes, want);
    EXPECT_EQ(k.mem[0], std::vector<uint32_t>(kWords, FLASH_IF_ERASED));
    EXPECT_EQ(k.mem[1], std::vector<uint32_t>(kWords, 0x12345678u)) << "the other sector untouched";
    EXPECT_EQ(k.cr & FLASH_CR_LOCK, FLASH_CR_LOCK);
    EXPECT_EQ(f.erase_polls_max, k.op_busy + 1u);
    EXPECT_EQ(k.refreshes, k.op_busy + 1u);
    EXPECT_EQ(k.cr_writes_while_busy, 0u);
    k.writes.clear();
    ASSERT_EQ(stm32_flash_erase(&f, 1), FLASH_IF_OK);
    EXPECT_EQ(k.writes[3], std::make_pair(std::string("CR"), 0x212u)) << "SNB = 2";
    EXPECT_EQ(k.mem[1], std::vector<uint32_t>(kWords, FLASH_IF_ERASED));
    EXPECT_EQ(f.erases, 2u);
}

// RM0090 3.6.4: PSIZE x32 and PG, then each word written at its address
// and BSY waited for, then locked.
TEST_F(Stm32Flash, ProgramFollowsTheReferenceManual)
{
    k.mem[1].assign(kWords, FLASH_IF_ERASED);
    const uint32_t w[3] = {0xA5A5A5A5u, 0x0u, 0x12345678u};
    ASSERT_EQ(stm32_flash_program(&f, 1, 5, w, 3), FLASH_IF_OK) << stm32_flash_status_text(f.status);
    const Log want = {{"KEYR", 0x45670123u}, {"KEYR", 0xCDEF89ABu}, {"SR", 0xF3u},      {"CR", 0x201u},
                      {"word 1:5", w[0]},    {"word 1:6", w[1]},    {"word 1:7", w[2]}, {"CR", 0x80000000u}};
    EXPECT_EQ(k.writes, want);
    EXPECT_EQ(k.mem[1][4], FLASH_IF_ERASED);
    EXPECT_EQ(k.mem[1][5], w[0]);
    EXPECT_EQ(k.mem[1][6], w[1]);
    EXPECT_EQ(k.mem[1][7], w[2]);
    EXPECT_EQ(k.mem[1][8], FLASH_IF_ERASED);
    EXPECT_EQ(f.words, 3u);
    EXPECT_EQ(f.program_polls_max, k.op_busy + 1u);
    EXPECT_EQ(k.cr_writes_while_busy, 0u);
}

// A BSY that does not clear: before the operation (nothing started, no key
// written), after an erase's STRT and after a word, each after exactly its
// bound of polls (the watchdog refreshed at each of the last two), and
// FLASH_CR not written after a timeout (on the chip that write would stall
// the bus until BSY clears).
TEST_F(Stm32Flash, EachWaitIsBounded)
{
    const uint32_t w[2] = {1u, 2u};
    k.busy_forever = true;
    EXPECT_EQ(stm32_flash_erase(&f, 0), FLASH_IF_FAILED);
    EXPECT_EQ(f.status, STM32_FLASH_BUSY_TIMEOUT);
    EXPECT_EQ(k.sr_reads, 100u + 1u) << "the erase's bound, then FLASH_SR kept";
    EXPECT_TRUE(k.writes.empty());
    EXPECT_EQ(stm32_flash_program(&f, 0, 0, w, 2), FLASH_IF_FAILED);
    EXPECT_EQ(f.status, STM32_FLASH_BUSY_TIMEOUT);
    EXPECT_TRUE(k.writes.empty());

    k.busy_forever = false;
    k.op_busy = 1000000;  // the erase does not end
    k.sr_reads = 0;
    EXPECT_EQ(stm32_flash_erase(&f, 0), FLASH_IF_FAILED);
    EXPECT_EQ(f.status, STM32_FLASH_ERASE_TIMEOUT);
    EXPECT_EQ(k.sr_reads, 1u + 100u + 1u) << "idle, the erase's bound, FLASH_SR kept";
    EXPECT_EQ(k.refreshes, 100u);
    EXPECT_EQ(k.writes.back(), std::make_pair(std::string("CR"), 0x1020Au)) << "nothing written after STRT";
    EXPECT_EQ(k.cr_writes_while_busy, 0u);
    EXPECT_NE(std::string(stm32_flash_status_text(f.status)).find("erase"), std::string::npos);

    k.busy_reads = 0;
    k.op_busy = 1000000;  // the first word does not end
    k.sr_reads = 0;
    k.refreshes = 0;
    k.writes.clear();
    k.mem[0].assign(kWords, FLASH_IF_ERASED);
    EXPECT_EQ(stm32_flash_program(&f, 0, 0, w, 2), FLASH_IF_FAILED);
    EXPECT_EQ(f.status, STM32_FLASH_PROGRAM_TIMEOUT);
    EXPECT_EQ(k.sr_reads, 1u + 10u + 1u) << "idle, the program's bound, FLASH_SR kept";
    EXPECT_EQ(k.refreshes, 10u);
    EXPECT_EQ(k.writes.back(), std::make_pair(std::string("word 0:0"), 1u)) << "the second word not written";
    EXPECT_EQ(k.cr_writes_while_busy, 0u);
}

// The chip's bounds: at most 42 polls a microsecond at 168 MHz (4 cycles
// a poll at least; the loop is 6 instructions, 7 with the watchdog), so
// the erase's bound lasts at least 1 s, twice DS8626's 500 ms for a 16 KB
// sector at x32, the program's at least 200 us, twice its 100 us a word.
TEST_F(Stm32Flash, BoundsAreAtLeastTwiceTheDatasheetsLongest)
{
    EXPECT_GE(STM32_FLASH_POLLS_PER_US, 168u / 4u);
    EXPECT_GE(STM32_FLASH_ERASE_POLLS / STM32_FLASH_POLLS_PER_US, 2u * 500000u);
    EXPECT_GE(STM32_FLASH_PROGRAM_POLLS / STM32_FLASH_POLLS_PER_US, 2u * 100u);
    EXPECT_EQ(STM32_FLASH_SECTOR_WORDS, 4096u);
    EXPECT_EQ(STM32_FLASH_SECTOR_B_ADDR - STM32_FLASH_SECTOR_A_ADDR, STM32_FLASH_SECTOR_BYTES);
}

// Each error flag of FLASH_SR (RM0090 3.9.4) after an erase and after a
// word: the failure named by its own code and text, FLASH_SR kept, the
// flag cleared (written 1), FLASH_CR locked again; a program stops at the
// word.
TEST_F(Stm32Flash, EachErrorFlagIsNamed)
{
    struct Flag {
        uint32_t bit;
        stm32_flash_status_t status;
        const char* name;
    };
    const Flag flags[] = {{FLASH_SR_OPERR, STM32_FLASH_OPERR, "OPERR"},
                          {FLASH_SR_WRPERR, STM32_FLASH_WRPERR, "WRPERR"},
                          {FLASH_SR_PGAERR, STM32_FLASH_PGAERR, "PGAERR"},
                          {FLASH_SR_PGPERR, STM32_FLASH_PGPERR, "PGPERR"},
                          {FLASH_SR_PGSERR, STM32_FLASH_PGSERR, "PGSERR"}};
    const uint32_t w[2] = {7u, 8u};
    for (const Flag& fl : flags) {
        for (bool erase : {true, false}) {
            k = FakeFlash{};  // a fresh model, then the driver on it
            SetUp();
            k.mem[0].assign(kWords, FLASH_IF_ERASED);
            k.inject = fl.bit;
            const flash_if_result_t r = erase ? stm32_flash_erase(&f, 0) : stm32_flash_program(&f, 0, 0, w, 2);
            EXPECT_EQ(r, FLASH_IF_FAILED) << fl.name;
            EXPECT_EQ(f.status, fl.status) << fl.name << (erase ? " erase" : " program");
            EXPECT_NE(std::string(stm32_flash_status_text(f.status)).find(fl.name), std::string::npos);
            EXPECT_EQ(f.sr & fl.bit, fl.bit);
            EXPECT_EQ(k.sr & FLASH_SR_ERRORS, 0u) << fl.name << ": cleared";
            EXPECT_EQ(k.writes.back(), std::make_pair(std::string("CR"), FLASH_CR_LOCK)) << fl.name;
            if (!erase) {
                EXPECT_EQ(f.words, 0u);
                for (const auto& wr : k.writes) EXPECT_NE(wr.first, "word 0:1") << fl.name << ": stopped at the word";
            }
        }
    }
}

// A bridge timer's outputs on (MOE of TIM1 or of TIM8): every operation
// refused before any register is written; the store says the save was
// refused and why; once off, the save goes through.
TEST_F(Stm32Flash, SaveWhileTheBridgeIsEnabledIsRefused)
{
    const uint32_t w[1] = {0u};
    for (tim_regs_t* t : {&k.tim1, &k.tim8}) {
        t->BDTR = TIM_BDTR_MOE;
        EXPECT_TRUE(stm32_flash_bridge_enabled(&f));
        EXPECT_EQ(stm32_flash_erase(&f, 0), FLASH_IF_REFUSED);
        EXPECT_EQ(f.status, STM32_FLASH_BRIDGE_ENABLED);
        EXPECT_EQ(stm32_flash_program(&f, 0, 0, w, 1), FLASH_IF_REFUSED);
        EXPECT_TRUE(k.writes.empty());
        EXPECT_EQ(k.mem[0], std::vector<uint32_t>(kWords, 0u));
        t->BDTR = 0;
    }
    std::vector<config_entry_t> defaults = {{1, 11, 100}, {2, 22, 200}};
    const config_schema_t schema{0x5C4E0001u, defaults.data(), 2};
    const flash_if_t fi = stm32_flash_interface(&f);
    config_store_t st;
    ASSERT_TRUE(config_store_init(&st, &fi, &schema));
    std::vector<config_entry_t> v = defaults;
    v[1].value = 201;
    k.tim1.BDTR = TIM_BDTR_MOE;
    EXPECT_FALSE(config_store_save(&st, v.data()));
    EXPECT_EQ(st.error, CONFIG_ERR_FLASH_REFUSED);
    EXPECT_STREQ(st.flash_error, stm32_flash_status_text(STM32_FLASH_BRIDGE_ENABLED));
    EXPECT_TRUE(k.writes.empty());
    k.tim1.BDTR = 0;
    ASSERT_TRUE(config_store_save(&st, v.data())) << config_store_last_error(&st) << ": " << st.flash_error;
    std::vector<config_entry_t> got(2);
    ASSERT_TRUE(config_store_load(&st, got.data()));
    EXPECT_EQ(got[1].value, 201u);
}

// FLASH_CR that stays locked after the keys (a wrong key earlier locks it
// until reset, RM0090 3.6.1): named, nothing else written.
TEST_F(Stm32Flash, UnlockThatFailsIsNamed)
{
    k.keys_ignored = true;
    EXPECT_EQ(stm32_flash_erase(&f, 0), FLASH_IF_FAILED);
    EXPECT_EQ(f.status, STM32_FLASH_UNLOCK_FAILED);
    const Log want = {{"KEYR", FLASH_KEY1}, {"KEYR", FLASH_KEY2}};
    EXPECT_EQ(k.writes, want);
}

// Error flags left set by something before (PGSERR and PGPERR after a
// reset under a debugger) are cleared first: the erase goes through.
TEST_F(Stm32Flash, StaleErrorFlagsAreClearedFirst)
{
    k.sr = FLASH_SR_PGSERR | FLASH_SR_PGPERR;
    EXPECT_EQ(stm32_flash_erase(&f, 1), FLASH_IF_OK) << stm32_flash_status_text(f.status);
    EXPECT_EQ(k.mem[1], std::vector<uint32_t>(kWords, FLASH_IF_ERASED));
}

// A sector or a range outside the store's: refused before any register.
TEST_F(Stm32Flash, OutsideTheSectorsIsRefused)
{
    const uint32_t w[2] = {0u, 0u};
    EXPECT_EQ(stm32_flash_erase(&f, 2), FLASH_IF_FAILED);
    EXPECT_EQ(f.status, STM32_FLASH_BAD_ARGS);
    EXPECT_EQ(stm32_flash_program(&f, 0, kWords - 1, w, 2), FLASH_IF_FAILED);
    EXPECT_EQ(stm32_flash_program(&f, 0, kWords + 1, w, 0), FLASH_IF_FAILED);
    EXPECT_EQ(stm32_flash_program(&f, 0, 0, nullptr, 1), FLASH_IF_FAILED);
    EXPECT_TRUE(k.writes.empty());
    EXPECT_EQ(stm32_flash_program(&f, 0, kWords - 2, w, 2), FLASH_IF_OK) << "the last two words: in range";
    EXPECT_FALSE(k.writes.empty());
}

// The store on the driver: 7 saves of 4 parameters (18 words, 3 a 64-word
// sector) erase SNB 1 (the model's sectors start at 0), then SNB 2, then
// SNB 1; every word programmed over erased bits only, none without PG;
// the last save is what a restart loads.
TEST_F(Stm32Flash, TheStoreRunsOnTheDriver)
{
    std::vector<config_entry_t> defaults = {{1, 11, 0}, {2, 22, 0}, {3, 33, 0}, {4, 44, 0}};
    const config_schema_t schema{0x5C4E0001u, defaults.data(), 4};
    const flash_if_t fi = stm32_flash_interface(&f);
    config_store_t st;
    ASSERT_TRUE(config_store_init(&st, &fi, &schema));
    std::vector<config_entry_t> v = defaults;
    ASSERT_TRUE(config_store_load(&st, v.data()));
    EXPECT_TRUE(st.loaded_defaults);
    std::vector<uint32_t> erased_snb;
    for (uint32_t s = 1; s <= 7; ++s) {
        for (auto& e : v) e.value = s * 10u + e.id;
        k.writes.clear();
        ASSERT_TRUE(config_store_save(&st, v.data())) << "save " << s << ": " << st.flash_error;
        for (const auto& wr : k.writes) {
            if (wr.first == "CR" && (wr.second & FLASH_CR_STRT)) erased_snb.push_back((wr.second >> 3) & 0xFu);
        }
    }
    EXPECT_EQ(erased_snb, (std::vector<uint32_t>{1, 2, 1})) << "saves 1, 4, 7 (the model's sectors start written)";
    EXPECT_EQ(k.nor_violations, 0u);
    EXPECT_EQ(k.sr & FLASH_SR_ERRORS, 0u);
    config_store_t st2;
    ASSERT_TRUE(config_store_init(&st2, &fi, &schema));
    std::vector<config_entry_t> got(4);
    ASSERT_TRUE(config_store_load(&st2, got.data()));
    EXPECT_EQ(st2.source, CONFIG_SOURCE_RECORD);
    EXPECT_EQ(st2.seq, 7u);
    for (size_t i = 0; i < 4; ++i) EXPECT_EQ(got[i].value, 70u + got[i].id);
}
