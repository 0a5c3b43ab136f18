/*
 * test_im_dtc.c - the induction-machine control law (firmware/dtc/im_dtc.h) through the app's
 * law dispatch (app/law.h), in closed loop with a double-precision T-model induction machine at a
 * held speed (support/dtc_ref.h, Casadei eq. 9) fed by an ideal six-switch inverter, with the
 * one-period actuation delay of hal.h. The machine and board are the converter's IM defaults
 * (dtc_config_si_im_defaults: the plant's default 4 kW machine); the assertions are the papers'
 * statements and closed forms, computed here in double from the machine's parameters:
 *   - a bad IM configuration is refused at init with the field named;
 *   - start-up (Casadei Fig. 17b): zero torque until the rotor flux is built, DC magnetising current,
 *     then the torque within a few ms; the voltage model with its low-pass cannot hold the flux
 *     at standstill (Casadei Fig. 17a's statement);
 *   - constant rotor flux (Casadei eq. 19) through a 50 % -> 300 % torque step;
 *   - Casadei Table 1 and ST-A..ST-D (Table 3) through the law, with the null-vector choice; the
 *     speed-dependent table (section 8) picks ST-D below and ST-A above its speed;
 *   - DSC (section 9): the hexagon (vertex / side-centre radius 1/cos 30 deg) above the section 8
 *     table's speed, ST-D's circle below it, with a hysteresis;
 *   - flux weakening (section 12): phi_s* at most once per window, T* by Casadei eqs. 33-34;
 *   - sensorless speed: flux angular speed minus the slip of Casadei eq. 16.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "dtc_config_si.h"
#include "dtc_ref.h"
#include "fixtest.h"
#include "im_dtc_internal.h"
#include "law.h"

typedef struct {
    dtc_config_si_t si;
    dtc_config_t cfg;
    dtc_bases_t b;
    dtc_ref_im_t x;
    law_t law;
    int sa, sb, sc;   /* legs applied during the current period */
    uint16_t th[3];   /* DSVM (LAW_OUT_THIRDS): the legs' three sub-interval states applied during
                       * the current period (bit 2 = first third) */
    double tspu;      /* Ts in pu time */
    double theta_e;   /* electrical rotor angle (encoder) */
    double ls, lr, m, sigma; /* pu machine */
} sim_t;

static void sim_defaults(sim_t *s)
{
    memset(s, 0, sizeof *s);
    dtc_config_si_im_defaults(&s->si);
    s->si.compensation = DTC_COMP_NONE; /* the reference inverter is ideal */
    s->si.deadtime_comp = 0;
    s->si.mode = DTC_MODE_TORQUE;
}

/* Converts, initialises the law and the machine at electrical speed w (pu). */
static void sim_start(sim_t *s, double w)
{
    char msg[256];
    const dtc_config_si_t *si = &s->si;
    if (dtc_config_from_si(si, &s->cfg, msg, sizeof msg) != DTC_SI_OK) {
        fail_msg("IM configuration refused: %s", msg);
    }
    assert_int_equal(law_init(&s->law, &s->cfg), DTC_OK);
    law_reset(&s->law);
    dtc_bases_from_si(si, &s->b);
    s->ls = (si->lls_h + si->lm_h) / s->b.l_base_h;
    s->lr = (si->llr_h + si->lm_h) / s->b.l_base_h;
    s->m = si->lm_h / s->b.l_base_h;
    s->sigma = 1.0 - s->m * s->m / (s->ls * s->lr);
    dtc_ref_im_init(&s->x, si->rs_ohm / s->b.z_base_ohm, si->rr_ohm / s->b.z_base_ohm, s->ls, s->lr,
                    s->m, w);
    s->tspu = si->ts_s * s->b.w_base_rad_s;
    s->sa = s->sb = s->sc = 0;
    s->theta_e = 0.0;
}

/* The encoder's count at the electrical angle theta_e, unwrapped (sim_period reads it modulo the
 * counts per turn). */
static double enc_turn_counts(const sim_t *s, double theta_e)
{
    return floor(theta_e / (2.0 * FIXTEST_PI * s->si.pole_pairs) * 4.0 * s->si.enc_lines);
}

/* One control period: measure, step the law, advance the machine with the legs of the PREVIOUS
 * step (hal.h: a command acts from the next period boundary). */
static void sim_period(sim_t *s, dtc_out_t *o)
{
    dtc_meas_t me;
    double ia, ib, va, vb;
    const double counts = 4.0 * s->si.enc_lines;
    double cnt;

    dtc_ref_im_currents(&s->x, &ia, &ib);
    me.ia_iq = fixtest_d_to_iq(ia);
    me.ib_iq = fixtest_d_to_iq(-0.5 * ia + 0.5 * sqrt(3.0) * ib);
    me.ic_iq = fixtest_d_to_iq(-0.5 * ia - 0.5 * sqrt(3.0) * ib);
    me.vdc_iq = IQ(1.0); /* V_base = the link voltage */
    me.vmid_iq = IQ(0.5);
    cnt = fmod(enc_turn_counts(s, s->theta_e), counts);
    me.enc_count = (uint16_t)(cnt < 0 ? cnt + counts : cnt);
    law_step(&s->law, &me, o);
    if (s->cfg.law == DTC_LAW_IM_DSVM) {
        for (int t = 2; t >= 0; t--) {
            dtc_ref_sstp_ideal((s->th[0] >> t) & 1, (s->th[1] >> t) & 1, (s->th[2] >> t) & 1, 1.0, &va, &vb);
            dtc_ref_im_step(&s->x, va, vb, s->tspu / 3.0, 2);
        }
        memcpy(s->th, o->thirds, sizeof s->th);
    } else {
        dtc_ref_sstp_ideal(s->sa, s->sb, s->sc, 1.0, &va, &vb);
        dtc_ref_im_step(&s->x, va, vb, s->tspu, 4);
    }
    s->theta_e += s->x.w * s->tspu;
    s->sa = o->sa;
    s->sb = o->sb;
    s->sc = o->sc;
}

static double psir_mag(const sim_t *s) { return hypot(s->x.pra, s->x.prb); }
static double psis_mag(const sim_t *s) { return hypot(s->x.psa, s->x.psb); }
static double wb_to_pu(const sim_t *s, double wb) { return wb / s->b.psi_base_wb; }
static double nm_to_pu(const sim_t *s, double nm) { return nm / s->b.t_base_nm; }
static double periods(const sim_t *s, double t) { return floor(t / s->si.ts_s + 0.5); }

static void set_torque(sim_t *s, double t_pu)
{
    dtc_refs_t r;
    law_refs_get(&s->law, &r);
    r.torque_ref_iq = fixtest_d_to_iq(t_pu);
    assert_int_equal(law_shadow_write(&s->law, &r), DTC_OK);
}

/* Runs until the start-up magnetisation ends (torque allowed); returns the periods it took, or
 * -1 if it did not end within n periods. Checks that T* is zero all along. */
static long run_magnetise(sim_t *s, long n, dtc_out_t *o)
{
    for (long k = 0; k < n; k++) {
        sim_period(s, o);
        if (s->law.u.im.magnetised != 0U) {
            return k;
        }
        assert_int_equal(o->te_ref_iq, 0);
    }
    return -1;
}

/* Magnetises at standstill (scenarios start at standstill: the radial start-up vector cannot
 * magnetise a machine that is already turning, whose rotor then brakes on the DC flux), then
 * holds the machine at electrical speed w and lets the law settle for t_settle seconds. */
static void sim_magnetise_at(sim_t *s, double w, double t_settle, dtc_out_t *o)
{
    assert_true(run_magnetise(s, s->cfg.u.im.ref.magn_periods + 10L, o) > 0);
    s->x.w = w;
    for (long k = 0; k < (long)periods(s, t_settle); k++) {
        sim_period(s, o);
    }
}

/* ---- configuration ------------------------------------------------------------------------- */

typedef void (*fmut_fn)(dtc_config_t *);
#define FMUT(name, stmt) static void name(dtc_config_t *c) { stmt; }
FMUT(f_kr, c->u.im.machine.kr_iq = 0)
FMUT(f_sigma_ls, c->u.im.machine.sigma_ls_iq = -1)
FMUT(f_rr, c->u.im.machine.rr_iq = 0)
FMUT(f_klo, c->u.im.est.k_lo_q31 = 0)
FMUT(f_whi, c->u.im.est.w_hi_iq = c->u.im.est.w_lo_iq - 1)
FMUT(f_est, c->est.estimator = DTC_EST_CURRENT)
/* the four-switch inverter runs the switching-table DTC only (im_dtc_fstp.c), without section
 * 12's flux weakening */
