/*
 * test_svm.c - fixed-point space-vector modulation (firmware/dtc/svm.h) against a double-precision
 * reference written the textbook way, independently of the carrier-based form the firmware uses:
 * the sector k = floor(angle / 60 deg) between the active vectors V_k and V_k+1 (V1 = 100 at 0 deg,
 * V2 = 110, ..., V6 = 101, length 2/3 V_dc, Casadei eq. 2), the dwell times of the volt-second
 * balance v Ts = t1 V_k + t2 V_k+1 (t1 = sqrt3 |v|/V_dc sin(60 deg - a), t2 = sqrt3 |v|/V_dc
 * sin(a), a the angle inside the sector), the null time t0 = 1 - t1 - t2 split equally between
 * V0 and V7 (seven-segment) or given wholly to the null vector that clamps the phase of the
 * largest |voltage| (two-phase), and a leg's duty the sum of the times of the vectors that turn
 * its upper device on. Overmodulation: t1, t2 scaled by 1/(t1 + t2) (hexagon, angle kept).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>

#include "fixtest.h"
#include "svm.h"

#define PI 3.14159265358979323846
#define LSB (1.0 / 16777216.0)

/* Upper-device states of V0..V7 for legs A, B, C (V1 = 100, V2 = 110, V3 = 010, V4 = 011,
 * V5 = 001, V6 = 101, V7 = 111). */
static const int kVec[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                               {0, 1, 1}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}};

/* The textbook reference: duties of legs A, B, C for (va, vb) on the link vdc. */
static int ref_svm(double va, double vb, double vdc, int two_phase, double d[3])
{
    const double mag = sqrt(va * va + vb * vb);
    double ang = atan2(vb, va);
    int k, om = 0;
    double a, t1, t2, t0, t7;
    if (ang < 0.0) {
        ang += 2.0 * PI;
    }
    k = (int)floor(ang / (PI / 3.0));
    if (k > 5) {
        k = 5;
    }
    a = ang - k * (PI / 3.0);
    t1 = sqrt(3.0) * mag / vdc * sin(PI / 3.0 - a);
    t2 = sqrt(3.0) * mag / vdc * sin(a);
    if (t1 + t2 > 1.0) {
        const double s = t1 + t2;
        t1 /= s;
        t2 /= s;
        om = 1;
    }
    t0 = 1.0 - t1 - t2;
    if (om) {
        t7 = 0.0;
    } else if (!two_phase) {
        t7 = t0 / 2.0;
    } else {
        /* the phase of the largest |voltage| is clamped: to the top rail (V7) when it is positive */
        const double ph[3] = {va, -0.5 * va + sqrt(3.0) / 2.0 * vb, -0.5 * va - sqrt(3.0) / 2.0 * vb};
        int big = 0;
        for (int x = 1; x < 3; x++) {
            if (fabs(ph[x]) > fabs(ph[big])) {
                big = x;
            }
        }
        t7 = ph[big] >= 0.0 ? t0 : 0.0;
    }
    for (int x = 0; x < 3; x++) {
        d[x] = t1 * kVec[k + 1][x] + t2 * kVec[(k + 1) % 6 + 1][x] + t7;
    }
    return om;
}

static const svm_params_t kSym = {SVM_SYMMETRIC, 0U, 0};
static const svm_params_t kTwo = {SVM_TWO_PHASE, 0U, 0};

static void run(const svm_params_t *p, double va, double vb, double vdc, svm_out_t *o)
{
    svm_t s;
    svm_reset(&s);
    svm_step(&s, p, fixtest_d_to_iq(va), fixtest_d_to_iq(vb), fixtest_d_to_iq(vdc), NULL, o);
}

/* Mean alpha/beta voltage of three duties on vdc (Casadei eq. 2 / Hoang eqs. 1-5). */
static void vs_of(const double d[3], double vdc, double *va, double *vb)
{
    *va = vdc * (2.0 * d[0] - d[1] - d[2]) / 3.0;
    *vb = vdc * (d[1] - d[2]) / sqrt(3.0);
}

/* Every sector, both modes, 7 magnitudes from 0 to the hexagon's inscribed circle and beyond to the
 * vertices, 720 angles each (0.5 deg, so every sector boundary 0, 60, ..., 300 deg is hit exactly):
 * duties within 8 LSB of the reference, and the volt-seconds (mean vector) within 8 LSB of the
 * command inside the hexagon. */
