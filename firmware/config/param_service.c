/*
 * param_service.c - the parameters of a running board served by id
 * (param_service.h).
 */
#include "config/param_service.h"

#include <stddef.h>
#include <string.h>

static bool fail(param_error_t *err, param_status_t status, uint16_t id, const char *text)
{
    if (err != NULL) {
        err->status = status;
        err->id = id;
        err->text = text;
    }
    return false;
}

static bool done(param_error_t *err)
{
    if (err != NULL) {
        err->status = PARAM_OK;
        err->id = PARAM_ID_NONE;
        err->text = "";
    }
    return true;
}

const param_table_t *param_service_table(const param_service_t *s, uint16_t id, void **target)
{
    const uint32_t k = (id <= PARAM_ID_BOARD_LAST) ? 0u : 1u;
    if (target != NULL) {
        *target = s->targets[k];
    }
    return s->tables[k];
}

/* The descriptor of the store's entry k (both tables' parameters in turn). */
static const param_desc_t *entry_desc(const param_service_t *s, uint32_t k)
{
    for (uint32_t t = 0; t < PARAM_SERVICE_TABLES; ++t) {
        if (s->tables[t] == NULL) continue;
        if (k < s->tables[t]->n_params) return &s->tables[t]->params[k];
        k -= s->tables[t]->n_params;
    }
    return NULL;
}

bool param_service_init(param_service_t *s, const param_table_t *board, void *board_target, const param_table_t *drive,
                        void *drive_target, config_store_t *store, const flash_if_t *flash, param_apply_fn apply,
                        void *apply_ctx, param_error_t *err)
{
    if (s == NULL || apply == NULL || (board == NULL && drive == NULL)) {
        return fail(err, PARAM_ERR_BAD_REQUEST, PARAM_ID_NONE, "param_service_init: no service, hook or table");
    }
    memset(s, 0, sizeof(*s));
    s->tables[0] = board;
    s->tables[1] = drive;
    s->targets[0] = board_target;
    s->targets[1] = drive_target;
    s->store = store;
    s->apply = apply;
    s->apply_ctx = apply_ctx;
    s->last_error.id = PARAM_ID_NONE;
    s->last_error.text = "";
    uint32_t n = 0;
    uint32_t hashes[PARAM_SERVICE_TABLES] = {0u, 0u};
    for (uint32_t t = 0; t < PARAM_SERVICE_TABLES; ++t) {
        const param_table_t *tab = s->tables[t];
        if (tab == NULL) continue;
        if (s->targets[t] == NULL) return fail(err, PARAM_ERR_BAD_REQUEST, PARAM_ID_NONE, "a table without a target");
        if (!params_table_check(tab, err)) return false;
        const bool board_range = tab->n_params == 0u || tab->params[0].id <= PARAM_ID_BOARD_LAST;
        if (board_range != (t == 0u)) {
            return fail(err, PARAM_ERR_BAD_REQUEST, tab->n_params > 0u ? tab->params[0].id : PARAM_ID_NONE,
                        "the board's table holds ids 0x0001-0x00FF, the drive's from 0x0100");
        }
        if (n + tab->n_params > PARAM_SERVICE_MAX_ENTRIES) {
            return fail(err, PARAM_ERR_BAD_REQUEST, PARAM_ID_NONE, "more parameters than PARAM_SERVICE_MAX_ENTRIES");
        }
        for (uint32_t k = 0; k < tab->n_params; ++k) {
            const param_desc_t *d = &tab->params[k];
            s->defaults[n].id = d->id;
            s->defaults[n].def_hash = d->def_hash;
            s->defaults[n].value = d->def.u32;
            ++n;
        }
        hashes[t] = tab->schema_hash;
    }
    if (n == 0u) return fail(err, PARAM_ERR_BAD_REQUEST, PARAM_ID_NONE, "no parameters");
    s->schema.hash = config_crc32(0u, hashes, PARAM_SERVICE_TABLES);
    s->schema.defaults = s->defaults;
    s->schema.n_entries = (uint16_t)n;
    if (store != NULL && !config_store_init(store, flash, &s->schema)) {
        return fail(err, PARAM_ERR_STORE_FAILED, PARAM_ID_NONE, config_store_last_error(store));
    }
    return done(err);
}

/* Every entry of values whose bits differ from the target's now into the
 * target (read-only ones are the image's and never written); the number
 * refused. */
static uint32_t write_entries(param_service_t *s, const config_entry_t *values)
{
    uint32_t refused = 0;
    for (uint32_t k = 0; k < s->schema.n_entries; ++k) {
        const param_desc_t *d = entry_desc(s, k);
        if (d->access == PARAM_RO) continue;
        void *target = NULL;
        const param_table_t *t = param_service_table(s, d->id, &target);
        param_value_t now;
        if (!params_read(t, target, d->id, &now, NULL)) {
            ++refused;
            continue;
        }
        if (now.u32 == values[k].value) continue; /* unchanged: the exact value stays */
        param_value_t v;
        v.u32 = values[k].value;
        if (!params_write(t, target, d->id, v, false, NULL)) ++refused;
    }
    return refused;
}

static bool apply_all(param_service_t *s, param_error_t *err)
{
    s->ready = s->apply(s->apply_ctx, NULL, PARAM_ID_NONE, err);
    return s->ready;
}

