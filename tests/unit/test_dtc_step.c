/*
 * test_dtc_step.c - the whole controller, dtc_step(), closed loop against a double-precision
 * surface PM machine (Hoang eqs. 6-10) fed by an ideal SSTP or FSTP inverter (Hoang Table I,
 * Casadei eq. 2) with the one-period actuation delay of hal.h; plus the timing contract, the
 * speed-loop rate, the shadow set and the mode switch.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>

#include "dtc.h"
#include "dtc_internal.h"
#include "vrec.h"
#include "dtc_config_si.h"
#include "dtc_ref.h"
#include "fixtest.h"

typedef struct {
    dtc_config_si_t si;
    dtc_config_t cfg;
    dtc_bases_t b;
    dtc_ref_pm_t m;
    double w_mech;    /* rad/s */
    double j_kgm2;    /* 0: constant speed */
    double load_nm;
    double tspu;
    int drops;            /* 1: the FSTP inverter has the Hoang Table III/IV drops and R_on */
    swtab_legs_t applied; /* legs in force during the current period */
} sim_t;

static void sim_init(sim_t *s, int topo, int est, int comp, int table, double rpm)
{
    dtc_config_si_defaults(&s->si);
    s->si.topology = topo;
    s->si.estimator = est;
    s->si.compensation = comp;
    s->si.sstp_table = table;
    s->si.dead_time_s = 0.0; /* the plant below has no dead time */
    assert_int_equal(dtc_config_from_si(&s->si, &s->cfg, NULL, 0), DTC_SI_OK);
    dtc_bases_from_si(&s->si, &s->b);
    s->w_mech = rpm * DTC_REF_PI / 30.0;
    s->tspu = s->si.ts_s * s->b.w_base_rad_s;
    dtc_ref_pm_init(&s->m, s->si.rs_ohm / s->b.z_base_ohm, s->si.ls_h / s->b.l_base_h,
                    s->si.psi_m_wb / s->b.psi_base_wb, s->w_mech / s->b.w_base_rad_s, 0.3, 0.0, 0.0);
    s->j_kgm2 = 0.0;
    s->load_nm = 0.0;
    s->drops = 0;
    s->applied = (swtab_legs_t){0U, 0U, 0U};
}

static void sim_meas(const sim_t *s, dtc_meas_t *me)
{
    double ia, ib;
    dtc_ref_pm_currents(&s->m, &ia, &ib);
    double a = ia, b = -0.5 * ia + 0.5 * sqrt(3.0) * ib, c = -0.5 * ia - 0.5 * sqrt(3.0) * ib;
    me->ia_iq = fixtest_d_to_iq(a);
    me->ib_iq = fixtest_d_to_iq(b);
    me->ic_iq = fixtest_d_to_iq(c);
    me->vdc_iq = IQ(1.0);
    me->vmid_iq = IQ(0.5);
    double turns = s->m.theta / (2.0 * DTC_REF_PI); /* p = 1: electrical = mechanical */
    double cnt = fmod(floor(turns * 8000.0), 8000.0);
    me->enc_count = (uint16_t)(cnt < 0 ? cnt + 8000.0 : cnt);
}

/* One control period: measure, step the controller, advance the plant with the legs written
 * by the PREVIOUS step (hal.h: a command takes effect at the next period boundary). */
static void sim_period(sim_t *s, dtc_t *c, dtc_out_t *o)
{
    dtc_meas_t me;
    double va, vb;
    sim_meas(s, &me);
    dtc_step(c, &me, o);
    if (s->si.topology == DTC_TOPO_FSTP && s->drops) {
        double ia, ib;
        dtc_ref_pm_currents(&s->m, &ia, &ib);
        dtc_ref_fstp_inverter(s->applied.sb, s->applied.sc, 1.0,
                              -0.5 * ia + 0.5 * sqrt(3.0) * ib, -0.5 * ia - 0.5 * sqrt(3.0) * ib,
                              s->si.v_ce_v / s->b.v_base_v, s->si.v_d_v / s->b.v_base_v,
                              s->si.r_on_ohm / s->b.z_base_ohm, &va, &vb);
    } else if (s->si.topology == DTC_TOPO_FSTP) {
        va = (1.0 - s->applied.sb - s->applied.sc) / 3.0; /* Hoang eqs. 17-19, Table I */
        vb = ((double)s->applied.sb - (double)s->applied.sc) / sqrt(3.0);
    } else {
        dtc_ref_clarke3(s->applied.sa, s->applied.sb, s->applied.sc, &va, &vb);
    }
    dtc_ref_pm_step(&s->m, va, vb, s->tspu, 4);
    if (s->j_kgm2 > 0.0) {
        double t_nm = dtc_ref_pm_torque(&s->m) * s->b.t_base_nm;
        s->w_mech += (t_nm - s->load_nm) / s->j_kgm2 * s->si.ts_s;
        s->m.w = s->w_mech / s->b.w_base_rad_s;
    }
    s->applied = (swtab_legs_t){o->sa, o->sb, o->sc};
}

