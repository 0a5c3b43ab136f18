/*
 * bench_dtc - drives dtc_step() in closed loop (FSTP, voltage model, proposed compensation:
 * the configuration with the most work per step) against the double-precision PM machine of
 * the unit tests, for valgrind --tool=callgrind (tools/bench/run_budget.sh).
 *
 * The two wrappers below are never inlined, so callgrind reports the inclusive instruction
 * count of dtc_step() separately for ordinary steps and for speed-loop steps (the worst case).
 * Prints the number of calls of each kind; the script divides.
 *
 * `bench_dtc N im` drives the induction-machine law (im_dtc_step) instead, against the double
 * T-model machine of the unit tests at a held speed (0.5 pu, rated torque, speed mode): the
 * improved estimator with a speed-dependent tau, constant rotor flux (Casadei eq. 19, a square root per
 * period), sensorless speed and the speed-dependent table, with the defaults' SSTP drop and
 * dead-time compensation: the variant with the most work per step (the machine is fed by the
 * ideal inverter; the compensation's cost does not depend on that). The start-up magnetisation (cheaper steps) runs through a third wrapper that the script
 * leaves out. `bench_dtc N im ideal`: the same without the drop and dead-time compensation.
 * `bench_dtc N imfstp`: the same law on the four-switch inverter (im_dtc_step_fstp, Hoang Table
 * II, the FSTP's equal-drop compensation), the machine fed with Hoang Table I's vectors.
 * `bench_dtc N sfvc`: the IM law's stator-flux vector control (im_sfvc_step: Casadei eqs. 18, 23, 24 and
 * the SVM with dead-time compensation) in the same conditions, at its 160 us period; `bench_dtc N
 * dfoc`: the rotor-flux-oriented control (im_dfoc_step, two-phase SVM), the same.
 * `bench_dtc N itc`: the PM indirect torque control (itc_step: rotor-frame current PI, FSTP SVM
 * with the measured mid-point and its regulation, the voltage-model observer with Hoang's Table VI
 * compensation) on the defaults' FSTP, 50 us, against the same PM machine fed by the mean voltage
 * of the duties (vrec of the effective duties on the 1 pu link). `bench_dtc N itc cm`: the same with
 * the current-model estimator (Hoang eqs. 8-9; the drop compensation then not used).
 * `bench_dtc N capture MODE`: the application's ISR body (app_core_step, PM law, the defaults'
 * configuration) in RUN on an idle measurement, N periods through the wrapper bench_app_step:
 * MODE none (no capture attached), off (attached, not recording) or on (four channels recorded
 * every period, a trigger that never fires): the capture's added cost in the ISR is the
 * difference.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app_core.h"
#include "capture.h"
#include "dtc.h"
#include "im_dtc.h"
#include "itc.h"
#include "vrec.h"
#include "dtc_config_si.h"
#include "dtc_ref.h"

#ifndef M_PI
#define M_PI DTC_REF_PI
#endif

/* One named, never-inlined call of a law's step per phase of the run (steady state, the speed
 * tick, start-up), so that the instruction count of each (run_budget.sh, callgrind) is found by
 * its symbol. */
#define BENCH_STEP(type, name, step)                                                                 \
    __attribute__((noinline)) void name(type *c, const dtc_meas_t *m, dtc_out_t *o);               \
    __attribute__((noinline)) void name(type *c, const dtc_meas_t *m, dtc_out_t *o) { step(c, m, o); }
BENCH_STEP(dtc_t, bench_step_normal, dtc_step)
BENCH_STEP(dtc_t, bench_step_tick, dtc_step)

static iq_t to_iq(double x) { return (iq_t)lrint(x * 16777216.0); }

/* The PM rig of the benches: the defaults' SI configuration (FSTP, voltage model, Hoang Table VI
 * compensation, speed mode) for the law, converted; the double-precision PM machine at 1450 rpm. */