static void test_every_sector_matches_reference(void **state)
{
    (void)state;
    const double vdc = 1.1;
    const double mags[] = {0.0, 0.05, 0.3, 0.5, 0.63, 1.1 / sqrt(3.0) - 1e-6, 2.0 / 3.0 * 1.1 - 1e-6};
    double worst = 0.0;
    for (int mode = 0; mode < 2; mode++) {
        const svm_params_t *p = mode ? &kTwo : &kSym;
        for (size_t im = 0; im < sizeof mags / sizeof mags[0]; im++) {
            for (int n = 0; n < 720; n++) {
                const double ang = n * PI / 360.0;
                const double va = mags[im] * cos(ang), vb = mags[im] * sin(ang);
                double d[3], dq[3], ra, rb;
                svm_out_t o;
                const int om = ref_svm(va, vb, vdc, mode, d);
                run(p, va, vb, vdc, &o);
                for (int x = 0; x < 3; x++) {
                    dq[x] = fixtest_iq_to_d(o.d_iq[x]);
                    /* two-phase at a 30-degree boundary: either clamp is right (|v_max| = |v_min|) */
                    if (mode == 1 && fabs(remainder(ang - PI / 6.0, PI / 3.0)) < 1e-9 && mags[im] > 0.0) {
                        continue;
                    }
                    if (fabs(dq[x] - d[x]) > worst) {
                        worst = fabs(dq[x] - d[x]);
                    }
                    fixtest_assert_lsb(dq[x], d[x], LSB, 8.0, "duty against the textbook SVM");
                    assert_true(o.d_iq[x] >= 0 && o.d_iq[x] <= IQ(1.0));
                    assert_int_equal(o.d_eff_iq[x], o.d_iq[x]); /* no dead-time compensation */
                }
                assert_int_equal(o.overmod, (uint16_t)om);
                vs_of(dq, vdc, &ra, &rb);
                if (!om) {
                    fixtest_assert_lsb(ra, va, LSB, 8.0, "alpha volt-seconds");
                    fixtest_assert_lsb(rb, vb, LSB, 8.0, "beta volt-seconds");
                }
            }
        }
    }
    print_message("worst duty error %.2f LSB\n", worst / LSB);
}

/* Inside the hexagon svm_step leaves the duties unclamped (svm.c: n_x + n_0 lies in [0, 1] when the
 * span is at most 1): random references on random links, both modes, most of them within 2^-18
 * of the hexagon's edge r(a) = V_dc / (sqrt3 cos(a mod 60 deg - 30 deg)) on either side, so that
 * the span's IQ rounding reaches exactly 1 pu: every duty in [0, 1], and inside the hexagon the
 * line-to-line duty differences are the reference's (n_x - n_y) within 8 LSB (the roundings of
 * v/V_dc and of the reciprocal). */
static void test_duties_in_range_at_the_hexagon_edge(void **state)
{
    (void)state;
    uint64_t x = 0x2545F4914F6CDD1DULL;
    long inside = 0;
    for (long n = 0; n < 400000; n++) {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        const double u1 = (double)(x >> 11) / 9007199254740992.0;
        const double u2 = (double)((x * 2654435761ULL) >> 11) / 9007199254740992.0;
        const double vdc = 0.5 + 1.5 * u1;
        const double ang = 2.0 * PI * u2;
        const double edge = vdc / (sqrt(3.0) * cos(fmod(ang, PI / 3.0) - PI / 6.0));
        const double mag = (n % 4 == 0) ? edge * u1 : edge * (1.0 + ldexp(u2 - 0.5, -17));
        const double va = mag * cos(ang), vb = mag * sin(ang);
        svm_out_t o;
        run((n & 1) ? &kTwo : &kSym, va, vb, vdc, &o);
        for (int k = 0; k < 3; k++) {
            assert_true(o.d_iq[k] >= 0 && o.d_iq[k] <= IQ(1.0));
        }
        if (o.overmod == 0U) {
            /* n_a - n_b = (3/2 va - sqrt3/2 vb) / vdc, n_b - n_c = sqrt3 vb / vdc */
            const double ab = (1.5 * va - 0.5 * sqrt(3.0) * vb) / vdc, bc = sqrt(3.0) * vb / vdc;
            fixtest_assert_lsb(fixtest_iq_to_d(o.d_iq[0] - o.d_iq[1]), ab, LSB, 8.0, "d_a - d_b");
            fixtest_assert_lsb(fixtest_iq_to_d(o.d_iq[1] - o.d_iq[2]), bc, LSB, 8.0, "d_b - d_c");
            inside++;
        }
    }
    assert_true(inside > 100000 && inside < 400000); /* both sides of the edge reached */
}

