/*
 * test_dtc_flux_est.c - stator-flux estimators (Hoang eqs. 8-9 and 15-16 with the low-pass).
 *
 * Current model: matches Hoang eqs. 8-9 to the LSB level over angle and current sweeps.
 * Voltage model: one step against the double recursion (LSB), trajectories (SNR), and tracking
 * of the analytic flux of a synthetic sinusoidal steady state at 1500 rpm and 100 rpm. The
 * low-pass in place of the integrator has a KNOWN error at electrical speed w:
 *     psi_est = jw / (jw + w_c) * psi    (gain w/sqrt(w^2+w_c^2), phase lead atan(w_c/w))
 * which at 100 rpm (w = 10.47 rad/s, w_c = 5 rad/s) is -9.8 % in magnitude and +25.5 deg: the
 * test asserts the estimate equals that filtered flux (the exact discrete-time response)
 * within tight bounds, and that the raw error against the true flux is the predicted one.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <complex.h>
#include <math.h>

#include "dtc.h"
#include "dtc_config_si.h"
#include "dtc_ref.h"
#include "fixtest.h"
#include "flux_est.h"

#define LSB (1.0 / 16777216.0)
#define Q15LSB (1.0 / 32768.0)

static dtc_config_t g_cfg;
static double g_wbase, g_tspu;

static int setup(void **state)
{
    (void)state;
    dtc_config_si_t si;
    dtc_config_si_defaults(&si);
    if (dtc_config_from_si(&si, &g_cfg, NULL, 0) != DTC_SI_OK) {
        return -1;
    }
    g_wbase = si.w_base_rad_s;
    g_tspu = si.ts_s * si.w_base_rad_s;
    return 0;
}

static void params_from_cfg(flux_est_params_t *p, uint16_t est)
{
    p->estimator = est;
    p->k_in_q31 = g_cfg.est.k_in_q31;
    p->k_leak_q31 = g_cfg.est.k_leak_q31;
    p->rs_iq = g_cfg.machine.rs_iq;
    p->ls_iq = g_cfg.u.pm_dtc.machine.ls_iq;
    p->psi_m_iq = g_cfg.u.pm_dtc.machine.psi_m_iq;
    p->enc_gain_q16 = g_cfg.board.enc_gain_q16;
    p->enc_offset = g_cfg.board.enc_offset;
    p->dl_iq = 0; /* the surface PM of Hoang Table VIII */
    p->inv_lq_iq = g_cfg.u.pm_dtc.machine.inv_ls_iq;
}

