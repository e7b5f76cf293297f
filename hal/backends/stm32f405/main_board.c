/*
 * main_board.c - the flashable image: the board's start-up, the image's
 * drive (MC_DRIVE) with its configuration for this board
 * (firmware/drives/<drive>/boards/<board>_config.c), the control interrupt;
 * the main loop only blinks the LEDs. Any start-up failure leaves the
 * bridges off and the fault code blinking (stm32_backend.h).
 */
#include "app_drive.h"
#include "boards/board.h"
#include "stm32_backend.h"
#include "stm32f405_regs.h"

static app_drive_t app;

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
    if (stm32_backend_init(&stm32_hw)) {
        if (!app_drive_init(&app, board_drive_cfg_words, board_drive_cfg_bytes, board.control_hz, board.can_node,
                            board.can_enable)) {
            stm32_backend_fault(STM32_FAULT_DRIVE);
        } else if (board.step_dir_enable && !step_dir_target(&app)) {
            stm32_backend_fault(STM32_FAULT_STEP_DIR_CONFIG);
        } else if (!hal_start(&app_drive_control, &app)) {
            stm32_backend_fault(STM32_FAULT_DRIVE);
        }
    }
    for (;;) {
        stm32_backend_idle();
        __asm__ volatile("wfi");
    }
}