FMUT(f_topo, { c->board.topology = DTC_TOPO_FSTP; c->est.compensation = DTC_COMP_NONE; c->law = DTC_LAW_IM_DSC; })
FMUT(f_topo_fw, { c->board.topology = DTC_TOPO_FSTP; c->est.compensation = DTC_COMP_NONE; c->u.im.fw.on = 1U; })
FMUT(f_fw_window, { c->u.im.fw.on = 1U; c->u.im.fw.window = 19U; })
FMUT(f_fw_kt, { c->u.im.fw.on = 1U; c->u.im.fw.kt_iq = 0; })
FMUT(f_table, c->u.im.sw.sstp_table = DTC_ST_SPEED + 1U)
FMUT(f_scheme, c->law = DTC_LAW_COUNT)
/* the PM law on the IM part, and an IM part without its tag */
FMUT(f_pm_law, c->law = DTC_LAW_PM_DTC)
FMUT(f_part, c->u.im.part = 0U)
/* DSVM: the outer torque band below the inner one; section 12's weakening */
FMUT(f_dsvm_band2, { c->law = DTC_LAW_IM_DSVM; c->u.im.sw.torque_band_iq = IQ(0.05); c->u.im.dsvm.torque_band2_iq = IQ(0.04); })
FMUT(f_dsvm_fw, { c->law = DTC_LAW_IM_DSVM; c->u.im.dsvm.torque_band2_iq = IQ(0.5); c->u.im.fw.on = 1U; })
/* a valid SFVC set (constant rotor flux, a gain below 1/ts_pu), then one field broken */
static void sfvc_ok(dtc_config_t *c)
{
    c->law = DTC_LAW_IM_SFVC;
    c->u.im.svm_mode = 1U;
    c->u.im.sfvc.kp_iq = IQ(1.0);
    c->u.im.ref.psir_ref_iq = IQ(0.5);
    c->u.im.ref.inv_psir_ref_iq = IQ(2.0);
}
FMUT(f_svm_mode, { sfvc_ok(c); c->u.im.svm_mode = 2U; })
FMUT(f_sfvc_kp0, { sfvc_ok(c); c->u.im.sfvc.kp_iq = 0; })
/* K_p = 100 pu > 1/ts_pu = 79.6 pu at the defaults' 40 us (K_p Ts = 1.26) */
FMUT(f_sfvc_kp_big, { sfvc_ok(c); c->u.im.sfvc.kp_iq = IQ(100.0); })
FMUT(f_sfvc_fw, { sfvc_ok(c); c->u.im.fw.on = 1U; })
FMUT(f_sfvc_psir, { sfvc_ok(c); c->u.im.ref.psir_ref_iq = 0; c->u.im.ref.inv_psir_ref_iq = 0; })
/* a valid DFOC set, then one field broken */
static void dfoc_ok(dtc_config_t *c)
{
    sfvc_ok(c);
    c->law = DTC_LAW_IM_DFOC;
    c->u.im.sfvc.kp_iq = 0; /* SFVC's gain is not DFOC's */
    c->u.im.dfoc.kp_iq = IQ(0.5);
    c->u.im.dfoc.ki_ts_iq = IQ(0.001);
    c->u.im.dfoc.id_ref_iq = IQ(0.4);
    c->u.im.dfoc.iq_per_t_iq = IQ(2.0);
}
FMUT(f_dfoc_kp, { dfoc_ok(c); c->u.im.dfoc.kp_iq = 0; })
FMUT(f_dfoc_ki, { dfoc_ok(c); c->u.im.dfoc.ki_ts_iq = -1; })
FMUT(f_dfoc_id, { dfoc_ok(c); c->u.im.dfoc.id_ref_iq = 0; })
FMUT(f_dfoc_iqt, { dfoc_ok(c); c->u.im.dfoc.iq_per_t_iq = 0; })
FMUT(f_dfoc_psir, { dfoc_ok(c); c->u.im.ref.psir_ref_iq = 0; c->u.im.ref.inv_psir_ref_iq = 0; })
FMUT(f_dfoc_fw, { dfoc_ok(c); c->u.im.fw.on = 1U; })
FMUT(f_sensor, c->speed.sensor = 2U)
FMUT(f_slip, c->u.im.ref.inv_psir_sq_iq = 0)
FMUT(f_magn, c->u.im.ref.magn_periods = 0U)

/* The host converter refuses si with code and names field in its message. */
static void expect_si_refused(const dtc_config_si_t *si, int code, const char *field)
{
    dtc_config_t c;
    char msg[256];
    assert_int_equal(dtc_config_from_si(si, &c, msg, sizeof msg), code);
    if (strstr(msg, field) == NULL) {
        fail_msg("converter message \"%s\" does not name %s", msg, field);
    }
}

static void test_bad_im_config_refused_with_field(void **state)
{
    static const struct {
        fmut_fn fn;
        int16_t code;
        const char *field;
    } cases[] = {
        {f_kr, DTC_ERR_MACHINE, "u.im.machine.kr_iq"},
        {f_sigma_ls, DTC_ERR_MACHINE, "u.im.machine.sigma_ls_iq"},
        {f_rr, DTC_ERR_MACHINE, "u.im.machine.rr_iq"},
        {f_klo, DTC_ERR_FLUX_EST, "u.im.est.k_lo_q31"},
        {f_whi, DTC_ERR_FLUX_EST, "u.im.est.w_hi_iq"},
        {f_est, DTC_ERR_VARIANT, "est.estimator"},
        {f_topo, DTC_ERR_VARIANT, "board.topology"},
        {f_topo_fw, DTC_ERR_VARIANT, "board.topology"},
        {f_fw_window, DTC_ERR_WEAKENING, "u.im.fw.window"},
        {f_fw_kt, DTC_ERR_WEAKENING, "u.im.fw.kt_iq"},
        {f_table, DTC_ERR_VARIANT, "u.im.sw.sstp_table"},
        {f_scheme, DTC_ERR_VARIANT, "law"},
        {f_pm_law, DTC_ERR_PART, "u.pm_dtc.part"},
        {f_part, DTC_ERR_PART, "u.im.part"},
        {f_dsvm_band2, DTC_ERR_BAND, "u.im.dsvm.torque_band2_iq"},
        {f_dsvm_fw, DTC_ERR_VARIANT, "u.im.fw.on"},
        {f_svm_mode, DTC_ERR_SVM, "u.im.svm_mode"},
        {f_sfvc_kp0, DTC_ERR_SVM, "u.im.sfvc.kp_iq"},
        {f_sfvc_kp_big, DTC_ERR_SVM, "u.im.sfvc.kp_iq"},
        {f_sfvc_fw, DTC_ERR_VARIANT, "u.im.fw.on"},
        {f_sfvc_psir, DTC_ERR_REFERENCE, "u.im.ref.psir_ref_iq"},
        {f_dfoc_kp, DTC_ERR_SVM, "u.im.dfoc.kp_iq"},
        {f_dfoc_ki, DTC_ERR_SVM, "u.im.dfoc.ki_ts_iq"},
        {f_dfoc_id, DTC_ERR_SVM, "u.im.dfoc.id_ref_iq"},
        {f_dfoc_iqt, DTC_ERR_SVM, "u.im.dfoc.iq_per_t_iq"},
        {f_dfoc_psir, DTC_ERR_REFERENCE, "u.im.ref.psir_ref_iq"},
        {f_dfoc_fw, DTC_ERR_VARIANT, "u.im.fw.on"},
        {f_sensor, DTC_ERR_VARIANT, "speed.sensor"},
        {f_slip, DTC_ERR_REFERENCE, "u.im.ref.inv_psir_sq_iq"},
        {f_magn, DTC_ERR_STARTUP, "u.im.ref.magn_periods"},
    };
    dtc_config_si_t si;
    dtc_config_t good, pm;
    law_t l;
    im_dtc_t im;
    dtc_t d;
    char msg[256];
    (void)state;

    dtc_config_si_im_defaults(&si);
    assert_int_equal(dtc_config_from_si(&si, &good, msg, sizeof msg), DTC_SI_OK);
    assert_int_equal(good.law, DTC_LAW_IM_DTC);
    assert_int_equal(law_init(&l, &good), DTC_OK);
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        dtc_config_t bad = good;
        const char *field = NULL;
        cases[k].fn(&bad);
        if (law_init(&l, &bad) != cases[k].code) {
            fail_msg("case %s: law_init returned %d, want %d", cases[k].field, law_init(&l, &bad),
                     cases[k].code);
        }
        assert_int_equal(law_check(&bad, &field), cases[k].code);
        if (strcmp(field, cases[k].field) != 0) {
            fail_msg("case %s: law_check named \"%s\"", cases[k].field, field);
        }
    }
    /* each law refuses the other's configuration; the PM one still needs its magnet */
    dtc_config_si_defaults(&si);
    assert_int_equal(dtc_config_from_si(&si, &pm, NULL, 0), DTC_SI_OK);
    assert_int_equal(im_dtc_init(&im, &pm), DTC_ERR_VARIANT);
    assert_int_equal(dtc_init(&d, &good), DTC_ERR_VARIANT);
    pm.u.pm_dtc.machine.psi_m_iq = 0;
    assert_int_equal(law_init(&l, &pm), DTC_ERR_MACHINE);
    /* the host converter names the SI field */
    dtc_config_si_im_defaults(&si);
    si.lm_h = 0.0;
    expect_si_refused(&si, DTC_SI_ERR_MACHINE, "lm_h");
    dtc_config_si_im_defaults(&si);
    si.topology = DTC_TOPO_FSTP; /* the FSTP takes the switching-table DTC only */
    si.compensation = DTC_COMP_FSTP_SIMPLE;
    si.law = DTC_LAW_IM_DSC;
    expect_si_refused(&si, DTC_SI_ERR_VARIANT, "topology");
    si.law = DTC_LAW_IM_DTC;
    si.flux_weakening = 1;
    expect_si_refused(&si, DTC_SI_ERR_VARIANT, "flux_weakening");
    si.flux_weakening = 0;
    {
        dtc_config_t f;
        assert_int_equal(dtc_config_from_si(&si, &f, NULL, 0), DTC_SI_OK);
        assert_int_equal(law_init(&l, &f), DTC_OK);
    }
    dtc_config_si_im_defaults(&si);
    si.flux_weakening = 1;
    si.fw_window = 10;
    expect_si_refused(&si, DTC_SI_ERR_IM, "fw_window");
    dtc_config_si_im_defaults(&si); /* a PM machine's field with the IM law: the key named */
    si.psi_m_wb = 0.1;
    expect_si_refused(&si, DTC_SI_ERR_VARIANT, "psi_m_wb");
    dtc_config_si_defaults(&si); /* and the reverse */
    si.lm_h = 0.2;
    expect_si_refused(&si, DTC_SI_ERR_VARIANT, "lm_h");
    dtc_config_si_im_defaults(&si);
    si.estimator = DTC_EST_CURRENT;
    expect_si_refused(&si, DTC_SI_ERR_VARIANT, "estimator");
}

