/*
 * crc16.h - CRC-16/CCITT-FALSE, the one checksum of the serial frames (frame.h) and of the stored
 * parameter records (store.h).
 *
 * CRC-16/CCITT-FALSE: polynomial 0x1021 (x^16 + x^12 + x^5 + 1), initial value 0xFFFF, octets
 * fed most significant bit first, no reflection, no final XOR. Check value: the nine ASCII octets
 * "123456789" give 0x29B1. A host computes the same value with Python's
 * binascii.crc_hqx(data, 0xFFFF). The non-zero initial value makes leading zero octets count
 * (CRC-16/XMODEM, the same polynomial with initial value 0, does not see them).
 *
 * Octets travel in 16-bit units (the C28x has no 8-bit type): only bits 7:0 of each unit are fed;
 * bits 15:8 are ignored. Bitwise, 8 shift/XOR steps per octet, no table (no constant RAM or flash
 * spent; the background loop runs it at line rate, 11.5 k octets/s at 115200 baud).
 */
#ifndef CRC16_H
#define CRC16_H

#include <stdint.h>

#define CRC16_INIT ((uint16_t)0xFFFFu)

/* The CRC after one more octet (bits 7:0 of octet). */
uint16_t crc16_update(uint16_t crc, uint16_t octet);

/* The CRC after the octets buf[0..n-1] (bits 7:0 of each unit), starting from crc. */
uint16_t crc16_octets(uint16_t crc, const uint16_t *buf, uint16_t n);

/* The CRC after the 16-bit words buf[0..n-1], each fed as two octets, high octet first (the
 * stored-parameter records: store.h). */
uint16_t crc16_words(uint16_t crc, const uint16_t *buf, uint16_t n);

#endif /* CRC16_H */
