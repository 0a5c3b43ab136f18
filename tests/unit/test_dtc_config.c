/*
 * test_dtc_config.c - the SI -> per-unit converter (tools/config) and the firmware's own
 * validation (dtc_init): the defaults convert to the numbers the per-unit bases predict, bad
 * configurations are refused with the right code and a message naming the field, both on the
 * host and at dtc_init.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#include "dtc.h"
#include "law.h"
#include "dtc_config_si.h"
#include "dtc_ref.h"
#include "fixtest.h"

static void test_defaults_convert_to_expected_pu(void **state)
{
    (void)state;
    dtc_config_si_t si;
    dtc_config_t cfg;
    dtc_bases_t b;
    char msg[256];

    dtc_config_si_defaults(&si);
    assert_int_equal(dtc_config_from_si(&si, &cfg, msg, sizeof msg), DTC_SI_OK);
    assert_int_equal(law_check(&cfg, NULL), DTC_OK);
    dtc_bases_from_si(&si, &b);

    /* Bases of dtc_base.h, computed by hand from Hoang Table VIII and the 70 V link. */
    assert_true(fabs(b.psi_base_wb - 70.0 / (100.0 * DTC_REF_PI)) < 1e-12);
    assert_true(fabs(b.z_base_ohm - 70.0 / 2.2) < 1e-12);
    assert_true(fabs(b.t_base_nm - 1.5 * (70.0 / (100.0 * DTC_REF_PI)) * 2.2) < 1e-12);
    /* Machine in pu, within one IQ24 LSB (0.5 LSB rounding). */
    fixtest_assert_lsb(fixtest_iq_to_d(cfg.machine.rs_iq), 0.466 / (70.0 / 2.2), 1.0 / 16777216.0, 0.5, "rs");
    fixtest_assert_lsb(fixtest_iq_to_d(cfg.u.pm_dtc.machine.ls_iq), 3.19e-3 / (70.0 / 2.2 / (100.0 * DTC_REF_PI)),
                       1.0 / 16777216.0, 0.5, "ls");
    fixtest_assert_lsb(fixtest_iq_to_d(cfg.u.pm_dtc.machine.psi_m_iq), 0.0928 / (70.0 / (100.0 * DTC_REF_PI)),
                       1.0 / 16777216.0, 0.5, "psi_m");
    /* Rated torque 0.3 N.m with the rated 2.2 A in quadrature: T = psi_m * i (pu) = 0.408. */
    assert_true(fabs(0.3 / b.t_base_nm - 0.0928 / b.psi_base_wb * 1.0) < 0.01);
    /* Low-pass: k_leak = 1 - exp(-5 * 50e-6), k_in -> Ts_pu = 50e-6 * 100 pi. */
    fixtest_assert_lsb(fixtest_q31_to_d(cfg.est.k_leak_q31), 1.0 - exp(-2.5e-4), 1.0 / 2147483648.0,
                       0.5, "k_leak");
    assert_true(fabs(fixtest_q31_to_d(cfg.est.k_in_q31) - 50e-6 * 100.0 * DTC_REF_PI) < 1e-5);
    /* Encoder: 8000 counts, 8.192 electrical LSB per count (p = 1). */
    assert_int_equal(cfg.board.enc_counts, 8000);
    assert_int_equal(cfg.board.enc_gain_q16, 536871U);
    /* One count per 500 us = 15 rpm = 0.005 pu of 3000 rpm. */
    fixtest_assert_lsb(fixtest_iq_to_d(cfg.speed.speed_k_iq), 15.0 / 3000.0, 1.0 / 16777216.0, 0.5,
                       "speed_k");
    assert_int_equal(cfg.board.topology, DTC_TOPO_FSTP);
    assert_int_equal(cfg.est.compensation, DTC_COMP_FSTP_PROPOSED);
    assert_int_equal(cfg.u.pm_dtc.sw.flux_band_iq, 0);
    assert_int_equal(cfg.u.pm_dtc.sw.torque_band_iq, 0);
}

typedef void (*mutate_fn)(dtc_config_si_t *);
typedef struct {
    mutate_fn fn;
    int code;
    const char *field;
} si_case_t;

