/*
 * stm32f405_regs.h - the STM32F405's registers this backend uses, written
 * here from the reference manual RM0090 (Rev 19): one struct per
 * peripheral with its registers at their offsets (checked by
 * _Static_assert), the base addresses of the memory map (RM0090 2.3), and
 * the bit fields the drivers set. No vendor header is used. Drivers take a
 * pointer to a block, so the host tests hand them fake blocks in RAM.
 */
#ifndef STM32F405_REGS_H
#define STM32F405_REGS_H

#include <stddef.h>
#include <stdint.h>

#define REG volatile uint32_t
#ifdef __cplusplus
#define STM32_ASSERT(c, m) static_assert(c, m)
#else
#define STM32_ASSERT(c, m) _Static_assert(c, m)
#endif

/* ---- RCC, RM0090 7.3 ---- */
typedef struct {
    REG CR, PLLCFGR, CFGR, CIR, AHB1RSTR, AHB2RSTR, AHB3RSTR, r1c;
    REG APB1RSTR, APB2RSTR, r28, r2c, AHB1ENR, AHB2ENR, AHB3ENR, r3c;
    REG APB1ENR, APB2ENR, r48, r4c, AHB1LPENR, AHB2LPENR, AHB3LPENR, r5c;
    REG APB1LPENR, APB2LPENR, r68, r6c, BDCR, CSR, r78, r7c, SSCGR, PLLI2SCFGR;
} rcc_regs_t;
STM32_ASSERT(offsetof(rcc_regs_t, CSR) == 0x74, "RCC_CSR at 0x74");
STM32_ASSERT(offsetof(rcc_regs_t, APB2ENR) == 0x44, "RCC_APB2ENR at 0x44");
#define RCC_CR_HSION (1u << 0)
#define RCC_CR_HSIRDY (1u << 1)
#define RCC_CR_HSEON (1u << 16)
#define RCC_CR_HSERDY (1u << 17)
#define RCC_CR_HSEBYP (1u << 18)
#define RCC_CR_CSSON (1u << 19)
#define RCC_CR_PLLON (1u << 24)
#define RCC_CR_PLLRDY (1u << 25)
#define RCC_PLLCFGR_M(m) ((uint32_t)(m) << 0)     /* 2..63 */
#define RCC_PLLCFGR_N(n) ((uint32_t)(n) << 6)     /* 50..432 */
#define RCC_PLLCFGR_P(p) ((uint32_t)((p) / 2u - 1u) << 16) /* 2, 4, 6, 8 */
#define RCC_PLLCFGR_SRC_HSE (1u << 22)
#define RCC_PLLCFGR_Q(q) ((uint32_t)(q) << 24)    /* 2..15 */
#define RCC_CFGR_SW_PLL (2u << 0)
#define RCC_CFGR_SWS_MASK (3u << 2)
#define RCC_CFGR_SWS_PLL (2u << 2)
#define RCC_CFGR_PPRE1_DIV4 (5u << 10)
#define RCC_CFGR_PPRE2_DIV2 (4u << 13)
#define RCC_CSR_LSION (1u << 0)
#define RCC_CSR_LSIRDY (1u << 1)
#define RCC_CSR_RMVF (1u << 24)
#define RCC_CSR_IWDGRSTF (1u << 29)
#define RCC_CSR_WWDGRSTF (1u << 30)
#define RCC_AHB1ENR_GPIO(port) (1u << (port)) /* port 0 = A */
#define RCC_APB1ENR_TIM2EN (1u << 0)
#define RCC_APB1ENR_SPI3EN (1u << 15) /* RM0090 7.3.13 */
#define RCC_APB1ENR_TIM3EN (1u << 1) /* RM0090 7.3.13 */
#define RCC_APB1ENR_TIM5EN (1u << 3) /* RM0090 7.3.13 */
#define RCC_APB1ENR_CAN1EN (1u << 25)
#define RCC_APB2ENR_TIM1EN (1u << 0)
#define RCC_APB2ENR_TIM8EN (1u << 1) /* RM0090 7.3.14 */
#define RCC_APB2ENR_ADC1EN (1u << 8)
#define RCC_APB2ENR_ADC2EN (1u << 9)
#define RCC_APB2ENR_ADC3EN (1u << 10)