/* ---- start-up ------------------------------------------------------------------------------- */

/* Casadei Fig. 17b with the improved estimator (tau = 0.01 s): at standstill and with the rated torque
 * commanded from the start, the law holds T* = 0 while it magnetises, the phase current a DC
 * magnetising current (test_startup_current_is_dc). The stator-flux reference is ramped at
 * rho = (I_n - I_m) L_s / tau_r (im_dtc.h), then held; the torque is allowed after the ramp and
 * tau_r ln(1/(1 - magn_frac)) more, when the machine's rotor flux is at least magn_frac phi_r*
 * (phi_r* = m/l_s phi_s*, the T model at zero slip) and not beyond phi_r* (2 %).
 * Then the torque reaches 90 % of T* within 5 ms. */
static void test_startup_magnetises_then_torque(void **state)
{
    sim_t s;
    dtc_out_t o;
    long k_mag;
    double psir_target, tau_r;
    (void)state;

    sim_defaults(&s);
    s.si.torque_ref_nm = s.si.rated_torque_nm;
    sim_start(&s, 0.0);
    psir_target = s.m / s.ls * wb_to_pu(&s, s.si.flux_ref_wb);
    tau_r = s.lr / s.x.rr * s.b.t_base_s; /* seconds */
    k_mag = run_magnetise(&s, (long)periods(&s, 10.0 * tau_r), &o);
    {
        /* the ramp to phi_s* at rho = (I_n - I_m) L_s / tau_r (im_dtc.h), then tau_r ln(1/(1 - f)) */
        const double ls_h = s.si.lls_h + s.si.lm_h;
        const double psis = s.si.psir_ref_wb > 0.0 ? s.si.psir_ref_wb * ls_h / s.si.lm_h : s.si.flux_ref_wb;
        const double i_m = psis / ls_h; /* phi_r* / M = (M/L_s) phi_s* / M */
        const double rho = (s.si.rated_current_a - i_m) * ls_h / tau_r;
        const double want = psis / (rho * s.si.ts_s) + tau_r * log(1.0 / (1.0 - s.si.magn_frac)) / s.si.ts_s;
        assert_true(fabs((double)(k_mag + 1) - want) <= 2.0);
    }
    assert_true(psir_mag(&s) >= s.si.magn_frac * psir_target);
    assert_true(psir_mag(&s) <= 1.02 * psir_target);
    /* the torque follows within 5 ms */
    {
        const double tref = nm_to_pu(&s, s.si.rated_torque_nm);
        long reached = -1;
        for (long k = 0; k < (long)periods(&s, 20e-3); k++) {
            sim_period(&s, &o);
            if (reached < 0 && dtc_ref_im_torque(&s.x) >= 0.9 * tref) {
                reached = k;
            }
        }
        assert_true(reached >= 0);
        assert_true(reached <= (long)periods(&s, 5e-3));
    }
}

/* The current during the magnetisation (no torque command): a DC current, its vector's
 * direction fixed over the last 2 ms, of magnitude within 10 % of the magnetising current of the
 * rotor-flux reference, phi_r* / m (steady DC: i_r = 0, phi_r = m i_s). magn_frac = 0.95. With the
 * estimator's quasi-static DC error the stator current is already that value while the rotor
 * flux still rises (i_s = (l_r phi_s - m phi_r)/D with phi_s = phi_s* - (phi_r* - phi_r) m/l_r);
 * being a difference of nearly equal fluxes over D = sigma l_s l_r it is ~15 times as sensitive to
 * the flux held by the comparator, hence 10 %. */
static void test_startup_current_is_dc(void **state)
{
    sim_t s;
    dtc_out_t o;
    double ang[2] = {0.0, 0.0}, ia, ib, psir_target;
    long n;
    (void)state;

    sim_defaults(&s);
    s.si.magn_frac = 0.95;
    sim_start(&s, 0.0);
    psir_target = s.m / s.ls * wb_to_pu(&s, s.si.flux_ref_wb);
    n = (long)s.cfg.u.im.ref.magn_periods - 2L;
    for (long k = 0; k < n; k++) {
        sim_period(&s, &o);
        if (k == n - (long)periods(&s, 2e-3)) {
            dtc_ref_im_currents(&s.x, &ia, &ib);
            ang[0] = atan2(ib, ia);
        }
    }
    assert_int_equal(o.te_ref_iq, 0);
    dtc_ref_im_currents(&s.x, &ia, &ib);
    ang[1] = atan2(ib, ia);
    assert_true(fabs(ang[1] - ang[0]) < 0.01);
    assert_true(fabs(hypot(ia, ib) / (psir_target / s.m) - 1.0) < 0.10);
}

/* Casadei Fig. 17a: with the voltage model (its low-pass at 5 rad/s instead of the pure integrator) the
 * estimate of a DC flux decays, so a law that holds the estimate at phi_s* keeps adding volt-seconds
 * to the machine. During the start-up the voltage model takes Casadei eq. 20's correction towards
 * the start-up's rotor-flux model (im_est.h), so the magnetisation at standstill reaches phi_s*
 * without over-magnetising (the real stator flux below 110 % of phi_s* throughout, and within
 * 5 % of it at the end); held at standstill at zero torque after the start-up, the low-pass alone
 * cannot hold the DC flux and the machine is over-magnetised (beyond 120 % of phi_s* within
 * 0.3 s): the limitation of Fig. 17a that remains (docs/sil.md). With the improved estimator it
 * converges with tau_r (im_dtc.h): from 0.3 s (2.3 tau_r) after the magnetisation on (zero torque
 * command) its mean is within 3 % of phi_s* and its ripple (zero bands, one period of actuation
 * delay) within 5 %. */
static void test_voltage_model_start_up_magnetises_but_cannot_hold_standstill_flux(void **state)
{
    sim_t s;
    dtc_out_t o;
    double worst_v = 0.0, worst_start = 0.0, end_start = 0.0, worst_i = 0.0, mean_i = 0.0, ref;
    long n_i = 0;
    (void)state;

    sim_defaults(&s);
    s.si.estimator = DTC_EST_VOLTAGE;
    s.si.i_trip_a = 1800.0 * s.si.adc_i_a_per_count; /* near the largest trip the ADC can see (the law alone) */
    sim_start(&s, 0.0);
    ref = wb_to_pu(&s, s.si.flux_ref_wb);
    for (long k = 0; k < (long)s.cfg.u.im.ref.magn_periods + (long)periods(&s, 0.3); k++) {
        sim_period(&s, &o);
        if (k < (long)s.cfg.u.im.ref.magn_periods) {
            worst_start = fmax(worst_start, psis_mag(&s) / ref);
            end_start = psis_mag(&s) / ref;
        } else {
            worst_v = fmax(worst_v, psis_mag(&s) / ref);
        }
    }
    printf("MEASURE voltage model at standstill: |phi_s| / phi_s* at most %.3f during the start-up, %.3f at its end, "
           "%.3f within 0.3 s after\n", worst_start, end_start, worst_v);
    assert_true(worst_start < 1.1);
    assert_true(fabs(end_start - 1.0) < 0.05);
    assert_true(worst_v > 1.2);

    sim_defaults(&s);
    sim_start(&s, 0.0);
    for (long k = 0; k < (long)s.cfg.u.im.ref.magn_periods + (long)periods(&s, 0.4); k++) {
        sim_period(&s, &o);
        if (k > (long)s.cfg.u.im.ref.magn_periods + (long)periods(&s, 0.3)) {
            worst_i = fmax(worst_i, fabs(psis_mag(&s) / ref - 1.0));
            mean_i += psis_mag(&s) / ref;
            n_i++;
        }
    }
    assert_true(fabs(mean_i / n_i - 1.0) < 0.03);
    assert_true(worst_i < 0.05);
}

