/*
 * test_dsvm.c - the DSVM switching tables (firmware/dtc/dsvm.h) recomputed entry by entry from the
 * criterion of docs/firmware-core.md ("DSVM"), in double precision, independently of the firmware:
 *   - vectors: the null and (a V_k + b V_k+1)/3, 1 <= a, 0 <= b, a + b <= 3, |V_k| = 1 at
 *     (k-1) 60 deg (37 points);
 *   - Casadei eq. 15 with phi_r taken along phi_s (load angle neglected) and the flux along
 *     u = (cos th, sin th): torque change ~ v . j u - e, e = w phi_s / |V_k| (Casadei eq. 14's term does
 *     not depend on v and drops out of the ranking); flux-magnitude change ~ v . u (Casadei eq. 10 without
 *     the resistive term);
 *   - a cell: the half-open sector interval of th (60 deg, or the 30-deg half sectors 1-, 1+ at
 *     high speed) and the EMF range (low |e| < E1; medium E1..E2; high E2..sqrt3/2, each sense);
 *   - admissible for a flux demand: v . u >= 0 (up) or <= 0 (down) for every th of the cell
 *     (sampled every 0.25 deg, ends included; the null is admissible for both);
 *   - the torque effect d = v . j u_c - e_c at the cell's centre (th_c, e_c); level +2: the
 *     largest d; +1: the smallest d > 0; 0: the smallest |d|; -1: the largest d < 0; -2: the
 *     smallest d (+-1 fall back to +-2 when no admissible vector has that sign); ties (1e-9) to
 *     the shorter vector (less voltage, less current ripple for the same torque effect), then
 *     the lower code.
 * Then the vector codes (sub-interval vectors and their mean), the rotation to sectors 2..6, the
 * half sector, the speed range, the five-level comparator and the PWM form of all 8 leg patterns
 * against hal.h's rule.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "fixtest.h"

#include <math.h>
#include <stdio.h>

#include "dsvm.h"
#include "hyst.h"
#include "swtab.h"

#define PI 3.14159265358979323846

static const int kVec[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                               {0, 1, 1}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}};

/* The nominal vector of a code, |V_k| = 1. */
static void ref_vec(int c, double *x, double *y)
{
    static const int ab[6][2] = {{1, 0}, {1, 1}, {1, 2}, {2, 0}, {2, 1}, {3, 0}};
    int k, i;
    double a0, a1;
    if (c == 0) {
        *x = *y = 0.0;
        return;
    }
    k = (c - 1) / 6;
    i = (c - 1) % 6;
    a0 = k * PI / 3.0;
    a1 = (k + 1) * PI / 3.0;
    *x = (ab[i][0] * cos(a0) + ab[i][1] * cos(a1)) / 3.0;
    *y = (ab[i][0] * sin(a0) + ab[i][1] * sin(a1)) / 3.0;
}

/* The criterion (file comment): the code for range r, flux demand f, level t. */
static int ref_table(int r, int f, int t)
{
    const double e1 = DSVM_E1, e2 = DSVM_E2, e3 = sqrt(3.0) / 2.0;
    const double th[7][2] = {{-30, 30}, {-30, 30}, {-30, 30}, {-30, 0}, {0, 30}, {-30, 0}, {0, 30}};
    const double el[7][2] = {{-e1, e1}, {e1, e2}, {-e2, -e1}, {e2, e3}, {e2, e3}, {-e3, -e2}, {-e3, -e2}};
    const double tc = 0.5 * (th[r][0] + th[r][1]) * PI / 180.0, ec = 0.5 * (el[r][0] + el[r][1]);
    int pass, best = -1;
    double bs = 0.0, bm = 0.0;
    for (pass = 0; pass < 2 && best < 0; pass++) {
        const int tt = pass == 0 ? t : (t > 0 ? 2 : (t < 0 ? -2 : 0));
        int c;
        for (c = 0; c < 37; c++) {
            double x, y, d, s, mag;
            int i, ok = 1;
            ref_vec(c, &x, &y);
            for (i = 0; i <= 120; i++) {
                const double a = (th[r][0] + (th[r][1] - th[r][0]) * i / 120.0) * PI / 180.0;
                const double df = x * cos(a) + y * sin(a);
                if (f ? df < -1e-9 : df > 1e-9) {
                    ok = 0;
                }
            }
            if (!ok) {
                continue;
            }
            d = -x * sin(tc) + y * cos(tc) - ec;
            mag = sqrt(x * x + y * y);
            if (tt == 2) {
                s = d;
            } else if (tt == -2) {
                s = -d;
            } else if (tt == 0) {
                s = -fabs(d);
            } else if (tt == 1) {
                if (!(d > 1e-9)) continue;
                s = -d;
            } else {
                if (!(d < -1e-9)) continue;
                s = d;
            }
            if (best < 0 || s > bs + 1e-9 || (s > bs - 1e-9 && mag < bm - 1e-9)) {
                best = c;
                bs = s;
                bm = mag;
            }
        }
    }
    return best;
}