static int pm_rig(int law, dtc_config_si_t *si, dtc_config_t *cfg, dtc_bases_t *b, dtc_ref_pm_t *m, double *w_mech)
{
    char msg[256];
    dtc_config_si_defaults(si);
    si->law = law;
    if (dtc_config_from_si(si, cfg, msg, sizeof msg) != DTC_SI_OK) {
        fprintf(stderr, "bench: %s\n", msg);
        return 1;
    }
    dtc_bases_from_si(si, b);
    *w_mech = 1450.0 * M_PI / 30.0;
    dtc_ref_pm_init(m, si->rs_ohm / b->z_base_ohm, si->ls_h / b->l_base_h, si->psi_m_wb / b->psi_base_wb,
                    *w_mech / b->w_base_rad_s, 0.0, 0.0, 0.0);
    return 0;
}

/* The measurements of one period from the PM machine: its currents (ia, ib: alpha/beta, pu), the
 * phase currents, a 1 pu link at its mid-point, the 8000-count encoder. */
static void pm_meas(const dtc_ref_pm_t *m, dtc_meas_t *me, double *ia, double *ib)
{
    dtc_ref_pm_currents(m, ia, ib);
    me->ia_iq = to_iq(*ia);
    me->ib_iq = to_iq(-0.5 * *ia + 0.5 * sqrt(3.0) * *ib);
    me->ic_iq = to_iq(-0.5 * *ia - 0.5 * sqrt(3.0) * *ib);
    me->vdc_iq = to_iq(1.0);
    me->vmid_iq = to_iq(0.5);
    {
        const double cnt = fmod(floor(m->theta / (2.0 * M_PI) * 8000.0), 8000.0);
        me->enc_count = (uint16_t)(cnt < 0 ? cnt + 8000.0 : cnt);
    }
}

BENCH_STEP(itc_t, bench_itc_normal, itc_step)
BENCH_STEP(itc_t, bench_itc_tick, itc_step)

/* The PM ITC in closed loop (see the header comment); cm: the current-model estimator. */
static int run_itc(long n, int cm)
{
    dtc_config_si_t si;
    dtc_config_t cfg;
    dtc_bases_t b;
    itc_t c;
    dtc_out_t o;
    dtc_ref_pm_t m;
    long n_tick = 0, n_norm = 0;
    double va = 0.0, vb = 0.0;
    double w_mech;
    if (pm_rig(DTC_LAW_PM_ITC, &si, &cfg, &b, &m, &w_mech) != 0) {
        return 1;
    }
    if (cm) {
        char msg[256];
        si.estimator = DTC_EST_CURRENT;
        if (dtc_config_from_si(&si, &cfg, msg, sizeof msg) != DTC_SI_OK) {
            fprintf(stderr, "bench: %s\n", msg);
            return 1;
        }
    }
    if (itc_init(&c, &cfg) != DTC_OK) {
        return 1;
    }
    const double tspu = si.ts_s * b.w_base_rad_s;
    for (long k = 0; k < n; k++) {
        dtc_meas_t me;
        double ia, ib;
        iq_t a, bb;
        pm_meas(&m, &me, &ia, &ib);
        if (c.speed_primed != 0U && c.div_cnt == 0U) {
            bench_itc_tick(&c, &me, &o);
            n_tick++;
        } else {
            bench_itc_normal(&c, &me, &o);
            n_norm++;
        }
        /* the machine gets the mean voltage of the previous step's duties (one period's delay) */
        dtc_ref_pm_step(&m, va, vb, tspu, 2);
        vrec_from_legs(c.svm_o.d_eff_iq[0], c.svm_o.d_eff_iq[1], c.svm_o.d_eff_iq[2], &a, &bb);
        va = (double)a / 16777216.0;
        vb = (double)bb / 16777216.0;
        double t_nm = dtc_ref_pm_torque(&m) * b.t_base_nm;
        w_mech += (t_nm - 0.1) / si.inertia_kgm2 * si.ts_s;
        m.w = w_mech / b.w_base_rad_s;
    }
    printf("calls normal %ld tick %ld\n", n_norm, n_tick);
    printf("final speed %.1f rpm (ref 1500)\n", w_mech * 30.0 / M_PI);
    return 0;
}