/* ---- constant rotor flux (Casadei eq. 19) --------------------------------------------------- */

/* Casadei Figs. 14-15 conditions in the unit loop: phi_r* constant (rotor_flux_ref), torque step from
 * 50 % to 300 % of rated at a held speed (0.5 pu). The law's stator-flux reference is Casadei eq. 19 (plus the rotor-flux trim, im_psir_trim) in
 * double within 1e-4 pu for the T* of the step that evaluated it (once per speed period, in the step
 * ref_slot: after the speed loop's (1), the step the application's held checks take (2), the
 * encoder plausibility's (3) and the supervision's (4), so that none of them carries two); the machine's rotor flux stays within 3 % of phi_r* through the step;
 * the mean torque over the last 10 ms follows T* within 5 %. */
static void test_constant_rotor_flux_torque_step(void **state)
{
    sim_t s;
    dtc_out_t o;
    double psir, worst = 0.0;
    long n_eval = 0;
    (void)state;

    sim_defaults(&s);
    s.si.psir_ref_wb = 0.5;
    s.si.torque_ref_nm = 0.5 * s.si.rated_torque_nm;
    /* a board whose trip level allows the paper's 300 %: about 55 A on this machine at
     * phi_r* = 0.5 Wb; with the rig's 55 A trip the torque limit the current allows is 224 %
     * (tools/config dtc_im_torque_at_current_nm) */
    s.si.i_trip_a = 80.0;
    sim_start(&s, 0.0);
    psir = wb_to_pu(&s, s.si.psir_ref_wb);
    sim_magnetise_at(&s, 0.5, 0.2, &o);
    assert_int_equal(s.law.u.im.cfg->speed.speed_div, 10);
    assert_int_equal(s.law.u.im.ref_slot, 6);
    assert_int_equal(s.law.u.im.sup.slot, 4);
    for (int step = 0; step < 2; step++) {
        const double tref = nm_to_pu(&s, (step == 0 ? 0.5 : 3.0) * s.si.rated_torque_nm);
        double tsum = 0.0;
        long n = (long)periods(&s, 0.05), nm = (long)periods(&s, 0.01);
        set_torque(&s, tref);
        for (long k = 0; k < n; k++) {
            const iq_t psi_ref_before = o.psi_ref_iq;
            sim_period(&s, &o);
            if (o.psi_ref_iq != psi_ref_before) {
                /* Casadei eq. 19 for the T* in force at the step that evaluated it, plus the
                 * rotor-flux trim times l_s/m (im_psir_trim), which stays within phi_r* / 8 */
                const double q = s.sigma * s.lr * fixtest_iq_to_d(o.te_ref_iq) / psir;
                const double trim = fixtest_iq_to_d(s.law.u.im.psir_trim_iq);
                const double want = s.ls / s.m * (sqrt(psir * psir + q * q) + trim);
                assert_true(fabs(trim) <= psir / 8.0 + 1e-6);
                assert_true(fabs(fixtest_iq_to_d(o.psi_ref_iq) - want) < 1e-4);
                assert_int_equal(s.law.u.im.div_cnt, s.law.u.im.ref_slot);
                n_eval++;
            }
            if (fabs(psir_mag(&s) / psir - 1.0) > worst) {
                worst = fabs(psir_mag(&s) / psir - 1.0);
            }
            if (k >= n - nm) {
                tsum += dtc_ref_im_torque(&s.x);
            }
        }
        assert_true(fabs(tsum / nm / tref - 1.0) < 0.05);
    }
    assert_true(worst < 0.03);
    assert_true(n_eval > 10); /* Casadei eq. 19 re-evaluated (once per speed period) */
}

/* ---- tables --------------------------------------------------------------------------------- */

/* Section 8: the speed-dependent table is ST-D below im_table_speed and ST-A above, for every
 * sector and comparator state (compared with Casadei Table 3 directly, after the null-vector choice). */
static void test_speed_dependent_table(void **state)
{
    sim_t s;
    dtc_out_t o;
    (void)state;

    sim_defaults(&s);
    s.si.sstp_table = DTC_ST_SPEED;
    sim_start(&s, 0.0);
    {
        im_dtc_t *c = &s.law.u.im;
        const iq_t w_sd = s.cfg.u.im.table_speed_iq;
        assert_true(w_sd > 0);
        c->magnetised = 1U;
        for (int sp = 0; sp < 2; sp++) {
            c->speed_iq = sp == 0 ? w_sd / 2 : w_sd + w_sd / 2;
            for (int sec = 0; sec < 6; sec++) {
                for (int fu = 0; fu < 2; fu++) {
                    for (int tu = 0; tu < 2; tu++) {
                        const double ang = sec * FIXTEST_PI / 3.0;
                        const double mag = fu ? 0.3 : 0.8; /* below / above phi_s* = 0.556 pu */
                        uint16_t got, want;
                        c->est.psi_alpha_iq = fixtest_d_to_iq(mag * cos(ang));
                        c->est.psi_beta_iq = fixtest_d_to_iq(mag * sin(ang));
                        c->psi_ref_iq = s.cfg.speed.flux_ref_iq;
                        c->te_ref_iq = tu ? IQ(0.5) : IQ(-0.5);
                        c->vec_1 = 1U;
                        got = im_dtc_select(c, 0, &o);
                        want = swtab_null_choice(swtab_sstp_st(sp == 0 ? DTC_ST_D : DTC_ST_A,
                                                               (uint16_t)(sec + 1), (uint16_t)fu,
                                                               (uint16_t)tu),
                                                 1U);
                        assert_int_equal(got, want);
                    }
                }
            }
        }
    }
}

/* Casadei Table 1 (three-level comparator) and Table 3 (ST-A..ST-D, two-level) through the law:
 * for every sector, flux demand and torque demand the law's vector is the table's, after the
 * null-vector choice for the fewest commutations from the present vector. */
static void test_tables_through_the_law(void **state)
{
    (void)state;
    for (int table = DTC_ST_BASIC; table <= DTC_ST_D; table++) {
        sim_t s;
        dtc_out_t o;
        sim_defaults(&s);
        s.si.sstp_table = table;
        sim_start(&s, 0.0);
        im_dtc_t *c = &s.law.u.im;
        c->magnetised = 1U;
        for (int sec = 0; sec < 6; sec++) {
            for (int fu = 0; fu < 2; fu++) {
                for (int tu = 0; tu < 2; tu++) {
                    for (uint16_t present = 0U; present < 8U; present++) {
                        const double ang = sec * FIXTEST_PI / 3.0;
                        const double mag = fu ? 0.3 : 0.8;
                        uint16_t got, want;
                        c->est.psi_alpha_iq = fixtest_d_to_iq(mag * cos(ang));
                        c->est.psi_beta_iq = fixtest_d_to_iq(mag * sin(ang));
                        c->psi_ref_iq = s.cfg.speed.flux_ref_iq;
                        c->te_ref_iq = tu ? IQ(0.5) : IQ(-0.5);
                        c->vec_1 = present;
                        got = im_dtc_select(c, 0, &o);
                        want = table == DTC_ST_BASIC
                                   ? swtab_sstp_basic((uint16_t)(sec + 1), (uint16_t)fu, (int16_t)(tu ? 1 : -1))
                                   : swtab_sstp_st((uint16_t)table, (uint16_t)(sec + 1), (uint16_t)fu, (uint16_t)tu);
                        assert_int_equal(got, swtab_null_choice(want, present));
                        assert_int_equal(o.torque_dem, tu ? 1 : -1);
                        assert_int_equal(o.flux_up, fu);
                        assert_int_equal(o.sector, sec + 1);
                    }
                }
            }
        }
    }
}

/* ---- DSC ------------------------------------------------------------------------------------ */

/* |phi_s| range and mean machine torque over two electrical periods at the held speed w (pu). */
static void dsc_locus(sim_t *s, double w, double *lo, double *hi, double *tmean)
{
    dtc_out_t o;
    const long n = (long)periods(s, 2.0 * 2.0 * FIXTEST_PI / (w * s->b.w_base_rad_s));
    double tsum = 0.0;
    *lo = 1e9;
    *hi = 0.0;
    for (long k = 0; k < n; k++) {
        sim_period(s, &o);
        *lo = fmin(*lo, psis_mag(s));
        *hi = fmax(*hi, psis_mag(s));
        tsum += dtc_ref_im_torque(&s->x);
    }
    *tmean = tsum / (double)n;
}

/* Section 9: above the speed at which section 8 hands ST-D over to ST-A (table_speed) the DSC's
 * stator flux runs on a hexagon whose sides lie at phi_s* from the origin: |phi_s| ranges from
 * phi_s* (side centres) to phi_s* / cos 30 deg (vertices). Below it the law runs ST-D's circular
 * path (im_dsc_hexagon): |phi_s| within 5 % of phi_s*, far from the hexagon's 15.5 % spread. The
 * path changes with a hysteresis of table_speed/16 either side: at table_speed itself the path
 * the law came with is kept, both ways. Half the rated torque; the mean torque follows T* within
 * 10 % on both paths. */
