/*
 * test_dtc_dcsupp.c - DC-current suppression of the voltage model (dtc.c dtc_dcsupp).
 *
 * Closed loop against the algebra it is derived from: the DTC holds the estimate plus the
 * correction c on a circle centred on the origin, so an estimate error delta leaves the machine
 * a DC current i = (-delta - c) / l_s; c must go to -delta at the rate w_d = |w|/20 (first order,
 * exp(-w_d t)), and a fundamental current I e^{jwt} must enter c only as l_s I / 20.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "fixtest.h"

#include <math.h>
#include <stdlib.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#include "dtc.h"
#include "dtc_internal.h"
#include "dtc_config_si.h"

static double d(iq_t x) { return (double)x / 16777216.0; }
static double d32(int32_t x) { return (double)x / 4294967296.0; } /* the Q32 state */
static iq_t q(double x) { return (iq_t)lround(x * 16777216.0); }

static void test_dc_error_removed_at_w_over_20(void **state)
{
    (void)state;
    dtc_config_si_t si;
    dtc_config_t cfg;
    dtc_t c;
    dtc_config_si_defaults(&si);
    assert_int_equal(dtc_config_from_si(&si, &cfg, NULL, 0), 0);
    assert_int_equal(cfg.u.pm_dtc.est.dc_supp, 1U);
    assert_int_equal(dtc_init(&c, &cfg), 0);
    const double ls = d(cfg.u.pm_dtc.machine.ls_iq), ts = si.ts_s * si.w_base_rad_s, w = 0.5; /* 1500 rpm */
    const double da = 0.004, db = -0.002; /* estimate error, pu (~ 4 % of psi_m) */
    c.vmid_dev_iq = 0; /* mid-point at V_dc/2: no regulation demand */
    c.speed_primed = 1U;
    c.on_cm = 0U;
    c.speed_iq = q(-w); /* either direction */
    c.dcs_kw_iq = (iq_t)lround((double)cfg.u.pm_dtc.est.dcs_k_iq * w); /* as the speed tick sets it: k |w| */
    const double tau = 20.0 / w; /* pu time */
    const int n_tau = (int)lround(tau / ts);
    for (int k = 1; k <= 6 * n_tau; k++) {
        clarke_out_t i = {0, 0, 0, q((-da - d32(c.dcs_alpha_iq)) / ls), q((-db - d32(c.dcs_beta_iq)) / ls)};
        iq_t pa = 0, pb = 0;
        dtc_dcsupp(&c, &i, &pa, &pb);
        assert_true(abs(pa - (c.dcs_alpha_iq >> 8)) <= 1);
        if (k == n_tau) {
            const double want = -da * (1.0 - exp(-1.0));
            assert_true(fabs(d32(c.dcs_alpha_iq) - want) < 0.01 * da);
        }
    }
    assert_true(fabs(d32(c.dcs_alpha_iq) + da) < 0.005 * da);
    assert_true(fabs(d32(c.dcs_beta_iq) + db) < 0.005 * fabs(db));
    /* the fundamental: c's ripple is l_s I / 20 */
    c.dcs_alpha_iq = 0;
    c.dcs_beta_iq = 0;
    c.speed_iq = q(w);
    c.dcs_kw_iq = (iq_t)lround((double)cfg.u.pm_dtc.est.dcs_k_iq * w);
    double cmax = -1.0, cmin = 1.0;
    const double amp = 1.0; /* rated current, pu */
    for (int k = 0; k < 4 * (int)lround(2.0 * M_PI / w / ts); k++) {
        const double th = w * ts * k;
        clarke_out_t i = {0, 0, 0, q(amp * cos(th)), q(amp * sin(th))};
        iq_t pa = 0, pb = 0;
        dtc_dcsupp(&c, &i, &pa, &pb);
        if (k > (int)lround(2.0 * M_PI / w / ts)) {
            cmax = fmax(cmax, d(pa));
            cmin = fmin(cmin, d(pa));
        }
    }
    /* amplitude of c_alpha over the last periods (the start leaves a DC part decaying at w_d) */
    const double camp = 0.5 * (cmax - cmin);
    print_message("DC suppression: fundamental in c %.3g pu, l_s I / 20 = %.3g pu\n", camp, ls * amp / 20.0);
    assert_true(fabs(camp - ls * amp / 20.0) < 0.1 * ls * amp / 20.0);
    /* on the current model: reset, nothing added */
    c.on_cm = 1U;
    clarke_out_t i = {0, 0, 0, q(1.0), q(1.0)};
    iq_t pa = 7, pb = 9;
    dtc_dcsupp(&c, &i, &pa, &pb);
    assert_int_equal(pa, 7);
    assert_int_equal(pb, 9);
    assert_int_equal(c.dcs_alpha_iq, 0);
}

