#include "bxcan.h"

bool bxcan_timing(uint32_t pclk_hz, uint32_t bitrate, uint32_t sample_permille, bxcan_timing_t *t)
{
    bool found = false;
    uint32_t best_err = 0xFFFFFFFFu;
    for (uint32_t tq = 8u; tq <= 25u; ++tq) {
        const uint64_t q = (uint64_t)bitrate * tq;
        if (q == 0u || (pclk_hz % q) != 0u) {
            continue;
        }
        const uint32_t brp = (uint32_t)(pclk_hz / q);
        if (brp < 1u || brp > 1024u) {
            continue;
        }
        /* sample point (1 + bs1)/tq nearest the target */
        for (uint32_t bs2 = 1u; bs2 <= 8u; ++bs2) {
            const uint32_t bs1 = tq - 1u - bs2;
            if (bs1 < 1u || bs1 > 16u) {
                continue;
            }
            const uint32_t sp = 1000u * (1u + bs1) / tq;
            const uint32_t err = sp > sample_permille ? sp - sample_permille : sample_permille - sp;
            if (sp < 750u || sp > 900u || err >= best_err) {
                continue;
            }
            best_err = err;
            found = true;
            t->brp = brp;
            t->tq = tq;
            t->bs1 = bs1;
            t->bs2 = bs2;
            t->sjw = bs2 < 4u ? bs2 : 4u; /* the largest resynchronisation jump allowed, <= BS2 */
            t->sample_permille = sp;
        }
    }
    if (found) {
        t->btr =
            CAN_BTR_BRP(t->brp - 1u) | CAN_BTR_TS1(t->bs1 - 1u) | CAN_BTR_TS2(t->bs2 - 1u) | CAN_BTR_SJW(t->sjw - 1u);
    }
    return found;
}

static bool wait_msr(can_regs_t *can, uint32_t mask, uint32_t want, uint32_t n)
{
    for (uint32_t k = 0; k < n; ++k) {
        if ((can->MSR & mask) == want) {
            return true;
        }
    }
    return false;
}

void bxcan_node_filter(can_regs_t *can, uint8_t node)
{
    /* filter bank 0, 32-bit mask mode, FIFO 0: id 0x200 | node in the
     * standard id (bits 31:21), mask 0x70F and IDE, RTR (standard data
     * frames only) */
    can->FMR |= CAN_FMR_FINIT;
    can->FA1R &= ~1u;
    can->FS1R |= 1u;   /* 32 bit */
    can->FM1R &= ~1u;  /* mask mode */
    can->FFA1R &= ~1u; /* FIFO 0 */
    can->FILTER[0].FR1 = CAN_TIR_STID(0x200u | (node & 0xFu));
    can->FILTER[0].FR2 = CAN_TIR_STID(0x70Fu) | CAN_RIR_IDE | CAN_RIR_RTR;
    can->FA1R |= 1u;
    can->FMR &= ~CAN_FMR_FINIT;
}

stm32_status_t bxcan_init(can_regs_t *can, const bxcan_timing_t *t, uint8_t node, uint32_t timeout_polls)
{
    can->MCR = CAN_MCR_INRQ; /* out of sleep, into initialisation */
    if (!wait_msr(can, CAN_MSR_INAK | CAN_MSR_SLAK, CAN_MSR_INAK, timeout_polls)) {
        return STM32_FAULT_CAN_TIMEOUT;
    }
    can->MCR = CAN_MCR_INRQ | CAN_MCR_ABOM | CAN_MCR_TXFP;
    can->BTR = t->btr;
    bxcan_node_filter(can, node);
    can->MCR &= ~CAN_MCR_INRQ; /* normal mode after 11 recessive bits on the bus */
    if (!wait_msr(can, CAN_MSR_INAK, 0u, timeout_polls)) {
        return STM32_FAULT_CAN_TIMEOUT;
    }
    return STM32_OK;
}

bool bxcan_send(can_regs_t *can, const hal_can_frame_t *f)
{
    for (uint32_t i = 0; i < 3u; ++i) {
        if ((can->TSR & CAN_TSR_TME(i)) == 0u) {
            continue;
        }
        can_tx_mailbox_t *m = &can->TX[i];
        const uint32_t dlc = f->dlc > 8u ? 8u : f->dlc;
        m->TDTR = dlc;
        m->TDLR = (uint32_t)f->data[0] | ((uint32_t)f->data[1] << 8) | ((uint32_t)f->data[2] << 16) |
                  ((uint32_t)f->data[3] << 24);
        m->TDHR = (uint32_t)f->data[4] | ((uint32_t)f->data[5] << 8) | ((uint32_t)f->data[6] << 16) |
                  ((uint32_t)f->data[7] << 24);
        m->TIR = CAN_TIR_STID(f->id & 0x7FFu) | CAN_TIR_TXRQ;
        return true;
    }
    return false;
}

bool bxcan_receive(can_regs_t *can, hal_can_frame_t *f)
{
    if ((can->RF0R & CAN_RFR_FMP_MASK) == 0u) {
        return false;
    }
    const can_rx_mailbox_t *m = &can->RX[0];
    const uint32_t rir = m->RIR;
    /* the filter passes standard data frames only; anything else is handed
     * on with an identifier no node accepts */
    f->id = ((rir & (CAN_RIR_IDE | CAN_RIR_RTR)) != 0u) ? 0xFFFFFFFFu : (rir >> 21);
    f->dlc = (uint8_t)(m->RDTR & 0xFu);
    const uint32_t lo = m->RDLR, hi = m->RDHR;
    for (uint32_t k = 0; k < 4u; ++k) {
        f->data[k] = (uint8_t)(lo >> (8u * k));
        f->data[4u + k] = (uint8_t)(hi >> (8u * k));
    }
    can->RF0R = CAN_RFR_RFOM; /* release the mailbox */
    return true;
}
