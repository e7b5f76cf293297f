#include "comm/can_tx.h"

/* Default rates (docs/can.md): the heartbeat every 100 ms, the version
 * (constant: for a host that joins late) every 1 s, the rest every 10 ms:
 * 611 frames/s, under 10 % of a 1 Mbit/s bus (about 7,700 8-byte
 * frames/s), and fast enough to plot a 2 s move. */
#define CAN_TX_HEARTBEAT_MS 100u
#define CAN_TX_VERSION_MS 1000u
#define CAN_TX_DEFAULT_MS 10u

static uint32_t ms_to_ticks(uint32_t ms, int32_t fs_hz)
{
    /* at least one sample for a non-zero period */
    const uint32_t n = (uint32_t)(((uint64_t)ms * (uint64_t)fs_hz + 999u) / 1000u);
    return (ms > 0u && n == 0u) ? 1u : n;
}

void can_tx_defaults(can_tx_config_t *c, uint8_t node, int32_t fs_hz)
{
    c->node = node;
    c->fs_hz = fs_hz;
    for (uint32_t m = 0; m < CAN_TLM_COUNT; ++m) {
        const uint32_t ms = (m == (uint32_t)CAN_TLM_HEARTBEAT) ? CAN_TX_HEARTBEAT_MS
                            : (m == (uint32_t)CAN_TLM_VERSION) ? CAN_TX_VERSION_MS
                                                               : CAN_TX_DEFAULT_MS;
        c->period_ticks[m] = ms_to_ticks(ms, fs_hz);
    }
}

bool can_tx_init(can_tx_t *t, const can_tx_config_t *cfg)
{
    if (cfg->node > CAN_LINK_NODE_MAX || cfg->fs_hz <= 0) {
        return false;
    }
    t->cfg = *cfg;
    for (uint32_t m = 0; m < CAN_TLM_COUNT; ++m) {
        t->due[m] = m; /* staggered by one sample */
    }
    t->head = 0;
    t->count = 0;
    t->sent = 0;
    t->dropped = 0;
    return true;
}

int32_t can_tx_next_due(const can_tx_t *t, uint32_t tick)
{
    for (uint32_t m = 0; m < CAN_TLM_COUNT; ++m) {
        /* due when tick has reached due[m] (wrap-safe difference) */
        if (t->cfg.period_ticks[m] != 0u && (int32_t)(tick - t->due[m]) >= 0) {
            return (int32_t)m;
        }
    }
    return -1;
}

void can_tx_step(can_tx_t *t, uint32_t tick, const can_telemetry_t *tlm)
{
    /* at most one message a sample: the first due */
    const int32_t next = can_tx_next_due(t, tick);
    if (next < 0) {
        return;
    }
    const uint32_t m = (uint32_t)next;
    t->due[m] = tick + t->cfg.period_ticks[m];
    can_frame_t f;
    if (!can_link_pack((can_tlm_msg_t)m, t->cfg.node, tlm, &f)) {
        return;
    }
    can_tx_push(t, &f, false);
}

/* The full queue's oldest telemetry frame removed (the oldest frame if
 * all are replies), the order of the others kept. */
static void drop_one(can_tx_t *t)
{
    const uint32_t mask = CAN_TX_QUEUE - 1u;
    uint32_t k = 0u;
    while (k < t->count && t->reply[(t->head + k) & mask]) {
        ++k;
    }
    if (k == t->count) {
        k = 0u;
    }
    /* the frames before it move one place on, over it */
    for (uint32_t j = k; j > 0u; --j) {
        t->q[(t->head + j) & mask] = t->q[(t->head + j - 1u) & mask];
        t->reply[(t->head + j) & mask] = t->reply[(t->head + j - 1u) & mask];
    }
    t->head = (t->head + 1u) & mask;
    t->count -= 1u;
    t->dropped += 1u;
}

void can_tx_push(can_tx_t *t, const can_frame_t *f, bool reply)
{
    if (t->count >= CAN_TX_QUEUE) {
        drop_one(t);
    }
    const uint32_t at = (t->head + t->count) & (CAN_TX_QUEUE - 1u);
    t->q[at] = *f;
    t->reply[at] = reply;
    t->count += 1u;
    t->sent += 1u;
}

bool can_tx_pop(can_tx_t *t, can_frame_t *f)
{
    if (t->count == 0u) {
        return false;
    }
    *f = t->q[t->head];
    t->head = (t->head + 1u) & (CAN_TX_QUEUE - 1u);
    t->count -= 1u;
    return true;
}

bool can_tx_set_period(can_tx_t *t, uint32_t tick, uint8_t m, uint16_t period_ms)
{
    if (m >= (uint8_t)CAN_TLM_COUNT || period_ms > 60000u) {
        return false;
    }
    t->cfg.period_ticks[m] = ms_to_ticks(period_ms, t->cfg.fs_hz);
    t->due[m] = tick;
    return true;
}
