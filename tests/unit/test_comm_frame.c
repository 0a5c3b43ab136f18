/*
 * test_comm_frame.c - the serial frames (firmware/comm/frame.h) and their CRC (crc16.h):
 *  - the CRC is CRC-16/CCITT-FALSE: its published check value, and a frame's CRC equal to what
 *    Python's binascii.crc_hqx(data, 0xFFFF) gives (value computed with Python, typed in);
 *  - encode/decode round trip at every payload length;
 *  - resynchronisation: garbage (with and without start octets) before a frame, every truncation
 *    of a frame followed by a good one, a too-long LEN, every single-bit error of frames of
 *    several lengths (each detected, the next frame still decoded), every burst of up to 16 bits;
 *  - bounded work per call, a full ring refuses octets, back-to-back frames at full load.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "fixtest.h"

#include "crc16.h"
#include "frame.h"

static frame_dec_t g_dec;

/* Deterministic pseudo-random octets (xorshift32). */
static uint32_t g_rng = 0x12345678u;
static uint16_t rnd_octet(void)
{
    g_rng ^= g_rng << 13;
    g_rng ^= g_rng >> 17;
    g_rng ^= g_rng << 5;
    return (uint16_t)(g_rng & 0xFFu);
}

/* Feeds octets, polling as the background loop does (a few steps per octet queued); collects the
 * decoded frames. Returns their count. */
static int feed(const uint16_t *o, int n, frame_t *out, int out_cap)
{
    int got = 0;
    for (int i = 0; i < n; i++) {
        while (frame_dec_room(&g_dec) == 0u) { /* the caller queues only what the ring accepts */
            if (frame_dec_poll(&g_dec, 2u)) {
                if (got < out_cap) {
                    out[got] = g_dec.frame;
                }
                got++;
            }
        }
        assert_int_equal(frame_dec_put(&g_dec, o[i]), 1);
        while (frame_dec_poll(&g_dec, 2u)) {
            if (got < out_cap) {
                out[got] = g_dec.frame;
            }
            got++;
        }
    }
    /* the line goes silent, then drain */
    frame_dec_idle(&g_dec);
    for (;;) {
        if (frame_dec_poll(&g_dec, 2u)) {
            if (got < out_cap) {
                out[got] = g_dec.frame;
            }
            got++;
        } else if (frame_dec_pending(&g_dec) == 0u && frame_dec_poll(&g_dec, 1u) == 0u &&
                   frame_dec_pending(&g_dec) == 0u) {
            break;
        }
    }
    return got;
}

static uint16_t make_frame(uint16_t *buf, uint16_t cmd, uint16_t seq, uint16_t len)
{
    uint16_t payload[FRAME_MAX_PAYLOAD];
    for (uint16_t i = 0; i < len; i++) {
        payload[i] = (uint16_t)((i * 37u + cmd + 0xA0u) & 0xFFu); /* includes 0xA5 start octets */
    }
    return frame_encode(buf, FRAME_MAX_OCTETS, cmd, seq, payload, len);
}

static void assert_frame(const frame_t *f, uint16_t cmd, uint16_t seq, uint16_t len)
{
    assert_int_equal(f->cmd, cmd);
    assert_int_equal(f->seq, seq);
    assert_int_equal(f->len, len);
    for (uint16_t i = 0; i < len; i++) {
        assert_int_equal(f->payload[i], (uint16_t)((i * 37u + cmd + 0xA0u) & 0xFFu));
    }
}

static int setup(void **state)
{
    (void)state;
    frame_dec_init(&g_dec);
    g_rng = 0x12345678u;
    return 0;
}

static void test_crc_ccitt_false(void **state)
{
    (void)state;
    const uint16_t check[9] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
    assert_int_equal(crc16_octets(CRC16_INIT, check, 9u), 0x29B1); /* CRC-16/CCITT-FALSE check */
    /* bits 15:8 of a unit are ignored */
    const uint16_t check_hi[9] = {0x131, 0x232, 0x333, 0x434, 0x535, 0x636, 0x737, 0x838, 0x939};
    assert_int_equal(crc16_octets(CRC16_INIT, check_hi, 9u), 0x29B1);
    /* words, high octet first */
    const uint16_t words[2] = {0x3132, 0x3334};
    const uint16_t octets[4] = {0x31, 0x32, 0x33, 0x34};
    assert_int_equal(crc16_words(CRC16_INIT, words, 2u), crc16_octets(CRC16_INIT, octets, 4u));
}

