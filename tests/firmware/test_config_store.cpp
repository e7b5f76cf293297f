// The configuration store (firmware/config/config_store.h) on a simulated
// NOR flash that can lose its power at any word of an erase or a program,
// half-way into the word included (sim_flash.h): a cut at every step of a
// save leaves, after a restart, the old configuration or the new one,
// never a mix; a flipped bit anywhere in a record refuses it; a full
// sector moves the newest record into the other (ping-pong); 10,000 saves
// in a row keep the last; a record of an older schema keeps the
// parameters whose definition did not change; a refused or failing flash
// leaves the previous record the newest.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "sim_flash.h"

extern "C" {
#include "config/config_store.h"
}

namespace {

// A schema of n parameters: ids 10, 20, ..., definition hashes and
// defaults distinct from any value saved below.
struct Schema {
    std::vector<config_entry_t> defaults;
    config_schema_t s{};
    Schema(uint32_t hash, uint16_t n)
    {
        for (uint16_t i = 0; i < n; ++i) {
            defaults.push_back(config_entry_t{static_cast<uint16_t>(10u * (i + 1u)), 0xD0000000u + i, 0xDEF00000u + i});
        }
        s = config_schema_t{hash, defaults.data(), n};
    }
};

// the values of save number k: every parameter differs from save to save
std::vector<config_entry_t> values_of(const Schema& sc, uint32_t k)
{
    std::vector<config_entry_t> v = sc.defaults;
    for (size_t i = 0; i < v.size(); ++i) v[i].value = k * 1000u + static_cast<uint32_t>(i);
    return v;
}

bool same_values(const std::vector<config_entry_t>& a, const std::vector<config_entry_t>& b)
{
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i) {
        if (a[i].id != b[i].id || a[i].def_hash != b[i].def_hash || a[i].value != b[i].value) return false;
    }
    return true;
}

// A restart: a new store over the flash as it is, loaded.
std::vector<config_entry_t> restart(SimFlash& fl, const Schema& sc, config_store_t* st_out = nullptr)
{
    const flash_if_t f = fl.interface();
    config_store_t st;
    EXPECT_TRUE(config_store_init(&st, &f, &sc.s));
    std::vector<config_entry_t> v(sc.defaults.size());
    EXPECT_TRUE(config_store_load(&st, v.data()));
    if (st_out) {
        *st_out = st;
        st_out->flash = nullptr;  // f is gone: the caller reads the fields only
    }
    return v;
}

// Saves values on a running store over fl (init, load, save).
bool save(SimFlash& fl, const Schema& sc, const std::vector<config_entry_t>& v, config_store_t* st_out = nullptr)
{
    const flash_if_t f = fl.interface();
    config_store_t st;
    EXPECT_TRUE(config_store_init(&st, &f, &sc.s));
    std::vector<config_entry_t> cur(sc.defaults.size());
    EXPECT_TRUE(config_store_load(&st, cur.data()));
    const bool ok = config_store_save(&st, v.data());
    if (st_out) {
        *st_out = st;
        st_out->flash = nullptr;
    }
    return ok;
}

}  // namespace

// zlib's crc32 of "12345678" and of "123456789" (the catalogue's check
// value), the bytes least significant first in each word.
TEST(ConfigStore, Crc32IsZlibs)
{
    const uint32_t w[3] = {0x34333231u, 0x38373635u, 0x39u};
    EXPECT_EQ(config_crc32(0, w, 2), 0x9AE0DAAFu);
    // continued: the 9th byte alone is not a word; check the continuation on words
    EXPECT_EQ(config_crc32(config_crc32(0, w, 1), w + 1, 1), 0x9AE0DAAFu);
    EXPECT_EQ(config_crc32(0, w, 0), 0u);
}

// A new board (both sectors erased) and a flash holding only garbage:
// the defaults, and the store says so and why.
TEST(ConfigStore, NoRecordGivesTheDefaultsAndSaysWhy)
{
    const Schema sc(0x5C4E0001u, 4);
    SimFlash fl(64);
    config_store_t st;
    std::vector<config_entry_t> v = restart(fl, sc, &st);
    EXPECT_TRUE(same_values(v, sc.defaults));
    EXPECT_TRUE(st.loaded_defaults);
    EXPECT_EQ(st.source, CONFIG_SOURCE_DEFAULTS);
    EXPECT_EQ(st.defaults_reason, CONFIG_ERR_NO_RECORD);
    EXPECT_EQ(st.n_defaulted, 4u);
    EXPECT_FALSE(st.has_record);

    fl.sector(1)[7] = 0x12345678u;  // something written, no record
    v = restart(fl, sc, &st);
    EXPECT_TRUE(same_values(v, sc.defaults));
    EXPECT_TRUE(st.loaded_defaults);
    EXPECT_EQ(st.defaults_reason, CONFIG_ERR_NO_VALID_RECORD);
}