BENCH_STEP(im_dtc_t, bench_im_normal, im_dtc_step)
BENCH_STEP(im_dtc_t, bench_im_tick, im_dtc_step)
BENCH_STEP(im_dtc_t, bench_im_start, im_dtc_step)
BENCH_STEP(im_dtc_t, bench_imfstp_normal, im_dtc_step_fstp)
BENCH_STEP(im_dtc_t, bench_imfstp_tick, im_dtc_step_fstp)
BENCH_STEP(im_dtc_t, bench_sfvc_normal, im_sfvc_step)
BENCH_STEP(im_dtc_t, bench_sfvc_tick, im_sfvc_step)
BENCH_STEP(im_dtc_t, bench_dfoc_normal, im_dfoc_step)
BENCH_STEP(im_dtc_t, bench_dfoc_tick, im_dfoc_step)
BENCH_STEP(im_dtc_t, bench_dsvm_normal, im_dsvm_step)
BENCH_STEP(im_dtc_t, bench_dsvm_tick, im_dsvm_step)

/* ideal: no drop or dead-time compensation; sfvc: 4 the DTC on the four-switch inverter
 * (im_dtc_step_fstp, Hoang Table II, the FSTP's equal-drop compensation, the machine fed with
 * Hoang Table I's vectors on a 1 pu link with the mid-point at 0.5 pu), 3 the DTC with DSVM (im_dsvm_step, 160 us, the
 * machine fed with the mean of the three sub-intervals, duty_iq), 1 the stator-flux vector control (im_sfvc_step,
 * symmetric SVM), 2 the rotor-flux-oriented control (im_dfoc_step, two-phase SVM), at the default
 * 6.25 kHz carrier = 160 us control period (their start-up steps run unwrapped), the machine fed
 * with the mean voltage of the duties. */
