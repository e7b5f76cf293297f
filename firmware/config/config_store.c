#include "config/config_store.h"

#include <stddef.h>

/* CRC-32 four bits at a time: 16 entries (64 bytes of flash) against the
 * 1 KB of a byte table; a save or a load reads at most two sectors. */
static const uint32_t crc_nibble[16] = {0x00000000u, 0x1DB71064u, 0x3B6E20C8u, 0x26D930ACu, 0x76DC4190u, 0x6B6B51F4u,
                                        0x4DB26158u, 0x5005713Cu, 0xEDB88320u, 0xF00F9344u, 0xD6D6A3E8u, 0xCB61B38Cu,
                                        0x9B64C2B0u, 0x86D3D2D4u, 0xA00AE278u, 0xBDBDF21Cu};

uint32_t config_crc32(uint32_t crc, const uint32_t *words, uint32_t n)
{
    uint32_t c = ~crc;
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t w = words[i];
        for (uint32_t b = 0; b < 32u; b += 4u) { /* the word's bytes least significant first */
            c ^= (w >> b) & 0xFu;
            c = (c >> 4) ^ crc_nibble[c & 0xFu];
        }
    }
    return ~c;
}

const char *config_store_error_text(config_error_t e)
{
    switch (e) {
    case CONFIG_OK: return "ok";
    case CONFIG_ERR_ARGS: return "bad arguments (NULL, an operation missing, no or too many entries, an id twice)";
    case CONFIG_ERR_TOO_LARGE: return "a record of the schema does not fit a sector";
    case CONFIG_ERR_NOT_SCHEMA: return "values not of the schema (ids or definition hashes)";
    case CONFIG_ERR_NO_RECORD: return "no record: both sectors erased, defaults";
    case CONFIG_ERR_NO_VALID_RECORD: return "no valid record (CRC, commit word or format): defaults";
    case CONFIG_ERR_FLASH_REFUSED: return "the flash refused the save (bridge enabled?): nothing written";
    case CONFIG_ERR_ERASE: return "flash erase failed";
    case CONFIG_ERR_NOT_ERASED: return "sector not erased after its erase";
    case CONFIG_ERR_PROGRAM: return "flash program failed";
    case CONFIG_ERR_VERIFY: return "a word read back differs from the word written";
    case CONFIG_ERR_SEQUENCE: return "sequence number exhausted";
    default: return "unknown error";
    }
}

const char *config_store_last_error(const config_store_t *s)
{
    return s != NULL ? config_store_error_text(s->error) : config_store_error_text(CONFIG_ERR_ARGS);
}

static bool fail(config_store_t *s, config_error_t e)
{
    s->error = e;
    return false;
}

/* The words of the record at offset of a sector of sector_words words, if
 * it is a whole and valid one (magic, this format, its length within the
 * sector, its CRC, its commit word); 0 otherwise. */
static uint32_t record_at(const uint32_t *base, uint32_t sector_words, uint32_t offset)
{
    if (offset > sector_words || sector_words - offset < CONFIG_RECORD_WORDS(0)) {
        return 0;
    }
    const uint32_t *r = base + offset;
    if (r[0] != CONFIG_MAGIC || (r[1] & 0xFFFFu) != CONFIG_FORMAT_VERSION) {
        return 0;
    }
    const uint32_t n = r[1] >> 16;
    const uint32_t len = CONFIG_RECORD_WORDS(n);
    if (n > CONFIG_MAX_ENTRIES || len > sector_words - offset) {
        return 0;
    }
    const uint32_t body = CONFIG_HEADER_WORDS + CONFIG_ENTRY_WORDS * n;
    if (config_crc32(0, r, body) != r[body] || r[body + 1u] != CONFIG_COMMIT) {
        return 0;
    }
    return len;
}

/* One sector's log: its valid records from offset 0 one after the other,
 * up to the first word that does not start one (erased, or a record cut
 * or corrupted: the log ends there and the sector takes no record after
 * it). The last record's sequence number and offset, and where the log
 * ends. Bounded: a record is at least CONFIG_RECORD_WORDS(0) words. */
typedef struct {
    bool any;        /* a valid record */
    uint32_t seq;    /* the last one's */
    uint32_t offset; /* the last one's */
    uint32_t end;    /* the first word after the log */
    bool blank;      /* every word of the sector erased */
} sector_log_t;

