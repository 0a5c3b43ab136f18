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
 * The rows the converter designs from what it holds in u.im.design (the current limit and the
 * torque limit it allows, the magnetisation's periods, the DSVM outer band, the DFOC current PI,
 * the encoder plausibility; check_im_design_rows) likewise, half an LSB plus the fixed-point
 * chain's 1e-7 relative, on DTC, DFOC and DSVM, for the 4 kW, the second machine
 * (tools/scenarios/im_second_machine.toml) and the 4 kW with every machine parameter 30 % high and
 * 30 % low.
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

/* app_ident_derive on the view of d, as app_ident_apply reads it (app_get_ident_view) */
static int16_t derive_of(const app_ident_t *d, const dtc_config_t *in, dtc_config_t *out)
{
    app_ident_view_t v;
    app_ident_view_of(d, &v);
    return app_ident_derive(&v, in, out);
}
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
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_OK);
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
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_OK);
    assert_int_equal(g_out.board.enc_reversed, 0U);
    g_d.res.enc_reversed = 0U;
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_OK);
    assert_int_equal(g_out.board.enc_reversed, 1U);
    assert_int_equal(g_out.board.enc_offset, g_d.res.enc_offset);
}

/* Another pole-pair count: the gain p 2^32 / N for p = 4. */
static void test_pole_pairs(void **state)
{
    (void)state;
    setup(DTC_TOPO_SSTP, 0.3, 0);
    g_d.res.pole_pairs = 4U;
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_OK);
    assert_int_equal(g_out.machine.pole_pairs, 4U);
    assert_true(fabs((double)g_out.board.enc_gain_q16 - ldexp(4.0, 32) / (double)g_in.board.enc_counts) <= 0.5);
}

/* The dead time: a negative result (V_0 below the thresholds) is 0; half a period is refused. */
static void test_dead_time_bounds(void **state)
{
    (void)state;
    setup(DTC_TOPO_FSTP, 0.0, 0);
    g_d.res.v0_iq = 0;
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_OK);
    assert_int_equal(g_out.board.td_ts_q15, 0);
    g_d.res.v0_iq = iq_of(0.6); /* 0.6 sqrt(3) / 2 > 1/2 of a period */
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_DEADTIME);
}

static void test_refusals(void **state)
{
    (void)state;
    setup(DTC_TOPO_SSTP, 0.0, 0);
    g_d.step = APP_IDENT_SPIN;
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_NOT_DONE);
    g_d.step = APP_IDENT_FAILED;
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_NOT_DONE);
    g_d.step = APP_IDENT_DONE;
    g_d.im_on = 1U;
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_LAW);
    g_d.im_on = 0U;
    g_in.law = DTC_LAW_IM_DTC;
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_LAW);
    g_in.law = DTC_LAW_PM_DTC;
    g_d.res.r_iq = g_in.board.r_on_iq;
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_RS);
    setup(DTC_TOPO_SSTP, 0.0, 0);
    g_d.res.l_ts_iq = 1;
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_LS);
}


/* ---- induction machine ---------------------------------------------------------------------- */

static double g_err_lsb;  /* the largest |row - its double formula| seen, LSB */
static double g_err_conv; /* the largest relative difference from the converter's row */

/* per row: the largest error against its formula (LSB) and against the converter (relative) */
#define N_ROWS 40
static struct {
    const char *row;
    double lsb, conv;
} g_rows[N_ROWS];

static void row_err(const char *row, double lsb, double conv)
{
    int k;
    for (k = 0; k < N_ROWS && g_rows[k].row != NULL && strcmp(g_rows[k].row, row) != 0; k++) {
    }
    if (k == N_ROWS) {
        return;
    }
    g_rows[k].row = row;
    g_rows[k].lsb = fmax(g_rows[k].lsb, lsb);
    g_rows[k].conv = fmax(g_rows[k].conv, conv);
}

/* |got - want| <= tol (LSB), the largest kept */
static void near_lsb(const char *row, double got, double want, double tol)
{
    const double e = fabs(got - want);
    row_err(row, e, 0.0);
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
    row_err(row, 0.0, e);
    if (e > g_err_conv) {
        g_err_conv = e;
    }
    if (!(e <= tol)) {
        fail_msg("%s: %.0f against the converter's %.0f (%.3g relative, tolerance %.3g)", row, got, want, e, tol);
    }
}