/* Torque mode at constant speed: mean torque and flux over the last 0.1 s. */
static void torque_run(int topo, int est, int comp, int table, double rpm, double tref_pu,
                       double *t_mean, double *psi_mean, double *est_err)
{
    sim_t s;
    dtc_t c;
    dtc_out_t o;
    sim_init(&s, topo, est, comp, table, rpm);
    s.cfg.speed.mode = DTC_MODE_TORQUE;
    s.cfg.speed.torque_ref_iq = fixtest_d_to_iq(tref_pu);
    assert_int_equal(dtc_init(&c, &s.cfg), DTC_OK);
    double ts = 0.0, ps = 0.0, ee = 0.0;
    int n = 0;
    for (int k = 0; k < 30000; k++) { /* 1.5 s: the voltage model's LPF settles (tau 0.2 s) */
        sim_period(&s, &c, &o);
        if (k >= 28000) {
            ts += dtc_ref_pm_torque(&s.m);
            ee += fixtest_iq_to_d(o.te_iq);
            ps += hypot(s.m.psi_a, s.m.psi_b);
            n++;
        }
    }
    /* estimate vs plant at the last sample (the estimate refers to the start of the period) */
    *t_mean = ts / n;
    *psi_mean = ps / n;
    *est_err = ee / n;
}

static void test_closed_loop_torque_mode(void **state)
{
    (void)state;
    const double psim = 0.0928 / (70.0 / (100 * DTC_REF_PI)), tref = 0.3;
    struct { int topo, est, comp, table; double rpm; const char *name; } runs[] = {
        {DTC_TOPO_FSTP, DTC_EST_CURRENT, DTC_COMP_NONE, 0, 1500.0, "FSTP current model 1500 rpm"},
        {DTC_TOPO_FSTP, DTC_EST_VOLTAGE, DTC_COMP_NONE, 0, 1500.0, "FSTP voltage model 1500 rpm"},
        {DTC_TOPO_SSTP, DTC_EST_CURRENT, DTC_COMP_NONE, DTC_ST_BASIC, 1500.0, "SSTP basic current 1500 rpm"},
        {DTC_TOPO_SSTP, DTC_EST_VOLTAGE, DTC_COMP_NONE, DTC_ST_A, 1500.0, "SSTP ST-A voltage 1500 rpm"},
        {DTC_TOPO_SSTP, DTC_EST_CURRENT, DTC_COMP_NONE, DTC_ST_D, 300.0, "SSTP ST-D current 300 rpm"},
        {DTC_TOPO_FSTP, DTC_EST_CURRENT, DTC_COMP_NONE, 0, 300.0, "FSTP current model 300 rpm"},
    };
    for (size_t k = 0; k < sizeof runs / sizeof runs[0]; k++) {
        double tm, pm, ee;
        torque_run(runs[k].topo, runs[k].est, runs[k].comp, runs[k].table, runs[k].rpm, tref,
                   &tm, &pm, &ee);
        print_message("%-30s mean torque %.4f pu (ref %.3f, estimated %.4f), mean |psi| %.4f pu "
                      "(ref %.4f)\n", runs[k].name, tm, tref, ee, pm, psim);
        /* The estimate agrees with the plant (current model: sampling only; voltage model: plus
         * the LPF's 3 % vector error at 1500 rpm, 0.02 pu of torque). */
        assert_true(fabs(ee - tm) < (runs[k].est == DTC_EST_CURRENT ? 0.002 : 0.02));
        /* The flux loop holds |psi| on its reference (zero band: within 1 %). */
        assert_true(fabs(pm - psim) < 0.01 * psim);
        /* The torque loop: with zero bands, one period of actuation delay and this machine's
         * small inductance (3.19 mH: one 50 us period of an active vector moves the torque by
         * psi_m * |v - e| * Ts / L_s = 0.07..0.16 pu), the hysteresis overshoots asymmetrically
         * (rising and falling slopes differ at speed), so the MEAN torque sits off the
         * reference by up to ~0.09 pu in torque mode (measured: 0.21..0.32 pu for 0.3 pu): a property of hysteresis DTC at
         * this sampling rate, not of the estimator (which matches the plant, above). In speed
         * mode the PI integrator absorbs it (test_closed_loop_speed_mode). */
        assert_true(fabs(tm - tref) < 0.1);
    }
}

