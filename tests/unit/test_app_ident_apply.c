/*
 * test_app_ident_apply.c - the identification's results into the configuration
 * (firmware/app/app_ident_apply.c app_ident_derive) against double precision: a finished PM
 * identification is made from a machine's SI values (app_ident.h formats), the configuration in
 * force from the same machine 30 % off; each derived row is compared with the exact double of its
 * formula on the same raw inputs (the rounding) and with the host converter's value for the true
 * machine (dtc_config_from_si: the quantisation of the inputs), and the result passes the law's
 * check. The refusals are named.
 *
 * An induction machine likewise (setup_im, check_im_rows): the identification's R_s, R_r, sigma L_s
 * and L_s (turning: the spin's L_s i_d over i_d) of the 4 kW machine (L_ls = L_lr, the split the
 * apply takes), the configuration in force from R_s, R_r, L_m 30 % high and the leakages 30 % low;
 * every derived IM row against its double formula on the same integer inputs (half an LSB) and
 * against the converter's value for the true machine (the inputs' quantisation: ts_pu's 2.4e-6).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "app_ident.h"
#include "dtc_config_si.h"
#include "law.h"

#define IQ1 16777216.0
#define PI 3.14159265358979323846

static dtc_config_si_t g_si;  /* the true machine */
static dtc_config_t g_ref;    /* the host converter's configuration of the true machine */
static dtc_config_t g_in;     /* the configuration in force: R_s, L_s, psi_m, T_d 30 % off */
static dtc_config_t g_out;
static app_ident_t g_d;
static dtc_bases_t g_b;

static int32_t iq_of(double x) { return (int32_t)lround(x * IQ1); }

/* The configuration from si, failing the test when the converter refuses it. */
static void convert(const dtc_config_si_t *si, dtc_config_t *cfg)
{
    char msg[256];
    if (dtc_config_from_si(si, cfg, msg, sizeof msg) != DTC_SI_OK) {
        fail_msg("configuration refused: %s", msg);
    }
}

/* The converter's configurations of the true machine g_si (g_ref, and its bases g_b) and of wrong
 * (g_in, the configuration in force), wrong's R_s and J 30 % high and its encoder forward besides
 * the caller's changes. */
static void convert_both(dtc_config_si_t *wrong)
{
    convert(&g_si, &g_ref);
    dtc_bases_from_si(&g_si, &g_b);
    wrong->rs_ohm = 1.3 * g_si.rs_ohm;
    wrong->inertia_kgm2 = 1.3 * g_si.inertia_kgm2;
    wrong->enc_reversed = 0;
    convert(wrong, &g_in);
}

/* res.j_q12 of the true J for the torque constant kt_nm_a (N.m/A): J / k_t in pu current x Ts^2
 * per count (a count = 2 pi / counts mechanical rad), Q12 (app_ident.h). */
static int32_t j_q12_of(double kt_nm_a)
{
    const double rad = 2.0 * PI / (4.0 * g_si.enc_lines);
    return (int32_t)lround(4096.0 * g_si.inertia_kgm2 * rad / (kt_nm_a * g_b.i_base_a * g_si.ts_s * g_si.ts_s));
}

/* The rows designed from J (app_ident_apply.c derive_speed) against the converter's for the true
 * J: the inputs' quantisation (j_q12's 1e-7, ts_pu's 2.4e-6 squared in Jn: 5e-6). */
static void check_speed_rows(void)
{
    const iq_t got[3] = {g_out.speed.kp_iq, g_out.speed.ki_ts_iq, g_out.prot.enc_freeze_speed_iq};
    const iq_t want[3] = {g_ref.speed.kp_iq, g_ref.speed.ki_ts_iq, g_ref.prot.enc_freeze_speed_iq};
    const char *name[3] = {"kp_iq", "ki_ts_iq", "enc_freeze_speed_iq"};
    int k;
    assert_true(g_in.speed.kp_iq != g_ref.speed.kp_iq); /* the configuration in force was 30 % off */
    for (k = 0; k < 3; k++) {
        const double e = fabs((double)got[k] - (double)want[k]);
        print_message("%s from J: %d against the converter's %d (%.0f LSB)\n", name[k], got[k], want[k], e);
        if (!(e <= 1.0 + 1e-5 * fabs((double)want[k]))) {
            fail_msg("%s: %d against the converter's %d", name[k], got[k], want[k]);
        }
    }
}

