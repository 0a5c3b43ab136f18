/*
 * test_dsc.c - Direct Self Control comparators (Casadei section 9): the flux components against
 * double precision, and a kinematic check of the derived leg-to-axis assignment: with the stator
 * flux moved by the selected voltage vectors (d psi/dt = v, the R_s-free DSC picture) it must run
 * along the hexagon of side distance phi*, in the commanded sense, with one leg commutating at each
 * of the six vertices per turn.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <cmocka.h>

#include "dsc.h"
#include "fixtest.h"
#include "swtab.h"

#define IQ_LSB (1.0 / (double)(1L << FIX_IQ_Q))
#define DEG (FIXTEST_PI / 180.0)

static void test_components(void **state)
{
    (void)state;
    const double ccw_axes[3] = {30.0, 150.0, 270.0}, cw_axes[3] = {330.0, 90.0, 210.0};
    fixtest_rng_t rng;
    fixtest_rng_seed(&rng, 9U);
    double worst = 0.0;
    for (int n = 0; n < 100000; ++n) {
        const double pa = 4.0 * (fixtest_rng_unit(&rng) - 0.5), pb = 4.0 * (fixtest_rng_unit(&rng) - 0.5);
        for (uint16_t ccw = 0U; ccw < 2U; ++ccw) {
            iq_t c[3];
            dsc_components(fixtest_d_to_iq(pa), fixtest_d_to_iq(pb), ccw, c);
            for (int x = 0; x < 3; ++x) {
                const double ax = (ccw ? ccw_axes[x] : cw_axes[x]) * DEG;
                const double ref = fixtest_iq_to_d(fixtest_d_to_iq(pa)) * cos(ax) +
                                   fixtest_iq_to_d(fixtest_d_to_iq(pb)) * sin(ax);
                const double e = fabs(fixtest_iq_to_d(c[x]) - ref) / IQ_LSB;
                worst = e > worst ? e : worst;
            }
        }
    }
    printf("MEASURE dsc components: worst %.3f LSB\n", worst);
    assert_true(worst <= 0.51);
}

/* Runs DSC on the kinematic flux model for `turns` turns from a flux inside the hexagon. */
static void hexagon(uint16_t ccw)
{
    const double ref = 0.8, dt = 0.002, step = 2.0 / 3.0 * dt; /* |V| = 2/3 pu (Casadei eq. 2) */
    double pa = 0.5, pb = 0.1, turned = 0.0, prev = atan2(pb, pa);
    dsc_t s;
    dsc_reset(&s, ccw, fixtest_d_to_iq(pa), fixtest_d_to_iq(pb));
    uint16_t legs_prev = (uint16_t)(4U * s.s[0] + 2U * s.s[1] + s.s[2]);
    int commutations = 0, counted_turn = 0, events_in_turn[8] = {0};
    double worst_vertex = 0.0, worst_angle = 0.0;
    for (long k = 0; k < 2000000L && turned < 8.0 * 2.0 * FIXTEST_PI; ++k) {
        const uint16_t v = dsc_step(&s, fixtest_d_to_iq(pa), fixtest_d_to_iq(pb), fixtest_d_to_iq(ref));
        const uint16_t legs = (uint16_t)(4U * s.s[0] + 2U * s.s[1] + s.s[2]);
        if (legs != legs_prev) {
            const uint16_t diff = (uint16_t)(legs ^ legs_prev);
            assert_true(diff == 1U || diff == 2U || diff == 4U); /* one leg at a time */
            ++commutations;
            if (turned > 2.0 * FIXTEST_PI) { /* after the first turn: on the hexagon */
                const double r = hypot(pa, pb), ang = atan2(pb, pa) / DEG;
                const double e_r = fabs(r - ref / cos(30.0 * DEG)), e_a = fabs(remainder(ang, 60.0));
                worst_vertex = e_r > worst_vertex ? e_r : worst_vertex;
                worst_angle = e_a > worst_angle ? e_a : worst_angle;
                ++events_in_turn[counted_turn < 7 ? counted_turn : 7];
            }
        }
        legs_prev = legs;
        assert_true(v >= 1U && v <= 6U);
        const swtab_legs_t l = swtab_sstp_legs(v);
        /* Casadei eq. 2: V = 2/3 (S_A + S_B a + S_C a^2). */
        pa += dt * (2.0 * l.sa - l.sb - l.sc) / 3.0;
        pb += dt * ((double)l.sb - (double)l.sc) / sqrt(3.0);
        const double now = atan2(pb, pa);
        turned += (ccw ? 1.0 : -1.0) * remainder(now - prev, 2.0 * FIXTEST_PI);
        prev = now;
        if (turned > 2.0 * FIXTEST_PI * (counted_turn + 2)) {
            ++counted_turn;
        }
    }
    printf("MEASURE dsc %s: %d commutations in 8 turns; vertices within %.4f pu of phi*/cos30 and %.3f deg of 60k\n",
           ccw ? "ccw" : "cw", commutations, worst_vertex, worst_angle);
    assert_true(turned >= 8.0 * 2.0 * FIXTEST_PI); /* it turned the commanded way */
    for (int t = 0; t < 6; ++t) {
        assert_int_equal(events_in_turn[t], 6);
    }
    assert_true(worst_vertex < 3.0 * step);
    assert_true(worst_angle < 0.5);
}

/* Reset anywhere on the circle (the start-up leaves the flux on a circle of radius phi*): the
 * states must be the hexagon's at that angle, so the vector turns the flux forward. Counter-
 * clockwise the side between the vertices at (j-1) 60 and j 60 degrees is run by V_{j+2}, which
 * lies 60..120 degrees ahead of the flux; clockwise 60..120 degrees behind. */
static void test_reset_on_the_hexagon(void **state)
{
    (void)state;
    const double ref = 0.8;
    int checked = 0;
    for (uint16_t ccw = 0U; ccw < 2U; ++ccw) {
        for (double deg = 0.5; deg < 360.0; deg += 1.0) {
            dsc_t s;
            const iq_t pa = fixtest_d_to_iq(ref * cos(deg * DEG)), pb = fixtest_d_to_iq(ref * sin(deg * DEG));
            dsc_reset(&s, ccw, pa, pb);
            /* a reference beyond every component: no comparator fires, the vector is the states' */
            const uint16_t v = dsc_step(&s, pa, pb, fixtest_d_to_iq(2.0 * ref));
            assert_true(v >= 1U && v <= 6U);
            const double ahead = remainder(60.0 * (double)(v - 1U) - deg, 360.0) * (ccw ? 1.0 : -1.0);
            if (ahead < 60.0 || ahead > 120.0) {
                printf("reset %s at %.1f deg: V%u is %.1f deg ahead\n", ccw ? "ccw" : "cw", deg, (unsigned)v, ahead);
            }
            assert_true(ahead >= 60.0 && ahead <= 120.0);
            ++checked;
        }
    }
    assert_int_equal(checked, 720);
}

static void test_hexagon_ccw(void **state)
{
    (void)state;
    hexagon(1U);
}

static void test_hexagon_cw(void **state)
{
    (void)state;
    hexagon(0U);
}

UNIT_TEST_MAIN("dsc", NULL,
               cmocka_unit_test(test_components),
               cmocka_unit_test(test_hexagon_ccw),
               cmocka_unit_test(test_hexagon_cw),
               cmocka_unit_test(test_reset_on_the_hexagon))
