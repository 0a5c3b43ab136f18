/*
 * frame.c - frame encoder and resynchronising decoder (frame.h).
 */
#include "frame.h"

#include "crc16.h"

#define RING_MASK ((uint16_t)(FRAME_RING - 1u))

enum {
    ST_HUNT = 0, /* looking for FRAME_SOF */
    ST_LEN,
    ST_CMD,
    ST_SEQ,
    ST_PAYLOAD,
    ST_CRC_HI,
    ST_CRC_LO
};

void frame_dec_init(frame_dec_t *d)
{
    uint16_t i;
    for (i = 0u; i < FRAME_RING; i++) {
        d->ring[i] = 0u;
    }
    d->head = 0u;
    d->rd = 0u;
    d->start = 0u;
    d->state = ST_HUNT;
    d->pos = 0u;
    d->crc = CRC16_INIT;
    d->crc_rx = 0u;
    d->idle = 0u;
    d->frame.cmd = 0u;
    d->frame.seq = 0u;
    d->frame.len = 0u;
    d->stats.frames = 0u;
    d->stats.crc_errors = 0u;
    d->stats.len_errors = 0u;
    d->stats.dropped = 0u;
    d->stats.timeouts = 0u;
}

void frame_dec_idle(frame_dec_t *d)
{
    d->idle = 1u;
}

uint16_t frame_dec_room(const frame_dec_t *d)
{
    return (uint16_t)(FRAME_RING - (uint16_t)(d->head - d->start));
}

uint16_t frame_dec_pending(const frame_dec_t *d)
{
    return (uint16_t)(d->head - d->rd);
}

uint16_t frame_dec_put(frame_dec_t *d, uint16_t octet)
{
    if (frame_dec_room(d) == 0u) {
        d->stats.dropped++;
        return 0u;
    }
    d->ring[d->head & RING_MASK] = (uint16_t)(octet & 0x00FFu);
    d->head++;
    d->idle = 0u;
    return 1u;
}

/* The candidate that started at d->start is not a frame: parse again from the octet after its
 * start octet. */
static void reject(frame_dec_t *d)
{
    d->start++;
    d->rd = d->start;
    d->state = ST_HUNT;
}

uint16_t frame_dec_poll(frame_dec_t *d, uint16_t max_steps)
{
    while (max_steps > 0u) {
        uint16_t o;
        if (d->rd == d->head) {
            if (d->idle == 0u || d->state == ST_HUNT) {
                break;
            }
            d->stats.timeouts++; /* silent line inside a candidate: it was truncated */
            reject(d);
            max_steps--;
            continue;
        }
        o = d->ring[d->rd & RING_MASK];
        max_steps--;
        d->rd++;
        switch (d->state) {
        case ST_HUNT:
            if (o == FRAME_SOF) {
                d->start = (uint16_t)(d->rd - 1u);
                d->crc = CRC16_INIT;
                d->state = ST_LEN;
            } else {
                d->start = d->rd; /* not needed any more */
            }
            break;
        case ST_LEN:
            if (o > FRAME_MAX_PAYLOAD) {
                d->stats.len_errors++;
                reject(d);
            } else {
                d->frame.len = o;
                d->crc = crc16_update(d->crc, o);
                d->state = ST_CMD;
            }
            break;
        case ST_CMD:
            d->frame.cmd = o;
            d->crc = crc16_update(d->crc, o);
            d->state = ST_SEQ;
            break;
        case ST_SEQ:
            d->frame.seq = o;
            d->crc = crc16_update(d->crc, o);
            d->pos = 0u;
            d->state = (d->frame.len > 0u) ? ST_PAYLOAD : ST_CRC_HI;
            break;
        case ST_PAYLOAD:
            d->frame.payload[d->pos] = o;
            d->pos++;
            d->crc = crc16_update(d->crc, o);
            if (d->pos >= d->frame.len) {
                d->state = ST_CRC_HI;
            }
            break;
        case ST_CRC_HI:
            d->crc_rx = (uint16_t)(o << 8);
            d->state = ST_CRC_LO;
            break;
        default: /* ST_CRC_LO */
            if ((uint16_t)(d->crc_rx | o) == d->crc) {
                d->start = d->rd; /* consumed */
                d->state = ST_HUNT;
                d->stats.frames++;
                return 1u;
            }
            d->stats.crc_errors++;
            reject(d);
            break;
        }
    }
    return 0u;
}

uint16_t frame_encode(uint16_t *out, uint16_t cap, uint16_t cmd, uint16_t seq, const uint16_t *payload,
                      uint16_t len)
{
    uint16_t i;
    uint16_t crc = CRC16_INIT;
    if (len > FRAME_MAX_PAYLOAD || cap < (uint16_t)(len + FRAME_OVERHEAD)) {
        return 0u;
    }
    out[0] = FRAME_SOF;
    out[1] = len;
    out[2] = (uint16_t)(cmd & 0x00FFu);
    out[3] = (uint16_t)(seq & 0x00FFu);
    for (i = 0u; i < len; i++) {
        out[4u + i] = (uint16_t)(payload[i] & 0x00FFu);
    }
    crc = crc16_octets(crc, &out[1], (uint16_t)(len + 3u));
    out[4u + len] = (uint16_t)(crc >> 8);
    out[5u + len] = (uint16_t)(crc & 0x00FFu);
    return (uint16_t)(len + FRAME_OVERHEAD);
}

void frame_put_u16(uint16_t *p, uint16_t v)
{
    p[0] = (uint16_t)(v & 0x00FFu);
    p[1] = (uint16_t)(v >> 8);
}

void frame_put_u32(uint16_t *p, uint32_t v)
{
    frame_put_u16(p, (uint16_t)(v & 0xFFFFu));
    frame_put_u16(&p[2], (uint16_t)(v >> 16));
}

uint16_t frame_get_u16(const uint16_t *p)
{
    return (uint16_t)((uint16_t)(p[0] & 0x00FFu) | (uint16_t)((p[1] & 0x00FFu) << 8));
}

uint32_t frame_get_u32(const uint16_t *p)
{
    return (uint32_t)frame_get_u16(p) | ((uint32_t)frame_get_u16(&p[2]) << 16);
}

void frame_put_i32(uint16_t *p, int32_t v)
{
    uint32_t u;
    if (v < 0) {
        u = (uint32_t)0xFFFFFFFFu - (uint32_t)(-(v + 1)); /* two's complement without conversion of a negative */
    } else {
        u = (uint32_t)v;
    }
    frame_put_u32(p, u);
}

int32_t frame_get_i32(const uint16_t *p)
{
    const uint32_t u = frame_get_u32(p);
    if (u >= 0x80000000u) {
        return (int32_t)-(int32_t)(0xFFFFFFFFu - u) - 1;
    }
    return (int32_t)u;
}