static void test_closed_loop_speed_mode(void **state)
{
    (void)state;
    sim_t s;
    dtc_t c;
    dtc_out_t o;
    sim_init(&s, DTC_TOPO_FSTP, DTC_EST_CURRENT, DTC_COMP_NONE, 0, 0.0);
    s.j_kgm2 = s.si.inertia_kgm2; /* the inertia the PI was designed for */
    s.load_nm = 0.1;
    assert_int_equal(dtc_init(&c, &s.cfg), DTC_OK); /* speed mode, 1500 rpm reference */
    double ws = 0.0, wmax = 0.0;
    int n = 0, ticks = 0;
    for (int k = 0; k < 10000; k++) { /* 0.5 s */
        sim_period(&s, &c, &o);
        ticks += o.speed_tick;
        double rpm = s.w_mech * 30.0 / DTC_REF_PI;
        wmax = fmax(wmax, rpm);
        if (k >= 8000) {
            ws += rpm;
            n++;
        }
        assert_true(fabs(fixtest_iq_to_d(o.te_ref_iq)) <= fixtest_iq_to_d(s.cfg.speed.torque_limit_iq));
    }
    print_message("speed mode: mean %.1f rpm over the last 0.1 s (ref 1500), peak %.1f rpm, "
                  "%d speed ticks in 10000 periods\n", ws / n, wmax, ticks);
    assert_true(fabs(ws / n - 1500.0) < 15.0); /* 1 %: one count at the 1-period window */
    assert_true(wmax < 1500.0 * 1.25);
    assert_int_equal(ticks, 999); /* every 10th call after the priming call */
}

static void test_voltage_model_start_up_at_speed(void **state)
{
    (void)state;
    /* FSTP, voltage model with the proposed compensation (the default), started at 1450 rpm
     * with the speed loop engaged: the seeded estimator keeps the drive under control from the
     * first period (an unseeded low-pass needs ~1 s to find the magnet flux). */
    sim_t s;
    dtc_t c;
    dtc_out_t o;
    sim_init(&s, DTC_TOPO_FSTP, DTC_EST_VOLTAGE, DTC_COMP_FSTP_PROPOSED, 0, 1450.0);
    s.drops = 1; /* the inverter the compensation is for: Hoang Table IV devices */
    s.j_kgm2 = s.si.inertia_kgm2;
    s.load_nm = 0.1;
    assert_int_equal(dtc_init(&c, &s.cfg), DTC_OK);
    double wmin = 1e9, ws = 0.0;
    int n = 0;
    for (int k = 0; k < 10000; k++) {
        sim_period(&s, &c, &o);
        double rpm = s.w_mech * 30.0 / DTC_REF_PI;
        wmin = fmin(wmin, rpm);
        if (k >= 8000) {
            ws += rpm;
            n++;
        }
    }
    print_message("voltage-model start at 1450 rpm: min %.1f rpm, mean %.1f rpm over the last 0.1 s\n",
                  wmin, ws / n);
    assert_true(wmin > 1300.0);
    assert_true(fabs(ws / n - 1500.0) < 15.0);
}

static void test_compensation_on_fstp_with_drops(void **state)
{
    (void)state;
    /* Hoang section III: an FSTP with real device drops (Table IV) run in torque mode at
     * 1500 rpm with the voltage model; the rms error of the estimated flux against the plant's
     * (sampled at the same instants) for no / simple (Hoang Table V) / proposed (Table VI + R_on)
     * compensation. Part of the error is the LPF's known 3.2 % at 1500 rpm (common to all);
     * the drops add to it unless compensated, and Hoang Table VI removes more than Table V. */
    const int comps[3] = {DTC_COMP_NONE, DTC_COMP_FSTP_SIMPLE, DTC_COMP_FSTP_PROPOSED};
    double rms[3], imb[3];
    for (int j = 0; j < 3; j++) {
        sim_t s;
        dtc_t c;
        dtc_out_t o;
        sim_init(&s, DTC_TOPO_FSTP, DTC_EST_VOLTAGE, comps[j], 0, 1500.0);
        s.drops = 1;
        s.cfg.speed.mode = DTC_MODE_TORQUE;
        s.cfg.speed.torque_ref_iq = IQ(0.3);
        assert_int_equal(dtc_init(&c, &s.cfg), DTC_OK);
        double e2 = 0.0, amax = 0.0, bmax = 0.0;
        int n = 0;
        for (int k = 0; k < 30000; k++) {
            double pa = s.m.psi_a, pb = s.m.psi_b; /* plant flux at the sampling instant */
            sim_period(&s, &c, &o);
            if (k >= 24000) {
                double da = fixtest_iq_to_d(o.psi_alpha_iq) - pa, db = fixtest_iq_to_d(o.psi_beta_iq) - pb;
                e2 += da * da + db * db;
                amax = fmax(amax, fabs(pa));
                bmax = fmax(bmax, fabs(pb));
                n++;
            }
        }
        rms[j] = sqrt(e2 / n);
        imb[j] = amax / bmax - 1.0; /* plant flux alpha/beta peak imbalance */
    }
    print_message("FSTP with drops, 1500 rpm, 0.3 pu: rms flux-estimate error none %.4f, "
                  "Table V %.4f, Table VI %.4f pu; plant flux alpha/beta peak imbalance "
                  "%+.2f %%, %+.2f %%, %+.2f %%\n", rms[0], rms[1], rms[2], 100 * imb[0],
                  100 * imb[1], 100 * imb[2]);
    assert_true(rms[2] < rms[0]);
    assert_true(rms[2] <= rms[1] * 1.02);
}

