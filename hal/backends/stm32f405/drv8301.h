/*
 * drv8301.h - TI's DRV8301 gate driver (datasheet SLOS719) configured over
 * the STM32F405's SPI (RM0090 28): its two current-shunt amplifiers' gain
 * and its over-current protection written into its control registers, read
 * back and compared (a gain the backend does not know would scale every
 * current sample wrong), and its status registers read. One SPI master for
 * one or more DRV8301s, each on its own chip select (a GPIO output, active
 * low, driven by software: SSM = 1, SSI = 1).
 *
 * The frame (SLOS719, SPI format): 16 bits, MSB first, SPI mode 1 (CPOL = 0,
 * CPHA = 1: the DRV8301 shifts SDO out on SCLK's rising edge and samples
 * SDI on its falling edge). Command word: bit 15 R/W (1 read), bits 14:11
 * the register's address, bits 10:0 the data. The DRV8301 answers a
 * command in the NEXT frame (it shifts out the answer to command N-1
 * while command N shifts in): response word bit 15 the frame error, bits
 * 14:11 the address, bits 10:0 the register's content. So a read is two
 * frames (the command, then the same command again whose answer carries
 * the register), and each frame is one nCS low-high cycle: the DRV8301
 * takes a word at nCS's rising edge.
 *
 * A frame on the STM32F405 (RM0090 28.3.5, full duplex master): nCS low,
 * wait for TXE (the transmit buffer empty), write DR, wait for RXNE (the
 * word received: the 16 clocks are over), read DR, wait for BSY to clear,
 * nCS high for cs_high_polls polls. Every wait is bounded (timeout_polls
 * polls): a flag that does not come is an error naming it, nCS left high.
 *
 * Errors: the code (stm32_status.h: STM32_FAULT_GATE_DRIVER_SPI for a
 * flag's timeout, STM32_FAULT_GATE_DRIVER_CONFIG for a register that does
 * not read back as written or an answer for another register) and a text
 * naming the chip, the register, the value written and the value read, or
 * the flag, kept in the bus's state (no heap: a fixed buffer).
 */
#ifndef STM32_DRV8301_H
#define STM32_DRV8301_H

#include <stdbool.h>
#include <stdint.h>

#include "stm32_status.h"
#include "stm32f405_regs.h"

/* registers (SLOS719, register map: addresses A3..A0) */
#define DRV8301_REG_STATUS1 0x0u
#define DRV8301_REG_STATUS2 0x1u
#define DRV8301_REG_CTRL1 0x2u
#define DRV8301_REG_CTRL2 0x3u
/* the 16-bit word */
#define DRV8301_FRAME_READ (1u << 15)          /* command: read; response: frame error */
#define DRV8301_FRAME_ADDR(a) (((uint32_t)(a) & 0xFu) << 11)
#define DRV8301_FRAME_ADDR_OF(w) (((uint32_t)(w) >> 11) & 0xFu)
#define DRV8301_DATA_MASK 0x7FFu
/* status register 1: FAULT (any fault latched), and per FET (high and low
 * side of legs A, B, C) an over-current, bits 5:0 */
#define DRV8301_STATUS1_FAULT (1u << 10)
#define DRV8301_STATUS1_FET_OC_MASK 0x3Fu
/* control register 1: GATE_CURRENT bits 1:0 (00: 1.7 A peak), GATE_RESET
 * bit 2 (0: normal), PWM_MODE bit 3 (0: six PWM inputs), OCP_MODE bits 5:4,
 * OC_ADJ_SET bits 10:6 (the FETs' V_DS that counts as over-current, code 0
 * 0.060 V ... 31 2.400 V) */
#define DRV8301_CTRL1_OCP_LATCH (1u << 4)      /* OCP_MODE 01: an over-current latches the FETs off, nFAULT low */
#define DRV8301_CTRL1_OC_ADJ(code) (((uint32_t)(code) & 0x1Fu) << 6)
/* control register 2: OCTW_MODE bits 1:0, GAIN bits 3:2, DC_CAL_CH1/CH2
 * bits 4, 5 (0: the amplifiers measure), OC_TOFF bit 6 */
