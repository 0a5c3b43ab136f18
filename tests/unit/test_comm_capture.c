/*
 * test_comm_capture.c - the triggered capture (firmware/comm/capture.h) against a reference
 * written here from the definition: the recorded samples are the ISR periods tick0 + j*decim;
 * the trigger sample is the first recorded sample, with at least `pre` recorded before it, that
 * meets the trigger condition; the capture is the `samples` recorded samples from pre before the
 * trigger sample on, each channel the value its variable held in that period.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "fixtest.h"

#include "capture.h"

static capture_t g_cap;
/* The application's variables the quantities are bound to. */
static volatile int32_t g_ia, g_psi_a, g_te;
static volatile uint16_t g_sector;

/* Signal values at ISR tick t (a slow triangle wave for ia, others derived). */
static int32_t ia_at(uint32_t t) { int32_t p = (int32_t)(t % 200u); return (p < 100 ? p : 200 - p) * 100000 - 5000000; }
static int32_t psi_at(uint32_t t) { return (int32_t)(t * 3u) - 7; }
static int32_t te_at(uint32_t t) { return -(int32_t)t; }
static uint16_t sector_at(uint32_t t) { return (uint16_t)(1u + t % 6u); }

static void set_vars(uint32_t t)
{
    g_ia = ia_at(t);
    g_psi_a = psi_at(t);
    g_te = te_at(t);
    g_sector = sector_at(t);
}

static int setup(void **state)
{
    (void)state;
    memset(&g_cap, 0x5A, sizeof g_cap);
    capture_init(&g_cap);
    assert_int_equal(capture_bind(&g_cap, CAPTURE_Q_I_A, &g_ia), 0);
    assert_int_equal(capture_bind(&g_cap, CAPTURE_Q_PSI_ALPHA_EST, &g_psi_a), 0);
    assert_int_equal(capture_bind(&g_cap, CAPTURE_Q_TORQUE_EST, &g_te), 0);
    assert_int_equal(capture_bind_u16(&g_cap, CAPTURE_Q_SECTOR, &g_sector), 0);
    assert_int_equal(capture_bind(&g_cap, CAPTURE_Q_COUNT, &g_te), 1);
    return 0;
}

static int32_t value_of(uint16_t q, uint32_t t)
{
    switch (q) {
    case CAPTURE_Q_I_A: return ia_at(t);
    case CAPTURE_Q_PSI_ALPHA_EST: return psi_at(t);
    case CAPTURE_Q_TORQUE_EST: return te_at(t);
    default: return (int32_t)sector_at(t);
    }
}

/* Reference trigger: returns the tick of the trigger sample, given the first recorded tick t0. */
static uint32_t ref_trigger_tick(const capture_setup_t *s, uint32_t t0, const uint32_t *fault_tick)
{
    const uint16_t q = s->quantity[s->trig_ch];
    for (uint32_t j = s->pre;; j++) {
        const uint32_t t = t0 + j * s->decim;
        const int32_t x = value_of(q, t);
        const int32_t xp = value_of(q, t - s->decim);
        int hit = 0;
        switch (s->trigger) {
        case CAPTURE_TRIG_NOW: hit = 1; break;
        case CAPTURE_TRIG_ABOVE: hit = x >= s->level; break;
        case CAPTURE_TRIG_BELOW: hit = x <= s->level; break;
        case CAPTURE_TRIG_RISING: hit = j > 0 && xp < s->level && x >= s->level; break;
        case CAPTURE_TRIG_FALLING: hit = j > 0 && xp > s->level && x <= s->level; break;
        default: hit = fault_tick != NULL && *fault_tick <= t && *fault_tick > t - s->decim; break;
        }
        if (hit) {
            return t;
        }
        assert_true(j < 100000u);
    }
}

/* Runs the ISR from tick t0 until done (or a bound), then checks every value against the
 * reference. fault_tick: a fault reported in that one period (TRIG_FAULT), or NULL. */
