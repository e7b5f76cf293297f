/*
 * config_store.h - the drive's configuration kept in flash across power
 * cuts: a set of parameters, each an id, a hash of its definition and 32
 * bits of value, written as one record with a magic word, the format's
 * version, the schema's hash, a sequence number and a CRC-32, then a
 * commit word written last. A record counts only once its commit word
 * reads back whole, so a cut at any point of a save (in the middle of a
 * word included) leaves the previous record the newest: after a restart
 * the drive has the old configuration or the new one, never a mix.
 * Records are appended one after the other in a sector (a log); when one
 * does not fit, the newest is written at the start of the other sector,
 * erased first (ping-pong: the sector holding the newest record is never
 * the one erased). At start the newest valid record of both sectors by
 * sequence number is read; with none, the defaults, and the store says so
 * (loaded_defaults, defaults_reason: for the telemetry). A record of
 * another schema keeps the parameters whose id and definition hash are
 * both in the current schema and defaults the others. Each write is read
 * back and compared. The store is generic over the parameter table: it
 * takes the schema (its hash and the defaults, in the table's order) and
 * never interprets a value. No allocation, no float, no global state; the
 * flash is reached through config/flash_if.h. Record format and the power
 * cut argument: docs/config_store.md.
 */
#ifndef CONFIG_CONFIG_STORE_H
#define CONFIG_CONFIG_STORE_H

#include <stdbool.h>
#include <stdint.h>

#include "config/flash_if.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Record layout, in 32-bit words (docs/config_store.md):
 *   [0] CONFIG_MAGIC
 *   [1] CONFIG_FORMAT_VERSION in bits 0-15, the entry count n in bits 16-31
 *   [2] schema hash
 *   [3] sequence number (1 for the first record ever written)
 *   [4 + 3 i] id of entry i (bits 0-15; bits 16-31 zero), [5 + 3 i] its
 *       definition hash, [6 + 3 i] its value's bits, i = 0 .. n-1
 *   [4 + 3 n] CRC-32 of words 0 .. 3 + 3 n
 *   [5 + 3 n] CONFIG_COMMIT, written last */
#define CONFIG_MAGIC 0x43464731u /* "1GFC" in memory: a record starts here */
#define CONFIG_FORMAT_VERSION 1u
#define CONFIG_COMMIT 0x00000000u /* every bit of the erased word cleared: any cut leaves one set */
#define CONFIG_HEADER_WORDS 4u
#define CONFIG_ENTRY_WORDS 3u
#define CONFIG_TRAILER_WORDS 2u /* the CRC, the commit word */
/* Entries in a schema: bounds the load's search (n x n comparisons at
 * start) and a record to 774 words, well within a 16 KB sector. */
#define CONFIG_MAX_ENTRIES 256u

/* The words of a record of n entries. */
#define CONFIG_RECORD_WORDS(n) (CONFIG_HEADER_WORDS + CONFIG_ENTRY_WORDS * (uint32_t)(n) + CONFIG_TRAILER_WORDS)

/* One parameter: its id in the table, the hash of its definition (name,
 * unit, type, range: what makes an old value still mean the same), its
 * value's 32 bits (a float's, an integer's: the table knows which). */
typedef struct {
    uint16_t id;
    uint32_t def_hash;
    uint32_t value;
} config_entry_t;

/* The parameter table as the store sees it. */
typedef struct {
    uint32_t hash;                  /* of the whole table: equal hashes, equal tables */
    const config_entry_t *defaults; /* n_entries, ids unique, in the table's order */
    uint16_t n_entries;             /* 1 .. CONFIG_MAX_ENTRIES */
} config_schema_t;

