#include "config/params.h"

#include <math.h>
#include <string.h>

static bool fail(param_error_t *err, param_status_t s, uint16_t id, const char *text)
{
    if (err != NULL) {
        err->status = s;
        err->id = id;
        err->text = text;
    }
    return false;
}

static bool done(param_error_t *err, uint16_t id)
{
    if (err != NULL) {
        err->status = PARAM_OK;
        err->id = id;
        err->text = "done";
    }
    return true;
}

const char *params_status_name(param_status_t s)
{
    switch (s) {
    case PARAM_OK: return "done";
    case PARAM_ERR_UNKNOWN_ID: return "unknown_id";
    case PARAM_ERR_READ_ONLY: return "read_only";
    case PARAM_ERR_OUT_OF_RANGE: return "out_of_range";
    case PARAM_ERR_NOT_WHILE_ENABLED: return "not_while_enabled";
    case PARAM_ERR_BAD_VALUE: return "bad_value";
    case PARAM_ERR_DESIGN_REFUSED: return "design_refused";
    case PARAM_ERR_STORE_FAILED: return "store_failed";
    case PARAM_ERR_BAD_REQUEST: return "bad_request";
    case PARAM_ERR_BUSY: return "busy";
    }
    return "unknown_status";
}

const char *params_type_name(param_type_t type)
{
    switch (type) {
    case PARAM_F32: return "f32";
    case PARAM_I32: return "i32";
    case PARAM_U32: return "u32";
    case PARAM_BOOL: return "bool";
    case PARAM_ENUM: return "enum";
    }
    return "?";
}

const char *params_access_name(param_access_t access)
{
    switch (access) {
    case PARAM_RO: return "ro";
    case PARAM_DISABLED: return "disabled";
    case PARAM_LIVE: return "live";
    }
    return "?";
}

