/*
 * test_dtc_param.c - the one description of the firmware's parameters (firmware/dtc/dtc_param.h)
 * against what derives from it: the firmware's checks refuse each row's first value outside its
 * range with the row's code and name, and accept its bounds; the ids are unique and found; the
 * access by id refuses read-only rows, out-of-range values and other laws' rows without changing
 * the configuration; each row's quantity turns the converter's per-unit value back into the SI
 * value it came from; the C emitter writes every row.
 */
#define _POSIX_C_SOURCE 200809L /* open_memstream */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "fixtest.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtc_config_si.h"
#include "dtc_params.h"
#include "law.h"

enum { CFG_PM_FSTP, CFG_PM_SSTP, CFG_IM, CFG_ITC, CFG_N };

static void make(int which, dtc_config_si_t *si, dtc_config_t *cfg)
{
    char msg[256];
    if (which == CFG_IM) {
        dtc_config_si_im_defaults(si);
    } else {
        dtc_config_si_defaults(si);
        if (which == CFG_PM_SSTP) {
            si->topology = DTC_TOPO_SSTP;
            si->compensation = DTC_COMP_SSTP;
        }
        if (which == CFG_ITC) {
            si->law = DTC_LAW_PM_ITC;
        }
    }
    assert_int_equal(dtc_config_from_si(si, cfg, msg, sizeof msg), DTC_SI_OK);
    assert_int_equal(law_check(cfg, NULL), DTC_OK);
}

/* The first raw value below lo (dir -1) or above hi (dir +1), 0 when the format has none. */
static int outside(const dtc_param_t *p, int dir, int64_t *v)
{
    dtc_config_t probe;
    *v = dir < 0 ? (int64_t)p->lo - 1 : (int64_t)p->hi + 1;
    memset(&probe, 0, sizeof probe);
    return dtc_param_store(&probe, p, *v) == 0;
}

static void test_check_refuses_each_row_outside_its_range(void **state)
{
    int which, dir;
    uint16_t l, k, tried = 0U;
    (void)state;
    for (which = 0; which < CFG_N; which++) {
        dtc_config_si_t si;
        dtc_config_t cfg;
        make(which, &si, &cfg);
        {
            const dtc_param_list_t *lists[2] = {&dtc_params_common, dtc_param_law_list(cfg.law)};
            assert_non_null(lists[1]);
            for (l = 0U; l < 2U; l++) {
                assert_int_equal(dtc_param_check_rows(&cfg, lists[l], &(const char *){""}), DTC_OK);
                for (k = 0U; k < lists[l]->n; k++) {
                    const dtc_param_t *p = &lists[l]->rows[k];
                    for (dir = -1; dir <= 1; dir += 2) {
                        dtc_config_t bad = cfg;
                        const char *field = "";
                        int64_t v;
                        int16_t rc;
                        if (!outside(p, dir, &v) || p->id == 2U) {
                            continue; /* the whole format is in range; the law: law_check's switch */
                        }
                        assert_int_equal(dtc_param_store(&bad, p, v), 0);
                        rc = law_check(&bad, &field);
                        if (rc != p->err || strcmp(field, p->name) != 0) {
                            fail_msg("row #%u %s = %lld: law_check gave %d (%s), the row says %d", (unsigned)p->id,
                                     p->name, (long long)v, rc, field, p->err);
                        }
                        tried++;
                    }
                    {
                        /* both bounds pass the row's own check (a relation with another field
                         * may still refuse them: that is the law's check) */
                        dtc_config_t edge = cfg;
                        const dtc_param_list_t one = {p, 1U};
                        const char *field = "";
                        assert_int_equal(dtc_param_store(&edge, p, p->lo), 0);
                        assert_int_equal(dtc_param_check_rows(&edge, &one, &field), DTC_OK);
                        assert_int_equal(dtc_param_store(&edge, p, p->hi), 0);
                        assert_int_equal(dtc_param_check_rows(&edge, &one, &field), DTC_OK);
                    }
                }
            }
        }
    }
    assert_true(tried > 200U);
}