/* Restoring mid-point reconstruction (dtc.c dtc_vmid_dev): the mid-point deviation d reaches the
 * law as (1 - beta) d, beta = min(1/16, k w^2). Physics it must keep, from the SI values of the
 * drive: the mid-point's swing i_a / (2 C w) becomes, through beta, an inductance error
 * beta / (3 C w^2) on phase A, which stays within l_s / 8 at every speed and uses that allowance
 * wherever beta is below its cap (a smaller beta would restore the mid-point against less link-
 * sensor error for nothing); where k w^2 reaches 1/16, beta is the full 1/16 that covers a link
 * sensor read 3.4 % low. */
static void test_restoring_beta_follows_the_speed(void **state)
{
    (void)state;
    dtc_config_si_t si;
    dtc_config_t cfg;
    dtc_t c;
    dtc_config_si_defaults(&si);
    si.topology = DTC_TOPO_FSTP;
    si.estimator = DTC_EST_VOLTAGE;
    si.fstp_vmid_measured = 1;
    si.vmid_cal = 1;
    assert_int_equal(dtc_config_from_si(&si, &cfg, NULL, 0), 0);
    assert_true(cfg.u.pm_dtc.est.vmid_beta_s_iq > 0);
    assert_int_equal(dtc_init(&c, &cfg), 0);
    const double vb = si.v_base_v, wb = si.w_base_rad_s, dv = 10.0; /* a 10 V deviation */
    const dtc_meas_t me = {0, 0, 0, q(si.vdc_v / vb), q((0.5 * si.vdc_v + dv) / vb), 0U};
    const double l_allow = si.ls_h / 8.0;
    for (double rpm = 0.0; rpm <= 3000.0; rpm += 50.0) {
        const double w = rpm * M_PI / 30.0 * (double)si.pole_pairs;
        c.speed_iq = q((rpm > 1000.0 ? 1.0 : -1.0) * w / wb); /* either direction */
        dtc_vmid_beta(&c);
        const double beta = 1.0 - d(dtc_vmid_dev(&c, &me)) * vb / dv;
        assert_true(beta >= -1e-5 && beta <= 1.0 / 16.0 + 1e-5);
        if (w > 0.0) {
            const double l_err = beta / (3.0 * si.c_dc_f * w * w);
            assert_true(l_err <= l_allow * 1.002 + 1e-12);
            if (beta < 1.0 / 16.0 - 1e-4 && rpm >= 50.0) {
                assert_true(l_err >= l_allow * 0.99);
            }
            if (l_allow * 3.0 * si.c_dc_f * w * w >= 1.0 / 16.0 * 1.001) {
                assert_true(fabs(beta - 1.0 / 16.0) < 1e-5);
            }
        }
        if (rpm == 200.0) {
            print_message("restoring beta at 200 rpm %.5f (inductance error %.3f mH, l_s / 8 = %.3f mH)\n", beta,
                          1e3 * beta / (3.0 * si.c_dc_f * w * w), 1e3 * l_allow);
        }
    }
    /* the derived hand-over keeps the voltage model where beta covers the link sensor's
     * tolerance, down to the speed it hands back at, (1 - hysteresis) of it */
    const double wb2 = (1.0 - si.handover_hyst_frac) * dtc_handover_default_rpm(&si) * M_PI / 30.0 * (double)si.pole_pairs;
    assert_true(fmin(1.0 / 16.0, dtc_vmid_beta_k(&si) * wb2 * wb2) >= 0.02 + 1.0 / si.vdc_v - 1e-9);
    /* no restoring term off the FSTP voltage model */
    si.estimator = DTC_EST_CURRENT;
    assert_int_equal(dtc_config_from_si(&si, &cfg, NULL, 0), 0);
    assert_int_equal(cfg.u.pm_dtc.est.vmid_beta_s_iq, 0);
}