static void test_voltage_model_uses_legs_from_two_steps_back(void **state)
{
    (void)state;
    /* Zero currents, V_dc = 1: the flux increment in step k must be k_in * V(vector of step
     * k-2) minus the leak (hal.h timing). */
    sim_t s;
    dtc_t c;
    dtc_out_t o[6];
    sim_init(&s, DTC_TOPO_SSTP, DTC_EST_VOLTAGE, DTC_COMP_NONE, DTC_ST_D, 0.0);
    s.cfg.machine.rs_iq = 0;
    s.cfg.u.pm_dtc.est.handover_speed_iq = 0; /* the voltage model from standstill (no current-model start) */
    s.cfg.u.pm_dtc.est.handover_hyst_iq = 0;
    assert_int_equal(dtc_init(&c, &s.cfg), DTC_OK);
    dtc_meas_t me = {0, 0, 0, IQ(1.0), IQ(0.5), 0U};
    for (int k = 0; k < 6; k++) {
        iq_t pa = c.fe.psi_alpha_iq, pb = c.fe.psi_beta_iq;
        dtc_step(&c, &me, &o[k]);
        double va = 0.0, vb = 0.0;
        if (k >= 2) {
            dtc_ref_clarke3(o[k - 2].sa, o[k - 2].sb, o[k - 2].sc, &va, &vb);
        }
        double kin = fixtest_q31_to_d(s.cfg.est.k_in_q31), kl = fixtest_q31_to_d(s.cfg.est.k_leak_q31);
        double ea = fixtest_iq_to_d(pa) * (1 - kl) + kin * va;
        double eb = fixtest_iq_to_d(pb) * (1 - kl) + kin * vb;
        double tol = 3.0;
        if (k == 0) {
            /* first step after init: seeded from Hoang eqs. 8-9 (zero current, angle 0): (psi_m, 0),
             * within psi_m times the sine table's error (fix_cos(0) = 1 - 2^-15) */
            ea = fixtest_iq_to_d(s.cfg.u.pm_dtc.machine.psi_m_iq);
            eb = 0.0;
            tol = 1000.0;
        }
        fixtest_assert_lsb(fixtest_iq_to_d(c.fe.psi_alpha_iq), ea, 1.0 / 16777216.0, tol, "timing a");
        fixtest_assert_lsb(fixtest_iq_to_d(c.fe.psi_beta_iq), eb, 1.0 / 16777216.0, tol, "timing b");
    }
    /* the flux moved away from the seed, so active vectors were applied */
    assert_true(c.fe.psi_alpha_iq != s.cfg.u.pm_dtc.machine.psi_m_iq || c.fe.psi_beta_iq != 0);
}

/* Start-up on the current model and hand-over (dtc_config.h): from standstill, J = 5e-4 kg m^2,
 * ideal FSTP, speed reference 1500 rpm. The voltage model takes over once the measured speed
 * exceeds the derived hand-over speed (941 rpm without compensation), with no jump in the flux estimate (it stays
 * within 2 % of psi_m of the true flux across the switch), and falls back below 80 % of it when
 * the reference goes to 200 rpm. */
