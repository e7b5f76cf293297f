/*
 * bxcan.h - CAN1 (RM0090 ch. 32) for the drive's node (comm/can_node.h):
 * the bit timing computed from the APB1 clock and checked, a receive
 * filter that passes only the node's command identifiers (0x200-0x2FF
 * with the node in the low four bits, standard data frames) into FIFO 0,
 * and non-blocking transmit (a free mailbox or false) and receive. Every
 * wait on the hardware is bounded.
 */
#ifndef STM32_BXCAN_H
#define STM32_BXCAN_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/hal_types.h"
#include "stm32_status.h"
#include "stm32f405_regs.h"

/* Sample point CiA 301 recommends at 1 Mbit/s: 87.5 %; accepted within
 * 75-90 %. Time quanta per bit: 8-25 (BS1 1-16, BS2 1-8). */
#define BXCAN_SAMPLE_PERMILLE 875u

typedef struct {
    uint32_t brp;         /* prescaler, 1..1024 */
    uint32_t tq;          /* quanta per bit: 1 + bs1 + bs2 */
    uint32_t bs1, bs2, sjw;
    uint32_t sample_permille;
    uint32_t btr;         /* CAN_BTR */
} bxcan_timing_t;

/* The exact bit rate from pclk_hz with the sample point nearest
 * sample_permille (75-90 %); false if none is exact. */
bool bxcan_timing(uint32_t pclk_hz, uint32_t bitrate, uint32_t sample_permille, bxcan_timing_t *t);

/* Filter bank 0 to node's commands: standard data frames 0x200-0x2FF
 * whose low 4 bits are node (RM0090 32.7.4: a filter bank may change
 * while the controller runs, in filter initialisation mode, FINIT). */
void bxcan_node_filter(can_regs_t *can, uint8_t node);

/* Initialisation mode, timing, automatic bus-off recovery, transmit in
 * request order, the node's filter; then normal mode. */
stm32_status_t bxcan_init(can_regs_t *can, const bxcan_timing_t *t, uint8_t node, uint32_t timeout_polls);

/* Into a free transmit mailbox; false if the three are busy. */
bool bxcan_send(can_regs_t *can, const hal_can_frame_t *f);

/* The oldest frame of FIFO 0; false if empty. */
bool bxcan_receive(can_regs_t *can, hal_can_frame_t *f);

#endif /* STM32_BXCAN_H */