/* The machines: the 4 kW IM (the defaults), the second machine, and the 4 kW with every machine
 * parameter 30 % off (R_s, R_r, L_m and both leakages by k, J by 2 - k). */
enum { IM_4KW = 0, IM_SECOND = 1, IM_4KW_PLUS30 = 2, IM_4KW_MINUS30 = 3 };
static int g_machine = IM_4KW;
static double g_dfoc_zeta; /* the DFOC current PI's damping (0: its zero on the stator pole) */
static int g_fw;           /* 1: Casadei sec. 12's flux weakening (DTC) */

/* tools/scenarios/im_second_machine.toml's motor, inverter, sensors, protection and control keys
 * (the rest the IM defaults, as the scenario leaves them): its bases as the defaults take them,
 * V_b = V_dc, I_b = the rated current. */
static void im_second_machine(dtc_config_si_t *si)
{
    si->rs_ohm = 2.9338;
    si->rr_ohm = 1.355;
    si->lls_h = 0.00587;
    si->llr_h = 0.00587;
    si->lm_h = 0.14375;
    si->pole_pairs = 2;
    si->rated_torque_nm = 23.5;
    si->rated_current_a = 10.9;
    si->topology = DTC_TOPO_SSTP;
    si->vdc_v = 565.0;
    si->adc_i_a_per_count = 2.0 * 40.0 / 4096.0;
    si->adc_vdc_v_per_count = 800.0 / 4096.0;
    si->adc_vmid_v_per_count = 800.0 / 4096.0;
    si->i_trip_a = 30.0;
    si->vdc_min_v = 400.0;
    si->vdc_max_v = 700.0;
    si->speed_bw_rad_s = 2.0 * PI * 10.0;
    si->flux_ref_wb = 0.96;
    si->torque_limit_nm = 47.0;
    si->v_base_v = 565.0;
    si->i_base_a = 10.9;
}

static void im_machine(dtc_config_si_t *si)
{
    if (g_machine == IM_SECOND) {
        im_second_machine(si);
    } else if (g_machine == IM_4KW_PLUS30 || g_machine == IM_4KW_MINUS30) {
        const double k = g_machine == IM_4KW_PLUS30 ? 1.3 : 0.7;
        si->rs_ohm *= k;
        si->rr_ohm *= k;
        si->lm_h *= k;
        si->lls_h *= k;
        si->llr_h *= k;
        si->inertia_kgm2 *= 2.0 - k;
    }
}

/* A finished identification of the IM g_si (g_machine; law, rotor-flux reference psir_ref_wb,
 * encoder direction rev, pole pairs p) as app_ident_im.c leaves it (app_ident_im.h units); the
 * configuration in force from the same machine with R_s, R_r, L_m 30 % high, L_ls, L_lr 30 % low. */
