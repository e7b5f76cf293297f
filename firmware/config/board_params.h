/*
 * board_params.h - the board's user parameters as one struct, what the
 * board's parameter table (firmware/config/generated/board_params.h, from
 * firmware/config/board_params.toml) reads and writes by id: the node's
 * CAN id, the telemetry's periods, the power stage's dead time. The
 * application applies them (the node id and periods to can_tx_config_t,
 * comm/can_tx.h; the dead time to the board's PWM): the board's constant
 * table (hal/backends/stm32f405/boards/<board>.c) gives their defaults.
 */
#ifndef CONFIG_BOARD_PARAMS_H
#define CONFIG_BOARD_PARAMS_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The telemetry messages, in CmdSetRate's order (comm/can_link.h's
 * can_tlm_t): 8 of them. */
#define BOARD_PARAMS_TLM_COUNT 8u

typedef struct {
    uint32_t can_node;                              /* 0-15: added to every message's id */
    uint32_t tlm_period_ms[BOARD_PARAMS_TLM_COUNT]; /* each message's period, 0: off */
    double dead_time_s;                             /* the bridge's dead time */
} board_params_t;

#ifdef __cplusplus
}
#endif

#endif /* CONFIG_BOARD_PARAMS_H */