/* The law's reconstruction takes the mid-point as V_dc/2 + (1 - beta) d (dtc_step): two laws in
 * the same state, one step with the mid-point d above V_dc/2 and one at V_dc/2, differ in the
 * estimated flux by the low-pass's input gain times the FSTP reconstruction of that difference,
 * (2/3)(1 - beta) d on v_alpha (Hoang eqs. 1-5 with phase A on the mid-point), turned by the
 * low-pass correction (1 - j r) (lpfcorr.h). At 1500 rpm beta = 1/16. */
static void test_reconstruction_takes_the_restored_mid_point(void **state)
{
    (void)state;
    dtc_config_si_t si;
    dtc_config_t cfg;
    dtc_t c1, c2;
    dtc_out_t o1, o2;
    dtc_config_si_defaults(&si);
    si.fstp_vmid_measured = 1;
    si.vmid_cal = 1;
    assert_int_equal(dtc_config_from_si(&si, &cfg, NULL, 0), 0);
    assert_true(cfg.u.pm_dtc.est.vmid_beta_s_iq > 0);
    assert_int_equal(dtc_init(&c1, &cfg), 0);
    const double vb = si.v_base_v, d_v = 10.0;
    dtc_meas_t m = {0, q(0.2), q(-0.2), q(si.vdc_v / vb), q(0.5 * si.vdc_v / vb), 0U};
    dtc_step(&c1, &m, &o1); /* primes the speed measurement, seeds the estimator */
    c1.on_cm = 0U;
    c1.speed_iq = q(1500.0 * M_PI / 30.0 / si.w_base_rad_s);
    dtc_vmid_beta(&c1);
    dtc_lpf_r(&c1);
    c1.div_cnt = 1U; /* no speed tick in the compared step */
    c2 = c1;
    dtc_step(&c1, &m, &o1);
    m.vmid_iq = q((0.5 * si.vdc_v + d_v) / vb);
    dtc_step(&c2, &m, &o2);
    const double beta = d(c1.vmid_beta_iq), r = d(c1.lpf_r_iq);
    const double k_in = (double)cfg.est.k_in_q31 / 2147483648.0;
    const double dva = (2.0 / 3.0) * (1.0 - beta) * d_v / vb;
    const double da = d(o2.psi_alpha_iq) - d(o1.psi_alpha_iq), db = d(o2.psi_beta_iq) - d(o1.psi_beta_iq);
    print_message("mid-point 10 V up at 1500 rpm: beta %.4f, flux step %.3e / %.3e pu (expected %.3e / %.3e)\n",
                  beta, da, db, k_in * dva, -k_in * r * dva);
    assert_true(fabs(beta - 1.0 / 16.0) < 1e-6);
    assert_true(fabs(da - k_in * dva) < 0.01 * k_in * dva);
    assert_true(fabs(db + k_in * r * dva) < 0.01 * k_in * dva + 4.0 / 16777216.0);
}

UNIT_TEST_MAIN("dtc dcsupp", NULL,
               cmocka_unit_test(test_dc_error_removed_at_w_over_20),
               cmocka_unit_test(test_restoring_beta_follows_the_speed),
               cmocka_unit_test(test_reconstruction_takes_the_restored_mid_point))