static void test_current_model_matches_eqs_8_9(void **state)
{
    (void)state;
    flux_est_params_t p;
    flux_est_t s;
    params_from_cfg(&p, DTC_EST_CURRENT);
    const double ls = fixtest_iq_to_d(p.ls_iq), psim = fixtest_iq_to_d(p.psi_m_iq);
    double worst_enc = 0.0, worst_ang = 0.0;
    fixtest_acc_t acc;
    fixtest_acc_init(&acc);
    for (int offs = 0; offs < 3; offs++) {
        p.enc_offset = (angle_t)(offs * 21845);
        flux_est_init(&s, &p);
        for (uint16_t count = 0; count < 8000U; count += 7U) {
            double ia = 2.5 * sin(count * 0.013), ib = -1.7 * cos(count * 0.021);
            flux_est_in_t in = {0, 0, fixtest_d_to_iq(ia), fixtest_d_to_iq(ib), count, 0};
            flux_est_step(&s, &in);
            /* exact electrical angle of the count (p = 1, 8000 counts/turn) plus the offset */
            double th = 2.0 * DTC_REF_PI * (count / 8000.0 + p.enc_offset / 65536.0);
            double ra = ls * ia + psim * cos(th), rb = ls * ib + psim * sin(th);
            double ea = fabs(fixtest_iq_to_d(s.psi_alpha_iq) - ra);
            double eb = fabs(fixtest_iq_to_d(s.psi_beta_iq) - rb);
            worst_enc = fmax(worst_enc, fmax(ea, eb));
            fixtest_acc_add(&acc, fixtest_iq_to_d(s.psi_alpha_iq), ra);
            /* with the firmware's own angle, only the arithmetic error remains */
            double tf = 2.0 * DTC_REF_PI * s.theta_e / 65536.0;
            ra = ls * ia + psim * cos(tf);
            rb = ls * ib + psim * sin(tf);
            worst_ang = fmax(worst_ang, fmax(fabs(fixtest_iq_to_d(s.psi_alpha_iq) - ra),
                                             fabs(fixtest_iq_to_d(s.psi_beta_iq) - rb)));
        }
    }
    /* Bound: psi_m times the sine table's own worst error (measured here over every angle;
     * fixmath.h documents 2 Q15 LSB, the table currently reaches 3.5), plus 0.1 Q15 LSB for the
     * IQ products; from counts add the angle truncation (< 1 angle LSB = psi_m*2pi/65536). */
    double sin_err = 0.0;
    for (int a = 0; a < 65536; a++) {
        sin_err = fmax(sin_err, fabs(fixtest_q15_to_d(fix_sin((angle_t)a)) -
                                     sin(2.0 * DTC_REF_PI * a / 65536.0)));
    }
    double bound_ang = psim * sin_err + 0.1 * Q15LSB;
    double bound_enc = bound_ang + psim * 2.0 * DTC_REF_PI / 65536.0;
    print_message("current model: %.3f Q15 LSB (bound %.3f) with the firmware angle, %.3f (bound "
                  "%.3f) from counts; fix_sin worst error %.2f Q15 LSB\n", worst_ang / Q15LSB,
                  bound_ang / Q15LSB, worst_enc / Q15LSB, bound_enc / Q15LSB, sin_err / Q15LSB);
    assert_true(worst_ang <= bound_ang);
    assert_true(worst_enc <= bound_enc);
    assert_true(bound_enc < 4.0 * Q15LSB); /* "LSB level": a few Q15 LSB of flux */
    fixtest_assert_snr(&acc, 80.0, "current model psi_alpha");
}

static void test_encoder_angle(void **state)
{
    (void)state;
    /* count -> angle: 8.192 LSB/count (p = 1); 4000 counts = half a turn; 8000 wraps to 0. */
    assert_int_equal(flux_est_angle(0U, g_cfg.board.enc_gain_q16, 0U), 0U);
    assert_int_equal(flux_est_angle(4000U, g_cfg.board.enc_gain_q16, 0U), 32768U);
    assert_int_equal(flux_est_angle(2000U, g_cfg.board.enc_gain_q16, 100U), 16384U + 100U);
    assert_int_equal(flux_est_angle(8000U, g_cfg.board.enc_gain_q16, 0U), 0U);
    /* two pole pairs: the electrical angle turns twice per revolution */
    uint32_t g2 = 1073742U; /* 65536*65536*2/8000 = 1073741.8, rounded */
    assert_int_equal(flux_est_angle(2000U, g2, 0U), 32768U);
    for (uint16_t c = 0; c < 8000U; c++) {
        double exact = fmod(c * 8.192, 65536.0);
        double got = flux_est_angle(c, g_cfg.board.enc_gain_q16, 0U);
        /* truncation (< 1 LSB) and the Q16 rounding of the gain (< 0.5/65536 LSB per count) */
        assert_true(got <= exact + c * 0.5 / 65536.0 && got > exact - 1.0 - c * 0.5 / 65536.0);
    }
}

static void test_lpf_step_lsb_and_saturation(void **state)
{
    (void)state;
    const double kin = fixtest_q31_to_d(g_cfg.est.k_in_q31), kl = fixtest_q31_to_d(g_cfg.est.k_leak_q31);
    for (int n = 0; n < 5000; n++) {
        double psi = -3.0 + 6.0 * n / 4999.0, e = 2.0 * sin(n * 0.37);
        iq_t pq = fixtest_d_to_iq(psi), eq = fixtest_d_to_iq(e);
        double ref = fixtest_iq_to_d(pq) + kin * fixtest_iq_to_d(eq) - kl * fixtest_iq_to_d(pq);
        fixtest_assert_lsb(fixtest_iq_to_d(flux_est_lpf(pq, eq, g_cfg.est.k_in_q31, g_cfg.est.k_leak_q31)),
                           ref, LSB, 0.5, "lpf one step");
    }
    /* saturation at both ends, no wrap */
    assert_int_equal(flux_est_lpf(IQ_MAX, IQ_MAX, Q31_MAX, 1), IQ_MAX);
    assert_int_equal(flux_est_lpf(IQ_MIN, IQ_MIN, Q31_MAX, 1), IQ_MIN);
    assert_true(flux_est_lpf(IQ_MAX - 5, IQ(10.0), g_cfg.est.k_in_q31, 0 + 1) == IQ_MAX);
}