// The words in flash are docs/config_store.md's: magic, version and count,
// schema hash, sequence number, (id, definition hash, value) per entry,
// zlib's CRC-32 of all that, the commit word; the second record right after.
TEST(ConfigStore, RecordLayoutAsDocumented)
{
    const Schema sc(0xABCD1234u, 2);
    SimFlash fl(64);
    ASSERT_TRUE(save(fl, sc, values_of(sc, 1)));
    const std::vector<uint32_t>& m = fl.sector(0);
    const uint32_t want[10] = {0x43464731u, 0x00020001u, 0xABCD1234u, 1u,          10u,
                               0xD0000000u, 1000u,       20u,         0xD0000001u, 1001u};
    for (int i = 0; i < 10; ++i) EXPECT_EQ(m[i], want[i]) << "word " << i;
    // zlib.crc32 of the 40 bytes, little-endian words
    uint8_t bytes[40];
    std::memcpy(bytes, want, sizeof bytes);
    uint32_t c = 0xFFFFFFFFu;
    for (uint8_t b : bytes) {
        c ^= b;
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    EXPECT_EQ(m[10], ~c);
    EXPECT_EQ(m[11], 0u) << "the commit word";
    EXPECT_EQ(m[12], FLASH_IF_ERASED);
    ASSERT_TRUE(save(fl, sc, values_of(sc, 2)));
    EXPECT_EQ(m[12], 0x43464731u);
    EXPECT_EQ(m[15], 2u) << "sequence number 2";
    EXPECT_EQ(fl.nor_violations, 0u);
}

TEST(ConfigStore, SaveThenRestartLoadsIt)
{
    const Schema sc(0x5C4E0001u, 5);
    SimFlash fl(128);
    config_store_t st;
    ASSERT_TRUE(save(fl, sc, values_of(sc, 7), &st));
    EXPECT_EQ(st.seq, 1u);
    const std::vector<config_entry_t> v = restart(fl, sc, &st);
    EXPECT_TRUE(same_values(v, values_of(sc, 7)));
    EXPECT_FALSE(st.loaded_defaults);
    EXPECT_EQ(st.source, CONFIG_SOURCE_RECORD);
    EXPECT_EQ(st.n_kept, 5u);
    EXPECT_EQ(st.seq, 1u);
}

// The power cut at every word operation of a save, cleanly between words
// and half-way into one, from five starting points: a new board (the old
// configuration is the defaults), a save appended in the sector, a save
// that must erase the other sector (the first full), the same when the
// sector erased holds older valid records (the second full), and a save
// after an earlier cut left a broken record behind. After the cut the store
// restarts and loads: the old values or the new ones, all of them, never a
// mix; the old until the commit word is whole, the new from then on. Then a
// save on the restarted store succeeds and is loaded: the store recovers.
TEST(ConfigStore, PowerCutAtEveryStepOfASaveLeavesOldOrNew)
{
    const Schema sc(0x5C4E0001u, 4);  // 18 words a record: 3 in a sector of 64
    struct Start {
        const char* name;
        uint32_t saves_before;  // saves done before the one cut
        bool broken_tail;       // and one of them cut half-way afterwards
    };
    const Start starts[] = {{"new board", 0, false},
                            {"append", 1, false},
                            {"into the other sector", 3, false},
                            {"erasing a sector of older records", 6, false},
                            {"after an earlier cut", 1, true}};
    for (const Start& start : starts) {
        SimFlash base(64);
        for (uint32_t k = 1; k <= start.saves_before; ++k) ASSERT_TRUE(save(base, sc, values_of(sc, k)));
        const std::vector<config_entry_t> old_v =
            start.saves_before > 0 ? values_of(sc, start.saves_before) : sc.defaults;
        if (start.broken_tail) {  // a save cut in its 7th word
            SimFlash tmp = base;
            tmp.cut_after(6, true);
            ASSERT_FALSE(save(tmp, sc, values_of(sc, 99)));
            base = tmp;
            base.power_back();
            ASSERT_TRUE(same_values(restart(base, sc), old_v));
        }
        const std::vector<config_entry_t> new_v = values_of(sc, 50);
        // the save's word operations without a cut
        SimFlash whole = base;
        const uint64_t ops0 = whole.ops;
        ASSERT_TRUE(save(whole, sc, new_v));
        const uint64_t total = whole.ops - ops0;
        ASSERT_GT(total, 0u);
        uint32_t n_old = 0, n_new = 0;
        for (uint64_t n = 0; n <= total; ++n) {
            for (bool half : {false, true}) {
                SimFlash fl = base;
                fl.cut_after(n, half);
                const bool ok = save(fl, sc, new_v);
                EXPECT_EQ(ok, n == total) << start.name << ": cut after " << n;
                fl.power_back();
                config_store_t st;
                const std::vector<config_entry_t> got = restart(fl, sc, &st);
                const bool is_old = same_values(got, old_v), is_new = same_values(got, new_v);
                ASSERT_TRUE(is_old || is_new)
                    << start.name << ": a mix after a cut after " << n << " words" << (half ? " and a half" : "");
                // the commit word is the save's last word: whole only when n == total
                EXPECT_EQ(is_new, n == total) << start.name << ": cut after " << n;
                if (is_old) {
                    ++n_old;
                    EXPECT_EQ(st.loaded_defaults, start.saves_before == 0);
                } else {
                    ++n_new;
                }
                // the restarted store saves again, and that is what loads
                const std::vector<config_entry_t> next_v = values_of(sc, 60);
                ASSERT_TRUE(save(fl, sc, next_v)) << start.name << ": cut after " << n;
                ASSERT_TRUE(same_values(restart(fl, sc), next_v)) << start.name << ": cut after " << n;
                EXPECT_EQ(fl.nor_violations, 0u);
            }
        }
        EXPECT_EQ(n_new, 2u) << start.name;
        EXPECT_EQ(n_old, 2u * total) << start.name;
    }
}

// One bit flipped anywhere in the newest record (each bit of each of its
// words in turn): the record is refused and the one before it is loaded;
// the same in the only record: the defaults, "no valid record".
TEST(ConfigStore, FlippedBitIsRefused)
{
    const Schema sc(0x5C4E0001u, 4);
    SimFlash base(64);
    ASSERT_TRUE(save(base, sc, values_of(sc, 1)));
    ASSERT_TRUE(save(base, sc, values_of(sc, 2)));
    const uint32_t len = CONFIG_RECORD_WORDS(4);
    for (uint32_t w = 0; w < len; ++w) {
        for (uint32_t b = 0; b < 32; ++b) {
            SimFlash fl = base;
            fl.sector(0)[len + w] ^= 1u << b;  // the second record
            ASSERT_TRUE(same_values(restart(fl, sc), values_of(sc, 1))) << "word " << w << " bit " << b;
            SimFlash one = base;
            one.sector(0)[w] ^= 1u << b;  // the first record, the only one (the second erased)
            std::fill(one.sector(0).begin() + len, one.sector(0).begin() + 2 * len, FLASH_IF_ERASED);
            config_store_t st;
            ASSERT_TRUE(same_values(restart(one, sc, &st), sc.defaults)) << "word " << w << " bit " << b;
            EXPECT_EQ(st.defaults_reason, CONFIG_ERR_NO_VALID_RECORD);
        }
    }
}

// 3 records fit a 64-word sector: saves 1-3 fill sector 0, save 4 erases
// sector 1 and starts it (sector 0 kept as it was until sector 1 is full),
// saves 5-6 follow it there, save 7 erases sector 0 and starts it.
TEST(ConfigStore, FullSectorIsCompactedIntoTheOther)
{
    const Schema sc(0x5C4E0001u, 4);
    const uint32_t len = CONFIG_RECORD_WORDS(4);
    SimFlash fl(64);
    config_store_t st;
    for (uint32_t k = 1; k <= 3; ++k) {
        ASSERT_TRUE(save(fl, sc, values_of(sc, k), &st));
        EXPECT_EQ(st.sector, 0u);
        EXPECT_EQ(st.offset, (k - 1) * len);
    }
    EXPECT_EQ(fl.erases[1], 0u);
    const std::vector<uint32_t> sector0 = fl.sector(0);
    ASSERT_TRUE(save(fl, sc, values_of(sc, 4), &st));
    EXPECT_EQ(st.sector, 1u);
    EXPECT_EQ(st.offset, 0u);
    EXPECT_EQ(st.compactions, 1u);
    EXPECT_EQ(fl.erases[1], 1u);
    EXPECT_EQ(fl.erases[0], 0u);
    EXPECT_EQ(fl.sector(0), sector0) << "the full sector stays as it was";
    EXPECT_TRUE(same_values(restart(fl, sc, &st), values_of(sc, 4)));
    EXPECT_EQ(st.seq, 4u);
    for (uint32_t k = 5; k <= 6; ++k) {
        ASSERT_TRUE(save(fl, sc, values_of(sc, k), &st));
        EXPECT_EQ(st.sector, 1u);
        EXPECT_EQ(st.offset, (k - 4) * len);
    }
    ASSERT_TRUE(save(fl, sc, values_of(sc, 7), &st));
    EXPECT_EQ(st.sector, 0u);
    EXPECT_EQ(st.offset, 0u);
    EXPECT_EQ(fl.erases[0], 1u);
    EXPECT_EQ(fl.erases[1], 1u);
    EXPECT_TRUE(same_values(restart(fl, sc), values_of(sc, 7)));
    EXPECT_EQ(fl.nor_violations, 0u);
}

// 10,000 saves in a row on one running store (the values differ each
// time): the last is loaded after a restart with sequence number 10,000;
// each erase after a sector filled (3 records each: 3,333 erases), every
// 1,000th save is loaded back by a restart on the way.
TEST(ConfigStore, TenThousandSavesKeepTheLast)
{
    const Schema sc(0x5C4E0001u, 4);
    SimFlash fl(64);
    const flash_if_t f = fl.interface();
    config_store_t st;
    ASSERT_TRUE(config_store_init(&st, &f, &sc.s));
    std::vector<config_entry_t> v(4);
    ASSERT_TRUE(config_store_load(&st, v.data()));
    for (uint32_t k = 1; k <= 10000; ++k) {
        ASSERT_TRUE(config_store_save(&st, values_of(sc, k).data()))
            << "save " << k << ": " << config_store_last_error(&st);
        if (k % 1000 == 0) {
            ASSERT_TRUE(same_values(restart(fl, sc), values_of(sc, k))) << "save " << k;
        }
    }
    config_store_t r;
    EXPECT_TRUE(same_values(restart(fl, sc, &r), values_of(sc, 10000)));
    EXPECT_EQ(r.seq, 10000u);
    EXPECT_EQ(st.saves, 10000u);
    EXPECT_EQ(st.compactions, 3333u);  // saves 4, 7, ..., 9,997, 10,000 (the first writes a new board as it is)
    EXPECT_EQ(fl.erases[0] + fl.erases[1], 3333u);
    EXPECT_EQ(fl.nor_violations, 0u);
}

// Schema 2 changed parameter 20's definition, dropped 40 and added 50: a
// record of schema 1 gives 10 and 30 their saved values, 20 and 50 their
// defaults (source MIGRATED); saved again under schema 2, all of it.
TEST(ConfigStore, OlderSchemaKeepsTheUnchangedParameters)
{
    const Schema s1(0x00000001u, 4);
    SimFlash fl(128);
    ASSERT_TRUE(save(fl, s1, values_of(s1, 3)));
    Schema s2(0x00000002u, 4);
    s2.defaults[1].def_hash = 0xD0000F01u;  // 20: its definition changed
    s2.defaults[3].id = 50;                 // 40 gone, 50 new
    config_store_t st;
    const std::vector<config_entry_t> v = restart(fl, s2, &st);
    EXPECT_EQ(v[0].value, 3000u);
    EXPECT_EQ(v[1].value, s2.defaults[1].value);
    EXPECT_EQ(v[2].value, 3002u);
    EXPECT_EQ(v[3].value, s2.defaults[3].value);
    EXPECT_EQ(st.source, CONFIG_SOURCE_MIGRATED);
    EXPECT_FALSE(st.loaded_defaults);
    EXPECT_EQ(st.n_kept, 2u);
    EXPECT_EQ(st.n_defaulted, 2u);
    ASSERT_TRUE(save(fl, s2, v));
    EXPECT_TRUE(same_values(restart(fl, s2, &st), v));
    EXPECT_EQ(st.source, CONFIG_SOURCE_RECORD);
    // the same ids and hashes under another schema hash: every value kept, but MIGRATED
    Schema s3 = s2;
    s3.s.hash = 3;
    restart(fl, s3, &st);
    EXPECT_EQ(st.n_kept, 4u);
    EXPECT_EQ(st.source, CONFIG_SOURCE_MIGRATED);
}

// A flash that refuses (the bridge enabled) is asked once and nothing is
// written, both when the save appends and when it would erase; the error
// names the refusal and carries the driver's text.
TEST(ConfigStore, RefusedSaveWritesNothing)
{
    const Schema sc(0x5C4E0001u, 4);
    for (uint32_t before : {1u, 3u}) {  // append; erase the other sector
        SimFlash fl(64);
        for (uint32_t k = 1; k <= before; ++k) ASSERT_TRUE(save(fl, sc, values_of(sc, k)));
        const SimFlash copy = fl;
        fl.refuse = true;
        config_store_t st;
        EXPECT_FALSE(save(fl, sc, values_of(sc, 9), &st));
        EXPECT_EQ(st.error, CONFIG_ERR_FLASH_REFUSED);
        EXPECT_STREQ(st.flash_error, "refused: bridge enabled");
        EXPECT_NE(std::string(config_store_error_text(st.error)).find("refused"), std::string::npos);
        EXPECT_EQ(fl.sector(0), copy.sector(0));
        EXPECT_EQ(fl.sector(1), copy.sector(1));
        fl.refuse = false;
        EXPECT_TRUE(same_values(restart(fl, sc), values_of(sc, before)));
    }
}

// A driver that says it programmed or erased while a word did not take:
// the read-back catches it (VERIFY, NOT_ERASED) and the previous record
// stays the newest.
TEST(ConfigStore, ReadBackCatchesAWordThatDidNotTake)
{
    const Schema sc(0x5C4E0001u, 4);
    SimFlash fl(64);
    ASSERT_TRUE(save(fl, sc, values_of(sc, 1)));
    fl.stuck_sector = 0;
    fl.stuck_word = CONFIG_RECORD_WORDS(4) + 6;  // the second record's first value
    fl.stuck_mask = 0x00000001u;                 // bit 0 stays 1 (2000 has it 0)
    config_store_t st;
    EXPECT_FALSE(save(fl, sc, values_of(sc, 2), &st));
    EXPECT_EQ(st.error, CONFIG_ERR_VERIFY);
    EXPECT_TRUE(same_values(restart(fl, sc), values_of(sc, 1)));

    SimFlash fl2(64);
    for (uint32_t k = 1; k <= 3; ++k) ASSERT_TRUE(save(fl2, sc, values_of(sc, k)));
    fl2.sector(1)[5] = 0;  // to be erased
    fl2.stuck_sector = 1;
    fl2.stuck_word = 5;
    fl2.stuck_mask = 0x80000000u;  // bit 31 stays 0 through the erase
    EXPECT_FALSE(save(fl2, sc, values_of(sc, 4), &st));
    EXPECT_EQ(st.error, CONFIG_ERR_NOT_ERASED);
    EXPECT_TRUE(same_values(restart(fl2, sc), values_of(sc, 3)));
}

// init refuses what the store cannot run: NULLs, a missing operation, no
// entries, an id twice, a record larger than a sector; save refuses values
// of another table.
TEST(ConfigStore, BadArgumentsAreRefused)
{
    Schema sc(0x5C4E0001u, 4);
    SimFlash fl(64);
    flash_if_t f = fl.interface();
    config_store_t st;
    EXPECT_FALSE(config_store_init(&st, nullptr, &sc.s));
    EXPECT_EQ(st.error, CONFIG_ERR_ARGS);
    EXPECT_FALSE(config_store_init(&st, &f, nullptr));
    flash_if_t no_erase = f;
    no_erase.erase = nullptr;
    EXPECT_FALSE(config_store_init(&st, &no_erase, &sc.s));
    config_schema_t empty = sc.s;
    empty.n_entries = 0;
    EXPECT_FALSE(config_store_init(&st, &f, &empty));
    Schema twice(1u, 3);
    twice.defaults[2].id = twice.defaults[0].id;
    EXPECT_FALSE(config_store_init(&st, &f, &twice.s));
    EXPECT_EQ(st.error, CONFIG_ERR_ARGS);
    const Schema big(1u, 20);  // 66 words > 64
    EXPECT_FALSE(config_store_init(&st, &f, &big.s));
    EXPECT_EQ(st.error, CONFIG_ERR_TOO_LARGE);
    const Schema fits(1u, 19);  // 63 words
    EXPECT_TRUE(config_store_init(&st, &f, &fits.s));

    ASSERT_TRUE(config_store_init(&st, &f, &sc.s));
    std::vector<config_entry_t> v = values_of(sc, 1);
    v[2].def_hash ^= 1u;
    EXPECT_FALSE(config_store_save(&st, v.data()));
    EXPECT_EQ(st.error, CONFIG_ERR_NOT_SCHEMA);
    EXPECT_EQ(fl.ops, 0u) << "nothing written";
    EXPECT_STREQ(config_store_last_error(&st), config_store_error_text(CONFIG_ERR_NOT_SCHEMA));
}