static void test_dsc_hexagon(void **state)
{
    sim_t s;
    dtc_out_t o;
    double lo, hi, tm, ref, tref, ws;
    (void)state;

    sim_defaults(&s);
    s.si.law = DTC_LAW_IM_DSC;
    s.si.torque_ref_nm = 0.5 * s.si.rated_torque_nm;
    sim_start(&s, 0.0);
    ref = wb_to_pu(&s, s.si.flux_ref_wb);
    tref = nm_to_pu(&s, s.si.torque_ref_nm);
    ws = fixtest_iq_to_d(s.cfg.u.im.table_speed_iq);
    assert_true(ws > 0.0);
    /* below: the circle, and it stays at table_speed */
    sim_magnetise_at(&s, 0.5 * ws, 0.2, &o);
    dsc_locus(&s, 0.5 * ws, &lo, &hi, &tm);
    assert_int_equal(s.law.u.im.dsc_on, 0U);
    assert_true(fabs(lo / ref - 1.0) < 0.05 && fabs(hi / ref - 1.0) < 0.05);
    assert_true(fabs(tm / tref - 1.0) < 0.1);
    s.x.w = ws;
    dsc_locus(&s, ws, &lo, &hi, &tm);
    assert_int_equal(s.law.u.im.dsc_on, 0U);
    /* above: the hexagon, and it stays at table_speed */
    s.x.w = 1.25 * ws;
    dsc_locus(&s, 1.25 * ws, &lo, &hi, &tm); /* the speed estimate crosses the threshold here */
    dsc_locus(&s, 1.25 * ws, &lo, &hi, &tm);
    assert_int_equal(s.law.u.im.dsc_on, 1U);
    assert_true(fabs(lo / ref - 1.0) < 0.04);
    assert_true(fabs(hi / (ref / cos(FIXTEST_PI / 6.0)) - 1.0) < 0.04);
    assert_true(fabs(tm / tref - 1.0) < 0.1);
    s.x.w = ws;
    dsc_locus(&s, ws, &lo, &hi, &tm);
    assert_int_equal(s.law.u.im.dsc_on, 1U);
    assert_true(hi / lo > 1.1);
    /* and back to the circle below the band */
    s.x.w = 0.8 * ws;
    dsc_locus(&s, 0.8 * ws, &lo, &hi, &tm);
    assert_int_equal(s.law.u.im.dsc_on, 0U);
}

/* ---- flux weakening ------------------------------------------------------------------------- */

/* Section 12 at twice the base speed with the rated torque commanded: phi_s* falls below its
 * rated value (the torque demand not met at the voltage limit), changes at most once per window of
 * N >= 20 periods (section 12.3), stays within [phi_min, rated]; T* is Casadei eq. 33 limited by eq. 34
 * (double, from the law's phi_s*, within 1e-4 pu). The reference settles at the voltage limit:
 * below Casadei eq. 32's bound with the six-step fundamental and above 0.6 of it (not at the minimum;
 * measured 0.79). The machine's mean torque is below T* there (measured 0.79 of it): one period
 * with the demand met per window of N suffices for a step up, so the flux hovers where T* is just
 * reached now and then. */
static void test_flux_weakening(void **state)
{
    sim_t s;
    dtc_out_t o;
    iq_t last = 0;
    long last_change = -1000, min_gap = 1000000, n;
    double tsum = 0.0, trefsum = 0.0;
    (void)state;

    sim_defaults(&s);
    s.si.flux_weakening = 1;
    s.si.torque_trim_tau_s = 0.0; /* T* from the command by Casadei eqs. 33-34 only */
    s.si.torque_ref_nm = s.si.rated_torque_nm;
    sim_start(&s, 0.0);
    sim_magnetise_at(&s, 2.0, 0.0, &o);
    last = o.psi_ref_iq; /* the rated flux: the first window may have begun before this loop */
    n = (long)periods(&s, 0.3);
    for (long k = 0; k < n; k++) {
        sim_period(&s, &o);
        if (o.psi_ref_iq != last) {
            if (k - last_change < min_gap && k > 0) {
                min_gap = k - last_change;
            }
            last_change = k;
            last = o.psi_ref_iq;
        }
        {
            const double psi = fixtest_iq_to_d(o.psi_ref_iq);
            const double rated = fixtest_iq_to_d(s.cfg.speed.flux_ref_iq);
            const double tcmd = nm_to_pu(&s, s.si.torque_ref_nm);
            const double kt = fixtest_iq_to_d(s.cfg.u.im.fw.kt_iq);
            const double want = fmin(tcmd * psi / rated, kt * psi * psi); /* Casadei eqs. 33-34 */
            assert_true(fabs(fixtest_iq_to_d(o.te_ref_iq) - want) < 1e-4);
            assert_true(psi <= rated + 1e-6);
            assert_true(psi >= fixtest_iq_to_d(s.cfg.u.im.fw.psi_min_iq) - 1e-6);
        }
        if (k >= n - (long)periods(&s, 0.02)) {
            tsum += dtc_ref_im_torque(&s.x);
            trefsum += fixtest_iq_to_d(o.te_ref_iq);
        }
    }
    assert_true(fixtest_iq_to_d(o.psi_ref_iq) < 0.9 * fixtest_iq_to_d(s.cfg.speed.flux_ref_iq));
    assert_true(min_gap >= 20);
    {
        /* Casadei Eq. 32 with the inverter's largest fundamental, the six-step 2/pi V_dc (V_base = V_dc),
         * at the stator frequency 2 pu + slip: |phi_s| <= (2/pi) / w_s (R_s I_s neglected). */
        const double psi = fixtest_iq_to_d(o.psi_ref_iq);
        const double limit = (2.0 / FIXTEST_PI) / 2.0;
        printf("MEASURE flux weakening at 2 pu: phi_s* %.3f pu (rated %.3f, eq. 32 six-step bound %.3f), machine "
               "torque %.3f of T* over 20 ms, min gap %ld periods\n",
               psi, fixtest_iq_to_d(s.cfg.speed.flux_ref_iq), limit, tsum / trefsum, min_gap);
    }
    assert_true(fixtest_iq_to_d(o.psi_ref_iq) <= (2.0 / FIXTEST_PI) / 2.0);
    assert_true(fixtest_iq_to_d(o.psi_ref_iq) > 0.6 * (2.0 / FIXTEST_PI) / 2.0);
    assert_true(tsum / trefsum > 0.75 && tsum / trefsum < 1.05);
}

/* ---- sensorless speed ----------------------------------------------------------------------- */

/* Held speed 0.5 pu, rated torque, no encoder: the estimated speed (rotor-flux angular speed
 * minus the slip of Casadei eq. 16) is within 1 % of the speed; the slip it removes is the machine's
 * (w_slip = r_r T / phi_r^2, Casadei eq. 16), so the flux speed alone would be off by that. */
static void test_sensorless_speed(void **state)
{
    sim_t s;
    dtc_out_t o;
    double slip, sum = 0.0;
    long n;
    (void)state;

    sim_defaults(&s);
    s.si.speed_sensor = DTC_SPEED_NONE;
    s.si.torque_ref_nm = s.si.rated_torque_nm;
    sim_start(&s, 0.0);
    sim_magnetise_at(&s, 0.5, 0.2, &o);
    n = (long)periods(&s, 0.02);
    for (long k = 0; k < n; k++) {
        sim_period(&s, &o);
        sum += fixtest_iq_to_d(o.speed_iq);
    }
    slip = s.x.rr * dtc_ref_im_torque(&s.x) / (psir_mag(&s) * psir_mag(&s));
    assert_true(slip > 0.01); /* the check below would pass without Casadei eq. 16 otherwise */
    assert_true(fabs(sum / n - 0.5) < 0.005);
}

/* ---- encoder plausibility --------------------------------------------------------------------- */

/* The encoder plausibility's comparison (im_dtc.h) runs in a step of its own on the speed-loop
 * step's values. Encoder fitted, half the base speed, rated torque, after the
 * magnetisation, over 0.1 s: no speed-loop step sets plaus_on; after each speed-loop step the
 * step that leaves div_cnt at im_plaus_slot (2 with speed_div 10) compares (and no other);
 * plaus_err is, to the bit, the sensorless speed
 * (im_speed_step, Casadei eqs. 16, 22) of the speed-loop step's rotor-flux angle and torque
 * estimate less that step's encoder speed through the same filter, formed here from what the
 * speed-loop step left (the sums of a comparison made in the speed-loop step itself); and a sound
 * encoder stays within the configured tolerance. */