static void test_handover_up_and_down(void **state)
{
    (void)state;
    sim_t s;
    dtc_t c;
    dtc_out_t o;
    sim_init(&s, DTC_TOPO_FSTP, DTC_EST_VOLTAGE, DTC_COMP_NONE, DTC_ST_BASIC, 0.0);
    const double rpm_per_pu = s.b.w_base_rad_s * 30.0 / DTC_REF_PI;
    s.j_kgm2 = 5e-4;
    assert_int_equal(dtc_init(&c, &s.cfg), DTC_OK);
    const double h_rpm = fixtest_iq_to_d(s.cfg.u.pm_dtc.est.handover_speed_iq) * s.b.w_base_rad_s * 30.0 / DTC_REF_PI;
    const double psi_m = fixtest_iq_to_d(s.cfg.u.pm_dtc.machine.psi_m_iq);
    assert_true(fabs(h_rpm - dtc_handover_default_rpm(&s.si)) < 0.1); /* 941 rpm: uncompensated */
    int up = -1, down = -1;
    uint16_t prev = 1U;
    for (int k = 0; k < 40000; k++) {
        if (k == 20000) {
            dtc_refs_t r;
            r = c.act;
            r.speed_ref_iq = fixtest_d_to_iq(200.0 / rpm_per_pu);
            assert_int_equal(dtc_shadow_publish(&c.sh, &r), DTC_OK);
        }
        const double pa = s.m.psi_a, pb = s.m.psi_b; /* the flux the step measures */
        sim_period(&s, &c, &o);
        double w_meas = fabs(fixtest_iq_to_d(c.speed_iq)) * rpm_per_pu;
        if (k < 5) {
            assert_int_equal(o.on_cm, 1U);
        }
        if (prev == 1U && o.on_cm == 0U) {
            up = k;
            assert_true(w_meas > h_rpm && w_meas < 1.1 * h_rpm);
            double ea = fixtest_iq_to_d(o.psi_alpha_iq) - pa;
            double eb = fixtest_iq_to_d(o.psi_beta_iq) - pb;
            if (!(sqrt(ea * ea + eb * eb) < 0.02 * psi_m)) {
                fail_msg("flux error at the hand-over %g pu (psi_m %g pu)", sqrt(ea * ea + eb * eb), psi_m);
            }
        }
        if (prev == 0U && o.on_cm == 1U) {
            down = k;
            assert_true(w_meas < 0.8 * h_rpm && w_meas > 0.7 * h_rpm);
        }
        prev = o.on_cm;
    }
    assert_true(up > 0 && up < 20000);
    assert_true(down > 20000);
    assert_int_equal(o.on_cm, 1U);
}

/* Dead-time error of the reconstruction (dtc_deadtime_i) against a double transcription of the
 * physics: a leg that turns on with the current leaving it loses V_dc T_d/T_s, one that turns
 * off with the current entering it gains it; every other case is exact. All 64 leg transitions x
 * current-sign cases, SSTP and FSTP, V_dc = 1 pu, T_d = 1 us, T_s = 50 us. */
static void test_deadtime_error(void **state)
{
    (void)state;
    for (int topo = 0; topo < 2; topo++) {
        sim_t s;
        dtc_t c;
        sim_init(&s, topo == 0 ? DTC_TOPO_SSTP : DTC_TOPO_FSTP, DTC_EST_VOLTAGE, DTC_COMP_NONE,
                 DTC_ST_BASIC, 0.0);
        s.cfg.board.td_ts_q15 = Q15(0.02);
        assert_int_equal(dtc_init(&c, &s.cfg), DTC_OK);
        for (int prev = 0; prev < 8; prev++) {
            for (int cur = 0; cur < 8; cur++) {
                for (int sg = 0; sg < 4; sg++) {
                    swtab_legs_t p = {(uint16_t)(prev & 1), (uint16_t)((prev >> 1) & 1), (uint16_t)((prev >> 2) & 1)};
                    swtab_legs_t q = {(uint16_t)(cur & 1), (uint16_t)((cur >> 1) & 1), (uint16_t)((cur >> 2) & 1)};
                    if (topo == 1) {
                        p.sa = 0U;
                        q.sa = 0U;
                    }
                    double i1 = (sg & 1) ? 0.4 : -0.4, i2 = (sg & 2) ? 0.3 : -0.5;
                    double ia, ib, ic;
                    dtc_meas_t me = {0, 0, 0, IQ(1.0), IQ(0.5), 0U};
                    if (topo == 0) {
                        ia = i1; ib = i2; ic = -(i1 + i2);
                        me.ia_iq = fixtest_d_to_iq(ia);
                        me.ib_iq = fixtest_d_to_iq(ib);
                    } else {
                        ib = i1; ic = i2; ia = -(i1 + i2);
                        me.ib_iq = fixtest_d_to_iq(ib);
                        me.ic_iq = fixtest_d_to_iq(ic);
                    }
                    const double il[3] = {ia, ib, ic};
                    const int sp[3] = {p.sa, p.sb, p.sc}, sq[3] = {q.sa, q.sb, q.sc};
                    double e[3];
                    for (int x = 0; x < 3; x++) {
                        e[x] = 0.0;
                        const double ed = (double)s.cfg.board.td_ts_q15 / 32768.0; /* Q15(0.02) */
                        if (sp[x] == 0 && sq[x] == 1 && il[x] > 0) e[x] = -ed;
                        if (sp[x] == 1 && sq[x] == 0 && il[x] < 0) e[x] = ed;
                    }
                    double wa = (2 * e[0] - e[1] - e[2]) / 3.0, wb = (e[1] - e[2]) / sqrt(3.0);
                    iq_t da, db;
                    clarke_out_t ci;
                    if (topo == 0) {
                        clarke_sstp(me.ia_iq, me.ib_iq, &ci);
                    } else {
                        clarke_fstp(me.ib_iq, me.ic_iq, &ci);
                    }
                    deadtime_error(&c.dt_p, me.vdc_iq, &ci, &p, &q, &da, &db);
                    fixtest_assert_lsb(fixtest_iq_to_d(da), wa, 1.0 / 16777216.0, 3.0, "dead time alpha");
                    fixtest_assert_lsb(fixtest_iq_to_d(db), wb, 1.0 / 16777216.0, 3.0, "dead time beta");
                }
            }
        }
    }
}