#define DRV8301_CTRL2_GAIN(code) (((uint32_t)(code) & 3u) << 2)
#define DRV8301_CTRL2_GAIN_OF(v) (((uint32_t)(v) >> 2) & 3u)

/* the amplifiers' gain (control register 2's GAIN field) */
typedef enum { DRV8301_GAIN_10 = 0, DRV8301_GAIN_20 = 1, DRV8301_GAIN_40 = 2, DRV8301_GAIN_80 = 3 } drv8301_gain_t;
/* its value in V/V: 10, 20, 40, 80 */
#define DRV8301_GAIN_VV(code) (10u << ((uint32_t)(code) & 3u))

/* One DRV8301: its chip select and a name for the error texts
 * (e.g. "M0 (nCS PC13)"). */
typedef struct {
    gpio_regs_t *cs_port;
    uint8_t cs_pin;
    const char *name;
} drv8301_chip_t;

/* The SPI master and the last error. */
typedef struct {
    spi_regs_t *spi;
    uint32_t timeout_polls; /* polls of a flag before it counts as a timeout */
    uint32_t cs_high_polls; /* polls nCS stays high after a frame */
    stm32_status_t status;  /* STM32_OK, or the last error's code */
    char error[128];        /* its text ("" if none) */
} drv8301_bus_t;

/* SPI's prescaler for a clock of at most max_hz from the APB clock pclk_hz
 * (f = pclk / 2^(br+1), br 0..7); false if even /256 is faster. */
bool drv8301_spi_divider(uint32_t pclk_hz, uint32_t max_hz, uint32_t *br);

/* The SPI as the DRV8301's master: mode 1, 16 bits, MSB first, software
 * chip selects, clock f_PCLK / 2^(br+1), enabled. */
void drv8301_bus_init(drv8301_bus_t *b, spi_regs_t *spi, uint32_t br, uint32_t timeout_polls, uint32_t cs_high_polls);

/* A chip's select: an output, high (not selected), low speed (DS8626: PC13
 * to PC15 switch at most 2 MHz). */
void drv8301_chip_init(const drv8301_chip_t *c);

/* One frame to chip c: out shifted out, the word shifted in meanwhile
 * stored in *in (may be NULL). False on a flag's timeout (the error set). */
bool drv8301_frame(drv8301_bus_t *b, const drv8301_chip_t *c, uint16_t out, uint16_t *in);

/* A register's 11 data bits: the read command, then again, whose answer
 * carries it. False on a timeout, or on an answer with the frame error bit
 * or another register's address (STM32_FAULT_GATE_DRIVER_CONFIG). */
bool drv8301_read(drv8301_bus_t *b, const drv8301_chip_t *c, uint32_t addr, uint16_t *data);

/* Writes control registers 1 and 2 (their 11 data bits), reads both back;
 * false on a timeout or if either differs from what was written (the
 * error names the chip, the register, the value written and the value
 * read). *ctrl2_read: control register 2 as read back (its GAIN field is
 * the gain the amplifiers run with). */
bool drv8301_configure(drv8301_bus_t *b, const drv8301_chip_t *c, uint16_t ctrl1, uint16_t ctrl2,
                       uint16_t *ctrl2_read);

/* The gate drivers' fault, for the text: "<what>; <chip> status 1 0x..,
 * status 2 0x.." for each of the n chips (their status registers read),
 * as STM32_FAULT_GATE_DRIVER_NFAULT. False if a read fails (the error is
 * then that read's). */
bool drv8301_fault_report(drv8301_bus_t *b, const drv8301_chip_t *chips, uint32_t n, const char *what);

/* A register's name, for texts ("status register 1", ... "control register 2"). */
const char *drv8301_register_name(uint32_t addr);

#endif /* STM32_DRV8301_H */