static sector_log_t scan_sector(const flash_if_t *f, uint32_t sector)
{
    const uint32_t *base = f->base[sector];
    sector_log_t l = {.any = false, .seq = 0, .offset = 0, .end = 0, .blank = false};
    for (;;) {
        const uint32_t len = record_at(base, f->sector_words, l.end);
        if (len == 0u) {
            break;
        }
        l.any = true;
        l.seq = base[l.end + 3u];
        l.offset = l.end;
        l.end += len;
    }
    l.blank = !l.any;
    for (uint32_t i = 0; i < f->sector_words && l.blank; ++i) {
        l.blank = base[i] == FLASH_IF_ERASED;
    }
    return l;
}

/* The newest valid record of both sectors (the lower sector on a tie,
 * which the saves never make). */
typedef struct {
    bool any;
    uint32_t sector;
    sector_log_t log[FLASH_IF_SECTORS];
} flash_view_t;

static flash_view_t scan(const flash_if_t *f)
{
    flash_view_t v = {.any = false, .sector = 0};
    for (uint32_t k = 0; k < FLASH_IF_SECTORS; ++k) {
        v.log[k] = scan_sector(f, k);
        if (v.log[k].any && (!v.any || v.log[k].seq > v.log[v.sector].seq)) {
            v.any = true;
            v.sector = k;
        }
    }
    return v;
}

bool config_store_init(config_store_t *s, const flash_if_t *flash, const config_schema_t *schema)
{
    if (s == NULL) {
        return false;
    }
    *s = (config_store_t){.flash = flash, .error = CONFIG_OK, .flash_error = ""};
    if (flash == NULL || schema == NULL || flash->erase == NULL || flash->program == NULL || flash->error == NULL ||
        schema->defaults == NULL || schema->n_entries == 0u || schema->n_entries > CONFIG_MAX_ENTRIES) {
        return fail(s, CONFIG_ERR_ARGS);
    }
    for (uint32_t k = 0; k < FLASH_IF_SECTORS; ++k) {
        if (flash->base[k] == NULL) {
            return fail(s, CONFIG_ERR_ARGS);
        }
    }
    for (uint32_t i = 0; i < schema->n_entries; ++i) {
        for (uint32_t j = i + 1u; j < schema->n_entries; ++j) {
            if (schema->defaults[i].id == schema->defaults[j].id) {
                return fail(s, CONFIG_ERR_ARGS);
            }
        }
    }
    if (CONFIG_RECORD_WORDS(schema->n_entries) > flash->sector_words) {
        return fail(s, CONFIG_ERR_TOO_LARGE);
    }
    s->schema = *schema;
    return true;
}

bool config_store_load(config_store_t *s, config_entry_t *values)
{
    if (s == NULL || values == NULL || s->flash == NULL || s->schema.defaults == NULL) {
        return s != NULL ? fail(s, CONFIG_ERR_ARGS) : false;
    }
    const flash_if_t *f = s->flash;
    const uint16_t n = s->schema.n_entries;
    for (uint32_t i = 0; i < n; ++i) {
        values[i] = s->schema.defaults[i];
    }
    const flash_view_t v = scan(f);
    s->has_record = v.any;
    s->error = CONFIG_OK;
    if (!v.any) {
        s->source = CONFIG_SOURCE_DEFAULTS;
        s->loaded_defaults = true;
        s->defaults_reason = v.log[0].blank && v.log[1].blank ? CONFIG_ERR_NO_RECORD : CONFIG_ERR_NO_VALID_RECORD;
        s->n_kept = 0;
        s->n_defaulted = n;
        s->seq = 0;
        s->sector = 0;
        s->offset = 0;
        return true;
    }
    const sector_log_t *l = &v.log[v.sector];
    const uint32_t *r = f->base[v.sector] + l->offset;
    const uint32_t m = r[1] >> 16;
    uint16_t kept = 0;
    for (uint32_t i = 0; i < n; ++i) {
        for (uint32_t j = 0; j < m; ++j) {
            const uint32_t *e = &r[CONFIG_HEADER_WORDS + CONFIG_ENTRY_WORDS * j];
            if (e[0] == values[i].id) {
                if (e[1] == values[i].def_hash) {
                    values[i].value = e[2];
                    ++kept;
                }
                break; /* the first entry of an id is its entry */
            }
        }
    }
    s->n_kept = kept;
    s->n_defaulted = (uint16_t)(n - kept);
    s->source = r[2] == s->schema.hash && kept == n ? CONFIG_SOURCE_RECORD : CONFIG_SOURCE_MIGRATED;
    s->loaded_defaults = false;
    s->defaults_reason = CONFIG_OK;
    s->seq = l->seq;
    s->sector = v.sector;
    s->offset = l->offset;
    return true;
}

