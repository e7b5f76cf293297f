#include "gpio.h"

void gpio_config(gpio_regs_t *g, uint32_t pin, gpio_mode_t mode, uint32_t af, gpio_pull_t pull)
{
    const uint32_t s2 = 2u * pin;
    g->MODER = (g->MODER & ~(3u << s2)) | ((uint32_t)mode << s2);
    g->OTYPER &= ~(1u << pin);                     /* push-pull */
    g->OSPEEDR = (g->OSPEEDR & ~(3u << s2)) | (2u << s2); /* fast: PWM edges */
    g->PUPDR = (g->PUPDR & ~(3u << s2)) | ((uint32_t)pull << s2);
    const uint32_t r = pin / 8u, s4 = 4u * (pin % 8u);
    g->AFR[r] = (g->AFR[r] & ~(0xFu << s4)) | ((af & 0xFu) << s4);
}
