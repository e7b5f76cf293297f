/*
 * can_node.h - a drive's node on the CAN bus: the telemetry schedule and
 * queue (comm/can_tx.h), the command side (comm/can_link.h) and the
 * counters a host sees in the heartbeat. What the telemetry carries and
 * what a command does are the drive's, through the drive interface
 * (drives/drive.h: status and command): the node calls an apply function
 * for each valid command (can_node_apply_drive for any drive_t) and
 * counts its verdict. The backend moves the frames
 * (hal_can_receive -> can_node_receive; can_node_peek/can_node_pop ->
 * hal_can_send), from the control callback or its own interrupt. A
 * refused frame changes nothing but the counters. Nothing allocates.
 */
#ifndef COMM_CAN_NODE_H
#define COMM_CAN_NODE_H

#include <stdbool.h>
#include <stdint.h>

#include "comm/can_link.h"
#include "comm/can_tx.h"
#include "drives/drive.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Frames taken from the bus per control sample at most: a burst beyond
 * it waits in the backend's receive queue (the bound keeps the step's
 * cost bounded; 4 commands per 100 us is far beyond any host's need). */
#define CAN_NODE_RX_PER_STEP 4u

/* What a drive does with a valid command: CAN_REJECT_NONE if carried out,
 * CAN_REJECT_MODE if refused (nothing changed). */
typedef can_reject_t (*can_apply_fn)(void *drive, const can_cmd_t *cmd);

/* The answer to a ParamRequest (cmd->kind CAN_CMD_PARAM): the status
 * (config/params.h param_status_t), the parameter's id and its 32 bits;
 * the node echoes op and seq in the ParamReply it queues. A handler that
 * answers later (an image whose design and flash writes run outside the
 * control interrupt) sets status CAN_PARAM_DEFERRED: nothing is queued
 * now, and its owner queues the answer with can_node_param_reply. */
#define CAN_PARAM_DEFERRED 0xFFu
typedef struct {
    uint8_t status;
    uint16_t id;
    uint32_t value;
} can_param_answer_t;
typedef void (*can_param_fn)(void *ctx, const can_cmd_t *req, can_param_answer_t *ans);

typedef struct {
    can_tx_t tx;
    uint32_t accepted;          /* commands carried out */
    uint32_t rejected;          /* commands refused: DLC, range, unknown id, mode */
    uint32_t ignored;           /* other nodes' and telemetry frames */
    can_reject_t last_reject;   /* the latest refusal's reason */
    uint32_t last_reject_id;    /* and its identifier */
    uint32_t heartbeats;        /* the heartbeat's Counter (wrapping at 16 bits on the bus) */
    uint32_t excess_steps;      /* the step/dir input's excess steps, set by its owner (0 without one) */
    uint8_t config_source;      /* where the parameters came from (ConfigSource), set by their owner (0: none) */
    bool params_refused;        /* the parameters do not design (ParamsRefused), set by their owner */
    can_param_fn param;         /* the parameters' handler (can_node_set_params), NULL: none */
    void *param_ctx;
    uint32_t param_replies;     /* ParamReply frames queued */
} can_node_t;

/* Resets the node's counters and its transmit schedule (can_tx_init),
 * with no parameters' handler. false: cfg refused (a node id above
 * CAN_LINK_NODE_MAX, no rate). */
bool can_node_init(can_node_t *n, const can_tx_config_t *cfg);

/* The handler that answers ParamRequest (an image with parameters: its
 * config/param_service.h); each request then gets one ParamReply, queued
 * as telemetry is (comm/can_tx.h: the oldest frame goes when the queue is
 * full). Without one a ParamRequest is refused as an unknown id. */
void can_node_set_params(can_node_t *n, can_param_fn fn, void *ctx);

/* Queues the ParamReply to a request answered later (CAN_PARAM_DEFERRED):
 * op and seq the request's, *a the answer (its status a param_status_t). */
void can_node_param_reply(can_node_t *n, uint8_t op, uint8_t seq, const can_param_answer_t *a);

/* One received frame: validated (can_link_parse); a CmdSetRate is carried
 * out here, a ParamRequest answered by the parameters' handler, any other
 * valid command by apply(drive, cmd). Returns the
 * verdict: CAN_REJECT_NONE when carried out. */
can_reject_t can_node_receive(can_node_t *n, uint32_t tick, const can_frame_t *f, can_apply_fn apply, void *drive);

/* True if a telemetry message is due at tick: the caller then fills the
 * telemetry (only then: it costs more than the check) and calls
 * can_node_transmit. */
bool can_node_due(const can_node_t *n, uint32_t tick);

/* Queues the due message (at most one per sample) with the node's own
 * fields (rejected commands, heartbeat counter) filled into *t. */
void can_node_transmit(can_node_t *n, uint32_t tick, can_telemetry_t *t);

/* The next frame to send, left queued; can_node_pop removes it once the
 * bus took it. */
bool can_node_peek(const can_node_t *n, can_frame_t *f);
void can_node_pop(can_node_t *n);

/* Any drive on the node, through the drive interface (drives/drive.h). */

/* can_apply_fn for a drive_t *drive: the command set to drive_command;
 * any refusal is CAN_REJECT_MODE (nothing changed). */
can_reject_t can_node_apply_drive(void *drive, const can_cmd_t *cmd);

/* The telemetry of drive d's last step: drive_status plus the DriveKind of
 * its operations, and what the backend measures (the bus, the step's
 * time; the drive measures neither). */
void can_node_drive_telemetry(const drive_t *d, mc_t v_bus_V, mc_t step_time_us, can_telemetry_t *t);

/* Once per control sample after drive_step: queues the telemetry due at
 * tick (the status is read only when one is due). */
void can_node_step_drive(can_node_t *n, const drive_t *d, uint32_t tick, mc_t v_bus_V, mc_t step_time_us);

#ifdef __cplusplus
}
#endif

#endif /* COMM_CAN_NODE_H */
