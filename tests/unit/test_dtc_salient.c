/*
 * test_dtc_salient.c - the PM law on a salient machine (l_q != l_d): the current model's q-axis
 * term (flux_est.h) and the actuation-delay prediction (pm_salient.c dtc_predict_salient), each
 * against a double-precision reference of the rotor-frame model psi_d = l_d i_d + psi_m, psi_q = l_q i_q
 * (Hoang eqs. 8-9 are its l_d = l_q case), and the prediction against the machine itself: the
 * salient machine's stator equations (Hoang eqs. 6-7) integrated over one period.
 *
 * The machine: Hoang Table VIII with L_q = 2 L_d (the converter's pu values, so the firmware and
 * the references share them).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>

#include "dtc.h"
#include "dtc_config_si.h"
#include "dtc_internal.h"
#include "dtc_ref.h"
#include "fixtest.h"
#include "flux_est.h"

#define LSB (1.0 / 16777216.0)

static dtc_config_t g_cfg;
static dtc_t g_c;
static double g_ld, g_lq, g_psim, g_rs, g_tspu, g_sin_err;

static int setup(void **state)
{
    (void)state;
    dtc_config_si_t si;
    dtc_config_si_defaults(&si);
    si.lq_h = 2.0 * si.ls_h;
    if (dtc_config_from_si(&si, &g_cfg, NULL, 0) != DTC_SI_OK || dtc_init(&g_c, &g_cfg) != DTC_OK) {
        return -1;
    }
    g_ld = fixtest_iq_to_d(g_cfg.u.pm_dtc.machine.ls_iq);
    g_lq = fixtest_iq_to_d(g_cfg.u.pm_dtc.machine.lq_iq);
    g_psim = fixtest_iq_to_d(g_cfg.u.pm_dtc.machine.psi_m_iq);
    g_rs = fixtest_iq_to_d(g_cfg.machine.rs_iq);
    g_tspu = fixtest_iq_to_d(g_cfg.board.ts_pu_iq);
    /* the sine table's own worst error (fixmath.h: a few Q15 LSB) */
    g_sin_err = 0.0;
    for (int a = 0; a < 65536; a++) {
        g_sin_err = fmax(g_sin_err, fabs(fixtest_q15_to_d(fix_sin((angle_t)a)) - sin(2.0 * DTC_REF_PI * a / 65536.0)));
    }
    return 0;
}

/* The rotor-frame flux of the current (ia, ib) at the angle th, in the stationary frame. */
static void model_flux(double ia, double ib, double th, double *pa, double *pb)
{
    const double c = cos(th), s = sin(th);
    const double id = ia * c + ib * s, iq = -ia * s + ib * c;
    const double pd = g_ld * id + g_psim, pq = g_lq * iq;
    *pa = pd * c - pq * s;
    *pb = pd * s + pq * c;
}

/* Its inverse: the current of the flux (pa, pb) at the angle th. */
static void model_current(double pa, double pb, double th, double *ia, double *ib)
{
    const double c = cos(th), s = sin(th);
    const double id = (pa * c + pb * s - g_psim) / g_ld, iq = (-pa * s + pb * c) / g_lq;
    *ia = id * c - iq * s;
    *ib = id * s + iq * c;
}

/* The current model with l_q = 2 l_d against the rotor-frame model, at the firmware's angle. Bound:
 * the sine table's error on each of the three projections (psi_m, dl i_q, and i_q itself times dl)
 * plus a few IQ LSB of rounded products. */
