#include "stm32_status.h"

const char *stm32_status_text(stm32_status_t s)
{
    switch (s) {
    case STM32_OK: return "ok";
    case STM32_FAULT_HSE_TIMEOUT: return "HSE crystal did not start";
    case STM32_FAULT_PLL_TIMEOUT: return "PLL did not lock";
    case STM32_FAULT_CLOCK_SWITCH: return "SYSCLK did not switch to the PLL";
    case STM32_FAULT_CLOCK_PLAN: return "no PLL setting gives the asked clock";
    case STM32_FAULT_ADC_TIMEOUT: return "ADC conversion timed out";
    case STM32_FAULT_ADC_OFFSET: return "current sensor offset out of range";
    case STM32_FAULT_CAN_TIMEOUT: return "bxCAN initialisation timed out";
    case STM32_FAULT_CAN_TIMING: return "no CAN bit timing for this clock";
    case STM32_FAULT_IWDG_TIMEOUT: return "watchdog registers did not update";
    case STM32_FAULT_WATCHDOG_RESET: return "reset by the independent watchdog";
    case STM32_FAULT_OVERCURRENT_BREAK: return "over-current: TIM1 break input";
    case STM32_FAULT_PWM_PLAN: return "PWM frequency or dead time not settable";
    case STM32_FAULT_DRIVE: return "the drive refused its configuration or latched a fault";
    case STM32_FAULT_UNEXPECTED_IRQ: return "unexpected interrupt or CPU fault";
    case STM32_FAULT_ENCODER_CONFIG: return "encoder: configuration the timer cannot run";
    case STM32_FAULT_ENCODER_TIMEOUT: return "encoder: its timer did not answer the update";
    case STM32_FAULT_ENCODER_STEP: return "encoder: count moved faster than any motor on the board";
    case STM32_FAULT_ENCODER_INDEX: return "encoder: index away from the count (counts lost)";
    case STM32_FAULT_PWM_SYNC: return "PWM: TIM8 did not start on TIM1's trigger";
    case STM32_FAULT_STEP_DIR_CONFIG: return "step/dir input: configuration the timer cannot run";
    case STM32_FAULT_STEP_DIR_TIMEOUT: return "step/dir input: its timer did not answer the update";
    case STM32_FAULT_GATE_DRIVER_SPI: return "gate driver: an SPI flag timed out";
    case STM32_FAULT_GATE_DRIVER_CONFIG: return "gate driver: a control register did not read back as written";
    case STM32_FAULT_GATE_DRIVER_NFAULT: return "gate driver: nFAULT asserted";
    default: return "unknown fault";
    }
}