/* ---- FLASH interface, RM0090 3.9 ---- */
typedef struct {
    REG ACR, KEYR, OPTKEYR, SR, CR, OPTCR;
} flash_regs_t;
#define FLASH_ACR_LATENCY(ws) ((uint32_t)(ws) << 0)
#define FLASH_ACR_LATENCY_MASK 7u
#define FLASH_ACR_PRFTEN (1u << 8)
#define FLASH_ACR_ICEN (1u << 9)
#define FLASH_ACR_DCEN (1u << 10)
STM32_ASSERT(offsetof(flash_regs_t, SR) == 0x0C, "FLASH_SR at 0x0C");
STM32_ASSERT(offsetof(flash_regs_t, CR) == 0x10, "FLASH_CR at 0x10");
/* the key sequence that unlocks FLASH_CR (RM0090 3.6.1, 3.9.2); a wrong
 * key locks it until the next reset */
#define FLASH_KEY1 0x45670123u
#define FLASH_KEY2 0xCDEF89ABu
/* FLASH_SR (RM0090 3.9.4): the error flags are cleared by writing 1 */
#define FLASH_SR_EOP (1u << 0)
#define FLASH_SR_OPERR (1u << 1)  /* operation error (set with ERRIE only) */
#define FLASH_SR_WRPERR (1u << 4) /* write protection error */
#define FLASH_SR_PGAERR (1u << 5) /* programming alignment error (a 128-bit row crossed) */
#define FLASH_SR_PGPERR (1u << 6) /* programming parallelism error (access size against PSIZE) */
#define FLASH_SR_PGSERR (1u << 7) /* programming sequence error (a write without PG, ...) */
#define FLASH_SR_ERRORS (FLASH_SR_OPERR | FLASH_SR_WRPERR | FLASH_SR_PGAERR | FLASH_SR_PGPERR | FLASH_SR_PGSERR)
#define FLASH_SR_BSY (1u << 16)
/* FLASH_CR (RM0090 3.9.5) */
#define FLASH_CR_PG (1u << 0)
#define FLASH_CR_SER (1u << 1)
#define FLASH_CR_SNB(n) (((uint32_t)(n) & 0xFu) << 3) /* sector 0-11 */
#define FLASH_CR_PSIZE_X32 (2u << 8)                  /* 32-bit program and erase parallelism (2.7-3.6 V, RM0090 3.6.2) */
#define FLASH_CR_STRT (1u << 16)
#define FLASH_CR_LOCK (1u << 31)

/* ---- GPIO, RM0090 8.4 ---- */
typedef struct {
    REG MODER, OTYPER, OSPEEDR, PUPDR, IDR, ODR, BSRR, LCKR, AFR[2];
} gpio_regs_t;
STM32_ASSERT(offsetof(gpio_regs_t, AFR) == 0x20, "GPIO_AFRL at 0x20");