static void test_encode_layout_matches_python(void **state)
{
    (void)state;
    /* binascii.crc_hqx(bytes([3, 0x01, 0x07, 0x10, 0xA5, 0xFF]), 0xFFFF) == 0x8494 */
    const uint16_t payload[3] = {0x10, 0xA5, 0x1FF};
    uint16_t out[16];
    assert_int_equal(frame_encode(out, 16u, 0x01u, 0x07u, payload, 3u), 9);
    const uint16_t expect[9] = {0xA5, 3, 0x01, 0x07, 0x10, 0xA5, 0xFF, 0x84, 0x94};
    for (int i = 0; i < 9; i++) {
        assert_int_equal(out[i], expect[i]);
    }
    /* refusals */
    assert_int_equal(frame_encode(out, 8u, 1u, 1u, payload, 3u), 0);
    uint16_t big[FRAME_MAX_OCTETS + 8];
    uint16_t pl[FRAME_MAX_PAYLOAD + 1];
    memset(pl, 0, sizeof pl);
    assert_int_equal(frame_encode(big, (uint16_t)(FRAME_MAX_OCTETS + 8), 1u, 1u, pl, FRAME_MAX_PAYLOAD + 1u), 0);
}

static void test_round_trip_every_length(void **state)
{
    (void)state;
    uint16_t buf[FRAME_MAX_OCTETS];
    frame_t out[2];
    for (uint16_t len = 0; len <= FRAME_MAX_PAYLOAD; len++) {
        const uint16_t n = make_frame(buf, (uint16_t)(len ^ 0x5Au), len, len);
        assert_int_equal(n, len + FRAME_OVERHEAD);
        assert_int_equal(feed(buf, n, out, 2), 1);
        assert_frame(&out[0], (uint16_t)(len ^ 0x5Au), len, len);
    }
    assert_int_equal(g_dec.stats.frames, FRAME_MAX_PAYLOAD + 1u);
    assert_int_equal(g_dec.stats.crc_errors, 0);
}

static void test_garbage_then_frame(void **state)
{
    (void)state;
    static uint16_t line[20000];
    uint16_t buf[FRAME_MAX_OCTETS];
    frame_t out[4];
    /* random garbage (about one octet in 256 is a start octet, some with a plausible LEN) */
    int n = 0;
    for (; n < 19000; n++) {
        line[n] = rnd_octet();
    }
    const uint16_t m = make_frame(buf, 0x22u, 0x33u, 17u);
    memcpy(&line[n], buf, m * sizeof buf[0]);
    n += m;
    assert_int_equal(feed(line, n, out, 4), 1);
    assert_frame(&out[0], 0x22u, 0x33u, 17u);
    /* garbage made of start octets only, and of start octet + maximal LEN */
    frame_dec_init(&g_dec);
    n = 0;
    for (int i = 0; i < 300; i++) {
        line[n++] = FRAME_SOF;
    }
    for (int i = 0; i < 50; i++) {
        line[n++] = FRAME_SOF;
        line[n++] = FRAME_MAX_PAYLOAD;
    }
    memcpy(&line[n], buf, m * sizeof buf[0]);
    n += m;
    assert_int_equal(feed(line, n, out, 4), 1);
    assert_frame(&out[0], 0x22u, 0x33u, 17u);
}

static void test_every_truncation_then_frame(void **state)
{
    (void)state;
    uint16_t f[FRAME_MAX_OCTETS];
    uint16_t g[FRAME_MAX_OCTETS];
    uint16_t line[2 * FRAME_MAX_OCTETS];
    frame_t out[4];
    const uint16_t lens[4] = {0u, 5u, 64u, FRAME_MAX_PAYLOAD};
    for (int li = 0; li < 4; li++) {
        const uint16_t nf = make_frame(f, 0x10u, 1u, lens[li]);
        const uint16_t ng = make_frame(g, 0x11u, 2u, 9u);
        for (uint16_t k = 1; k < nf; k++) {
            frame_dec_init(&g_dec);
            memcpy(line, f, k * sizeof f[0]);
            memcpy(&line[k], g, ng * sizeof g[0]);
            assert_int_equal(feed(line, k + ng, out, 4), 1);
            assert_frame(&out[0], 0x11u, 2u, 9u);
        }
    }
}

/* A truncated long frame holds a short good frame behind it until the line goes idle; then the
 * good frame is delivered, once. */