/* A finished identification of the machine g_si on topology topo, offset off_e (electrical rad at
 * raw count 0) and direction rev, as app_ident_results.c leaves it (app_ident.h units). */
static void setup(int topo, double off_e, int rev)
{
    dtc_config_si_t wrong;
    double ts, z_b, g, v0;
    dtc_config_si_defaults(&g_si);
    ts = g_si.ts_s;
    g_si.topology = topo;
    if (topo == DTC_TOPO_SSTP) {
        g_si.compensation = DTC_COMP_SSTP;
    }
    g_si.enc_offset_rad = off_e;
    g_si.enc_reversed = rev;
    wrong = g_si;
    wrong.ls_h *= 0.7;
    wrong.psi_m_wb *= 1.3;
    wrong.dead_time_s *= 0.7;
    wrong.enc_offset_rad = 0.0;
    convert_both(&wrong);
    memset(&g_d, 0, sizeof g_d);
    z_b = g_b.z_base_ohm;
    g_d.step = APP_IDENT_DONE;
    g_d.res.axis = topo == DTC_TOPO_FSTP ? 16384U : 0U;
    g_d.res.r_iq = iq_of((g_si.rs_ohm + g_si.r_on_ohm) / z_b);
    g_d.res.l_ts_iq = iq_of(g_si.ls_h / (z_b * ts));
    g_d.res.psi_iq = iq_of(g_si.psi_m_wb / g_b.psi_base_wb);
    /* V_0 = g (V_CE + V_d + 2 V_dc T_d / T_s) (docs/commissioning.md section 1) */
    g = topo == DTC_TOPO_FSTP ? 1.0 / sqrt(3.0) : 2.0 / 3.0;
    v0 = g * (g_si.v_ce_v + g_si.v_d_v + 2.0 * g_si.vdc_v * g_si.dead_time_s / ts);
    g_d.res.v0_iq = iq_of(v0 / g_b.v_base_v);
    g_d.vdc_iq = iq_of(g_si.vdc_v / g_b.v_base_v);
    g_d.res.pole_pairs = (uint16_t)g_si.pole_pairs;
    g_d.res.enc_reversed = (uint16_t)rev;
    g_d.res.j_q12 = j_q12_of(1.5 * g_si.pole_pairs * g_si.psi_m_wb);
    {
        double t = off_e / (2.0 * PI);
        t -= floor(t);
        g_d.res.enc_offset = (angle_t)((uint32_t)lround(t * 65536.0) & 0xFFFFU);
    }
}

/* Each derived row against its formula in double on the same raw inputs, and against the host
 * converter's value of the true machine. */
