/*
 * can_tx.h - the telemetry schedule and transmit queue of a drive on CAN
 * (messages of tools/can/drive.dbc, packed by comm/can_link.h).
 *
 * The control step calls can_tx_step() once per sample: it packs at most
 * one due message into a fixed-size queue, so its cost per sample is
 * bounded by one pack whatever the rates; the backend's transmit side
 * (an interrupt, or the simulator) takes frames with can_tx_pop(). Nothing
 * blocks: when the queue is full the oldest queued frame makes room for
 * the due message and is counted as dropped (telemetry: the newest is what
 * a host wants after a bus outage, as a plot's last point).
 * Rates per message are set in samples at init and by CmdSetRate (ms);
 * period 0 turns a message off. Nothing allocates.
 */
#ifndef COMM_CAN_TX_H
#define COMM_CAN_TX_H

#include <stdbool.h>
#include <stdint.h>

#include "comm/can_link.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 16 frames: at the default rates (one message a ms) more than a bus
 * outage of 2 ms would need; a power of two (the ring's index is a mask). */
#define CAN_TX_QUEUE 16u

typedef struct {
    uint8_t node;                              /* 0-15 */
    int32_t fs_hz;                             /* control rate: ms to samples */
    uint32_t period_ticks[CAN_TLM_COUNT];      /* 0: off */
} can_tx_config_t;

typedef struct {
    can_tx_config_t cfg;
    uint32_t due[CAN_TLM_COUNT];               /* sample at which each is next due */
    can_frame_t q[CAN_TX_QUEUE];
    bool reply[CAN_TX_QUEUE];                  /* q[k] answers a request (kept over telemetry) */
    uint32_t head;                             /* next frame to pop */
    uint32_t count;
    uint32_t sent;                             /* queued since init */
    uint32_t dropped;                          /* queued, then pushed out by a newer one (queue full) */
} can_tx_t;

/* Default periods: heartbeat 100 ms, every other message 10 ms, each first
 * due at a different sample (staggered, so one sample rarely has two). */
void can_tx_defaults(can_tx_config_t *c, uint8_t node, int32_t fs_hz);

/* Validates cfg (node 0..CAN_LINK_NODE_MAX, fs_hz > 0) and resets the
 * schedule and the queue. false: refused, t untouched. */
bool can_tx_init(can_tx_t *t, const can_tx_config_t *cfg);

/* Once per control sample: queues the first due message (at most one),
 * pushing out the oldest frame when the queue is full. */
void can_tx_step(can_tx_t *t, uint32_t tick, const can_telemetry_t *tlm);

/* Queues frame f: a reply (a ParamReply, comm/can_node.h) or telemetry.
 * When the queue is full the oldest telemetry frame goes (the newest
 * telemetry stays, and a reply is never pushed out by telemetry: a host
 * waits for it, while the next telemetry frame replaces the lost one);
 * only a queue of replies loses its oldest reply. */
void can_tx_push(can_tx_t *t, const can_frame_t *f, bool reply);

/* The message can_tx_step would queue at tick (the first due one), or -1. */
int32_t can_tx_next_due(const can_tx_t *t, uint32_t tick);

/* True if a message is due at tick. */
static inline bool can_tx_due(const can_tx_t *t, uint32_t tick) { return can_tx_next_due(t, tick) >= 0; }

/* The next frame to transmit, if any. */
bool can_tx_pop(can_tx_t *t, can_frame_t *f);

/* CmdSetRate: message m every period_ms (0: off), from the next sample.
 * Returns false (nothing changed) for an unknown m or a period beyond
 * 60000 ms. */
bool can_tx_set_period(can_tx_t *t, uint32_t tick, uint8_t m, uint16_t period_ms);

#ifdef __cplusplus
}
#endif

#endif /* COMM_CAN_TX_H */