static void setup_im(int law, double psir_ref_wb, int rev, int p)
{
    dtc_config_si_t wrong;
    double ts, z_b, ls, lr, sls, id;
    dtc_config_si_im_defaults(&g_si);
    im_machine(&g_si);
    g_si.law = law;
    g_si.dfoc_zeta = g_dfoc_zeta;
    g_si.flux_weakening = g_fw;
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

/* The steady-state torque at the current i, pu (the converter's dtc_im_torque_at_current_nm with
 * L_r = L_s): L_M i_d sqrt(i^2 - i_d^2); HUGE_VAL when the stator flux leaves no i_d. */
static double im_torque_at(double i, double ls, double sls, double lm, double m, double psir)
{
    double id2;
    if (g_in.u.im.ref.psir_ref_iq > 0) {
        id2 = (psir / m) * (psir / m);
    } else {
        const double phi = (double)g_in.speed.flux_ref_iq / IQ1, sli = sls * i;
        if (phi <= sli) {
            return HUGE_VAL;
        }
        id2 = (phi * phi - sli * sli) / (ls * ls - sls * sls);
    }
    return i * i > id2 ? lm * sqrt(id2) * sqrt(i * i - id2) : 0.0;
}

/* ceil(x), and whether x is within 1e-6 of an integer (where the fixed point may take the
 * neighbouring integer) */
static int ceil_near(double x, double *c)
{
    *c = ceil(x);
    return fabs(x - nearbyint(x)) < 1e-6;
}

/* The rows designed from u.im.design (app_ident_apply.c derive_im_design) against their double
 * formulas on the same integer inputs (ls, sls, lm: the applied L_s, sigma L_s, L_M in LSB) and
 * against the converter's rows for the true machine. */
static void check_im_design_rows(double ls_lsb, double sls_lsb, double lm_lsb)
{
    const dtc_im_cfg_t *o = &g_out.u.im, *r = &g_ref.u.im;
    const dtc_im_design_cfg_t *g = &g_in.u.im.design;
    const double ls = ls_lsb / IQ1, sls = sls_lsb / IQ1, lm = lm_lsb / IQ1, m = sqrt(ls * lm);
    const double ts = (double)g_in.board.ts_pu_iq / IQ1, rs = (double)g_out.machine.rs_iq / IQ1;
    const double rr = (double)g_d.res.im.rr_iq / IQ1;
    const double p = (double)g_out.machine.pole_pairs, p_in = (double)g_in.machine.pole_pairs;
    const double psir = g_in.u.im.ref.psir_ref_iq > 0 ? (double)g_in.u.im.ref.psir_ref_iq / IQ1
                                                      : (double)g_in.speed.flux_ref_iq / IQ1 * sqrt(lm / ls);
    const double t_d = (double)g->torque_limit_iq / IQ1 * p_in / p;
    const int modulated = g_in.law == DTC_LAW_IM_SFVC || g_in.law == DTC_LAW_IM_DFOC || g_in.law == DTC_LAW_IM_DSVM;
    const double vdc = (double)g->vdc_iq / IQ1;
    const double vmax = g_in.board.topology == DTC_TOPO_SSTP ? 2.0 * vdc / 3.0 : vdc / sqrt(3.0);
    const double itrip = (double)g_in.prot.i_trip_iq / IQ1;
    double di, ilim, t_lim = t_d, c;
    /* the design the converter holds */
    assert_true(g->vdc_iq > 0 && g->torque_limit_iq > 0 && g->magn_wait_iq > 0);
    assert_int_equal(g->derived & DTC_IM_DESIGN_ILIM_N, 2U);
    /* the current step and the current limit (dtc_ilim_step_a, dtc_ilim_default_a) */
    di = vmax + rs * itrip;
    if (!modulated) {
        const double wmax = (double)g_in.speed.speed_limit_iq / IQ1 * p / p_in;
        di += fmin(wmax * psir * m / ls, vmax);
    }
    di *= ts / sls;
    ilim = fmax(itrip - 2.0 * di, 0.0);
    {
        /* the excursion above the held current: dI, on SFVC and the DFOC's zeta = 0 design (first-order
         * current loops, no overshoot) V_max T_s / (4 sigma L_s) */
        const int ripple = g_in.law == DTC_LAW_IM_SFVC || (g_in.law == DTC_LAW_IM_DFOC && !(g_dfoc_zeta > 0.0));
        const double h = ripple ? vmax * ts / (4.0 * sls) : di;
        const double t_i = im_torque_at(ilim - h, ls, sls, lm, m, psir);
        double want_ilim = fmin(IQ1 * ilim, (double)g_in.prot.i_trip_iq - 1.0);
        if (ilim > 0.0 && !(t_i > 0.0)) {
            want_ilim = 0.0;
        } else if (ilim > 0.0 && t_i < t_lim) {
            t_lim = t_i;
        }
        print_message("current limit %.4f pu (converter %.4f, in force %.4f), torque limit %.4f pu (converter %.4f, "
                      "configured %.4f)\n", (double)g_out.prot.i_lim_iq / IQ1, (double)g_ref.prot.i_lim_iq / IQ1,
                      (double)g_in.prot.i_lim_iq / IQ1, (double)g_out.speed.torque_limit_iq / IQ1,
                      (double)g_ref.speed.torque_limit_iq / IQ1, t_d);
        near_lsb("prot.i_lim_iq", (double)g_out.prot.i_lim_iq, want_ilim, 0.5 + 1e-7 * want_ilim);
        near_lsb("speed.torque_limit_iq", (double)g_out.speed.torque_limit_iq, IQ1 * t_lim, 0.5 + 1e-7 * IQ1 * t_lim);
    }
    assert_true(g_in.prot.i_lim_iq != g_ref.prot.i_lim_iq); /* the configuration in force was off */
    near_conv("prot.i_lim_iq", (double)g_out.prot.i_lim_iq, (double)g_ref.prot.i_lim_iq, 5e-6);
    near_conv("speed.torque_limit_iq", (double)g_out.speed.torque_limit_iq, (double)g_ref.speed.torque_limit_iq, 5e-6);
    assert_true(labs((long)g_out.speed.torque_ref_iq) <= (long)g_out.speed.torque_limit_iq);
    /* the magnetisation: ceil(phi_s,final / (rho T_s)) + ceil(tau_r ln(1/(1 - magn_frac)) / T_s) */
    {
        const double ramp = (1.0 - psir / m) * rr * ts;
        const double psis = g_in.u.im.ref.psir_ref_iq > 0 ? psir * ls / m : (double)g_in.speed.flux_ref_iq / IQ1;
        double c2;
        const int near1 = ceil_near(psis / ramp, &c);
        const int near2 = ceil_near(ls * ((double)g->magn_wait_iq / IQ1) / (rr * ts), &c2);
        print_message("magn_periods %u (converter %u, in force %u)\n", o->ref.magn_periods, r->ref.magn_periods,
                      g_in.u.im.ref.magn_periods);
        if (!(near1 || near2)) {
            assert_int_equal(o->ref.magn_periods, (unsigned)(c + c2));
        } else {
            assert_true(fabs((double)o->ref.magn_periods - (c + c2)) <= 1.0);
        }
        assert_true(abs((int)o->ref.magn_periods - (int)r->ref.magn_periods) <= 1);
        assert_true(g_in.u.im.ref.magn_periods != r->ref.magn_periods);
    }
    if (g_in.law == DTC_LAW_IM_DSVM) {
        const double dt = m * (2.0 / 3.0 * vdc) * psir * ts / (sls * ls);
        const double b2 = fmax(2.0 * dt, (double)g_in.u.im.sw.torque_band_iq / IQ1);
        assert_int_equal(g->derived & DTC_IM_DESIGN_BAND2, DTC_IM_DESIGN_BAND2);
        near_lsb("dsvm.torque_band2_iq", (double)o->dsvm.torque_band2_iq, IQ1 * b2, 0.5 + 1e-7 * IQ1 * b2);
        near_conv("dsvm.torque_band2_iq", (double)o->dsvm.torque_band2_iq, (double)r->dsvm.torque_band2_iq, 5e-6);
        assert_true(g_in.u.im.dsvm.torque_band2_iq != r->dsvm.torque_band2_iq);
    }
    if (g_in.law == DTC_LAW_IM_DFOC) {
        /* the design the gains in force hold: w_c = K_p' / sigma L_s' (zeta = 0), or with zeta > 0
         * the same w_c and zeta: K_p = (K_p' + R_s') sigma L_s / sigma L_s' - R_s,
         * K_i T_s = K_i' T_s sigma L_s / sigma L_s' */
        const double kp_in = (double)g_in.u.im.dfoc.kp_iq / IQ1, ki_in = (double)g_in.u.im.dfoc.ki_ts_iq / IQ1;
        const double sls_in = (double)g_in.u.im.machine.sigma_ls_iq / IQ1, rs_in = (double)g_in.machine.rs_iq / IQ1;
        const double wc = kp_in / sls_in;
        const double kp = g_dfoc_zeta > 0.0 ? (kp_in + rs_in) * sls / sls_in - rs : sls * wc;
        const double ki = g_dfoc_zeta > 0.0 ? ki_in * sls / sls_in : rs * wc * ts;
        near_lsb("dfoc.kp_iq", (double)o->dfoc.kp_iq, IQ1 * kp, 0.5 + 1e-7 * IQ1 * kp);
        near_lsb("dfoc.ki_ts_iq", (double)o->dfoc.ki_ts_iq, IQ1 * ki, 0.5 + 1e-7 * IQ1 * ki);
        /* against the converter: the gains in force carry their own rounding (K_i' T_s of about 1e5
         * LSB: 5e-6 in the zeta > 0 form), R_s its quantisation (2 LSB), and the rows theirs */
        near_conv("dfoc.kp_iq", (double)o->dfoc.kp_iq, (double)r->dfoc.kp_iq, 5e-6);
        near_conv("dfoc.ki_ts_iq", (double)o->dfoc.ki_ts_iq, (double)r->dfoc.ki_ts_iq,
                  5e-6 + 2.0 / (double)g_ref.machine.rs_iq + 1.0 / (double)r->dfoc.ki_ts_iq +
                      0.5 / (double)g_in.u.im.dfoc.ki_ts_iq);
        assert_true(g_in.u.im.dfoc.kp_iq != r->dfoc.kp_iq);
    }
    /* the encoder plausibility: 1.5 w_slip + T_lim ts speed_div / Jn, Jn the identified J in pu */
    {
        const double kt_spin = nearbyint(lm_lsb * (double)g_d.res.im.id_iq / IQ1) / IQ1;
        const double jn = (double)g_d.res.j_q12 / 4096.0 * kt_spin * (double)g_in.board.enc_counts * ts * ts /
                          ((double)105414357 / IQ1 * p);
        double slip = rr * t_d / (psir * psir), tol;
        assert_true(r->ref.enc_plaus_iq > 0 && g_in.u.im.ref.enc_plaus_iq > 0);
        if (g_in.u.im.fw.on != 0U) {
            const double psi_min = (double)g_in.u.im.fw.psi_min_iq / IQ1, psir_min = psi_min * sqrt(lm / ls);
            const double kt = lm / (2.0 * sls * ls);
            slip = fmax(slip, rr * fmin(t_d, kt * psi_min * psi_min) / (psir_min * psir_min));
        }
        tol = 1.5 * slip + t_d * ts * (double)g_in.speed.speed_div / jn;
        near_lsb("ref.enc_plaus_iq", (double)o->ref.enc_plaus_iq, IQ1 * tol, 0.5 + 1e-7 * IQ1 * tol);
        near_conv("ref.enc_plaus_iq", (double)o->ref.enc_plaus_iq, (double)r->ref.enc_plaus_iq, 5e-6);
        assert_true(g_in.u.im.ref.enc_plaus_iq != r->ref.enc_plaus_iq);
    }
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
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_OK);
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
    /* not written: the encoder offset (an IM has no magnet to align to) */
    assert_int_equal(g_out.board.enc_offset, g_in.board.enc_offset);
    check_im_design_rows(ls, sls, lm);
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
}

