/*
 * test_svm4.c - FSTP space-vector modulation (firmware/dtc/svm4.h) against a double-precision
 * reference written from the four active vectors, independently of the carrier-based form:
 * V(S_B, S_C) = (2/3)(v_lo + a S_B V_dc + a^2 S_C V_dc) (Hoang Table I with the measured lower
 * capacitor v_lo, eqs. 1-5), the parallelogram split by its V(00)-V(11) diagonal into two
 * triangles, the volt-second balance v = t00 V00 + t10 V10 + t11 V11 (or with V01) solved in the
 * triangle whose weights are all >= 0, and the leg duties d_B = t10 + t11, d_C = t01 + t11.
 * Outside the parallelogram the reference is scaled along its angle onto the boundary (the
 * largest k in [0, 1] with a feasible solution, by bisection). Swept over angles, magnitudes
 * (inside, the inscribed circle, overmodulation up to 20x) and balanced and unbalanced links.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>

#include "fixtest.h"
#include "svm4.h"

#define PI 3.14159265358979323846
#define LSB (1.0 / 16777216.0)

/* V(S_B, S_C) on a link vdc with the lower capacitor at vlo, alpha/beta. */
static void vec(int sb, int sc, double vdc, double vlo, double *va, double *vb)
{
    const double pa = vlo, pb = sb * vdc, pc = sc * vdc;
    *va = (2.0 * pa - pb - pc) / 3.0;
    *vb = (pb - pc) / sqrt(3.0);
}

/* Weights of (va, vb) in the triangle V00, Vx, V11 (x = 10 or 01): solves
 * v - V00 = w_x (Vx - V00) + w_11 (V11 - V00); returns 1 when all three are >= -eps. */
static int tri(double va, double vb, double vdc, double vlo, int x10, double *t00, double *tx, double *t11)
{
    double a0, b0, ax, bx, a1, b1;
    vec(0, 0, vdc, vlo, &a0, &b0);
    vec(x10 ? 1 : 0, x10 ? 0 : 1, vdc, vlo, &ax, &bx);
    vec(1, 1, vdc, vlo, &a1, &b1);
    {
        const double m11 = ax - a0, m12 = a1 - a0, m21 = bx - b0, m22 = b1 - b0;
        const double det = m11 * m22 - m12 * m21;
        const double ra = va - a0, rb = vb - b0;
        *tx = (ra * m22 - m12 * rb) / det;
        *t11 = (m11 * rb - m21 * ra) / det;
        *t00 = 1.0 - *tx - *t11;
    }
    return *t00 >= -1e-12 && *tx >= -1e-12 && *t11 >= -1e-12;
}

static int feasible(double va, double vb, double vdc, double vlo, double d[2])
{
    double t00, tx, t11;
    if (tri(va, vb, vdc, vlo, 1, &t00, &tx, &t11)) {
        d[0] = tx + t11;
        d[1] = t11;
        return 1;
    }
    if (tri(va, vb, vdc, vlo, 0, &t00, &tx, &t11)) {
        d[0] = t11;
        d[1] = tx + t11;
        return 1;
    }
    return 0;
}

/* Reference duties of legs B, C; returns 1 for overmodulation. */
static int ref_svm4(double va, double vb, double vdc, double vlo, double d[2])
{
    double lo = 0.0, hi = 1.0;
    if (feasible(va, vb, vdc, vlo, d)) {
        return 0;
    }
    for (int n = 0; n < 80; n++) {
        const double k = 0.5 * (lo + hi);
        double t[2];
        if (feasible(k * va, k * vb, vdc, vlo, t)) {
            lo = k;
        } else {
            hi = k;
        }
    }
    assert_true(feasible(lo * va, lo * vb, vdc, vlo, d));
    return 1;
}

static const svm4_params_t kNoDt = {0U, 0};

static void run(double va, double vb, double vdc, double vlo, svm_out_t *o)
{
    svm4_t s;
    svm4_reset(&s);
    svm4_step(&s, &kNoDt, fixtest_d_to_iq(va), fixtest_d_to_iq(vb), fixtest_d_to_iq(vdc), fixtest_d_to_iq(vlo), NULL, o);
}

/* Every direction (0.5 deg steps), magnitudes from 0 through the inscribed circle to 20x outside,
 * on a balanced link and on links whose mid-point sits at 40 % and 62 % (and a 1.3 pu link):
 * duties within 4 LSB of the reference; inside, the mean vector of the duties (phase A at m)
 * within 4 LSB of the command; the overmodulation flag as the reference says away from the
 * boundary. */