typedef enum {
    CONFIG_OK = 0,
    CONFIG_ERR_ARGS = 1,            /* a NULL, an operation missing, no entries, too many, an id twice */
    CONFIG_ERR_TOO_LARGE = 2,       /* a record of the schema does not fit a sector */
    CONFIG_ERR_NOT_SCHEMA = 3,      /* values to save whose ids or definition hashes are not the schema's */
    CONFIG_ERR_NO_RECORD = 4,       /* load: both sectors erased (a new board): the defaults */
    CONFIG_ERR_NO_VALID_RECORD = 5, /* load: something written, no record whole and valid: the defaults */
    CONFIG_ERR_FLASH_REFUSED = 6,   /* the flash refused (the bridge is enabled): nothing written */
    CONFIG_ERR_ERASE = 7,           /* the erase failed (the driver's error says how) */
    CONFIG_ERR_NOT_ERASED = 8,      /* the sector read back after its erase holds a word not erased */
    CONFIG_ERR_PROGRAM = 9,         /* a program failed (the driver's error says how) */
    CONFIG_ERR_VERIFY = 10,         /* a word read back differs from the word written */
    CONFIG_ERR_SEQUENCE = 11        /* the sequence number would wrap (2^32 - 1 saves) */
} config_error_t;

/* Where the values of the last load came from. */
typedef enum {
    CONFIG_SOURCE_NONE = 0,     /* not loaded */
    CONFIG_SOURCE_RECORD = 1,   /* a record of this schema: every value */
    CONFIG_SOURCE_MIGRATED = 2, /* a record of another schema: n_kept values, n_defaulted defaults */
    CONFIG_SOURCE_DEFAULTS = 3  /* no valid record: the defaults (defaults_reason) */
} config_source_t;

typedef struct {
    const flash_if_t *flash;
    config_schema_t schema;
    /* the last load, for the telemetry */
    config_source_t source;
    bool loaded_defaults;           /* source == CONFIG_SOURCE_DEFAULTS */
    config_error_t defaults_reason; /* CONFIG_ERR_NO_RECORD or CONFIG_ERR_NO_VALID_RECORD; CONFIG_OK otherwise */
    uint16_t n_kept, n_defaulted;   /* values taken from the record, and from the defaults */
    /* the newest record (after a load or a save) */
    bool has_record;
    uint32_t seq;    /* its sequence number (0: none) */
    uint32_t sector; /* where it is: sector and word offset */
    uint32_t offset;
    /* since init */
    uint32_t saves;          /* saves that succeeded */
    uint32_t compactions;    /* of them, those that erased the other sector */
    config_error_t error;    /* the last failure's, CONFIG_OK after a success */
    const char *flash_error; /* the flash driver's text of the last flash failure, "" if none */
} config_store_t;

/* Binds the store to its flash and schema (both kept by pointer: they
 * outlive the store). Reads nothing. False (error set) on bad arguments
 * or a schema whose record does not fit a sector. */
bool config_store_init(config_store_t *s, const flash_if_t *flash, const config_schema_t *schema);

/* values[0 .. n_entries): the schema's defaults overlaid with the newest
 * valid record's values of the same id and definition hash. True when
 * values holds the configuration, the defaults included (the store's
 * source, loaded_defaults and defaults_reason say which); false only on
 * bad arguments. */
bool config_store_load(config_store_t *s, config_entry_t *values);

/* Writes values (the schema's ids and definition hashes, in its order) as
 * the newest record: after the newest in its sector if it fits there,
 * else at the start of the other sector, erased first. Each write read
 * back. False (error set, flash_error the driver's text) if anything
 * failed or was refused: the previous record then stays the newest. */
bool config_store_save(config_store_t *s, const config_entry_t *values);

/* A short English text for an error, never NULL. */
const char *config_store_error_text(config_error_t e);

/* The text of the store's last error ("ok" if none). */
const char *config_store_last_error(const config_store_t *s);

/* CRC-32 (IEEE 802.3: reflected, polynomial 0xEDB88320, initial and final
 * XOR 0xFFFFFFFF) over n words, each as its 4 bytes least significant
 * first (the bytes in memory on the Cortex-M: zlib's crc32 of a dump).
 * Continue with crc = the previous result (0 to start). */
uint32_t config_crc32(uint32_t crc, const uint32_t *words, uint32_t n);

#ifdef __cplusplus
}
#endif

#endif /* CONFIG_CONFIG_STORE_H */