static void test_truncated_released_by_idle(void **state)
{
    (void)state;
    uint16_t f[FRAME_MAX_OCTETS];
    uint16_t g[FRAME_MAX_OCTETS];
    const uint16_t nf = make_frame(f, 0x10u, 1u, 100u);
    const uint16_t ng = make_frame(g, 0x11u, 2u, 3u);
    for (uint16_t i = 0; i < 10u; i++) {
        frame_dec_put(&g_dec, f[i]);
    }
    for (uint16_t i = 0; i < ng; i++) {
        frame_dec_put(&g_dec, g[i]);
    }
    assert_int_equal(frame_dec_poll(&g_dec, 1000u), 0); /* waiting for 100 payload octets */
    assert_int_equal(frame_dec_pending(&g_dec), 0);
    frame_dec_idle(&g_dec);
    assert_int_equal(frame_dec_poll(&g_dec, 1000u), 1);
    assert_frame(&g_dec.frame, 0x11u, 2u, 3u);
    assert_int_equal(frame_dec_poll(&g_dec, 1000u), 0);
    assert_int_equal(g_dec.stats.timeouts, 1);
    assert_true(nf > 10u);
    /* idle on a hunting decoder does nothing; an octet ends the idle state */
    frame_dec_idle(&g_dec);
    assert_int_equal(frame_dec_poll(&g_dec, 1000u), 0);
    assert_int_equal(g_dec.stats.timeouts, 1);
    frame_dec_put(&g_dec, FRAME_SOF);
    frame_dec_put(&g_dec, 5u);
    assert_int_equal(frame_dec_poll(&g_dec, 1000u), 0);
    assert_int_equal(g_dec.stats.timeouts, 1);
}

static void test_len_too_large(void **state)
{
    (void)state;
    uint16_t g[FRAME_MAX_OCTETS];
    uint16_t line[FRAME_MAX_OCTETS + 2];
    frame_t out[2];
    line[0] = FRAME_SOF;
    line[1] = FRAME_MAX_PAYLOAD + 1u;
    const uint16_t ng = make_frame(g, 0x11u, 2u, 3u);
    memcpy(&line[2], g, ng * sizeof g[0]);
    assert_int_equal(feed(line, ng + 2, out, 2), 1);
    assert_frame(&out[0], 0x11u, 2u, 3u);
    assert_int_equal(g_dec.stats.len_errors, 1);
}

/* Every error pattern of burst_bits consecutive bits (first and last flipped, the ones between
 * all flipped) at every position: CRC-16 detects every burst up to 16 bits. The frame carrying
 * the error is never delivered; the frame after it always is. */
static void check_bursts(uint16_t len, int burst_bits)
{
    uint16_t f[FRAME_MAX_OCTETS];
    uint16_t g[FRAME_MAX_OCTETS];
    uint16_t line[2 * FRAME_MAX_OCTETS];
    frame_t out[4];
    const uint16_t nf = make_frame(f, 0x30u, 9u, len);
    const uint16_t ng = make_frame(g, 0x31u, 10u, 4u);
    const int bits = 8 * nf;
    for (int b = 0; b + burst_bits <= bits; b++) {
        frame_dec_init(&g_dec);
        memcpy(line, f, nf * sizeof f[0]);
        for (int j = b; j < b + burst_bits; j++) {
            line[j / 8] = (uint16_t)(line[j / 8] ^ (0x80u >> (j % 8)));
        }
        memcpy(&line[nf], g, ng * sizeof g[0]);
        assert_int_equal(feed(line, nf + ng, out, 4), 1);
        assert_frame(&out[0], 0x31u, 10u, 4u);
    }
}

static void test_every_single_bit_error(void **state)
{
    (void)state;
    check_bursts(0u, 1);
    check_bursts(1u, 1);
    check_bursts(16u, 1);
    check_bursts(FRAME_MAX_PAYLOAD, 1);
}

static void test_bursts_up_to_16_bits(void **state)
{
    (void)state;
    for (int w = 2; w <= 16; w++) {
        check_bursts(12u, w);
    }
}

