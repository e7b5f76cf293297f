#include "drv8301.h"

#include "gpio.h"

/* ---- the error text: a fixed buffer, no printf ---- */

static void err_clear(drv8301_bus_t *b)
{
    b->status = STM32_OK;
    b->error[0] = '\0';
}

static void err_put(drv8301_bus_t *b, const char *s)
{
    uint32_t n = 0u;
    while (n + 1u < sizeof b->error && b->error[n] != '\0') ++n;
    while (n + 1u < sizeof b->error && *s != '\0') b->error[n++] = *s++;
    b->error[n] = '\0';
}

/* "0x" and v in hex, at least three digits (11 data bits) */
static void err_hex(drv8301_bus_t *b, uint32_t v)
{
    char t[11] = {'0', 'x'};
    uint32_t digits = 3u;
    while (digits < 8u && (v >> (4u * digits)) != 0u) ++digits;
    for (uint32_t k = 0u; k < digits; ++k) t[2u + k] = "0123456789ABCDEF"[(v >> (4u * (digits - 1u - k))) & 0xFu];
    t[2u + digits] = '\0';
    err_put(b, t);
}

static void err_chip(drv8301_bus_t *b, stm32_status_t code, const drv8301_chip_t *c)
{
    err_clear(b);
    b->status = code;
    err_put(b, "DRV8301 ");
    err_put(b, c->name != 0 ? c->name : "?");
    err_put(b, ": ");
}

const char *drv8301_register_name(uint32_t addr)
{
    switch (addr) {
    case DRV8301_REG_STATUS1: return "status register 1";
    case DRV8301_REG_STATUS2: return "status register 2";
    case DRV8301_REG_CTRL1: return "control register 1";
    case DRV8301_REG_CTRL2: return "control register 2";
    default: return "register ?";
    }
}

/* ---- the SPI ---- */

bool drv8301_spi_divider(uint32_t pclk_hz, uint32_t max_hz, uint32_t *br)
{
    for (uint32_t x = 0u; x < 8u; ++x) {
        if ((pclk_hz >> (x + 1u)) <= max_hz) {
            *br = x;
            return true;
        }
    }
    return false;
}

void drv8301_bus_init(drv8301_bus_t *b, spi_regs_t *spi, uint32_t br, uint32_t timeout_polls, uint32_t cs_high_polls)
{
    b->spi = spi;
    b->timeout_polls = timeout_polls;
    b->cs_high_polls = cs_high_polls;
    err_clear(b);
    /* RM0090 28.3.3, master: configured while SPE = 0, then enabled. Mode 1
     * (CPOL = 0, CPHA = 1), 16-bit frames (DFF), MSB first, the slave
     * select by software (SSM, SSI = 1: never a mode fault) */
    spi->CR1 = 0u;
    spi->CR2 = 0u;
    spi->CR1 = SPI_CR1_CPHA | SPI_CR1_MSTR | SPI_CR1_BR(br & 7u) | SPI_CR1_SSI | SPI_CR1_SSM | SPI_CR1_DFF;
    spi->CR1 |= SPI_CR1_SPE;
}

void drv8301_chip_init(const drv8301_chip_t *c)
{
    gpio_write(c->cs_port, c->cs_pin, true);
    gpio_config(c->cs_port, c->cs_pin, GPIO_OUTPUT, 0u, GPIO_NO_PULL);
    /* low speed (OSPEEDR 00): PC13-PC15 switch at most 2 MHz (DS8626) */
    c->cs_port->OSPEEDR &= ~(3u << (2u * c->cs_pin));
}

static void cs_high(const drv8301_bus_t *b, const drv8301_chip_t *c)
{
    gpio_write(c->cs_port, c->cs_pin, true);
    /* nCS high between two words (the DRV8301 takes a word at its rising edge) */
    for (volatile uint32_t k = 0u; k < b->cs_high_polls; ++k) {
    }
}

/* waits for (SR & flag) == want; false after timeout_polls polls */
static bool wait_flag(const drv8301_bus_t *b, uint32_t flag, bool want)
{
    for (uint32_t k = 0u; k < b->timeout_polls; ++k) {
        if (((b->spi->SR & flag) != 0u) == want) return true;
    }
    return false;
}

static bool timed_out(drv8301_bus_t *b, const drv8301_chip_t *c, const char *flag, uint16_t out)
{
    cs_high(b, c);
    err_chip(b, STM32_FAULT_GATE_DRIVER_SPI, c);
    err_put(b, "SPI ");
    err_put(b, flag);
    err_put(b, " timed out (frame ");
    err_hex(b, out);
    err_put(b, ")");
    return false;
}