static void test_current_model_salient(void **state)
{
    (void)state;
    flux_est_t s;
    flux_est_init(&s, &g_c.fe_p);
    assert_true(g_c.fe_p.dl_iq > 0);
    assert_true(fabs(g_lq / g_ld - 2.0) < 1e-5);
    const double dl = fixtest_iq_to_d(g_c.fe_p.dl_iq);
    double worst = 0.0, worst_surface = 0.0, bound = 0.0;
    for (uint16_t count = 0; count < 8000U; count += 7U) {
        const double ia = 2.5 * sin(count * 0.013), ib = -1.7 * cos(count * 0.021);
        flux_est_in_t in = {0, 0, fixtest_d_to_iq(ia), fixtest_d_to_iq(ib), count, 0};
        flux_est_seed(&s, &in);
        const double th = 2.0 * DTC_REF_PI * s.theta_e / 65536.0;
        double ra, rb;
        model_flux(ia, ib, th, &ra, &rb);
        worst = fmax(worst, fmax(fabs(fixtest_iq_to_d(s.psi_alpha_iq) - ra),
                                 fabs(fixtest_iq_to_d(s.psi_beta_iq) - rb)));
        /* Hoang eqs. 8-9 with l_s = l_d: what the surface model would make of this machine */
        worst_surface = fmax(worst_surface, fmax(fabs(g_ld * ia + g_psim * cos(th) - ra),
                                                 fabs(g_ld * ib + g_psim * sin(th) - rb)));
        bound = fmax(bound, g_sin_err * (g_psim + 3.0 * dl * hypot(ia, ib)) + 8.0 * LSB);
    }
    print_message("salient current model: worst %.3g pu (bound %.3g); Hoang eqs. 8-9 on L_d: %.3g pu\n", worst, bound,
                  worst_surface);
    assert_true(worst <= bound);
    /* the q axis's flux error of the surface model is dl |i_q|: up to 2.5 x L_d here */
    assert_true(worst_surface > 100.0 * bound);
}

/* One period of the salient machine (Hoang eqs. 6-7 with the rotor-frame model), the stator
 * voltage v constant, the rotor turning at w (pu, with t in pu of 1 / w_b): RK4, 400 sub-steps. */
static void machine_period(double va, double vb, double w, double th0, double *pa, double *pb)
{
    const int n = 400;
    const double h = g_tspu / n;
    for (int k = 0; k < n; k++) {
        const double t = k * h;
        double ka[4], kb[4];
        for (int st = 0; st < 4; st++) {
            const double f = st == 0 ? 0.0 : st == 3 ? 1.0 : 0.5;
            const double qa = *pa + (st == 0 ? 0.0 : f * h * ka[st - 1]);
            const double qb = *pb + (st == 0 ? 0.0 : f * h * kb[st - 1]);
            double ia, ib;
            model_current(qa, qb, th0 + w * (t + f * h), &ia, &ib);
            ka[st] = va - g_rs * ia;
            kb[st] = vb - g_rs * ib;
        }
        *pa += h * (ka[0] + 2.0 * ka[1] + 2.0 * ka[2] + ka[3]) / 6.0;
        *pb += h * (kb[0] + 2.0 * kb[1] + 2.0 * kb[2] + kb[3]) / 6.0;
    }
}

/* dtc_predict_salient on the salient machine: against the double of the same first-order step (the
 * arithmetic) and against the machine integrated over the period (the physics: the salient step's
 * error is second order in the period, far below the error of the surface step on l_d, which
 * misses the q axis's inductance). */