#define MUT(name, stmt) static void name(dtc_config_si_t *s) { stmt; }
MUT(m_ls_neg, s->ls_h = -1e-3)
MUT(m_ls_zero, s->ls_h = 0.0)
MUT(m_rs_neg, s->rs_ohm = -0.1)
MUT(m_psi_zero, s->psi_m_wb = 0.0)
MUT(m_pp_zero, s->pole_pairs = 0)
MUT(m_vdc_zero, s->vdc_v = 0.0)
MUT(m_vd_neg, s->v_d_v = -1.0)
MUT(m_ts_zero, s->ts_s = 0.0)
MUT(m_div_zero, s->speed_div = 0)
MUT(m_ts_long, s->ts_s = 5e-3)
MUT(m_lines, s->enc_lines = 20000)
MUT(m_band_neg, s->flux_band_wb = -0.001)
MUT(m_tband_neg, s->torque_band_nm = -0.01)
MUT(m_cut_zero, s->lpf_cutoff_rad_s = 0.0)
MUT(m_cut_high, s->lpf_cutoff_rad_s = 70000.0)
MUT(m_bw_fast, s->speed_bw_rad_s = 1000.0)
MUT(m_kp_neg, { s->pi_from_bandwidth = 0; s->kp_nm_s_rad = -1.0; })
MUT(m_kp_overflow, { s->pi_from_bandwidth = 0; s->kp_nm_s_rad = 1.0; s->ki_nm_rad = 0.0; })
MUT(m_tlim_zero, s->torque_limit_nm = 0.0)
MUT(m_flux_ref_zero, s->flux_ref_wb = 0.0)
MUT(m_speed_ref_high, s->speed_ref_rpm = 4000.0)
MUT(m_topo_bad, s->topology = 7)
MUT(m_comp_mismatch, { s->topology = DTC_TOPO_SSTP; s->compensation = DTC_COMP_FSTP_PROPOSED; })
MUT(m_comp_mismatch2, s->compensation = DTC_COMP_SSTP)
MUT(m_table_bad, s->sstp_table = 9)
MUT(m_adc_gain, s->adc_i_a_per_count = 0.0)
MUT(m_adc_off, s->adc_vdc_offset = 5000)
MUT(m_base, s->i_base_a = 0.0)
MUT(m_vdc_order, s->vdc_min_v = 100.0)
MUT(m_rs_huge, s->rs_ohm = 1e4)
MUT(m_band_tiny, s->flux_band_wb = 1e-12)
MUT(m_handover_neg, { s->handover_auto = 0; s->handover_speed_rpm = -1.0; })
MUT(m_handover_hyst, s->handover_hyst_frac = 1.5)
MUT(m_delay, s->delay_comp = 2)
MUT(m_deadtime, s->deadtime_comp = 3)
MUT(m_dead_time_long, s->dead_time_s = 30e-6)
MUT(m_ilim_neg, { s->current_limit_auto = 0; s->current_limit_a = -1.0; })
MUT(m_ilim_trip, { s->current_limit_auto = 0; s->current_limit_a = 6.0; })
MUT(m_polarity, s->polarity_mid = 2)
MUT(m_vmid_cal, s->vmid_cal = 2)
MUT(m_lpf_comp, s->lpf_comp = 2)
MUT(m_dc_supp, s->dc_supp = 2)
MUT(m_c_dc, s->c_dc_f = 0.0)

