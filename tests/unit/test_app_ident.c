/*
 * test_app_ident.c - self-commissioning (firmware/app/app_ident.h) against a double-precision
 * R-L load on the SSTP: each period the ISR's compare values become the legs' mean voltages,
 * each phase loses V_f sign(i) + R_on i (Hoang Table III averaged over the period), and the
 * alpha-beta R-L circuit is integrated exactly over the period with the command of the period
 * before (hal.h: the command of period k governs period k + 1). No rotor: the encoder stands
 * still. Checks the fit against the model's own numbers: slope R_s + R_on, intercept
 * (4/3) V_f on the alpha axis, L_s; the encoder step named as not counting; the open phase; the
 * over-current stop on the very sample.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "fixtest.h"

#include "app_ident.h"
#include "app_ident_internal.h" /* ID_SIGN_GAP */
#include "dtc_config_si.h"

#define IQ1 16777216.0

static dtc_config_si_t g_si;
static dtc_config_t g_cfg;
static dtc_bases_t g_b;

static void setup_sstp(void)
{
    char msg[200];
    dtc_config_si_defaults(&g_si);
    g_si.topology = DTC_TOPO_SSTP;
    g_si.compensation = DTC_COMP_SSTP;
    g_si.mode = DTC_MODE_TORQUE;
    if (dtc_config_from_si(&g_si, &g_cfg, msg, sizeof msg) != DTC_SI_OK) {
        fail_msg("default configuration refused: %s", msg);
    }
    dtc_bases_from_si(&g_si, &g_b);
}

typedef struct {
    double r, l, vf, ron, vdc, ts;
    int open;      /* 1: no current can flow */
    double i[2];   /* alpha, beta, A */
} load_t;

static double sgn(double x) { return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0); }

/* One period under cmd (PWM form, upper active high: duty = (T1PR - cmpr) / T1PR). */
static void load_step(load_t *p, const hal_cmd_t *cmd, uint16_t t1pr)
{
    const double ia = p->i[0], ib = -0.5 * p->i[0] + 0.5 * sqrt(3.0) * p->i[1], ic = -ia - ib;
    const double iph[3] = {ia, ib, ic};
    double u[3], mean = 0.0, va, vb;
    int x;
    if (cmd->enable == 0U || p->open != 0) {
        p->i[0] = 0.0;
        p->i[1] = 0.0;
        return;
    }
    for (x = 0; x < 3; x++) {
        const double d = ((double)t1pr - (double)cmd->cmpr_up[x]) / (double)t1pr;
        u[x] = d * p->vdc - (p->vf * sgn(iph[x]) + p->ron * iph[x]);
        mean += u[x] / 3.0;
    }
    va = u[0] - mean;
    vb = ((u[1] - mean) - (u[2] - mean)) / sqrt(3.0);
    {
        const double e = exp(-p->r * p->ts / p->l);
        p->i[0] = p->i[0] * e + va / p->r * (1.0 - e);
        p->i[1] = p->i[1] * e + vb / p->r * (1.0 - e);
    }
}

/* Runs the identification on the load until it ends (or max_periods); returns the periods run. */
static uint32_t run(app_ident_t *d, load_t *p, uint32_t max_periods)
{
    hal_cmd_t cmd, prev;
    dtc_meas_t pu;
    uint32_t k;
    const uint16_t t1pr = 1875U;
    memset(&prev, 0, sizeof prev);
    memset(&pu, 0, sizeof pu);
    pu.vdc_iq = (iq_t)lround(p->vdc / g_b.v_base_v * IQ1);
    pu.enc_count = 100U;
    app_ident_start(d, &g_cfg, pu.enc_count, pu.vdc_iq);
    for (k = 0U; k < max_periods; k++) {
        const double ia = p->i[0], ib = -0.5 * p->i[0] + 0.5 * sqrt(3.0) * p->i[1];
        pu.ia_iq = (iq_t)lround(ia / g_b.i_base_a * IQ1);
        pu.ib_iq = (iq_t)lround(ib / g_b.i_base_a * IQ1);
        pu.ic_iq = -pu.ia_iq - pu.ib_iq;
        memset(&cmd, 0, sizeof cmd);
        if (app_ident_isr(d, &g_cfg, &pu, t1pr, &cmd) != 0U) {
            cmd.enable = 0U;
        }
        app_ident_service(d, &g_cfg);
        load_step(p, &prev, t1pr);
        prev = cmd;
        if (d->step == (uint16_t)APP_IDENT_DONE || d->step == (uint16_t)APP_IDENT_FAILED) {
            break;
        }
    }
    return k;
}

static app_ident_t g_d;