static int run_im(long n, int ideal, int sfvc)
{
    dtc_config_si_t si;
    dtc_config_t cfg;
    dtc_bases_t b;
    im_dtc_t c;
    dtc_out_t o;
    dtc_ref_im_t x;
    char msg[256];
    long n_tick = 0, n_norm = 0;
    int sa = 0, sb = 0, sc = 0;
    double ls, lr, theta = 0.0;
    double d1[3] = {0.5, 0.5, 0.5}; /* sfvc: the duties returned by the previous step */

    dtc_config_si_im_defaults(&si); /* SSTP drop ([29]) and dead-time compensation on */
    if (ideal) { /* `bench_dtc N im ideal`: both compensations off */
        si.compensation = DTC_COMP_NONE;
        si.deadtime_comp = 0;
    }
    si.tau_lo_s = 0.01;
    si.tau_hi_s = 0.05;
    si.tau_w_lo_rpm = 100.0;
    si.tau_w_hi_rpm = 1000.0;
    si.psir_ref_wb = 0.5;
    si.speed_sensor = DTC_SPEED_NONE;
    si.sstp_table = DTC_ST_SPEED;
    si.speed_ref_rpm = 750.0;
    if (sfvc == 4) {
        si.topology = DTC_TOPO_FSTP;
        si.compensation = ideal ? DTC_COMP_NONE : DTC_COMP_FSTP_SIMPLE;
        si.sstp_table = DTC_ST_BASIC;
    } else if (sfvc) {
        si.law = sfvc == 3 ? DTC_LAW_IM_DSVM : sfvc == 2 ? DTC_LAW_IM_DFOC : DTC_LAW_IM_SFVC;
        si.svm_mode = sfvc == 2 ? 1 : 0;
        si.ts_s = 1.0 / 6250.0;
        si.carrier_hz = sfvc == 3 ? 0.0 : 6250.0;
        if (sfvc == 3) {
            si.sstp_table = DTC_ST_BASIC;
            si.torque_band_nm = 0.05 * 26.5;
            si.flux_band_wb = 0.01;
        }
    }
    if (dtc_config_from_si(&si, &cfg, msg, sizeof msg) != DTC_SI_OK) {
        fprintf(stderr, "bench: %s\n", msg);
        return 1;
    }
    if (im_dtc_init(&c, &cfg) != DTC_OK) {
        return 1;
    }
    dtc_bases_from_si(&si, &b);
    ls = (si.lls_h + si.lm_h) / b.l_base_h;
    lr = (si.llr_h + si.lm_h) / b.l_base_h;
    dtc_ref_im_init(&x, si.rs_ohm / b.z_base_ohm, si.rr_ohm / b.z_base_ohm, ls, lr,
                    si.lm_h / b.l_base_h, 0.0);
    const double tspu = si.ts_s * b.w_base_rad_s;
    for (long k = 0; k < n + (long)cfg.u.im.ref.magn_periods; k++) {
        dtc_meas_t me;
        double ia, ib, va, vb;
        dtc_ref_im_currents(&x, &ia, &ib);
        me.ia_iq = to_iq(ia);
        me.ib_iq = to_iq(-0.5 * ia + 0.5 * sqrt(3.0) * ib);
        me.ic_iq = to_iq(-0.5 * ia - 0.5 * sqrt(3.0) * ib);
        me.vdc_iq = to_iq(1.0);
        me.vmid_iq = to_iq(0.5);
        double cnt = fmod(floor(theta / (2.0 * M_PI * si.pole_pairs) * 8000.0), 8000.0);
        me.enc_count = (uint16_t)(cnt < 0 ? cnt + 8000.0 : cnt);
        if (sfvc == 4) {
            /* the FSTP's currents are i_b, i_c (clarke_fstp) */
            if (c.magnetised == 0U) {
                im_dtc_step_fstp(&c, &me, &o);
            } else if (c.div_cnt == 0U) {
                x.w = 0.5;
                bench_imfstp_tick(&c, &me, &o);
                n_tick++;
            } else {
                x.w = 0.5;
                bench_imfstp_normal(&c, &me, &o);
                n_norm++;
            }
        } else if (c.magnetised == 0U) {
            if (sfvc == 3) {
                im_dsvm_step(&c, &me, &o);
            } else if (sfvc == 2) {
                im_dfoc_step(&c, &me, &o);
            } else if (sfvc) {
                im_sfvc_step(&c, &me, &o);
            } else {
                bench_im_start(&c, &me, &o);
            }
        } else if (c.div_cnt == 0U) {
            /* held at 0.5 pu once magnetised (the machine is magnetised at standstill) */
            x.w = 0.5;
            if (sfvc == 3) {
                bench_dsvm_tick(&c, &me, &o);
            } else if (sfvc == 2) {
                bench_dfoc_tick(&c, &me, &o);
            } else if (sfvc) {
                bench_sfvc_tick(&c, &me, &o);
            } else {
                bench_im_tick(&c, &me, &o);
            }
            n_tick++;
        } else {
            x.w = 0.5;
            if (sfvc == 3) {
                bench_dsvm_normal(&c, &me, &o);
            } else if (sfvc == 2) {
                bench_dfoc_normal(&c, &me, &o);
            } else if (sfvc) {
                bench_sfvc_normal(&c, &me, &o);
            } else {
                bench_im_normal(&c, &me, &o);
            }
            n_norm++;
        }
        if (sfvc == 4) {
            /* Hoang Table I with leg A on the mid-point at 0.5 pu (vrec.h) */
            va = (1.0 - sb - sc) / 3.0;
            vb = (sb - sc) / sqrt(3.0);
        } else if (sfvc) {
            /* the mean voltage of the previous step's duties on a 1 pu link (Casadei eq. 2): the
             * one-period delay of hal.h; the inverter's dead time as the SVM models it (d_eff) */
            va = (2.0 * d1[0] - d1[1] - d1[2]) / 3.0;
            vb = (d1[1] - d1[2]) / sqrt(3.0);
            for (int j = 0; j < 3; j++) {
                d1[j] = (double)(sfvc == 3 ? o.duty_iq[j] : c.svm_o.d_eff_iq[j]) / 16777216.0;
            }
        } else {
            dtc_ref_sstp_ideal(sa, sb, sc, 1.0, &va, &vb);
        }
        dtc_ref_im_step(&x, va, vb, tspu, sfvc != 0 && sfvc != 4 ? 8 : 2); /* the same 20 us sub-step */
        theta += x.w * tspu;
        sa = (int)o.sa;
        sb = (int)o.sb;
        sc = (int)o.sc;
    }
    printf("calls normal %ld tick %ld\n", n_norm, n_tick);
    printf("IM law: final torque %.3f pu, estimated speed %.3f pu (held 0.5)\n",
           dtc_ref_im_torque(&x), (double)o.speed_iq / 16777216.0);
    return 0;
}