static void test_encoder_plausibility_compares_the_speed_loop_values_in_the_supervision_step(void **state)
{
    sim_t s;
    dtc_out_t o;
    im_speed_t ref;
    iq_t ref_filt = 0, te = 0, w = 0;
    angle_t th = 0U;
    uint16_t pending = 0U, synced = 0U;
    long n, k, ticks = 0, compared = 0;
    const im_dtc_t *c;
    (void)state;

    sim_defaults(&s);
    s.si.torque_ref_nm = s.si.rated_torque_nm;
    sim_start(&s, 0.0);
    sim_magnetise_at(&s, 0.5, 0.2, &o);
    c = &s.law.u.im;
    assert_true(c->cfg->u.im.ref.enc_plaus_iq > 0);
    assert_true(c->cfg->speed.speed_div > 4U); /* the comparison's step is not the speed loop's */
    assert_int_not_equal(im_plaus_slot(c->cfg->speed.speed_div), 1U);
    memset(&ref, 0, sizeof ref);
    n = (long)periods(&s, 0.1);
    for (k = 0; k < n; k++) {
        sim_period(&s, &o);
        if (o.speed_tick != 0U) {
            assert_int_equal(c->plaus_on, 0U);
            if (synced == 0U) { /* the filters' state before this speed period's comparison */
                ref = c->isp;
                ref_filt = c->enc_filt_iq;
                synced = 1U;
            }
            th = c->est.theta_r;
            te = o.te_iq;
            w = c->speed_iq;
            pending = synced;
            ticks++;
        } else if (pending != 0U && c->div_cnt == im_plaus_slot(c->cfg->speed.speed_div)) {
            im_speed_step(&ref, &c->isp_p, th, te, c->cfg->u.im.ref.inv_psir_sq_iq);
            ref_filt = im_speed_lpf(ref_filt, w, c->isp_p.k_filt_q31);
            assert_int_equal(c->plaus_on, 1U);
            assert_int_equal(c->plaus_err_iq, fix_sub32(ref.speed_iq, ref_filt));
            assert_true(fix_abs32(c->plaus_err_iq) < c->cfg->u.im.ref.enc_plaus_iq);
            pending = 0U;
            compared++;
        } else {
            assert_int_equal(c->plaus_on, 0U);
        }
    }
    assert_true(ticks >= 20);
    assert_true(compared >= ticks - 1);
}

/* The current prediction the application's sensor plausibility reads (law.h law_i_pred,
 * im_dtc.h im_dtc_i_pred) against the double-precision machine (dtc_ref_im) the law drives, with
 * the encoder at rated torque and half the base speed: after each step, the predicted phase-A
 * current of the next sample is the machine's current of that sample within a few per cent of the
 * current's change over the period (the forward Euler step of Casadei eqs. A7-A9 and the flux
 * estimate), while a prediction of no change at all misses by the whole change. */
static void test_current_prediction_matches_the_machine(void **state)
{
    sim_t s;
    dtc_out_t o;
    double e2 = 0.0, d2 = 0.0;
    long n, k;
    (void)state;

    sim_defaults(&s);
    s.si.torque_ref_nm = s.si.rated_torque_nm;
    sim_start(&s, 0.0);
    sim_magnetise_at(&s, 0.5, 0.2, &o);
    n = (long)periods(&s, 0.02);
    for (k = 0; k < n; k++) {
        iq_t i1[3];
        double ia0, ib0, ia1, ib1;
        dtc_ref_im_currents(&s.x, &ia0, &ib0);
        sim_period(&s, &o);
        assert_int_equal(law_i_pred(&s.law, IQ(1.0), i1), 1U);
        dtc_ref_im_currents(&s.x, &ia1, &ib1); /* the machine at the next sample */
        e2 += (fixtest_iq_to_d(i1[0]) - ia1) * (fixtest_iq_to_d(i1[0]) - ia1);
        d2 += (ia1 - ia0) * (ia1 - ia0);
    }
    printf("MEASURE IM current prediction: rms error %.4f pu against an rms change of %.4f pu a period\n",
           sqrt(e2 / (double)n), sqrt(d2 / (double)n));
    assert_true(d2 > 0.0);
    assert_true(e2 < 0.05 * 0.05 * d2);
}

/* The current model behind Casadei eq. 20's reference at low speed (im_sup.h, im_dtc_internal.h
 * im_cm_ref), encoder fitted, 10 % of rated torque held at 5 % of the base speed: over 0.2 s after
 * the settling
 *   - the firmware's model against the same recursion in double precision, from the same sampled
 *     currents and encoder counts (the rotation of a step: its count difference times
 *     2 pi p / counts), with m and Ts/tau_r from the SI machine: within 1e-4 pu;
 *   - the model's rotor flux against the machine's (the double T model, the same instant): the T
 *     model's rotor equation with the machine's parameters is exact, so within 1 % of |phi_r|, and
 *     the estimate's rotor flux (eq. 21) with it;
 *   - the blend weight against b = clamp(4/3 - (w Ts)^2 / (3W), 0, 1), W = k_r (Ts/tau)(Ts/tau_r)
 *     from the SI values, within 1e-3, and b = 1 here (the slow pole w^2 tau / k_r below 1/tau_r);
 * then at the base speed b = 0 and the paper's reference alone (in->ref_vec 0). */
static void test_current_model_reference_at_low_speed(void **state)
{
    sim_t s;
    dtc_out_t o;
    double ca = 0.0, cb = 0.0, mia = 0.0, mib = 0.0, worst_fx = 0.0, worst_cm = 0.0, worst_est = 0.0;
    double kr, W, w_ts, b, cnt_prev;
    long k, n;
    const im_dtc_t *c;
    (void)state;

    sim_defaults(&s);
    s.si.cm_ref = 0; /* off: Casadei eq. 20 at every speed */
    sim_start(&s, 0.05);
    assert_int_equal(s.law.u.im.sup.cm_on, 0U);
    assert_int_equal(s.law.u.im.sup.cm_b_iq, 0);
    s.si.cm_ref = 1; /* the converter's default */
    s.si.torque_ref_nm = 0.1 * s.si.rated_torque_nm;
    sim_start(&s, 0.05);
    sim_magnetise_at(&s, 0.05, 0.5, &o);
    c = &s.law.u.im;
    kr = s.lr / s.m;
    W = kr * (s.si.ts_s / s.si.tau_lo_s) * (s.si.ts_s * s.si.rr_ohm / ((s.si.llr_h + s.si.lm_h)));
    assert_int_equal(c->sup.cm_on, 1U);
    ca = fixtest_iq_to_d(c->sup.cm_alpha_iq);
    cb = fixtest_iq_to_d(c->sup.cm_beta_iq);
    mia = fixtest_iq_to_d(c->sup.cm_mi_alpha_iq);
    mib = fixtest_iq_to_d(c->sup.cm_mi_beta_iq);
    n = (long)periods(&s, 0.2);
    cnt_prev = enc_turn_counts(&s, s.theta_e - s.x.w * s.tspu); /* the last step's count */
    for (k = 0; k < n; k++) {
        const double pra = s.x.pra, prb = s.x.prb, kt = s.si.ts_s * s.si.rr_ohm / (s.si.llr_h + s.si.lm_h);
        const double cnt = enc_turn_counts(&s, s.theta_e); /* the count this step reads */
        double wt, na;
        sim_period(&s, &o);
        /* the double recursion: the previous instant's m i, the rotation of the count step */
        wt = (cnt - cnt_prev) * 2.0 * FIXTEST_PI * s.si.pole_pairs / (4.0 * s.si.enc_lines);
        cnt_prev = cnt;
        na = ca + kt * (mia - ca) - wt * cb;
        cb = cb + kt * (mib - cb) + wt * na;
        ca = na;
        mia = s.m * fixtest_iq_to_d(c->i.i_alpha_iq);
        mib = s.m * fixtest_iq_to_d(c->i.i_beta_iq);
        worst_fx = fmax(worst_fx, hypot(fixtest_iq_to_d(c->sup.cm_alpha_iq) - ca, fixtest_iq_to_d(c->sup.cm_beta_iq) - cb));
        worst_cm = fmax(worst_cm, hypot(fixtest_iq_to_d(c->sup.cm_alpha_iq) - pra, fixtest_iq_to_d(c->sup.cm_beta_iq) - prb) /
                                      hypot(pra, prb));
        worst_est = fmax(worst_est, hypot(fixtest_iq_to_d(c->est.psir_alpha_iq) - pra,
                                          fixtest_iq_to_d(c->est.psir_beta_iq) - prb) / hypot(pra, prb));
    }
    w_ts = fixtest_iq_to_d(c->speed_iq) * s.tspu;
    b = fmin(1.0, fmax(0.0, 4.0 / 3.0 - w_ts * w_ts / (3.0 * W)));
    printf("MEASURE IM current model at 5 %% speed: fixed vs double %.2e pu; vs the machine's rotor flux %.3f %%, "
           "the estimate's %.3f %%; b %.4f (double %.4f)\n",
           worst_fx, 100.0 * worst_cm, 100.0 * worst_est, fixtest_iq_to_d(c->sup.cm_b_iq), b);
    assert_true(worst_fx < 1e-4);
    assert_true(worst_cm < 0.01);
    assert_true(worst_est < 0.01);
    assert_true(fabs(fixtest_iq_to_d(c->sup.cm_b_iq) - b) < 1e-3);
    assert_true(b > 0.999);
    assert_int_equal(c->ein.ref_vec, 1U);

    /* halfway in the blend, (w Ts)^2 = 2.5 W: b = 1/2 */
    s.x.w = sqrt(2.5 * W) / s.tspu;
    for (k = 0; k < (long)periods(&s, 0.05); k++) {
        sim_period(&s, &o);
    }
    while (c->div_cnt != c->sup.slot) { /* to the supervision's step of this speed period */
        sim_period(&s, &o);
    }
    w_ts = fixtest_iq_to_d(c->speed_iq) * s.tspu;
    b = fmin(1.0, fmax(0.0, 4.0 / 3.0 - w_ts * w_ts / (3.0 * W)));
    printf("MEASURE IM current model blend at w %.4f pu: b %.4f (double %.4f)\n", fixtest_iq_to_d(c->speed_iq),
           fixtest_iq_to_d(c->sup.cm_b_iq), b);
    assert_true(b > 0.4 && b < 0.6);
    assert_true(fabs(fixtest_iq_to_d(c->sup.cm_b_iq) - b) < 1e-3);
    assert_int_equal(c->ein.ref_vec, 1U);

    /* the base speed: the slow pole far above 4/tau_r, the paper's reference alone */
    s.x.w = 1.0;
    for (k = 0; k < (long)periods(&s, 0.05); k++) {
        sim_period(&s, &o);
    }
    w_ts = fixtest_iq_to_d(c->speed_iq) * s.tspu;
    assert_true(w_ts * w_ts > 4.0 * W);
    assert_int_equal(c->sup.cm_b_iq, 0);
    assert_int_equal(c->ein.ref_vec, 0U);
}

