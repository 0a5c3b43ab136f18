/*
 * test_comm_store.c - the two-copy parameter store (firmware/comm/store.h) on a model of the
 * storage medium with a power cut at every word written.
 *
 * The medium model (the hal_store_* functions, defined here) has two kinds:
 *   EEPROM: words are rewritten in place, erase does nothing;
 *   flash:  erase sets words to 0xFFFF, a write can only clear bits (new = old AND value).
 * A power cut after k words (each word written or erased counts one) leaves the word being
 * written and the rest of that call's words at pseudo-random values (a page or a sector caught
 * mid-cycle), and every later call of that power-on fails without effect (the code stops). A
 * boot afterwards must find a valid set: the newest completed save, or the copy it was
 * replacing when the cut came before the save's last word; never a mix, never garbage.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "fixtest.h"

#include "crc16.h"
#include "hal.h"
#include "store.h"

/* ---- the medium model ---------------------------------------------------------------------- */
#define MEDIUM_WORDS 128u
#define ERASE_WORDS 64u
enum { KIND_EEPROM = 0, KIND_FLASH = 1 };
static struct {
    uint16_t w[MEDIUM_WORDS];
    uint16_t words;    /* hal_store_words() */
    int kind;
    long budget;       /* words that can still be written before the cut; < 0: no cut */
    int dead;          /* the power is off */
    uint32_t rng;
    uint16_t stuck_mask; /* bits that read 0 (a failed cell), at stuck_addr */
    uint16_t stuck_addr;
    long ops;          /* words written/erased so far */
} g_m;

static uint16_t rnd16(void)
{
    g_m.rng ^= g_m.rng << 13;
    g_m.rng ^= g_m.rng >> 17;
    g_m.rng ^= g_m.rng << 5;
    return (uint16_t)g_m.rng;
}

/* One word operation; returns 0 if the power went at it (the rest of the call is garbage). */
static int spend(void)
{
    g_m.ops++;
    if (g_m.budget < 0) {
        return 1;
    }
    if (g_m.budget == 0) {
        g_m.dead = 1;
        return 0;
    }
    g_m.budget--;
    return 1;
}

uint16_t hal_store_words(void) { return g_m.words; }
uint16_t hal_store_erase_words(void) { return ERASE_WORDS; }

uint16_t hal_store_read(uint16_t addr, uint16_t *buf, uint16_t n)
{
    if (g_m.dead) {
        return HAL_STORE_ERR_DEVICE;
    }
    if ((uint32_t)addr + n > g_m.words) {
        return HAL_STORE_ERR_RANGE;
    }
    for (uint16_t i = 0; i < n; i++) {
        buf[i] = g_m.w[addr + i];
        if ((uint16_t)(addr + i) == g_m.stuck_addr) {
            buf[i] = (uint16_t)(buf[i] & ~g_m.stuck_mask);
        }
    }
    return HAL_STORE_OK;
}

uint16_t hal_store_write(uint16_t addr, const uint16_t *buf, uint16_t n)
{
    if (g_m.dead) {
        return HAL_STORE_ERR_DEVICE;
    }
    if ((uint32_t)addr + n > g_m.words) {
        return HAL_STORE_ERR_RANGE;
    }
    for (uint16_t i = 0; i < n; i++) {
        if (!spend()) {
            for (uint16_t j = i; j < n; j++) {
                g_m.w[addr + j] = rnd16();
            }
            return HAL_STORE_ERR_DEVICE;
        }
        g_m.w[addr + i] = (g_m.kind == KIND_FLASH) ? (uint16_t)(g_m.w[addr + i] & buf[i]) : buf[i];
    }
    return HAL_STORE_OK;
}

uint16_t hal_store_erase(uint16_t addr, uint16_t n)
{
    if (g_m.dead) {
        return HAL_STORE_ERR_DEVICE;
    }
    if ((uint32_t)addr + n > g_m.words || (addr % ERASE_WORDS) != 0u || (n % ERASE_WORDS) != 0u) {
        return HAL_STORE_ERR_RANGE;
    }
    if (g_m.kind == KIND_EEPROM) {
        return HAL_STORE_OK;
    }
    for (uint16_t i = 0; i < n; i++) {
        if (!spend()) {
            for (uint16_t j = i; j < n; j++) {
                g_m.w[addr + j] = rnd16();
            }
            return HAL_STORE_ERR_DEVICE;
        }
        g_m.w[addr + i] = 0xFFFFu;
    }
    return HAL_STORE_OK;
}

static void medium_reset(int kind)
{
    memset(&g_m, 0, sizeof g_m);
    g_m.words = MEDIUM_WORDS;
    g_m.kind = kind;
    g_m.budget = -1;
    g_m.rng = 0x9E3779B9u;
    g_m.stuck_addr = 0xFFFFu;
    for (uint16_t i = 0; i < MEDIUM_WORDS; i++) {
        g_m.w[i] = (kind == KIND_FLASH) ? 0xFFFFu : rnd16(); /* new part: erased / anything */
    }
}

static void power_on(void)
{
    g_m.dead = 0;
    g_m.budget = -1;
}