/* The ISR body through a wrapper callgrind can count. */
__attribute__((noinline)) uint16_t bench_app_step(app_core_t *a, const hal_meas_t *m, hal_cmd_t *cmd);
__attribute__((noinline)) uint16_t bench_app_step(app_core_t *a, const hal_meas_t *m, hal_cmd_t *cmd)
{
    return app_core_step(a, m, cmd);
}

static int run_capture(long n, const char *mode)
{
    static app_core_t a;
    static capture_t cap;
    dtc_config_si_t si;
    dtc_config_t cfg;
    dtc_bases_t b;
    dtc_ref_pm_t m;
    double w_mech;
    hal_meas_t meas;
    hal_cmd_t cmd;
    long k;
    const capture_setup_t s = {4U, {CAPTURE_Q_TORQUE_EST, CAPTURE_Q_PSI_ALPHA_EST, CAPTURE_Q_PSI_BETA_EST, CAPTURE_Q_SPEED},
                               128U, 0U, 1U, CAPTURE_TRIG_ABOVE, 0U, 0x7FFFFFFF};
    if (pm_rig(DTC_LAW_PM_DTC, &si, &cfg, &b, &m, &w_mech) != 0) {
        return 1;
    }
    /* the measurement is idle, not a machine's: torque mode at zero torque, and the current
     * sensors' plausibility check (which rightly trips on currents that ignore the voltage) off */
    cfg.speed.mode = DTC_MODE_TORQUE;
    cfg.speed.torque_ref_iq = 0;
    cfg.prot.i_plaus = 0U;
    if (app_core_init(&a, &cfg) != 0) {
        return 1;
    }
    memset(&meas, 0, sizeof meas);
    for (k = 0; k < 3; k++) {
        meas.adc[k] = cfg.board.adc_i_offset[k];
    }
    meas.adc[HAL_ADC_VDC] = (uint16_t)(si.vdc_v / si.adc_vdc_v_per_count + 0.5);
    meas.adc[HAL_ADC_VMID] = (uint16_t)(si.vdc_v / 2.0 / si.adc_vdc_v_per_count + 0.5);
    for (k = 0; k < 4096 && a.st.state != APP_STATE_RUN; k++) {
        (void)app_core_step(&a, &meas, &cmd);
        meas.tick++;
    }
    if (a.st.state != APP_STATE_RUN) {
        fprintf(stderr, "bench: the application did not reach RUN (state %u, fault %u)\n", a.st.state, a.st.fault);
        return 1;
    }
    if (strcmp(mode, "none") != 0) {
        capture_init(&cap);
        app_core_attach(&a, &cap, NULL);
        if (strcmp(mode, "on") == 0 && capture_setup(&cap, &s) != CAPTURE_OK) {
            return 1;
        }
    }
    for (k = 0; k < n; k++) {
        (void)bench_app_step(&a, &meas, &cmd);
        meas.tick++;
    }
    printf("calls capture %ld (%s), state %u (fault %u), capture state %u\n", n, mode, a.st.state, a.st.fault,
           capture_state(&cap));
    return a.st.state == APP_STATE_RUN ? 0 : 1;
}

