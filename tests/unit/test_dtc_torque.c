/*
 * test_dtc_torque.c - torque (Hoang eq. 10) and flux magnitude (eq. 11) against double
 * references, sweeps and saturation edges.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>

#include "dtc_ref.h"
#include "fixtest.h"
#include "torque.h"

#define LSB (1.0 / 16777216.0)

static void test_torque_eq10_sweep(void **state)
{
    (void)state;
    fixtest_acc_t acc;
    fixtest_acc_init(&acc);
    for (int n = 0; n < 20000; n++) {
        double th = n * 0.00731, ps = 0.1 + 1.5 * (n % 113) / 112.0;
        double pa = ps * cos(th), pb = ps * sin(th);
        double ia = 3.0 * cos(th + 1.0 + n * 1e-4), ib = 3.0 * sin(th + 1.0 + n * 1e-4);
        iq_t qpa = fixtest_d_to_iq(pa), qpb = fixtest_d_to_iq(pb);
        iq_t qia = fixtest_d_to_iq(ia), qib = fixtest_d_to_iq(ib);
        /* reference from the rounded inputs: the function's own error is one rounding */
        double ref = fixtest_iq_to_d(qpa) * fixtest_iq_to_d(qib) -
                     fixtest_iq_to_d(qpb) * fixtest_iq_to_d(qia);
        double got = fixtest_iq_to_d(torque_eq10(qpa, qpb, qia, qib));
        fixtest_assert_lsb(got, ref, LSB, 0.5, "torque eq. 10");
        /* and against the unrounded physics: input rounding adds |psi| + |i| LSB at most */
        fixtest_assert_lsb(got, pa * ib - pb * ia, LSB, 0.5 + 0.5 * (3.0 + 1.6) * 2.0, "eq. 10 exact");
        fixtest_acc_add(&acc, got, pa * ib - pb * ia);
    }
    fixtest_assert_snr(&acc, 130.0, "torque trajectory");
}

static void test_torque_saturates(void **state)
{
    (void)state;
    /* the extreme products: |difference| reaches 2^63 - 2^31, still exact in 64 bits */
    assert_int_equal(torque_eq10(IQ_MAX, IQ_MIN, IQ_MAX, IQ_MAX), IQ_MAX);
    assert_int_equal(torque_eq10(IQ_MIN, IQ_MAX, IQ_MAX, IQ_MAX), IQ_MIN);
    assert_int_equal(torque_eq10(IQ_MIN, IQ_MIN, IQ_MAX, IQ_MIN), IQ_MAX);
    /* equal extreme products cancel exactly: (2^31-1)^2 - (-2^31)^2 = -2^32 + 1 -> -256 LSB */
    assert_int_equal(torque_eq10(IQ_MAX, IQ_MIN, IQ_MIN, IQ_MAX), -256);
    assert_int_equal(torque_eq10(IQ(12.0), 0, 0, IQ(11.0)), IQ_MAX); /* 132 pu > 128 */
    assert_int_equal(torque_eq10(IQ(-12.0), 0, 0, IQ(11.0)), IQ_MIN);
    assert_int_equal(torque_eq10(1, 0, 0, 1), 0);                   /* 2^-48 rounds to 0 */
    assert_int_equal(torque_eq10(IQ(1.0), 0, 0, 1), 1);
    assert_int_equal(torque_eq10(IQ(1.0), 0, 0, -1), -1);
}

static void test_flux_magnitude_eq11(void **state)
{
    (void)state;
    for (int n = 0; n < 20000; n++) {
        double th = n * 0.0113, m = 3.0 * n / 19999.0;
        iq_t a = fixtest_d_to_iq(m * cos(th)), b = fixtest_d_to_iq(m * sin(th));
        double ref = hypot(fixtest_iq_to_d(a), fixtest_iq_to_d(b));
        /* iq_mag rounds to nearest (fixmath.h): |error| < 0.5 LSB (+1e-6 LSB for the double
         * reference's own rounding). */
        double got = fixtest_iq_to_d(torque_flux_mag(a, b));
        fixtest_assert_lsb(got, ref, LSB, 0.500001, "|psi| (eq. 11)");
    }
    assert_int_equal(torque_flux_mag(IQ_MAX, IQ_MAX), IQ_MAX); /* 181 pu saturates */
    assert_int_equal(torque_flux_mag(0, 0), 0);
    assert_int_equal(torque_flux_mag(IQ_MIN, 0), IQ_MAX);
}

UNIT_TEST_MAIN("dtc torque", NULL,
               cmocka_unit_test(test_torque_eq10_sweep),
               cmocka_unit_test(test_torque_saturates),
               cmocka_unit_test(test_flux_magnitude_eq11))