static void test_bounded_work_and_full_ring(void **state)
{
    (void)state;
    uint16_t f[FRAME_MAX_OCTETS];
    const uint16_t nf = make_frame(f, 0x40u, 1u, 10u);
    for (uint16_t i = 0; i < nf; i++) {
        assert_int_equal(frame_dec_put(&g_dec, f[i]), 1);
    }
    /* one octet per call: the frame completes on the last octet's call, not before */
    for (uint16_t i = 0; i + 1u < nf; i++) {
        assert_int_equal(frame_dec_poll(&g_dec, 1u), 0);
        assert_int_equal(frame_dec_pending(&g_dec), nf - i - 1u);
    }
    assert_int_equal(frame_dec_poll(&g_dec, 1u), 1);
    assert_int_equal(frame_dec_poll(&g_dec, 1u), 0);
    /* a full ring refuses and counts */
    frame_dec_init(&g_dec);
    for (uint16_t i = 0; i < FRAME_RING; i++) {
        assert_int_equal(frame_dec_put(&g_dec, 0x00u), 1);
    }
    assert_int_equal(frame_dec_room(&g_dec), 0);
    assert_int_equal(frame_dec_put(&g_dec, 0x00u), 0);
    assert_int_equal(g_dec.stats.dropped, 1);
    /* garbage is released as it is parsed */
    assert_int_equal(frame_dec_poll(&g_dec, 10u), 0);
    assert_int_equal(frame_dec_room(&g_dec), 10);
}

/* Back-to-back frames at full load with garbage between some: the caller queues only what the
 * ring accepts (frame_dec_room), two parse steps per octet; every good frame is decoded in order. */
static void test_full_load_stream(void **state)
{
    (void)state;
    static uint16_t line[200000];
    uint16_t f[FRAME_MAX_OCTETS];
    int n = 0;
    int frames = 0;
    for (int k = 0; k < 1000; k++) {
        const uint16_t len = (uint16_t)(rnd_octet() % (FRAME_MAX_PAYLOAD + 1u));
        const uint16_t nf = make_frame(f, (uint16_t)(k & 0x7F), (uint16_t)(k & 0xFF), len);
        if (k % 7 == 3) { /* a truncated frame, then garbage */
            memcpy(&line[n], f, (nf / 2u) * sizeof f[0]);
            n += nf / 2;
            for (int i = 0; i < 5; i++) {
                line[n++] = rnd_octet();
            }
            continue;
        }
        memcpy(&line[n], f, nf * sizeof f[0]);
        n += nf;
        frames++;
    }
    int got = 0;
    int i = 0;
    int k_expect = 0;
    while (i < n || frame_dec_pending(&g_dec) > 0u) {
        if (i < n && frame_dec_room(&g_dec) > 0u) {
            frame_dec_put(&g_dec, line[i++]);
        }
        if (frame_dec_poll(&g_dec, 2u)) {
            while (k_expect % 7 == 3) {
                k_expect++;
            }
            assert_int_equal(g_dec.frame.seq, (uint16_t)(k_expect & 0xFF));
            assert_int_equal(g_dec.frame.cmd, (uint16_t)(k_expect & 0x7F));
            k_expect++;
            got++;
        }
    }
    assert_int_equal(got, frames);
    assert_int_equal(g_dec.stats.dropped, 0);
}

static void test_payload_fields(void **state)
{
    (void)state;
    uint16_t p[4];
    frame_put_u16(p, 0xBEEFu);
    assert_int_equal(p[0], 0xEF);
    assert_int_equal(p[1], 0xBE);
    assert_int_equal(frame_get_u16(p), 0xBEEF);
    frame_put_u32(p, 0x12345678u);
    assert_int_equal(p[0], 0x78);
    assert_int_equal(p[3], 0x12);
    assert_int_equal(frame_get_u32(p), 0x12345678u);
    const int32_t v[6] = {0, 1, -1, 2147483647, (-2147483647 - 1), -123456};
    for (int i = 0; i < 6; i++) {
        frame_put_i32(p, v[i]);
        uint32_t u = (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
        assert_int_equal(u, (uint32_t)v[i]); /* two's complement, little-endian */
        assert_int_equal(frame_get_i32(p), v[i]);
    }
}

UNIT_TEST_MAIN("comm frame", NULL,
               cmocka_unit_test_setup(test_crc_ccitt_false, setup),
               cmocka_unit_test_setup(test_encode_layout_matches_python, setup),
               cmocka_unit_test_setup(test_round_trip_every_length, setup),
               cmocka_unit_test_setup(test_garbage_then_frame, setup),
               cmocka_unit_test_setup(test_every_truncation_then_frame, setup),
               cmocka_unit_test_setup(test_truncated_released_by_idle, setup),
               cmocka_unit_test_setup(test_len_too_large, setup),
               cmocka_unit_test_setup(test_every_single_bit_error, setup),
               cmocka_unit_test_setup(test_bursts_up_to_16_bits, setup),
               cmocka_unit_test_setup(test_bounded_work_and_full_ring, setup),
               cmocka_unit_test_setup(test_full_load_stream, setup),
               cmocka_unit_test_setup(test_payload_fields, setup))