/* ---- TIM1 (advanced); TIM2, TIM3 (general purpose), RM0090 17.4, 18.4 ---- */
typedef struct {
    REG CR1, CR2, SMCR, DIER, SR, EGR, CCMR1, CCMR2, CCER, CNT, PSC, ARR, RCR;
    REG CCR[4];
    REG BDTR, DCR, DMAR;
} tim_regs_t;
STM32_ASSERT(offsetof(tim_regs_t, RCR) == 0x30, "TIMx_RCR at 0x30");
STM32_ASSERT(offsetof(tim_regs_t, BDTR) == 0x44, "TIM1_BDTR at 0x44");
#define TIM_CR1_CEN (1u << 0)
#define TIM_CR1_URS (1u << 2)
#define TIM_CR1_CMS_CENTER1 (1u << 5) /* centre-aligned mode 1 */
#define TIM_CR1_CMS_MASK (3u << 5)
#define TIM_CR1_ARPE (1u << 7)
#define TIM_CR1_DIR (1u << 4)         /* counting down; read-only in encoder mode (RM0090 18.4.1) */
#define TIM_SMCR_SMS_ENCODER3 (3u << 0) /* encoder mode 3: both edges of TI1FP1 and TI2FP2 (RM0090 18.4.3) */
#define TIM_SMCR_SMS_MASK (7u << 0)
#define TIM_SMCR_SMS_TRIGGER (6u << 0)  /* trigger mode: the counter starts at TRGI's rising edge (RM0090 17.4.3) */
#define TIM_SMCR_SMS_EXT_CLOCK1 (7u << 0) /* external clock mode 1: TRGI's rising edges clock the counter */
#define TIM_SMCR_TS(x) ((uint32_t)(x) << 4)
#define TIM_SMCR_TS_MASK (7u << 4)
#define TIM_SMCR_TS_ITR0 0u             /* TIM8's ITR0 = TIM1's TRGO (RM0090 17.4.3, table 86) */
#define TIM_SMCR_TS_TI1FP1 5u           /* filtered timer input 1 */
#define TIM_CR2_MMS_ENABLE (1u << 4)  /* TRGO = CEN: the counter's enable starts the slaves */
#define TIM_CR2_MMS_MASK (7u << 4)
#define TIM_CR2_MMS_UPDATE (2u << 4)  /* TRGO on the update event */
#define TIM_CR2_MMS_OC4REF (7u << 4)  /* TRGO = OC4REF */
#define TIM_DIER_UIE (1u << 0)
#define TIM_DIER_BIE (1u << 7)
#define TIM_SR_UIF (1u << 0)
#define TIM_SR_BIF (1u << 7)
#define TIM_SR_CCIF(ch) (1u << (1u + (ch)))  /* CCxIF, ch 0-3 (RM0090 18.4.5) */
#define TIM_SR_CCOF(ch) (1u << (9u + (ch)))  /* CCxOF: a capture while CCxIF was set */
#define TIM_EGR_UG (1u << 0)
#define TIM_CCMR_OC_PWM1(ch) ((6u << 4) << (8u * ((ch) & 1u))) /* in CCMR1 (ch 0, 1) or CCMR2 (2, 3) */
#define TIM_CCMR_OC_PWM2(ch) ((7u << 4) << (8u * ((ch) & 1u)))
#define TIM_CCMR_OC_PE(ch) ((1u << 3) << (8u * ((ch) & 1u)))
/* input capture (RM0090 18.4.7, 18.4.8): CCxS = 01, ICx mapped on TIx;
 * ICxF the digital filter, 0..15 */
#define TIM_CCMR_CC_IN_TI(ch) (1u << (8u * ((ch) & 1u)))
#define TIM_CCMR_IC_F(ch, f) (((uint32_t)(f) & 0xFu) << (4u + 8u * ((ch) & 1u)))
#define TIM_CCER_CCE(ch) (1u << (4u * (ch)))
#define TIM_CCER_CCP(ch) (1u << (4u * (ch) + 1u)) /* input: TIx inverted (RM0090 18.4.9) */
#define TIM_CCER_CCNE(ch) (1u << (4u * (ch) + 2u))
#define TIM_BDTR_DTG_MASK 0xFFu
#define TIM_BDTR_OSSI (1u << 10)
#define TIM_BDTR_OSSR (1u << 11)
#define TIM_BDTR_BKE (1u << 12)
#define TIM_BDTR_BKP (1u << 13) /* break active high */
#define TIM_BDTR_MOE (1u << 15)

/* ---- ADC, RM0090 13.13 ---- */
typedef struct {
    REG SR, CR1, CR2, SMPR1, SMPR2, JOFR[4], HTR, LTR, SQR1, SQR2, SQR3, JSQR, JDR[4], DR;
} adc_regs_t;
STM32_ASSERT(offsetof(adc_regs_t, JSQR) == 0x38, "ADC_JSQR at 0x38");
STM32_ASSERT(offsetof(adc_regs_t, JDR) == 0x3C, "ADC_JDR1 at 0x3C");
typedef struct {
    REG CSR, CCR, CDR;
} adc_common_regs_t;
#define ADC_SR_JEOC (1u << 2)
#define ADC_SR_OVR (1u << 5)
#define ADC_CR1_JEOCIE (1u << 7)
#define ADC_CR1_SCAN (1u << 8)
#define ADC_CR2_ADON (1u << 0)
#define ADC_CR2_JEXTSEL(x) ((uint32_t)(x) << 16)
#define ADC_JEXTSEL_TIM1_TRGO 1u
#define ADC_JEXTSEL_MASK (0xFu << 16)
#define ADC_CR2_JEXTEN_RISING (1u << 20)
#define ADC_CR2_JEXTEN_MASK (3u << 20)
#define ADC_CR2_JSWSTART (1u << 22)
#define ADC_CCR_ADCPRE_DIV4 (1u << 16)

