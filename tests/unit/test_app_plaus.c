/*
 * test_app_plaus.c - the current-sensor plausibility block (firmware/app/app_plaus.h) against a
 * double-precision evaluation of the same criterion, on synthetic sample sequences:
 *  - a healthy channel whose measured change is the predicted one times k, k from 0.6 to 1.6 (an
 *    inductance error of -40 .. +60 %), with noise: never trips;
 *  - a stuck channel (measured change 0, or noise only) whose predicted change is large: trips at
 *    the first full window, and names that channel, for every phase and every start in the window;
 *  - an idle drive (predicted change below the floor): never trips, whatever the measurement;
 *  - a law without a prediction (NULL): never trips, and the window restarts;
 *  - a channel that is not measured (derived): never named.
 * The fixed-point test of the regression slope, 4 cov(dm, dp) < var(dp), is compared with the
 * double one on every window, so the rounding to IQ16 never changes a decision away from the
 * threshold; a constant bias on the prediction (a model error) changes nothing.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdlib.h>

#include <cmocka.h>

#include "fixtest.h"

#include "app_plaus.h"

#define PU(x) ((iq_t)((x) * 16777216.0))
#define WIN (1U << APP_PLAUS_WIN_LOG2)

/* 4.9 mA per count on a 6 A base: 1/1224 pu per count */
static const double kGainPu = 1.0 / 1224.0;

static uint32_t rng = 12345U;
static double noise(double amp)
{
    rng = rng * 1664525U + 1013904223U;
    return amp * (((double)(rng >> 8) / 16777216.0) * 2.0 - 1.0);
}

/* A predicted change pattern of a switching drive: +-d alternating with a smaller return. */
static double dpred(uint32_t k, uint16_t ph, double d)
{
    static const double shape[6] = {1.0, -0.6, 0.8, -1.0, 0.5, -0.7};
    return d * shape[(k + 2U * ph) % 6U];
}

typedef struct {
    app_plaus_params_t p;
    app_plaus_t s;
    double i[3];
    double sum_mp[3], sum_pp[3];
    uint32_t n;
} rig_t;

static void rig_init(rig_t *r)
{
    app_plaus_init(&r->p, PU(kGainPu), APP_PLAUS_WIN_LOG2, APP_PLAUS_BIAS_LOG2);
    app_plaus_reset(&r->s);
    for (int k = 0; k < 3; k++) {
        r->i[k] = 0.3 * (k - 1);
        r->sum_mp[k] = r->sum_pp[k] = 0.0;
    }
    r->n = 0U;
}

/* One period: the law predicts i + dp for each phase; the sensors report i + k_x dp (+ noise)
 * next time. Returns the block's decision and checks it against the double criterion. */
static uint16_t rig_step(rig_t *r, uint32_t t, const double k[3], double d, double noise_pu, uint16_t measured,
                        int with_pred)
{
    iq_t iq[3], i1q[3];
    double dp[3];
    for (int x = 0; x < 3; x++) {
        iq[x] = PU(r->i[x]);
        dp[x] = dpred(t, (uint16_t)x, d);
        i1q[x] = PU(r->i[x] + dp[x]);
    }
    const uint16_t bad = app_plaus_step(&r->s, &r->p, iq, with_pred ? i1q : NULL, measured, 0U);
    /* the next sample */
    for (int x = 0; x < 3; x++) {
        r->i[x] += k[x] * dp[x] + noise(noise_pu);
    }
    return bad;
}

static void test_healthy_channels_never_trip(void **state)
{
    (void)state;
    for (double k = 0.6; k <= 1.61; k += 0.1) {
        rig_t r;
        const double kk[3] = {k, k, k};
        rig_init(&r);
        for (uint32_t t = 0; t < 2000U; t++) {
            /* 0.05 pu per period, noise 2 counts */
            assert_int_equal(rig_step(&r, t, kk, 0.05, 2.0 * kGainPu, 3U, 1), 0);
        }
    }
}

