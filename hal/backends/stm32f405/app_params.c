#include "app_params.h"

#include <string.h>

/* The order of the slots' stores against the data they guard: a compiler
 * barrier (one core; the interrupt sees memory in program order). */
static inline void slot_fence(void) { __atomic_signal_fence(__ATOMIC_SEQ_CST); }

static void set_why(app_params_t *p, const char *a, const char *b)
{
    size_t n = 0u;
    for (const char *s = a; s != NULL && *s != '\0' && n + 1u < sizeof p->why; ++s) p->why[n++] = *s;
    for (const char *s = b; s != NULL && *s != '\0' && n + 1u < sizeof p->why; ++s) p->why[n++] = *s;
    p->why[n] = '\0';
}

static bool refuse(param_error_t *err, param_status_t st, uint16_t id, const char *text)
{
    err->status = st;
    err->id = id;
    err->text = text;
    return false;
}

/* The node's id and telemetry periods from the board's parameters b. */
static void node_apply(app_params_t *p, const board_params_t *b, uint32_t tick)
{
    p->node->tx.cfg.node = (uint8_t)b->can_node;
    for (uint8_t m = 0u; m < BOARD_PARAMS_TLM_COUNT; ++m) {
        (void)can_tx_set_period(&p->node->tx, tick, m, (uint16_t)b->tlm_period_ms[m]);
    }
}

/* The drive's encoder counts as its parameters set them (0: none). */
static uint32_t encoder_counts(const app_params_t *p, const void *input)
{
    param_value_t v = {.u32 = 0u};
    param_error_t e;
    if (p->encoder_counts_id == PARAM_ID_NONE || !params_read(p->design->params, input, p->encoder_counts_id, &v, &e)) {
        return 0u;
    }
    return v.u32;
}

/* The configuration taken (in the interrupt, or at start): the drive
 * initialised from next (cfg_drive), the board's part and the node from
 * cfg_board, the encoder's counts from cfg_input. */
static const char *take(app_params_t *p)
{
    if (p->cfg_drive) {
        if (!drive_init(p->drive, &p->next)) {
            const char *why = p->drive->ops->config_problem != NULL ? p->drive->ops->config_problem(&p->next) : NULL;
            return why != NULL ? why : "the drive refused its configuration";
        }
        if (p->running) {
            /* a change at run time leaves the drive disabled (a drive may
             * start enabled, holding at rest: at power-up only) */
            drive_cmd_t off;
            memset(&off, 0, sizeof off);
            off.kind = DRIVE_CMD_ENABLE;
            off.enable = false;
            (void)drive_command(p->drive, &off);
        }
    }
    if (p->hooks.board_apply != NULL) {
        const char *why = p->hooks.board_apply(p->hooks.ctx, p->cfg_board, encoder_counts(p, p->cfg_input));
        if (why != NULL) return why;
    }
    node_apply(p, p->cfg_board, p->tick);
    return NULL;
}

/* The design from input into next (drive: a drive's parameter changed)
 * and its hand-over with the board's parameters b, waited for. */