int main(int argc, char **argv)
{
    long n = argc > 1 ? atol(argv[1]) : 20000;
    if (argc > 2 && strcmp(argv[2], "im") == 0) {
        return run_im(n, argc > 3 && strcmp(argv[3], "ideal") == 0, 0);
    }
    if (argc > 2 && strcmp(argv[2], "imfstp") == 0) {
        return run_im(n, argc > 3 && strcmp(argv[3], "ideal") == 0, 4);
    }
    if (argc > 2 && strcmp(argv[2], "sfvc") == 0) {
        return run_im(n, 0, 1);
    }
    if (argc > 2 && strcmp(argv[2], "dfoc") == 0) {
        return run_im(n, 0, 2);
    }
    if (argc > 2 && strcmp(argv[2], "dsvm") == 0) {
        return run_im(n, 0, 3);
    }
    if (argc > 2 && strcmp(argv[2], "itc") == 0) {
        return run_itc(n, argc > 3 && strcmp(argv[3], "cm") == 0);
    }
    if (argc > 3 && strcmp(argv[2], "capture") == 0) {
        return run_capture(n, argv[3]);
    }
    dtc_config_si_t si;
    dtc_config_t cfg;
    dtc_bases_t b;
    dtc_t c;
    dtc_out_t o;
    dtc_ref_pm_t m;
    long n_tick = 0, n_norm = 0;
    unsigned sa = 0, sb = 0, sc = 0;

    double w_mech;
    if (pm_rig(DTC_LAW_PM_DTC, &si, &cfg, &b, &m, &w_mech) != 0 || dtc_init(&c, &cfg) != DTC_OK) {
        return 1;
    }
    const double tspu = si.ts_s * b.w_base_rad_s;
    for (long k = 0; k < n; k++) {
        dtc_meas_t me;
        double ia, ib, va, vb;
        pm_meas(&m, &me, &ia, &ib);
        /* the next call is a speed-loop step when the divider is at zero (after priming) */
        if (c.speed_primed != 0U && c.div_cnt == 0U) {
            bench_step_tick(&c, &me, &o);
            n_tick++;
        } else {
            bench_step_normal(&c, &me, &o);
            n_norm++;
        }
        /* FSTP with Hoang Table IV device drops (Table III + eq. 20), which the compensation is for */
        dtc_ref_fstp_inverter((int)sb, (int)sc, 1.0, -0.5 * ia + 0.5 * sqrt(3.0) * ib,
                              -0.5 * ia - 0.5 * sqrt(3.0) * ib, si.v_ce_v / b.v_base_v,
                              si.v_d_v / b.v_base_v, si.r_on_ohm / b.z_base_ohm, &va, &vb);
        dtc_ref_pm_step(&m, va, vb, tspu, 2);
        double t_nm = dtc_ref_pm_torque(&m) * b.t_base_nm;
        w_mech += (t_nm - 0.1) / si.inertia_kgm2 * si.ts_s;
        m.w = w_mech / b.w_base_rad_s;
        sa = o.sa;
        sb = o.sb;
        sc = o.sc;
    }
    (void)sa;
    printf("calls normal %ld tick %ld\n", n_norm, n_tick);
    printf("final speed %.1f rpm (ref 1500)\n", w_mech * 30.0 / M_PI);
    return 0;
}