static void check_rows(void)
{
    const double ls_raw = (double)g_d.res.l_ts_iq * (double)g_in.board.ts_pu_iq / IQ1;
    const double n = (double)g_in.board.enc_counts;
    const double gain = ldexp((double)g_d.res.pole_pairs, 32) / n;
    const char *f = NULL;
    int16_t rc;
    assert_int_equal(app_ident_derive(&g_d, &g_in, &g_out), APP_IDENT_APPLY_OK);
    rc = law_check(&g_out, &f);
    if (rc != 0) {
        fail_msg("law_check refused the applied configuration: %d (%s)", rc, f != NULL ? f : "");
    }
    /* R_s: the slope less R_on, exact; the converter's within the inputs' rounding */
    assert_int_equal(g_out.machine.rs_iq, g_d.res.r_iq - g_in.board.r_on_iq);
    assert_true(labs((long)g_out.machine.rs_iq - (long)g_ref.machine.rs_iq) <= 2L);
    /* L_s: the product rounded to nearest */
    assert_true(fabs((double)g_out.u.pm_dtc.machine.ls_iq - ls_raw) <= 0.5);
    /* the converter's L_s within ts_pu_iq's quantisation (half an LSB of ~2.6e5: 2e-6) plus l_ts's */
    assert_true(fabs((double)g_out.u.pm_dtc.machine.ls_iq / (double)g_ref.u.pm_dtc.machine.ls_iq - 1.0) < 4e-6);
    /* 1 / L_s: 2^48 / ls rounded to nearest */
    assert_true(fabs((double)g_out.u.pm_dtc.machine.inv_ls_iq - ldexp(1.0, 48) / (double)g_out.u.pm_dtc.machine.ls_iq) <= 0.5);
    assert_true(fabs((double)g_out.u.pm_dtc.machine.inv_ls_iq / (double)g_ref.u.pm_dtc.machine.inv_ls_iq - 1.0) < 4e-6);
    /* psi_m: the identified value itself */
    assert_int_equal(g_out.u.pm_dtc.machine.psi_m_iq, g_d.res.psi_iq);
    assert_true(labs((long)g_out.u.pm_dtc.machine.psi_m_iq - (long)g_ref.u.pm_dtc.machine.psi_m_iq) <= 1L);
    /* pole pairs and the encoder gain: p 2^32 / N rounded to nearest, the converter's exactly */
    assert_int_equal(g_out.machine.pole_pairs, g_ref.machine.pole_pairs);
    assert_true(fabs((double)g_out.board.enc_gain_q16 - gain) <= 0.5);
    assert_int_equal(g_out.board.enc_gain_q16, g_ref.board.enc_gain_q16);
    /* direction and offset as the converter writes them for the true offset (one LSB: the offset's
     * own rounding into res.enc_offset) */
    assert_int_equal(g_out.board.enc_reversed, g_ref.board.enc_reversed);
    assert_true(abs((int)(int16_t)(uint16_t)(g_out.board.enc_offset - g_ref.board.enc_offset)) <= 1);
    /* dead time over the period, Q15: the converter's within one LSB */
    assert_true(abs((int)g_out.board.td_ts_q15 - (int)g_ref.board.td_ts_q15) <= 1);
    /* the rows not identified are those in force */
    assert_int_equal(g_out.board.v_ce_iq, g_in.board.v_ce_iq);
    assert_int_equal(g_out.board.r_on_iq, g_in.board.r_on_iq);
    check_speed_rows();
}

static void test_fstp_forward(void **state)
{
    (void)state;
    setup(DTC_TOPO_FSTP, 1.0, 0);
    check_rows();
}

static void test_sstp_reversed(void **state)
{
    (void)state;
    setup(DTC_TOPO_SSTP, -2.5 + 2.0 * PI, 1);
    check_rows();
}

/* The identification sees the count the configuration's direction gives it (app_core_step): on a
 * configuration with the encoder reversed, a count found running down means the raw count runs
 * forward. */
static void test_reversed_in_force(void **state)
{
    (void)state;
    setup(DTC_TOPO_SSTP, 0.7, 1);
    g_in.board.enc_reversed = 1U;
    assert_int_equal(app_ident_derive(&g_d, &g_in, &g_out), APP_IDENT_APPLY_OK);
    assert_int_equal(g_out.board.enc_reversed, 0U);
    g_d.res.enc_reversed = 0U;
    assert_int_equal(app_ident_derive(&g_d, &g_in, &g_out), APP_IDENT_APPLY_OK);
    assert_int_equal(g_out.board.enc_reversed, 1U);
    assert_int_equal(g_out.board.enc_offset, g_d.res.enc_offset);
}

/* Another pole-pair count: the gain p 2^32 / N for p = 4. */
static void test_pole_pairs(void **state)
{
    (void)state;
    setup(DTC_TOPO_SSTP, 0.3, 0);
    g_d.res.pole_pairs = 4U;
    assert_int_equal(app_ident_derive(&g_d, &g_in, &g_out), APP_IDENT_APPLY_OK);
    assert_int_equal(g_out.machine.pole_pairs, 4U);
    assert_true(fabs((double)g_out.board.enc_gain_q16 - ldexp(4.0, 32) / (double)g_in.board.enc_counts) <= 0.5);
}

