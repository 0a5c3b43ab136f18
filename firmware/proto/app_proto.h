/*
 * app_proto.h - the serial protocol's dispatcher (proto.h commands over frame.h frames), run by
 * the background loop (app_background), never by the ISR: it reads the line, decodes frames,
 * answers each decoded request with exactly one frame (the response or PROTO_ERROR) and sends the
 * telemetry stream. It reaches the drive only through app.h's background calls: the references
 * through the shadow set (app_set_refs), arming through the core's requests (app_arm,
 * app_disarm), the capture's set-up and read-out, the fault log's reader.
 *
 * Work per pass is bounded: at most APP_PROTO_RX_OCTETS octets read, APP_PROTO_PARSE_STEPS
 * octets parsed and one request handled; a response not yet taken by the transmit FIFO holds
 * the next request back (the decoder's ring keeps the octets meanwhile), so nothing waits.
 *
 * Time comes from the ISR tick (app_get_status): a line silent for PROTO_IDLE_MS ends a
 * truncated frame (frame_dec_idle); the command timeout is counted by the ISR (app_core.h).
 */
#ifndef APP_PROTO_H
#define APP_PROTO_H

#include <stdint.h>

#include "capture.h"
#include "faultlog.h"
#include "frame.h"

#define APP_PROTO_RX_OCTETS 16u    /* octets read from the line per pass (one receive FIFO) */
#define APP_PROTO_PARSE_STEPS 64u  /* octets parsed per pass */
#define APP_FW_VERSION 0x0100u     /* firmware version in HELLO: major << 8 | minor */

typedef struct {
    frame_dec_t dec;
    uint16_t tx[FRAME_MAX_OCTETS]; /* the frame being sent */
    uint16_t tx_len, tx_pos;       /* its octets, and those the line took */
    uint32_t period_ns;            /* control period */
    uint32_t idle_ticks;           /* PROTO_IDLE_MS in control periods */
    uint32_t last_rx_tick;         /* tick of the last octet received */
    uint16_t rx_seen;              /* an octet arrived since the line was last declared idle */
    uint16_t timeout_ms;           /* comm_timeout_s in ms, 0 = off */
    /* telemetry stream (PROTO_TELEMETRY_START) */
    uint16_t tm_on, tm_seq, tm_decim, tm_count;
    uint16_t tm_q[4];
    uint32_t tm_next;              /* tick of the next telemetry frame */
    frame_t out;                   /* the answer (or telemetry frame) being built */
} app_proto_t;

/* Empty decoder, nothing to send, telemetry off; period_ns the control period (> 0). */
void app_proto_init(app_proto_t *p, uint32_t period_ns);

/* The drive's one protocol instance, with the capture and fault log it serves: after app_init,
 * before the ISR is enabled, app_proto_start empties them, attaches them to the application
 * (app_attach) and starts the protocol at the control period period_ns (APP_ISR_PERIOD_NS on
 * the F2812); app_proto_background is its pass of the background loop. */
#define APP_ISR_PERIOD_NS 50000UL
void app_proto_start(uint32_t period_ns);
void app_proto_background(void);

/* The capture and the fault log of app_proto_start (background access as capture.h and
 * faultlog.h say). */
capture_t *app_capture(void);
const faultlog_t *app_faultlog(void);

/* One background pass: line -> decoder -> at most one request handled -> line. */
void app_proto_poll(app_proto_t *p);

/* Answers one decoded request rq into rs (cmd, seq, len, payload). Pure with respect to the
 * line (the fuzz target calls it directly). */
void app_proto_handle(app_proto_t *p, const frame_t *rq, frame_t *rs);

/* The command timeout in ms (0 = off) in force: the comm_timeout_s parameter. */
uint16_t app_proto_timeout_ms(const app_proto_t *p);

#endif /* APP_PROTO_H */