/* Runs the voltage model on a synthetic steady state at electrical speed w_pu: surface PM with
 * i = j*iq*e^{j theta} (q-axis current), psi = psi_m e^{j theta} + ls i, v = rs i + j w psi.
 * Returns worst |est - filtered| and |est - true| relative to |psi| over the last turn. */
static void run_vm(double w_pu, double iq_pu, double *err_filtered, double *err_true,
                   double *err_compensated, fixtest_acc_t *acc)
{
    flux_est_params_t p;
    flux_est_t s;
    params_from_cfg(&p, DTC_EST_VOLTAGE);
    flux_est_init(&s, &p);
    const double rs = fixtest_iq_to_d(p.rs_iq), ls = fixtest_iq_to_d(p.ls_iq);
    const double psim = fixtest_iq_to_d(p.psi_m_iq);
    const double kin = fixtest_q31_to_d(p.k_in_q31), a = 1.0 - fixtest_q31_to_d(p.k_leak_q31);
    const double wc_pu = 5.0 / g_wbase;
    const double complex Psi = psim + ls * I * iq_pu, Icur = I * iq_pu;
    const double complex E = rs * Icur + I * w_pu * Psi - rs * Icur; /* e = v - rs i */
    const double dth = w_pu * g_tspu;
    /* exact discrete steady-state response of psi[k+1] = a psi[k] + kin e[k] to e = E z^k */
    const double complex z = cexp(I * dth), H = kin / (z - a);
    /* run 14 LPF time constants (transient e^-14 = 8e-7), then measure over one electrical turn */
    long n_settle = (long)(14.0 / (5.0 * 50e-6)), n_turn = (long)(2.0 * DTC_REF_PI / dth) + 1;
    *err_filtered = *err_true = *err_compensated = 0.0;
    for (long k = 0; k < n_settle + n_turn; k++) {
        double th = dth * (double)k;
        double complex rot = cexp(I * th);
        double complex v = (rs * Icur + I * w_pu * Psi) * rot, i = Icur * rot;
        flux_est_in_t in = {fixtest_d_to_iq(creal(v)), fixtest_d_to_iq(cimag(v)),
                            fixtest_d_to_iq(creal(i)), fixtest_d_to_iq(cimag(i)), 0U, 0};
        flux_est_step(&s, &in);
        if (k >= n_settle) {
            /* the state after step k holds psi[k+1] */
            double complex est = fixtest_iq_to_d(s.psi_alpha_iq) + I * fixtest_iq_to_d(s.psi_beta_iq);
            double complex filt = H * E * rot * z;
            double complex truth = Psi * rot * z;
            /* undo the continuous LPF's known gain/phase: (jw + wc)/jw */
            double complex comp = est * (I * w_pu + wc_pu) / (I * w_pu);
            *err_filtered = fmax(*err_filtered, cabs(est - filt) / cabs(Psi));
            *err_true = fmax(*err_true, cabs(est - truth) / cabs(Psi));
            *err_compensated = fmax(*err_compensated, cabs(comp - truth) / cabs(Psi));
            if (acc != NULL) {
                fixtest_acc_add(acc, creal(est), creal(filt));
                fixtest_acc_add(acc, cimag(est), cimag(filt));
            }
        }
    }
}