/* The dead time: a negative result (V_0 below the thresholds) is 0; half a period is refused. */
static void test_dead_time_bounds(void **state)
{
    (void)state;
    setup(DTC_TOPO_FSTP, 0.0, 0);
    g_d.res.v0_iq = 0;
    assert_int_equal(app_ident_derive(&g_d, &g_in, &g_out), APP_IDENT_APPLY_OK);
    assert_int_equal(g_out.board.td_ts_q15, 0);
    g_d.res.v0_iq = iq_of(0.6); /* 0.6 sqrt(3) / 2 > 1/2 of a period */
    assert_int_equal(app_ident_derive(&g_d, &g_in, &g_out), APP_IDENT_APPLY_DEADTIME);
}

static void test_refusals(void **state)
{
    (void)state;
    setup(DTC_TOPO_SSTP, 0.0, 0);
    g_d.step = APP_IDENT_SPIN;
    assert_int_equal(app_ident_derive(&g_d, &g_in, &g_out), APP_IDENT_APPLY_NOT_DONE);
    g_d.step = APP_IDENT_FAILED;
    assert_int_equal(app_ident_derive(&g_d, &g_in, &g_out), APP_IDENT_APPLY_NOT_DONE);
    g_d.step = APP_IDENT_DONE;
    g_d.im_on = 1U;
    assert_int_equal(app_ident_derive(&g_d, &g_in, &g_out), APP_IDENT_APPLY_LAW);
    g_d.im_on = 0U;
    g_in.law = DTC_LAW_IM_DTC;
    assert_int_equal(app_ident_derive(&g_d, &g_in, &g_out), APP_IDENT_APPLY_LAW);
    g_in.law = DTC_LAW_PM_DTC;
    g_d.res.r_iq = g_in.board.r_on_iq;
    assert_int_equal(app_ident_derive(&g_d, &g_in, &g_out), APP_IDENT_APPLY_RS);
    setup(DTC_TOPO_SSTP, 0.0, 0);
    g_d.res.l_ts_iq = 1;
    assert_int_equal(app_ident_derive(&g_d, &g_in, &g_out), APP_IDENT_APPLY_LS);
}


/* ---- induction machine ---------------------------------------------------------------------- */

static double g_err_lsb;  /* the largest |row - its double formula| seen, LSB */
static double g_err_conv; /* the largest relative difference from the converter's row */

/* |got - want| <= tol (LSB), the largest kept */
static void near_lsb(const char *row, double got, double want, double tol)
{
    const double e = fabs(got - want);
    if (e > g_err_lsb) {
        g_err_lsb = e;
    }
    if (!(e <= tol)) {
        fail_msg("%s: %.3f against its formula %.3f (%.3f LSB, tolerance %.3f)", row, got, want, e, tol);
    }
}

/* |got / want - 1| <= tol, the largest kept */
static void near_conv(const char *row, double got, double want, double tol)
{
    const double e = fabs(got / want - 1.0);
    if (e > g_err_conv) {
        g_err_conv = e;
    }
    if (!(e <= tol)) {
        fail_msg("%s: %.0f against the converter's %.0f (%.3g relative, tolerance %.3g)", row, got, want, e, tol);
    }
}

/* A finished identification of the IM g_si (law, rotor-flux reference psir_ref_wb, encoder
 * direction rev, pole pairs p) as app_ident_im.c leaves it (app_ident_im.h units); the
 * configuration in force from the same machine with R_s, R_r, L_m 30 % high, L_ls, L_lr 30 % low. */
