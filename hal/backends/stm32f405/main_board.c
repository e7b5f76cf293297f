/*
 * main_board.c - the flashable image: the drive's and the board's user
 * parameters first (app_params.h: the image's values for this board,
 * firmware/drives/<drive>/boards/<board>[_<variant>]_params.c, over the
 * tables' defaults; the store's newest record in flash sectors 1 and 2
 * over those; the drive designed on the board from the result), then the
 * board's start-up with the node id, dead time and encoder counts they
 * give, then the control interrupt. The main loop serves the parameters'
 * requests (the design, the flash writes) and blinks the LEDs. Any
 * start-up failure leaves the bridges off and the fault code blinking
 * (stm32_backend.h).
 */
#include "app_drive.h"
#include "app_params.h"
#include "boards/board.h"
#include "config/generated/board_params.h"
#include "flash.h"
#include "stm32_backend.h"
#include "stm32f405_regs.h"

#if !defined(MC_DESIGN_OPS) || !defined(MC_BOARD_PARAMS)
#error "MC_DESIGN_OPS, MC_BOARD_PARAMS: the drive's design and the board's parameters, defined by CMakeLists.txt"
#endif

extern const drive_design_ops_t MC_DESIGN_OPS; /* the image's drive's design (design/ops/) */

/* The image's values of the drive's parameters for this board (generated
 * from the board's scenario by mc_pil_gen --board-params). */
extern const app_param_value_t board_drive_values[];
extern const uint32_t board_drive_values_count;
extern const char board_drive_values_source[];

static app_drive_t app;
static app_params_t params;
static stm32_flash_t flash;

/* the board's part of the parameters (app_params_hooks_t.board_apply) */
static const char *board_apply(void *ctx, const board_params_t *b, uint32_t encoder_counts)
{
    (void)ctx;
    /* the dead time to the nanosecond, rounded (the timer's plan rounds
     * its ticks up: never shorter than asked, pwm_tim1.h) */
    const double ns = b->dead_time_s * 1e9 + 0.5;
    const stm32_status_t st = stm32_backend_configure((uint8_t)b->can_node, (uint32_t)ns, encoder_counts);
    return st == STM32_OK ? NULL : stm32_status_text(st);
}

/* a save's guard: the bridges' outputs off around the flash writes */
static void pause(void *ctx, bool on)
{
    (void)ctx;
    (void)stm32_backend_pause(on);
}

/* the board's step/dir input as the drive's target (a position drive) */
static bool step_dir_target(app_drive_t *a)
{
    int32_t count0 = 0;
    if (!stm32_backend_step_count(&count0)) return false;
    const step_shaper_config_t c = {
        .step_angle_rad = (mc_t)board.step_angle_rad,
        .speed_max_rad_s = (mc_t)board.step_speed_max_rad_s,
        .accel_max_rad_s2 = (mc_t)board.step_accel_max_rad_s2,
        .fs_hz = (int32_t)board.control_hz,
    };
    /* a speed drive has no position target: the input stays unused */
    return app_drive_step_dir(a, &c, count0) || a->drive.ops->kind != DRIVE_KIND_POSITION;
}

int main(void)
{
    /* SysTick free-running at the core clock: the step's cycle count */
    SYST_RVR = 0x00FFFFFFu;
    SYST_CVR = 0u;
    SYST_CSR = 5u;
    stm32_flash_hw_t fhw;
    stm32_flash_chip(&fhw, stm32_hw.tim1, board.topology == PWM_TWO_BRIDGES_TIM1_TIM8 ? stm32_hw.tim8 : NULL,
                     board.watchdog_us != 0u ? stm32_hw.iwdg : NULL);
    stm32_flash_init(&flash, &fhw);
    const flash_if_t fi = stm32_flash_interface(&flash);
    const app_params_hooks_t hooks = {.board_apply = &board_apply, .pause = &pause, .wait = NULL, .ctx = NULL};
    param_error_t err;
    const bool designed =
        app_drive_init_params(&app, &params, &MC_DESIGN_OPS, &MC_BOARD_PARAMS, board_drive_values,
                              board_drive_values_count, board.control_hz, board.can_enable, &fi, &hooks, &err);
    if (stm32_backend_init(&stm32_hw)) {
        if (!designed) {
            stm32_backend_fault(STM32_FAULT_DRIVE);
        } else if (board.step_dir_enable && !step_dir_target(&app)) {
            stm32_backend_fault(STM32_FAULT_STEP_DIR_CONFIG);
        } else {
            params.running = true;
            if (!hal_start(&app_drive_control, &app)) {
                params.running = false;
                stm32_backend_fault(STM32_FAULT_DRIVE);
            }
        }
    }
    for (;;) {
        stm32_backend_idle();
        app_params_poll(&params);
        __asm__ volatile("wfi");
    }
}