static void run_and_check(const capture_setup_t *s, uint32_t t0, const uint32_t *fault_tick)
{
    assert_int_equal(capture_setup(&g_cap, s), CAPTURE_OK);
    assert_int_equal(capture_state(&g_cap), CAPTURE_ARMED);
    uint32_t t = t0;
    for (; t < t0 + 200000u && capture_state(&g_cap) != CAPTURE_DONE; t++) {
        set_vars(t);
        capture_isr(&g_cap, t, (uint16_t)(fault_tick != NULL && *fault_tick == t));
    }
    assert_int_equal(capture_state(&g_cap), CAPTURE_DONE);
    const uint32_t tt = ref_trigger_tick(s, t0, fault_tick);
    const uint32_t first = tt - (uint32_t)s->pre * s->decim;
    assert_int_equal(capture_first_tick(&g_cap), first);
    for (uint16_t k = 0; k < s->samples; k++) {
        for (uint16_t ch = 0; ch < s->count; ch++) {
            assert_int_equal(capture_read(&g_cap, k, ch), value_of(s->quantity[ch], first + (uint32_t)k * s->decim));
        }
    }
    /* the ISR leaves a finished capture alone */
    const int32_t v0 = capture_read(&g_cap, 0u, 0u);
    for (uint32_t u = t; u < t + 50u; u++) {
        set_vars(u);
        capture_isr(&g_cap, u, 1u);
    }
    assert_int_equal(capture_read(&g_cap, 0u, 0u), v0);
    assert_int_equal(capture_first_tick(&g_cap), first);
}

static capture_setup_t base(void)
{
    capture_setup_t s;
    memset(&s, 0, sizeof s);
    s.count = 4u;
    s.quantity[0] = CAPTURE_Q_I_A;
    s.quantity[1] = CAPTURE_Q_PSI_ALPHA_EST;
    s.quantity[2] = CAPTURE_Q_TORQUE_EST;
    s.quantity[3] = CAPTURE_Q_SECTOR;
    s.samples = (uint16_t)(CAPTURE_BUF_WORDS32 / 4u);
    s.pre = 0u;
    s.decim = 1u;
    s.trigger = CAPTURE_TRIG_NOW;
    return s;
}

static void test_off_does_nothing(void **state)
{
    (void)state;
    const capture_t before = g_cap;
    for (uint32_t t = 0; t < 100u; t++) {
        capture_isr(&g_cap, t, 1u);
    }
    assert_memory_equal(&g_cap, &before, sizeof before);
    assert_int_equal(capture_read(&g_cap, 0u, 0u), 0);
}

static void test_now_every_period_and_decimated(void **state)
{
    (void)state;
    capture_setup_t s = base();
    run_and_check(&s, 1000u, NULL);
    s.decim = 7u;
    s.pre = 10u; /* NOW with a pre-trigger history: triggers once the history is full */
    run_and_check(&s, 5u, NULL);
    s.count = 1u;
    s.samples = CAPTURE_BUF_WORDS32; /* the whole buffer on one channel */
    s.pre = (uint16_t)(CAPTURE_BUF_WORDS32 - 1u);
    s.decim = 2u;
    run_and_check(&s, 0u, NULL);
}

static void test_level_and_edge_with_pretrigger(void **state)
{
    (void)state;
    capture_setup_t s = base();
    s.pre = 64u;
    s.trig_ch = 0u; /* ia */
    s.level = 2000000;
    /* armed while ia is already above the level at the start: ABOVE fires as soon as the
     * history is full, RISING waits for the next crossing (t = 270) */
    const uint32_t t0 = 80u;
    assert_true(ia_at(t0) >= s.level);
    const uint16_t kinds[4] = {CAPTURE_TRIG_ABOVE, CAPTURE_TRIG_BELOW, CAPTURE_TRIG_RISING, CAPTURE_TRIG_FALLING};
    for (int i = 0; i < 4; i++) {
        s.trigger = kinds[i];
        for (uint16_t decim = 1u; decim <= 3u; decim++) {
            s.decim = decim;
            run_and_check(&s, t0, NULL);
        }
    }
    /* a rising edge lands where the wave crosses the level going up (ia rises 100000 per tick
     * from -5e6 at t = 0 mod 200: crosses 2e6 at t = 70 mod 200) */
    s.trigger = CAPTURE_TRIG_RISING;
    s.decim = 1u;
    run_and_check(&s, t0, NULL);
    assert_int_equal(capture_first_tick(&g_cap) + s.pre, 270u);
    /* the edge on the uint16 channel (sector 1..6 rising through 4) */
    s.trig_ch = 3u;
    s.level = 4;
    run_and_check(&s, 3u, NULL);
    /* a long wait: the ring wraps many times before the trigger */
    s.trig_ch = 1u;
    s.trigger = CAPTURE_TRIG_ABOVE;
    s.level = psi_at(50000u);
    run_and_check(&s, 0u, NULL);
}