static void setup_im(int law, double psir_ref_wb, int rev, int p)
{
    dtc_config_si_t wrong;
    double ts, z_b, ls, lr, sls, id;
    dtc_config_si_im_defaults(&g_si);
    g_si.law = law;
    g_si.psir_ref_wb = psir_ref_wb;
    g_si.enc_reversed = rev;
    g_si.pole_pairs = p;
    wrong = g_si;
    wrong.rr_ohm *= 1.3;
    wrong.lm_h *= 1.3;
    wrong.lls_h *= 0.7;
    wrong.llr_h *= 0.7;
    wrong.pole_pairs = 2;
    convert_both(&wrong);
    ts = g_si.ts_s;
    z_b = g_b.z_base_ohm;
    ls = g_si.lls_h + g_si.lm_h;
    lr = g_si.llr_h + g_si.lm_h;
    sls = ls - g_si.lm_h * g_si.lm_h / lr;
    memset(&g_d, 0, sizeof g_d);
    g_d.step = APP_IDENT_DONE;
    g_d.im_on = 1U;
    g_d.res.axis = 0U;
    g_d.res.r_iq = iq_of((g_si.rs_ohm + g_si.r_on_ohm) / z_b);
    g_d.res.v0_iq = iq_of(2.0 / 3.0 * (g_si.v_ce_v + g_si.v_d_v + 2.0 * g_si.vdc_v * g_si.dead_time_s / ts) / g_b.v_base_v);
    g_d.vdc_iq = iq_of(g_si.vdc_v / g_b.v_base_v);
    g_d.res.pole_pairs = (uint16_t)p;
    g_d.res.enc_reversed = (uint16_t)rev;
    g_d.res.im.ls_ts_iq = iq_of(ls / (z_b * ts));
    g_d.res.im.lsig_ts_iq = iq_of(sls / (z_b * ts));
    g_d.res.im.taur_q4 = (int32_t)lround(16.0 * lr / g_si.rr_ohm / ts);
    g_d.res.im.rr_iq = iq_of(g_si.rr_ohm / z_b);
    /* the spin: i_d the stator flux reference over L_s, psi the stator flux L_s i_d */
    id = g_si.flux_ref_wb / ls;
    g_d.res.im.id_iq = iq_of(id / g_b.i_base_a);
    g_d.res.psi_iq = iq_of(ls * ((double)g_d.res.im.id_iq / IQ1 * g_b.i_base_a) / g_b.psi_base_wb);
    /* the spin's J over k_t = 3/2 p L_M i_d (app_ident_im.c), L_M = L_s - sigma L_s */
    g_d.res.j_q12 = j_q12_of(1.5 * p * (ls - sls) * ((double)g_d.res.im.id_iq / IQ1 * g_b.i_base_a));
}

/* Each derived IM row against its double formula on the same integer inputs and against the
 * converter's row for the true machine. */
