/*
 * f2812_eeprom.c - the storage medium of hal.h on a 25LC256-class SPI EEPROM on SPI-A (fact sheet
 * 9.2; f2812_board.h). Word w lives at octets 2w (high) and 2w + 1 (low).
 *
 * Why an EEPROM and not the F2812's flash (docs/operate.md, "Stored parameters"): a flash sector
 * erase takes about 10 s with the CPU in TI's API and interrupts off for up to 3-4 ms at a time,
 * so the drive must be stopped, the API is a TI binary each user must link, a power cut during
 * the erase can deplete the sector, and the endurance is about 20 000 cycles. The EEPROM writes
 * a 64-octet page in 5 ms without stalling the CPU, in place (no erase), for 10^6 cycles, with
 * code that is ours and tested here, for four pins and one part on the board.
 *
 * Commands (EE ✔): WREN 0x06 in its own chip-select frame before every WRITE (the part clears
 * its write-enable latch after each write); WRITE 0x02 + 16-bit octet address + data, never
 * across a 64-octet page (the address wraps inside the page); READ 0x03 + address, then any
 * number of octets; RDSR 0x05 returns the status register, WIP bit 0 = write in progress.
 * hal_store_erase does nothing but check its range: words are rewritten in place.
 */
#include "hal.h"

#include "f2812_board.h"
#include "f2812_hal.h"

#define EE_WREN 0x06u
#define EE_WRITE 0x02u
#define EE_READ 0x03u
#define EE_RDSR 0x05u
#define EE_SR_WIP 0x01u
#define EE_ERASE_WORDS ((uint16_t)(F2812_EEPROM_PAGE_OCTETS / 2u))

static uint16_t in_range(uint16_t addr, uint16_t n)
{
    return (uint16_t)((uint32_t)addr + n <= (uint32_t)F2812_EEPROM_WORDS);
}

/* Command opcode + octet address of word addr (chip select already low). */
static uint16_t send_cmd(uint16_t op, uint16_t addr)
{
    const uint16_t oa = (uint16_t)(addr << 1);
    uint16_t rx;
    return (uint16_t)(f2812_spi_xfer(op, &rx) && f2812_spi_xfer((uint16_t)(oa >> 8), &rx) && f2812_spi_xfer((uint16_t)(oa & 0xFFu), &rx));
}

/* Waits for the end of the write cycle, servicing the watchdog. */
static uint16_t wait_ready(void)
{
    uint16_t polls;
    for (polls = 0u; polls < F2812_EEPROM_WIP_POLLS; polls++) {
        uint16_t sr = 0u;
        uint16_t ok;
        f2812_spi_cs(1u);
        ok = (uint16_t)(f2812_spi_xfer(EE_RDSR, &sr) && f2812_spi_xfer(0x00u, &sr));
        f2812_spi_cs(0u);
        if (ok == 0u) {
            return HAL_STORE_ERR_DEVICE;
        }
        if ((sr & EE_SR_WIP) == 0u) {
            return HAL_STORE_OK;
        }
        hal_watchdog_service();
    }
    return HAL_STORE_ERR_DEVICE;
}

uint16_t hal_store_words(void) { return (uint16_t)F2812_EEPROM_WORDS; }

uint16_t hal_store_erase_words(void) { return EE_ERASE_WORDS; }

uint16_t hal_store_read(uint16_t addr, uint16_t *buf, uint16_t n)
{
    uint16_t i;
    uint16_t ok;
    if (in_range(addr, n) == 0u) {
        return HAL_STORE_ERR_RANGE;
    }
    f2812_spi_cs(1u);
    ok = send_cmd(EE_READ, addr);
    for (i = 0u; ok != 0u && i < n; i++) {
        uint16_t hi = 0u;
        uint16_t lo = 0u;
        ok = (uint16_t)(f2812_spi_xfer(0x00u, &hi) && f2812_spi_xfer(0x00u, &lo));
        buf[i] = (uint16_t)((uint16_t)(hi << 8) | lo);
    }
    f2812_spi_cs(0u);
    return ok != 0u ? HAL_STORE_OK : HAL_STORE_ERR_DEVICE;
}

uint16_t hal_store_write(uint16_t addr, const uint16_t *buf, uint16_t n)
{
    uint16_t done = 0u;
    if (in_range(addr, n) == 0u) {
        return HAL_STORE_ERR_RANGE;
    }
    while (done < n) {
        const uint16_t a = (uint16_t)(addr + done);
        /* words left in a's page */
        uint16_t chunk = (uint16_t)(EE_ERASE_WORDS - (a & (uint16_t)(EE_ERASE_WORDS - 1u)));
        uint16_t i;
        uint16_t ok;
        uint16_t rx;
        uint16_t r;
        if (chunk > (uint16_t)(n - done)) {
            chunk = (uint16_t)(n - done);
        }
        f2812_spi_cs(1u);
        ok = f2812_spi_xfer(EE_WREN, &rx);
        f2812_spi_cs(0u);
        f2812_spi_cs(1u);
        ok = (uint16_t)(ok && send_cmd(EE_WRITE, a));
        for (i = 0u; ok != 0u && i < chunk; i++) {
            const uint16_t w = buf[done + i];
            ok = (uint16_t)(f2812_spi_xfer((uint16_t)(w >> 8), &rx) && f2812_spi_xfer((uint16_t)(w & 0xFFu), &rx));
        }
        f2812_spi_cs(0u); /* the write cycle starts at the rising chip select */
        if (ok == 0u) {
            return HAL_STORE_ERR_DEVICE;
        }
        r = wait_ready();
        if (r != HAL_STORE_OK) {
            return r;
        }
        done = (uint16_t)(done + chunk);
    }
    return HAL_STORE_OK;
}

uint16_t hal_store_erase(uint16_t addr, uint16_t n)
{
    if (in_range(addr, n) == 0u || (addr & (uint16_t)(EE_ERASE_WORDS - 1u)) != 0u ||
        (n & (uint16_t)(EE_ERASE_WORDS - 1u)) != 0u) {
        return HAL_STORE_ERR_RANGE;
    }
    return HAL_STORE_OK;
}