/* A model error that biases every predicted change (the back-EMF off by some per cent) leaves a
 * healthy channel healthy: the means are taken out of the slope. */
static void test_a_biased_prediction_is_not_a_fault(void **state)
{
    (void)state;
    for (double bias = -0.03; bias <= 0.031; bias += 0.01) {
        app_plaus_params_t p;
        app_plaus_t s;
        double i = 0.2;
        app_plaus_init(&p, PU(kGainPu), APP_PLAUS_WIN_LOG2, APP_PLAUS_BIAS_LOG2);
        app_plaus_reset(&s);
        for (uint32_t t = 0; t < 2000U; t++) {
            const double d = dpred(t, 0U, 0.02); /* the true change, small */
            iq_t iq[3] = {PU(i), 0, 0}, i1q[3] = {PU(i + d + bias), 0, 0};
            assert_int_equal(app_plaus_step(&s, &p, iq, i1q, 1U, 0U), 0U);
            i += d;
        }
    }
}

static void test_a_stuck_channel_trips_within_two_windows(void **state)
{
    (void)state;
    for (uint16_t ph = 0; ph < 2; ph++) {
        for (uint32_t start = 0; start < WIN; start++) {
            rig_t r;
            double kk[3] = {1.0, 1.0, 1.0};
            uint32_t t, tripped = 0U;
            uint16_t bad = 0U;
            rig_init(&r);
            for (t = 0; t < 64U + start; t++) {
                assert_int_equal(rig_step(&r, t, kk, 0.05, 1.0 * kGainPu, 3U, 1), 0);
            }
            kk[ph] = 0.0; /* stuck from now on (noise only) */
            for (; t < 64U + start + 4U * WIN && bad == 0U; t++) {
                bad = rig_step(&r, t, kk, 0.05, 1.0 * kGainPu, 3U, 1);
                tripped = t - (64U + start);
            }
            assert_int_equal(bad, 1U << ph);
            /* the first window that holds only stuck samples ends at most 2 windows later */
            assert_true(tripped <= 2U * WIN);
        }
    }
}

/* A sensor that lost most of its gain (it follows 15 % of each change: below the 1/4 of the
 * checks, above the 1/16 of "stood still") fails every window, but is reported only at the end of
 * the second failed window in a row; one that stands still is reported on the first. */
static void test_a_failure_that_moves_waits_one_window(void **state)
{
    (void)state;
    for (int still = 0; still < 2; still++) {
        rig_t r;
        double kk[3] = {1.0, 1.0, 1.0};
        uint32_t t, first = 0U;
        uint16_t bad = 0U;
        rig_init(&r);
        for (t = 0; t < 8U * WIN; t++) {
            assert_int_equal(rig_step(&r, t, kk, 0.05, 0.0, 3U, 1), 0);
        }
        kk[0] = still != 0 ? 0.0 : 0.15; /* from a window's start */
        for (; t < 12U * WIN && bad == 0U; t++) {
            bad = rig_step(&r, t, kk, 0.05, 0.0, 3U, 1);
            first = t - 8U * WIN;
        }
        assert_int_equal(bad, 1U);
        /* the first window holds the change's first sample: it ends after WIN samples */
        assert_int_equal(first + 1U, (still != 0 ? 1U : 2U) * WIN + 1U);
    }
}

/* A window that ends in a held period (app_plaus_step's hold: the application's speed-loop slots
 * 0 and 1) is judged at the start of the first later call out of the held periods, at the latest
 * of the second later call: the same decisions as a block that judges at once, each one or two
 * periods later where the window ended in a held period, with the hold of a speed loop every 10
 * periods (slots 0 and 1), every 3, and every period; a channel stuck from period 200 on is
 * reported by both. */