/* Delay compensation (dtc_predict) against the double PM model: from a state of the reference
 * machine at 1500 rpm with the committed vector, the prediction of flux, current-based torque at
 * k+1 must match the machine integrated over one period (4 RK steps) within 0.5 % of rated
 * torque and 0.2 % of psi_m: it is a first-order step of the same equations. */
static void test_delay_prediction_matches_machine(void **state)
{
    (void)state;
    sim_t s;
    dtc_t c;
    dtc_out_t o;
    sim_init(&s, DTC_TOPO_FSTP, DTC_EST_CURRENT, DTC_COMP_NONE, DTC_ST_BASIC, 1500.0);
    assert_int_equal(dtc_init(&c, &s.cfg), DTC_OK);
    double worst_t = 0.0, worst_p = 0.0;
    for (int k = 0; k < 4000; k++) {
        sim_period(&s, &c, &o);
        if (k < 100) {
            continue;
        }
        /* the state now: plant at the start of the period in which legs_1 (= s.applied) acts */
        dtc_meas_t me;
        sim_meas(&s, &me);
        clarke_out_t i;
        clarke_fstp(me.ib_iq, me.ic_iq, &i);
        iq_t pa = fixtest_d_to_iq(s.m.psi_a), pb = fixtest_d_to_iq(s.m.psi_b), te = 0;
        vrec_fstp(c.legs_1.sb, c.legs_1.sc, me.vdc_iq, me.vmid_iq, 0U, &c.v1_alpha_iq, &c.v1_beta_iq);
        c.v1f_alpha_iq = c.v1f_beta_iq = c.v1d_alpha_iq = c.v1d_beta_iq = 0;
        dtc_predict(&c, &i, &pa, &pb, &te);
        dtc_ref_pm_t m = s.m;
        double va = (1.0 - c.legs_1.sb - c.legs_1.sc) / 3.0, vb = ((double)c.legs_1.sb - (double)c.legs_1.sc) / sqrt(3.0);
        dtc_ref_pm_step(&m, va, vb, s.tspu, 4);
        double dt = fabs(fixtest_iq_to_d(te) - dtc_ref_pm_torque(&m));
        double dp = hypot(fixtest_iq_to_d(pa) - m.psi_a, fixtest_iq_to_d(pb) - m.psi_b);
        worst_t = dt > worst_t ? dt : worst_t;
        worst_p = dp > worst_p ? dp : worst_p;
    }
    const double t_rated = 0.3 / s.b.t_base_nm, psi_m = s.si.psi_m_wb / s.b.psi_base_wb;
    print_message("[ MEASURE  ] prediction error: torque %.4f %% of rated, flux %.4f %% of psi_m\n",
                  100.0 * worst_t / t_rated, 100.0 * worst_p / psi_m);
    assert_true(worst_t < 0.005 * t_rated);
    assert_true(worst_p < 0.002 * psi_m);
}