static void test_bad_si_configs_refused_with_field(void **state)
{
    (void)state;
    static const si_case_t cases[] = {
        {m_ls_neg, DTC_SI_ERR_MACHINE, "ls_h"},
        {m_ls_zero, DTC_SI_ERR_MACHINE, "ls_h"},
        {m_rs_neg, DTC_SI_ERR_MACHINE, "rs_ohm"},
        {m_psi_zero, DTC_SI_ERR_MACHINE, "psi_m_wb"},
        {m_pp_zero, DTC_SI_ERR_MACHINE, "pole_pairs"},
        {m_vdc_zero, DTC_SI_ERR_INVERTER, "vdc_v"},
        {m_vd_neg, DTC_SI_ERR_INVERTER, "v_d_v"},
        {m_ts_zero, DTC_SI_ERR_TIMING, "ts_s"},
        {m_div_zero, DTC_SI_ERR_TIMING, "speed_div"},
        {m_ts_long, DTC_SI_ERR_BASE, "ts_s"},
        {m_lines, DTC_SI_ERR_ENCODER, "enc_lines"},
        {m_band_neg, DTC_SI_ERR_BAND, "flux_band_wb"},
        {m_tband_neg, DTC_SI_ERR_BAND, "torque_band_nm"},
        {m_cut_zero, DTC_SI_ERR_CUTOFF, "lpf_cutoff_rad_s"},
        {m_cut_high, DTC_SI_ERR_CUTOFF, "lpf_cutoff_rad_s"},
        {m_bw_fast, DTC_SI_ERR_GAIN, "speed_bw_rad_s"},
        {m_kp_neg, DTC_SI_ERR_GAIN, "kp_nm_s_rad"},
        {m_kp_overflow, DTC_SI_ERR_RANGE, "kp_nm_s_rad"}, /* 1 N.m s/rad = 427 pu > 128 */
        {m_tlim_zero, DTC_SI_ERR_LIMIT, "torque_limit_nm"},
        {m_flux_ref_zero, DTC_SI_ERR_REFERENCE, "flux_ref_wb"},
        {m_speed_ref_high, DTC_SI_ERR_REFERENCE, "speed_ref_rpm"},
        {m_topo_bad, DTC_SI_ERR_VARIANT, "topology"},
        {m_comp_mismatch, DTC_SI_ERR_VARIANT, "compensation"},
        {m_comp_mismatch2, DTC_SI_ERR_VARIANT, "compensation"},
        {m_table_bad, DTC_SI_ERR_VARIANT, "sstp_table"},
        {m_adc_gain, DTC_SI_ERR_ADC, "adc_i_a_per_count"},
        {m_adc_off, DTC_SI_ERR_ADC, "adc_vdc_offset"},
        {m_base, DTC_SI_ERR_BASE, "i_base_a"},
        {m_vdc_order, DTC_SI_ERR_LIMIT, "vdc_min_v"},
        {m_rs_huge, DTC_SI_ERR_RANGE, "rs_ohm"}, /* 314 pu overflows IQ24 */
        {m_band_tiny, DTC_SI_ERR_RANGE, "flux_band_wb"}, /* below one LSB */
        {m_handover_neg, DTC_SI_ERR_HANDOVER, "handover_speed_rpm"},
        {m_handover_hyst, DTC_SI_ERR_HANDOVER, "handover_hyst_frac"},
        {m_delay, DTC_SI_ERR_DELAY, "delay_comp"},
        {m_deadtime, DTC_SI_ERR_DEADTIME, "deadtime_comp"},
        {m_dead_time_long, DTC_SI_ERR_DEADTIME, "dead_time_s"},
        {m_ilim_neg, DTC_SI_ERR_ILIM, "current_limit_a"},
        {m_ilim_trip, DTC_SI_ERR_ILIM, "current_limit_a"},
        {m_polarity, DTC_SI_ERR_ILIM, "polarity_mid"},
        {m_vmid_cal, DTC_SI_ERR_ILIM, "vmid_cal"},
        {m_lpf_comp, DTC_SI_ERR_CUTOFF, "lpf_comp"},
        {m_dc_supp, DTC_SI_ERR_CUTOFF, "dc_supp"},
        {m_c_dc, DTC_SI_ERR_INVERTER, "c_dc_f"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        dtc_config_si_t si;
        dtc_config_t cfg;
        char msg[256];
        dtc_config_si_defaults(&si);
        cases[k].fn(&si);
        int rc = dtc_config_from_si(&si, &cfg, msg, sizeof msg);
        if (rc != cases[k].code || strstr(msg, cases[k].field) == NULL) {
            fail_msg("case %zu (%s): code %d (want %d), message \"%s\"", k, cases[k].field, rc,
                     cases[k].code, msg);
        }
    }
    assert_int_equal(dtc_config_from_si(NULL, NULL, NULL, 0), DTC_SI_ERR_NULL);
}

typedef void (*fw_mutate_fn)(dtc_config_t *);
typedef struct {
    fw_mutate_fn fn;
    int16_t code;
    const char *field; /* law_check's name of the refused field */
} fw_case_t;
#define FMUT(name, stmt) static void name(dtc_config_t *c) { stmt; }
FMUT(f_version, c->version = 99U)
FMUT(f_topo, c->board.topology = 2U)
FMUT(f_est, c->est.estimator = 5U)
FMUT(f_table, c->u.pm_dtc.sw.sstp_table = 5U)
FMUT(f_mode, c->speed.mode = 2U)
FMUT(f_vmid, c->board.fstp_vmid_measured = 2U)
FMUT(f_comp, c->est.compensation = 4U)
FMUT(f_comp_topo, c->est.compensation = DTC_COMP_SSTP)
FMUT(f_ls, c->u.pm_dtc.machine.ls_iq = 0)
FMUT(f_rs, c->machine.rs_iq = -1)
FMUT(f_psi, c->u.pm_dtc.machine.psi_m_iq = -5)
FMUT(f_kin, c->est.k_in_q31 = 0)
FMUT(f_kleak, c->est.k_leak_q31 = -3)
FMUT(f_enc, c->board.enc_counts = 0U)
FMUT(f_enc_gain, c->board.enc_gain_q16 = 0U)
FMUT(f_band, c->u.pm_dtc.sw.torque_band_iq = -1)
FMUT(f_div, c->speed.speed_div = 0U)
FMUT(f_sk, c->speed.speed_k_iq = 0)
FMUT(f_kp, c->speed.kp_iq = -1)
FMUT(f_lim, c->speed.torque_limit_iq = 0)
FMUT(f_fref, c->speed.flux_ref_iq = 0)
FMUT(f_sref, c->speed.speed_ref_iq = IQ(2.0))
FMUT(f_tref, c->speed.torque_ref_iq = IQ(-1.0))
FMUT(f_drop, c->board.v_d_iq = -1)
FMUT(f_adc, c->board.adc_i_offset[2] = 4096U)
FMUT(f_adc_gain, c->board.adc_vdc_gain_iq = 0)
FMUT(f_base, c->board.w_base_mrad_s = 0U)
FMUT(f_limit, c->prot.vdc_min_iq = c->prot.vdc_max_iq)
FMUT(f_handover, c->u.pm_dtc.est.handover_speed_iq = -1)
FMUT(f_handover_hyst, c->u.pm_dtc.est.handover_hyst_iq = c->u.pm_dtc.est.handover_speed_iq + 1)
FMUT(f_delay, c->u.pm_dtc.est.delay_comp = 2U)
FMUT(f_ts_pu, c->board.ts_pu_iq = 0)
FMUT(f_inv_ls, c->u.pm_dtc.machine.inv_ls_iq = -1)
/* a configuration without L_q (its row left 0) is refused, naming it */
FMUT(f_lq, c->u.pm_dtc.machine.lq_iq = 0)
FMUT(f_deadtime, c->est.deadtime_comp = 2U)
FMUT(f_td, c->board.td_ts_q15 = Q15(0.5))
FMUT(f_law, c->law = DTC_LAW_COUNT)
/* the IM law on the PM law's part: its tag is not the IM part's */
FMUT(f_law_part, c->law = DTC_LAW_IM_DSC)
FMUT(f_part, c->u.pm_dtc.part = DTC_PART_IM)
FMUT(f_ilim_neg, c->prot.i_lim_iq = -1)
FMUT(f_ilim_trip, c->prot.i_lim_iq = c->prot.i_trip_iq)
FMUT(f_polarity, c->u.pm_dtc.est.polarity_mid = 2U)
FMUT(f_vmid_cal, c->board.vmid_cal = 2U)
FMUT(f_lpf_comp, c->u.pm_dtc.est.lpf_comp = 2U)
FMUT(f_lpf_wc, c->u.pm_dtc.est.wc_pu_iq = 0)
FMUT(f_dcs, c->u.pm_dtc.est.dc_supp = 2U)
FMUT(f_dcs_k, c->u.pm_dtc.est.dcs_k_iq = 0)
FMUT(f_vmid_g, c->u.pm_dtc.est.vmid_g_iq = -1)
/* the defaults measure no mid-point: neither mid-point term may be on */
FMUT(f_vmid_g_nomid, c->u.pm_dtc.est.vmid_g_iq = 1)
FMUT(f_vmid_beta_nomid, c->u.pm_dtc.est.vmid_beta_s_iq = 1)
FMUT(f_vmid_beta_neg, c->u.pm_dtc.est.vmid_beta_s_iq = -1)

static void test_dtc_init_refuses_bad_struct(void **state)
{
    (void)state;
    static const fw_case_t cases[] = {
        {f_version, DTC_ERR_VERSION, "version"}, {f_topo, DTC_ERR_VARIANT, "board.topology"},
        {f_est, DTC_ERR_VARIANT, "est.estimator"}, {f_table, DTC_ERR_VARIANT, "u.pm_dtc.sw.sstp_table"},
        {f_mode, DTC_ERR_VARIANT, "speed.mode"}, {f_vmid, DTC_ERR_VARIANT, "board.fstp_vmid_measured"},
        {f_comp, DTC_ERR_COMPENSATION, "est.compensation"},
        {f_comp_topo, DTC_ERR_COMPENSATION, "est.compensation"},
        {f_ls, DTC_ERR_MACHINE, "u.pm_dtc.machine.ls_iq"}, {f_rs, DTC_ERR_MACHINE, "machine.rs_iq"},
        {f_psi, DTC_ERR_MACHINE, "u.pm_dtc.machine.psi_m_iq"}, {f_kin, DTC_ERR_FLUX_EST, "est.k_in_q31"},
        {f_kleak, DTC_ERR_FLUX_EST, "est.k_leak_q31"}, {f_enc, DTC_ERR_ENCODER, "board.enc_counts"},
        {f_enc_gain, DTC_ERR_ENCODER, "board.enc_gain_q16"}, {f_band, DTC_ERR_BAND, "u.pm_dtc.sw.torque_band_iq"},
        {f_div, DTC_ERR_SPEED, "speed.speed_div"}, {f_sk, DTC_ERR_SPEED, "speed.speed_k_iq"},
        {f_kp, DTC_ERR_PI, "speed.kp_iq"}, {f_lim, DTC_ERR_PI, "speed.torque_limit_iq"},
        {f_fref, DTC_ERR_REFERENCE, "speed.flux_ref_iq"}, {f_sref, DTC_ERR_REFERENCE, "speed.speed_ref_iq"},
        {f_tref, DTC_ERR_REFERENCE, "speed.torque_ref_iq"}, {f_drop, DTC_ERR_DROP, "board.v_d_iq"},
        {f_adc, DTC_ERR_ADC, "board.adc_i_offset[2]"}, {f_adc_gain, DTC_ERR_ADC, "board.adc_vdc_gain_iq"},
        {f_base, DTC_ERR_BASE, "board.w_base_mrad_s"}, {f_limit, DTC_ERR_LIMIT, "prot.vdc_min_iq"},
        {f_handover, DTC_ERR_HANDOVER, "u.pm_dtc.est.handover_speed_iq"},
        {f_handover_hyst, DTC_ERR_HANDOVER, "u.pm_dtc.est.handover_hyst_iq"},
        {f_delay, DTC_ERR_DELAY, "u.pm_dtc.est.delay_comp"}, {f_ts_pu, DTC_ERR_DELAY, "board.ts_pu_iq"},
        {f_inv_ls, DTC_ERR_MACHINE, "u.pm_dtc.machine.inv_ls_iq"},
        {f_lq, DTC_ERR_MACHINE, "u.pm_dtc.machine.lq_iq"},
        {f_deadtime, DTC_ERR_DEADTIME, "est.deadtime_comp"}, {f_td, DTC_ERR_DEADTIME, "board.td_ts_q15"},
        {f_law, DTC_ERR_VARIANT, "law"}, {f_law_part, DTC_ERR_PART, "u.im.part"},
        {f_part, DTC_ERR_PART, "u.pm_dtc.part"},
        {f_ilim_neg, DTC_ERR_ILIM, "prot.i_lim_iq"}, {f_ilim_trip, DTC_ERR_ILIM, "prot.i_lim_iq"},
        {f_polarity, DTC_ERR_POLARITY, "u.pm_dtc.est.polarity_mid"}, {f_vmid_cal, DTC_ERR_POLARITY, "board.vmid_cal"},
        {f_lpf_comp, DTC_ERR_LPFCOMP, "u.pm_dtc.est.lpf_comp"}, {f_lpf_wc, DTC_ERR_LPFCOMP, "u.pm_dtc.est.wc_pu_iq"},
        {f_dcs, DTC_ERR_DCSUPP, "u.pm_dtc.est.dc_supp"}, {f_dcs_k, DTC_ERR_DCSUPP, "u.pm_dtc.est.dcs_k_iq"},
        {f_vmid_g, DTC_ERR_DCSUPP, "u.pm_dtc.est.vmid_g_iq"}, {f_vmid_g_nomid, DTC_ERR_DCSUPP, "u.pm_dtc.est.vmid_g_iq"},
        {f_vmid_beta_nomid, DTC_ERR_DCSUPP, "u.pm_dtc.est.vmid_beta_s_iq"},
        {f_vmid_beta_neg, DTC_ERR_DCSUPP, "u.pm_dtc.est.vmid_beta_s_iq"},
    };
    dtc_config_si_t si;
    dtc_config_t good;
    dtc_t c;

    dtc_config_si_defaults(&si);
    assert_int_equal(dtc_config_from_si(&si, &good, NULL, 0), DTC_SI_OK);
    assert_int_equal(dtc_init(&c, &good), DTC_OK);
    assert_ptr_equal(c.cfg, &good);
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        dtc_config_t bad = good;
        cases[k].fn(&bad);
        law_t l;
        int16_t rc = law_init(&l, &bad);
        const char *field = NULL;
        if (rc != cases[k].code) {
            fail_msg("firmware case %zu: law_init returned %d, want %d", k, rc, cases[k].code);
        }
        assert_true(dtc_init(&c, &bad) != DTC_OK); /* the PM law's own init refuses it too */
        if (law_check(&bad, &field) != cases[k].code || strcmp(field, cases[k].field) != 0) {
            fail_msg("firmware case %zu: law_check names \"%s\", want \"%s\"", k, field,
                     cases[k].field);
        }
        assert_null(c.cfg);
    }
    assert_int_equal(dtc_init(&c, NULL), DTC_ERR_NULL);
    assert_int_equal(dtc_init(NULL, &good), DTC_ERR_NULL);
}