static bool design_and_hand_over(app_params_t *p, bool drive, const void *input, const board_params_t *b, uint16_t id,
                                 param_error_t *err)
{
    if (drive) {
        char text[APP_PARAMS_WHY_BYTES];
        text[0] = '\0';
        memset(&p->next, 0, sizeof p->next);
        if (!p->design->design(input, &p->next, text, sizeof text)) {
            set_why(p, text, NULL);
            return refuse(err, PARAM_ERR_DESIGN_REFUSED, id, p->why);
        }
        /* refused here rather than by drive_init in the interrupt, which
         * would leave the drive in FAULT */
        const char *bad = p->drive->ops->config_problem != NULL ? p->drive->ops->config_problem(&p->next) : NULL;
        if (bad != NULL) {
            set_why(p, "the drive refuses the design: ", bad);
            return refuse(err, PARAM_ERR_DESIGN_REFUSED, id, p->why);
        }
    }
    p->cfg_drive = drive;
    p->cfg_input = input;
    p->cfg_board = b;
    const char *why = NULL;
    if (!p->running) {
        why = take(p);
    } else {
        p->cfg_why = NULL;
        slot_fence();
        p->cfg_slot = APP_SLOT_POSTED;
        uint32_t polls = 0u;
        while (p->cfg_slot != APP_SLOT_DONE && polls < APP_PARAMS_OFFER_POLLS) {
            if (p->hooks.wait != NULL) p->hooks.wait(p->hooks.ctx);
            ++polls;
        }
        slot_fence();
        if (p->cfg_slot != APP_SLOT_DONE) {
            p->cfg_slot = APP_SLOT_IDLE;
            set_why(p, "the control interrupt did not take the configuration", NULL);
            return refuse(err, PARAM_ERR_DESIGN_REFUSED, id, p->why);
        }
        why = p->cfg_why;
        p->cfg_slot = APP_SLOT_IDLE;
    }
    if (why != NULL) {
        set_why(p, why, NULL);
        return refuse(err, PARAM_ERR_DESIGN_REFUSED, id, p->why);
    }
    return true;
}

/* param_apply_fn: a change of the board's table applies its part only
 * (while the drive's parameters design: else they are designed again, the
 * drive running from another configuration meanwhile); a drive's
 * parameter, or every parameter (t NULL), designs again. */
static bool apply(void *ctx, const param_table_t *t, uint16_t id, param_error_t *err)
{
    app_params_t *p = (app_params_t *)ctx;
    const bool drive = t == NULL || t != p->board_table || !param_service_ready(&p->service);
    return design_and_hand_over(p, drive, p->input.b, &p->board, id, err);
}

bool app_params_init(app_params_t *p, const drive_design_ops_t *design, const param_table_t *board_table,
                     drive_t *drive, can_node_t *node, const flash_if_t *flash, const app_params_hooks_t *hooks,
                     param_error_t *err)
{
    memset(p, 0, sizeof *p);
    if (design == NULL || board_table == NULL || drive == NULL || node == NULL || hooks == NULL) {
        return refuse(err, PARAM_ERR_BAD_REQUEST, PARAM_ID_NONE, "app_params_init: a NULL argument");
    }
    if (design->input_bytes > APP_PARAMS_INPUT_BYTES) {
        return refuse(err, PARAM_ERR_BAD_REQUEST, PARAM_ID_NONE,
                      "the drive's design input is larger than APP_PARAMS_INPUT_BYTES");
    }
    if (design->config_bytes != drive->ops->config_bytes || design->config_bytes > sizeof p->next) {
        return refuse(err, PARAM_ERR_BAD_REQUEST, PARAM_ID_NONE, "the design's configuration is not the drive's");
    }
    if (board_table->target_bytes != sizeof p->board) {
        return refuse(err, PARAM_ERR_BAD_REQUEST, PARAM_ID_NONE, "the board's table is not over board_params_t");
    }
    p->design = design;
    p->board_table = board_table;
    p->drive = drive;
    p->node = node;
    p->hooks = *hooks;
    p->encoder_counts_id = PARAM_ID_NONE;
    for (uint16_t k = 0u; k < design->params->n_params; ++k) {
        if (strcmp(design->params->params[k].name, "encoder_counts") == 0) {
            p->encoder_counts_id = design->params->params[k].id;
        }
    }
    return param_service_init(&p->service, board_table, &p->board, design->params, p->input.b,
                              flash != NULL ? &p->store : NULL, flash, &apply, p, err);
}