static void test_prediction_salient(void **state)
{
    (void)state;
    dtc_t *const c = &g_c;
    /* 1/l_q as dtc_init formed it (Newton steps: a few IQ LSB of the reciprocal) */
    assert_true(fabs(fixtest_iq_to_d(c->fe_p.inv_lq_iq) - 1.0 / g_lq) <= 4.0 * LSB);
    double worst_arith = 0.0, bound = 0.0, e_sal = 0.0, e_surf = 0.0;
    for (int k = 0; k < 500; k++) {
        const double th = 2.0 * DTC_REF_PI * k / 500.0 * 7.0;
        const double w = 1.2 * sin(k * 0.37);                                   /* up to 1.2 x rated speed */
        const double i_d = 0.8 * cos(k * 0.11), i_q = 1.5 * sin(k * 0.23);       /* pu */
        const double va = 0.55 * cos(k * 0.71), vb = 0.55 * sin(k * 0.71 + 0.3); /* within the link */
        const angle_t a = (angle_t)lround(fmod(th, 2.0 * DTC_REF_PI) / (2.0 * DTC_REF_PI) * 65536.0);
        const double thq = 2.0 * DTC_REF_PI * a / 65536.0;
        const double ia = i_d * cos(thq) - i_q * sin(thq), ib = i_d * sin(thq) + i_q * cos(thq);
        double pa, pb;
        model_flux(ia, ib, thq, &pa, &pb);
        clarke_out_t i;
        clarke_inv(fixtest_d_to_iq(ia), fixtest_d_to_iq(ib), &i);
        const double iad = fixtest_iq_to_d(i.i_alpha_iq), ibd = fixtest_iq_to_d(i.i_beta_iq);
        c->fe.theta_e = a;
        c->wts_iq = iq_mpy(fixtest_d_to_iq(w), g_cfg.board.ts_pu_iq);
        c->v1_alpha_iq = fixtest_d_to_iq(va);
        c->v1_beta_iq = fixtest_d_to_iq(vb);
        c->v1f_alpha_iq = c->v1f_beta_iq = c->v1d_alpha_iq = c->v1d_beta_iq = 0;
        c->ri_alpha_iq = iq_mpy(g_cfg.machine.rs_iq, i.i_alpha_iq);
        c->ri_beta_iq = iq_mpy(g_cfg.machine.rs_iq, i.i_beta_iq);
        iq_t psa = fixtest_d_to_iq(pa), psb = fixtest_d_to_iq(pb), te;
        const double psad = fixtest_iq_to_d(psa), psbd = fixtest_iq_to_d(psb);
        dtc_predict_salient(c, &i, &psa, &psb, &te); /* dtc_step calls it in place of dtc_predict */
        const double fa = fixtest_iq_to_d(c->i1.i_alpha_iq), fb = fixtest_iq_to_d(c->i1.i_beta_iq);

        /* the first-order step in double (dtc_predict_salient's comment) */
        const double wts = fixtest_iq_to_d(c->wts_iq);
        const double dpa = g_tspu * (va - g_rs * iad), dpb = g_tspu * (vb - g_rs * ibd);
        const double xa = dpa + wts * psbd, xb = dpb - wts * psad;
        const double cs = cos(thq), sn = sin(thq);
        const double yd = xa * cs + xb * sn, yq = -xa * sn + xb * cs;
        const double ea = iad + (yd / g_ld) * cs - (yq / g_lq) * sn - wts * ibd; /* exact 1/l_q */
        const double eb = ibd + (yd / g_ld) * sn + (yq / g_lq) * cs + wts * iad;
        /* the surface step on l_d (Hoang eqs. 6-9 with l_s = l_d) */
        const double sa = iad + (xa + wts * g_ld * ibd) / g_ld, sb = ibd + (xb - wts * g_ld * iad) / g_ld;
        worst_arith = fmax(worst_arith, fmax(fabs(fa - ea), fabs(fb - eb)));
        /* rounded products times 1 / l_d (each inner term within a few LSB), and the sine table's
         * error on the projections of x into the rotor frame and back, |y| = |x|, times 1 / l_d */
        bound = fmax(bound, 16.0 * LSB / g_ld + 4.0 * g_sin_err * hypot(xa, xb) / g_ld);

        /* the machine over the period from the same state */
        double ma = pa, mb = pb, ta, tb;
        machine_period(va, vb, w, thq, &ma, &mb);
        model_current(ma, mb, thq + w * g_tspu, &ta, &tb);
        e_sal = fmax(e_sal, hypot(ea - ta, eb - tb));
        e_surf = fmax(e_surf, hypot(sa - ta, sb - tb));
    }
    print_message("salient prediction: arithmetic %.3g pu (bound %.3g); against the machine %.3g pu, the surface "
                  "step on L_d %.3g pu\n",
                  worst_arith, bound, e_sal, e_surf);
    assert_true(worst_arith <= bound);
    assert_true(e_sal < 0.1 * e_surf);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_current_model_salient),
                                       cmocka_unit_test(test_prediction_salient)};
    return cmocka_run_group_tests(tests, setup, NULL);
}
