/*
 * app_drive.h - the application of the STM32F405 image: paper 001's speed
 * drive and its CAN node (comm/can_node.h, through the drive interface) behind hal.h's control
 * callback, as the simulator's can_glue does it: the drive's step, up to
 * CAN_NODE_RX_PER_STEP received commands, the telemetry due, the queue
 * onto the bus while it takes frames.
 */
#ifndef STM32_APP_DRIVE_H
#define STM32_APP_DRIVE_H

#include <stdbool.h>
#include <stdint.h>

#include "comm/can_node.h"
#include "drives/paper001/paper001_drive.h"
#include "hal/hal.h"

typedef struct {
    paper001_drive_t drive;
    can_node_t node;
    bool can;
    uint32_t step_cycles;        /* SysTick cycles of the last drive step (0: not measured) */
} app_drive_t;

/* Copies the configuration words, initialises the drive and the node. */
bool app_drive_init(app_drive_t *a, const uint32_t *cfg_words, uint8_t node, bool can);

/* hal_control_fn; ctx is the app_drive_t. */
void app_drive_control(void *ctx, const hal_sample_t *in, hal_command_t *out);

#endif /* STM32_APP_DRIVE_H */