static void test_im_dsvm(void **state)
{
    (void)state;
    setup_im(DTC_LAW_IM_DSVM, 0.53, 0, 2);
    check_im_rows();
}

/* the second machine (tools/scenarios/im_second_machine.toml): DTC on its stator-flux reference,
 * DFOC and DSVM on its rotor-flux reference */
static void test_im_second_machine(void **state)
{
    (void)state;
    g_machine = IM_SECOND;
    setup_im(DTC_LAW_IM_DTC, 0.0, 0, 2);
    check_im_rows();
    g_fw = 1; /* the encoder plausibility's slip over the flux weakening's range */
    setup_im(DTC_LAW_IM_DTC, 0.0, 0, 2);
    assert_int_equal(g_in.u.im.fw.on, 1U);
    check_im_rows();
    g_fw = 0;
    setup_im(DTC_LAW_IM_DFOC, 0.90, 1, 2);
    check_im_rows();
    g_dfoc_zeta = 0.7; /* the PI's two poles at w_c: K_p = 2 zeta w_c sigma L_s - R_s, K_i = sigma L_s w_c^2 */
    setup_im(DTC_LAW_IM_DFOC, 0.90, 0, 2);
    check_im_rows();
    g_dfoc_zeta = 0.0;
    setup_im(DTC_LAW_IM_SFVC, 0.90, 0, 2);
    check_im_rows();
    setup_im(DTC_LAW_IM_DSVM, 0.90, 0, 2);
    check_im_rows();
    g_machine = IM_4KW;
}

