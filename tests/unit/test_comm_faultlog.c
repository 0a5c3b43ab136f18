/*
 * test_comm_faultlog.c - the fault ring (firmware/comm/faultlog.h): entries in order newest
 * first, the ring keeps the last FAULTLOG_ENTRIES (8) and drops the oldest, the snapshot comes
 * back bit for bit, the reader detects an entry rewritten during its copy, and nothing but
 * faultlog_init empties it.
 */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <signal.h>
#include <sys/time.h>
#include <cmocka.h>

#include "fixtest.h"

#include "faultlog.h"

static faultlog_t g_log;

static faultlog_snapshot_t snap_for(uint32_t k)
{
    faultlog_snapshot_t s;
    s.ia_iq = (int32_t)(k * 1000u) - 16777216; /* -1 pu + ... */
    s.ib_iq = (int32_t)k;
    s.ic_iq = -(int32_t)k;
    s.vdc_iq = 16777216;
    s.vmid_iq = 8388608;
    s.speed_iq = INT32_MIN + (int32_t)k;
    s.psi_alpha_iq = INT32_MAX - (int32_t)k;
    s.psi_beta_iq = 3;
    s.te_iq = 4;
    s.te_ref_iq = 5;
    s.speed_ref_iq = 6;
    s.sector = (uint16_t)(1u + k % 6u);
    s.vector = (uint16_t)(k % 8u);
    s.state = 2u;
    return s;
}

static void record(uint32_t k)
{
    const faultlog_snapshot_t s = snap_for(k);
    faultlog_record(&g_log, 1000u + k, (uint16_t)(k % 12u), (int16_t)(k % 3u) - 1, &s);
}

static void assert_entry(const faultlog_entry_t *e, uint32_t k)
{
    const faultlog_snapshot_t s = snap_for(k);
    assert_int_equal(e->tick, 1000u + k);
    assert_int_equal(e->reason, k % 12u);
    assert_int_equal(e->detail, (int16_t)(k % 3u) - 1);
    assert_true(e->snap.ia_iq == s.ia_iq && e->snap.ib_iq == s.ib_iq && e->snap.ic_iq == s.ic_iq);
    assert_true(e->snap.vdc_iq == s.vdc_iq && e->snap.vmid_iq == s.vmid_iq);
    assert_true(e->snap.speed_iq == s.speed_iq && e->snap.psi_alpha_iq == s.psi_alpha_iq);
    assert_true(e->snap.psi_beta_iq == s.psi_beta_iq && e->snap.te_iq == s.te_iq);
    assert_true(e->snap.te_ref_iq == s.te_ref_iq && e->snap.speed_ref_iq == s.speed_ref_iq);
    assert_true(e->snap.sector == s.sector && e->snap.vector == s.vector && e->snap.state == s.state);
}

static int setup(void **state)
{
    (void)state;
    memset(&g_log, 0xEE, sizeof g_log); /* boot: RAM holds anything */
    faultlog_init(&g_log);
    return 0;
}

static void test_empty(void **state)
{
    (void)state;
    faultlog_entry_t e;
    assert_int_equal(faultlog_count(&g_log), 0);
    assert_int_equal(faultlog_get(&g_log, 0u, &e), FAULTLOG_EMPTY);
}

static void test_order_and_ring(void **state)
{
    (void)state;
    faultlog_entry_t e;
    for (uint32_t k = 0; k < 3; k++) {
        record(k);
    }
    assert_int_equal(faultlog_count(&g_log), 3);
    for (uint16_t i = 0; i < 3; i++) {
        assert_int_equal(faultlog_get(&g_log, i, &e), FAULTLOG_OK);
        assert_entry(&e, 2u - i); /* newest first */
    }
    assert_int_equal(faultlog_get(&g_log, 3u, &e), FAULTLOG_EMPTY);
    /* 20 faults in all: the last 8 are held, newest first */
    for (uint32_t k = 3; k < 20; k++) {
        record(k);
    }
    assert_int_equal(faultlog_count(&g_log), FAULTLOG_ENTRIES);
    assert_int_equal(g_log.recorded, 20);
    for (uint16_t i = 0; i < FAULTLOG_ENTRIES; i++) {
        assert_int_equal(faultlog_get(&g_log, i, &e), FAULTLOG_OK);
        assert_entry(&e, 19u - i);
    }
    assert_int_equal(faultlog_get(&g_log, FAULTLOG_ENTRIES, &e), FAULTLOG_EMPTY);
}