/* The trip level `which` (0 current, 1 over-voltage): one LSB below the largest reading `full`
 * accepted, at it refused (a trip fires above its level, so at the reading it never fires). */
static void expect_trip_edge(const dtc_config_t *base, int which, int64_t full, const char *name)
{
    dtc_config_t c = *base;
    const char *field = "";
    iq_t *level = which != 0 ? &c.prot.vdc_max_iq : &c.prot.i_trip_iq;
    *level = (iq_t)(full - 1);
    assert_int_equal(law_check(&c, &field), DTC_OK);
    *level = (iq_t)full;
    assert_int_equal(law_check(&c, &field), DTC_ERR_LIMIT);
    assert_string_equal(field, name);
}

/* A trip level the ADC cannot see never fires: the current trip at or above the largest current
 * a measured channel reads (gain x (2047 - the offset tolerance) counts from the 2048 offset),
 * the over-voltage trip at or above the divider's full scale. Refused with the field. */
static void test_trips_beyond_the_adc_range_refused(void **state)
{
    (void)state;
    dtc_config_si_t si;
    dtc_config_t cfg, bad;
    const char *field = "";
    dtc_config_si_defaults(&si);
    assert_int_equal(dtc_config_from_si(&si, &cfg, NULL, 0), DTC_SI_OK);
    /* current: 2047 counts from the 2048 offset, less the calibration's tolerance */
    expect_trip_edge(&cfg, 0, (int64_t)cfg.board.adc_i_gain_iq * (2047 - DTC_ADC_OFFSET_TOL_COUNTS), "prot.i_trip_iq");
    expect_trip_edge(&cfg, 1, (int64_t)cfg.board.adc_vdc_gain_iq * 4095, "prot.vdc_max_iq");
    bad = cfg;
    bad.board.adc_i_offset[1] = 3000; /* B, measured on the FSTP, off-centre: 1095 counts above it */
    bad.prot.i_trip_iq = (iq_t)((int64_t)cfg.board.adc_i_gain_iq * (1095 - DTC_ADC_OFFSET_TOL_COUNTS));
    bad.prot.i_lim_iq = 0; /* the current limit and the hold below the trip are checked first */
    bad.prot.i_hold_iq = 0;
    assert_int_equal(law_check(&bad, &field), DTC_ERR_LIMIT);
    assert_string_equal(field, "prot.i_trip_iq");
    bad.board.adc_i_offset[1] = 2048;
    bad.board.adc_i_offset[0] = 3000; /* A is not measured on the FSTP with two sensors: no effect */
    assert_int_equal(law_check(&bad, &field), DTC_OK);
    /* the SI side: 12 A on the 10 A sensor range is refused by the firmware's check */
    char msg[256];
    si.i_trip_a = 12.0;
    assert_int_not_equal(dtc_config_from_si(&si, &cfg, msg, sizeof msg), DTC_SI_OK);
    assert_non_null(strstr(msg, "prot.i_trip_iq"));
}

