/*
 * bench_proto - the background loop's pass (app_proto_background: read the line, decode, answer
 * one request, start sending) for valgrind --tool=callgrind (tools/bench/run_budget.sh, section 1h).
 *
 *   bench_proto N CMD    CMD one of the names below
 *
 * The drive: the defaults' PM configuration, command arming, the protocol started, READY on a
 * healthy measurement at standstill (as tests/fuzz/fuzz_proto.c). N times: one request of CMD is
 * put on the line whole (every request here fits the 16-octet receive FIFO, so one pass reads,
 * decodes and answers it), one pass runs through the wrapper bench_pass (the pass callgrind
 * counts), then periods (ISR and background) until the answer is out and the drive is back where
 * it was. The inclusive count of bench_pass divided by N is the cost of a pass that handles CMD;
 * the largest over the commands is the background loop's worst pass. The medium is RAM of the
 * F2812 board's EEPROM geometry (16384 words, 32-word pages).
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "app_proto.h"
#include "dtc_config_si.h"
#include "frame.h"
#include "hal.h"
#include "hal_null.h"
#include "proto.h"

#define STORE_WORDS 16384u
#define LINE_OCTETS 256u

static uint16_t g_rx[LINE_OCTETS];
static uint16_t g_rx_n, g_rx_rd;
static uint32_t g_tx_octets, g_errors;
static uint16_t g_store[STORE_WORDS];

uint16_t hal_serial_read(uint16_t *buf, uint16_t max)
{
    uint16_t n = 0U;
    while (n < max && n < 16U && g_rx_rd < g_rx_n) {
        buf[n++] = g_rx[g_rx_rd++];
    }
    return n;
}
uint16_t hal_serial_write(const uint16_t *buf, uint16_t n)
{
    if (n > 2U && buf[2] == PROTO_ERROR) {
        g_errors++; /* a whole frame per call: this line takes everything */
    }
    g_tx_octets += n;
    return n; /* a line that takes everything: the pass's own work only */
}
uint16_t hal_store_words(void) { return (uint16_t)STORE_WORDS; }
uint16_t hal_store_erase_words(void) { return 32U; }
uint16_t hal_store_read(uint16_t addr, uint16_t *buf, uint16_t n)
{
    memcpy(buf, &g_store[addr], (size_t)n * sizeof *buf);
    return HAL_STORE_OK;
}
uint16_t hal_store_write(uint16_t addr, const uint16_t *buf, uint16_t n)
{
    memcpy(&g_store[addr], buf, (size_t)n * sizeof *buf);
    return HAL_STORE_OK;
}
uint16_t hal_store_erase(uint16_t addr, uint16_t n)
{
    (void)addr, (void)n;
    return HAL_STORE_OK;
}

__attribute__((noinline)) void bench_pass(void);
__attribute__((noinline)) void bench_pass(void) { app_proto_background(); }

static void period(void)
{
    app_isr();
    app_background();
    app_proto_background();
    hal_null_tick++;
}

static void put(uint16_t cmd, const uint16_t *pl, uint16_t len)
{
    g_rx_n = frame_encode(g_rx, LINE_OCTETS, cmd, 1U, pl, len);
    g_rx_rd = 0U;
}

/* The requests: name, command, payload (octets). */
typedef struct {
    const char *name;
    uint16_t cmd;
    uint16_t len;
    uint16_t pl[8];
} req_t;

static const req_t k_req[] = {
    {"hello", PROTO_HELLO, 0U, {0}},
    {"status", PROTO_STATUS, 0U, {0}},
    {"param_desc", PROTO_PARAM_DESC, 2U, {0, 0}},
    {"param_read", PROTO_PARAM_READ, 2U, {1, 0xF0}},
    {"param_write", PROTO_PARAM_WRITE, 6U, {1, 0xF0, 0x64, 0, 0, 0}},      /* comm_timeout_s 0.1 s */
    {"param_write_cfg", PROTO_PARAM_WRITE, 6U, {0, 0, 0, 0, 0, 0}},        /* a configuration row: below */
    {"save", PROTO_PARAMS_SAVE, 0U, {0}},
    {"restore", PROTO_PARAMS_RESTORE, 2U, {0, 0}},
    {"restore_compiled", PROTO_PARAMS_RESTORE, 2U, {1, 0}},
    {"capture_read", PROTO_CAPTURE_READ, 4U, {0, 0, 29, 0}},
    {"faultlog_read", PROTO_FAULTLOG_READ, 2U, {0, 0}},
    {"arm_refused", PROTO_ARM, 0U, {0}}, /* a speed reference set first: below */
    {"identify_result", PROTO_IDENTIFY, 2U, {2, 0}},
    {"telemetry_start", PROTO_TELEMETRY_START, 6U, {1, 0, 1, 0, 5, 0}},
};

