/*
 * test_dtc_clarke_vrec.c - Clarke transform from two measured currents and the phase-voltage
 * reconstruction (Hoang eqs. 1-5, 17-19, Table I; Casadei eq. 2) against double references.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>

#include "clarke.h"
#include "dtc_ref.h"
#include "fixtest.h"
#include "vrec.h"

#define LSB (1.0 / 16777216.0)

static void test_clarke_sweep_lsb(void **state)
{
    (void)state;
    fixtest_acc_t acc_a, acc_b;
    fixtest_acc_init(&acc_a);
    fixtest_acc_init(&acc_b);
    /* Balanced sets of amplitude 0..3 pu over a turn, both topologies. */
    for (int n = 0; n < 2000; n++) {
        double amp = 3.0 * (n % 97) / 96.0, th = 2.0 * DTC_REF_PI * n / 2000.0;
        double ia = amp * cos(th), ib = amp * cos(th - 2.0 * DTC_REF_PI / 3.0);
        double ic = -ia - ib;
        double ra, rb;
        clarke_out_t o;
        dtc_ref_clarke3(ia, ib, ic, &ra, &rb);

        clarke_sstp(fixtest_d_to_iq(ia), fixtest_d_to_iq(ib), &o);
        /* Inputs are rounded (0.5 LSB each); (a + 2b)/sqrt3 amplifies to 0.5*3/sqrt3 = 0.87 LSB,
         * plus 0.5 LSB output rounding: bound 1.5 LSB. */
        fixtest_assert_lsb(fixtest_iq_to_d(o.i_alpha_iq), ra, LSB, 0.5, "sstp i_alpha");
        fixtest_assert_lsb(fixtest_iq_to_d(o.i_beta_iq), rb, LSB, 1.5, "sstp i_beta");
        fixtest_assert_lsb(fixtest_iq_to_d(o.ic_iq), ic, LSB, 1.0, "sstp i_c");
        fixtest_acc_add(&acc_a, fixtest_iq_to_d(o.i_beta_iq), rb);

        clarke_fstp(fixtest_d_to_iq(ib), fixtest_d_to_iq(ic), &o);
        fixtest_assert_lsb(fixtest_iq_to_d(o.i_alpha_iq), ra, LSB, 1.0, "fstp i_alpha");
        fixtest_assert_lsb(fixtest_iq_to_d(o.i_beta_iq), rb, LSB, 1.5, "fstp i_beta");
        fixtest_assert_lsb(fixtest_iq_to_d(o.ia_iq), ia, LSB, 1.0, "fstp i_a");
        fixtest_acc_add(&acc_b, fixtest_iq_to_d(o.i_beta_iq), rb);
    }
    /* 1 LSB of Q24 on signals of ~1.5 pu rms: SNR ~ 20log10(1.5 * 2^24) ~ 148 dB. */
    fixtest_assert_snr(&acc_a, 140.0, "sstp i_beta trajectory");
    fixtest_assert_snr(&acc_b, 140.0, "fstp i_beta trajectory");
}

static void test_clarke_saturates_at_edges(void **state)
{
    (void)state;
    clarke_out_t o;
    /* i_a = i_b = +max: i_c = -(2 max) saturates to IQ_MIN, i_beta saturates to IQ_MAX. */
    clarke_sstp(IQ_MAX, IQ_MAX, &o);
    assert_int_equal(o.ic_iq, IQ_MIN + 1); /* -(IQ_MAX) after the saturated sum */
    assert_int_equal(o.i_beta_iq, q31_mul(IQ_MAX, CLARKE_INV_SQRT3_Q31));
    assert_true(o.i_beta_iq > 0);
    clarke_sstp(IQ_MIN, IQ_MIN, &o);
    assert_int_equal(o.ic_iq, IQ_MAX);
    assert_true(o.i_beta_iq < 0);
    clarke_fstp(IQ_MAX, IQ_MIN, &o);
    assert_true(o.i_beta_iq > 0); /* difference saturates, no wrap to negative */
    clarke_fstp(IQ_MIN, IQ_MAX, &o);
    assert_true(o.i_beta_iq < 0);
    clarke_fstp(IQ_MIN, IQ_MIN, &o);
    assert_int_equal(o.ia_iq, IQ_MAX);
    /* +-1 LSB around zero */
    clarke_fstp(1, -1, &o);
    assert_int_equal(o.ia_iq, 0);
    assert_int_equal(o.i_beta_iq, 1); /* 2/sqrt3 = 1.15 -> 1 */
}