/* the 4 kW with every machine parameter 30 % high and 30 % low */
static void test_im_variation(void **state)
{
    (void)state;
    for (g_machine = IM_4KW_PLUS30; g_machine <= IM_4KW_MINUS30; g_machine++) {
        setup_im(DTC_LAW_IM_DTC, 0.0, 0, 2);
        check_im_rows();
        setup_im(DTC_LAW_IM_DFOC, 0.53, 0, 2);
        check_im_rows();
        setup_im(DTC_LAW_IM_DSVM, 0.53, 1, 2);
        check_im_rows();
    }
    g_machine = IM_4KW;
    print_message("IM rows: largest error against the formulas %.4f LSB, against the converter %.3g relative\n",
                  g_err_lsb, g_err_conv);
    {
        int k;
        for (k = 0; k < N_ROWS && g_rows[k].row != NULL; k++) {
            print_message("  %-22s %.4f LSB, %.3g relative\n", g_rows[k].row, g_rows[k].lsb, g_rows[k].conv);
        }
    }
}

/* no flux measured turning (a spin without i_d): the standing L_s */
static void test_im_standing_ls(void **state)
{
    (void)state;
    setup_im(DTC_LAW_IM_DTC, 0.53, 0, 2);
    g_d.res.im.id_iq = 0;
    g_d.res.j_q12 = 0; /* a spin without i_d has no torque constant: no J */
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_OK);
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
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_LAW);
    g_d.im_on = 1U;
    /* L_s not above sigma L_s, turning and standing */
    g_d.res.im.lsig_ts_iq = g_d.res.im.ls_ts_iq;
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_IM);
    setup_im(DTC_LAW_IM_DTC, 0.53, 0, 2);
    g_d.res.im.rr_iq = 0;
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_IM);
    /* a DFOC current PI whose gains in force give K_p = (K_p' + R_s') sigma L_s / sigma L_s' - R_s
     * not positive (K_p' and R_s' 1 LSB: not the zeta = 0 design, K_i' T_s far above R_s' w_c T_s) */
    setup_im(DTC_LAW_IM_DFOC, 0.53, 0, 2);
    g_in.u.im.dfoc.kp_iq = 1;
    g_in.machine.rs_iq = 1;
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_IM);
    /* a configuration without the design rows (all 0) keeps the rows designed from them */
    setup_im(DTC_LAW_IM_DFOC, 0.53, 0, 2);
    memset(&g_in.u.im.design, 0, sizeof g_in.u.im.design);
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_OK);
    assert_int_equal(g_out.prot.i_lim_iq, g_in.prot.i_lim_iq);
    assert_int_equal(g_out.speed.torque_limit_iq, g_in.speed.torque_limit_iq);
    assert_int_equal(g_out.u.im.ref.magn_periods, g_in.u.im.ref.magn_periods);
    assert_int_equal(g_out.u.im.ref.enc_plaus_iq, g_in.u.im.ref.enc_plaus_iq);
    /* a magnetising current phi_r* / M at rated: M three times too small */
    setup_im(DTC_LAW_IM_DTC, 0.53, 0, 2);
    g_d.res.psi_iq /= 8;
    assert_int_equal(derive_of(&g_d, &g_in, &g_out), APP_IDENT_APPLY_IM);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fstp_forward),     cmocka_unit_test(test_sstp_reversed),
        cmocka_unit_test(test_reversed_in_force), cmocka_unit_test(test_pole_pairs),
        cmocka_unit_test(test_dead_time_bounds), cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_im_dtc),           cmocka_unit_test(test_im_derived_rotor_flux),
        cmocka_unit_test(test_im_dfoc),          cmocka_unit_test(test_im_dsvm),
        cmocka_unit_test(test_im_second_machine), cmocka_unit_test(test_im_variation),
        cmocka_unit_test(test_im_standing_ls),   cmocka_unit_test(test_im_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
