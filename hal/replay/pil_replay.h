/*
 * pil_replay.h - the replay loop shared by every PIL program (host, simavr, qemu): rebuild the
 * configuration from the recording, initialise the unchanged application (app_init), then per
 * ISR feed the recorded input through the unchanged ISR entry (app_isr, app_background) and
 * encode what it commanded (pil_format.h). Each program only moves bytes in and out.
 */
#ifndef PIL_REPLAY_H
#define PIL_REPLAY_H

#include "pil_format.h"

/* Rebuilds the configuration from blob (h->config_fields * 4 bytes) and calls hal_init() and
 * app_init(). Returns app_init()'s code (0 or a negative enum dtc_err). */
int16_t pil_replay_init(const pil_header_t *h, const uint8_t *blob);

/* pil_replay_init in two parts, for a target whose blob buffer should not share the stack with
 * app_init's frames (the ATmega2560's 8 KB): pil_replay_decode rebuilds the configuration (the
 * blob is not read after it returns), pil_replay_start calls hal_init() and app_init() and returns
 * app_init()'s code. */
void pil_replay_decode(const uint8_t *blob);
int16_t pil_replay_start(const pil_header_t *h);

/* One ISR: in (PIL_IN_BYTES) -> app_isr(); app_background() -> out (PIL_OUT_BYTES). */
void pil_replay_isr(const uint8_t *in, uint8_t *out);

/* Provided by each program: called right before and right after app_isr() (cycle markers on
 * the emulators; empty on the host). */
void pil_target_isr_begin(void);
void pil_target_isr_end(void);

#endif /* PIL_REPLAY_H */
