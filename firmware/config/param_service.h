/*
 * param_service.h - the parameters of a running board, served by id: the
 * board's table and its drive's (config/params.h) bound to the structs
 * they set, the configuration store (config/config_store.h) that keeps
 * them across power cuts, and the application's hook that makes a change
 * take effect (a drive's parameter: the design runs again and the drive is
 * initialised from it; a telemetry period: the node's schedule). One call
 * answers one request (ParamRequest on CAN, tools/can/drive.dbc): read,
 * write, save, restore the defaults, list; each answer is done or a named
 * refusal (param_status_t) with a short text for the programs that can
 * show one. At start the store's newest record is loaded over the
 * defaults (a record of an older schema keeps what did not change) and the
 * hook runs once. A save while the bridge is enabled is refused here, not
 * only by the flash driver. A write the hook refuses (the design refused
 * the parameters) keeps the value, so that a change that needs two writes
 * can be made, and leaves the service not ready until a later change
 * designs: the application keeps the drive disabled meanwhile
 * (param_service_ready). No allocation, no global state; float and double
 * (the images that design on the board are float).
 */
#ifndef CONFIG_PARAM_SERVICE_H
#define CONFIG_PARAM_SERVICE_H

#include <stdbool.h>
#include <stdint.h>

#include "config/config_store.h"
#include "config/params.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The tables a service serves: the board's and the drive's. */
#define PARAM_SERVICE_TABLES 2u

/* The parameters of both tables together at most (the store's record and
 * the service's two entry arrays are sized by it: 2 x 96 x 12 B of RAM).
 * Today's largest pair: 10 of the board's and 30 of paper 000's. */
#define PARAM_SERVICE_MAX_ENTRIES 96u

/* A request as it travels (ParamRequest's signals; op the 4 bits as
 * received, a param_op_t or not: an unknown one is answered bad_request). */
typedef struct {
    uint8_t op;
    uint8_t seq;
    uint16_t id;
    param_value_t value;
} param_request_t;

/* Its answer (ParamReply's signals): op, seq echoed; id the parameter
 * answered (list: the one found, PARAM_ID_NONE past the last); value the
 * parameter's after the request (read, write, list), else 0. */
typedef struct {
    uint8_t op;
    param_status_t status;
    uint8_t seq;
    uint16_t id;
    param_value_t value;
} param_reply_t;

/* Makes a change take effect: t the table changed and id its parameter
 * (PARAM_ID_NONE after a load or the defaults: every parameter). True if
 * done; false with err set (PARAM_ERR_DESIGN_REFUSED and a text naming the
 * parameter and the reason): the service is then not ready. */
typedef bool (*param_apply_fn)(void *ctx, const param_table_t *t, uint16_t id, param_error_t *err);

typedef struct {
    const param_table_t *tables[PARAM_SERVICE_TABLES]; /* [0] the board's, [1] the drive's */
    void *targets[PARAM_SERVICE_TABLES];               /* the structs they set */
    config_store_t *store;                             /* NULL: no store (save refused: store_failed) */
    param_apply_fn apply;
    void *apply_ctx;
    config_schema_t schema;                             /* both tables' parameters for the store */
    config_entry_t defaults[PARAM_SERVICE_MAX_ENTRIES]; /* the base: the tables' defaults, or the targets' at start */
    config_entry_t values[PARAM_SERVICE_MAX_ENTRIES];   /* a load's and a save's */
    bool ready;                                         /* the last apply succeeded */
    param_error_t last_error;                           /* the last refusal (status PARAM_OK: none) */
    uint32_t served, refused;                           /* requests answered done, and refused */
} param_service_t;

/* Binds the tables to their targets, the store (or NULL) to its flash
 * (flash: NULL without a store) and the hook, and builds the store's
 * schema from the tables' defaults. Sets nothing in the targets. False
 * (err set) on a table that is not consistent (params_table_check), an id
 * in both, more than PARAM_SERVICE_MAX_ENTRIES parameters, or a store
 * refused. */
bool param_service_init(param_service_t *s, const param_table_t *board, void *board_target, const param_table_t *drive,
                        void *drive_target, config_store_t *store, const flash_if_t *flash, param_apply_fn apply,
                        void *apply_ctx, param_error_t *err);

/* The start: the base into both targets, then the store's newest record
 * over them (a value the table refuses keeps the base's and is counted in
 * *n_refused), then the hook once. The base is the tables' defaults, or
 * with keep_targets what the targets hold already (a host program's
 * scenario: a value the record does not change keeps its exact double).
 * True if the hook applied them; false (err set) if it refused: the
 * service is not ready. The store's own outcome (a record, migrated, the
 * defaults and why) is in the store's fields. */
bool param_service_start(param_service_t *s, bool keep_targets, uint32_t *n_refused, param_error_t *err);

/* One request; enabled: the bridge is enabled now. Always fills *reply.
 * Defaults: every value back to the base (not saved). */
void param_service_request(param_service_t *s, const param_request_t *req, bool enabled, param_reply_t *reply);

/* True after a start or a change the hook applied: the drive may be
 * enabled. */
static inline bool param_service_ready(const param_service_t *s) { return s->ready; }

/* Where the parameters came from at the start, as the heartbeat's
 * ConfigSource gives it (tools/can/drive.dbc): 0 no store, 1 the store's
 * record, 2 a record of another schema, 3 the defaults (nothing stored),
 * 4 the defaults (nothing whole and valid stored). */
uint8_t param_service_config_source(const param_service_t *s);

/* The table of id (the board's range or the drives'), or NULL. */
const param_table_t *param_service_table(const param_service_t *s, uint16_t id, void **target);

#ifdef __cplusplus
}
#endif

#endif /* CONFIG_PARAM_SERVICE_H */