/* DSVM (im_dsvm.c): the voltage kept for the estimator is the period's mean voltage less R_s times
 * the mean of the current's ripple about the straight line between the two samples, so that the
 * estimator's resistive drop on the sampled current (im_est.h) is R_s times the period's mean
 * current. Checked against the double machine: the law runs at 5 % of the base speed at 10 % of
 * rated torque; at every step the pattern it returns is applied to a copy of the machine third
 * by third (RK4, 40 sub-steps a third), the current's mean over the period measured, and the
 * law's kept voltage (v1, the pattern's) compared with the mean voltage less r_s (i_mean - i_line).
 * The ripple's drop is asserted above 1e-4 pu on some periods (measured 3.6e-4 pu, 2.6 % of r_s
 * times the magnetising current, against the IQ resolution of 6e-8 pu), so the check of the kept
 * voltage to 5 % of it cannot pass with the term left out. */
/* The DFOC's rotor-flux term (im_dfoc.c im_dfoc_id_ref): while regenerating (T* w_s < 0) i_d* m is
 * phi_r* + K_f (phi_r* - |phi_r|) with K_f = (l_r/m)(tau_r/tau), the flux loop as fast as Casadei
 * eq. 20's correction (l_r/m)/tau, which closes the loop of the estimate's angle error through the
 * machine's i_d (gain (l_r/m)(i_q/i_d)/(tau w_s), docs/sil.md); motoring, or before the machine is
 * magnetised, nothing beyond the trim. Expected values from the SI machine. */
static void test_dfoc_flux_term_only_while_regenerating(void **state)
{
    sim_t s;
    (void)state;
    sim_defaults(&s);
    s.si.law = DTC_LAW_IM_DFOC;
    s.si.psir_ref_wb = 0.53;
    sim_start(&s, 0.0);
    {
        im_dtc_t *c = &s.law.u.im;
        const double tau_r = (s.si.llr_h + s.si.lm_h) / s.si.rr_ohm;
        const double kf = (s.si.llr_h + s.si.lm_h) / s.si.lm_h * tau_r / s.si.tau_lo_s;
        const double psir = 0.53 / s.b.psi_base_wb, e = 0.02 / s.b.psi_base_wb; /* 20 mWb low */
        const double id0 = fixtest_iq_to_d(s.cfg.u.im.dfoc.id_ref_iq);
        const int32_t kf_q16 = c->foc_kf_q16;
        /* the gain per Ts/tau: (l_r/m)(tau_r/Ts) */
        assert_true(fabs((double)kf_q16 / 65536.0 - kf * s.si.tau_lo_s / s.si.ts_s) < 1e-4 * kf * s.si.tau_lo_s / s.si.ts_s);
        c->magnetised = 1U;
        c->psir_trim_iq = 0;
        c->est.k_q31 = s.cfg.u.im.est.k_lo_q31;
        c->psir_ref_iq = s.cfg.u.im.ref.psir_ref_iq;
        c->est.psir_mag_iq = (iq_t)lround((psir - e) * 16777216.0);
        c->speed_iq = IQ(0.5);
        c->sr_ws_iq = IQ(0.5);
        c->te_ref_iq = IQ(-0.3); /* braking: T* w_s < 0 */
        im_dfoc_id_ref(c);
        assert_true(fabs(fixtest_iq_to_d(c->foc_id_ref_iq) - id0 * (1.0 + kf * e / psir)) < 2e-3 * id0);
        c->te_ref_iq = IQ(0.3); /* motoring: the loop is negative, the trim alone */
        im_dfoc_id_ref(c);
        assert_true(fabs(fixtest_iq_to_d(c->foc_id_ref_iq) - id0) < 1e-6);
        c->te_ref_iq = IQ(-0.3);
        c->magnetised = 0U; /* the start-up: nothing */
        im_dfoc_id_ref(c);
        assert_true(fabs(fixtest_iq_to_d(c->foc_id_ref_iq) - id0) < 1e-6);
        printf("MEASURE DFOC flux term: K_f %.2f (tau_r %.4f s, tau %.4f s), i_d* %.4f pu for %.4f at 20 mWb low\n", kf,
               tau_r, s.si.tau_lo_s, id0 * (1.0 + kf * e / psir), id0);
    }
}

static void test_dsvm_voltage_takes_the_mean_ripple_current(void **state)
{
    sim_t s;
    dtc_out_t o;
    double worst = 0.0, big = 0.0, rs;
    long k;
    (void)state;

    sim_defaults(&s);
    s.si.law = DTC_LAW_IM_DSVM;
    s.si.dead_time_s = 0.0; /* the reference inverter has none */
    s.si.torque_ref_nm = 0.1 * s.si.rated_torque_nm;
    sim_start(&s, 0.05);
    sim_magnetise_at(&s, 0.05, 0.2, &o);
    rs = s.si.rs_ohm / s.b.z_base_ohm;
    for (k = 0; k < 2000; k++) {
        dtc_ref_im_t y;
        double i0a, i0b, i3a, i3b, sa = 0.0, sb = 0.0, va = 0.0, vb = 0.0, ea, eb, fa, fb;
        int t, j;
        const im_dtc_t *c = &s.law.u.im;
        sim_period(&s, &o);
        y = s.x;
        dtc_ref_im_currents(&y, &i0a, &i0b);
        for (t = 0; t < 3; t++) {
            double pa, pb;
            const int bit = 2 - t;
            dtc_ref_sstp_ideal((o.thirds[0] >> bit) & 1, (o.thirds[1] >> bit) & 1, (o.thirds[2] >> bit) & 1, 1.0,
                               &pa, &pb);
            va += pa / 3.0;
            vb += pb / 3.0;
            for (j = 0; j < 40; j++) {
                double ia, ib, ja, jb;
                dtc_ref_im_currents(&y, &ia, &ib);
                dtc_ref_im_step(&y, pa, pb, s.tspu / 120.0, 1);
                dtc_ref_im_currents(&y, &ja, &jb);
                sa += (ia + ja) / 2.0 / 120.0;
                sb += (ib + jb) / 2.0 / 120.0;
            }
        }
        dtc_ref_im_currents(&y, &i3a, &i3b);
        /* expected: mean voltage less r_s times the ripple's mean; the law's v1 (V_dc = 1 pu) */
        ea = va - rs * (sa - 0.5 * (i0a + i3a));
        eb = vb - rs * (sb - 0.5 * (i0b + i3b));
        fa = fixtest_iq_to_d(c->v1_alpha_iq);
        fb = fixtest_iq_to_d(c->v1_beta_iq);
        worst = fmax(worst, hypot(fa - ea, fb - eb));
        big = fmax(big, rs * hypot(sa - 0.5 * (i0a + i3a), sb - 0.5 * (i0b + i3b)));
    }
    printf("MEASURE DSVM kept voltage: worst error %.2e pu; largest ripple drop %.2e pu (r_s i_d %.2e pu)\n", worst,
           big, rs * hypot(s.x.pra, s.x.prb) / s.m);
    assert_true(big > 1e-4);
    assert_true(worst < 0.05 * big);
}

/* The live reconfiguration after a leg failure (im_dtc_reconfigure): the host's post-fault
 * configuration is the same IM DTC on the FSTP with the FSTP's compensation and the flux scaled to
 * what the FSTP's voltage holds (dtc_config_post_fault_si); the estimator's vectors are turned by
 * -x 120 deg into the frame whose phase A' is the failed phase x (Clarke of the permuted phases,
 * against a double rotation), the rotor-flux angle with them, the leg history permuted, the
 * relay's interval armed, the failed phase's axis of a magnetised estimate taken again from the
 * rotor flux (im_dtc_reconfig.c im_reseed_alpha); a phase beyond C, a post of another law or topology and a running law
 * other than the DTC are refused with the controller unchanged. */