/* The derived hand-over speed (dtc_config_si.h) for Hoang Table VIII / Table IV / 5 rad/s:
 * back-EMF 3x the drop: 3 (1.25 + 0.075 * 2.2) / 0.0928 = 45.74 rad/s; LPF: 10 * 5 = 50 rad/s;
 * the larger, 50 rad/s electrical, p = 1: 477.46 rpm, i.e. 50 / (2 pi 3000/60) = 0.159155 pu. */
static void test_handover_default_from_machine(void **state)
{
    dtc_config_si_t si;
    dtc_config_t cfg;
    (void)state;
    dtc_config_si_defaults(&si);
    assert_true(fabs(dtc_handover_default_rpm(&si) - 500.0 * 3.0 / M_PI) < 1e-9);
    assert_int_equal(dtc_config_from_si(&si, &cfg, NULL, 0), DTC_SI_OK);
    assert_true(fabs((double)cfg.u.pm_dtc.est.handover_speed_iq / 16777216.0 - 50.0 / (100.0 * M_PI)) < 1e-7);
    assert_true(fabs((double)cfg.u.pm_dtc.est.handover_hyst_iq / 16777216.0 - 0.2 * 50.0 / (100.0 * M_PI)) < 1e-7);
    /* a weaker magnet: the back-EMF rule takes over, 3 * 1.415 / 0.05 = 84.9 rad/s */
    si.psi_m_wb = 0.05;
    si.flux_ref_wb = 0.05;
    assert_true(fabs(dtc_handover_default_rpm(&si) - 84.9 * 30.0 / M_PI) < 1e-6);
    /* the current-budget rule (dtc_config_si.h), closed form with the Hoang Table VIII / IV numbers:
     * I_lim = 6 - 50e-6 (70/sqrt(3) + 0.0928 * 100 pi + 0.466 * 6) / 3.19e-3 on the FSTP,
     * I_r = 0.3 / (1.5 * 0.0928), w = (4/pi) k V_r / (L_s sqrt(I_lim^2 - I_r^2)). */
    si.psi_m_wb = 0.0928;
    si.flux_ref_wb = 0.0928;
    {
        const double i_lim = 6.0 - 50e-6 * (70.0 / sqrt(3.0) + 0.0928 * 100.0 * M_PI + 0.466 * 6.0) / 3.19e-3;
        const double head = sqrt(i_lim * i_lim - pow(0.3 / (1.5 * 0.0928), 2.0));
        const double w_none = 4.0 / M_PI * (2.0 / 3.0) * (1.25 + 0.075 * i_lim) / (3.19e-3 * head);
        si.compensation = DTC_COMP_NONE;
        assert_true(fabs(dtc_handover_default_rpm(&si) - w_none * 30.0 / M_PI) < 1e-6);
        assert_true(fabs(w_none * 30.0 / M_PI - 941.0) < 1.0);
        /* Hoang Table V leaves |V_d - V_f| + R_on I = 0.35 + 0.365 V: 43.6 rad/s, below the 50 of the low-pass */
        si.compensation = DTC_COMP_FSTP_SIMPLE;
        assert_true(fabs(dtc_handover_default_rpm(&si) - 500.0 * 3.0 / M_PI) < 1e-9);
        /* an uncompensated dead time adds V_dc T_d / T_s = 1.4 V to the residual */
        si.deadtime_comp = 0;
        {
            const double w = 4.0 / M_PI * (2.0 / 3.0) * (0.35 + 0.075 * i_lim + 1.4) / (3.19e-3 * head);
            assert_true(fabs(dtc_handover_default_rpm(&si) - w * 30.0 / M_PI) < 1e-6);
        }
        si.deadtime_comp = 1;
    }
    /* SSTP without compensation: three switched legs (k = 1), I_lim with V_max = 2 V_dc / 3 */
    si.topology = DTC_TOPO_SSTP;
    si.compensation = DTC_COMP_NONE;
    {
        const double i_lim = 6.0 - 50e-6 * (140.0 / 3.0 + 0.0928 * 100.0 * M_PI + 0.466 * 6.0) / 3.19e-3;
        const double head = sqrt(i_lim * i_lim - pow(0.3 / (1.5 * 0.0928), 2.0));
        const double w = 4.0 / M_PI * (1.25 + 0.075 * i_lim) / (3.19e-3 * head);
        assert_true(fabs(dtc_handover_default_rpm(&si) - w * 30.0 / M_PI) < 1e-6);
        assert_true(fabs(w * 30.0 / M_PI - 1441.0) < 1.0);
    }
    si.topology = DTC_TOPO_FSTP;
    si.compensation = DTC_COMP_FSTP_PROPOSED;
    /* explicit 0: no hand-over */
    si.handover_auto = 0;
    si.handover_speed_rpm = 0.0;
    assert_int_equal(dtc_config_from_si(&si, &cfg, NULL, 0), DTC_SI_OK);
    assert_int_equal(cfg.u.pm_dtc.est.handover_speed_iq, 0);
}