static void test_rs_drop_ls_against_the_load(void **state)
{
    load_t p = {0.466, 3.19e-3, 1.0, 0.075, 70.0, 50e-6, 0, {0.0, 0.0}};
    double z_b, r, v0, l;
    (void)state;
    setup_sstp();
    z_b = g_b.v_base_v / g_b.i_base_a;
    run(&g_d, &p, 200000U);
    /* no rotor: the electrical steps complete, the encoder step finds a count that never moves */
    assert_int_equal(g_d.step, APP_IDENT_FAILED);
    assert_int_equal(g_d.fail, APP_IDENT_FAIL_ENC_NOT_COUNTING);
    assert_int_equal(g_d.fail_step, APP_IDENT_ENCODER);
    assert_int_equal(g_d.res.axis, 0); /* SSTP: alpha */
    r = g_d.res.r_iq / IQ1 * z_b;
    v0 = g_d.res.v0_iq / IQ1 * g_b.v_base_v;
    l = g_d.res.l_ts_iq / IQ1 * z_b * p.ts;
    /* alpha axis: i_a = I, i_b = i_c = -I/2; per phase -V_f sign(i) - R_on i, so
     * v_alpha = (R_s + R_on) i_alpha + (2/3)(V_f + V_f). The fit sees the commanded voltage, the
     * load the one the compare values give: they differ by up to one PWM count, V_dc / T1PR
     * (37 mV), per level, so the intercept is good to that and the slope to that over the span of
     * the levels (3/4 of rated). */
    const double v_count = p.vdc / 1875.0;
    if (fabs(r - (p.r + p.ron)) > v_count / (0.75 * g_b.i_base_a)) {
        fail_msg("slope %.6f ohm, model R_s + R_on = %.6f", r, p.r + p.ron);
    }
    if (fabs(v0 - 4.0 / 3.0 * p.vf) > v_count) {
        fail_msg("intercept %.6f V, model (4/3) V_f = %.6f", v0, 4.0 / 3.0 * p.vf);
    }
    if (fabs(l - p.l) > 0.01 * p.l) {
        fail_msg("L %.6e H, model %.6e", l, p.l);
    }
    /* the four levels at 1, 3/4, 1/2, 1/4 of rated */
    assert_true(fabs(g_d.res.level_i_iq[0] / IQ1 - 1.0) < 0.002);
    assert_true(fabs(g_d.res.level_i_iq[3] / IQ1 - 0.25) < 0.002);
}

static void test_open_phase_named(void **state)
{
    load_t p = {0.466, 3.19e-3, 1.0, 0.075, 70.0, 50e-6, 1, {0.0, 0.0}};
    uint32_t k;
    hal_cmd_t cmd;
    dtc_meas_t pu;
    (void)state;
    setup_sstp();
    k = run(&g_d, &p, 40000U);
    assert_int_equal(g_d.step, APP_IDENT_FAILED);
    assert_int_equal(g_d.fail, APP_IDENT_FAIL_OPEN_PHASE);
    assert_int_equal(g_d.fail_step, APP_IDENT_RS);
    assert_true(k < 20000U); /* within 1 s */
    memset(&pu, 0, sizeof pu);
    assert_int_equal(app_ident_isr(&g_d, &g_cfg, &pu, 1875U, &cmd), 1U); /* gates stay off */
}

static void test_overcurrent_on_the_sample(void **state)
{
    hal_cmd_t cmd;
    dtc_meas_t pu;
    uint32_t k;
    (void)state;
    setup_sstp();
    memset(&pu, 0, sizeof pu);
    pu.vdc_iq = (iq_t)IQ1;
    app_ident_start(&g_d, &g_cfg, 0U, pu.vdc_iq);
    /* the start's gap: gates off while the rotor hold's current decays, above the limit too */
    pu.ib_iq = (iq_t)(2 * IQ1);
    pu.ic_iq = -pu.ib_iq;
    for (k = 0U; k < ID_SIGN_GAP; k++) {
        assert_int_equal(app_ident_isr(&g_d, &g_cfg, &pu, 1875U, &cmd), 1U);
    }
    assert_int_equal(g_d.fail, APP_IDENT_OK);
    pu.ib_iq = 0;
    pu.ic_iq = 0;
    assert_int_equal(app_ident_isr(&g_d, &g_cfg, &pu, 1875U, &cmd), 0U);
    pu.ib_iq = (iq_t)(1.25 * IQ1); /* at the limit: not yet (the sign pulse ends, the gates go off) */
    pu.ic_iq = -pu.ib_iq;
    (void)app_ident_isr(&g_d, &g_cfg, &pu, 1875U, &cmd);
    assert_int_equal(g_d.fail, APP_IDENT_OK);
    pu.ib_iq += 1;
    assert_int_equal(app_ident_isr(&g_d, &g_cfg, &pu, 1875U, &cmd), 1U);
    assert_int_equal(g_d.fail, APP_IDENT_FAIL_OVERCURRENT);
    assert_int_equal(g_d.fail_detail, 1); /* phase B */
}

UNIT_TEST_MAIN("app ident", NULL,
               cmocka_unit_test(test_rs_drop_ls_against_the_load),
               cmocka_unit_test(test_open_phase_named),
               cmocka_unit_test(test_overcurrent_on_the_sample))