static void test_sweep_matches_four_vector_reference(void **state)
{
    (void)state;
    const double links[][2] = {{1.0, 0.5}, {1.0, 0.4}, {1.0, 0.62}, {1.3, 0.65}, {1.3, 0.55}};
    double worst = 0.0;
    int n_om = 0, n_lin = 0;
    for (size_t l = 0; l < sizeof links / sizeof links[0]; l++) {
        const double vdc = links[l][0], vlo = links[l][1];
        const double r_in = fmin(vlo, vdc - vlo) / sqrt(3.0);
        const double mags[] = {0.0, 0.05 * r_in, 0.5 * r_in, 0.999 * r_in, 1.2 * r_in, 2.0 * r_in, 20.0 * r_in};
        for (size_t im = 0; im < sizeof mags / sizeof mags[0]; im++) {
            for (int n = 0; n < 720; n++) {
                const double ang = n * PI / 360.0;
                const double va = mags[im] * cos(ang), vb = mags[im] * sin(ang);
                double d[2];
                svm_out_t o;
                const int om = ref_svm4(va, vb, vdc, vlo, d);
                run(va, vb, vdc, vlo, &o);
                for (int x = 0; x < 2; x++) {
                    const double dq = fixtest_iq_to_d(o.d_iq[x + 1]);
                    worst = fmax(worst, fabs(dq - d[x]));
                    fixtest_assert_lsb(dq, d[x], LSB, 4.0, "FSTP duty against the four-vector reference");
                    assert_true(o.d_iq[x + 1] >= 0 && o.d_iq[x + 1] <= IQ(1.0));
                }
                fixtest_assert_lsb(fixtest_iq_to_d(o.d_iq[0]), vlo / vdc, LSB, 2.0, "phase A at the mid-point");
                if (im <= 3) {
                    const double da = fixtest_iq_to_d(o.d_iq[0]), db = fixtest_iq_to_d(o.d_iq[1]),
                                 dc = fixtest_iq_to_d(o.d_iq[2]);
                    fixtest_assert_lsb(vdc * (2.0 * da - db - dc) / 3.0, va, LSB, 4.0, "alpha volt-seconds");
                    fixtest_assert_lsb(vdc * (db - dc) / sqrt(3.0), vb, LSB, 4.0, "beta volt-seconds");
                    assert_int_equal(o.overmod, 0U);
                    n_lin++;
                } else if (im >= 5) {
                    assert_int_equal(o.overmod, (uint16_t)om);
                    n_om += om;
                }
            }
        }
    }
    assert_true(n_om > 1000 && n_lin > 1000);
    print_message("worst FSTP duty error %.2f LSB\n", worst / LSB);
}

/* Overmodulation keeps the angle: the mean vector of the clamped duties points where the command
 * does (within 1e-5 rad) and one leg sits on a rail; the unbalanced link's boundary is where the
 * vectors it really has put it (a reference that fits with v_lo = V_dc/2 but not with v_lo =
 * 0.4 V_dc is flagged). */
static void test_overmodulation_keeps_angle_on_unbalanced_link(void **state)
{
    (void)state;
    const double vdc = 1.0, vlo = 0.4;
    for (int n = 0; n < 360; n++) {
        const double ang = n * PI / 180.0 + 0.01;
        const double va = 3.0 * cos(ang), vb = 3.0 * sin(ang);
        svm_out_t o;
        run(va, vb, vdc, vlo, &o);
        {
            const double da = fixtest_iq_to_d(o.d_iq[0]), db = fixtest_iq_to_d(o.d_iq[1]), dc = fixtest_iq_to_d(o.d_iq[2]);
            const double ra = vdc * (2.0 * da - db - dc) / 3.0, rb = vdc * (db - dc) / sqrt(3.0);
            assert_int_equal(o.overmod, 1U);
            assert_true(fabs(remainder(atan2(rb, ra) - ang, 2.0 * PI)) < 1e-5);
            assert_true(o.d_iq[1] == 0 || o.d_iq[1] == IQ(1.0) || o.d_iq[2] == 0 || o.d_iq[2] == IQ(1.0));
        }
    }
    {
        /* along -alpha (u_B = u_C = 1.5 |v|): room 1 - m = 0.5 balanced, 0.6 at m = 0.4 */
        svm_out_t o;
        run(-0.35, 0.0, 1.0, 0.5, &o);
        assert_int_equal(o.overmod, 1U);
        run(-0.35, 0.0, 1.0, 0.4, &o);
        assert_int_equal(o.overmod, 0U);
        /* along +alpha the room is m: 0.5 balanced, 0.4 unbalanced */
        run(0.3, 0.0, 1.0, 0.5, &o);
        assert_int_equal(o.overmod, 0U);
        run(0.3, 0.0, 1.0, 0.4, &o);
        assert_int_equal(o.overmod, 1U);
        fixtest_assert_lsb(fixtest_iq_to_d(o.d_iq[1]), 0.0, LSB, 1.0, "leg B on the lower rail");
    }
}