static void test_voltage_model_1500rpm(void **state)
{
    (void)state;
    double ef, et, ec;
    fixtest_acc_t acc;
    fixtest_acc_init(&acc);
    run_vm(0.5, 1.0, &ef, &et, &ec, &acc); /* 1500 rpm, rated current */
    print_message("1500 rpm: |est-filtered| %.2e, |est-true| %.2e, |compensated-true| %.2e (rel)\n",
                  ef, et, ec);
    /* Fixed point vs the exact discrete response: the once-per-step rounding (<= 0.5 LSB) is
     * summed by the low-pass with gain 1/k_leak = 4000 in the worst case: 2000 LSB = 1.2e-4 pu =
     * 2.9e-4 of |psi| (the Q24 dead band, see flux_est.h); input rounding adds 32 LSB. */
    assert_true(ef < 2e-5); /* measured 1e-6: the rounding errors of a moving input average */
    /* Against the true flux: LPF error wc/|jw + wc| = 5/157 = 3.2 % (phase 1.8 deg), plus the
     * half-sample delay of the held input, w Ts/2 = 0.4 %. */
    assert_true(et < 0.032 + 0.005 && et > 0.025);
    /* Undoing the continuous LPF leaves the half-sample ZOH term only. */
    assert_true(ec < 0.005);
    fixtest_assert_snr(&acc, 100.0, "voltage model 1500 rpm vs exact discrete response");
}

static void test_voltage_model_100rpm(void **state)
{
    (void)state;
    double ef, et, ec;
    fixtest_acc_t acc;
    fixtest_acc_init(&acc);
    run_vm(1.0 / 30.0, 1.0, &ef, &et, &ec, &acc); /* 100 rpm */
    print_message("100 rpm: |est-filtered| %.2e, |est-true| %.2e, |compensated-true| %.2e (rel)\n",
                  ef, et, ec);
    assert_true(ef < 2e-5);
    /* Known LPF error at 10.47 rad/s: |wc/(jw + wc)| = 5/11.6 = 43 % vector error (-9.8 % in
     * magnitude, 25.5 deg of phase lead). The estimate shows exactly that, no more. */
    const double w = 100.0 / 60.0 * 2.0 * DTC_REF_PI, pred = 5.0 / hypot(w, 5.0);
    assert_true(fabs(et - pred) < 0.005);
    assert_true(ec < 0.001);
    fixtest_assert_snr(&acc, 100.0, "voltage model 100 rpm vs exact discrete response");
}

static void test_voltage_model_offset_does_not_drift(void **state)
{
    (void)state;
    /* A 1 % current-sensor-like DC error in e would ramp a pure integrator without bound; the
     * low-pass settles at e/w_c,pu (Hoang section IV, [27]). 0.01 pu / (5/314.16) = 0.628 pu. */
    flux_est_params_t p;
    flux_est_t s;
    params_from_cfg(&p, DTC_EST_VOLTAGE);
    p.rs_iq = 0;
    flux_est_init(&s, &p);
    flux_est_in_t in = {IQ(0.01), IQ(-0.01), 0, 0, 0U, 0};
    for (long k = 0; k < 200000; k++) { /* 10 s = 50 time constants */
        flux_est_step(&s, &in);
    }
    const double expect = 0.01 / (5.0 / g_wbase);
    /* the equilibrium of the quantised constants, k_in * e / k_leak, is within 1e-5 of it */
    const double eq = fixtest_iq_to_d(IQ(0.01)) * (double)p.k_in_q31 / (double)p.k_leak_q31;
    assert_true(fabs(eq - expect) < 1e-5);
    /* Within the Q24 dead band of the rounded update: 0.5 LSB / k_leak = 2000 LSB. */
    fixtest_assert_lsb(fixtest_iq_to_d(s.psi_alpha_iq), eq, LSB, 2001.0, "offset settles");
    fixtest_assert_lsb(fixtest_iq_to_d(s.psi_beta_iq), -eq, LSB, 2001.0, "offset settles");
    flux_est_reset(&s);
    assert_int_equal(s.psi_alpha_iq, 0);
}

UNIT_TEST_MAIN("dtc flux est", setup,
               cmocka_unit_test(test_current_model_matches_eqs_8_9),
               cmocka_unit_test(test_encoder_angle),
               cmocka_unit_test(test_lpf_step_lsb_and_saturation),
               cmocka_unit_test(test_voltage_model_1500rpm),
               cmocka_unit_test(test_voltage_model_100rpm),
               cmocka_unit_test(test_voltage_model_offset_does_not_drift))