static void test_a_held_window_is_judged_one_or_two_periods_later(void **state)
{
    const uint16_t divs[3] = {10U, 3U, 1U};
    (void)state;
    for (uint16_t d = 0U; d < 3U; d++) {
        app_plaus_params_t p;
        app_plaus_t a, b;
        double i[3] = {-0.3, 0.0, 0.3};
        uint16_t owed[3] = {0U, 0U, 0U}; /* owed[j]: what b must return j calls from now */
        uint16_t n_bad = 0U, n_late = 0U;
        app_plaus_init(&p, PU(kGainPu), APP_PLAUS_WIN_LOG2, APP_PLAUS_BIAS_LOG2);
        app_plaus_reset(&a);
        app_plaus_reset(&b);
        for (uint32_t t = 0; t < 400U; t++) {
            const uint16_t hold = (uint16_t)(t % divs[d] < 2U ? 1U : 0U);
            const uint16_t hold_next = (uint16_t)((t + 1U) % divs[d] < 2U ? 1U : 0U);
            iq_t iq[3], i1q[3];
            double dp[3];
            uint16_t ra, rb;
            for (int x = 0; x < 3; x++) {
                iq[x] = PU(i[x]);
                dp[x] = dpred(t, (uint16_t)x, 0.05);
                i1q[x] = PU(i[x] + dp[x]);
            }
            ra = app_plaus_step(&a, &p, iq, i1q, 3U, 0U);
            rb = app_plaus_step(&b, &p, iq, i1q, 3U, hold);
            if ((a.judged & APP_PLAUS_JUDGED_NOW) != 0U) {
                /* a's window ended now: b judges it now, at the next call out of the hold, or at
                 * the second call from now */
                const uint16_t j = hold == 0U ? 0U : hold_next == 0U ? 1U : 2U;
                owed[j] = (uint16_t)(owed[j] | ra);
                assert_int_equal(b.n, 0U);
                assert_int_equal(b.due, hold != 0U ? 1U : 0U);
                assert_int_equal(b.judged & APP_PLAUS_JUDGED_NOW, hold == 0U ? APP_PLAUS_JUDGED_NOW : 0U);
                n_late = (uint16_t)(n_late + (j != 0U && ra != 0U ? 1U : 0U));
            }
            assert_int_equal(rb, owed[0]);
            owed[0] = owed[1];
            owed[1] = owed[2];
            owed[2] = 0U;
            n_bad = (uint16_t)(n_bad + (ra != 0U ? 1U : 0U));
            for (int x = 0; x < 3; x++) {
                i[x] += (t >= 200U && x == 0 ? 0.0 : 1.0) * dp[x]; /* phase A stuck from 200 on */
            }
        }
        assert_true(n_bad > 0U);
        if (d == 2U) {
            assert_true(n_late > 0U); /* held every period: every report comes two calls late */
        }
    }
}

static void test_idle_drive_never_trips(void **state)
{
    rig_t r;
    const double kk[3] = {0.0, 0.0, 0.0};
    (void)state;
    rig_init(&r);
    /* the prediction moves 2 counts per period: below the floor of APP_PLAUS_FLOOR_COUNTS */
    for (uint32_t t = 0; t < 1000U; t++) {
        assert_int_equal(rig_step(&r, t, kk, 2.0 * kGainPu, 0.0, 7U, 1), 0);
    }
}

static void test_no_prediction_rests(void **state)
{
    rig_t r;
    const double kk[3] = {0.0, 0.0, 0.0};
    (void)state;
    rig_init(&r);
    for (uint32_t t = 0; t < 1000U; t++) {
        assert_int_equal(rig_step(&r, t, kk, 0.05, 0.0, 7U, 0), 0);
    }
    assert_int_equal(r.s.primed, 0U);
}

static void test_derived_channel_is_never_named(void **state)
{
    rig_t r;
    const double kk[3] = {1.0, 1.0, 0.0}; /* phase C "stuck", but it is the derived one */
    (void)state;
    rig_init(&r);
    for (uint32_t t = 0; t < 1000U; t++) {
        assert_int_equal(rig_step(&r, t, kk, 0.05, 0.0, 3U, 1), 0);
    }
}