static void every_entry_follows_the_criterion(void **state)
{
    int r, f, t, n = 0, used[37] = {0}, nused = 0, i;
    (void)state;
    for (r = 0; r < 7; r++) {
        for (f = 0; f < 2; f++) {
            for (t = -2; t <= 2; t++) {
                const int want = ref_table(r, f, t);
                const int got = (int)dsvm_table((uint16_t)r, (uint16_t)f, (int16_t)t);
                if (want != got) {
                    fprintf(stderr, "range %d flux_up %d level %d: criterion %d, firmware %d\n", r, f, t, want, got);
                }
                assert_int_equal(got, want);
                used[got] = 1;
                n++;
            }
        }
    }
    for (i = 0; i < 37; i++) {
        nused += used[i];
    }
    assert_int_equal(n, 70);
    fprintf(stderr, "70 entries, %d distinct vectors of the 37 in sector 1's tables\n", nused);
}

/* The paper's high-speed example (sec. 11): ccw, torque increase: flux down -> "333" in 1+ and
 * "332" in 1-; flux up -> "223" / "222" (whatever the half, these two). */
static void the_papers_high_speed_example(void **state)
{
    (void)state;
    assert_int_equal(dsvm_table(DSVM_HIGH_CCW_P, 0U, 2), 18); /* V3 V3 V3 */
    assert_int_equal(dsvm_table(DSVM_HIGH_CCW_M, 0U, 2), 9);  /* V3 V3 V2 */
    assert_int_equal(dsvm_table(DSVM_HIGH_CCW_P, 1U, 2), 11); /* V2 V2 V3 */
    assert_int_equal(dsvm_table(DSVM_HIGH_CCW_M, 1U, 2), 12); /* V2 V2 V2 */
}

static void codes_are_the_ring_and_the_null(void **state)
{
    uint16_t c, s;
    (void)state;
    for (c = 0; c < 74; c++) {
        uint16_t v[3];
        double x = 0.0, y = 0.0, rx, ry;
        int n, changes = 0;
        const uint16_t code = (uint16_t)(c % 37), nv = c < 37 ? 7U : 0U;
        dsvm_vectors(code, nv, v);
        for (n = 0; n < 3; n++) {
            const int *l = kVec[v[n]];
            /* Casadei eq. 2 over 2/3 V_dc: alpha = (2 a - b - c)/2, beta = (b - c) sqrt3/2 */
            x += (2.0 * l[0] - l[1] - l[2]) / 2.0 / 3.0;
            y += (l[1] - l[2]) * sqrt(3.0) / 2.0 / 3.0;
        }
        ref_vec(code, &rx, &ry);
        assert_true(fabs(x - rx) < 1e-12 && fabs(y - ry) < 1e-12);
        /* inside the period, one commutation at a time: every leg's states change at most once
         * (the order of dsvm_vectors) */
        for (n = 0; n < 3; n++) {
            changes = (kVec[v[0]][n] != kVec[v[1]][n]) + (kVec[v[1]][n] != kVec[v[2]][n]);
            assert_true(changes <= 1);
        }
        for (s = 1; s <= 6; s++) {
            const uint16_t cr = dsvm_rotate(code, s);
            double x2, y2;
            const double a = (s - 1) * PI / 3.0;
            ref_vec(cr, &x2, &y2);
            assert_true(fabs(x2 - (rx * cos(a) - ry * sin(a))) < 1e-12);
            assert_true(fabs(y2 - (rx * sin(a) + ry * cos(a))) < 1e-12);
        }
    }
}

static void half_sector_and_range(void **state)
{
    int deg;
    (void)state;
    for (deg = -29; deg < 330; deg += 2) {
        const double a = deg * PI / 180.0;
        const iq_t pa = (iq_t)lround(0.9 * cos(a) * 16777216.0), pb = (iq_t)lround(0.9 * sin(a) * 16777216.0);
        const uint16_t k = fix_sector6(pa, pb);
        const double rel = deg - (k - 1) * 60.0;
        assert_int_equal(dsvm_half(k, pa, pb), rel >= 0.0 ? 1 : 0);
    }
    /* vdc = 1.5 pu: |V_k| = 1 pu; psi* = 1 pu, so e = w */
    {
        const iq_t vdc = (iq_t)(1.5 * 16777216.0), one = (iq_t)16777216;
        assert_int_equal(dsvm_range((iq_t)(0.19 * 16777216.0), one, vdc, 0U), DSVM_LOW);
        assert_int_equal(dsvm_range((iq_t)(-0.19 * 16777216.0), one, vdc, 1U), DSVM_LOW);
        assert_int_equal(dsvm_range((iq_t)(0.21 * 16777216.0), one, vdc, 1U), DSVM_MED_CCW);
        assert_int_equal(dsvm_range((iq_t)(-0.49 * 16777216.0), one, vdc, 1U), DSVM_MED_CW);
        assert_int_equal(dsvm_range((iq_t)(0.51 * 16777216.0), one, vdc, 0U), DSVM_HIGH_CCW_M);
        assert_int_equal(dsvm_range((iq_t)(0.51 * 16777216.0), one, vdc, 1U), DSVM_HIGH_CCW_P);
        assert_int_equal(dsvm_range((iq_t)(-0.51 * 16777216.0), one, vdc, 0U), DSVM_HIGH_CW_M);
        assert_int_equal(dsvm_range((iq_t)(-0.51 * 16777216.0), one, vdc, 1U), DSVM_HIGH_CW_P);
    }
}