bool param_service_start(param_service_t *s, bool keep_targets, uint32_t *n_refused, param_error_t *err)
{
    uint32_t refused = 0;
    for (uint32_t k = 0; k < s->schema.n_entries; ++k) {
        const param_desc_t *d = entry_desc(s, k);
        void *target = NULL;
        const param_table_t *t = param_service_table(s, d->id, &target);
        if (keep_targets) {
            param_value_t v;
            if (params_read(t, target, d->id, &v, NULL)) s->defaults[k].value = v.u32;
        }
    }
    if (!keep_targets) {
        for (uint32_t t = 0; t < PARAM_SERVICE_TABLES; ++t) {
            if (s->tables[t] != NULL && !params_set_defaults(s->tables[t], s->targets[t], err)) return false;
        }
    }
    if (s->store != NULL && config_store_load(s->store, s->values)) {
        refused = write_entries(s, s->values);
    }
    if (n_refused != NULL) *n_refused = refused;
    return apply_all(s, err);
}

/* The reply's value: the parameter's now (0 if it cannot be read). */
static param_value_t value_of(const param_service_t *s, uint16_t id)
{
    param_value_t v;
    v.u32 = 0u;
    void *target = NULL;
    const param_table_t *t = param_service_table(s, id, &target);
    if (t == NULL || !params_read(t, target, id, &v, NULL)) v.u32 = 0u;
    return v;
}

static bool op_save(param_service_t *s, bool enabled, param_error_t *err)
{
    if (enabled) return fail(err, PARAM_ERR_NOT_WHILE_ENABLED, PARAM_ID_NONE, "save: the bridge is enabled");
    if (s->store == NULL) return fail(err, PARAM_ERR_STORE_FAILED, PARAM_ID_NONE, "save: this image has no store");
    if (!s->ready) {
        return fail(err, PARAM_ERR_DESIGN_REFUSED, PARAM_ID_NONE, "save: the parameters do not design, not saved");
    }
    for (uint32_t k = 0; k < s->schema.n_entries; ++k) {
        s->values[k] = s->defaults[k];
        s->values[k].value = value_of(s, s->defaults[k].id).u32;
    }
    if (!config_store_save(s->store, s->values)) {
        return fail(err, PARAM_ERR_STORE_FAILED, PARAM_ID_NONE, config_store_last_error(s->store));
    }
    return done(err);
}

static bool op_write(param_service_t *s, const param_request_t *req, bool enabled, param_error_t *err)
{
    void *target = NULL;
    const param_table_t *t = param_service_table(s, req->id, &target);
    if (t == NULL) return fail(err, PARAM_ERR_UNKNOWN_ID, req->id, "no parameter of this id in the image");
    if (!params_write(t, target, req->id, req->value, enabled, err)) return false;
    s->ready = s->apply(s->apply_ctx, t, req->id, err);
    return s->ready;
}

static bool op_list(const param_service_t *s, const param_request_t *req, uint16_t *id, param_error_t *err)
{
    for (uint32_t t = 0; t < PARAM_SERVICE_TABLES; ++t) {
        if (s->tables[t] == NULL) continue;
        const param_desc_t *d = params_next(s->tables[t], req->id);
        if (d != NULL) {
            *id = d->id;
            return done(err);
        }
    }
    *id = PARAM_ID_NONE;
    return fail(err, PARAM_ERR_UNKNOWN_ID, PARAM_ID_NONE, "list: no parameter at or after this id");
}

void param_service_request(param_service_t *s, const param_request_t *req, bool enabled, param_reply_t *reply)
{
    param_error_t err;
    err.status = PARAM_OK;
    err.id = PARAM_ID_NONE;
    err.text = "";
    reply->op = req->op;
    reply->seq = req->seq;
    reply->id = req->id;
    reply->value.u32 = 0u;
    bool ok = false;
    bool with_value = false;
    switch (req->op) {
    case PARAM_OP_READ: {
        void *target = NULL;
        const param_table_t *t = param_service_table(s, req->id, &target);
        ok = t != NULL ? params_read(t, target, req->id, &reply->value, &err)
                       : fail(&err, PARAM_ERR_UNKNOWN_ID, req->id, "no parameter of this id in the image");
        break;
    }
    case PARAM_OP_WRITE:
        ok = op_write(s, req, enabled, &err);
        with_value = err.status == PARAM_OK || err.status == PARAM_ERR_DESIGN_REFUSED;
        break;
    case PARAM_OP_SAVE: ok = op_save(s, enabled, &err); break;
    case PARAM_OP_DEFAULTS:
        if (enabled) {
            ok = fail(&err, PARAM_ERR_NOT_WHILE_ENABLED, PARAM_ID_NONE, "defaults: the bridge is enabled");
        } else {
            (void)write_entries(s, s->defaults);
            ok = apply_all(s, &err);
        }
        break;
    case PARAM_OP_LIST:
        ok = op_list(s, req, &reply->id, &err);
        with_value = ok;
        break;
    default: ok = fail(&err, PARAM_ERR_BAD_REQUEST, req->id, "unknown op"); break;
    }
    if (with_value) reply->value = value_of(s, reply->id);
    reply->status = ok ? PARAM_OK : err.status;
    if (ok) {
        ++s->served;
    } else {
        ++s->refused;
        s->last_error = err;
    }
}

uint8_t param_service_config_source(const param_service_t *s)
{
    if (s->store == NULL) return 0u;
    switch (s->store->source) {
    case CONFIG_SOURCE_RECORD: return 1u;
    case CONFIG_SOURCE_MIGRATED: return 2u;
    case CONFIG_SOURCE_DEFAULTS: return s->store->defaults_reason == CONFIG_ERR_NO_RECORD ? 3u : 4u;
    default: return 0u;
    }
}