static void check_im_rows(void)
{
    const dtc_im_cfg_t *o = &g_out.u.im, *r = &g_ref.u.im;
    const double ts = (double)g_in.board.ts_pu_iq;
    const double ls_raw = (double)g_d.res.psi_iq * IQ1 / (double)g_d.res.im.id_iq;
    const double sls_raw = (double)g_d.res.im.lsig_ts_iq * ts / IQ1;
    const char *f = NULL;
    double ls, sls, lm, psir;
    int16_t rc;
    assert_int_equal(app_ident_derive(&g_d, &g_in, &g_out), APP_IDENT_APPLY_OK);
    rc = law_check(&g_out, &f);
    if (rc != 0) {
        fail_msg("law_check refused the applied configuration: %d (%s)", rc, f != NULL ? f : "");
    }
    /* the inputs: sigma L_s and L_s (turning) rounded to nearest */
    near_lsb("sigma_ls_iq", (double)o->machine.sigma_ls_iq, sls_raw, 0.5);
    assert_int_equal(o->machine.sigma_lr_iq, o->machine.sigma_ls_iq);
    sls = (double)o->machine.sigma_ls_iq;
    ls = nearbyint(ls_raw);
    lm = ls - sls;
    /* the T model with L_ls = L_lr: M = sqrt(L_s L_M), L_r/M = L_s/M = sqrt(L_s/L_M), M/L_s */
    near_lsb("m_iq", (double)o->machine.m_iq, sqrt(ls * lm), 0.5);
    near_lsb("kr_iq", (double)o->machine.kr_iq, IQ1 * sqrt(ls / lm), 0.5 + 1e-6);
    assert_int_equal(o->machine.ks_iq, o->machine.kr_iq);
    near_lsb("inv_ks_iq", (double)o->machine.inv_ks_iq, IQ1 * sqrt(lm / ls), 0.5 + 1e-6);
    assert_int_equal(o->machine.rr_iq, g_d.res.im.rr_iq);
    /* Casadei eq. 34's k_T = (1 - sigma) / (2 sigma l_s) = L_M / (2 sigma L_s L_s) */
    near_lsb("kt_iq", (double)o->fw.kt_iq, IQ1 * lm / (2.0 * sls / IQ1 * ls), 0.5);
    /* T_s / tau_r = ts_pu r_r / l_r, Q31 */
    near_lsb("magn_k_q31", (double)o->ref.magn_k_q31, 2147483648.0 * ts * (double)g_d.res.im.rr_iq / (IQ1 * ls), 0.5);
    if (g_in.u.im.ref.psir_ref_iq > 0) {
        psir = (double)g_in.u.im.ref.psir_ref_iq;
        assert_int_equal(o->ref.inv_psir_sq_iq, g_in.u.im.ref.inv_psir_sq_iq);
    } else {
        const double fl = (double)g_in.speed.flux_ref_iq;
        /* 1 / phi_r*^2, phi_r* = (M / L_s) phi_s*: L_s / (phi_s*^2 L_M); two quotients (1/64 LSB) */
        near_lsb("inv_psir_sq_iq", (double)o->ref.inv_psir_sq_iq, ldexp(ls / (fl * fl * lm), 72), 0.5 + 1.0 / 64.0);
        psir = nearbyint(fl * (double)o->machine.inv_ks_iq / IQ1);
        near_conv("inv_psir_sq_iq", (double)o->ref.inv_psir_sq_iq, (double)r->ref.inv_psir_sq_iq, 5e-6);
    }
    /* the start-up's flux ramp (1 - phi_r* / M) r_r ts (the current base is the rated current) */
    near_lsb("magn_ramp_iq", (double)o->ref.magn_ramp_iq,
             (1.0 - psir / (double)o->machine.m_iq) * (double)g_d.res.im.rr_iq * ts / IQ1, 0.5 + 0.01);
    if (g_in.law == DTC_LAW_IM_DFOC) {
        near_lsb("dfoc.id_ref_iq", (double)o->dfoc.id_ref_iq, IQ1 * psir / (double)o->machine.m_iq, 0.5);
        near_lsb("dfoc.iq_per_t_iq", (double)o->dfoc.iq_per_t_iq, IQ1 * sqrt(ls / lm) * IQ1 / psir, 0.5 + 1e-3);
        near_conv("dfoc.id_ref_iq", (double)o->dfoc.id_ref_iq, (double)r->dfoc.id_ref_iq, 5e-6);
        near_conv("dfoc.iq_per_t_iq", (double)o->dfoc.iq_per_t_iq, (double)r->dfoc.iq_per_t_iq, 5e-6);
    }
    /* against the converter of the true machine: the inputs' quantisation (ts_pu_iq: 2.4e-6) */
    {
        const char *name[10] = {"sigma_ls_iq", "sigma_lr_iq", "m_iq", "kr_iq", "ks_iq",
                                "inv_ks_iq", "rr_iq", "kt_iq", "magn_k_q31", "magn_ramp_iq"};
        const int32_t got[10] = {o->machine.sigma_ls_iq, o->machine.sigma_lr_iq, o->machine.m_iq, o->machine.kr_iq,
                                 o->machine.ks_iq, o->machine.inv_ks_iq, o->machine.rr_iq, o->fw.kt_iq,
                                 o->ref.magn_k_q31, o->ref.magn_ramp_iq};
        const int32_t want[10] = {r->machine.sigma_ls_iq, r->machine.sigma_lr_iq, r->machine.m_iq, r->machine.kr_iq,
                                  r->machine.ks_iq, r->machine.inv_ks_iq, r->machine.rr_iq, r->fw.kt_iq,
                                  r->ref.magn_k_q31, r->ref.magn_ramp_iq};
        int k;
        for (k = 0; k < 10; k++) {
            near_conv(name[k], (double)got[k], (double)want[k], 5e-6);
        }
    }
    assert_true(labs((long)g_out.machine.rs_iq - (long)g_ref.machine.rs_iq) <= 2L);
    assert_int_equal(g_out.machine.pole_pairs, g_ref.machine.pole_pairs);
    assert_int_equal(g_out.board.enc_gain_q16, g_ref.board.enc_gain_q16);
    assert_int_equal(g_out.board.enc_reversed, g_ref.board.enc_reversed);
    assert_true(abs((int)g_out.board.td_ts_q15 - (int)g_ref.board.td_ts_q15) <= 1);
    /* not written: the rows the image cannot derive (app_ident_apply.c) */
    assert_int_equal(o->ref.magn_periods, g_in.u.im.ref.magn_periods);
    assert_int_equal(o->ref.enc_plaus_iq, g_in.u.im.ref.enc_plaus_iq);
    assert_int_equal(g_out.board.enc_offset, g_in.board.enc_offset);
    check_speed_rows();
}