static void test_shadow_set_and_modes(void **state)
{
    (void)state;
    sim_t s;
    dtc_t c;
    dtc_out_t o;
    dtc_refs_t r, got;
    sim_init(&s, DTC_TOPO_FSTP, DTC_EST_CURRENT, DTC_COMP_NONE, 0, 600.0);
    s.cfg.speed.mode = DTC_MODE_TORQUE;
    s.cfg.speed.torque_ref_iq = IQ(0.2);
    s.cfg.speed.torque_trim_k_q15 = 0; /* this test isolates the shadow set: reference = set in force */
    assert_int_equal(dtc_init(&c, &s.cfg), DTC_OK);
    sim_period(&s, &c, &o);
    fixtest_assert_lsb(fixtest_iq_to_d(o.te_ref_iq), 0.2, 1.0 / 16777216.0, 0.5, "initial ref");

    r = c.act;
    r.torque_ref_iq = IQ(0.35);
    r.flux_ref_iq = IQ(0.40);
    assert_int_equal(dtc_shadow_publish(&c.sh, &r), DTC_OK);
    sim_period(&s, &c, &o); /* adopted at the top of the next step */
    fixtest_assert_lsb(fixtest_iq_to_d(o.te_ref_iq), 0.35, 1.0 / 16777216.0, 0.5, "adopted");
    got = c.act;
    assert_int_equal(got.flux_ref_iq, IQ(0.40));

    /* a write interrupted half-way (sequence odd) is not adopted */
    c.sh.seq = (uint16_t)(c.sh.seq + 1U);
    c.sh.torque_ref_iq = IQ(-0.1);
    sim_period(&s, &c, &o);
    fixtest_assert_lsb(fixtest_iq_to_d(o.te_ref_iq), 0.35, 1.0 / 16777216.0, 0.5, "not half");
    c.sh.seq = (uint16_t)(c.sh.seq + 1U); /* the writer completes */
    sim_period(&s, &c, &o);
    got = c.act;
    assert_int_equal(got.torque_ref_iq, IQ(-0.1));

    /* references beyond the limits are clamped on adoption; invalid sets are refused */
    r.torque_ref_iq = IQ(5.0);
    assert_int_equal(dtc_shadow_publish(&c.sh, &r), DTC_OK);
    sim_period(&s, &c, &o);
    assert_int_equal(o.te_ref_iq, s.cfg.speed.torque_limit_iq);
    r.flux_ref_iq = 0;
    assert_int_equal(dtc_shadow_publish(&c.sh, &r), DTC_ERR_REFERENCE);
    r.flux_ref_iq = IQ(0.4);
    r.kp_iq = -1;
    assert_int_equal(dtc_shadow_publish(&c.sh, &r), DTC_ERR_PI);
    r.kp_iq = 0;
    r.mode = 7U;
    assert_int_equal(dtc_shadow_publish(&c.sh, &r), DTC_ERR_VARIANT);

    /* torque -> speed mode is bumpless: the PI integrator starts at the torque in force */
    r.mode = DTC_MODE_SPEED;
    r.torque_ref_iq = IQ(0.25);
    r.kp_iq = 0;
    r.ki_ts_iq = 0;
    assert_int_equal(dtc_shadow_publish(&c.sh, &r), DTC_OK);
    iq_t before = o.te_ref_iq;
    for (int k = 0; k < 20; k++) {
        sim_period(&s, &c, &o);
    }
    assert_int_equal(o.te_ref_iq, before); /* kp = ki = 0: the output stays where it was */
}

/* Torque mode at constant speed (FSTP, current model, zero bands): the bang-bang torque loop with
 * the one-period actuation delay settles below the reference; the mean-torque trim (dtc.c step 5)
 * brings the mean of the estimate to the reference within 1 %, and never lets the reference in
 * force leave +-torque_limit. */
static double torque_mode_mean(q15_t k, double ref_pu, iq_t *ref_max)
{
    sim_t s;
    dtc_t c;
    dtc_out_t o;
    double sum = 0.0;
    int n;
    sim_init(&s, DTC_TOPO_FSTP, DTC_EST_CURRENT, DTC_COMP_NONE, 0, 1500.0);
    s.cfg.speed.mode = DTC_MODE_TORQUE;
    s.cfg.speed.torque_ref_iq = fixtest_d_to_iq(ref_pu);
    s.cfg.speed.torque_trim_k_q15 = k;
    assert_int_equal(dtc_init(&c, &s.cfg), DTC_OK);
    *ref_max = 0;
    for (n = 0; n < 12000; n++) { /* 0.6 s: 30 trim time constants */
        sim_period(&s, &c, &o);
        if (n >= 8000) {
            sum += fixtest_iq_to_d(o.te_iq);
        }
        if (fix_abs32(o.te_ref_iq) > *ref_max) {
            *ref_max = fix_abs32(o.te_ref_iq);
        }
    }
    return sum / 4000.0;
}

static void test_torque_mode_trim(void **state)
{
    (void)state;
    sim_t s;
    iq_t ref_max;
    double ref, off, on;
    sim_init(&s, DTC_TOPO_FSTP, DTC_EST_CURRENT, DTC_COMP_NONE, 0, 1500.0);
    ref = 0.3 / s.b.t_base_nm; /* rated torque, 0.3 N.m */
    off = torque_mode_mean(0, ref, &ref_max);
    on = torque_mode_mean(s.cfg.speed.torque_trim_k_q15, ref, &ref_max);
    print_message("[ MEASURE  ] torque mode mean/ref: trim off %.4f, trim on %.4f\n", off / ref, on / ref);
    assert_true(s.cfg.speed.torque_trim_k_q15 > 0);  /* on by default (tau = 20 ms) */
    assert_true(fabs(off / ref - 1.0) > 0.03); /* the offset the trim exists for */
    assert_true(fabs(on / ref - 1.0) < 0.01);
    assert_true(ref_max <= s.cfg.speed.torque_limit_iq);
}