static void test_ids_unique_and_found(void **state)
{
    const dtc_param_list_t *lists[4] = {&dtc_params_common, &dtc_params_pm_dtc, &dtc_params_im, &dtc_params_pm_itc};
    uint16_t n = 0U, l, k, i;
    (void)state;
    for (l = 0U; l < 4U; l++) {
        for (k = 0U; k < lists[l]->n; k++) {
            const dtc_param_t *p = &lists[l]->rows[k];
            assert_ptr_equal(dtc_param_find(p->id), p);
            assert_true(p->lo <= p->hi);
            assert_true(p->qty < DTC_PQ_COUNT);
            n++;
        }
    }
    assert_int_equal(dtc_param_count(), n);
    for (i = 0U; i < dtc_param_count(); i++) {
        for (k = (uint16_t)(i + 1U); k < dtc_param_count(); k++) {
            assert_true(dtc_param_at(i)->id != dtc_param_at(k)->id);
            assert_true(strcmp(dtc_param_at(i)->name, dtc_param_at(k)->name) != 0);
        }
    }
    assert_null(dtc_param_at(dtc_param_count()));
    assert_null(dtc_param_find(0U));
    /* the ISR recording's blob is as long as the longer of the PM DTC's and IM's parts
     * (hal/replay/pil_format.c): the ITC's must not be longer */
    assert_true(dtc_params_pm_itc.n <= dtc_params_im.n);
}

static void test_set_by_id(void **state)
{
    dtc_config_si_t si;
    dtc_config_t cfg, before;
    int32_t raw = 0;
    const dtc_param_t *kp = dtc_param_find(65U), *ls = dtc_param_find(115U), *rr = dtc_param_find(201U);
    const dtc_param_t *band = dtc_param_find(103U), *base = dtc_param_find(3U);
    (void)state;
    make(CFG_PM_FSTP, &si, &cfg);
    assert_string_equal(kp->name, "speed.kp_iq");
    assert_true((kp->flags & DTC_PARAM_LIVE) != 0U);
    before = cfg;
    /* a derived row, a row of another law, a value outside the range: refused, nothing written */
    assert_int_equal(dtc_param_set(&cfg, ls, 1000), DTC_ERR_READONLY);
    assert_int_equal(dtc_param_set(&cfg, rr, 1000), DTC_ERR_READONLY);
    assert_int_equal(dtc_param_set(&cfg, band, -1), DTC_ERR_BAND);
    assert_int_equal(dtc_param_get(&cfg, dtc_param_find(221U), &raw), DTC_ERR_PART);
    assert_int_equal(dtc_param_set(&cfg, dtc_param_find(221U), 0), DTC_ERR_PART);
    assert_memory_equal(&cfg, &before, sizeof cfg);
    /* a writable row: written and read back; U32 rows round-trip their bit pattern */
    assert_int_equal(dtc_param_set(&cfg, band, 12345), DTC_OK);
    assert_int_equal(dtc_param_get(&cfg, band, &raw), DTC_OK);
    assert_int_equal(raw, 12345);
    assert_int_equal(cfg.u.pm_dtc.sw.torque_band_iq, 12345);
    assert_int_equal(dtc_param_get(&cfg, base, &raw), DTC_OK);
    assert_int_equal((uint32_t)raw, cfg.board.v_base_mv);
}

/* Each row's quantity takes the converter's per-unit value back to the SI value it came from. */
static void expect_si(const dtc_config_t *cfg, uint16_t id, double si_value)
{
    const dtc_param_t *p = dtc_param_find(id);
    const double scale = dtc_param_si_scale(cfg, p->qty);
    const double got = dtc_param_value(cfg, p) * scale;
    /* one LSB of the stored format (the converter rounds to the nearest), and 1e-5 relative: the
     * board carries its bases in whole milli-units (board.w_base_mrad_s 314159 for 100 pi) */
    const double lsb = p->fmt == DTC_PF_Q31 ? 1.0 / 2147483648.0 : p->fmt == DTC_PF_Q15 ? 1.0 / 32768.0 : 1.0 / 16777216.0;
    assert_non_null(p);
    if (fabs(got - si_value) > lsb * fabs(scale) + 1e-5 * fabs(si_value)) {
        fail_msg("#%u %s: %.9g %s, converter input %.9g", (unsigned)id, p->name, got, dtc_param_unit(p->qty), si_value);
    }
}

