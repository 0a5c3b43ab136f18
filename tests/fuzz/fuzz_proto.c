/*
 * fuzz_proto.c - libFuzzer harness of the serial protocol's dispatcher (firmware/proto) with the
 * application it drives (app.c, app_core.c) on a healthy drive at standstill: the fuzz input is
 * the host's side of the line.
 *
 * The drive: the default PM configuration (tools/config dtc_config_from_si), command arming
 * (app_set_arming), the protocol started (app_proto_start); the HAL below gives every period a
 * healthy measurement (offsets, the nominal DC link, a still encoder) and models the SCI: the
 * dispatcher reads what the host sent, up to the 16-octet FIFO per pass, and the transmit side
 * takes 16 octets per period. Per period: app_isr, app_background, app_proto_background, as
 * dtc-sil serve and the F2812 main loop do.
 *
 * Input: records until it runs out (op byte, then its bytes):
 *   op % 4 == 0  raw octets (1..64 of them);
 *   op % 4 == 1  a well-formed frame: a command id (from the protocol's list, or any octet),
 *                a payload of 0..24 octets from the input, the right CRC;
 *   op % 4 == 2  a well-formed frame with one bit flipped, or cut short;
 *   op % 4 == 3  time passes: 1..1024 periods with nothing sent.
 * Then the line stays silent until it is idle and every request has been answered for 64
 * periods, at most 2000 periods.
 *
 * Invariants (each violation aborts):
 *   1. never armed without a valid arm frame: every READY -> RUN transition follows an ARM frame
 *      that the drive decoded (a reference decoder fed the same octets as the dispatcher counts
 *      them) and that no other transition used; likewise every entry into the identification
 *      (the gates driven by it) follows an IDENTIFY frame;
 *   2. never a parameter out of range: every row of the configuration's parameter description
 *      (dtc_params.h) reads within [lo, hi] after each write;
 *   3. never blocked: after the silence every decoded request has had exactly one answer (its
 *      response or an ERROR frame), the unsolicited telemetry apart;
 *   4. the ISR's state touched only through the shadow protocol: while armed, no parameter that
 *      is not live (DTC_PARAM_LIVE) changes, and the configuration is never replaced.
 */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "app_proto.h"
#include "dtc_config_si.h"
#include "dtc_params.h"
#include "frame.h"
#include "fuzz_reader.h"
#include "hal.h"
#include "hal_null.h"
#include "proto.h"