static void test_outputs_consistent(void **state)
{
    (void)state;
    sim_t s;
    dtc_t c;
    dtc_out_t o;
    sim_init(&s, DTC_TOPO_SSTP, DTC_EST_CURRENT, DTC_COMP_NONE, DTC_ST_BASIC, 900.0);
    s.cfg.u.pm_dtc.est.delay_comp = 0U; /* the comparators then work on the reported estimate */
    assert_int_equal(dtc_init(&c, &s.cfg), DTC_OK);
    for (int k = 0; k < 2000; k++) {
        sim_period(&s, &c, &o);
        swtab_legs_t l = swtab_sstp_legs(o.vector);
        assert_true(o.vector <= 7U && o.sector >= 1U && o.sector <= 6U);
        assert_true(l.sa == o.sa && l.sb == o.sb && l.sc == o.sc);
        /* flux comparator (Hoang eq. 13) against eq. 11's magnitude: outside the band the decision is forced */
        const iq_t mag = dtc_out_flux_mag(&o);
        if (mag < s.cfg.speed.flux_ref_iq - s.cfg.u.pm_dtc.sw.flux_band_iq / 2 - 1) {
            assert_int_equal(o.flux_up, 1U);
        } else if (mag > s.cfg.speed.flux_ref_iq + s.cfg.u.pm_dtc.sw.flux_band_iq / 2 + 1) {
            assert_int_equal(o.flux_up, 0U);
        }
    }
    /* reset: speed re-primed, voltage-model flux cleared until the next step seeds it */
    dtc_reset(&c);
    assert_int_equal(c.fe.psi_alpha_iq, 0);
    assert_int_equal(c.speed_primed, 0);
}

static void test_extreme_measurements_all_variants(void **state)
{
    (void)state;
    /* Every variant fed full-scale, zero and random measurements (an ADC fault, a trip in
     * progress): no wrap-around (the sanitizer build fails on any signed overflow), outputs
     * always a valid vector, flux and torque saturated rather than wrapped. */
    static const iq_t vals[] = {IQ_MAX, IQ_MIN, 0, 1, -1, IQ(127.9), IQ(-127.9), IQ(1.0)};
    uint32_t rnd = 12345U;
    for (int topo = 0; topo <= 1; topo++)
        for (int est = 0; est <= 1; est++)
            for (int comp = 0; comp <= 3; comp++)
                for (int tab = 0; tab <= 4; tab++) {
                    if ((topo == DTC_TOPO_SSTP && comp >= 2) || (topo == DTC_TOPO_FSTP && comp == 1)) {
                        continue;
                    }
                    sim_t s;
                    dtc_t c;
                    dtc_out_t o;
                    sim_init(&s, topo, est, comp, tab, 0.0);
                    assert_int_equal(dtc_init(&c, &s.cfg), DTC_OK);
                    for (int k = 0; k < 300; k++) {
                        dtc_meas_t me;
                        rnd = rnd * 1664525U + 1013904223U;
                        me.ia_iq = vals[(rnd >> 8) & 7U];
                        me.ib_iq = vals[(rnd >> 11) & 7U];
                        me.ic_iq = vals[(rnd >> 14) & 7U];
                        me.vdc_iq = vals[(rnd >> 17) & 7U];
                        me.vmid_iq = vals[(rnd >> 20) & 7U];
                        me.enc_count = (uint16_t)((rnd >> 3) % 8000U);
                        dtc_step(&c, &me, &o);
                        if (topo == DTC_TOPO_FSTP) {
                            assert_true(o.vector >= 1U && o.vector <= 4U && o.sector <= 4U);
                        } else {
                            assert_true(o.vector <= 7U && o.sector <= 6U);
                        }
                        assert_true(o.sector >= 1U);
                        assert_true(o.sa <= 1U && o.sb <= 1U && o.sc <= 1U);
                        assert_true(o.te_ref_iq <= s.cfg.speed.torque_limit_iq &&
                                    o.te_ref_iq >= -s.cfg.speed.torque_limit_iq);
                    }
                }
}

UNIT_TEST_MAIN("dtc step", NULL,
               cmocka_unit_test(test_closed_loop_torque_mode),
               cmocka_unit_test(test_closed_loop_speed_mode),
               cmocka_unit_test(test_voltage_model_start_up_at_speed),
               cmocka_unit_test(test_compensation_on_fstp_with_drops),
               cmocka_unit_test(test_voltage_model_uses_legs_from_two_steps_back),
               cmocka_unit_test(test_handover_up_and_down),
               cmocka_unit_test(test_deadtime_error),
               cmocka_unit_test(test_delay_prediction_matches_machine),
               cmocka_unit_test(test_shadow_set_and_modes),
               cmocka_unit_test(test_torque_mode_trim),
               cmocka_unit_test(test_outputs_consistent),
               cmocka_unit_test(test_extreme_measurements_all_variants))