static void test_fault_trigger_between_decimated_samples(void **state)
{
    (void)state;
    capture_setup_t s = base();
    s.trigger = CAPTURE_TRIG_FAULT;
    s.pre = 100u;
    s.decim = 10u;
    const uint32_t fault = 1000u + 100u * 10u + 5u * 10u + 3u; /* not a recorded period */
    run_and_check(&s, 1000u, &fault);
    /* the trigger sample is the first recorded period at or after the fault */
    assert_int_equal(capture_first_tick(&g_cap) + 100u * 10u, 1000u + 100u * 10u + 6u * 10u);
}
/* The trigger levels at int32's ends, where a test written as a difference or a negation would
 * overflow (capture.c forms below/falling as ~x >= ~L): a level trigger at the end it includes
 * fires on the first sample the history allows; an edge through a level no sample can pass
 * never fires. */
static void test_levels_at_the_int32_limits(void **state)
{
    (void)state;
    capture_setup_t s = base();
    s.pre = 3u;
    s.trig_ch = 2u; /* te = -t */
    s.trigger = CAPTURE_TRIG_ABOVE;
    s.level = INT32_MIN;
    run_and_check(&s, 10u, NULL);
    assert_int_equal(capture_first_tick(&g_cap), 10u);
    s.trigger = CAPTURE_TRIG_BELOW;
    s.level = INT32_MAX;
    run_and_check(&s, 10u, NULL);
    assert_int_equal(capture_first_tick(&g_cap), 10u);
    const uint16_t never[2] = {CAPTURE_TRIG_RISING, CAPTURE_TRIG_FALLING};
    const int32_t at[2] = {INT32_MIN, INT32_MAX};
    for (int i = 0; i < 2; i++) {
        s.trigger = never[i];
        s.level = at[i];
        assert_int_equal(capture_setup(&g_cap, &s), CAPTURE_OK);
        for (uint32_t t = 0u; t < 3000u; t++) {
            set_vars(t);
            capture_isr(&g_cap, t, 0u);
        }
        assert_int_equal(capture_state(&g_cap), CAPTURE_ARMED);
    }
}

static void test_setup_refusals(void **state)
{
    (void)state;
    capture_setup_t s = base();
    s.count = 0u;
    assert_int_equal(capture_setup(&g_cap, &s), CAPTURE_ERR_COUNT);
    s.count = CAPTURE_CHANNELS + 1u;
    assert_int_equal(capture_setup(&g_cap, &s), CAPTURE_ERR_COUNT);
    s = base();
    s.quantity[2] = CAPTURE_Q_VDC; /* not bound */
    assert_int_equal(capture_setup(&g_cap, &s), CAPTURE_ERR_QUANTITY);
    s.quantity[2] = CAPTURE_Q_COUNT;
    assert_int_equal(capture_setup(&g_cap, &s), CAPTURE_ERR_QUANTITY);
    s = base();
    s.samples = (uint16_t)(CAPTURE_BUF_WORDS32 / 4u + 1u);
    assert_int_equal(capture_setup(&g_cap, &s), CAPTURE_ERR_SAMPLES);
    s.samples = 0u;
    assert_int_equal(capture_setup(&g_cap, &s), CAPTURE_ERR_SAMPLES);
    s = base();
    s.pre = s.samples;
    assert_int_equal(capture_setup(&g_cap, &s), CAPTURE_ERR_PRE);
    s = base();
    s.decim = 0u;
    assert_int_equal(capture_setup(&g_cap, &s), CAPTURE_ERR_DECIM);
    s = base();
    s.trigger = CAPTURE_TRIG_COUNT;
    assert_int_equal(capture_setup(&g_cap, &s), CAPTURE_ERR_TRIGGER);
    s.trigger = CAPTURE_TRIG_RISING;
    s.trig_ch = 4u;
    assert_int_equal(capture_setup(&g_cap, &s), CAPTURE_ERR_TRIGGER);
    assert_int_equal(capture_state(&g_cap), CAPTURE_OFF); /* a refused set-up leaves it off */
    /* a good set-up arms; stop turns it off */
    s = base();
    assert_int_equal(capture_setup(&g_cap, &s), CAPTURE_OK);
    assert_int_equal(capture_state(&g_cap), CAPTURE_ARMED);
    capture_stop(&g_cap);
    assert_int_equal(capture_state(&g_cap), CAPTURE_OFF);
}

UNIT_TEST_MAIN("comm capture", NULL,
               cmocka_unit_test_setup(test_off_does_nothing, setup),
               cmocka_unit_test_setup(test_now_every_period_and_decimated, setup),
               cmocka_unit_test_setup(test_level_and_edge_with_pretrigger, setup),
               cmocka_unit_test_setup(test_fault_trigger_between_decimated_samples, setup),
               cmocka_unit_test_setup(test_levels_at_the_int32_limits, setup),
               cmocka_unit_test_setup(test_setup_refusals, setup))