/* ---- the parameter sets ---------------------------------------------------------------------- */
#define N 20u
#define VERSION 0x0103u
static uint16_t g_defaults[N];

static void make_set(uint16_t *d, uint16_t id)
{
    for (uint16_t i = 0; i < N; i++) {
        d[i] = (uint16_t)(id * 1000u + i * 7u); /* id 0 = the compiled-in defaults */
    }
}

/* Which set a boot loaded: its id, or -1 for anything that is no set. */
static int boot_id(store_t *st)
{
    uint16_t d[N];
    power_on();
    const uint16_t r = store_boot(st, VERSION, d, g_defaults, N);
    for (uint16_t id = 0; id < 64; id++) {
        uint16_t e[N];
        make_set(e, id);
        if (memcmp(d, e, sizeof d) == 0) {
            assert_int_equal(r, id == 0 ? STORE_DEFAULTS : STORE_OK);
            return id;
        }
    }
    return -1;
}

static uint16_t save_id(store_t *st, uint16_t id)
{
    uint16_t d[N];
    make_set(d, id);
    return store_save(st, 0u, VERSION, d, N);
}

static int setup(void **state)
{
    (void)state;
    make_set(g_defaults, 0u);
    return 0;
}

/* Word operations of one complete save on the current medium. */
static long ops_of_save(store_t *st, uint16_t id)
{
    uint16_t saved[MEDIUM_WORDS];
    memcpy(saved, g_m.w, sizeof saved);
    const store_t st0 = *st;
    const long before = g_m.ops;
    assert_int_equal(save_id(st, id), STORE_OK);
    const long ops = g_m.ops - before;
    memcpy(g_m.w, saved, sizeof saved);
    *st = st0;
    return ops;
}

/* From the medium as it is (previous newest set `old`), cut a save of `id` at every word; after
 * each cut a boot must give `old` (cut before the save's last word) or `id` (after it), and a
 * further save of `id2`, cut at every word too when `nested`, must again give one of the sets. */
static void cut_everywhere(int old, uint16_t id, int nested, uint16_t id2)
{
    store_t st;
    assert_int_equal(boot_id(&st), old);
    const long w = ops_of_save(&st, id);
    uint16_t snap[MEDIUM_WORDS];
    memcpy(snap, g_m.w, sizeof snap);
    for (long k = 0; k <= w; k++) {
        memcpy(g_m.w, snap, sizeof snap);
        assert_int_equal(boot_id(&st), old);
        g_m.budget = k;
        const uint16_t r = save_id(&st, id);
        const int got = boot_id(&st);
        if (k >= w) {
            assert_int_equal(r, STORE_OK);
            assert_int_equal(got, id);
        } else if (k < w - 1) {
            assert_int_not_equal(r, STORE_OK);
            assert_int_equal(got, old);
        } else { /* the cut hit the last word, STORE_MAGIC itself: either, never garbage */
            assert_true(got == old || got == (int)id);
        }
        if (nested) {
            uint16_t mid[MEDIUM_WORDS];
            memcpy(mid, g_m.w, sizeof mid);
            const long w2 = ops_of_save(&st, id2);
            for (long k2 = 0; k2 <= w2; k2++) {
                memcpy(g_m.w, mid, sizeof mid);
                store_t st2;
                assert_int_equal(boot_id(&st2), got);
                g_m.budget = k2;
                (void)save_id(&st2, id2);
                const int got2 = boot_id(&st2);
                if (k2 >= w2) {
                    assert_int_equal(got2, id2);
                } else if (k2 < w2 - 1) {
                    assert_int_equal(got2, got);
                } else {
                    assert_true(got2 == got || got2 == (int)id2);
                }
                /* and the store keeps working: a complete save after it all is what boots */
                assert_int_equal(save_id(&st2, 63u), STORE_OK);
                assert_int_equal(boot_id(&st2), 63);
            }
        }
    }
}

static void run_cuts(int kind)
{
    store_t st;
    /* new part: defaults; a first save cut everywhere */
    medium_reset(kind);
    cut_everywhere(0, 1u, 1, 2u);
    /* one copy on the medium */
    medium_reset(kind);
    assert_int_equal(boot_id(&st), 0);
    assert_int_equal(save_id(&st, 1u), STORE_OK);
    cut_everywhere(1, 2u, 1, 3u);
    /* two copies on the medium (the save goes over the older) */
    medium_reset(kind);
    assert_int_equal(boot_id(&st), 0);
    assert_int_equal(save_id(&st, 1u), STORE_OK);
    assert_int_equal(save_id(&st, 2u), STORE_OK);
    cut_everywhere(2, 3u, 1, 4u);
    /* many saves alternate between the slots and the newest always boots */
    medium_reset(kind);
    assert_int_equal(boot_id(&st), 0);
    for (uint16_t id = 1; id < 30; id++) {
        assert_int_equal(save_id(&st, id), STORE_OK);
        assert_int_equal(st.seq, (uint32_t)id);
        assert_int_equal(st.newest, (id - 1u) & 1u);
        assert_int_equal(boot_id(&st), (int)id);
    }
}

