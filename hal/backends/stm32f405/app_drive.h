/*
 * app_drive.h - the application of the STM32F405 image: the drive chosen
 * at configure time (CMake MC_DRIVE, cmake/mc_drive.cmake; the stm32f405
 * preset's is paper 001's speed drive), found in the registry and run
 * through the drive interface (drives/drive.h), with its CAN node
 * (comm/can_node.h) behind hal.h's control callback, as the simulator's
 * can_glue does it: the drive's step, up to CAN_NODE_RX_PER_STEP received
 * commands, the telemetry due, the queue onto the bus while it takes
 * frames. With its user parameters (app_params.h: the flashable image)
 * the drive is designed on the board from them, they are served over CAN
 * and CmdEnable waits for them to design. Nothing here names a drive.
 */
#ifndef STM32_APP_DRIVE_H
#define STM32_APP_DRIVE_H

#include <stdbool.h>
#include <stdint.h>

#include "app_params.h"
#include "comm/can_node.h"
#include "drives/registry.h"
#include "hal/hal.h"
#include "trajectory/step_shaper.h"

typedef struct {
    drive_storage_t storage;     /* the drive's state (drive.self points here) */
    drive_t drive;
    can_node_t node;
    bool can;
    uint32_t step_cycles;        /* SysTick cycles of the last drive step (0: not measured) */
    bool step_dir;               /* the board's step/dir input drives the target (app_drive_step_dir) */
    step_shaper_t shaper;
    app_params_t *params;        /* the parameters (app_drive_init_params), NULL: a fixed configuration */
} app_drive_t;

/* The name of the image's drive (MC_DRIVE). */
const char *app_drive_name(void);

/* Binds the image's drive, copies the configuration words (cfg_bytes long:
 * the drive's config_bytes, else false), initialises the drive and the
 * node (telemetry rates for control_hz). */
bool app_drive_init(app_drive_t *a, const uint32_t *cfg_words, uint32_t cfg_bytes, uint32_t control_hz, uint8_t node,
                    bool can);

/* Binds the image's drive and starts its parameters (app_params_init,
 * app_params_start: the design on the board from the image's values and
 * the store's record, the node's id and periods from the board's
 * parameters); the node answers ParamRequest from then on (can). False
 * (err set) if not even the image's own values design. */
bool app_drive_init_params(app_drive_t *a, app_params_t *p, const drive_design_ops_t *design,
                           const param_table_t *board_table, const app_param_value_t *values, uint32_t n_values,
                           uint32_t control_hz, bool can, const flash_if_t *flash, const app_params_hooks_t *hooks,
                           param_error_t *err);

/* The board's step/dir input as the drive's target (a position drive
 * only: false for another, or a shaper configuration it cannot run): each
 * control step then reads the count (stm32_backend_step_count) and offers
 * the shaper's moves to the drive (drive_command, DRIVE_CMD_MOVE, as a CAN
 * move comes); the excess steps go into the node's telemetry (Timing
 * ExcessSteps). CAN moves still work: the later of the two wins. */
bool app_drive_step_dir(app_drive_t *a, const step_shaper_config_t *cfg, int32_t count0);

/* hal_control_fn; ctx is the app_drive_t. */
void app_drive_control(void *ctx, const hal_sample_t *in, hal_command_t *out);

#endif /* STM32_APP_DRIVE_H */