/* The four vectors themselves: a reference on V(S_B, S_C) gives duties (S_B, S_C). */
static void test_vertices_are_the_switching_states(void **state)
{
    (void)state;
    const double vlos[] = {0.5, 0.42};
    for (size_t l = 0; l < 2; l++) {
        for (int s = 0; s < 4; s++) {
            const int sb = s >> 1, sc = s & 1;
            double va, vb;
            svm_out_t o;
            vec(sb, sc, 1.0, vlos[l], &va, &vb);
            run(va, vb, 1.0, vlos[l], &o);
            fixtest_assert_lsb(fixtest_iq_to_d(o.d_iq[1]), sb, LSB, 4.0, "vertex leg B");
            fixtest_assert_lsb(fixtest_iq_to_d(o.d_iq[2]), sc, LSB, 4.0, "vertex leg C");
        }
    }
}

/* No link: every duty 1/2; the reciprocal follows a moving link. */
static void test_no_link_and_moving_link(void **state)
{
    (void)state;
    svm4_t s;
    svm_out_t o;
    svm4_reset(&s);
    svm4_step(&s, &kNoDt, IQ(0.1), IQ(0.1), 0, 0, NULL, &o);
    for (int x = 0; x < 3; x++) {
        assert_int_equal(o.d_iq[x], IQ(0.5));
    }
    for (int n = 0; n < 200; n++) {
        const double vdc = 1.0 + 0.1 * sin(n * 0.05), vlo = 0.5 * vdc + 0.02 * cos(n * 0.07);
        const double va = 0.2 * cos(n * 0.1), vb = 0.2 * sin(n * 0.1);
        double d[2] = {0.0, 0.0};
        ref_svm4(va, vb, vdc, vlo, d);
        svm4_step(&s, &kNoDt, fixtest_d_to_iq(va), fixtest_d_to_iq(vb), fixtest_d_to_iq(vdc), fixtest_d_to_iq(vlo), NULL, &o);
        fixtest_assert_lsb(fixtest_iq_to_d(o.d_iq[1]), d[0], LSB, 4.0, "leg B, moving link");
        fixtest_assert_lsb(fixtest_iq_to_d(o.d_iq[2]), d[1], LSB, 4.0, "leg C, moving link");
    }
}

/* Dead-time compensation on legs B and C (svm.h's rule): a switching leg whose current leaves it
 * (i > 0) is commanded T_d/T_s more, one whose current enters (i < 0) T_d/T_s less, and the
 * effective duties are the uncompensated ones; phase A (no devices) stays at m; without currents
 * nothing is compensated. */
static void test_dead_time_on_the_switched_legs(void **state)
{
    (void)state;
    const svm4_params_t p = {1U, IQ(0.02)};
    clarke_out_t i;
    svm4_t s;
    svm_out_t o, o0;
    svm4_reset(&s);
    clarke_inv(IQ(0.0), IQ(0.5), &i); /* i_b > 0, i_c < 0 */
    svm4_step(&s, &p, IQ(0.05), IQ(0.1), IQ(1.0), IQ(0.45), &i, &o);
    svm4_step(&s, &kNoDt, IQ(0.05), IQ(0.1), IQ(1.0), IQ(0.45), NULL, &o0);
    assert_true(i.ib_iq > 0 && i.ic_iq < 0);
    fixtest_assert_lsb(fixtest_iq_to_d(o.d_iq[1]), fixtest_iq_to_d(o0.d_iq[1]) + 0.02, LSB, 1.0, "leg B + T_d/T_s");
    fixtest_assert_lsb(fixtest_iq_to_d(o.d_iq[2]), fixtest_iq_to_d(o0.d_iq[2]) - 0.02, LSB, 1.0, "leg C - T_d/T_s");
    assert_int_equal(o.d_eff_iq[1], o0.d_iq[1]);
    assert_int_equal(o.d_eff_iq[2], o0.d_iq[2]);
    assert_int_equal(o.d_iq[0], o0.d_iq[0]);
    svm4_step(&s, &p, IQ(0.05), IQ(0.1), IQ(1.0), IQ(0.45), NULL, &o);
    assert_int_equal(o.d_iq[1], o0.d_iq[1]);
}

UNIT_TEST_MAIN("svm4", NULL,
               cmocka_unit_test(test_sweep_matches_four_vector_reference),
               cmocka_unit_test(test_overmodulation_keeps_angle_on_unbalanced_link),
               cmocka_unit_test(test_vertices_are_the_switching_states),
               cmocka_unit_test(test_no_link_and_moving_link),
               cmocka_unit_test(test_dead_time_on_the_switched_legs))