static void test_power_cut_every_word_eeprom(void **state)
{
    (void)state;
    run_cuts(KIND_EEPROM);
}

static void test_power_cut_every_word_flash(void **state)
{
    (void)state;
    run_cuts(KIND_FLASH);
}

static void test_refusals(void **state)
{
    (void)state;
    store_t st;
    uint16_t d[N];
    medium_reset(KIND_FLASH);
    assert_int_equal(boot_id(&st), 0);
    assert_int_equal(save_id(&st, 1u), STORE_OK);
    /* armed: refused, nothing written */
    uint16_t snap[MEDIUM_WORDS];
    memcpy(snap, g_m.w, sizeof snap);
    make_set(d, 2u);
    assert_int_equal(store_save(&st, 1u, VERSION, d, N), STORE_ERR_ARMED);
    assert_memory_equal(snap, g_m.w, sizeof snap);
    /* a set larger than a slot */
    uint16_t big[ERASE_WORDS];
    memset(big, 0, sizeof big);
    assert_int_equal(store_save(&st, 0u, VERSION, big, (uint16_t)(ERASE_WORDS - STORE_HEADER_WORDS + 1u)), STORE_ERR_SIZE);
    /* another layout version never loads: the defaults do */
    uint16_t out[N];
    assert_int_equal(store_boot(&st, (uint16_t)(VERSION + 1u), out, g_defaults, N), STORE_DEFAULTS);
    assert_memory_equal(out, g_defaults, sizeof out);
    /* nor another length */
    assert_int_equal(store_boot(&st, VERSION, out, g_defaults, N - 1u), STORE_DEFAULTS);
    /* a failed cell: the read-back catches it, the old copy stays */
    assert_int_equal(boot_id(&st), 1);
    g_m.stuck_addr = (uint16_t)(ERASE_WORDS + STORE_HEADER_WORDS + 3u); /* slot 1, data word 3 */
    g_m.stuck_mask = 0x0004u;
    make_set(d, 2u);
    d[3] = 0xFFFFu;
    assert_int_equal(store_save(&st, 0u, VERSION, d, N), STORE_ERR_VERIFY);
    g_m.stuck_addr = 0xFFFFu;
    assert_int_equal(boot_id(&st), 1);
    /* no medium: defaults, and saving is refused */
    medium_reset(KIND_FLASH);
    g_m.words = 0u;
    assert_int_equal(boot_id(&st), 0);
    assert_int_equal(save_id(&st, 1u), STORE_ERR_SIZE);
}

/* A corrupted stored copy (a flipped bit anywhere in it) is never loaded: every single-bit error
 * of the newest copy makes the boot fall back to the older copy. */
static void test_corruption_falls_back(void **state)
{
    (void)state;
    store_t st;
    medium_reset(KIND_EEPROM);
    assert_int_equal(boot_id(&st), 0);
    assert_int_equal(save_id(&st, 1u), STORE_OK); /* slot 0 */
    assert_int_equal(save_id(&st, 2u), STORE_OK); /* slot 1 */
    for (uint16_t w = 0; w < STORE_HEADER_WORDS + N; w++) {
        for (uint16_t b = 0; b < 16u; b++) {
            g_m.w[ERASE_WORDS + w] ^= (uint16_t)(1u << b);
            const int got = boot_id(&st);
            /* a flipped sequence bit can only make the copy look older or newer; the set is 2 */
            if (w == 2u || w == 3u) {
                assert_true(got == 1 || got == 2);
            } else {
                assert_int_equal(got, 1);
            }
            g_m.w[ERASE_WORDS + w] ^= (uint16_t)(1u << b);
        }
    }
    assert_int_equal(boot_id(&st), 2);
}

/* The sequence number compares modulo 2^32: a copy with 0 follows one with 0xFFFFFFFF. */
static void test_sequence_wraps(void **state)
{
    (void)state;
    store_t st;
    medium_reset(KIND_EEPROM);
    uint16_t rec[STORE_HEADER_WORDS + N];
    rec[0] = STORE_MAGIC;
    rec[1] = VERSION;
    rec[2] = 0xFFFFu;
    rec[3] = 0xFFFFu;
    rec[4] = N;
    make_set(&rec[STORE_HEADER_WORDS], 7u);
    rec[5] = crc16_words(crc16_words(CRC16_INIT, &rec[1], 4u), &rec[STORE_HEADER_WORDS], N);
    memcpy(g_m.w, rec, sizeof rec);
    assert_int_equal(boot_id(&st), 7);
    assert_int_equal(st.seq, 0xFFFFFFFFu);
    assert_int_equal(save_id(&st, 8u), STORE_OK);
    assert_int_equal(st.seq, 0u);
    assert_int_equal(boot_id(&st), 8);
}

UNIT_TEST_MAIN("comm store", NULL,
               cmocka_unit_test_setup(test_power_cut_every_word_eeprom, setup),
               cmocka_unit_test_setup(test_power_cut_every_word_flash, setup),
               cmocka_unit_test_setup(test_refusals, setup),
               cmocka_unit_test_setup(test_corruption_falls_back, setup),
               cmocka_unit_test_setup(test_sequence_wraps, setup))