/* Zero reference: all three legs at 1/2 (symmetric: 50 % square waves, V0 and V7 a quarter period
 * each) and, two-phase, every leg clamped to the same rail (no switching at all). The duty sums:
 * symmetric d_max + d_min = 1 (centred null times); two-phase one leg at 0 or 1. */
static void test_zero_reference_and_duty_sums(void **state)
{
    (void)state;
    svm_out_t o;
    run(&kSym, 0.0, 0.0, 1.0, &o);
    for (int x = 0; x < 3; x++) {
        assert_int_equal(o.d_iq[x], IQ(0.5));
    }
    run(&kTwo, 0.0, 0.0, 1.0, &o);
    for (int x = 0; x < 3; x++) {
        assert_int_equal(o.d_iq[x], IQ(1.0)); /* max + min = 0 >= 0: top clamp, V7 */
    }
    for (int n = 0; n < 360; n++) {
        const double va = 0.4 * cos(n * PI / 180.0), vb = 0.4 * sin(n * PI / 180.0);
        iq_t mx, mn;
        run(&kSym, va, vb, 1.0, &o);
        mx = o.d_iq[0] > o.d_iq[1] ? o.d_iq[0] : o.d_iq[1];
        mx = mx > o.d_iq[2] ? mx : o.d_iq[2];
        mn = o.d_iq[0] < o.d_iq[1] ? o.d_iq[0] : o.d_iq[1];
        mn = mn < o.d_iq[2] ? mn : o.d_iq[2];
        assert_true(labs((long)(mx + mn) - (long)IQ(1.0)) <= 2);
        run(&kTwo, va, vb, 1.0, &o);
        {
            int clamped = 0;
            for (int x = 0; x < 3; x++) {
                clamped += o.d_iq[x] == 0 || o.d_iq[x] == IQ(1.0);
            }
            assert_true(clamped >= 1);
        }
    }
}

/* Full duty: a reference on a vertex of the hexagon (V1, length 2/3 V_dc) gives legs 1, 0, 0 in
 * both modes: the active vector for the whole period. Beyond it the same. */
static void test_full_duty_at_the_vertices(void **state)
{
    (void)state;
    for (int k = 0; k < 6; k++) {
        for (int mode = 0; mode < 2; mode++) {
            const double ang = k * PI / 3.0;
            svm_out_t o;
            run(mode ? &kTwo : &kSym, 2.0 / 3.0 * cos(ang), 2.0 / 3.0 * sin(ang), 1.0, &o);
            for (int x = 0; x < 3; x++) {
                fixtest_assert_lsb(fixtest_iq_to_d(o.d_iq[x]), kVec[k + 1][x], LSB, 8.0, "vertex duty");
            }
            run(mode ? &kTwo : &kSym, 3.0 * cos(ang), 3.0 * sin(ang), 1.0, &o);
            assert_int_equal(o.overmod, 1U);
            for (int x = 0; x < 3; x++) {
                fixtest_assert_lsb(fixtest_iq_to_d(o.d_iq[x]), kVec[k + 1][x], LSB, 8.0, "beyond the vertex");
            }
        }
    }
}

/* Overmodulation: a reference 1.5x and 20x outside the hexagon lands on its boundary (d_max = 1,
 * d_min = 0) at the commanded angle (within 1e-5 rad), in both modes; the inscribed-circle
 * magnitude V_dc/sqrt3 between two vertices (30 deg) is the boundary (d_max - d_min = 1, no
 * flag), just above it the flag is set. Also a large link (2 pu, small 1/V_dc) and a small one
 * (0.3 pu). */
static void test_overmodulation_keeps_the_angle(void **state)
{
    (void)state;
    const double vdcs[] = {0.3, 1.0, 2.0};
    for (size_t iv = 0; iv < 3; iv++) {
        const double vdc = vdcs[iv];
        for (int n = 0; n < 72; n++) {
            for (int mode = 0; mode < 2; mode++) {
                const double ang = n * 5.0 * PI / 180.0 + 0.01;
                for (double f = 1.5; f < 25.0; f *= 13.3) {
                    const double r = f * 2.0 / 3.0 * vdc;
                    double d[3], dr[3], va, vb;
                    svm_out_t o;
                    ref_svm(r * cos(ang), r * sin(ang), vdc, mode, dr);
                    run(mode ? &kTwo : &kSym, r * cos(ang), r * sin(ang), vdc, &o);
                    assert_int_equal(o.overmod, 1U);
                    for (int x = 0; x < 3; x++) {
                        d[x] = fixtest_iq_to_d(o.d_iq[x]);
                        fixtest_assert_lsb(d[x], dr[x], LSB, 16.0, "overmodulated duty");
                    }
                    vs_of(d, vdc, &va, &vb);
                    {
                        double e = atan2(vb, va) - atan2(sin(ang), cos(ang));
                        e = remainder(e, 2.0 * PI);
                        assert_true(fabs(e) < 1e-5);
                    }
                }
            }
        }
    }
    {
        svm_out_t o;
        const double r = 1.0 / sqrt(3.0);
        run(&kSym, r * cos(PI / 6.0) * (1.0 - 1e-5), r * sin(PI / 6.0) * (1.0 - 1e-5), 1.0, &o);
        assert_int_equal(o.overmod, 0U);
        run(&kSym, r * cos(PI / 6.0) * (1.0 + 1e-5), r * sin(PI / 6.0) * (1.0 + 1e-5), 1.0, &o);
        assert_int_equal(o.overmod, 1U);
    }
}

