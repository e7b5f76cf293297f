/*
 * stm32_status.h - why the STM32F405 backend is in its fault state: one
 * code per start-up or run-time failure, readable on the debugger
 * (stm32_backend_fault), blinked on the status LED (the code's number of
 * flashes, then a pause), returned by hal_last_error() as text and, once
 * the drive runs, carried to the drive as HAL status bits (its fault code
 * then reaches the CAN heartbeat).
 */
#ifndef STM32_STATUS_H
#define STM32_STATUS_H

typedef enum {
    STM32_OK = 0,
    STM32_FAULT_HSE_TIMEOUT = 1,     /* the crystal did not start (HSERDY) */
    STM32_FAULT_PLL_TIMEOUT = 2,     /* the PLL did not lock (PLLRDY) */
    STM32_FAULT_CLOCK_SWITCH = 3,    /* SYSCLK did not switch to the PLL (SWS) */
    STM32_FAULT_CLOCK_PLAN = 4,      /* no PLL setting gives the asked clocks */
    STM32_FAULT_ADC_TIMEOUT = 5,     /* a conversion did not end (JEOC) */
    STM32_FAULT_ADC_OFFSET = 6,      /* a current sensor's zero outside its tolerance */
    STM32_FAULT_CAN_TIMEOUT = 7,     /* bxCAN did not enter or leave initialisation (INAK) */
    STM32_FAULT_CAN_TIMING = 8,      /* no bit timing gives the bit rate from this clock */
    STM32_FAULT_IWDG_TIMEOUT = 9,    /* the watchdog's registers did not update (PVU/RVU) */
    STM32_FAULT_WATCHDOG_RESET = 10, /* the last reset came from the independent watchdog */
    STM32_FAULT_OVERCURRENT_BREAK = 11, /* TIM1's break input fired: bridges off by hardware */
    STM32_FAULT_PWM_PLAN = 12,       /* the PWM frequency or dead time cannot be set */
    STM32_FAULT_DRIVE = 13,          /* the drive refused its configuration or latched a fault */
    STM32_FAULT_UNEXPECTED_IRQ = 14, /* an interrupt without a handler, or a CPU fault */
    /* the encoder (encoder_tim.h): at start-up a fault; while running the
     * angle is withheld (samples without has_angle) and the code kept */
    STM32_FAULT_ENCODER_CONFIG = 15,  /* counts per turn, filter or limits the timer cannot run */
    STM32_FAULT_ENCODER_TIMEOUT = 16, /* the encoder's timer did not answer its update (UIF) */
    STM32_FAULT_ENCODER_STEP = 17,    /* the count moved more than max_step_counts between two reads */
    STM32_FAULT_ENCODER_INDEX = 18,   /* an index away from where the count puts it */
    STM32_FAULT_PWM_SYNC = 19,        /* TIM8 did not start on TIM1's trigger (pwm_start_synchronised) */
    STM32_FAULT_STEP_DIR_CONFIG = 20, /* the step/dir input's timer or pins cannot be set as asked */
    STM32_FAULT_STEP_DIR_TIMEOUT = 21, /* the step counter's timer did not answer its update (UIF) */
    /* the gate drivers configured over SPI (drv8301.h) */
    STM32_FAULT_GATE_DRIVER_SPI = 22,    /* an SPI flag (TXE, RXNE, BSY) did not come: the text names it */
    STM32_FAULT_GATE_DRIVER_CONFIG = 23, /* a control register did not read back as written (or a bad answer) */
    STM32_FAULT_GATE_DRIVER_NFAULT = 24  /* nFAULT asserted: at start, or while running (the bridges off) */
} stm32_status_t;

/* A short English text for status s, never NULL. */
const char *stm32_status_text(stm32_status_t s);

#endif /* STM32_STATUS_H */