static void five_level_comparator(void **state)
{
    hyst5_t h;
    (void)state;
    hyst5_init(&h, 100, 300); /* h1 = 50, h2 = 150 LSB */
    assert_int_equal(hyst5_step(&h, 151), 2);
    assert_int_equal(hyst5_step(&h, 100), 1);
    assert_int_equal(hyst5_step(&h, 10), 1);
    assert_int_equal(hyst5_step(&h, -1), 0);
    assert_int_equal(hyst5_step(&h, -51), -1);
    assert_int_equal(hyst5_step(&h, -151), -2);
    assert_int_equal(hyst5_step(&h, -20), -1);
    assert_int_equal(hyst5_step(&h, 1), 0);
    assert_int_equal(hyst5_step(&h, 50), 0);
}

/* hal.h: timer 1 counts 0 -> T1PR (first half) -> 0; the output is active while T1CNT >= the
 * compare value in force (cmpr_up rising, cmpr_dn falling); act 0: active = upper on. The upper
 * state at the centre of each third must be the pattern's bit. */
static void all_eight_patterns_in_the_pwm_form(void **state)
{
    static const uint16_t periods[] = {3U, 4U, 5U, 100U, 1499U, 3000U, 3001U, 65534U};
    size_t n;
    (void)state;
    for (n = 0; n < sizeof periods / sizeof periods[0]; n++) {
        const uint16_t t1pr = periods[n];
        const uint16_t c23 = dsvm_c23(t1pr);
        uint16_t pat;
        assert_int_equal(c23, (uint16_t)floor(2.0 * t1pr / 3.0 + 0.5));
        for (pat = 0; pat < 8; pat++) {
            uint16_t up, dn, act;
            int third;
            dsvm_pwm(pat, t1pr, c23, &up, &dn, &act);
            for (third = 0; third < 3; third++) {
                const double t = (third + 0.5) / 3.0; /* fraction of the period */
                const double cnt = t < 0.5 ? 2.0 * t * t1pr : 2.0 * (1.0 - t) * t1pr;
                const int active = cnt >= (t < 0.5 ? up : dn);
                const int upper = act == 0U ? active : !active;
                assert_int_equal(upper, (pat >> (2 - third)) & 1);
            }
        }
    }
    {
        uint32_t t;
        for (t = 1U; t < 65535U; t++) {
            assert_int_equal(dsvm_c23((uint16_t)t), (uint16_t)((2U * t + 1U) / 3U));
        }
    }
}

static void patterns_of_a_code(void **state)
{
    uint16_t v[3], pat[3], c, nv, prev, p;
    (void)state;
    /* the control path's look-ups against the definitions */
    for (nv = 0U; nv <= 7U; nv = (uint16_t)(nv + 7U)) {
        for (c = 0U; c < DSVM_NCODE; c++) {
            uint16_t q[3];
            dsvm_vectors(c, nv, v);
            dsvm_patterns(v, pat);
            dsvm_code_patterns(c, nv, q);
            assert_int_equal(q[0], pat[0]);
            assert_int_equal(q[1], pat[1]);
            assert_int_equal(q[2], pat[2]);
        }
    }
    for (prev = 0U; prev < 2U; prev++) {
        for (p = 0U; p < 8U; p++) {
            const uint16_t e = dsvm_edges(prev, p);
            int s0 = prev, on = 0, r = 0, f = 0, n;
            for (n = 0; n < 3; n++) {
                const int s = (p >> (2 - n)) & 1;
                on += s;
                r += s > s0;
                f += s < s0;
                s0 = s;
            }
            assert_int_equal(e & 3U, on);
            assert_int_equal((e >> 2) & 3U, r);
            assert_int_equal((e >> 4) & 3U, f);
        }
    }
    dsvm_vectors(9U, 0U, v); /* "332": V3 V3 V2 = 010 010 110 */
    dsvm_patterns(v, pat);
    assert_int_equal(pat[0], 1); /* leg A 0 0 1 */
    assert_int_equal(pat[1], 7);
    assert_int_equal(pat[2], 0);
}

UNIT_TEST_MAIN("dsvm", NULL,
               cmocka_unit_test(every_entry_follows_the_criterion),
               cmocka_unit_test(the_papers_high_speed_example),
               cmocka_unit_test(codes_are_the_ring_and_the_null),
               cmocka_unit_test(half_sector_and_range),
               cmocka_unit_test(five_level_comparator),
               cmocka_unit_test(all_eight_patterns_in_the_pwm_form),
               cmocka_unit_test(patterns_of_a_code))
