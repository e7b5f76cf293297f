#include "comm/can_node.h"

void can_node_init(can_node_t *n, const can_tx_config_t *cfg)
{
    can_tx_init(&n->tx, cfg);
    n->accepted = 0;
    n->rejected = 0;
    n->ignored = 0;
    n->last_reject = CAN_REJECT_NONE;
    n->last_reject_id = 0;
    n->heartbeats = 0;
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