const param_desc_t *params_find(const param_table_t *t, uint16_t id, param_error_t *err)
{
    if (t == NULL) {
        (void)fail(err, PARAM_ERR_BAD_REQUEST, id, "no table");
        return NULL;
    }
    /* ascending ids (params_table_check): a binary search */
    uint32_t lo = 0u, hi = t->n_params;
    while (lo < hi) {
        const uint32_t mid = lo + (hi - lo) / 2u;
        const uint16_t m = t->params[mid].id;
        if (m == id) {
            (void)done(err, id);
            return &t->params[mid];
        }
        if (m < id) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    (void)fail(err, PARAM_ERR_UNKNOWN_ID, id, "no parameter of this id");
    return NULL;
}

const param_desc_t *params_next(const param_table_t *t, uint16_t id)
{
    if (t == NULL) return NULL;
    for (uint32_t k = 0; k < t->n_params; ++k) {
        if (t->params[k].id >= id) return &t->params[k];
    }
    return NULL;
}

bool params_check_value(const param_desc_t *d, param_value_t v, param_error_t *err)
{
    if (d == NULL) return fail(err, PARAM_ERR_BAD_REQUEST, PARAM_ID_NONE, "no parameter");
    switch (d->type) {
    case PARAM_F32:
        if (!isfinite(v.f32)) return fail(err, PARAM_ERR_BAD_VALUE, d->id, "not a finite number");
        if (!(v.f32 >= d->min.f32 && v.f32 <= d->max.f32)) {
            return fail(err, PARAM_ERR_OUT_OF_RANGE, d->id, "outside [min, max]");
        }
        break;
    case PARAM_I32:
        if (v.i32 < d->min.i32 || v.i32 > d->max.i32) {
            return fail(err, PARAM_ERR_OUT_OF_RANGE, d->id, "outside [min, max]");
        }
        break;
    case PARAM_U32:
        if (v.u32 < d->min.u32 || v.u32 > d->max.u32) {
            return fail(err, PARAM_ERR_OUT_OF_RANGE, d->id, "outside [min, max]");
        }
        break;
    case PARAM_BOOL:
        if (v.u32 > 1u) return fail(err, PARAM_ERR_BAD_VALUE, d->id, "a bool is 0 or 1");
        break;
    case PARAM_ENUM:
        if (v.i32 < 0 || v.i32 >= (int32_t)d->n_names) {
            return fail(err, PARAM_ERR_BAD_VALUE, d->id, "not one of the enum's values");
        }
        break;
    default: return fail(err, PARAM_ERR_BAD_VALUE, d->id, "unknown type");
    }
    return done(err, d->id);
}

bool params_may_write(const param_desc_t *d, bool enabled, param_error_t *err)
{
    if (d == NULL) return fail(err, PARAM_ERR_BAD_REQUEST, PARAM_ID_NONE, "no parameter");
    switch (d->access) {
    case PARAM_RO: return fail(err, PARAM_ERR_READ_ONLY, d->id, "read-only");
    case PARAM_DISABLED:
        if (enabled) return fail(err, PARAM_ERR_NOT_WHILE_ENABLED, d->id, "only while the bridge is disabled");
        break;
    case PARAM_LIVE: break;
    default: return fail(err, PARAM_ERR_READ_ONLY, d->id, "unknown access");
    }
    return done(err, d->id);
}

/* The value of d's type as a double: an f32 equal to the default rounded
 * to float32 is the default's exact double (params.h). */
static double value_as_double(const param_desc_t *d, param_value_t v)
{
    switch (d->type) {
    case PARAM_F32: return v.f32 == d->def.f32 ? d->def_exact : (double)v.f32;
    case PARAM_I32:
    case PARAM_ENUM: return (double)v.i32;
    case PARAM_U32:
    case PARAM_BOOL: return (double)v.u32;
    }
    return 0.0;
}

/* Stores x (an integer where the field is one: the table's check makes
 * sure only integer types set integer fields) into the field at base. */
static void store_field(param_field_t field, unsigned char *at, double x)
{
    switch (field) {
    case PARAM_FIELD_DOUBLE: memcpy(at, &x, sizeof x); break;
    case PARAM_FIELD_INT: {
        const int i = (int)x;
        memcpy(at, &i, sizeof i);
        break;
    }
    case PARAM_FIELD_LONG: {
        const long l = (long)x;
        memcpy(at, &l, sizeof l);
        break;
    }
    case PARAM_FIELD_BOOL: {
        const bool b = x != 0.0;
        memcpy(at, &b, sizeof b);
        break;
    }
    case PARAM_FIELD_UINT: {
        const unsigned int u = (unsigned int)x;
        memcpy(at, &u, sizeof u);
        break;
    }
    case PARAM_FIELD_ULONG: {
        const unsigned long u = (unsigned long)x;
        memcpy(at, &u, sizeof u);
        break;
    }
    }
}

static double load_field(param_field_t field, const unsigned char *at)
{
    switch (field) {
    case PARAM_FIELD_DOUBLE: {
        double x;
        memcpy(&x, at, sizeof x);
        return x;
    }
    case PARAM_FIELD_INT: {
        int i;
        memcpy(&i, at, sizeof i);
        return (double)i;
    }
    case PARAM_FIELD_LONG: {
        long l;
        memcpy(&l, at, sizeof l);
        return (double)l;
    }
    case PARAM_FIELD_BOOL: {
        bool b;
        memcpy(&b, at, sizeof b);
        return b ? 1.0 : 0.0;
    }
    case PARAM_FIELD_UINT: {
        unsigned int u;
        memcpy(&u, at, sizeof u);
        return (double)u;
    }
    case PARAM_FIELD_ULONG: {
        unsigned long u;
        memcpy(&u, at, sizeof u);
        return (double)u;
    }
    }
    return 0.0;
}

bool params_write(const param_table_t *t, void *target, uint16_t id, param_value_t v, bool enabled, param_error_t *err)
{
    if (target == NULL) return fail(err, PARAM_ERR_BAD_REQUEST, id, "no target");
    const param_desc_t *d = params_find(t, id, err);
    if (d == NULL) return false;
    if (!params_may_write(d, enabled, err) || !params_check_value(d, v, err)) return false;
    store_field(d->field, (unsigned char *)target + d->offset, value_as_double(d, v));
    return done(err, id);
}

bool params_read(const param_table_t *t, const void *target, uint16_t id, param_value_t *v, param_error_t *err)
{
    if (target == NULL || v == NULL) return fail(err, PARAM_ERR_BAD_REQUEST, id, "no target or value");
    const param_desc_t *d = params_find(t, id, err);
    if (d == NULL) return false;
    const double x = load_field(d->field, (const unsigned char *)target + d->offset);
    switch (d->type) {
    case PARAM_F32: v->f32 = (float)x; break;
    case PARAM_I32:
    case PARAM_ENUM: v->i32 = (int32_t)x; break;
    case PARAM_U32:
    case PARAM_BOOL: v->u32 = (uint32_t)x; break;
    }
    return done(err, id);
}

bool params_set_defaults(const param_table_t *t, void *target, param_error_t *err)
{
    if (t == NULL || target == NULL) return fail(err, PARAM_ERR_BAD_REQUEST, PARAM_ID_NONE, "no table or target");
    unsigned char *base = (unsigned char *)target;
    for (uint32_t k = 0; k < t->n_fixed; ++k) {
        store_field(t->fixed[k].field, base + t->fixed[k].offset, t->fixed[k].value);
    }
    for (uint32_t k = 0; k < t->n_params; ++k) {
        store_field(t->params[k].field, base + t->params[k].offset, t->params[k].def_exact);
    }
    return done(err, PARAM_ID_NONE);
}

static uint32_t field_bytes(param_field_t field)
{
    switch (field) {
    case PARAM_FIELD_DOUBLE: return (uint32_t)sizeof(double);
    case PARAM_FIELD_INT: return (uint32_t)sizeof(int);
    case PARAM_FIELD_LONG: return (uint32_t)sizeof(long);
    case PARAM_FIELD_BOOL: return (uint32_t)sizeof(bool);
    case PARAM_FIELD_UINT: return (uint32_t)sizeof(unsigned int);
    case PARAM_FIELD_ULONG: return (uint32_t)sizeof(unsigned long);
    }
    return 0u;
}

/* Which fields a type may set: f32 a double; the integers an integer
 * field (an enum's C type is unsigned int with GCC and Clang when it has
 * no negative value: the C enums the design inputs hold); a bool also a
 * bool. */
static bool field_fits(param_type_t type, param_field_t field)
{
    switch (type) {
    case PARAM_F32: return field == PARAM_FIELD_DOUBLE;
    case PARAM_I32:
    case PARAM_ENUM: return field == PARAM_FIELD_INT || field == PARAM_FIELD_LONG || field == PARAM_FIELD_UINT;
    case PARAM_U32: return field == PARAM_FIELD_UINT || field == PARAM_FIELD_ULONG || field == PARAM_FIELD_LONG;
    case PARAM_BOOL: return field == PARAM_FIELD_BOOL || field == PARAM_FIELD_INT || field == PARAM_FIELD_UINT;
    }
    return false;
}

bool params_table_check(const param_table_t *t, param_error_t *err)
{
    if (t == NULL || (t->n_params > 0u && t->params == NULL) || (t->n_fixed > 0u && t->fixed == NULL)) {
        return fail(err, PARAM_ERR_BAD_REQUEST, PARAM_ID_NONE, "no table");
    }
    for (uint32_t k = 0; k < t->n_params; ++k) {
        const param_desc_t *d = &t->params[k];
        const bool board = d->id >= PARAM_ID_BOARD_FIRST && d->id <= PARAM_ID_BOARD_LAST;
        const bool drive = d->id >= PARAM_ID_DRIVE_FIRST && d->id != PARAM_ID_NONE;
        if (!(board || drive)) return fail(err, PARAM_ERR_BAD_REQUEST, d->id, "id outside both ranges");
        if (k > 0u) {
            const uint16_t prev = t->params[k - 1u].id;
            if (d->id <= prev) return fail(err, PARAM_ERR_BAD_REQUEST, d->id, "ids not ascending");
            const bool prev_board = prev <= PARAM_ID_BOARD_LAST;
            if (prev_board != board) return fail(err, PARAM_ERR_BAD_REQUEST, d->id, "board and drive ids in one table");
        }
        if (!field_fits(d->type, d->field)) return fail(err, PARAM_ERR_BAD_REQUEST, d->id, "field type unfit");
        if (d->offset + field_bytes(d->field) > t->target_bytes) {
            return fail(err, PARAM_ERR_BAD_REQUEST, d->id, "field outside the struct");
        }
        if ((d->type == PARAM_ENUM) != (d->names != NULL && d->n_names > 0u)) {
            return fail(err, PARAM_ERR_BAD_REQUEST, d->id, "enum names");
        }
        if (d->name == NULL || d->unit == NULL) return fail(err, PARAM_ERR_BAD_REQUEST, d->id, "no name or unit");
        param_error_t e;
        if (!params_check_value(d, d->def, &e)) return fail(err, PARAM_ERR_BAD_REQUEST, d->id, "default not valid");
        if (d->type == PARAM_F32 ? (float)d->def_exact != d->def.f32 : value_as_double(d, d->def) != d->def_exact) {
            return fail(err, PARAM_ERR_BAD_REQUEST, d->id, "default's two forms differ");
        }
    }
    for (uint32_t k = 0; k < t->n_fixed; ++k) {
        if (t->fixed[k].offset + field_bytes(t->fixed[k].field) > t->target_bytes) {
            return fail(err, PARAM_ERR_BAD_REQUEST, PARAM_ID_NONE, "fixed field outside the struct");
        }
    }
    return done(err, PARAM_ID_NONE);
}