/* the driver's answer as the store's error */
static bool flash_failed(config_store_t *s, flash_if_result_t r, config_error_t failed)
{
    s->flash_error = s->flash->error(s->flash->ctx);
    return fail(s, r == FLASH_IF_REFUSED ? CONFIG_ERR_FLASH_REFUSED : failed);
}

/* programs words[0..n) at (sector, *offset), reads them back, advances
 * *offset; *crc continued over them when crc is not NULL */
static bool put(config_store_t *s, uint32_t sector, uint32_t *offset, const uint32_t *words, uint32_t n, uint32_t *crc)
{
    const flash_if_t *f = s->flash;
    const flash_if_result_t r = f->program(f->ctx, sector, *offset, words, n);
    if (r != FLASH_IF_OK) {
        return flash_failed(s, r, CONFIG_ERR_PROGRAM);
    }
    const uint32_t *back = f->base[sector] + *offset;
    for (uint32_t i = 0; i < n; ++i) {
        if (back[i] != words[i]) {
            return fail(s, CONFIG_ERR_VERIFY);
        }
    }
    if (crc != NULL) {
        *crc = config_crc32(*crc, words, n);
    }
    *offset += n;
    return true;
}

bool config_store_save(config_store_t *s, const config_entry_t *values)
{
    if (s == NULL || values == NULL || s->flash == NULL || s->schema.defaults == NULL) {
        return s != NULL ? fail(s, CONFIG_ERR_ARGS) : false;
    }
    const flash_if_t *f = s->flash;
    const uint16_t n = s->schema.n_entries;
    s->flash_error = "";
    for (uint32_t i = 0; i < n; ++i) {
        if (values[i].id != s->schema.defaults[i].id || values[i].def_hash != s->schema.defaults[i].def_hash) {
            return fail(s, CONFIG_ERR_NOT_SCHEMA);
        }
    }
    /* the flash is the state: read again, whatever happened since */
    const flash_view_t v = scan(f);
    const uint32_t seq = v.any ? v.log[v.sector].seq : 0u;
    if (seq == UINT32_MAX) {
        return fail(s, CONFIG_ERR_SEQUENCE);
    }
    const uint32_t len = CONFIG_RECORD_WORDS(n);
    /* after the newest record, or at the start of sector 0 without one:
     * if the record fits there and every word it takes is erased */
    uint32_t sector = v.any ? v.sector : 0u;
    uint32_t at = v.any ? v.log[sector].end : 0u;
    bool append = len <= f->sector_words - at;
    for (uint32_t i = 0; i < len && append; ++i) {
        append = f->base[sector][at + i] == FLASH_IF_ERASED;
    }
    if (!append) {
        /* the other sector, which holds no record newer than the newest
         * (sector 0 on a flash without a record): erased, then checked */
        sector = v.any ? 1u - v.sector : 0u;
        at = 0;
        const flash_if_result_t r = f->erase(f->ctx, sector);
        if (r != FLASH_IF_OK) {
            return flash_failed(s, r, CONFIG_ERR_ERASE);
        }
        for (uint32_t i = 0; i < f->sector_words; ++i) {
            if (f->base[sector][i] != FLASH_IF_ERASED) {
                return fail(s, CONFIG_ERR_NOT_ERASED);
            }
        }
    }
    const uint32_t start = at;
    uint32_t crc = 0;
    const uint32_t header[CONFIG_HEADER_WORDS] = {CONFIG_MAGIC, CONFIG_FORMAT_VERSION | ((uint32_t)n << 16),
                                                  s->schema.hash, seq + 1u};
    if (!put(s, sector, &at, header, CONFIG_HEADER_WORDS, &crc)) {
        return false;
    }
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t e[CONFIG_ENTRY_WORDS] = {values[i].id, values[i].def_hash, values[i].value};
        if (!put(s, sector, &at, e, CONFIG_ENTRY_WORDS, &crc)) {
            return false;
        }
    }
    /* the CRC, then the commit word alone: the record counts from here */
    const uint32_t commit[2] = {crc, CONFIG_COMMIT};
    if (!put(s, sector, &at, &commit[0], 1u, NULL) || !put(s, sector, &at, &commit[1], 1u, NULL)) {
        return false;
    }
    s->has_record = true;
    s->seq = seq + 1u;
    s->sector = sector;
    s->offset = start;
    s->saves++;
    if (!append) {
        s->compactions++;
    }
    s->error = CONFIG_OK;
    return true;
}