/* Dead-time compensation: a switching leg gets sgn(i) T_d/T_s added and its expected effective
 * duty is the uncompensated one; i = 0 is left alone; a clamped leg (two-phase) is not touched;
 * a duty within T_d/T_s of a rail is clamped there (no edge, no error), and the effective duty is
 * then the rail; without compensation the effective duty is d - sgn(i) T_d/T_s. */
static void test_deadtime_compensation_edges(void **state)
{
    (void)state;
    const double td = 0.02;
    svm_params_t p = {SVM_SYMMETRIC, 1U, 0};
    clarke_out_t i;
    svm_t s;
    svm_out_t o, o0;
    p.td_iq = iq_from_q15(fixtest_d_to_q15(td)); /* the Q15 of the configuration */
    const double tdq = fixtest_iq_to_d(p.td_iq);
    i.ia_iq = IQ(0.5);
    i.ib_iq = IQ(-0.2);
    i.ic_iq = 0;
    svm_reset(&s);
    run(&kSym, 0.2, 0.1, 1.0, &o0);
    svm_step(&s, &p, IQ(0.2), IQ(0.1), IQ(1.0), &i, &o);
    fixtest_assert_lsb(fixtest_iq_to_d(o.d_iq[0]), fixtest_iq_to_d(o0.d_iq[0]) + tdq, LSB, 2.0, "i > 0: + Td/Ts");
    fixtest_assert_lsb(fixtest_iq_to_d(o.d_iq[1]), fixtest_iq_to_d(o0.d_iq[1]) - tdq, LSB, 2.0, "i < 0: - Td/Ts");
    assert_int_equal(o.d_iq[2], o0.d_iq[2]); /* i = 0 */
    for (int x = 0; x < 3; x++) {
        assert_true(labs((long)(o.d_eff_iq[x] - o0.d_iq[x])) <= 1);
    }
    /* near the rails: symmetric at a reference close to V1 (d_a ~ 0.99, d_b ~ d_c ~ 0.01) */
    svm_step(&s, &p, IQ(0.66), IQ(0.0), IQ(1.0), &i, &o);
    assert_int_equal(o.d_iq[0], IQ(1.0)); /* 0.99 + 0.02 clamped: no edge */
    assert_int_equal(o.d_eff_iq[0], IQ(1.0));
    assert_int_equal(o.d_iq[1], 0);       /* 0.005 - 0.02 clamped */
    assert_int_equal(o.d_eff_iq[1], 0);
    /* two-phase: the clamped leg stays clamped whatever its current */
    p.mode = SVM_TWO_PHASE;
    i.ia_iq = IQ(-0.5);
    svm_step(&s, &p, IQ(0.3), IQ(0.0), IQ(1.0), &i, &o);
    assert_int_equal(o.d_iq[0], IQ(1.0));
    assert_int_equal(o.d_eff_iq[0], IQ(1.0));
    /* compensation off: the effective duty carries the dead-time error */
    p.mode = SVM_SYMMETRIC;
    p.dt_comp = 0U;
    i.ia_iq = IQ(0.5);
    svm_step(&s, &p, IQ(0.2), IQ(0.1), IQ(1.0), &i, &o);
    assert_int_equal(o.d_iq[0], o0.d_iq[0]);
    fixtest_assert_lsb(fixtest_iq_to_d(o.d_eff_iq[0]), fixtest_iq_to_d(o0.d_iq[0]) - tdq, LSB, 2.0, "off: d - Td/Ts");
}

/* 1/V_dc: re-seeded from any state, exact to an LSB for links from 2^-6 to 100 pu, and tracked
 * across a slow ramp with one call per step; a non-positive link gives zero volts. */
