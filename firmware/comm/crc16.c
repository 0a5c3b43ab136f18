/*
 * crc16.c - CRC-16/CCITT-FALSE (crc16.h).
 */
#include "crc16.h"

uint16_t crc16_update(uint16_t crc, uint16_t octet)
{
    uint16_t i;
    crc = (uint16_t)(crc ^ (uint16_t)((octet & 0x00FFu) << 8));
    for (i = 0u; i < 8u; i++) {
        if ((crc & 0x8000u) != 0u) {
            crc = (uint16_t)((uint16_t)(crc << 1) ^ 0x1021u);
        } else {
            crc = (uint16_t)(crc << 1);
        }
    }
    return crc;
}

uint16_t crc16_octets(uint16_t crc, const uint16_t *buf, uint16_t n)
{
    uint16_t i;
    for (i = 0u; i < n; i++) {
        crc = crc16_update(crc, buf[i]);
    }
    return crc;
}

uint16_t crc16_words(uint16_t crc, const uint16_t *buf, uint16_t n)
{
    uint16_t i;
    for (i = 0u; i < n; i++) {
        crc = crc16_update(crc, (uint16_t)(buf[i] >> 8));
        crc = crc16_update(crc, buf[i]);
    }
    return crc;
}