static void test_hoang_table_i_reproduced(void **state)
{
    (void)state;
    /* FSTP, S_A = 1/2 (Hoang eqs. 17-19), vdc = 1 pu: every row of Table I. */
    const uint16_t sbsc[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int v = 1; v <= 4; v++) {
        double t[5];
        iq_t va, vb;
        dtc_ref_table_i(v, t);
        vrec_fstp(sbsc[v - 1][0], sbsc[v - 1][1], IQ(1.0), 0, 0U, &va, &vb);
        fixtest_assert_lsb(fixtest_iq_to_d(va), t[3], LSB, 1.0, "Table I v_alpha");
        fixtest_assert_lsb(fixtest_iq_to_d(vb), t[4], LSB, 1.0, "Table I v_beta");
        /* Hoang Eqs. 17-19 give the phase voltages of Table I, and eqs. 4-5 map them to alpha-beta. */
        double sb = sbsc[v - 1][0], sc = sbsc[v - 1][1], ra, rb;
        assert_true(fabs((1.0 - sb - sc) / 3.0 - t[0]) < 1e-15);
        assert_true(fabs((4.0 * sb - 2.0 * sc - 1.0) / 6.0 - t[1]) < 1e-15);
        assert_true(fabs((4.0 * sc - 2.0 * sb - 1.0) / 6.0 - t[2]) < 1e-15);
        dtc_ref_clarke3(t[0], t[1], t[2], &ra, &rb);
        assert_true(fabs(ra - t[3]) < 1e-15 && fabs(rb - t[4]) < 1e-15);
        /* Measured mid-point exactly at V_dc/2 gives the same vector. */
        iq_t va2, vb2;
        vrec_fstp(sbsc[v - 1][0], sbsc[v - 1][1], IQ(1.0), IQ(0.5), 1U, &va2, &vb2);
        assert_int_equal(va2, va);
        assert_int_equal(vb2, vb);
    }
}

static void test_sstp_vectors_casadei_eq2(void **state)
{
    (void)state;
    /* Active vectors: length 2/3 V_dc at (k-1)*60 deg; nulls: zero (Casadei eq. 2). */
    const uint16_t legs[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                 {0, 1, 1}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}};
    for (int k = 0; k < 8; k++) {
        iq_t va, vb;
        double vdc = 1.1;
        vrec_sstp(legs[k][0], legs[k][1], legs[k][2], fixtest_d_to_iq(vdc), &va, &vb);
        double ea = 0.0, eb = 0.0;
        if (k >= 1 && k <= 6) {
            ea = 2.0 / 3.0 * vdc * cos((k - 1) * DTC_REF_PI / 3.0);
            eb = 2.0 / 3.0 * vdc * sin((k - 1) * DTC_REF_PI / 3.0);
        }
        fixtest_assert_lsb(fixtest_iq_to_d(va), ea, LSB, 1.5, "sstp v_alpha");
        fixtest_assert_lsb(fixtest_iq_to_d(vb), eb, LSB, 1.5, "sstp v_beta");
    }
}

static void test_fstp_measured_midpoint_drift(void **state)
{
    (void)state;
    /* Mid-point drifted to 0.45 V_dc: leg A at 0.45, the vectors shift along alpha by
     * 2*(0.45 - 0.5)/3 V_dc (Hoang eq. 4 with v_a0 = V_mid), beta unchanged. Sweep V_dc and V_mid. */
    for (int n = 0; n < 400; n++) {
        double vdc = 0.5 + n * 0.0025, vmid = vdc * (0.4 + 0.2 * (n % 21) / 20.0);
        for (int s = 0; s < 4; s++) {
            int sb = s >> 1, sc = s & 1;
            iq_t va, vb;
            double ra, rb;
            vrec_fstp((uint16_t)sb, (uint16_t)sc, fixtest_d_to_iq(vdc), fixtest_d_to_iq(vmid), 1U,
                      &va, &vb);
            /* reference from the leg voltages with the neutral eliminated (Hoang eqs. 1-5) */
            double va0 = vmid, vb0 = sb * vdc, vc0 = sc * vdc, vn0 = (va0 + vb0 + vc0) / 3.0;
            dtc_ref_clarke3(va0 - vn0, vb0 - vn0, vc0 - vn0, &ra, &rb);
            fixtest_assert_lsb(fixtest_iq_to_d(va), ra, LSB, 2.0, "vmid v_alpha");
            fixtest_assert_lsb(fixtest_iq_to_d(vb), rb, LSB, 1.5, "vmid v_beta");
        }
    }
    /* Saturation: an absurd V_dc at the IQ limit does not wrap. */
    iq_t va, vb;
    vrec_sstp(1U, 0U, 0U, IQ_MAX, &va, &vb);
    assert_true(va > IQ(40.0));
    vrec_sstp(0U, 1U, 1U, IQ_MAX, &va, &vb);
    assert_true(va < IQ(-40.0));
}

UNIT_TEST_MAIN("dtc clarke vrec", NULL,
               cmocka_unit_test(test_clarke_sweep_lsb),
               cmocka_unit_test(test_clarke_saturates_at_edges),
               cmocka_unit_test(test_hoang_table_i_reproduced),
               cmocka_unit_test(test_sstp_vectors_casadei_eq2),
               cmocka_unit_test(test_fstp_measured_midpoint_drift))
