/*
 * test_im_fw.c - flux weakening by the torque-comparator monitor (Casadei et al. 2006, section 12):
 * the window rule of 12.2, the update-rate rule of 12.3, and the torque reference of Casadei eqs. 33-34
 * against their double-precision values.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <cmocka.h>

#include "fixtest.h"
#include "im_fw.h"

#define IQ_LSB (1.0 / (double)(1L << FIX_IQ_Q))

static im_fw_params_t params(void)
{
    /* Rated stator flux 0.95 pu, pull-out torque 3.4 x rated at rated flux: k_T = 3.4 / 0.95^2. */
    im_fw_params_t p = {40U,
                        fixtest_d_to_iq(0.01),
                        fixtest_d_to_iq(0.005),
                        fixtest_d_to_iq(0.2),
                        fixtest_d_to_iq(0.95),
                        fixtest_d_to_iq(1.0 / 0.95),
                        fixtest_d_to_iq(3.4 / (0.95 * 0.95))};
    return p;
}

static void test_window_rule(void **state)
{
    (void)state;
    const im_fw_params_t p = params();
    im_fw_t s;
    assert_int_equal(im_fw_check(&p), 0);
    im_fw_reset(&s, &p);
    assert_int_equal(s.psi_ref_iq, p.psi_rated_iq);
    /* No null vector for 5 windows: five steps down, each exactly at the end of a window. */
    for (int k = 1; k <= 5 * 40; ++k) {
        const iq_t before = s.psi_ref_iq;
        (void)im_fw_step(&s, &p, 0U, fixtest_d_to_iq(1.0));
        if (k % 40 == 0) {
            assert_int_equal(s.psi_ref_iq, before - p.step_down_iq);
        } else {
            assert_int_equal(s.psi_ref_iq, before);
        }
    }
    fixtest_assert_lsb(fixtest_iq_to_d(s.psi_ref_iq), 0.90, IQ_LSB, 4.0, "flux after 5 windows down");
    /* One null vector anywhere in a window: one step up. */
    for (int k = 1; k <= 40; ++k) {
        (void)im_fw_step(&s, &p, k == 17 ? 1U : 0U, 0);
    }
    fixtest_assert_lsb(fixtest_iq_to_d(s.psi_ref_iq), 0.905, IQ_LSB, 4.0, "flux after a window with a null");
    /* Bounds: never below phi_min, never above rated. */
    for (int k = 0; k < 40 * 200; ++k) {
        (void)im_fw_step(&s, &p, 0U, 0);
    }
    assert_int_equal(s.psi_ref_iq, p.psi_min_iq);
    for (int k = 0; k < 40 * 400; ++k) {
        (void)im_fw_step(&s, &p, 1U, 0);
    }
    assert_int_equal(s.psi_ref_iq, p.psi_rated_iq);
}

static void test_torque_reference_eqs_33_34(void **state)
{
    (void)state;
    const im_fw_params_t p = params();
    const double kt = 3.4 / (0.95 * 0.95);
    double worst = 0.0;
    int limited = 0;
    for (double psi = 0.2; psi <= 0.95 + 1e-9; psi += 0.05) {
        for (double tc = -3.0; tc <= 3.0; tc += 0.5) {
            im_fw_t s = {fixtest_d_to_iq(psi), 0U, 0U};
            const iq_t t = im_fw_step(&s, &p, 1U, fixtest_d_to_iq(tc));
            double ref = tc * psi / 0.95;                 /* Casadei eq. 33 */
            const double tmax = kt * psi * psi;           /* Casadei eq. 34 */
            if (fabs(ref) > tmax) {
                ref = ref > 0 ? tmax : -tmax;
                ++limited;
            }
            const double e = fabs(fixtest_iq_to_d(t) - ref) / IQ_LSB;
            worst = e > worst ? e : worst;
        }
    }
    printf("MEASURE flux weakening torque reference: worst %.2f LSB over the grid (%d points limited by eq. 34)\n",
           worst, limited);
    assert_true(limited > 10);
    assert_true(worst <= 6.0);
}

static void test_bad_parameters_are_refused(void **state)
{
    (void)state;
    im_fw_params_t p = params();
    p.window = 19U; /* section 12.3: at least 20 DTC periods per flux update */
    assert_int_not_equal(im_fw_check(&p), 0);
    p = params();
    p.psi_min_iq = fixtest_d_to_iq(1.0);
    assert_int_not_equal(im_fw_check(&p), 0);
    p = params();
    p.step_down_iq = 0;
    assert_int_not_equal(im_fw_check(&p), 0);
    p = params();
    p.kt_iq = -1;
    assert_int_not_equal(im_fw_check(&p), 0);
}

UNIT_TEST_MAIN("im fw", NULL,
               cmocka_unit_test(test_window_rule),
               cmocka_unit_test(test_torque_reference_eqs_33_34),
               cmocka_unit_test(test_bad_parameters_are_refused))
