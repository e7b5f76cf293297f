/*
 * app_params.h - an image's user parameters served over CAN while its
 * drive runs: the board's table and the drive's (config/param_service.h),
 * the drive's configuration designed on the board from them with the
 * host's design code (design/ops/drive_design_ops.h), and the
 * configuration store in flash (config/config_store.h). The service, the
 * design and the flash writes run in the main loop (app_params_poll): a
 * design takes about 0.3 ms and a sector erase up to 500 ms, against the
 * control interrupt's 100 us. The interrupt's part (app_params_answer as
 * the node's parameter handler, app_params_control at every sample) only
 * moves requests and results through two one-slot mailboxes:
 *   - a request: the interrupt takes it with the drive's enabled state at
 *     that sample and answers it later (CAN_PARAM_DEFERRED); the main loop
 *     serves it and leaves the reply, which the interrupt queues at its
 *     next sample. A request while another is served is refused busy (the
 *     host retries, as tools/can/drivecan.py does).
 *   - a configuration: a change the service applies is designed in the
 *     main loop and offered to the interrupt, which initialises the drive
 *     from it (left disabled), sets the node's id and telemetry periods and
 *     the board's part (the hook: dead time, encoder counts) and answers;
 *     the main loop waits for that answer, bounded.
 * CmdEnable is refused while a request or a configuration is in flight or
 * the parameters do not design (app_params_may_enable). A save turns the
 * bridges' outputs off around the flash writes (the pause hook: the
 * STM32F405's flash refuses to write while they are on, flash.h) and back
 * on after. At start: the board's defaults and the drive's design
 * defaults, the image's own values over them (the board's scenario,
 * firmware/drives/<drive>/boards/<board>_params.c: the base that
 * "defaults" restores), the store's newest record over those, then the
 * design. A stored record that does not design leaves the drive designed
 * from the base but not ready (enable refused) until a change designs,
 * and says so (start_refused, start_error). No allocation, no global
 * state: the image owns one app_params_t.
 */
#ifndef STM32_APP_PARAMS_H
#define STM32_APP_PARAMS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "comm/can_node.h"
#include "config/board_params.h"
#include "config/param_service.h"
#include "design/ops/drive_design_ops.h"
#include "drives/registry.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The largest design input of the drives (design/ops/; checked at init). */
#define APP_PARAMS_INPUT_BYTES 2048u
/* The main loop's wait for the interrupt to take a configuration, in
 * polls: a poll (a volatile load, a compare, a count) takes at least 3
 * cycles, so at 168 MHz at least 0.18 s, 1,800 control periods. */
#define APP_PARAMS_OFFER_POLLS 10000000u
/* The length of a refusal's text kept for the reply's log. */
#define APP_PARAMS_WHY_BYTES 96u

/* A value of the drive's parameters the image sets over the table's
 * default (the board's scenario, generated: <board>_params.c). */
typedef struct {
    uint16_t id;
    uint32_t value; /* the value's 32 bits (param_value_t) */
} app_param_value_t;

/* What the image does around the parameters. */
typedef struct {
    /* the board's part, from the control interrupt (and once at start,
     * before it runs): the node's id, the dead time, the encoder's counts
     * (0: none read); NULL text when done, else why not */
    const char *(*board_apply)(void *ctx, const board_params_t *b, uint32_t encoder_counts);
    /* a save's guard: pause true before the flash writes, false after */
    void (*pause)(void *ctx, bool pause);
    /* called at each poll of a wait for the interrupt (NULL on a board,
     * where the interrupt preempts the wait; a host test's control step) */
    void (*wait)(void *ctx);
    void *ctx;
} app_params_hooks_t;

typedef enum { APP_SLOT_IDLE = 0u, APP_SLOT_POSTED = 1u, APP_SLOT_DONE = 2u } app_slot_t;

typedef struct {
    const drive_design_ops_t *design;
    const param_table_t *board_table;
    drive_t *drive;
    can_node_t *node;
    app_params_hooks_t hooks;
    param_service_t service;
    config_store_t store;
    board_params_t board, board_base; /* the service's target, the base's */
    union {
        uint8_t b[APP_PARAMS_INPUT_BYTES];
        double align;
    } input, base;               /* the design input (the service's target), the base's */
    drive_config_storage_t next; /* the configuration designed, for the interrupt */
    uint16_t encoder_counts_id;  /* the drive's encoder_counts parameter, PARAM_ID_NONE: none */
    bool running;                /* the interrupt calls app_params_control */
    uint32_t tick;               /* the interrupt's last sample */
    /* the request's slot: POSTED by the interrupt, DONE by the main loop */
    volatile uint32_t req_slot;
    param_request_t req;
    bool req_enabled; /* the drive was enabled when the request came */
    param_reply_t reply;
    /* the configuration's slot: POSTED by the main loop, DONE by the interrupt */
    volatile uint32_t cfg_slot;
    bool cfg_drive;                  /* with the drive's configuration (next), else the board's part only */
    const void *cfg_input;           /* the design input it came from (the encoder's counts) */
    const board_params_t *cfg_board; /* the board's parameters to apply */
    const char *cfg_why;             /* the interrupt's answer: NULL taken, else why not */
    char why[APP_PARAMS_WHY_BYTES];  /* a design's refusal */
    bool start_refused;              /* the stored parameters did not design at start */
    param_error_t start_error;       /* why (its text in start_why) */
    char start_why[APP_PARAMS_WHY_BYTES];
    uint32_t n_refused; /* stored values the tables refused at start */
    uint32_t busy;      /* requests refused: another in flight */
} app_params_t;

/* Binds the drive's design and parameters, the board's table (its
 * defaults: the board's), the drive (bound, not initialised) and its node,
 * the store over flash (NULL: none, save refused) and the hooks. False
 * (err set) on a table, a store or an input the image cannot hold. */
bool app_params_init(app_params_t *p, const drive_design_ops_t *design, const param_table_t *board_table,
                     drive_t *drive, can_node_t *node, const flash_if_t *flash, const app_params_hooks_t *hooks,
                     param_error_t *err);

/* The start (before the interrupt runs): the base (the tables' defaults,
 * the image's values over them), the store's record over it, the design,
 * the drive initialised from it, the node (id, periods for control_hz)
 * and the board's part set. True if the drive runs designed (ready, or
 * the stored parameters refused and the base designed: start_refused);
 * false (err set) if not even the base designs. */
bool app_params_start(app_params_t *p, const app_param_value_t *values, uint32_t n_values, uint32_t control_hz,
                      param_error_t *err);

/* can_param_fn (the node's handler, in the interrupt; ctx: the
 * app_params_t): the request posted for the main loop. */
void app_params_answer(void *ctx, const can_cmd_t *req, can_param_answer_t *ans);

/* The interrupt's part at each sample (after the node took the received
 * frames): a posted configuration taken, a served request's reply queued. */
void app_params_control(app_params_t *p, uint32_t tick);

/* The main loop's part: a posted request served (a save between the
 * pause hook's calls). */
void app_params_poll(app_params_t *p);

/* True if CmdEnable may enable the drive now: the parameters designed and
 * nothing in flight. */
bool app_params_may_enable(const app_params_t *p);

#ifdef __cplusplus
}
#endif

#endif /* STM32_APP_PARAMS_H */