#define FUZZ_CHECK(cond, ...)                                                                      \
    do {                                                                                          \
        if (!(cond)) {                                                                            \
            fprintf(stderr, "fuzz_proto: invariant failed: %s: ", #cond);                         \
            fprintf(stderr, __VA_ARGS__);                                                         \
            fputc('\n', stderr);                                                                  \
            abort();                                                                              \
        }                                                                                         \
    } while (0)

#define LINE_MAX_OCTETS 65536u
#define PARAM_MAX 512u

static dtc_config_si_t g_si;
static dtc_config_t g_cfg;
/* host -> drive: octets sent, octets the dispatcher read */
static uint16_t g_rx[LINE_MAX_OCTETS];
static size_t g_rx_n, g_rx_rd;
static uint16_t g_tx_credit;
static frame_dec_t g_ref_rx; /* the requests, decoded as the dispatcher reads them */
static frame_dec_t g_ref_tx; /* the drive's answers */
static uint32_t g_requests, g_answers, g_arm_frames, g_arms, g_ident_frames, g_idents;
static int32_t g_armed_raw[PARAM_MAX];
static uint32_t g_last_rx_tick; /* the dispatcher's idle rule, mirrored for the reference decoder */
static uint16_t g_rx_seen;

/* ---- the HAL ------------------------------------------------------------------------------ */
/* The reference decoder parses everything queued (the dispatcher parses it too, before its line
 * goes idle), counting the requests and the arm frames among them. */
static void ref_rx_drain(void)
{
    for (;;) {
        /* poll(1) with nothing queued: a truncated candidate on a silent line is rejected and its
         * octets queued again; otherwise nothing is left to do */
        if (frame_dec_poll(&g_ref_rx, 8U) != 0U ||
            (frame_dec_pending(&g_ref_rx) == 0U && frame_dec_poll(&g_ref_rx, 1U) != 0U)) {
            g_requests++;
            if (g_ref_rx.frame.cmd == PROTO_ARM) {
                g_arm_frames++;
            }
            if (g_ref_rx.frame.cmd == PROTO_IDENTIFY) {
                g_ident_frames++;
            }
        } else if (frame_dec_pending(&g_ref_rx) == 0U) {
            break;
        }
    }
}

uint16_t hal_serial_read(uint16_t *buf, uint16_t max)
{
    uint16_t n = 0U;
    while (n < max && n < 16U && g_rx_rd < g_rx_n) {
        buf[n] = g_rx[g_rx_rd++];
        (void)frame_dec_put(&g_ref_rx, buf[n]);
        g_last_rx_tick = hal_null_tick;
        g_rx_seen = 1U;
        ref_rx_drain();
        n++;
    }
    return n;
}
uint16_t hal_serial_write(const uint16_t *buf, uint16_t n)
{
    uint16_t k;
    if (n > g_tx_credit) {
        n = g_tx_credit;
    }
    g_tx_credit = (uint16_t)(g_tx_credit - n);
    for (k = 0U; k < n; k++) {
        FUZZ_CHECK(buf[k] <= 0xFFU, "octet %u above 8 bits", buf[k]);
        (void)frame_dec_put(&g_ref_tx, buf[k]);
        for (;;) {
            if (frame_dec_poll(&g_ref_tx, 8U) != 0U) {
                if (g_ref_tx.frame.cmd != PROTO_TELEMETRY) {
                    g_answers++;
                }
            } else if (frame_dec_pending(&g_ref_tx) == 0U) {
                break;
            }
        }
    }
    return n;
}
uint16_t hal_store_words(void) { return 0U; }
uint16_t hal_store_erase_words(void) { return 1U; }
uint16_t hal_store_read(uint16_t addr, uint16_t *buf, uint16_t n)
{
    (void)addr, (void)buf, (void)n;
    return HAL_STORE_ERR_NONE;
}
uint16_t hal_store_write(uint16_t addr, const uint16_t *buf, uint16_t n)
{
    (void)addr, (void)buf, (void)n;
    return HAL_STORE_ERR_NONE;
}
uint16_t hal_store_erase(uint16_t addr, uint16_t n)
{
    (void)addr, (void)n;
    return HAL_STORE_ERR_NONE;
}

/* ---- invariants --------------------------------------------------------------------------- */

static void check_params(void)
{
    const dtc_config_t *c = app_config();
    uint16_t i;
    for (i = 0U; i < dtc_param_count(); i++) {
        const dtc_param_t *p = dtc_param_at(i);
        int32_t raw = 0;
        if ((p->flags & DTC_PARAM_RO) != 0U || dtc_param_get(c, p, &raw) != DTC_OK) {
            continue; /* derived, or not this law's */
        }
        FUZZ_CHECK(raw >= p->lo && raw <= p->hi, "%s = %ld outside [%ld, %ld]", p->name, (long)raw, (long)p->lo,
                   (long)p->hi);
    }
}

static void snapshot_params(void)
{
    uint16_t i;
    for (i = 0U; i < dtc_param_count() && i < PARAM_MAX; i++) {
        g_armed_raw[i] = 0;
        (void)dtc_param_get(app_config(), dtc_param_at(i), &g_armed_raw[i]);
    }
}

static void check_armed_params(void)
{
    uint16_t i;
    for (i = 0U; i < dtc_param_count() && i < PARAM_MAX; i++) {
        const dtc_param_t *p = dtc_param_at(i);
        int32_t raw = 0;
        (void)dtc_param_get(app_config(), p, &raw);
        FUZZ_CHECK((p->flags & DTC_PARAM_LIVE) != 0U || raw == g_armed_raw[i], "%s changed while armed", p->name);
    }
}

static void period(void)
{
    static uint16_t was_run, was_ident;
    app_status_t s;
    g_tx_credit = 16U;
    app_isr();
    app_background();
    app_proto_background();
    if (g_rx_seen != 0U && hal_null_tick - g_last_rx_tick >= (uint32_t)PROTO_IDLE_MS * 1000000UL / 50000UL &&
        frame_dec_pending(&g_ref_rx) == 0U) {
        frame_dec_idle(&g_ref_rx); /* a truncated request ends as the dispatcher ends it */
        g_rx_seen = 0U;
        ref_rx_drain(); /* a request that began inside it is found now */
    }
    hal_null_tick++;
    app_get_status(&s);
    if (s.state == APP_STATE_RUN && was_run == 0U) {
        g_arms++;
        FUZZ_CHECK(g_arms <= g_arm_frames, "armed %u times on %u arm frames", g_arms, g_arm_frames);
        snapshot_params();
    } else if (s.state == APP_STATE_RUN && (hal_null_tick & 63U) == 0U) {
        check_armed_params();
    }
    if (s.state == APP_STATE_IDENT && was_ident == 0U) {
        g_idents++;
        FUZZ_CHECK(g_idents <= g_ident_frames, "identifying %u times on %u identify frames", g_idents,
                   g_ident_frames);
    }
    was_run = (uint16_t)(s.state == APP_STATE_RUN ? 1U : 0U);
    was_ident = (uint16_t)(s.state == APP_STATE_IDENT ? 1U : 0U);
    if ((hal_null_tick & 255U) == 0U) {
        check_params();
    }
}

/* ---- input -------------------------------------------------------------------------------- */

static void send(uint16_t octet)
{
    if (g_rx_n < LINE_MAX_OCTETS) {
        g_rx[g_rx_n++] = (uint16_t)(octet & 0xFFU);
    }
}

static const uint16_t k_cmds[] = {PROTO_HELLO,          PROTO_STATUS,        PROTO_PARAM_DESC,      PROTO_PARAM_READ,
                                  PROTO_PARAM_WRITE,    PROTO_ARM,           PROTO_DISARM,          PROTO_SPEED_REF,
                                  PROTO_TORQUE_REF,     PROTO_FAULT_CLEAR,   PROTO_TELEMETRY_START, PROTO_TELEMETRY_STOP,
                                  PROTO_CAPTURE_SETUP,  PROTO_CAPTURE_STATUS, PROTO_CAPTURE_READ,   PROTO_CAPTURE_STOP,
                                  PROTO_FAULTLOG_READ,  PROTO_PARAMS_SAVE,   PROTO_PARAMS_RESTORE,  PROTO_IDENTIFY};

/* With FUZZ_PROTO_STATS set in the environment the harness prints what the inputs sent in all
 * (every input libFuzzer executed, each checked against the invariants above: the fuzzed frames
 * that docs/operate.md counts), every 4096 inputs and at exit (an interrupted run ends without
 * the exit line). */
static uint64_t stat_inputs, stat_good, stat_damaged, stat_raw_octets, stat_decoded;
static int g_stats_on;

static void stats_print(void)
{
    fprintf(stderr,
            "fuzz_proto: inputs %llu; frames sent %llu (well-formed %llu, damaged or cut %llu), raw octets %llu; "
            "requests decoded and answered %llu\n",
            (unsigned long long)stat_inputs, (unsigned long long)(stat_good + stat_damaged),
            (unsigned long long)stat_good, (unsigned long long)stat_damaged, (unsigned long long)stat_raw_octets,
            (unsigned long long)stat_decoded);
}

static void frame_op(rd_t *r, uint16_t damage)
{
    uint16_t f[FRAME_MAX_OCTETS], pl[24];
    const uint8_t c = rd_u8(r);
    const uint16_t cmd = c < 200U ? k_cmds[c % (sizeof k_cmds / sizeof k_cmds[0])] : (uint16_t)rd_u8(r);
    const uint16_t len = (uint16_t)(rd_u8(r) % 25U);
    uint16_t k, n;
    for (k = 0U; k < len; k++) {
        pl[k] = rd_u8(r);
    }
    n = frame_encode(f, FRAME_MAX_OCTETS, cmd, rd_u8(r), pl, len);
    if (damage != 0U) {
        const uint8_t how = rd_u8(r);
        if ((how & 1U) != 0U) {
            const uint16_t at = (uint16_t)(1U + (uint16_t)(how >> 1) % (uint16_t)(n - 1U));
            f[at] ^= (uint16_t)(1U << (rd_u8(r) & 7U));
        } else {
            n = (uint16_t)(1U + (uint16_t)(how >> 1) % (uint16_t)(n - 1U));
        }
    }
    for (k = 0U; k < n; k++) {
        send(f[k]);
    }
    if (damage != 0U) {
        stat_damaged++;
    } else {
        stat_good++;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    rd_t r = {data, size};
    char msg[200];
    uint32_t k, quiet = 0U;
    if (g_si.ts_s == 0.0) {
        dtc_config_si_defaults(&g_si);
        if (dtc_config_from_si(&g_si, &g_cfg, msg, sizeof msg) != DTC_SI_OK) {
            fprintf(stderr, "fuzz_proto: default configuration refused: %s\n", msg);
            abort();
        }
        g_stats_on = getenv("FUZZ_PROTO_STATS") != NULL;
        if (g_stats_on != 0) {
            atexit(stats_print);
        }
    }
    stat_inputs++;
    memset(&hal_null_meas, 0, sizeof hal_null_meas);
    for (k = 0U; k < 3U; k++) {
        hal_null_meas.adc[k] = g_cfg.board.adc_i_offset[k];
    }
    hal_null_meas.adc[HAL_ADC_VDC] = (uint16_t)(g_si.vdc_v / g_si.adc_vdc_v_per_count + 0.5);
    hal_null_meas.adc[HAL_ADC_VMID] = (uint16_t)(g_si.vdc_v / 2.0 / g_si.adc_vdc_v_per_count + 0.5);
    hal_null_meas.qep_count = 100U;
    hal_null_tick = 0U;
    g_rx_n = 0U;
    g_rx_rd = 0U;
    g_requests = g_answers = g_arm_frames = g_arms = g_ident_frames = g_idents = 0U;
    g_rx_seen = 0U;
    frame_dec_init(&g_ref_rx);
    frame_dec_init(&g_ref_tx);
    FUZZ_CHECK(app_init(&g_cfg) == 0, "app_init refused the default configuration");
    app_set_arming(APP_ARM_COMMAND);
    app_proto_start(50000U);
    for (k = 0U; k < 200U; k++) {
        period();
    }
    while (r.n > 0U && hal_null_tick < 60000U) {
        const uint8_t op = rd_u8(&r);
        switch (op & 3U) {
        case 0U: {
            const uint16_t n = (uint16_t)(1U + rd_u8(&r) % 64U);
            for (k = 0U; k < n; k++) {
                send(rd_u8(&r));
            }
            stat_raw_octets += n;
            break;
        }
        case 1U:
            frame_op(&r, 0U);
            break;
        case 2U:
            frame_op(&r, 1U);
            break;
        default: {
            const uint32_t n = 1U + 4U * (uint32_t)rd_u8(&r);
            for (k = 0U; k < n; k++) {
                period();
            }
            break;
        }
        }
        /* the octets queued so far go out before the next record: no silence inside a frame */
        while (g_rx_rd < g_rx_n) {
            period();
        }
    }
    /* the silence: the line declared idle (a truncated request ended, one that began inside it
     * found), then 64 periods with every request answered; at most 2000 periods */
    for (k = 0U; k < 2000U; k++) {
        period();
        if (g_answers == g_requests && g_rx_seen == 0U) {
            if (++quiet >= 64U) {
                break;
            }
        } else {
            quiet = 0U;
        }
    }
    check_params();
    FUZZ_CHECK(g_answers == g_requests, "%lu requests decoded, %lu answered", (unsigned long)g_requests,
               (unsigned long)g_answers);
    stat_decoded += g_requests;
    if (g_stats_on != 0 && stat_inputs % 4096U == 0U) {
        stats_print();
    }
    return 0;
}