/* The counter wraps at 2^16 without losing the order. */
static void test_counter_wrap(void **state)
{
    (void)state;
    faultlog_entry_t e;
    g_log.recorded = 65533u;
    for (uint32_t k = 0; k < 6; k++) {
        record(k);
    }
    assert_int_equal(g_log.recorded, 3);
    assert_int_equal(faultlog_count(&g_log), 3); /* after a wrap the count restarts (2^16 faults) */
    for (uint16_t i = 0; i < 3; i++) {
        assert_int_equal(faultlog_get(&g_log, i, &e), FAULTLOG_OK);
        assert_entry(&e, 5u - i);
    }
}

/* A reader interrupted by the ISR: a POSIX interval timer plays the ISR and records faults from
 * its signal handler while the main program reads the oldest entry (the one the next record
 * rewrites) in a loop. Every copy returned FAULTLOG_OK must be one fault whole (its snapshot is
 * the one of its own tick), never a mix of two. */
static volatile uint32_t g_isr_k;
static void isr_handler(int sig)
{
    (void)sig;
    record(g_isr_k);
    g_isr_k++;
}

static void test_reader_interrupted_by_isr(void **state)
{
    (void)state;
    for (g_isr_k = 0; g_isr_k < FAULTLOG_ENTRIES; g_isr_k++) {
        record(g_isr_k);
    }
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = isr_handler;
    sigaction(SIGALRM, &sa, NULL);
    struct itimerval it = {{0, 20}, {0, 20}}; /* every 20 us */
    setitimer(ITIMER_REAL, &it, NULL);
    uint32_t ok = 0, busy = 0;
    while (g_isr_k < 3000u) {
        faultlog_entry_t e;
        const uint16_t r = faultlog_get(&g_log, FAULTLOG_ENTRIES - 1u, &e);
        if (r == FAULTLOG_OK) {
            assert_true(e.tick >= 1000u);
            assert_entry(&e, e.tick - 1000u);
            ok++;
        } else {
            assert_int_equal(r, FAULTLOG_BUSY);
            busy++;
        }
    }
    struct itimerval off = {{0, 0}, {0, 0}};
    setitimer(ITIMER_REAL, &off, NULL);
    signal(SIGALRM, SIG_DFL);
    print_message("reads: %u whole, %u discarded as rewritten\n", (unsigned)ok, (unsigned)busy);
    assert_true(ok > 0u);
}

/* The log is not the application's fault state: nothing short of faultlog_init clears it. */
static void test_kept_until_init(void **state)
{
    (void)state;
    faultlog_entry_t e;
    record(42u);
    /* a fault clear is the application's business: the log has no clear call at all */
    assert_int_equal(faultlog_get(&g_log, 0u, &e), FAULTLOG_OK);
    assert_entry(&e, 42u);
    faultlog_init(&g_log);
    assert_int_equal(faultlog_count(&g_log), 0);
}

UNIT_TEST_MAIN("comm faultlog", NULL,
               cmocka_unit_test_setup(test_empty, setup),
               cmocka_unit_test_setup(test_order_and_ring, setup),
               cmocka_unit_test_setup(test_counter_wrap, setup),
               cmocka_unit_test_setup(test_reader_interrupted_by_isr, setup),
               cmocka_unit_test_setup(test_kept_until_init, setup))