static void test_reconfigure_turns_the_estimate_into_the_new_frame(void **state)
{
    dtc_config_si_t si, post_si;
    dtc_config_t pre, post, bad;
    char msg[200];
    int x;
    (void)state;
    dtc_config_si_im_defaults(&si);
    si.i_sensors3 = 1;
    si.reconfig_relay = 1;
    si.relay_delay_s = 15e-3;
    si.mode = DTC_MODE_SPEED;
    si.speed_ref_rpm = 1000.0;
    si.psir_ref_wb = 0.53;
    assert_int_equal(dtc_config_from_si(&si, &pre, msg, sizeof msg), DTC_SI_OK);
    assert_int_equal(dtc_config_post_fault_si(&si, &post_si), DTC_SI_OK);
    assert_int_equal(post_si.topology, DTC_TOPO_FSTP);
    assert_int_equal(post_si.compensation, DTC_COMP_FSTP_SIMPLE);
    /* the stator flux the circle inside the FSTP's rhombus holds after R_s I_n at 1000 rpm plus
     * the rated slip (Casadei eq. 16), over the configured flux; the rhombus's alpha vertex V_dc/3
     * less 2/3 of the mid-point's swing I_n / (2 C w_e), its beta vertex V_dc/sqrt3 */
    {
        const double psir = 0.53, ws = si.rr_ohm * si.rated_torque_nm / (1.5 * si.pole_pairs * psir * psir);
        const double we = 1000.0 * FIXTEST_PI / 30.0 * si.pole_pairs + ws;
        const double a = si.vdc_v / 3.0 - 2.0 / 3.0 * si.rated_current_a / (2.0 * si.c_dc_f * we);
        const double b = si.vdc_v / sqrt(3.0);
        const double k = (a * b / sqrt(a * a + b * b) - si.rs_ohm * si.rated_current_a) / we / si.flux_ref_wb;
        assert_true(si.c_dc_f > 0.0);
        assert_true(k < 1.0);
        assert_true(fabs(post_si.flux_ref_wb - k * si.flux_ref_wb) < 1e-9);
        assert_true(fabs(post_si.psir_ref_wb - k * 0.53) < 1e-9);
    }
    assert_int_equal(dtc_config_from_si(&post_si, &post, msg, sizeof msg), DTC_SI_OK);
    for (x = 0; x < 3; x++) {
        im_dtc_t c;
        const double r = -2.0 * FIXTEST_PI * x / 3.0;
        const double v[5][2] = {{0.6, -0.3}, {0.55, 0.2}, {-0.4, 0.7}, {0.1, -0.9}, {0.02, 0.03}};
        iq_t *const f[5][2] = {{&c.est.psi_alpha_iq, &c.est.psi_beta_iq}, {&c.est.psir_alpha_iq, &c.est.psir_beta_iq},
                               {&c.est.x_alpha_iq, &c.est.x_beta_iq}, {&c.est.u_alpha_iq, &c.est.u_beta_iq},
                               {&c.est.ri_alpha_iq, &c.est.ri_beta_iq}};
        const uint16_t l[3] = {1U, 0U, 1U};
        int k;
        assert_int_equal(im_dtc_init(&c, &pre), DTC_OK);
        for (k = 0; k < 5; k++) {
            *f[k][0] = IQ(v[k][0]);
            *f[k][1] = IQ(v[k][1]);
        }
        c.est.theta_r = 12000U;
        c.legs_1.sa = l[0];
        c.legs_1.sb = l[1];
        c.legs_1.sc = l[2];
        assert_int_equal(im_dtc_reconfigure(&c, &post, 3U), DTC_ERR_RECONFIG);
        assert_ptr_equal(c.cfg, &pre);
        assert_int_equal(im_dtc_reconfigure(&c, &post, (uint16_t)x), DTC_OK);
        assert_ptr_equal(c.cfg, &post);
        for (k = 0; k < 5; k++) {
            const double ra = cos(r) * v[k][0] - sin(r) * v[k][1], rb = sin(r) * v[k][0] + cos(r) * v[k][1];
            assert_true(fabs(*f[k][0] / 16777216.0 - ra) < 1e-4);
            assert_true(fabs(*f[k][1] / 16777216.0 - rb) < 1e-4);
        }
        /* -x 120 deg in angle_t (21845.33 LSB per 120 deg) */
        {
            const long want = (12000L - lround(x * 65536.0 / 3.0)) & 0xFFFFL;
            const long d = (long)c.est.theta_r - want;
            assert_true(d >= -1L && d <= 1L);
        }
        /* legs (a, b, c) = (1, 0, 1): b' = leg x+1, c' = leg x+2, a' (the failed leg) off */
        assert_int_equal(c.legs_1.sa, 0U);
        assert_int_equal(c.legs_1.sb, l[(x + 1) % 3]);
        assert_int_equal(c.legs_1.sc, l[(x + 2) % 3]);
        assert_int_equal(c.open_wait, post.prot.relay_periods);
        assert_int_equal(c.il_p.fstp, 1U);
        assert_int_equal(c.dt_p.fstp, 1U);
        assert_int_equal(c.psir_fall, 0U); /* not magnetised: no rotor flux to follow */
    }
    /* A magnetised drive: the alpha part (the failed phase's axis) is taken again from the turned
     * beta part and the estimator's rotor-flux reference, x = (m/l_r) phi_r* (Casadei eq. 21),
     * x_alpha = sign(x_alpha) sqrt(|x|^2 - x_beta^2), phi_s,alpha = x_alpha (i_alpha = 0),
     * phi_r,alpha = (l_r/m) x_alpha, against a double reference; the rotor flux then followed from
     * the reference in force. */
    for (x = 0; x < 3; x++) {
        im_dtc_t c;
        const double r = -2.0 * FIXTEST_PI * x / 3.0, xa0 = 0.3, xb0 = -0.2;
        const double xb = sin(r) * xa0 + cos(r) * xb0, xa_turned = cos(r) * xa0 - sin(r) * xb0;
        const double kr = (si.llr_h + si.lm_h) / si.lm_h;
        double xm, xa;
        assert_int_equal(im_dtc_init(&c, &pre), DTC_OK);
        c.magnetised = 1U;
        c.psir_ref_iq = pre.u.im.ref.psir_ref_iq;
        c.est.x_alpha_iq = IQ(xa0);
        c.est.x_beta_iq = IQ(xb0);
        assert_int_equal(im_dtc_reconfigure(&c, &post, (uint16_t)x), DTC_OK);
        xm = c.psir_ref_iq / 16777216.0 / kr;
        xa = (xa_turned < 0.0 ? -1.0 : 1.0) * sqrt(xm * xm - xb * xb);
        assert_true(fabs(c.est.x_beta_iq / 16777216.0 - xb) < 1e-4);
        assert_true(fabs(c.est.x_alpha_iq / 16777216.0 - xa) < 1e-4);
        assert_int_equal(c.est.psi_alpha_iq, c.est.x_alpha_iq);
        assert_true(fabs(c.est.psir_alpha_iq / 16777216.0 - kr * xa) < 1e-4);
        assert_int_equal(c.psir_fall, 1U);
        assert_int_equal(c.magn_psir_iq, c.psir_ref_iq);
    }
    {
        im_dtc_t c;
        assert_int_equal(im_dtc_init(&c, &pre), DTC_OK);
        bad = post;
        bad.board.topology = DTC_TOPO_SSTP;
        bad.est.compensation = DTC_COMP_SSTP;
        assert_int_equal(im_dtc_reconfigure(&c, &bad, 0U), DTC_ERR_RECONFIG);
        bad = post;
        bad.law = DTC_LAW_IM_DSC;
        assert_int_equal(im_dtc_reconfigure(&c, &bad, 0U), DTC_ERR_RECONFIG);
        bad = pre;
        bad.law = DTC_LAW_IM_DSC;
        assert_int_equal(im_dtc_init(&c, &bad), DTC_OK);
        assert_int_equal(im_dtc_reconfigure(&c, &post, 0U), DTC_ERR_RECONFIG);
        assert_ptr_equal(c.cfg, &bad);
    }
}

UNIT_TEST_MAIN("im dtc", NULL,
               cmocka_unit_test(test_bad_im_config_refused_with_field),
               cmocka_unit_test(test_startup_magnetises_then_torque),
               cmocka_unit_test(test_startup_current_is_dc),
               cmocka_unit_test(test_voltage_model_start_up_magnetises_but_cannot_hold_standstill_flux),
               cmocka_unit_test(test_constant_rotor_flux_torque_step),
               cmocka_unit_test(test_speed_dependent_table),
               cmocka_unit_test(test_tables_through_the_law),
               cmocka_unit_test(test_dsc_hexagon),
               cmocka_unit_test(test_flux_weakening),
               cmocka_unit_test(test_sensorless_speed),
               cmocka_unit_test(test_encoder_plausibility_compares_the_speed_loop_values_in_the_supervision_step),
               cmocka_unit_test(test_current_prediction_matches_the_machine),
        cmocka_unit_test(test_current_model_reference_at_low_speed),
               cmocka_unit_test(test_dfoc_flux_term_only_while_regenerating),
               cmocka_unit_test(test_dsvm_voltage_takes_the_mean_ripple_current),
               cmocka_unit_test(test_reconfigure_turns_the_estimate_into_the_new_frame))