/* ---- bxCAN, RM0090 32.9 ---- */
typedef struct {
    REG TIR, TDTR, TDLR, TDHR;
} can_tx_mailbox_t;
typedef struct {
    REG RIR, RDTR, RDLR, RDHR;
} can_rx_mailbox_t;
typedef struct {
    REG FR1, FR2;
} can_filter_t;
typedef struct {
    REG MCR, MSR, TSR, RF0R, RF1R, IER, ESR, BTR;
    REG r020[88];
    can_tx_mailbox_t TX[3];
    can_rx_mailbox_t RX[2];
    REG r1d0[12];
    REG FMR, FM1R, r208, FS1R, r210, FFA1R, r218, FA1R;
    REG r220[8];
    can_filter_t FILTER[28];
} can_regs_t;
STM32_ASSERT(offsetof(can_regs_t, TX) == 0x180, "CAN_TI0R at 0x180");
STM32_ASSERT(offsetof(can_regs_t, RX) == 0x1B0, "CAN_RI0R at 0x1B0");
STM32_ASSERT(offsetof(can_regs_t, FMR) == 0x200, "CAN_FMR at 0x200");
STM32_ASSERT(offsetof(can_regs_t, FA1R) == 0x21C, "CAN_FA1R at 0x21C");
STM32_ASSERT(offsetof(can_regs_t, FILTER) == 0x240, "CAN_F0R1 at 0x240");
#define CAN_MCR_INRQ (1u << 0)
#define CAN_MCR_SLEEP (1u << 1)
#define CAN_MCR_TXFP (1u << 2)
#define CAN_MCR_ABOM (1u << 6)
#define CAN_MSR_INAK (1u << 0)
#define CAN_MSR_SLAK (1u << 1)
#define CAN_TSR_TME(i) (1u << (26u + (i)))
#define CAN_RFR_FMP_MASK 3u
#define CAN_RFR_FOVR (1u << 4)
#define CAN_RFR_RFOM (1u << 5)
#define CAN_IER_TMEIE (1u << 0)
#define CAN_IER_FMPIE0 (1u << 1)
#define CAN_IER_BOFIE (1u << 10)
#define CAN_IER_ERRIE (1u << 15)
#define CAN_ESR_BOFF (1u << 2)
#define CAN_TIR_TXRQ (1u << 0)
#define CAN_TIR_STID(id) ((uint32_t)(id) << 21)
#define CAN_RIR_IDE (1u << 2)
#define CAN_RIR_RTR (1u << 1)
#define CAN_FMR_FINIT (1u << 0)
#define CAN_BTR_BRP(x) ((uint32_t)(x) << 0)
#define CAN_BTR_TS1(x) ((uint32_t)(x) << 16)
#define CAN_BTR_TS2(x) ((uint32_t)(x) << 20)
#define CAN_BTR_SJW(x) ((uint32_t)(x) << 24)

/* ---- IWDG, RM0090 19.4 ---- */
typedef struct {
    REG KR, PR, RLR, SR;
} iwdg_regs_t;
#define IWDG_KEY_ENABLE 0xCCCCu
#define IWDG_KEY_REFRESH 0xAAAAu
#define IWDG_KEY_UNLOCK 0x5555u
#define IWDG_SR_PVU (1u << 0)
#define IWDG_SR_RVU (1u << 1)

/* ---- SPI, RM0090 28.5 (SPI mode; the I2S registers after them unused) ---- */
typedef struct {
    REG CR1, CR2, SR, DR, CRCPR, RXCRCR, TXCRCR, I2SCFGR, I2SPR;
} spi_regs_t;
STM32_ASSERT(offsetof(spi_regs_t, DR) == 0x0C, "SPI_DR at 0x0C");
STM32_ASSERT(offsetof(spi_regs_t, I2SPR) == 0x20, "SPI_I2SPR at 0x20");
#define SPI_CR1_CPHA (1u << 0)     /* data captured on the second clock edge */
#define SPI_CR1_CPOL (1u << 1)     /* clock idle high */
#define SPI_CR1_MSTR (1u << 2)
#define SPI_CR1_BR(x) ((uint32_t)(x) << 3) /* f_PCLK / 2^(x+1), x 0..7 */
#define SPI_CR1_SPE (1u << 6)
#define SPI_CR1_LSBFIRST (1u << 7)
#define SPI_CR1_SSI (1u << 8)      /* the internal NSS level with SSM */
#define SPI_CR1_SSM (1u << 9)      /* software slave management */
#define SPI_CR1_DFF (1u << 11)     /* 16-bit frames */
#define SPI_SR_RXNE (1u << 0)
#define SPI_SR_TXE (1u << 1)
#define SPI_SR_MODF (1u << 5)
#define SPI_SR_OVR (1u << 6)
#define SPI_SR_BSY (1u << 7)

