/*
 * pil_console_store.c - hal.h's parameter store for the emulated consoles (pil_console.h): the
 * range checks and the word loops once, over the binding's word access (the Cortex-M image's RAM
 * array, the AVR image's EEPROM). An EEPROM rewrites words in place, so an erase of a range on
 * erase-unit boundaries has nothing to do.
 */
#include <stdint.h>

#include "hal.h"
#include "pil_console.h"

/* 1 when [addr, addr + n) lies in the store (32-bit sum: no wrap). */
static uint16_t in_store(uint16_t addr, uint16_t n)
{
    return (uint16_t)((uint32_t)addr + n <= (uint32_t)hal_store_words());
}

uint16_t hal_store_read(uint16_t addr, uint16_t *buf, uint16_t n)
{
    uint16_t k;
    if (in_store(addr, n) == 0U) {
        return HAL_STORE_ERR_RANGE;
    }
    for (k = 0U; k < n; k++) {
        buf[k] = pil_console_store_get((uint16_t)(addr + k));
    }
    return HAL_STORE_OK;
}

uint16_t hal_store_write(uint16_t addr, const uint16_t *buf, uint16_t n)
{
    uint16_t k;
    if (in_store(addr, n) == 0U) {
        return HAL_STORE_ERR_RANGE;
    }
    for (k = 0U; k < n; k++) {
        pil_console_store_put((uint16_t)(addr + k), buf[k]);
    }
    return HAL_STORE_OK;
}

uint16_t hal_store_erase(uint16_t addr, uint16_t n)
{
    const uint16_t unit = hal_store_erase_words();
    if (in_store(addr, n) == 0U || (addr & (unit - 1U)) != 0U || (n & (unit - 1U)) != 0U) {
        return HAL_STORE_ERR_RANGE;
    }
    return HAL_STORE_OK;
}