int main(int argc, char **argv)
{
    static dtc_config_si_t si;
    static dtc_config_t cfg;
    char msg[200];
    const long n = argc > 2 ? atol(argv[1]) : 0;
    const req_t *r = NULL;
    req_t w;
    long k;
    size_t i;
    uint32_t j;
    for (i = 0; argc > 2 && i < sizeof k_req / sizeof k_req[0]; i++) {
        if (strcmp(argv[2], k_req[i].name) == 0) {
            r = &k_req[i];
        }
    }
    if (n <= 0 || r == NULL) {
        fprintf(stderr, "usage: bench_proto N CMD (CMD:");
        for (i = 0; i < sizeof k_req / sizeof k_req[0]; i++) {
            fprintf(stderr, " %s", k_req[i].name);
        }
        fprintf(stderr, ")\n");
        return 2;
    }
    dtc_config_si_defaults(&si);
    if (dtc_config_from_si(&si, &cfg, msg, sizeof msg) != DTC_SI_OK) {
        fprintf(stderr, "bench_proto: %s\n", msg);
        return 1;
    }
    for (k = 0; k < 3; k++) {
        hal_null_meas.adc[k] = cfg.board.adc_i_offset[k];
    }
    hal_null_meas.adc[HAL_ADC_VDC] = (uint16_t)(si.vdc_v / si.adc_vdc_v_per_count + 0.5);
    hal_null_meas.adc[HAL_ADC_VMID] = (uint16_t)(si.vdc_v / 2.0 / si.adc_vdc_v_per_count + 0.5);
    hal_null_meas.qep_count = 100U;
    for (j = 0; j < STORE_WORDS; j++) {
        g_store[j] = 0xFFFFU;
    }
    if (app_init(&cfg) != 0) {
        return 1;
    }
    app_set_arming(APP_ARM_COMMAND);
    app_proto_start(50000U);
    for (j = 0; j < 4000U; j++) {
        period();
    }
    w = *r;
    if (strcmp(r->name, "param_write_cfg") == 0) {
        /* the speed loop's torque limit (row 67, speed.torque_limit_iq) at its value: a
         * configuration row, re-checked by law_check and applied by a restart on the copy
         * (app_reconfigure) */
        frame_put_u16(&w.pl[0], 67U);
        frame_put_i32(&w.pl[2], cfg.speed.torque_limit_iq);
    }
    if (strcmp(r->name, "capture_read") == 0) {
        /* one channel, 64 samples at once, done */
        const uint16_t setup[24] = {1, 0, CAPTURE_Q_VDC, 0, 0, 0, 0, 0, 0, 0, 64, 0, 0, 0, 1, 0, CAPTURE_TRIG_NOW, 0};
        put(PROTO_CAPTURE_SETUP, setup, 24U);
        for (j = 0; j < 200U; j++) {
            period();
        }
    }
    if (strcmp(r->name, "arm_refused") == 0) {
        const uint16_t ref[4] = {0, 0, 0x10, 0}; /* speed reference 2^-4 pu */
        put(PROTO_SPEED_REF, ref, 4U);
        for (j = 0; j < 200U; j++) {
            period();
        }
    }
    if (strcmp(r->name, "faultlog_read") == 0) {
        /* a hardware trip in the log (an entry with its snapshot), cleared: READY again */
        hal_null_meas.trip = 1U;
        for (j = 0; j < 10U; j++) {
            period();
        }
        hal_null_meas.trip = 0U;
        put(PROTO_FAULT_CLEAR, NULL, 0U);
        for (j = 0; j < 2000U; j++) {
            period();
        }
    }
    if (strcmp(r->name, "restore") == 0) {
        put(PROTO_PARAMS_SAVE, NULL, 0U);
        for (j = 0; j < 200U; j++) {
            period();
        }
    }
    for (k = 0; k < n; k++) {
        put(w.cmd, w.pl, w.len);
        app_isr();
        app_background();
        bench_pass();
        hal_null_tick++;
        for (j = 0; j < 2000U; j++) {
            period(); /* the answer out; after a restart on a new configuration, READY again */
        }
    }
    {
        app_status_t s;
        app_get_status(&s);
        printf("calls bench_pass %ld (%s), %lu octets answered, %lu error frames, state %u, fault %u\n", n,
               r->name, (unsigned long)g_tx_octets, (unsigned long)g_errors, s.state, s.fault);
        /* every request carried out, except the arm refused with its reason */
        return (g_errors == 0U) == (strcmp(r->name, "arm_refused") != 0) && s.state == APP_STATE_READY ? 0 : 1;
    }
}
