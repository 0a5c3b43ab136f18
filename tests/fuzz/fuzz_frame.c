/*
 * fuzz_frame.c - libFuzzer harness of the serial frame decoder (firmware/comm/frame.h).
 *
 * Input: any octets, fed to the decoder as the background loop would (queued while the ring has
 * room, parsed a few steps at a time), then a silent line (frame_dec_idle), then one known good
 * frame, another silent line and the same frame again.
 *
 * Invariants (each violation aborts, so libFuzzer reports it):
 *   1. nothing is invented: every frame decoded re-encodes to octets that occur in what was fed,
 *      at or after the start of the previous frame decoded;
 *   2. the ring never refuses an octet the caller was told it had room for, and never loses one;
 *   3. after a silent line the decoder is idle (nothing pending, hunting), whatever came before;
 *   4. a good frame sent after a silent line is always decoded, whole and exactly once.
 * Bounded work is structural (frame_dec_poll's max_steps); the sanitizers check the memory.
 */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "frame.h"

#define MAX_IN 4096
static frame_dec_t g_dec;
static uint16_t g_line[MAX_IN + 3 * FRAME_MAX_OCTETS];
static size_t g_n;
static size_t g_last_pos;

static void check(int ok)
{
    if (!ok) {
        abort();
    }
}

/* Invariant 1: the decoded frame occurs in the line at or after the previous one's start. */
static void on_frame(void)
{
    uint16_t enc[FRAME_MAX_OCTETS];
    const uint16_t m = frame_encode(enc, FRAME_MAX_OCTETS, g_dec.frame.cmd, g_dec.frame.seq, g_dec.frame.payload,
                                    g_dec.frame.len);
    check(m == g_dec.frame.len + FRAME_OVERHEAD);
    for (size_t p = g_last_pos; p + m <= g_n; p++) {
        if (memcmp(&g_line[p], enc, m * sizeof enc[0]) == 0) {
            g_last_pos = p + 1u;
            return;
        }
    }
    abort();
}

static int drain(void)
{
    int frames = 0;
    for (int guard = 0; guard < 100000; guard++) {
        if (frame_dec_poll(&g_dec, 3u)) {
            on_frame();
            frames++;
        } else if (frame_dec_pending(&g_dec) == 0u && frame_dec_poll(&g_dec, 1u) == 0u &&
                   frame_dec_pending(&g_dec) == 0u) {
            return frames;
        }
    }
    abort(); /* the decoder must settle: every octet is parsed a bounded number of times */
}

static int feed(const uint16_t *o, size_t n)
{
    int frames = 0;
    for (size_t i = 0; i < n; i++) {
        while (frame_dec_room(&g_dec) == 0u) {
            if (frame_dec_poll(&g_dec, 2u)) {
                on_frame();
                frames++;
            }
        }
        g_line[g_n++] = (uint16_t)(o[i] & 0xFFu);
        check(frame_dec_put(&g_dec, o[i]) == 1u); /* invariant 2 */
        if (frame_dec_poll(&g_dec, 2u)) {
            on_frame();
            frames++;
        }
    }
    return frames;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const uint16_t payload[5] = {0xA5, 0x00, 0xFF, 0x5A, 0xA5};
    uint16_t good[FRAME_MAX_OCTETS];
    uint16_t in[MAX_IN];
    size_t n = size < MAX_IN ? size : MAX_IN;
    frame_dec_init(&g_dec);
    g_n = 0u;
    g_last_pos = 0u;
    for (size_t i = 0; i < n; i++) {
        in[i] = data[i];
    }
    (void)feed(in, n);
    frame_dec_idle(&g_dec);
    (void)drain();
    check(frame_dec_pending(&g_dec) == 0u && g_dec.state == 0u); /* invariant 3: hunting */
    const uint16_t m = frame_encode(good, FRAME_MAX_OCTETS, 0x02u, 0x77u, payload, 5u);
    for (int rep = 0; rep < 2; rep++) {
        g_last_pos = g_n; /* the good frame must be found in what follows */
        int frames = feed(good, m);
        frame_dec_idle(&g_dec);
        frames += drain();
        check(frames == 1); /* invariant 4 */
        check(g_dec.frame.cmd == 0x02u && g_dec.frame.seq == 0x77u && g_dec.frame.len == 5u);
        check(memcmp(g_dec.frame.payload, payload, sizeof payload) == 0);
    }
    check(g_dec.stats.dropped == 0u);
    return 0;
}
