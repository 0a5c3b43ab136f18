/*
 * pil_avr_main.c - the AVR (ATmega2560, 16-bit int) replay image of processor-in-the-loop
 * (docs/pil.md), run by tools/pil/pil-simavr in simavr.
 *
 * Channel: three general-purpose I/O registers, which simavr lets the host program intercept
 * (avr_register_io_read / avr_register_io_write):
 *   GPIOR1 read   the next byte of the recording file, in file order (header, configuration,
 *                 then per ISR the input record and the recorded output record, which this
 *                 image skips);
 *   GPIOR0 write  the next byte of the output file (one output record per ISR);
 *   GPIOR2 write  a marker: PIL_AVR_ISR_BEGIN / PIL_AVR_ISR_END around app_isr() (the host
 *                 takes simavr's cycle counter at both), PIL_AVR_DONE at the end, or
 *                 PIL_AVR_ERROR_HEADER / PIL_AVR_ERROR_INIT followed by the code (enum pil_err,
 *                 or app_init's enum dtc_err) on GPIOR0.
 * The recording is streamed, so its length is not limited by the AVR's RAM or flash.
 */
#include <avr/io.h>

#include "pil_avr_channel.h"
#include "pil_replay.h"

/* Configuration fields this image can hold (pil_config_fields() must not exceed it: 106 with the
 * parameter rows of the common part and the IM part, the longest law part; two to spare). The
 * ATmega2560 has 8 KB of RAM, which its constants share (the parameter rows, dtc_param.h). The blob
 * is needed only until pil_replay_decode has rebuilt the configuration from it, so it lives on the
 * stack of load_config (below), whose frame is given back before app_init runs
 * (pil_replay_start) and before the first ISR: the blob and app_init's frames never share the
 * stack. Each field allowed costs 4 bytes of load_config's frame. A longer blob is refused at run
 * time. */
#define PIL_CONFIG_MAX 108U

void pil_target_isr_begin(void)
{
    GPIOR2 = PIL_AVR_ISR_BEGIN;
}

void pil_target_isr_end(void)
{
    GPIOR2 = PIL_AVR_ISR_END;
}

static void get(uint8_t *b, uint16_t n)
{
    uint16_t i;
    for (i = 0U; i < n; ++i) {
        b[i] = GPIOR1;
    }
}

static void put(const uint8_t *b, uint16_t n)
{
    uint16_t i;
    for (i = 0U; i < n; ++i) {
        GPIOR0 = b[i];
    }
}

static void fail(uint8_t kind, int16_t code)
{
    GPIOR2 = kind;
    GPIOR0 = (uint8_t)(uint16_t)code;
    for (;;) {
    }
}

/* Reads the configuration blob and rebuilds the configuration from it; fails on a blob longer
 * than PIL_CONFIG_MAX fields. */
static __attribute__((noinline)) void load_config(const pil_header_t *h)
{
    uint8_t blob[4U * PIL_CONFIG_MAX];

    if (h->config_fields > PIL_CONFIG_MAX) {
        fail(PIL_AVR_ERROR_HEADER, PIL_ERR_LAYOUT);
    }
    get(blob, (uint16_t)(4U * h->config_fields));
    pil_replay_decode(blob);
}

int main(void)
{
    uint8_t hb[PIL_HEADER_BYTES];
    uint8_t in[PIL_IN_BYTES + PIL_OUT_BYTES];
    uint8_t out[PIL_OUT_BYTES];
    pil_header_t h;
    int16_t rc;
    uint32_t k;

    get(hb, PIL_HEADER_BYTES);
    rc = pil_header_decode(hb, &h);
    if (rc != PIL_OK) {
        fail(PIL_AVR_ERROR_HEADER, rc);
    }
    load_config(&h);
    rc = pil_replay_start(&h); /* the application refuses the configuration: named */
    if (rc != 0) {
        fail(PIL_AVR_ERROR_INIT, rc);
    }
    for (k = 0UL; k < h.isr_count; ++k) {
        get(in, PIL_IN_BYTES + PIL_OUT_BYTES);
        pil_replay_isr(in, out);
        put(out, PIL_OUT_BYTES);
    }
    GPIOR2 = PIL_AVR_DONE;
    for (;;) {
    }
}