static void test_quantities_give_back_si(void **state)
{
    dtc_config_si_t si;
    dtc_config_t cfg;
    const double w_el = 2.0 * 3.14159265358979323846 / 60.0;
    (void)state;
    make(CFG_PM_FSTP, &si, &cfg);
    expect_si(&cfg, 46U, si.rs_ohm);
    expect_si(&cfg, 115U, si.ls_h);
    expect_si(&cfg, 117U, 1.0 / si.ls_h);
    expect_si(&cfg, 116U, si.psi_m_wb);
    expect_si(&cfg, 11U, si.v_ce_v);
    expect_si(&cfg, 12U, si.v_d_v);
    expect_si(&cfg, 30U, si.i_trip_a);
    expect_si(&cfg, 31U, si.vdc_max_v);
    expect_si(&cfg, 67U, si.torque_limit_nm);
    expect_si(&cfg, 69U, si.speed_limit_rpm * w_el * si.pole_pairs);
    expect_si(&cfg, 70U, si.flux_ref_wb);
    expect_si(&cfg, 8U, si.ts_s);
    expect_si(&cfg, 17U, si.adc_i_a_per_count);
    expect_si(&cfg, 21U, si.adc_vdc_v_per_count);
    make(CFG_IM, &si, &cfg);
    expect_si(&cfg, 201U, si.rr_ohm);
    expect_si(&cfg, 207U, si.lm_h);
    expect_si(&cfg, 46U, si.rs_ohm);
    make(CFG_ITC, &si, &cfg);
    expect_si(&cfg, 310U, si.ls_h);
    expect_si(&cfg, 311U, si.psi_m_wb);
}

/* The emitter writes one line per row of the common part and of the law's part, with its value. */
static void test_emitter_writes_every_row(void **state)
{
    int which;
    (void)state;
    for (which = 0; which < CFG_N; which++) {
        dtc_config_si_t si;
        dtc_config_t cfg;
        char *buf = NULL;
        size_t len = 0U;
        FILE *f = open_memstream(&buf, &len);
        const dtc_param_list_t *lists[2];
        uint16_t l, k;
        make(which, &si, &cfg);
        lists[0] = &dtc_params_common;
        lists[1] = dtc_param_law_list(cfg.law);
        assert_int_equal(dtc_config_emit_c(&cfg, "my_cfg", f), 0);
        fclose(f);
        assert_non_null(strstr(buf, "const dtc_config_t my_cfg = {"));
        for (l = 0U; l < 2U; l++) {
            for (k = 0U; k < lists[l]->n; k++) {
                const dtc_param_t *p = &lists[l]->rows[k];
                char key[128];
                snprintf(key, sizeof key, "    .%s = %lld%s, /* #%u", p->name, (long long)dtc_param_raw(&cfg, p),
                         p->fmt == DTC_PF_U16 || p->fmt == DTC_PF_U32 || p->fmt == DTC_PF_ANGLE ? "U" : "",
                         (unsigned)p->id);
                if (strstr(buf, key) == NULL) {
                    fail_msg("emitted file lacks \"%s\"", key);
                }
            }
        }
        free(buf);
        assert_int_equal(dtc_config_emit_c(&cfg, "x", NULL), -1);
    }
}

UNIT_TEST_MAIN("dtc param", NULL,
               cmocka_unit_test(test_check_refuses_each_row_outside_its_range),
               cmocka_unit_test(test_ids_unique_and_found),
               cmocka_unit_test(test_set_by_id),
               cmocka_unit_test(test_quantities_give_back_si),
               cmocka_unit_test(test_emitter_writes_every_row))
