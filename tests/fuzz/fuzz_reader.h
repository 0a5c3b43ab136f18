/*
 * fuzz_reader.h - the fuzz harnesses' reader of their input: bytes past the end read as 0, so
 * every input is a valid one.
 */
#ifndef FUZZ_READER_H
#define FUZZ_READER_H

#include <stddef.h>
#include <stdint.h>

typedef struct {
    const uint8_t *p;
    size_t n;
} rd_t;

static inline uint8_t rd_u8(rd_t *r)
{
    uint8_t v = 0U;
    if (r->n > 0U) {
        v = *r->p++;
        r->n--;
    }
    return v;
}

static inline uint16_t rd_u16(rd_t *r)
{
    uint16_t lo = rd_u8(r);
    return (uint16_t)(lo | ((uint16_t)rd_u8(r) << 8));
}

static inline uint32_t rd_u32(rd_t *r)
{
    uint32_t lo = rd_u16(r);
    return lo | ((uint32_t)rd_u16(r) << 16);
}

#endif /* FUZZ_READER_H */
