/*
 * pil_cm_main.c - the Cortex-M replay image of processor-in-the-loop (docs/pil.md), run by
 * tools/pil/pil_compare.py in qemu-system-arm -M mps2-an385 with semihosting:
 *   reads pil_in.bin (the recording) and writes pil_out.bin (one output record per ISR) and
 *   pil_cycles.bin (SysTick counts of every app_isr() call, u32 little-endian) in qemu's working
 *   directory. With -icount shift=N every instruction advances the clock by 2^N ns, so the
 *   SysTick counts (25 MHz processor clock) measure instructions, not Cortex-M cycles.
 * With a file pil_capture.bin in that directory (tools/pil/pil_profile.py --capture) a capture is
 * attached and armed for the whole replay: four channels every period, an edge trigger that never
 * fires, so every ISR runs the capture's longest per-period path (its sample and the trigger test;
 * capture.h). The capture writes no output: the replay's records are the same.
 * Exits through SYS_EXIT: ApplicationExit on success, anything else on an error.
 */
#include <stdint.h>

#include "app.h"
#include "capture.h"
#include "pil_replay.h"

#define SYS_OPEN 0x01U
#define SYS_WRITE0 0x04U
#define SYS_CLOSE 0x02U
#define SYS_WRITE 0x05U
#define SYS_READ 0x06U
#define SYS_EXIT 0x18U
#define ADP_STOPPED_APPLICATION_EXIT 0x20026UL
#define ADP_STOPPED_RUNTIME_ERROR 0x20023UL

#define SYST_CSR (*(volatile uint32_t *)0xE000E010UL)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014UL)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018UL)

#define PIL_CONFIG_MAX 256U
#define CYC_BUF 256U

static uint8_t g_blob[4U * PIL_CONFIG_MAX];
static capture_t g_cap;
static uint32_t g_cyc[CYC_BUF];
static uint32_t g_ncyc;
static uint32_t g_t0;

static uint32_t semi(uint32_t op, const void *arg)
{
    register uint32_t r0 __asm("r0") = op;
    register const void *r1 __asm("r1") = arg;
    __asm volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

static void semi_exit(uint32_t reason)
{
    (void)semi(SYS_EXIT, (const void *)(uintptr_t)reason);
    for (;;) {
    }
}

static void semi_fail(const char *why)
{
    (void)semi(SYS_WRITE0, why);
    semi_exit(ADP_STOPPED_RUNTIME_ERROR);
}

static uint32_t semi_open(const char *name, uint32_t len, uint32_t mode)
{
    uint32_t a[3];
    a[0] = (uint32_t)(uintptr_t)name;
    a[1] = mode;
    a[2] = len;
    return semi(SYS_OPEN, a);
}

/* Reads or writes exactly n bytes, or stops with an error. */
static void semi_rw(uint32_t op, uint32_t fd, const void *buf, uint32_t n)
{
    uint32_t a[3];
    a[0] = fd;
    a[1] = (uint32_t)(uintptr_t)buf;
    a[2] = n;
    if (semi(op, a) != 0U) {
        semi_fail("pil_cm: short read or write (recording truncated?)\n");
    }
}

void pil_target_isr_begin(void)
{
    g_t0 = SYST_CVR;
}

void pil_target_isr_end(void)
{
    const uint32_t t1 = SYST_CVR;
    g_cyc[g_ncyc++] = (g_t0 - t1) & 0xFFFFFFUL; /* SysTick counts down, 24 bits */
}

/* The capture of --capture, armed: the phase currents and the estimated flux every period, 128
 * samples, a rising edge of i_a through INT32_MAX as its trigger (never met). */
static void capture_on(void)
{
    capture_setup_t s;
    s.count = 4U;
    s.quantity[0] = (uint16_t)CAPTURE_Q_I_A;
    s.quantity[1] = (uint16_t)CAPTURE_Q_I_B;
    s.quantity[2] = (uint16_t)CAPTURE_Q_PSI_ALPHA_EST;
    s.quantity[3] = (uint16_t)CAPTURE_Q_PSI_BETA_EST;
    s.samples = 128U;
    s.pre = 64U;
    s.decim = 1U;
    s.trigger = (uint16_t)CAPTURE_TRIG_RISING;
    s.trig_ch = 0U;
    s.level = INT32_MAX;
    capture_init(&g_cap);
    app_attach(&g_cap, 0);
    if (capture_setup(&g_cap, &s) != (uint16_t)CAPTURE_OK) {
        semi_fail("pil_cm: the capture's set-up was refused\n");
    }
}

static void flush_cycles(uint32_t fd)
{
    uint8_t b[4U * CYC_BUF];
    uint32_t i;
    for (i = 0U; i < g_ncyc; ++i) {
        b[4U * i] = (uint8_t)(g_cyc[i] & 0xFFU);
        b[4U * i + 1U] = (uint8_t)((g_cyc[i] >> 8) & 0xFFU);
        b[4U * i + 2U] = (uint8_t)((g_cyc[i] >> 16) & 0xFFU);
        b[4U * i + 3U] = (uint8_t)(g_cyc[i] >> 24);
    }
    if (g_ncyc != 0U) {
        semi_rw(SYS_WRITE, fd, b, 4U * g_ncyc);
    }
    g_ncyc = 0U;
}

int main(void)
{
    uint8_t hb[PIL_HEADER_BYTES];
    uint8_t in[PIL_IN_BYTES + PIL_OUT_BYTES];
    uint8_t out[PIL_OUT_BYTES];
    pil_header_t h;
    uint32_t fin, fout, fcyc, k;

    fin = semi_open("pil_in.bin", 10U, 1U);     /* "rb" */
    fout = semi_open("pil_out.bin", 11U, 5U);   /* "wb" */
    fcyc = semi_open("pil_cycles.bin", 14U, 5U); /* "wb" */
    if (fin == 0xFFFFFFFFUL || fout == 0xFFFFFFFFUL || fcyc == 0xFFFFFFFFUL) {
        semi_fail("pil_cm: cannot open pil_in.bin, pil_out.bin or pil_cycles.bin\n");
    }
    semi_rw(SYS_READ, fin, hb, PIL_HEADER_BYTES);
    if (pil_header_decode(hb, &h) != PIL_OK || h.config_fields > PIL_CONFIG_MAX) {
        semi_fail("pil_cm: not a recording this image replays\n");
    }
    semi_rw(SYS_READ, fin, g_blob, 4U * h.config_fields);
    if (pil_replay_init(&h, g_blob) != 0) {
        semi_fail("pil_cm: app_init() refused the recorded configuration\n");
    }
    {
        uint32_t fcap = semi_open("pil_capture.bin", 15U, 1U); /* "rb": present = capture on */
        if (fcap != 0xFFFFFFFFUL) {
            (void)semi(SYS_CLOSE, &fcap);
            capture_on();
        }
    }
    SYST_RVR = 0xFFFFFFUL;
    SYST_CVR = 0U;
    SYST_CSR = 5U; /* enabled, processor clock, no interrupt */
    for (k = 0U; k < h.isr_count; ++k) {
        semi_rw(SYS_READ, fin, in, PIL_IN_BYTES + PIL_OUT_BYTES);
        pil_replay_isr(in, out);
        semi_rw(SYS_WRITE, fout, out, PIL_OUT_BYTES);
        if (g_ncyc == CYC_BUF) {
            flush_cycles(fcyc);
        }
    }
    flush_cycles(fcyc);
    (void)semi(SYS_CLOSE, &fout);
    (void)semi(SYS_CLOSE, &fcyc);
    semi_exit(ADP_STOPPED_APPLICATION_EXIT);
    return 0;
}