static void test_im_dtc(void **state)
{
    (void)state;
    setup_im(DTC_LAW_IM_DTC, 0.53, 0, 2);
    check_im_rows();
}

/* the rotor-flux reference derived from the stator flux's (psir_ref_wb = 0): 1 / phi_r*^2 written */
static void test_im_derived_rotor_flux(void **state)
{
    (void)state;
    setup_im(DTC_LAW_IM_DTC, 0.0, 1, 3);
    check_im_rows();
}

static void test_im_dfoc(void **state)
{
    (void)state;
    setup_im(DTC_LAW_IM_DFOC, 0.53, 0, 2);
    check_im_rows();
    print_message("IM rows: largest error against the formulas %.4f LSB, against the converter %.3g relative\n",
                  g_err_lsb, g_err_conv);
}

/* no flux measured turning (a spin without i_d): the standing L_s */
static void test_im_standing_ls(void **state)
{
    (void)state;
    setup_im(DTC_LAW_IM_DTC, 0.53, 0, 2);
    g_d.res.im.id_iq = 0;
    g_d.res.j_q12 = 0; /* a spin without i_d has no torque constant: no J */
    assert_int_equal(app_ident_derive(&g_d, &g_in, &g_out), APP_IDENT_APPLY_OK);
    {
        const double ls = nearbyint((double)g_d.res.im.ls_ts_iq * (double)g_in.board.ts_pu_iq / IQ1);
        const double lm = ls - (double)g_out.u.im.machine.sigma_ls_iq;
        near_lsb("m_iq (standing L_s)", (double)g_out.u.im.machine.m_iq, sqrt(ls * lm), 0.5);
    }
}

static void test_im_refusals(void **state)
{
    (void)state;
    setup_im(DTC_LAW_IM_DTC, 0.53, 0, 2);
    /* the machines must agree: an IM's identification on a PM configuration and a PM's on an IM's */
    g_d.im_on = 0U;
    assert_int_equal(app_ident_derive(&g_d, &g_in, &g_out), APP_IDENT_APPLY_LAW);
    g_d.im_on = 1U;
    /* L_s not above sigma L_s, turning and standing */
    g_d.res.im.lsig_ts_iq = g_d.res.im.ls_ts_iq;
    assert_int_equal(app_ident_derive(&g_d, &g_in, &g_out), APP_IDENT_APPLY_IM);
    setup_im(DTC_LAW_IM_DTC, 0.53, 0, 2);
    g_d.res.im.rr_iq = 0;
    assert_int_equal(app_ident_derive(&g_d, &g_in, &g_out), APP_IDENT_APPLY_IM);
    /* a magnetising current phi_r* / M at rated: M three times too small */
    setup_im(DTC_LAW_IM_DTC, 0.53, 0, 2);
    g_d.res.psi_iq /= 8;
    assert_int_equal(app_ident_derive(&g_d, &g_in, &g_out), APP_IDENT_APPLY_IM);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fstp_forward),     cmocka_unit_test(test_sstp_reversed),
        cmocka_unit_test(test_reversed_in_force), cmocka_unit_test(test_pole_pairs),
        cmocka_unit_test(test_dead_time_bounds), cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_im_dtc),           cmocka_unit_test(test_im_derived_rotor_flux),
        cmocka_unit_test(test_im_dfoc),          cmocka_unit_test(test_im_standing_ls),
        cmocka_unit_test(test_im_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