bool drv8301_frame(drv8301_bus_t *b, const drv8301_chip_t *c, uint16_t out, uint16_t *in)
{
    spi_regs_t *spi = b->spi;
    gpio_write(c->cs_port, c->cs_pin, false);
    if (!wait_flag(b, SPI_SR_TXE, true)) return timed_out(b, c, "TXE (transmit buffer empty)", out);
    spi->DR = out;
    if (!wait_flag(b, SPI_SR_RXNE, true)) return timed_out(b, c, "RXNE (word received)", out);
    const uint16_t word = (uint16_t)(spi->DR & 0xFFFFu);
    if (!wait_flag(b, SPI_SR_BSY, false)) return timed_out(b, c, "BSY (bus busy)", out);
    cs_high(b, c);
    if (in != 0) *in = word;
    return true;
}

bool drv8301_read(drv8301_bus_t *b, const drv8301_chip_t *c, uint32_t addr, uint16_t *data)
{
    const uint16_t cmd = (uint16_t)(DRV8301_FRAME_READ | DRV8301_FRAME_ADDR(addr));
    uint16_t answer = 0u;
    /* the command; then again: its answer is the register (one frame late) */
    if (!drv8301_frame(b, c, cmd, 0) || !drv8301_frame(b, c, cmd, &answer)) return false;
    if ((answer & DRV8301_FRAME_READ) != 0u || DRV8301_FRAME_ADDR_OF(answer) != (addr & 0xFu)) {
        err_chip(b, STM32_FAULT_GATE_DRIVER_CONFIG, c);
        err_put(b, drv8301_register_name(addr));
        err_put(b, " read answered ");
        err_hex(b, answer);
        err_put(b, (answer & DRV8301_FRAME_READ) != 0u ? " (frame error)" : " (another register's address)");
        return false;
    }
    *data = (uint16_t)(answer & DRV8301_DATA_MASK);
    return true;
}

static bool write_reg(drv8301_bus_t *b, const drv8301_chip_t *c, uint32_t addr, uint16_t data)
{
    return drv8301_frame(b, c, (uint16_t)(DRV8301_FRAME_ADDR(addr) | (data & DRV8301_DATA_MASK)), 0);
}

static bool read_back(drv8301_bus_t *b, const drv8301_chip_t *c, uint32_t addr, uint16_t written, uint16_t *read)
{
    if (!drv8301_read(b, c, addr, read)) return false;
    if (*read != (written & DRV8301_DATA_MASK)) {
        err_chip(b, STM32_FAULT_GATE_DRIVER_CONFIG, c);
        err_put(b, drv8301_register_name(addr));
        err_put(b, " written ");
        err_hex(b, written & DRV8301_DATA_MASK);
        err_put(b, ", read back ");
        err_hex(b, *read);
        return false;
    }
    return true;
}

bool drv8301_configure(drv8301_bus_t *b, const drv8301_chip_t *c, uint16_t ctrl1, uint16_t ctrl2, uint16_t *ctrl2_read)
{
    err_clear(b);
    uint16_t r1 = 0u, r2 = 0u;
    if (!write_reg(b, c, DRV8301_REG_CTRL1, ctrl1) || !write_reg(b, c, DRV8301_REG_CTRL2, ctrl2) ||
        !read_back(b, c, DRV8301_REG_CTRL1, ctrl1, &r1) || !read_back(b, c, DRV8301_REG_CTRL2, ctrl2, &r2)) {
        return false;
    }
    *ctrl2_read = r2;
    return true;
}

bool drv8301_fault_report(drv8301_bus_t *b, const drv8301_chip_t *chips, uint32_t n, const char *what)
{
    uint16_t s1[2] = {0u, 0u}, s2[2] = {0u, 0u};
    for (uint32_t k = 0u; k < n && k < 2u; ++k) {
        if (!drv8301_read(b, &chips[k], DRV8301_REG_STATUS1, &s1[k]) ||
            !drv8301_read(b, &chips[k], DRV8301_REG_STATUS2, &s2[k])) {
            return false;
        }
    }
    err_clear(b);
    b->status = STM32_FAULT_GATE_DRIVER_NFAULT;
    err_put(b, what);
    for (uint32_t k = 0u; k < n && k < 2u; ++k) {
        err_put(b, "; ");
        err_put(b, chips[k].name != 0 ? chips[k].name : "?");
        err_put(b, " status 1 ");
        err_hex(b, s1[k]);
        err_put(b, ", 2 ");
        err_hex(b, s2[k]);
    }
    return true;
}