/* The fixed-point decision equals the double one on random windows away from the threshold. */
static void test_decision_matches_double_reference(void **state)
{
    (void)state;
    for (int trial = 0; trial < 2000; trial++) {
        app_plaus_params_t p;
        app_plaus_t s;
        double sm = 0.0, sp = 0.0, smp = 0.0, spp = 0.0, i = noise(1.0), i1, b_learnt = 0.0;
        const double k = noise(1.5) + 0.5; /* -1 .. 2 */
        const double bias = (trial % 3) == 0 ? noise(0.1) : 0.0; /* a model error on some trials */
        uint16_t bad = 0U;
        app_plaus_init(&p, PU(kGainPu), APP_PLAUS_WIN_LOG2, APP_PLAUS_BIAS_LOG2);
        app_plaus_reset(&s);
        for (uint32_t t = 0; t <= WIN; t++) {
            const double dp = noise(0.1) + bias;
            iq_t iq[3] = {PU(i), 0, 0}, i1q[3] = {0, 0, 0};
            i1 = i + dp;
            i1q[0] = PU(i1);
            bad = app_plaus_step(&s, &p, iq, i1q, 1U, 0U);
            if (t < WIN) {
                const double inext = i + k * (dp - bias);
                /* what the block will see: the rounded samples */
                const double dm_q = (double)(PU(inext) - PU(i)) / 16777216.0;
                const double dp_q = (double)(PU(i1) - PU(i)) / 16777216.0;
                /* the block takes out the bias it has learnt (app_plaus.h), then learns */
                const double dp_c = dp_q - b_learnt;
                b_learnt += ((dp_q - dm_q) - b_learnt) / (double)(1U << APP_PLAUS_BIAS_LOG2);
                sm += dm_q;
                sp += dp_c;
                smp += dm_q * dp_c;
                spp += dp_c * dp_c;
                i = inext;
            }
        }
        {
            /* suspect: the ratio against 1/4 over a large enough prediction; follows: the
             * regression slope cov / var against 1/4 over a varying one (N^2 scaled) */
            const double cov = WIN * smp - sm * sp, var = WIN * spp - sp * sp;
            const double f2 = (APP_PLAUS_FLOOR_COUNTS * kGainPu) * (APP_PLAUS_FLOOR_COUNTS * kGainPu);
            const double floor_raw = WIN * f2, floor_var = (double)WIN * WIN * f2;
            if (fabs(4.0 * cov - var) > 1e-3 * var && fabs(var - floor_var) > 1e-3 * floor_var &&
                fabs(4.0 * smp - spp) > 1e-3 * spp && fabs(spp - floor_raw) > 1e-3 * floor_raw &&
                fabs(16.0 * fabs(smp) - spp) > 1e-3 * spp) {
                const int suspect = spp > floor_raw && 4.0 * smp < spp;
                const int follows = var > floor_var && 4.0 * cov >= var;
                /* the first failed window is reported at once only when the channel stood still
                 * (|smp| < spp / 16); otherwise a second one in a row is needed (app_plaus.h) */
                const int still = 16.0 * fabs(smp) < spp;
                assert_int_equal(bad, (suspect && !follows && still) ? 1U : 0U);
            }
        }
    }
}

UNIT_TEST_MAIN("app plaus", NULL,
               cmocka_unit_test(test_healthy_channels_never_trip),
               cmocka_unit_test(test_a_biased_prediction_is_not_a_fault),
               cmocka_unit_test(test_a_stuck_channel_trips_within_two_windows),
               cmocka_unit_test(test_a_failure_that_moves_waits_one_window),
               cmocka_unit_test(test_a_held_window_is_judged_one_or_two_periods_later),
               cmocka_unit_test(test_idle_drive_never_trips),
               cmocka_unit_test(test_no_prediction_rests),
               cmocka_unit_test(test_derived_channel_is_never_named),
               cmocka_unit_test(test_decision_matches_double_reference))