bool app_params_start(app_params_t *p, const app_param_value_t *values, uint32_t n_values, uint32_t control_hz,
                      param_error_t *err)
{
    p->running = false;
    p->tick = 0u;
    /* the base: the tables' defaults, the image's values over them */
    if (!params_set_defaults(p->board_table, &p->board, err) ||
        !drive_design_defaults_input(p->design, p->input.b, err)) {
        return false;
    }
    for (uint32_t k = 0u; k < n_values; ++k) {
        const param_value_t v = {.u32 = values[k].value};
        if (!params_write(p->design->params, p->input.b, values[k].id, v, false, err)) {
            return false;
        }
    }
    memcpy(p->base.b, p->input.b, sizeof p->base.b);
    p->board_base = p->board;
    can_tx_config_t tc;
    can_tx_defaults(&tc, (uint8_t)p->board.can_node, (int32_t)control_hz);
    if (!can_node_init(p->node, &tc)) {
        return refuse(err, PARAM_ERR_OUT_OF_RANGE, PARAM_ID_NONE, "the board's node id");
    }
    can_node_set_params(p->node, &app_params_answer, p);
    /* the store's record over the base, the design */
    p->n_refused = 0u;
    if (param_service_start(&p->service, true, &p->n_refused, err)) {
        p->start_refused = false;
        return true;
    }
    /* the stored parameters do not design: the drive runs from the base,
     * not ready, the stored values kept for the host to mend */
    p->start_refused = true;
    set_why(p, err->text, NULL);
    p->start_error = *err;
    p->start_error.text = p->start_why;
    memcpy(p->start_why, p->why, sizeof p->start_why);
    return design_and_hand_over(p, true, p->base.b, &p->board_base, PARAM_ID_NONE, err);
}

void app_params_answer(void *ctx, const can_cmd_t *req, can_param_answer_t *ans)
{
    app_params_t *p = (app_params_t *)ctx;
    if (p->req_slot != APP_SLOT_IDLE) {
        p->busy += 1u;
        ans->status = (uint8_t)PARAM_ERR_BUSY;
        ans->id = req->param_id;
        ans->value = 0u;
        return;
    }
    drive_status_t st;
    drive_status(p->drive, &st);
    p->req.op = req->param_op;
    p->req.seq = req->param_seq;
    p->req.id = req->param_id;
    p->req.value.u32 = req->param_value;
    p->req_enabled = st.enabled;
    slot_fence();
    p->req_slot = APP_SLOT_POSTED;
    ans->status = CAN_PARAM_DEFERRED;
}

void app_params_control(app_params_t *p, uint32_t tick)
{
    p->tick = tick;
    if (p->cfg_slot == APP_SLOT_POSTED) {
        slot_fence();
        p->cfg_why = take(p);
        slot_fence();
        p->cfg_slot = APP_SLOT_DONE;
    }
    if (p->req_slot == APP_SLOT_DONE) {
        slot_fence();
        const can_param_answer_t a = {
            .status = (uint8_t)p->reply.status, .id = p->reply.id, .value = p->reply.value.u32};
        can_node_param_reply(p->node, p->reply.op, p->reply.seq, &a);
        slot_fence();
        p->req_slot = APP_SLOT_IDLE;
    }
}

void app_params_poll(app_params_t *p)
{
    if (p->req_slot != APP_SLOT_POSTED) return;
    slot_fence();
    const bool save = p->req.op == (uint8_t)PARAM_OP_SAVE && !p->req_enabled;
    if (save && p->hooks.pause != NULL) p->hooks.pause(p->hooks.ctx, true);
    param_service_request(&p->service, &p->req, p->req_enabled, &p->reply);
    if (save && p->hooks.pause != NULL) p->hooks.pause(p->hooks.ctx, false);
    if (p->reply.status == PARAM_OK && p->start_refused && param_service_ready(&p->service)) {
        p->start_refused = false; /* a change designed: the stored parameters mended */
    }
    slot_fence();
    p->req_slot = APP_SLOT_DONE;
}

bool app_params_may_enable(const app_params_t *p)
{
    return param_service_ready(&p->service) && p->req_slot == APP_SLOT_IDLE && p->cfg_slot == APP_SLOT_IDLE;
}