static void test_every_variant_converts_and_inits(void **state)
{
    (void)state;
    for (int topo = 0; topo <= 1; topo++)
        for (int est = 0; est <= 1; est++)
            for (int comp = 0; comp <= 3; comp++)
                for (int tab = 0; tab <= 4; tab++) {
                    dtc_config_si_t si;
                    dtc_config_t cfg;
                    dtc_t c;
                    char msg[256];
                    int ok = !((topo == DTC_TOPO_SSTP && comp >= 2) || (topo == DTC_TOPO_FSTP && comp == 1));
                    dtc_config_si_defaults(&si);
                    si.topology = topo;
                    si.estimator = est;
                    si.compensation = comp;
                    si.sstp_table = tab;
                    int rc = dtc_config_from_si(&si, &cfg, msg, sizeof msg);
                    if (ok) {
                        assert_int_equal(rc, DTC_SI_OK);
                        assert_int_equal(dtc_init(&c, &cfg), DTC_OK);
                    } else {
                        assert_int_equal(rc, DTC_SI_ERR_VARIANT);
                    }
                }
}

UNIT_TEST_MAIN("dtc config", NULL,
               cmocka_unit_test(test_defaults_convert_to_expected_pu),
               cmocka_unit_test(test_bad_si_configs_refused_with_field),
               cmocka_unit_test(test_dtc_init_refuses_bad_struct),
               cmocka_unit_test(test_trips_beyond_the_adc_range_refused),
               cmocka_unit_test(test_handover_default_from_machine),
               cmocka_unit_test(test_every_variant_converts_and_inits))
