#include "comm/can_node.h"

#include <stddef.h>

bool can_node_init(can_node_t *n, const can_tx_config_t *cfg)
{
    if (!can_tx_init(&n->tx, cfg)) {
        return false;
    }
    n->accepted = 0;
    n->rejected = 0;
    n->ignored = 0;
    n->last_reject = CAN_REJECT_NONE;
    n->last_reject_id = 0;
    n->heartbeats = 0;
    n->excess_steps = 0;
    n->config_source = 0u;
    n->params_refused = false;
    n->param = NULL;
    n->param_ctx = NULL;
    n->param_replies = 0;
    return true;
}

void can_node_set_params(can_node_t *n, can_param_fn fn, void *ctx)
{
    n->param = fn;
    n->param_ctx = ctx;
}

/* A ParamRequest: the handler's answer as a ParamReply. */
static can_reject_t answer_param(can_node_t *n, const can_cmd_t *cmd)
{
    if (n->param == NULL) {
        return CAN_REJECT_UNKNOWN_ID; /* an image without parameters */
    }
    can_param_answer_t a = {0};
    n->param(n->param_ctx, cmd, &a);
    if (a.status != CAN_PARAM_DEFERRED) {
        can_node_param_reply(n, cmd->param_op, cmd->param_seq, &a);
    }
    return CAN_REJECT_NONE;
}

void can_node_param_reply(can_node_t *n, uint8_t op, uint8_t seq, const can_param_answer_t *a)
{
    can_frame_t f;
    can_link_pack_param_reply(n->tx.cfg.node, op, a->status, seq, a->id, a->value, &f);
    can_tx_push(&n->tx, &f, true);
    n->param_replies += 1u;
}

can_reject_t can_node_receive(can_node_t *n, uint32_t tick, const can_frame_t *f, can_apply_fn apply, void *drive)
{
    can_cmd_t cmd;
    can_reject_t r = can_link_parse(n->tx.cfg.node, f, &cmd);
    if (r == CAN_REJECT_NOT_OURS) {
        n->ignored += 1u;
        return r;
    }
    if (r == CAN_REJECT_NONE) {
        if (cmd.kind == CAN_CMD_SET_RATE) {
            r = can_tx_set_period(&n->tx, tick, cmd.message, cmd.period_ms) ? CAN_REJECT_NONE : CAN_REJECT_RANGE;
        } else if (cmd.kind == CAN_CMD_PARAM) {
            r = answer_param(n, &cmd);
        } else {
            r = apply(drive, &cmd);
        }
    }
    if (r == CAN_REJECT_NONE) {
        n->accepted += 1u;
    } else {
        n->rejected += 1u;
        n->last_reject = r;
        n->last_reject_id = f->id;
    }
    return r;
}

bool can_node_due(const can_node_t *n, uint32_t tick)
{
    return can_tx_due(&n->tx, tick);
}

void can_node_transmit(can_node_t *n, uint32_t tick, can_telemetry_t *t)
{
    t->rejected_commands = (uint8_t)(n->rejected & 0xFFu);
    t->counter = (uint16_t)(n->heartbeats & 0xFFFFu);
    const uint32_t before = n->tx.sent;
    const bool heartbeat_due = can_tx_next_due(&n->tx, tick) == (int32_t)CAN_TLM_HEARTBEAT;
    can_tx_step(&n->tx, tick, t);
    if (heartbeat_due && n->tx.sent != before) {
        n->heartbeats += 1u;
    }
}

bool can_node_peek(const can_node_t *n, can_frame_t *f)
{
    if (n->tx.count == 0u) {
        return false;
    }
    *f = n->tx.q[n->tx.head];
    return true;
}

void can_node_pop(can_node_t *n)
{
    can_frame_t unused;
    (void)can_tx_pop(&n->tx, &unused);
}

can_reject_t can_node_apply_drive(void *drive, const can_cmd_t *cmd)
{
    drive_t *d = (drive_t *)drive;
    drive_cmd_t c;
    switch (cmd->kind) {
    case CAN_CMD_ENABLE: c.kind = DRIVE_CMD_ENABLE; break;
    case CAN_CMD_MOVE: c.kind = DRIVE_CMD_MOVE; break;
    case CAN_CMD_SPEED: c.kind = DRIVE_CMD_SPEED; break;
    case CAN_CMD_STOP: c.kind = DRIVE_CMD_STOP; break;
    case CAN_CMD_SET_OMEGA_LIM: c.kind = DRIVE_CMD_SET_OMEGA_LIM; break;
    case CAN_CMD_CLEAR_FAULTS: c.kind = DRIVE_CMD_CLEAR_FAULTS; break;
    default: return CAN_REJECT_MODE; /* CmdSetRate is the node's; none is not a command */
    }
    c.enable = cmd->enable;
    c.theta_to_rad = cmd->theta_to_rad;
    c.duration_s = cmd->duration_s;
    c.omega_ref_rad_s = cmd->omega_ref_rad_s;
    c.ramp_rad_s2 = cmd->ramp_rad_s2;
    c.omega_lim_rad_s = cmd->omega_lim_rad_s;
    return drive_command(d, &c) == DRIVE_REFUSE_NONE ? CAN_REJECT_NONE : CAN_REJECT_MODE;
}

void can_node_drive_telemetry(const drive_t *d, mc_t v_bus_V, mc_t step_time_us, can_telemetry_t *t)
{
    drive_status(d, &t->drive);
    t->drive_kind = d->ops->can_kind;
    t->v_bus_V = v_bus_V;
    t->step_time_us = step_time_us;
    t->excess_steps = 0u;
}

void can_node_step_drive(can_node_t *n, const drive_t *d, uint32_t tick, mc_t v_bus_V, mc_t step_time_us)
{
    if (!can_node_due(n, tick)) {
        return;
    }
    can_telemetry_t t;
    can_node_drive_telemetry(d, v_bus_V, step_time_us, &t);
    t.excess_steps = (uint16_t)(n->excess_steps & 0xFFFFu);
    t.config_source = n->config_source;
    t.params_refused = n->params_refused;
    can_node_transmit(n, tick, &t);
}