static void test_reciprocal_and_link(void **state)
{
    (void)state;
    const double xs[] = {1.0 / 64.0, 0.3, 0.999, 1.0, 1.7, 3.0, 40.0, 100.0};
    for (size_t n = 0; n < sizeof xs / sizeof xs[0]; n++) {
        const iq_t seeds[] = {0, -5, IQ(1.0), IQ(100.0)};
        for (size_t k = 0; k < 4; k++) {
            const double y = fixtest_iq_to_d(svm_recip(seeds[k], fixtest_d_to_iq(xs[n])));
            assert_true(fabs(y - 1.0 / xs[n]) <= 4.0 * LSB + 2e-7 / xs[n]);
        }
    }
    {
        iq_t y = 0;
        for (int k = 0; k < 1000; k++) {
            const double x = 0.8 + 0.4 * k / 1000.0;
            y = svm_recip(y, fixtest_d_to_iq(x));
            assert_true(fabs(fixtest_iq_to_d(y) - 1.0 / x) <= 4.0 * LSB);
        }
    }
    {
        svm_out_t o;
        run(&kSym, 0.3, 0.2, 0.0, &o);
        for (int x = 0; x < 3; x++) {
            assert_int_equal(o.d_iq[x], IQ(0.5));
        }
    }
}

/* The overmodulation's 1/span (svm_recip_span): the IQ rounding of 1/x (half up) for x in
 * [1, 128) pu, against the double quotient 2^48 / x (exact to 2^-29 LSB below 2^24) and the exact
 * integer rounding floor((2^49 + x) / 2x): every x in [1, 1 + 2^-4] pu, the table's 32 intervals at
 * every octave around their ends, and a stride through the whole range. */
static void check_recip_span(int64_t x)
{
    const iq_t y = svm_recip_span((iq_t)x);
    const double yd = 281474976710656.0 / (double)x;
    const int64_t yr = (((int64_t)1 << 49) + x) / (2 * x);
    assert_true(fabs((double)y - yd) <= 0.5 + 1e-6);
    assert_int_equal(y, yr);
}

static void test_overmodulation_reciprocal_is_rounded(void **state)
{
    (void)state;
    int64_t x;
    for (x = (int64_t)1 << 24; x <= ((int64_t)1 << 24) + ((int64_t)1 << 20); x++) {
        check_recip_span(x);
    }
    for (int m = 0; m < 7; m++) {
        for (int64_t j = 0; j <= 32; j++) {
            const int64_t edge = ((32 + j) << (19 + m));
            for (int64_t d = -300; d <= 300; d++) {
                if (edge + d >= ((int64_t)1 << 24) && edge + d < ((int64_t)1 << 31)) {
                    check_recip_span(edge + d);
                }
            }
        }
    }
    for (x = (int64_t)1 << 24; x < ((int64_t)1 << 31); x += 9973) {
        check_recip_span(x);
    }
}

/* Compare values (hal.h): duty 1 -> 0, 0 -> T1PR + 1, 1/2 -> T1PR/2, and the on-time
 * ts (1 - c/T1PR) within half a count of d ts for every duty step. */
static void test_compare_values(void **state)
{
    (void)state;
    const uint16_t t1pr = 6000U;
    assert_int_equal(svm_cmpr(IQ(1.0), t1pr), 0);
    assert_int_equal(svm_cmpr(0, t1pr), t1pr + 1U);
    assert_int_equal(svm_cmpr(-5, t1pr), t1pr + 1U);
    assert_int_equal(svm_cmpr(IQ(0.5), t1pr), 3000U);
    assert_int_equal(svm_cmpr(IQ(1.0) + 9, t1pr), 0);
    for (int k = 1; k < 1000; k++) {
        const double d = k / 1000.0;
        const uint16_t c = svm_cmpr(fixtest_d_to_iq(d), t1pr);
        const double on = c > t1pr ? 0.0 : 1.0 - (double)c / t1pr;
        assert_true(fabs(on - d) <= 0.5 / t1pr + 1e-9);
    }
}

UNIT_TEST_MAIN("svm", NULL,
               cmocka_unit_test(test_every_sector_matches_reference),
               cmocka_unit_test(test_duties_in_range_at_the_hexagon_edge),
               cmocka_unit_test(test_zero_reference_and_duty_sums),
               cmocka_unit_test(test_full_duty_at_the_vertices),
               cmocka_unit_test(test_overmodulation_keeps_the_angle),
               cmocka_unit_test(test_deadtime_compensation_edges),
               cmocka_unit_test(test_reciprocal_and_link),
               cmocka_unit_test(test_overmodulation_reciprocal_is_rounded),
               cmocka_unit_test(test_compare_values))
