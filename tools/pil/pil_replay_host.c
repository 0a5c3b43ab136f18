/*
 * pil_replay_host.c - pil-replay: replays an ISR recording (docs/pil.md) on the host build of the
 * firmware through hal/replay and writes one output record per ISR.
 *
 *   pil-replay RECORDING OUTPUT
 *
 * Exit 0 on success; 1 on a usage or file error; 2 when the recording is not one this build can
 * replay; 3 when app_init() refuses the recorded configuration.
 */
#include <stdio.h>
#include <stdlib.h>

#include "pil_replay.h"

void pil_target_isr_begin(void)
{
}

void pil_target_isr_end(void)
{
}

int main(int argc, char **argv)
{
    FILE *in, *out;
    uint8_t hb[PIL_HEADER_BYTES];
    uint8_t *blob;
    uint8_t rec[PIL_IN_BYTES + PIL_OUT_BYTES];
    uint8_t ob[PIL_OUT_BYTES];
    pil_header_t h;
    int16_t rc;
    uint32_t k;

    if (argc != 3) {
        fprintf(stderr, "usage: pil-replay RECORDING OUTPUT\n");
        return 1;
    }
    in = fopen(argv[1], "rb");
    if (in == NULL) {
        fprintf(stderr, "pil-replay: %s: cannot open\n", argv[1]);
        return 1;
    }
    if (fread(hb, 1, sizeof hb, in) != sizeof hb) {
        fprintf(stderr, "pil-replay: %s: shorter than a header\n", argv[1]);
        return 2;
    }
    rc = pil_header_decode(hb, &h);
    if (rc != PIL_OK) {
        fprintf(stderr, "pil-replay: %s: not a replayable recording (pil_err %d)\n", argv[1], rc);
        return 2;
    }
    blob = malloc(4U * h.config_fields);
    if (blob == NULL || fread(blob, 4U, h.config_fields, in) != h.config_fields) {
        fprintf(stderr, "pil-replay: %s: configuration truncated\n", argv[1]);
        return 2;
    }
    rc = pil_replay_init(&h, blob);
    free(blob);
    if (rc != 0) {
        fprintf(stderr, "pil-replay: app_init() refused the recorded configuration (dtc_err %d)\n", rc);
        return 3;
    }
    out = fopen(argv[2], "wb");
    if (out == NULL) {
        fprintf(stderr, "pil-replay: %s: cannot open for writing\n", argv[2]);
        return 1;
    }
    for (k = 0; k < h.isr_count; ++k) {
        if (fread(rec, 1, sizeof rec, in) != sizeof rec) {
            fprintf(stderr, "pil-replay: %s: truncated at ISR %lu\n", argv[1], (unsigned long)k);
            return 2;
        }
        pil_replay_isr(rec, ob);
        if (fwrite(ob, 1, sizeof ob, out) != sizeof ob) {
            fprintf(stderr, "pil-replay: %s: write failed\n", argv[2]);
            return 1;
        }
    }
    fclose(in);
    if (fclose(out) != 0) {
        fprintf(stderr, "pil-replay: %s: write failed\n", argv[2]);
        return 1;
    }
    return 0;
}
