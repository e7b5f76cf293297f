/*
 * gpio.h - pin set-up (RM0090 8.3): mode, output type and speed, pull,
 * alternate function; and the output level of a plain output.
 */
#ifndef STM32_GPIO_H
#define STM32_GPIO_H

#include <stdbool.h>
#include <stdint.h>

#include "stm32f405_regs.h"

typedef enum { GPIO_INPUT = 0, GPIO_OUTPUT = 1, GPIO_AF = 2, GPIO_ANALOG = 3 } gpio_mode_t;
typedef enum { GPIO_NO_PULL = 0, GPIO_PULL_UP = 1, GPIO_PULL_DOWN = 2 } gpio_pull_t;

/* A pin of the board file: port 0 = A, 1 = B, ...; pin 0-15. */
typedef struct {
    uint8_t port, pin, af;
} gpio_pin_t;

void gpio_config(gpio_regs_t *g, uint32_t pin, gpio_mode_t mode, uint32_t af, gpio_pull_t pull);

static inline void gpio_write(gpio_regs_t *g, uint32_t pin, bool high)
{
    g->BSRR = high ? (1u << pin) : (1u << (pin + 16u));
}

#endif /* STM32_GPIO_H */
