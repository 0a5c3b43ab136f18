/*
 * frame.h - binary frames of the serial protocol (proto.h): an encoder and a streaming decoder
 * that resynchronises after garbage, truncated frames and bad CRCs.
 *
 * Frame on the line (octets; each held in bits 7:0 of a uint16_t, the C28x has no 8-bit type):
 *
 *   SOF   LEN   CMD   SEQ   PAYLOAD[LEN]   CRC_HI   CRC_LO
 *   0xA5  0..FRAME_MAX_PAYLOAD
 *
 *   SOF      start octet, FRAME_SOF.
 *   LEN      payload length in octets, at most FRAME_MAX_PAYLOAD (a larger value is not a frame).
 *   CMD      command id (proto.h); a response carries the request's id | PROTO_RESPONSE.
 *   SEQ      sequence number chosen by the host, echoed in the response (matches answers to
 *            requests and shows lost frames).
 *   CRC      CRC-16/CCITT-FALSE (crc16.h) over LEN, CMD, SEQ and the payload (not SOF), sent
 *            high octet first. Python: binascii.crc_hqx(bytes([LEN, CMD, SEQ]) + payload, 0xFFFF).
 * Multi-octet payload fields are little-endian (frame_put_u16/u32, Python struct '<').
 *
 * Decoder. Octets are queued with frame_dec_put() into a ring (FRAME_RING octets) and parsed by
 * frame_dec_poll(), at most max_steps octets per call: the work per call is bounded, there is no
 * division (the ring index wraps with a mask). The ring keeps every octet from the start octet of
 * the frame being parsed: when that candidate turns out not to be a frame (LEN too large, CRC
 * wrong), parsing resumes at the octet after its start octet, so a real frame that began inside
 * the garbage or inside a truncated frame is still found. Each octet is parsed at most
 * FRAME_MAX_OCTETS times. The ring holds two maximal frames, so it never blocks: while
 * frame_dec_room() > 0 octets can be queued.
 */
#ifndef FRAME_H
#define FRAME_H

#include <stdint.h>

#define FRAME_SOF 0xA5u
#define FRAME_MAX_PAYLOAD 120u
#define FRAME_OVERHEAD 6u /* SOF, LEN, CMD, SEQ, CRC_HI, CRC_LO */
#define FRAME_MAX_OCTETS (FRAME_MAX_PAYLOAD + FRAME_OVERHEAD)
#define FRAME_RING 256u /* power of two >= 2 * FRAME_MAX_OCTETS */

#if (FRAME_RING & (FRAME_RING - 1u)) != 0u || FRAME_RING < 2u * FRAME_MAX_OCTETS || FRAME_MAX_PAYLOAD > 255u
#error "FRAME_RING must be a power of two holding two maximal frames; LEN is one octet"
#endif

/* A decoded frame (or one to encode). */
typedef struct {
    uint16_t cmd;                        /* command id, 0..255 */
    uint16_t seq;                        /* sequence number, 0..255 */
    uint16_t len;                        /* payload octets, 0..FRAME_MAX_PAYLOAD */
    uint16_t payload[FRAME_MAX_PAYLOAD]; /* one octet per unit, bits 7:0 */
} frame_t;

/* Decoder counters (wrap at 2^16; diagnostics for the status command). */
typedef struct {
    uint16_t frames;    /* frames decoded */
    uint16_t crc_errors; /* candidates with a wrong CRC */
    uint16_t len_errors; /* candidates with LEN > FRAME_MAX_PAYLOAD */
    uint16_t timeouts;  /* candidates rejected because the line went idle inside them */
    uint16_t dropped;   /* octets refused by frame_dec_put (ring full) */
} frame_dec_stats_t;

typedef struct {
    uint16_t ring[FRAME_RING];
    uint16_t head;  /* next free slot (free-running, masked on access) */
    uint16_t rd;    /* next octet to parse */
    uint16_t start; /* oldest octet still needed: the current candidate's start octet */
    uint16_t state; /* parser state (frame.c) */
    uint16_t pos;   /* payload octets parsed */
    uint16_t crc;   /* running CRC of the candidate */
    uint16_t crc_rx; /* received CRC, high octet */
    uint16_t idle;  /* 1: the line is silent (frame_dec_idle) and no octet was queued since */
    frame_t frame;  /* the candidate; a complete frame after frame_dec_poll() returned 1 */
    frame_dec_stats_t stats;
} frame_dec_t;

void frame_dec_init(frame_dec_t *d);

/* Octets that frame_dec_put() accepts now (0..FRAME_RING). */
uint16_t frame_dec_room(const frame_dec_t *d);

/* Queues one octet (bits 7:0). Returns 1, or 0 when the ring is full (octet dropped, counted). */
uint16_t frame_dec_put(frame_dec_t *d, uint16_t octet);

/* Parses up to max_steps queued octets. Returns 1 when a frame is complete (it stays in d->frame
 * until the next call), else 0: the queue is empty or max_steps octets were parsed without
 * completing a frame (frame_dec_pending() tells which). */
uint16_t frame_dec_poll(frame_dec_t *d, uint16_t max_steps);

/* The line has been silent for PROTO_IDLE_MS (frame.h "Line idle"). O(1). */
void frame_dec_idle(frame_dec_t *d);

/* Queued octets not parsed yet (a rejected candidate's octets are queued again). */
uint16_t frame_dec_pending(const frame_dec_t *d);

/* Encodes a frame into out[0..cap-1]. Returns the octet count (FRAME_OVERHEAD + len), or 0 when
 * len > FRAME_MAX_PAYLOAD or the frame does not fit in cap. cmd and seq are taken modulo 256,
 * payload octets as bits 7:0. */
uint16_t frame_encode(uint16_t *out, uint16_t cap, uint16_t cmd, uint16_t seq, const uint16_t *payload,
                      uint16_t len);

/* Little-endian payload fields: put writes at p[0..], get reads from p[0..] (octets in bits 7:0). */
void frame_put_u16(uint16_t *p, uint16_t v);
void frame_put_u32(uint16_t *p, uint32_t v);
uint16_t frame_get_u16(const uint16_t *p);
uint32_t frame_get_u32(const uint16_t *p);
/* int32 as its two's-complement bits (no implementation-defined conversion: the sign is rebuilt
 * explicitly). */
void frame_put_i32(uint16_t *p, int32_t v);
int32_t frame_get_i32(const uint16_t *p);

#endif /* FRAME_H */