/* ---- memory map, RM0090 2.3 ---- */
#define STM32_TIM2_BASE 0x40000000u
#define STM32_TIM3_BASE 0x40000400u
#define STM32_TIM5_BASE 0x40000C00u
#define STM32_IWDG_BASE 0x40003000u
#define STM32_SPI3_BASE 0x40003C00u
#define STM32_CAN1_BASE 0x40006400u
#define STM32_TIM1_BASE 0x40010000u
#define STM32_TIM8_BASE 0x40010400u
#define STM32_ADC1_BASE 0x40012000u
#define STM32_ADC2_BASE 0x40012100u
#define STM32_ADC3_BASE 0x40012200u
#define STM32_ADC_COMMON_BASE 0x40012300u
#define STM32_GPIO_BASE(port) (0x40020000u + 0x400u * (uint32_t)(port))
#define STM32_RCC_BASE 0x40023800u
#define STM32_FLASH_IF_BASE 0x40023C00u

/* ---- EXTI and SYSCFG's EXTI line selection (RM0090 12.3, 9.2.3) ---- */
typedef struct {
    REG IMR, EMR, RTSR, FTSR, SWIER, PR;
} exti_regs_t;
STM32_ASSERT(offsetof(exti_regs_t, PR) == 0x14, "EXTI_PR at 0x14");
typedef struct {
    REG MEMRMP, PMC, EXTICR[4];
} syscfg_regs_t;
STM32_ASSERT(offsetof(syscfg_regs_t, EXTICR) == 0x08, "SYSCFG_EXTICR1 at 0x08");
#define STM32_EXTI_BASE 0x40013C00u
#define STM32_SYSCFG_BASE 0x40013800u
#define RCC_APB2ENR_SYSCFGEN (1u << 14) /* RM0090 7.3.14 */

/* ---- Cortex-M4 system control (ARMv7-M ARM B3) ---- */
#define SCB_CPACR (*(volatile uint32_t *)(uintptr_t)0xE000ED88u)
#define SCB_VTOR (*(volatile uint32_t *)(uintptr_t)0xE000ED08u)
#define NVIC_ISER(n) (*(volatile uint32_t *)(uintptr_t)(0xE000E100u + 4u * (uint32_t)(n)))
#define NVIC_ICER(n) (*(volatile uint32_t *)(uintptr_t)(0xE000E180u + 4u * (uint32_t)(n)))
#define NVIC_IPR8(irq) (*(volatile uint8_t *)(uintptr_t)(0xE000E400u + (uint32_t)(irq)))
#define SYST_CSR (*(volatile uint32_t *)(uintptr_t)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)(uintptr_t)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)(uintptr_t)0xE000E018u)

/* Interrupt numbers of the STM32F405 (RM0090 table 61) the backend uses. */
#define IRQ_ADC 18
#define IRQ_CAN1_TX 19
#define IRQ_CAN1_RX0 20
#define IRQ_CAN1_SCE 22
#define IRQ_TIM1_BRK_TIM9 24
#define IRQ_TIM2 28
#define IRQ_EXTI0 6 /* EXTI lines 0-4: 6-10 (RM0090 table 61) */
#define STM32F405_N_IRQ 82

/* Interrupts off and on around a short critical section (no-ops in a host
 * build of the drivers' tests). */
static inline void stm32_irq_disable(void)
{
#if defined(__arm__)
    __asm__ volatile("cpsid i" ::: "memory");
#endif
}
static inline void stm32_irq_enable(void)
{
#if defined(__arm__)
    __asm__ volatile("cpsie i" ::: "memory");
#endif
}

#endif /* STM32F405_REGS_H */
