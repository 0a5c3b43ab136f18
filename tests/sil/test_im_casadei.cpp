// test_im_casadei.cpp - the induction-machine drive (Casadei et al. 2006) under the conditions of
// the paper's figures, through the scenario API: tools/scenarios/im_dtc_speed.toml (the default
// IM on its rig: SSTP on 311 V with the plant's device drops and dead time, 40 us, improved
// estimator tau = 0.01 s) with --set overrides, the firmware as dtc-sil runs it
// (make_controller), the plant's true quantities read every period. References that change
// during a run (torque pulses and steps, speed profiles) go through the application's shadow set
// (app_set_refs), as the background loop of the DSP would publish them. Every run starts at
// standstill and magnetises the machine at zero torque (Casadei Fig. 17b) before anything else.
//
// Assertions are the papers' statements with a margin, on the plant: never the firmware's own
// estimate where the plant can say. Each test prints a MEASURE line (the figures of the report).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

extern "C" {
#include "app.h"
#include "dtc_config_si.h"
}

#include "controller_adapter.hpp"
#include "hal_host.hpp"
#include "im_rig.hpp"
#include "metrics.hpp"
#include "run.hpp"
#include "scenario.hpp"

using namespace sil;
using sil_test::kIqOne;
using sil_test::kScenario;
using sil_test::Rig;

namespace {

// Every run here is under the paper's conditions, its estimator included: Casadei eq. 20's
// reference phi_r* e^{j theta} at every speed (control.current_model_ref = false). The product's
// default with the encoder pulls eq. 20 towards a rotor-flux current model at low speed
// (firmware/dtc/im_sup.h), an estimator the paper does not have, whose standstill flux, offset
// paths and torque rise at 100 rpm differ from the figures'.
struct PaperRig : Rig {
    explicit PaperRig(std::vector<std::string> sets) : Rig(paper_estimator(std::move(sets))) {}
    static std::vector<std::string> paper_estimator(std::vector<std::string> sets)
    {
        sets.insert(sets.begin(), "control.current_model_ref=false");
        return sets;
    }
};

// Machine constants of the default IM (the plant's, as the scenario builds it).
struct Machine {
    double ls, lr, m, sigma, tau_r;
    int p;
    explicit Machine(const Scenario& sc)
    {
        m = sc.motor.lm_h;
        ls = sc.motor.lls_h + m;
        lr = sc.motor.llr_h + m;
        sigma = 1.0 - m * m / (ls * lr);
        tau_r = lr / sc.motor.rr_ohm;
        p = static_cast<int>(sc.motor.pole_pairs);
    }
    // Steady state at constant rotor flux phi_r carrying torque t (rotor-flux frame, Casadei eq. 19):
    // phi_sd = (L_s/M) phi_r, phi_sq = sigma L_s i_q, T = 3/2 p (M/L_r) phi_r i_q.
    double stator_flux(double phi_r, double t) const
    {
        const double iq = t * lr / (1.5 * p * m * phi_r);
        return std::hypot(ls / m * phi_r, sigma * ls * iq);
    }
};

} // namespace

// ---- Casadei Fig. 17: start-up at zero torque, then a rated torque step ------------------------
// Casadei sec. 10.2: with a pure integrator the machine cannot be magnetised at zero torque and
// the torque then rises slowly (the voltage model here is magnetised by the start-up's
// correction, then over-magnetised when held at DC); with the improved estimator (tau = 0.01 s) the phase current
// settles to the magnetising current at zero torque and the torque reaches its reference within
// a few ms. Rotor held at standstill (the dynamometer), torque mode, T* = 0, then rated.
struct StartUp {
    double psir_before = 0.0, i_dc = 0.0, i_drift = 0.0, rise_ms = -1.0, te_worst_magn = 0.0;
    double i_peak_magn = 0.0; // largest current-vector magnitude during the magnetisation
    double psir_magn = 0.0;   // the plant's rotor flux when the magnetisation ends
    std::string fault;
};
static StartUp start_up(const std::string& estimator, std::vector<std::string> extra = {})
{
    std::vector<std::string> sets = {"control.mode=torque", "control.torque_ref_nm=0", "load.type=speed",
                                     "load.speed_rpm=0", "control.estimator=" + estimator, "duration_s=2"};
    sets.insert(sets.end(), extra.begin(), extra.end());
    PaperRig r(sets);
    StartUp o;
    if (!r.ok) {
        return o;
    }
    r.record("fig17_" + estimator, 2);
    const double t_magn = static_cast<double>(r.cfg.u.im.ref.magn_periods) * r.ts();
    r.run(64.0 * r.ts() + t_magn, [&] {
        o.te_worst_magn = std::fmax(o.te_worst_magn, std::fabs(r.st().te_nm));
        o.i_peak_magn = std::fmax(o.i_peak_magn, r.imag());
    });
    o.psir_magn = r.psir();
    r.run(0.3); // torque allowed, still commanded zero: the rotor flux completes its rise (tau_r)
    // The 50 ms before the torque step: the mean current-vector magnitude (the DC magnetising
    // current) and the spread of its 5 ms means (a DC current has none).
    double sum = 0.0, lo = 1e9, hi = 0.0, part = 0.0;
    long n = 0;
    const long n5 = r.periods(0.005);
    r.run(0.05, [&] {
        sum += r.imag();
        part += r.imag();
        if (++n % n5 == 0) {
            lo = std::fmin(lo, part / static_cast<double>(n5));
            hi = std::fmax(hi, part / static_cast<double>(n5));
            part = 0.0;
        }
    });
    o.i_dc = sum / static_cast<double>(n);
    o.i_drift = (hi - lo) / std::fmax(o.i_dc, 1e-9);
    o.psir_before = r.psir();
    const double t_rated = r.sc.motor.rated_torque_nm;
    r.refs(DTC_MODE_TORQUE, t_rated, 0.0);
    long k = 0;
    r.run(0.1, [&] {
        ++k;
        if (o.rise_ms < 0.0 && r.st().te_nm >= 0.9 * t_rated) {
            o.rise_ms = static_cast<double>(k) * r.ts() * 1e3;
        }
    });
    o.fault = r.fault();
    return o;
}

TEST(ImCasadei, Fig17ImprovedEstimatorMagnetisesAtZeroTorqueAndTheTorqueFollowsInMilliseconds)
{
    const StartUp imp = start_up("improved");
    const StartUp vol = start_up("voltage");
    std::printf("MEASURE Fig17 voltage: rotor flux %.3f Wb at the end of the magnetisation, then held at T* = 0: DC "
                "current %.2f A (spread %.2f %%), rotor flux %.3f Wb, rise %.2f ms, fault %s\n",
                vol.psir_magn, vol.i_dc, 100.0 * vol.i_drift, vol.psir_before, vol.rise_ms, vol.fault.c_str());
    std::printf("MEASURE Fig17 improved: DC current %.2f A (5 ms means spread %.2f %%), rotor flux %.3f Wb, max |T| "
                "while magnetising %.2f N*m, peak current %.1f A (rated %.1f), rise to 90 %% rated %.2f ms, fault %s\n",
                imp.i_dc, 100.0 * imp.i_drift, imp.psir_before, imp.te_worst_magn, imp.i_peak_magn,
                PLANT_DEF_IM_RATED_CURRENT_A, imp.rise_ms, imp.fault.c_str());
    // Improved estimator: a steady DC current vector, the machine's magnetising current (plant
    // rotor flux / M), the rotor flux at its reference within 10 % (measured 8 % low: the residual
    // voltage error at DC, docs/firmware-core.md), no torque; then the rated torque within 5 ms.
    const double psir_ref = 0.53; // im_dtc_speed.toml control.rotor_flux_ref_wb
    EXPECT_EQ(imp.fault, "none");
    EXPECT_NEAR(imp.i_dc, imp.psir_before / PLANT_DEF_IM_LM_H, 0.05 * imp.i_dc);
    EXPECT_LT(imp.i_drift, 0.05);
    EXPECT_LT(imp.te_worst_magn, 0.05 * PLANT_DEF_IM_RATED_TORQUE_NM);
    // The start-up ramp (im_dtc.h) holds the magnetising current at the rated current, plus the
    // ripple of the flux comparator on top (a step of phi_s* would head for phi_s*/(sigma L_s),
    // 5.7x rated).
    EXPECT_LT(imp.i_peak_magn, 1.25 * PLANT_DEF_IM_RATED_CURRENT_A);
    EXPECT_NEAR(imp.psir_before, psir_ref, 0.10 * psir_ref);
    ASSERT_GT(imp.rise_ms, 0.0);
    EXPECT_LE(imp.rise_ms, 5.0);
    // Voltage model (Casadei eq. 1, a low-pass for the integrator), Fig. 17a, on the rig's trips
    // (the start-up ramp holds the current below rated, im_dtc.h). During the start-up it takes
    // Casadei eq. 20's correction towards the start-up's rotor-flux model (im_est.h), so the
    // magnetisation itself reaches the reference (within 10 %, as the improved estimator's).
    // Held at standstill at zero torque after it, the low-pass alone cannot hold the DC flux (its
    // estimate decays at 5 rad/s while the machine keeps it): the machine is over-magnetised
    // (rotor flux more than 20 % above its reference; the current not a steady DC), the
    // statement of Fig. 17a that remains for the low-pass at DC.
    EXPECT_EQ(vol.fault, "none");
    EXPECT_NEAR(vol.psir_magn, psir_ref, 0.10 * psir_ref);
    EXPECT_GT(vol.psir_before / psir_ref - 1.0, 0.2);
    EXPECT_GT(vol.i_drift, 0.05);
}

// ---- common: magnetised at standstill, then torque mode at a held speed --------------------------
// Torque mode: the firmware magnetises at zero torque at standstill (Casadei Fig. 17b); T* = t0_nm as soon
// as torque is allowed, the dynamometer takes the rotor to rpm in 0.2 s, and 0.2 s of settling (the
// mean-torque trim, 20 ms). No hold at T* = 0 after the magnetisation: ST-A cannot hold the flux
// there (test Sec6StACannotHoldTheFluxAtZeroTorqueAtStandstill).
static void to_operating_point(Rig& r, double rpm, double t0_nm)
{
    r.magnetise(0.0);
    r.refs(DTC_MODE_TORQUE, t0_nm, 0.0);
    r.ramp_held_speed(rpm, 0.2);
    r.run(0.2);
}

static std::vector<std::string> torque_at_held_speed(std::vector<std::string> extra)
{
    std::vector<std::string> s = {"control.mode=torque", "control.torque_ref_nm=0", "load.type=speed",
                                  "load.speed_rpm=0", "duration_s=5"};
    s.insert(s.end(), extra.begin(), extra.end());
    return s;
}

// ---- Casadei Figs. 14-15: 50 % -> 300 % rated torque step at constant rotor flux ------------------
// Casadei sec. 10.1: the torque follows in a few ms (rise <= 3 ms), the rotor flux magnitude stays
// constant (circular locus, within 2 %) and the stator flux rises as Casadei eq. 19 demands. The paper
// gives no speed: 500 rpm held (well above 1/tau of the estimator's DC region) and standstill.
// The 300 % request is held at the torque the current limit allows (tools/config
// dtc_im_torque_at_current_nm: 224 % on this rig's 55 A trip, which the scenario checker caps at
// 3 x the rated current): the rise, the rotor flux and Casadei eq. 19 are checked at that torque,
// and the peak current below the trip.
struct Step14 {
    double rise_ms = -1.0, psir_worst = 0.0, psis_before = 0.0, psis_after = 0.0, psir_mean = 0.0, i_peak = 0.0;
    double t_hi = 0.0; // the step's torque: 300 % held at the torque limit in force
    std::string fault;
};
static Step14 step_14(double rpm)
{
    PaperRig r(torque_at_held_speed({}));
    Step14 o;
    if (!r.ok) {
        return o;
    }
    const double tr = r.sc.motor.rated_torque_nm;
    to_operating_point(r, rpm, 0.5 * tr);
    r.record("fig14_" + std::to_string(static_cast<int>(rpm)) + "rpm");
    double s = 0.0;
    long n = 0;
    r.run(0.02, [&] {
        s += r.psis();
        ++n;
    });
    o.psis_before = s / static_cast<double>(n);
    const double psir_ref = r.sc.control.rotor_flux_ref_wb;
    o.t_hi = std::fmin(3.0 * tr, static_cast<double>(r.cfg.speed.torque_limit_iq) / 16777216.0 * r.b.t_base_nm);
    r.refs(DTC_MODE_TORQUE, 3.0 * tr, 0.0);
    long k = 0;
    double sa = 0.0, sr = 0.0;
    long na = 0;
    r.run(0.04, [&] {
        ++k;
        if (o.rise_ms < 0.0 && r.st().te_nm >= 0.9 * o.t_hi) {
            o.rise_ms = static_cast<double>(k) * r.ts() * 1e3;
        }
        o.psir_worst = std::fmax(o.psir_worst, std::fabs(r.psir() / psir_ref - 1.0));
        o.i_peak = std::fmax(o.i_peak, r.imag());
        if (k > r.periods(0.01)) {
            sa += r.psis();
            sr += r.psir();
            ++na;
        }
    });
    o.psis_after = sa / static_cast<double>(na);
    o.psir_mean = sr / static_cast<double>(na);
    o.fault = r.fault();
    return o;
}

TEST(ImCasadei, Fig14And15TorqueStepTo300PercentAtConstantRotorFlux)
{
    Scenario sc;
    Diagnostics d;
    ASSERT_TRUE(load_scenario(kScenario, {}, &sc, &d)) << d.text();
    const Machine mc(sc);
    const double psir_ref = sc.control.rotor_flux_ref_wb, tr = sc.motor.rated_torque_nm;
    const double eq19_before = mc.stator_flux(psir_ref, 0.5 * tr);
    for (double rpm : {500.0, 0.0}) {
        const Step14 o = step_14(rpm);
        const double eq19_after = mc.stator_flux(psir_ref, o.t_hi);
        std::printf("MEASURE Fig14-15 at %.0f rpm: 300 %% requested, %.1f %% allowed by the current limit; rise to 90 %% of it "
                    "%.2f ms, rotor flux worst %.2f %% of %.2f Wb "
                    "(mean after %.3f), stator flux %.3f -> %.3f Wb (eq. 19: %.3f -> %.3f), peak current %.1f A, fault %s\n",
                    rpm, 100.0 * o.t_hi / tr, o.rise_ms, 100.0 * o.psir_worst, psir_ref, o.psir_mean, o.psis_before, o.psis_after,
                    eq19_before, eq19_after, o.i_peak, o.fault.c_str());
        EXPECT_GT(o.t_hi, 2.0 * tr); // the step still more than doubles the torque
        EXPECT_LT(o.i_peak, sc.protection.overcurrent_a);
        if (rpm > 0.0) {
            EXPECT_EQ(o.fault, "none");
            ASSERT_GT(o.rise_ms, 0.0);
            EXPECT_LE(o.rise_ms, 3.0);
            EXPECT_LT(o.psir_worst, 0.03);
            EXPECT_NEAR(o.psis_before, eq19_before, 0.03 * eq19_before);
            EXPECT_NEAR(o.psis_after, eq19_after, 0.03 * eq19_after);
        }
    }
}

// ---- Casadei Fig. 5: torque pulse +18 -> -18 N*m for 8.8 ms at a held speed, ST-A against ST-D ----------
// Casadei sec. 6: at 20 rad/s the response with ST-A (null vectors for the decrease) is sluggish
// and with ST-D (backward active vectors) quick; at 100 rad/s both are quick and almost equal.
// Response time: from the -18 N*m command until the plant torque is 90 % of the way down. Before
// the pulse the drive must hold +18 N*m with its flux estimate on the machine's (a response time
// of a drive that lost its flux means nothing).
struct Pulse {
    double t_ms = -1.0, te_before = 0.0, psi_err = 0.0;
    double pred_null_ms = 0.0, pred_backward_ms = 0.0; // closed form, below
    std::string fault;
};

// Closed-form response times from Casadei eqs. 14-15 on the plant's state at the pulse. With the
// rotor flux constant over a few ms, dT/dt = -a T - b, a = (R_s/L_s + R_r/L_r)/sigma (Casadei eq. 14) and
// b from eq. 15: the back-EMF term k w |phi_s||phi_r| cos(delta) for a null vector, plus the voltage
// term k |v| |phi_r| 0.866 cos(theta) for ST-D's backward vectors V_k-1 / V_k-2 (their mean, theta
// = the stator-flux angle from its sector's centre), with k = 3/2 p M / (sigma L_s L_r) (the 3/2 of
// the plant's torque A10, which Casadei eq. 15 leaves in its scaling). So T(t) = (T0 + b/a) e^-at - b/a
// and the time to T1 is ln((T0 + b/a)/(T1 + b/a)) / a.
static void predict_pulse(const Rig& r, double t0, double t1, Pulse* o)
{
    const Scenario& sc = r.sc;
    const double m = sc.motor.lm_h, ls = sc.motor.lls_h + m, lr = sc.motor.llr_h + m;
    const double sigma = 1.0 - m * m / (ls * lr);
    const double p = static_cast<double>(sc.motor.pole_pairs);
    const double a = (sc.motor.rs_ohm / ls + sc.motor.rr_ohm / lr) / sigma;
    const double k = 1.5 * p * m / (sigma * ls * lr);
    const plant_state_t& st = r.st();
    const double ths = std::atan2(st.psi_beta_wb, st.psi_alpha_wb), thr = std::atan2(st.psi_r_beta_wb, st.psi_r_alpha_wb);
    const double w = p * st.omega_m_rad_s;
    const double b_null = k * w * r.psis() * r.psir() * std::cos(ths - thr);
    const double theta = std::remainder(ths, kPi / 3.0); // sectors centred on the six vectors
    const double b_back = b_null + k * (2.0 / 3.0) * st.vdc_v * r.psir() * 0.866 * std::cos(theta);
    const auto t_ms = [&](double b) { return 1e3 * std::log((t0 + b / a) / (t1 + b / a)) / a; };
    o->pred_null_ms = t_ms(b_null);
    o->pred_backward_ms = t_ms(b_back);
}
static Pulse pulse_response(const std::string& table, double w_mech)
{
    PaperRig r(torque_at_held_speed({"control.table=" + table}));
    Pulse o;
    if (!r.ok) {
        return o;
    }
    to_operating_point(r, w_mech * 30.0 / kPi, 18.0);
    r.record("fig5_" + table + "_" + std::to_string(static_cast<int>(std::lround(w_mech))));
    const double pb = r.b.psi_base_wb / kIqOne;
    double s = 0.0, e = 0.0;
    long n = 0;
    r.run(0.02, [&] {
        s += r.st().te_nm;
        const app_status_t st = r.status();
        e = std::fmax(e, std::hypot(st.out.psi_alpha_iq * pb - r.st().psi_alpha_wb, st.out.psi_beta_iq * pb - r.st().psi_beta_wb));
        ++n;
    });
    o.te_before = s / static_cast<double>(n);
    o.psi_err = e / r.sc.control.flux_ref_wb;
    predict_pulse(r, r.st().te_nm, 18.0 - 0.9 * 36.0, &o);
    r.refs(DTC_MODE_TORQUE, -18.0, 0.0);
    long k = 0;
    r.run(0.0088, [&] {
        ++k;
        if (o.t_ms < 0.0 && r.st().te_nm <= 18.0 - 0.9 * 36.0) {
            o.t_ms = static_cast<double>(k) * r.ts() * 1e3;
        }
    });
    r.refs(DTC_MODE_TORQUE, 18.0, 0.0);
    r.run(0.01);
    o.fault = r.fault();
    return o;
}

static void print_pulse(const char* what, const Pulse& p)
{
    std::printf("MEASURE Fig5 %s: response %.2f ms (-1 = not within the 8.8 ms pulse; eqs. 14-15: null vectors %.2f ms, "
                "backward vectors %.2f ms), torque before %.2f N*m, worst flux-estimate error before %.1f %% of phi_s*, fault %s\n",
                what, p.t_ms, p.pred_null_ms, p.pred_backward_ms, p.te_before, 100.0 * p.psi_err, p.fault.c_str());
}

// The paper: at 20 rad/s ST-A's response (null vectors for the decrease) is
// sluggish against ST-D's; at 100 rad/s both are quick "and almost identical". The physical reason
// is Casadei eq. 15: a null vector lowers the torque only through the back-EMF term, which grows with the
// speed, while ST-D's backward vectors add the full inverter voltage. Asserted: each response
// time within 25 % + 2 periods of that closed form (predict_pulse), sluggish against quick at
// 20 rad/s (ratio > 3), quick at 100 rad/s (ST-A < 1 ms, a ninth of the pulse) with a ratio at
// least halved. How close "almost identical" gets depends on |v| against w |phi_s|: on this rig
// (311 V link, 0.55 Wb) the closed form gives about 2.5 at 100 rad/s, printed beside the measure.
TEST(ImCasadei, Fig5StASluggishAtLowSpeedStDQuickBothQuickAtHighSpeed)
{
    const Pulse a20 = pulse_response("st-a", 20.0), a100 = pulse_response("st-a", 100.0);
    const Pulse d20 = pulse_response("st-d", 20.0), d100 = pulse_response("st-d", 100.0);
    print_pulse("ST-A 20 rad/s", a20);
    print_pulse("ST-A 100 rad/s", a100);
    print_pulse("ST-D 20 rad/s", d20);
    print_pulse("ST-D 100 rad/s", d100);
    std::printf("MEASURE Fig5 ratio ST-A / ST-D: %.2f at 20 rad/s (eqs. 14-15: %.2f), %.2f at 100 rad/s (eqs. 14-15: %.2f)\n",
                a20.t_ms / d20.t_ms, a20.pred_null_ms / d20.pred_backward_ms, a100.t_ms / d100.t_ms,
                a100.pred_null_ms / d100.pred_backward_ms);
    constexpr double kPeriodMs = 0.04;
    for (const Pulse* p : {&a20, &a100, &d20, &d100}) {
        EXPECT_EQ(p->fault, "none");
        EXPECT_NEAR(p->te_before, 18.0, 0.1 * 18.0);
        EXPECT_LT(p->psi_err, 0.10);
        ASSERT_GT(p->t_ms, 0.0);
    }
    for (const Pulse* p : {&a20, &a100}) {
        EXPECT_NEAR(p->t_ms, p->pred_null_ms, 0.25 * p->pred_null_ms + 2.0 * kPeriodMs);
    }
    for (const Pulse* p : {&d20, &d100}) {
        EXPECT_NEAR(p->t_ms, p->pred_backward_ms, 0.25 * p->pred_backward_ms + 2.0 * kPeriodMs);
        EXPECT_LT(p->t_ms, 1.0); // quick at both speeds
    }
    EXPECT_GT(a20.t_ms / d20.t_ms, 3.0); // sluggish against quick
    EXPECT_LT(a100.t_ms, 1.0);           // quick
    EXPECT_LT(a100.t_ms / d100.t_ms, 0.5 * a20.t_ms / d20.t_ms);
}

// ST-A holding T* = 0 at standstill: the T-decrease row has only null vectors, and at standstill a
// null vector takes the torque to zero without ever crossing the lower band, so the comparator
// stays at "decrease" and the inverter applies nothing while the flux decays through R_s (Casadei
// sec. 6: ST-A is a two-quadrant table). The improved estimator does not see it: with e = phi_s,est -
// phi_s, Casadei eq. 20 gives de/dt = (phi_r* - phi_r)/tau - (L_r/M) e/tau, so e settles at (M/L_r)(phi_r* -
// phi_r) and the estimate stays near the reference. A drive that must hold zero torque at
// standstill uses ST-D or the speed-dependent table (ST-D there); both hold the flux.
TEST(ImCasadei, Sec6StACannotHoldTheFluxAtZeroTorqueAtStandstill)
{
    for (const char* table : {"st-a", "st-d", "speed-dependent"}) {
        PaperRig r(torque_at_held_speed({std::string("control.table=") + table}));
        ASSERT_TRUE(r.ok);
        r.magnetise(0.0);
        r.record(std::string("sec6_") + table, 5);
        const double before = r.psis();
        r.run(0.2);
        const app_status_t st = r.status();
        const double est = std::hypot(static_cast<double>(st.out.psi_alpha_iq), static_cast<double>(st.out.psi_beta_iq)) *
                           r.b.psi_base_wb / kIqOne;
        std::printf("MEASURE Sec6 %s, T* = 0 at standstill for 0.2 s: plant |phi_s| %.3f -> %.3f Wb, estimate %.3f Wb, fault %s\n",
                    table, before, r.psis(), est, r.fault().c_str());
        EXPECT_EQ(r.fault(), "none");
        if (std::string(table) == "st-a") {
            EXPECT_LT(r.psis(), 0.6 * before);  // the flux decays
            EXPECT_GT(est, 0.9 * before);       // and the estimate hides it
        } else {
            EXPECT_NEAR(r.psis(), before, 0.05 * before);
        }
    }
}

// ---- Section 8: the speed-dependent table -----------------------------------------------------
// ST-D below the hand-over speed (derived: 779 rpm), ST-A above. Casadei sec. 8: "a better torque
// response over the whole speed range and a reduction in the torque ripple". Asserted as the
// physics of Casadei eqs. 14-15 gives them: at low speed the table's response is ST-D's (quick, Fig. 5)
// where ST-A's is sluggish; at high speed its ripple is ST-A's, lower than ST-D's, whose backward
// vectors take a large torque step in every 40 us period (rated torque held, zero bands). Not a
// claim of this drive: a lower ripple than ST-A at low speed. With a comparator sampled every
// 40 us the ripple follows the per-period torque steps, and ST-A's null vectors lower the torque
// slowly at low speed (the same Casadei eq. 15 term that makes its response sluggish), so ST-A ripples
// less there; the test asserts that ordering and prints the figures.
struct Ripple {
    double rms = 0.0, mean = 0.0;
    std::string fault;
};
static Ripple ripple(const std::string& table, double rpm)
{
    PaperRig r(torque_at_held_speed({"control.table=" + table}));
    Ripple o;
    if (!r.ok) {
        return o;
    }
    to_operating_point(r, rpm, r.sc.motor.rated_torque_nm);
    double s = 0.0, s2 = 0.0;
    long n = 0;
    r.run(0.1, [&] {
        s += r.st().te_nm;
        s2 += r.st().te_nm * r.st().te_nm;
        ++n;
    });
    o.mean = s / static_cast<double>(n);
    o.rms = std::sqrt(std::fmax(0.0, s2 / static_cast<double>(n) - o.mean * o.mean));
    o.fault = r.fault();
    return o;
}

TEST(ImCasadei, Sec8SpeedDependentTableAgainstStAAndStD)
{
    const double lo = 150.0, hi = 1300.0;
    const Ripple sd_lo = ripple("speed-dependent", lo), a_lo = ripple("st-a", lo), d_lo = ripple("st-d", lo);
    const Ripple sd_hi = ripple("speed-dependent", hi), a_hi = ripple("st-a", hi), d_hi = ripple("st-d", hi);
    std::printf("MEASURE Sec8 torque ripple rms / mean (N*m) at %.0f rpm: speed-dependent %.2f / %.2f, ST-A %.2f / %.2f, "
                "ST-D %.2f / %.2f; at %.0f rpm: speed-dependent %.2f / %.2f, ST-A %.2f / %.2f, ST-D %.2f / %.2f\n",
                lo, sd_lo.rms, sd_lo.mean, a_lo.rms, a_lo.mean, d_lo.rms, d_lo.mean, hi, sd_hi.rms, sd_hi.mean,
                a_hi.rms, a_hi.mean, d_hi.rms, d_hi.mean);
    const Pulse sd20 = pulse_response("speed-dependent", 20.0), a20 = pulse_response("st-a", 20.0);
    const Pulse sd_fast = pulse_response("speed-dependent", hi * kPi / 30.0);
    print_pulse("speed-dependent 20 rad/s", sd20);
    print_pulse("speed-dependent at the high speed", sd_fast);
    const double tr = PLANT_DEF_IM_RATED_TORQUE_NM;
    for (const Ripple* r : {&sd_lo, &sd_hi, &a_lo, &a_hi, &d_lo, &d_hi}) {
        EXPECT_EQ(r->fault, "none");
        EXPECT_NEAR(r->mean, tr, 0.1 * tr);
    }
    // Response: quick over the whole speed range, where ST-A is sluggish at low speed.
    for (const Pulse* p : {&sd20, &sd_fast}) {
        EXPECT_EQ(p->fault, "none");
        ASSERT_GT(p->t_ms, 0.0);
        EXPECT_LT(p->t_ms, 1.0);
    }
    EXPECT_GT(a20.t_ms, 3.0 * sd20.t_ms);
    // Ripple: at high speed the table is ST-A and ripples less than ST-D.
    EXPECT_LT(sd_hi.rms, 0.8 * d_hi.rms);
    EXPECT_NEAR(sd_hi.rms, a_hi.rms, 0.15 * a_hi.rms);
    // At low speed the table is ST-D; ST-A's slow null-vector decrease ripples less (see above).
    EXPECT_NEAR(sd_lo.rms, d_lo.rms, 0.15 * d_lo.rms);
    EXPECT_LT(a_lo.rms, d_lo.rms);
}

// ---- Casadei Fig. 13 and section 9: DSC hexagon, fewer commutations than DTC ----------------------
// Rated torque at 1000 rpm held. DTC (Casadei Table 1) with a flux band of 0.14 phi_s* traces a DSC-like
// polygon (Fig. 13): |phi_s| spans about cos 30 deg .. 1 of its peak like a hexagon; without the
// band the locus is a circle. DSC itself: the test below.
struct Locus {
    double ratio = 0.0, comm_per_period = 0.0;
    std::string fault;
};
static Locus locus(const std::string& name, const std::vector<std::string>& sets)
{
    PaperRig r(torque_at_held_speed(sets));
    Locus o;
    if (!r.ok) {
        return o;
    }
    to_operating_point(r, 1000.0, r.sc.motor.rated_torque_nm);
    r.record(name);
    double lo = 1e9, hi = 0.0, ang = 0.0, prev = std::atan2(r.st().psi_beta_wb, r.st().psi_alpha_wb);
    long comm = 0;
    hal_cmd_t last = r.h->applied_cmd();
    r.run(0.1, [&] {
        lo = std::fmin(lo, r.psis());
        hi = std::fmax(hi, r.psis());
        const double a = std::atan2(r.st().psi_beta_wb, r.st().psi_alpha_wb);
        ang += std::remainder(a - prev, 2.0 * kPi);
        prev = a;
        const hal_cmd_t c = r.h->applied_cmd();
        comm += (c.sa != last.sa) + (c.sb != last.sb) + (c.sc != last.sc);
        last = c;
    });
    o.ratio = lo / hi;
    o.comm_per_period = static_cast<double>(comm) / std::fmax(std::fabs(ang) / (2.0 * kPi), 1e-9);
    o.fault = r.fault();
    return o;
}

TEST(ImCasadei, Fig13DtcWithWideFluxBandTracesAHexagonLikeLocus)
{
    const Locus wide = locus("fig13_dtc_band014", {"control.flux_band_wb=0.077"}); // 0.14 x 0.55 Wb
    const Locus narrow = locus("fig13_dtc_band0", {});
    std::printf("MEASURE Fig13 |phi_s| min/max, leg commutations per electrical period: DTC band 0.14 phi_s* %.3f, %.1f; "
                "DTC band 0 %.3f, %.1f\n",
                wide.ratio, wide.comm_per_period, narrow.ratio, narrow.comm_per_period);
    EXPECT_EQ(wide.fault, "none");
    EXPECT_EQ(narrow.fault, "none");
    EXPECT_NEAR(wide.ratio, std::cos(kPi / 6.0), 0.06); // a hexagon's inner/outer radius
    EXPECT_GT(narrow.ratio, 0.93);                      // a circle
    EXPECT_LT(wide.comm_per_period, narrow.comm_per_period);
}

// Section 9. DSC takes over from the start-up magnetisation (flux on the alpha axis, built by
// V1) with the leg states of the hexagon at the flux's angle (dsc.h) and traces the hexagon:
// |phi_s| min/max = cos 30 deg (inner/outer radius), with fewer leg commutations per electrical
// period than DTC at the same speed and torque.
TEST(ImCasadei, Sec9DscHexagonWithFewerCommutationsThanDtc)
{
    const Locus dsc = locus("sec9_dsc", {"control.scheme=dsc"});
    const Locus dtc = locus("sec9_dtc", {});
    std::printf("MEASURE Sec9 DSC |phi_s| min/max %.3f, commutations per period %.1f (DTC %.1f), fault %s\n", dsc.ratio,
                dsc.comm_per_period, dtc.comm_per_period, dsc.fault.c_str());
    EXPECT_EQ(dsc.fault, "none");
    EXPECT_NEAR(dsc.ratio, std::cos(kPi / 6.0), 0.05);
    EXPECT_LT(dsc.comm_per_period, dtc.comm_per_period);
}

// ---- Casadei Figs. 22-24: parameter errors at omega = 1 rad/s, rated torque, tau = 0.01 s ----------
// Casadei sec. 10.8: with the improved estimator the rotor-flux error due to a 10 % low or high
// stator resistance in the firmware, or a 0.01 A current-sensor offset, settles to a bounded
// value; with the basic (voltage-model) estimator it grows. Rotor held at the paper's omega = 1
// rad/s, electrical (Casadei's omega is electrical: 4.77 rpm on the 4-pole IM), by the
// dynamometer, rated torque. Error: the plant's |phi_r| against phi_r* over 1.5 s.
// The voltage-model runs have their sensors and trips at 1 kA so that their error can grow (on
// the rig's trips the R_s-high case stops on over-current); the improved ones run on the rig's.
struct Sens {
    std::vector<double> err;    // |phi_r| / phi_r* - 1 at 0.25 s intervals after the torque is applied
    std::vector<double> series; // the same every period over the 1.5 s
    double mean = 0.0;          // its mean over the 1.5 s, every period
    double osc_ws = 0.0;        // amplitude of its component at the stator frequency w_s (whole periods)
    double ts = 0.0;
    std::string fault;
};
// Amplitude of the component of x (one sample per ts) at w rad/s: one DFT line over the whole
// periods of w that fit.
static double line_at(const std::vector<double>& x, double w, double ts)
{
    const auto per = static_cast<std::size_t>(2.0 * kPi / w / ts);
    const std::size_t len = per > 0 ? x.size() / per * per : 0;
    double c = 0.0, sn = 0.0;
    for (std::size_t k = 0; k < len; ++k) {
        const double ph = w * static_cast<double>(k) * ts;
        c += x[k] * std::cos(ph);
        sn += x[k] * std::sin(ph);
    }
    return len > 0 ? 2.0 * std::hypot(c, sn) / static_cast<double>(len) : 0.0;
}
// drift_a: a phase-A current-sensor offset that appears once the drive is at its operating point
// (after the start-up calibration, which would remove it).
static Sens sensitivity(const std::string& name, const std::string& estimator, const std::vector<std::string>& mismatch,
                        double drift_a = 0.0, double ws = 0.0, int quarters = 6, double drift_b = 0.0)
{
    std::vector<std::string> sets = {"control.estimator=" + estimator};
    if (estimator == "voltage") {
        sets.insert(sets.end(), {"sensors.current_range_a=1000", "protection.overcurrent_a=850",
                                 "protection.hw_trip_current_a=0", "protection.allow_unsafe=true"});
    }
    sets.insert(sets.end(), mismatch.begin(), mismatch.end());
    PaperRig r(torque_at_held_speed(sets));
    Sens o;
    if (!r.ok) {
        return o;
    }
    to_operating_point(r, 30.0 / kPi / static_cast<double>(r.sc.motor.pole_pairs), r.sc.motor.rated_torque_nm);
    r.h->set_current_offset(0, drift_a);
    r.h->set_current_offset(1, drift_b);
    r.record("fig22_" + name + "_" + estimator, 10);
    const double ref = r.sc.control.rotor_flux_ref_wb;
    double sum = 0.0;
    long n = 0;
    std::vector<double> e;
    for (int i = 0; i < quarters && r.fault() == "none"; ++i) {
        r.run(0.25, [&] {
            e.push_back(r.psir() / ref - 1.0);
            sum += e.back();
            ++n;
        });
        o.err.push_back(r.psir() / ref - 1.0);
    }
    o.mean = sum / static_cast<double>(std::max(n, 1L));
    if (ws > 0.0) {
        o.osc_ws = line_at(e, ws, r.ts());
    }
    o.series = e;
    o.ts = r.ts();
    o.fault = r.fault();
    return o;
}

// The operating point of Casadei Figs. 22-24 on the scenario's machine: rated torque at phi_r*, the
// rotor at omega = 1 rad/s electrical; i_sq and the stator frequency w_s = omega + slip (Casadei eq. 16).
struct Fig22Point {
    Scenario sc;
    double phr = 0.0, tq = 0.0, isq = 0.0, ws = 0.0;
};
static Fig22Point fig22_point()
{
    Fig22Point o;
    Diagnostics d;
    EXPECT_TRUE(load_scenario(kScenario, {}, &o.sc, &d));
    const Machine mc(o.sc);
    o.phr = o.sc.control.rotor_flux_ref_wb;
    o.tq = o.sc.motor.rated_torque_nm;
    o.isq = o.tq * mc.lr / (1.5 * mc.p * mc.m * o.phr);
    o.ws = 1.0 + mc.m / mc.tau_r * o.isq / o.phr;
    return o;
}

// The offset's own oscillation: the run with the offset (da on phase A, db on B, appearing after the
// calibration) less the same run without it, its line at w_s and its largest line between w_s / 2
// and 2 w_s over the last 3 s of 5 s.
struct OffsetLine {
    double osc = 0.0, w_pk = 0.0, a_pk = 0.0;   // the offset's own: line at w_s, largest line and where
    double osc_total = 0.0, base_osc = 0.0;     // the runs' own lines at w_s, with and without the offset
    double mean = 0.0, base_mean = 0.0;         // their mean rotor-flux errors
    std::vector<double> err;                    // the run with the offset, every 0.25 s
    std::string fault;
};
static OffsetLine offset_own_line(const std::string& tag, const std::vector<std::string>& sets, double da, double db,
                                  double ws)
{
    const Sens base = sensitivity("none_path_" + tag, "improved", sets, 0.0, ws, 20);
    const Sens drf = sensitivity("drift_path_" + tag, "improved", sets, da, ws, 20, db);
    OffsetLine o;
    const std::size_t n_all = std::min(base.series.size(), drf.series.size());
    const auto n_tail = std::min(n_all, static_cast<std::size_t>(3.0 / std::max(drf.ts, 1e-9)));
    std::vector<double> d(n_tail);
    for (std::size_t k = 0; k < n_tail; ++k) {
        d[k] = drf.series[n_all - n_tail + k] - base.series[n_all - n_tail + k];
    }
    for (double w = 0.5 * ws; w <= 2.0 * ws; w += 0.01 * ws) {
        const double a = line_at(d, w, drf.ts);
        if (a > o.a_pk) {
            o.a_pk = a;
            o.w_pk = w;
        }
    }
    o.osc = line_at(d, ws, drf.ts);
    o.osc_total = drf.osc_ws;
    o.base_osc = base.osc_ws;
    o.mean = drf.mean;
    o.base_mean = base.mean;
    o.err = drf.err;
    o.fault = drf.fault;
    return o;
}

TEST(ImCasadei, Figs22To24ImprovedEstimatorErrorBoundedBasicGrows)
{
    const double rs = PLANT_DEF_IM_RS_OHM;
    const struct {
        const char* name;
        const char* file;
        std::vector<std::string> sets;
    } cases[] = {
        {"no parameter error", "none", {}},
        {"R_s 10 % low", "rs_low", {"firmware.rs_ohm=" + std::to_string(0.9 * rs)}},
        {"R_s 10 % high", "rs_high", {"firmware.rs_ohm=" + std::to_string(1.1 * rs)}},
        {"0.01 A offset", "offset", {"sensors.current_offset_a=[0.01, 0, 0]"}},
    };
    // Steady state with the R_s error alone (Casadei eqs. 25-26 at steady state, first order): the drive
    // holds the estimated rotor flux at phi_r*, so Casadei eq. 20's correction is idle and the estimate
    // error e = phi_s,est - phi_s obeys j w_s e = -dR_s i_s; the rotor flux is then off by
    // -(L_r/M) e, whose component along phi_r is (L_r/M) dR_s i_sq / w_s, independent of tau as
    // sec. 10.8 says. i_sq and the stator frequency w_s = p w + slip (Casadei eq. 16) from the machine at
    // rated torque and phi_r*.
    const Fig22Point pt = fig22_point();
    const Machine mc(pt.sc);
    const double ws = pt.ws;
    const double theory_per_dr = mc.lr / mc.m * pt.isq / ws / pt.phr; // relative rotor-flux error per ohm of dR_s
    double mean_none = 0.0;
    for (const auto& c : cases) {
        const Sens imp = sensitivity(c.file, "improved", c.sets);
        const Sens vol = sensitivity(c.file, "voltage", c.sets);
        const std::string file = c.file;
        if (file == "none") {
            mean_none = imp.mean;
        } else if (file == "rs_low" || file == "rs_high") {
            // Against the no-error run (the device drops' residual, the same in both, cancels).
            const double dr = (file == "rs_low" ? -0.1 : 0.1) * rs;
            std::printf("MEASURE Figs22-24 %s: improved mean rotor-flux error %.2f %% (%.2f %% against the no-error run), "
                        "theory (eq. 26 steady state) %.2f %%\n",
                        c.name, 100.0 * imp.mean, 100.0 * (imp.mean - mean_none), 100.0 * theory_per_dr * dr);
            EXPECT_NEAR(imp.mean - mean_none, theory_per_dr * dr, 0.025) << c.name;
        }
        std::string a, b;
        for (double e : imp.err) a += std::to_string(100.0 * e).substr(0, 6) + " ";
        for (double e : vol.err) b += std::to_string(100.0 * e).substr(0, 6) + " ";
        std::printf("MEASURE Figs22-24 %s: rotor-flux error %% every 0.25 s: improved [%s] fault %s; voltage [%s] fault %s\n",
                    c.name, a.c_str(), imp.fault.c_str(), b.c_str(), vol.fault.c_str());
        auto worst = [](const Sens& x) {
            double w = 0.0;
            for (double e : x.err) w = std::fmax(w, std::fabs(e));
            return w;
        };
        // Improved: bounded, of the order of the parameter error (measured: within +-4.5 % with no
        // error, the residual voltage error of the devices at 1 rad/s; -7..-11 % for R_s 10 % low,
        // +4..+12 % for 10 % high). The 0.01 A offset is a fifth of an ADC count (+-100 A over 12
        // bits: 0.049 A) and the firmware calibrates the offsets with the gates off: the run is
        // the no-error run within a count, so Casadei Fig. 24's effect is below this rig's resolution.
        EXPECT_EQ(imp.fault, "none") << c.name;
        ASSERT_EQ(imp.err.size(), 6u) << c.name;
        EXPECT_LT(worst(imp), 0.15) << c.name;
        // Basic: the error wanders far beyond (the low-pass cannot hold the flux at 1 rad/s).
        EXPECT_GT(worst(vol), 2.0 * worst(imp)) << c.name;
    }
    // Casadei Fig. 24 with an offset the ADC resolves and the calibration cannot remove: 0.25 A (five
    // counts, 1.3 % of the rated current) on phase A, appearing once the drive is at its point (a
    // drift). A DC offset in the stationary frame is a disturbance at the stator frequency w_s in
    // the rotor-flux frame (Casadei eq. 28's cos/sin of the flux angle): the improved estimator's
    // rotor-flux error oscillates at w_s around its no-offset value, bounded (sec. 10.8). The
    // amplitude Casadei eq. 26 predicts is not compared (eq. 28's [B] is not reproduced in the tools).
    // The offset's own oscillation: the run with the offset less the run without (the two are the
    // same run until the offset appears), over 5 s, its line at w_s and the frequency of its largest
    // line between w_s / 2 and 2 w_s over the last 3 s: eq. 27's dominant poles lie near w_s with
    // a time constant of about 0.5 s on this machine, so the oscillation takes seconds to reach its
    // steady amplitude. Under the basic DTC and under the SFVC, the scheme of Casadei eqs. 26-28;
    // tools/report/casadei_items.py sets the amplitude beside eq. 26's prediction.
    const double drift = 0.25;
    // The SFVC with ideal devices also at half and twice the estimator's tau: eq. 26's amplitude
    // goes with tau (the casadei_items comparison holds each against its own prediction).
    for (const std::string scheme :
         {"dtc", "dtc_ideal", "sfvc", "sfvc_ideal", "sfvc_ideal_tau0.005", "sfvc_ideal_tau0.02"}) {
        std::vector<std::string> sets = {"control.scheme=" + scheme.substr(0, scheme.find('_'))};
        if (scheme.find("_ideal") != std::string::npos) { // eqs. 26-28 know no device drops: the plant's and the compensation off
            sets.insert(sets.end(), {"inverter.drops=false", "control.compensation=none"});
        }
        if (scheme.find("_tau") != std::string::npos) {
            sets.push_back("control.observer_tau_s=" + scheme.substr(scheme.find("_tau") + 4));
        }
        const OffsetLine o = offset_own_line(scheme, sets, drift, 0.0, ws);
        std::printf("MEASURE Fig24 %s %.2f A offset after the calibration, improved estimator: rotor-flux error at w_s = %.2f "
                    "rad/s %.2f %% (without the offset %.2f %%), the offset's own %.2f %%, its largest line %.2f %% at %.2f "
                    "rad/s, mean %.2f %% (%.2f %%), fault %s\n",
                    scheme.c_str(), drift, ws, 100.0 * o.osc_total, 100.0 * o.base_osc, 100.0 * o.osc, 100.0 * o.a_pk,
                    o.w_pk, 100.0 * o.mean, 100.0 * o.base_mean, o.fault.c_str());
        EXPECT_EQ(o.fault, "none") << scheme;
        EXPECT_GT(o.osc, 3.0 * o.base_osc) << scheme; // the oscillation at w_s is the offset's
        EXPECT_NEAR(o.w_pk, ws, 0.1 * ws) << scheme;  // at the stator frequency (Casadei sec. 10.8)
        const bool long_tau = scheme.find("_tau0.02") != std::string::npos; // eq. 26: twice the amplitude
        for (double e : o.err) {
            EXPECT_LT(std::fabs(e), long_tau ? 0.3 : 0.15) << scheme; // bounded
        }
    }
}

// ---- Casadei Fig. 24: which path multiplies the offset --------------------------------------------
// Casadei eq. 26 (tools/report/im_linear.py) takes the offset in by two paths only: R_s di in the
// estimator's EMF (eq. 20) and sigma L_s di in eq. 21's rotor flux; on this machine the two
// nearly cancel at w_s (R_s path alone 9.5 %, sigma L_s path alone 2.8 %, together 6.7 % for 0.25 A
// on phase A at tau = 0.01 s), so any further term in phase with R_s di is multiplied about five
// times in the amplitude. The drive has one such term: the dead-time compensation (svm.h for the
// SFVC, vrec.h deadtime_error for the DTC) takes each leg's current sign from the measured current,
// so around each zero crossing of the phases the offset moves (A, and C = -(A + B) reconstructed),
// it assumes the wrong sign for di / |i| of the half period. The voltage the estimator assumes then
// differs from the plant's by 2 V_dt there (V_dt = V_dc T_d / T_pwm per leg transition pair): on
// average an extra resistance 2 V_dt / (pi |i|) on the offset's path, in its direction. Each path
// switched off in turn, the offset's own oscillation measured as in Figs22To24 (ideal devices unless
// stated, 0.25 A on phase A after the calibration, or the same length on the alpha axis);
// tools/report/casadei_items.py sets each beside eq. 26 with and without that extra resistance.
TEST(ImCasadei, Fig24OffsetPathsSwitchedOffOneAtATime)
{
    const Fig22Point pt = fig22_point();
    const double ws = pt.ws;
    const std::vector<std::string> ideal = {"inverter.drops=false", "control.compensation=none"};
    const double da = 0.25;
    const double mag = da * 2.0 / std::sqrt(3.0); // |(1, 1/sqrt(3))| da: phase A's offset as an alpha-beta vector
    const struct {
        const char* tag;
        const char* scheme;
        bool ideal, dead_time, dt_comp;
        double tau, a, b; // tau 0: the scenario's
    } cases[] = {
        {"dtc_ideal", "dtc", true, true, true, 0.0, da, 0.0},
        {"dtc_ideal_no_dt", "dtc", true, false, false, 0.0, da, 0.0},
        {"dtc_ideal_no_dt_alpha", "dtc", true, false, false, 0.0, mag, -0.5 * mag},
        {"dtc_ideal_no_dt_tau0.005", "dtc", true, false, false, 0.005, da, 0.0},
        {"dtc_ideal_no_dt_tau0.02", "dtc", true, false, false, 0.02, da, 0.0},
        {"dtc_drops_no_dt", "dtc", false, false, false, 0.0, da, 0.0},
        {"sfvc_ideal", "sfvc", true, true, true, 0.0, da, 0.0},
        {"sfvc_ideal_dt_uncompensated", "sfvc", true, true, false, 0.0, da, 0.0},
        {"sfvc_ideal_no_dt", "sfvc", true, false, false, 0.0, da, 0.0},
    };
    std::map<std::string, OffsetLine> got;
    for (const auto& c : cases) {
        std::vector<std::string> sets = {std::string("control.scheme=") + c.scheme};
        if (c.ideal) {
            sets.insert(sets.end(), ideal.begin(), ideal.end());
        }
        sets.push_back(std::string("inverter.dead_time=") + (c.dead_time ? "true" : "false"));
        sets.push_back(std::string("control.deadtime_comp=") + (c.dt_comp ? "true" : "false"));
        if (c.tau > 0.0) {
            sets.push_back("control.observer_tau_s=" + std::to_string(c.tau));
        }
        const OffsetLine o = offset_own_line(c.tag, sets, c.a, c.b, ws);
        std::printf("MEASURE Fig24path %s offset A %.4f B %.4f A, tau %g s: the offset's own %.3f %% at w_s = %.2f rad/s, "
                    "largest line at %.2f rad/s, fault %s\n",
                    c.tag, c.a, c.b, c.tau > 0.0 ? c.tau : pt.sc.control.observer_tau_s, 100.0 * o.osc, ws, o.w_pk,
                    o.fault.c_str());
        EXPECT_EQ(o.fault, "none") << c.tag;
        got[c.tag] = o;
    }
    const auto amp = [&](const char* tag) { return got[tag].osc; };
    // The DTC without the dead time: the offset's oscillation at w_s, in the same direction whatever
    // the phase (the Clarke transform only makes it a vector: phase A's 0.25 A and the alpha-axis
    // 0.289 A of the same length give the same amplitude), and as Casadei eq. 26 says proportional
    // to tau on this machine (eq. 26: 3.31 / 6.62 / 13.24 % at tau 5 / 10 / 20 ms, x 2.00 per
    // doubling; tools/report/casadei_items.py holds each against eq. 26's own number).
    for (const char* tag : {"dtc_ideal_no_dt", "dtc_ideal_no_dt_alpha", "dtc_ideal_no_dt_tau0.005", "dtc_ideal_no_dt_tau0.02"}) {
        EXPECT_NEAR(got[tag].w_pk, ws, 0.1 * ws) << tag;
    }
    EXPECT_NEAR(amp("dtc_ideal_no_dt_alpha") / amp("dtc_ideal_no_dt"), 1.0, 0.1);
    EXPECT_NEAR(amp("dtc_ideal_no_dt") / amp("dtc_ideal_no_dt_tau0.005"), 2.0, 0.3);
    EXPECT_NEAR(amp("dtc_ideal_no_dt_tau0.02") / amp("dtc_ideal_no_dt"), 2.0, 0.3);
    // The sign-dependent voltages the estimator takes from the measured current's sign each raise it:
    // the dead time (measured +15 % with the sign of the sample at the period's end, +6.4 % with the
    // sign at the switching instant, the previous sample, im_dtc_estimate) and the device drops
    // (+16 %; 2 V / (pi |i|) of resistance in phase with R_s di, V = (V_CE + V_D) / 2, estimates +11 %).
    EXPECT_GT(amp("dtc_ideal") / amp("dtc_ideal_no_dt"), 1.03);
    EXPECT_GT(amp("dtc_drops_no_dt") / amp("dtc_ideal_no_dt"), 1.07);
    // Compensated at the gates or not, the estimator's sign model of the dead time (svm.h d_eff) is
    // the same: the same amplitude.
    EXPECT_NEAR(amp("sfvc_ideal_dt_uncompensated") / amp("sfvc_ideal"), 1.0, 0.05);
    // The SFVC without the dead time: bounded (the fault check above), its largest line printed (a
    // mode below w_s that the offset's step excites, which eq. 27 does not have: a finding, reported
    // by casadei_items, not asserted).
}

// ---- Casadei Fig. 25: sensorless, 50 -> 220 rpm and back to 0 with regenerative braking ------------
// Speed mode without an encoder (speed from the stator-flux angular speed minus the slip of
// Casadei eq. 16), the rotor's inertia only, under the paper's conditions: the firmware's stator
// resistance 10 % below the machine's (Delta R_s = -10 %, Casadei eq. 25), tau = 0.01 s. Bound on
// |estimated - true speed| in steady state (last 0.2 s of each step) and through the transients.
// The braking from 220 rpm to 0 is regenerative at the shaft: the machine takes the rotor's
// kinetic energy as a generator (the integral of T omega over the braking is negative). On the DC
// link it is measured and printed, not asserted: braking at the torque limit on the rotor's own
// inertia takes a few ms, and the copper and device losses at that current exceed the 3.5 J of
// kinetic energy, so the source keeps delivering and the link voltage does not rise (the paper's
// rig, with its unprinted inertia, braked over a longer time).
TEST(ImCasadei, Fig25SensorlessSpeedEstimateFollowsTheSpeed)
{
    PaperRig r({"control.speed_sensor=none", "control.speed_ref_rpm=50", "load.type=inertia", "duration_s=10",
           "firmware.rs_ohm=" + std::to_string(0.9 * PLANT_DEF_IM_RS_OHM)});
    ASSERT_TRUE(r.ok);
    r.magnetise(0.1);
    r.record("fig25", 5);
    const struct {
        double rpm, t_s;
    } steps[] = {{50.0, 0.6}, {220.0, 0.8}, {0.0, 0.8}};
    double worst_all = 0.0, worst_at = 0.0, worst_speed = 0.0;
    std::string line;
    double e_in_brake_start = 0.0, e_in_brake_min = 0.0, vdc_brake_max = 0.0, e_kin_220 = 0.0, e_shaft = 0.0;
    double e_loss_start = 0.0, e_loss_brake = 0.0;
    for (const auto& s : steps) {
        r.refs(DTC_MODE_SPEED, 0.0, s.rpm);
        double worst_ss = 0.0, mean_true = 0.0;
        long k = 0, n_ss = 0;
        const long n = r.periods(s.t_s), n_from = n - r.periods(0.2);
        const bool braking = s.rpm == 0.0;
        if (braking) {
            e_in_brake_start = e_in_brake_min = r.st().e_dc_in_j;
            e_kin_220 = r.st().e_kinetic_j;
            e_loss_start = r.st().e_copper_j + r.st().e_device_j;
        }
        r.run(s.t_s, [&] {
            if (braking) {
                e_in_brake_min = std::fmin(e_in_brake_min, r.st().e_dc_in_j);
                vdc_brake_max = std::fmax(vdc_brake_max, r.st().vdc_v);
                e_shaft += r.st().te_nm * r.st().omega_m_rad_s * r.ts();
                if (r.st().speed_rpm > 1.0) {
                    e_loss_brake = r.st().e_copper_j + r.st().e_device_j - e_loss_start;
                }
            }
            if (++k % 10 != 0) return; // the speed loop's rate
            const double e = std::fabs(r.speed_est_rpm() - r.st().speed_rpm);
            if (e > worst_all) {
                worst_all = e;
                worst_at = r.h->time_s();
                worst_speed = r.st().speed_rpm;
            }
            if (k >= n_from) {
                worst_ss = std::fmax(worst_ss, e);
                mean_true += r.st().speed_rpm;
                ++n_ss;
            }
        });
        mean_true /= static_cast<double>(std::max(n_ss, 1L));
        char b[200];
        std::snprintf(b, sizeof b, "ref %.0f rpm: true mean %.1f rpm, worst |est - true| last 0.2 s %.1f rpm; ", s.rpm,
                      mean_true, worst_ss);
        line += b;
        EXPECT_EQ(r.fault(), "none") << s.rpm;
        EXPECT_NEAR(mean_true, s.rpm, 10.0) << s.rpm;  // the drive holds the speed without a sensor
        EXPECT_LT(worst_ss, 15.0) << s.rpm;             // 1 % of the 1440 rpm rating
    }
    std::printf("MEASURE Fig25 %s worst through the transients %.1f rpm at t = %.3f s (true speed %.1f rpm; the "
                "torque is allowed at %.3f s), fault %s\n", line.c_str(), worst_all, worst_at, worst_speed,
                static_cast<double>(r.cfg.u.im.ref.magn_periods + 64) * r.ts(), r.fault().c_str());
    // Through the transients the estimate lags the true speed by its filter (speed_filter_s,
    // 5 ms) times the acceleration: at the torque limit on this rotor's inertia alone,
    // 79.5 N*m / 0.0131 kg m^2 = 6070 rad/s^2, the 220 rpm are braked away in 4 ms. Bound: that
    // lag, (T_limit / J) tau_filter, plus the steady-state bound.
    const double lag_rpm = r.sc.control.torque_limit_nm / r.sc.motor.j_kgm2 * r.si.speed_filter_s * 30.0 / kPi;
    EXPECT_LT(worst_all, lag_rpm + 15.0);
    // Regenerative braking at the shaft: the machine absorbs the rotor's kinetic energy (within 10 %).
    const double returned = e_in_brake_start - e_in_brake_min;
    std::printf("MEASURE Fig25 braking 220 -> 0 rpm (Delta R_s = -10 %%): shaft energy into the machine %.2f J (the "
                "rotor's kinetic energy %.2f J), copper and device losses until standstill %.2f J, energy returned "
                "to the DC source %.2f J, DC link up to %.2f V (source %.1f V)\n",
                -e_shaft, e_kin_220, e_loss_brake, returned, vdc_brake_max, r.sc.inverter.vdc_v);
    EXPECT_NEAR(-e_shaft, e_kin_220, 0.1 * e_kin_220);
}

// ---- Casadei Fig. 32: flux weakening from standstill to 400 % of the base speed --------------------
// Casadei sec. 12: torque mode (the "gas pedal" T_command = rated), the rotor's inertia only,
// from standstill at rated flux. Above the base speed the torque-comparator monitor (im_fw.h) steps phi_s* down;
// T* = T_command phi_s* / phi_s,rated (Casadei eq. 33), at most k_T phi_s*^2 (eq. 34); the current stays
// nearly constant in the constant-power range. Checked on the firmware's own references (the
// figure's traces 2 and 4) and on the plant's current and speed.
struct Fw {
    double t_end = -1.0, psi_at_end = 0.0, i_lo = 0.0, i_hi = 0.0, i_mean = 0.0, ref_err = 0.0, eq34 = 0.0;
    std::string fault;
};
static Fw flux_weakening_run()
{
    Fw o;
    PaperRig r({"control.flux_weakening=true", "control.rotor_flux_ref_wb=0", "control.mode=torque",
           "control.torque_ref_nm=0", "load.type=inertia", "duration_s=10"});
    if (!r.ok) {
        return o;
    }
    r.magnetise(0.05);
    const double t_cmd = r.sc.motor.rated_torque_nm, base = r.sc.motor.rated_speed_rpm;
    const double psi_rated = r.sc.control.flux_ref_wb, pb = r.b.psi_base_wb / kIqOne;
    const Machine mc(r.sc);
    const double kt = 0.75 * mc.p * mc.m * mc.m / (mc.sigma * mc.lr * mc.ls * mc.ls); // Casadei eq. 31
    r.refs(DTC_MODE_TORQUE, t_cmd, 0.0);
    r.record("fig32", 10);
    double next_mark = 0.25;
    std::string marks;
    double worst_eq34 = -1e9;
    double worst_ref_err = 0.0, i_lo = 1e9, i_hi = 0.0, psi_at_end = 0.0, t_end = -1.0, i_sum = 0.0;
    long k = 0, n_cp = 0, n_i = 0;
    double i_acc = 0.0;
    const long n5 = r.periods(0.005);
    for (; k < r.periods(4.0) && r.fault() == "none"; ++k) {
        r.period();
        const double spd = r.st().speed_rpm;
        i_acc += r.imag();
        if (++n_i == n5) {
            const double i5 = i_acc / static_cast<double>(n5);
            i_acc = 0.0;
            n_i = 0;
            if (spd > 1.5 * base && spd < 4.0 * base) { // constant-power range, 5 ms means
                i_lo = std::fmin(i_lo, i5);
                i_hi = std::fmax(i_hi, i5);
                i_sum += i5;
                ++n_cp;
            }
        }
        if (k % 10 == 0) {
            const app_status_t st = r.status();
            const double psi_ref = st.out.psi_ref_iq * pb;
            const double t_ref = st.out.te_ref_iq / kIqOne * r.b.t_base_nm;
            if (spd > 0.05 * base) { // the torque allowed and the rotor turning: Casadei eqs. 33-34 in force
                const double expect = std::fmin(t_cmd * psi_ref / psi_rated, kt * psi_ref * psi_ref);
                worst_ref_err = std::fmax(worst_ref_err, std::fabs(t_ref - expect) / t_cmd);
                worst_eq34 = std::fmax(worst_eq34, (t_ref - kt * psi_ref * psi_ref) / t_cmd);
                psi_at_end = psi_ref;
            }
            if (spd > next_mark * base) {
                char b[120];
                std::snprintf(b, sizeof b, "%.2fx base at %.3f s: phi_s* %.3f Wb, T* %.1f N*m, |i| %.1f A; ", next_mark,
                              r.h->time_s(), psi_ref, t_ref, r.imag());
                marks += b;
                next_mark += next_mark < 1.0 ? 0.25 : 0.5;
            }
        }
        if (spd >= 4.0 * base) {
            t_end = r.h->time_s();
            break;
        }
    }
    const double i_mean = i_sum / static_cast<double>(std::max(n_cp, 1L));
    std::printf("MEASURE Fig32 400 %% base speed (%.0f rpm) reached at %.3f s (-1 = not within 4 s; speed %.0f rpm), "
                "flux reference there %.3f Wb (rated %.2f), |i| in 150..400 %% base: %.1f..%.1f A (mean %.1f), T* vs "
                "eqs. 33/34 worst %.1f %% of T_command (k_T %.3f N*m/Wb^2), fault %s\n",
                4.0 * base, t_end, r.st().speed_rpm, psi_at_end, psi_rated, i_lo, i_hi, i_mean,
                100.0 * worst_ref_err, kt, r.fault().c_str());
    std::printf("MEASURE Fig32 trajectory: %s\nMEASURE Fig32 T* above eq. 34's limit by at most %.1f %% of T_command\n",
                marks.c_str(), 100.0 * worst_eq34);
    o.t_end = t_end;
    o.psi_at_end = psi_at_end;
    o.i_lo = i_lo;
    o.i_hi = i_hi;
    o.i_mean = i_mean;
    o.ref_err = worst_ref_err;
    o.eq34 = worst_eq34;
    o.fault = r.fault();
    return o;
}

TEST(ImCasadei, Fig32FluxWeakeningTorqueReferenceWithinEq34)
{
    // The flux reference is weakened, T* follows Casadei eq. 33 (T_command phi_s*/phi_s,rated) and never
    // exceeds Casadei eq. 34's k_T phi_s*^2 (k_T from eq. 31 and the plant's machine).
    const Fw o = flux_weakening_run();
    EXPECT_EQ(o.fault, "none");
    EXPECT_LT(o.psi_at_end, 0.55);
    EXPECT_LT(o.eq34, 0.02);
    EXPECT_LT(o.ref_err, 0.02);
}

// Casadei Fig. 32's speed and current: the monitor of the torque comparator (im_fw.h) holds the rated
// flux up to about the base speed (the torque demand is met there) and weakens it above, where
// the back-EMF reaches the voltage limit (Casadei eq. 32); the current is then nearly constant.
TEST(ImCasadei, Fig32FluxWeakeningReaches400PercentWithNearlyConstantCurrent)
{
    const Fw o = flux_weakening_run();
    EXPECT_EQ(o.fault, "none");
    ASSERT_GT(o.t_end, 0.0);
    // nearly constant current in the constant-power range (the paper gives no number): the spread of
    // the 5 ms means was 0.264 with the dead-time error taken on the current's sign at the period's
    // end, 0.301 with the sign at the switching instant (the previous sample, im_dtc_estimate),
    // which the torque accuracy at low speed needs; the bound covers both
    EXPECT_LT((o.i_hi - o.i_lo) / o.i_mean, 0.35);
}

// ---- Fault and input handling of the IM drive ------------------------------------------------------
// Through dtc-sil's run API: an over-current trips to gates off and says so; a DC link outside
// the protection window trips; a bad IM configuration is refused naming the scenario key.
TEST(ImCasadei, FaultsTripTheImDriveAndBadConfigurationIsRefused)
{
    auto run = [](const std::vector<std::string>& sets, RunResult* r, std::string* err) {
        Scenario sc;
        Diagnostics d;
        EXPECT_TRUE(load_scenario(kScenario, sets, &sc, &d)) << d.text();
        return run_scenario(sc, RunOptions{}, r, err);
    };
    // Over-current: a trip set below the magnetising current (about 10 A) stops the drive during
    // the start-up magnetisation. The firmware's own trip, so no hardware comparator; the IM law
    // makes no current prediction and two sensors have no sum, so without the comparator nothing
    // would find a failed sensor: that board needs protection.allow_unsafe.
    {
        RunResult r;
        std::string err;
        ASSERT_TRUE(run({"duration_s=0.3", "metrics_window_s=0.05", "protection.overcurrent_a=5",
                         "protection.hw_trip_current_a=0", "protection.allow_unsafe=true"},
                        &r, &err))
            << err;
        EXPECT_EQ(r.info.fault, "overcurrent");
    }
    // DC link below the window: 180 V on a 200..400 V window.
    {
        RunResult r;
        std::string err;
        ASSERT_TRUE(run({"duration_s=0.05", "metrics_window_s=0.02", "inverter.vdc_v=180"}, &r, &err)) << err;
        EXPECT_EQ(r.info.fault, "dc_undervoltage");
    }
    // A configuration the converter cannot represent (Ts/tau below one Q31 LSB): refused by the
    // scenario check, which runs the converter, before any period; key and origin named.
    {
        Scenario sc;
        Diagnostics d;
        EXPECT_FALSE(load_scenario(kScenario, {"control.observer_tau_s=1e9"}, &sc, &d));
        EXPECT_NE(d.text().find("'control.observer_tau_s=1e9': control.observer_tau_s: tau_lo_s (Ts/tau)"),
                  std::string::npos)
            << d.text();
    }
}

// ---- Secs. 10.3-10.5: stator-flux vector control (SFVC) with SVM at a constant switching frequency --
// Casadei Fig. 18's scheme (control.scheme = "sfvc", firmware/dtc/im_sfvc.c): the stator-flux reference
// vector from T* and phi_r* (Casadei eq. 18), the flux regulator with R_s and back-EMF feed-forward (eqs.
// 23-24), symmetric SVM with dead-time compensation at the carrier 1/ts_s. The phase-A current
// is sampled every 10 us inside the control periods (Harness::set_substeps), with the plant's
// stator-flux angle for a window of whole fundamental periods (sil::whole_period_window), so the
// current's switching ripple is seen, not only its value at the period boundaries.
// Mean switching frequency as Casadei defines it (sec. 13): inverter leg-state changes per second
// / 6, i.e. turn-on events per device per second; for symmetric SVM every leg switches twice per
// carrier period, so it is the carrier (two-phase: 2/3 of it).
struct CurrentRipple {
    double thd_pct = 0.0;      // sil::spectrum thd_pct of i_a: every line but DC and the fundamental
    double f1_hz = 0.0;        // fundamental of the window
    double carrier_frac = 0.0; // share of that ripple energy within +-6 f1 of the multiples of f_c
    double f_sw_hz = 0.0;      // leg-state changes per second / 6
    double te_mean = 0.0;      // plant torque over the window
    double te_ripple = 0.0;    // its rms deviation from the mean
    double clamped_frac = 0.0; // PWM form: share of the periods with a leg held for the whole period
    std::string fault;
};

// Leg-state changes of one period of a command: its changes inside the period plus one at its start
// where the leg's state there differs from the previous period's end. The PWM form's states and
// instants are the harness's own (Harness::pwm_leg_edges, the EV-A rule of hal.h, checked in
// test_hal_host_pwm.cpp); the leg-state form holds each leg for the whole period.
static int leg_changes(const hal_host::Harness& h, const hal_cmd_t& c, const hal_cmd_t& prev)
{
    auto edges = [&h](const hal_cmd_t& cmd, int x) {
        if (cmd.form == HAL_CMD_PWM) {
            return h.pwm_leg_edges(cmd, x);
        }
        const std::uint16_t s[3] = {cmd.sa, cmd.sb, cmd.sc};
        plant_leg_edges_t e{};
        e.state0 = s[x] != 0u ? 1 : 0;
        return e;
    };
    int n = 0;
    for (int x = 0; x < 3; ++x) {
        const plant_leg_edges_t now = edges(c, x), before = edges(prev, x);
        n += now.n + ((before.state0 ^ (before.n & 1)) != now.state0 ? 1 : 0);
    }
    return n;
}

// One run: magnetised at standstill, T* applied, the dynamometer's speed ramped to rpm, 0.3 s to
// settle, then a window of window_s sampled every 10 us. f_c: the carrier for the band share.
static CurrentRipple ripple_run(const std::vector<std::string>& sets, double rpm, double t_nm, double f_c_hz,
                         double window_s = 0.2, const std::string& wave_name = "")
{
    PaperRig r(torque_at_held_speed(sets));
    CurrentRipple o;
    if (!r.ok) {
        return o;
    }
    to_operating_point(r, rpm, t_nm);
    r.run(0.1);
    const int sub = static_cast<int>(std::lround(r.ts() / 10e-6));
    std::vector<double> ia, th;
    double unwrap = 0.0, last = 0.0;
    r.h->set_substeps(sub, [&](const plant_t* p) {
        plant_state_t s;
        plant_get_state(p, &s);
        const double a = std::atan2(s.psi_beta_wb, s.psi_alpha_wb);
        if (!th.empty()) {
            unwrap += std::remainder(a - last, 2.0 * kPi);
        } else {
            unwrap = a;
        }
        last = a;
        ia.push_back(s.i_a);
        th.push_back(unwrap);
    });
    const std::uint16_t t1pr = r.h->hal_pwm_period();
    hal_cmd_t prev = r.h->applied_cmd();
    long changes = 0, n = 0, clamped = 0;
    double ts = 0.0, ts2 = 0.0;
    r.run(window_s, [&] {
        const hal_cmd_t c = r.h->applied_cmd();
        changes += leg_changes(*r.h, c, prev);
        if (c.form == HAL_CMD_PWM) {
            bool any = false;
            for (int x = 0; x < 3; ++x) {
                any = any || c.cmpr_up[x] == 0u || c.cmpr_up[x] > t1pr;
            }
            clamped += any ? 1 : 0;
        }
        prev = c;
        ts += r.st().te_nm;
        ts2 += r.st().te_nm * r.st().te_nm;
        ++n;
    });
    r.h->set_substeps(1, {});
    if (const char* dir = std::getenv("DTC_FIGURE_DIR"); dir && *dir && !wave_name.empty()) {
        // The 10 us phase-A samples for the report's spectra (tools/plot/casadei_report.py).
        if (std::FILE* f = std::fopen((std::string(dir) + "/" + wave_name + ".csv").c_str(), "w")) {
            std::fprintf(f, "dt_s,i_a_a\n");
            for (double v : ia) {
                std::fprintf(f, "%.9g,%.6f\n", r.ts() / sub, v);
            }
            std::fclose(f);
        }
    }
    o.fault = r.fault();
    o.f_sw_hz = static_cast<double>(changes) / (static_cast<double>(n) * r.ts()) / 6.0;
    o.clamped_frac = static_cast<double>(clamped) / static_cast<double>(n);
    o.te_mean = ts / static_cast<double>(n);
    o.te_ripple = std::sqrt(std::fmax(ts2 / static_cast<double>(n) - o.te_mean * o.te_mean, 0.0));
    const Window w = whole_period_window(th, th.size());
    if (w.periods < 2) {
        ADD_FAILURE() << "no whole fundamental periods in the window";
        return o;
    }
    const double dt = r.ts() / sub;
    const double* x = ia.data() + w.begin;
    o.thd_pct = spectrum(x, w.n, w.periods).thd_pct;
    o.f1_hz = w.periods / (static_cast<double>(w.n) * dt);
    // CurrentRipple energy (Parseval): sum x^2 minus the DC and the fundamental's lines; band energy
    // from the DFT bins within +-6 f1 of m f_c, m = 1, 2, ... below the Nyquist rate.
    const std::size_t nn = w.n;
    auto bin = [&](long k) {
        const double dw = -2.0 * kPi * static_cast<double>(k) / static_cast<double>(nn);
        double re = 0.0, im = 0.0, c = 1.0, s = 0.0;
        const double cw = std::cos(dw), sw = std::sin(dw);
        for (std::size_t t = 0; t < nn; ++t) {
            re += x[t] * c;
            im += x[t] * s;
            const double c2 = c * cw - s * sw;
            s = c * sw + s * cw;
            c = c2;
        }
        return re * re + im * im;
    };
    double sum2 = 0.0;
    for (std::size_t t = 0; t < nn; ++t) {
        sum2 += x[t] * x[t];
    }
    const double e_ripple = sum2 - bin(0) / static_cast<double>(nn) - 2.0 * bin(w.periods) / static_cast<double>(nn);
    const double df = 1.0 / (static_cast<double>(nn) * dt);
    const long half = static_cast<long>(6.0 * o.f1_hz / df);
    double e_band = 0.0;
    for (int m = 1; m * f_c_hz + 6.0 * o.f1_hz < 0.5 / dt; ++m) {
        const long kc = std::lround(m * f_c_hz / df);
        for (long k = kc - half; k <= kc + half; ++k) {
            e_band += 2.0 * bin(k) / static_cast<double>(nn);
        }
    }
    o.carrier_frac = e_band / e_ripple;
    return o;
}

static std::vector<std::string> sfvc_sets(double carrier_hz, const char* modulation = "symmetric")
{
    return {"control.scheme=sfvc", "control.carrier_hz=" + std::to_string(carrier_hz),
            std::string("control.modulation=") + modulation};
}

// Sec. 10.5, Casadei Figs. 19-20: the torque follows T* (rated, 26.5 N*m) from a standstill start at the
// rated 1440 rpm and at 144 rpm (10 %); the default carrier (6.25 kHz). At 144 rpm every leg
// switches twice per period (f_sw = the carrier). At 1440 rpm the stator voltage Casadei eq. 24 asks for,
// about w_s |phi_s| with eq. 19's 0.60 Wb at rated torque (phi_r* 0.53 Wb) and 50 Hz, 190 V,
// exceeds the linear range of the 311 V link, V_dc/sqrt3 = 180 V: the SVM clamps the reference
// onto its hexagon in part of the periods (svm.h) and the switching frequency falls below the
// carrier; the torque still follows.
TEST(ImCasadei, Sec10SfvcTorqueFollowsTheReferenceAtRatedAndLowSpeed)
{
    for (double rpm : {1440.0, 144.0}) {
        Rig probe(torque_at_held_speed({"control.scheme=sfvc"}));
        ASSERT_TRUE(probe.ok);
        const double f_c = probe.sc.control.carrier_hz;
        const double tr = probe.sc.motor.rated_torque_nm;
        // a window of at least three fundamental periods (144 rpm: about 7 Hz)
        const CurrentRipple o = ripple_run({"control.scheme=sfvc"}, rpm, tr, f_c, rpm < 500.0 ? 0.6 : 0.2);
        std::printf("MEASURE Sec10 SFVC %.0f rpm: torque %.3f N*m (T* %.1f), rms ripple %.3f N*m, i_a THD %.2f %%, "
                    "f_sw %.0f Hz (carrier %.0f Hz), periods with a clamped leg %.1f %%, fault %s\n",
                    rpm, o.te_mean, tr, o.te_ripple, o.thd_pct, o.f_sw_hz, f_c, 100.0 * o.clamped_frac, o.fault.c_str());
        EXPECT_EQ(o.fault, "none");
        EXPECT_NEAR(o.te_mean, tr, 0.03 * tr) << rpm;
        if (rpm < 500.0) {
            EXPECT_NEAR(o.f_sw_hz, f_c, 0.02 * f_c) << rpm; // symmetric SVM: every leg twice per period
            EXPECT_EQ(o.clamped_frac, 0.0);
        } else {
            EXPECT_LE(o.f_sw_hz, f_c * 1.001);
            EXPECT_GT(o.clamped_frac, 0.0); // the overmodulation the link forces at rated speed and torque
        }
    }
}

// Sec. 10.3: constant switching frequency. At 720 rpm (Casadei Table 5's half speed), rated torque, SFVC
// with symmetric SVM at a 3 kHz carrier against basic DTC (Table 1, 40 us, the default zero bands)
// at the same mean switching frequency (Casadei's definition; the DTC's is measured, about 3.06 kHz
// there, and must be within 5 % of the carrier; zero bands are its highest, the 40 us sampling
// bounds it): the SFVC current's ripple sits at the carrier's multiples and their sidebands (most
// of its energy within +-6 f1 of m f_c), the DTC's does not, and the SFVC current's THD is below
// the DTC's. (At 1440 rpm and rated torque the SFVC needs more than the linear range of the 311 V
// link: Sec10SfvcTorqueFollowsTheReferenceAtRatedAndLowSpeed.)
TEST(ImCasadei, Sec10SfvcSwitchesAtTheCarrierWithLowerThdThanDtc)
{
    const double f_c = 3000.0; // T1PR = 12500 counts
    const double tr = PLANT_DEF_IM_RATED_TORQUE_NM;
    // the speed loop is not used (torque mode); at 333 us per period the default divider's 3.3 ms
    // speed period is too slow for the default 10 Hz speed bandwidth (tools/config refuses it)
    std::vector<std::string> sets = sfvc_sets(f_c);
    sets.push_back("control.speed_loop_divider=5");
    const CurrentRipple s = ripple_run(sets, 720.0, tr, f_c, 0.4);
    const CurrentRipple d = ripple_run({}, 720.0, tr, f_c, 0.4);
    std::printf("MEASURE Sec10 720 rpm rated: SFVC f_sw %.0f Hz, THD %.2f %%, carrier-band share %.3f; DTC f_sw %.0f "
                "Hz, THD %.2f %%, carrier-band share %.3f\n",
                s.f_sw_hz, s.thd_pct, s.carrier_frac, d.f_sw_hz, d.thd_pct, d.carrier_frac);
    EXPECT_EQ(s.fault, "none");
    EXPECT_EQ(d.fault, "none");
    EXPECT_NEAR(s.f_sw_hz, f_c, 0.02 * f_c);
    EXPECT_NEAR(d.f_sw_hz, f_c, 0.05 * f_c);
    EXPECT_GT(s.carrier_frac, 0.8);
    EXPECT_LT(d.carrier_frac, 0.5 * s.carrier_frac);
    EXPECT_LT(s.thd_pct, d.thd_pct);
}

// ---- Sec. 13: the DFOC baseline on the same SVM ----------------------------------------------------
// Direct rotor-flux-oriented control (control.scheme = "dfoc", firmware/dtc/im_dfoc.c): PI
// current regulators in the rotor-flux frame of the same improved estimator, two-phase
// modulation (the key's default for dfoc) at the 160 us cycle of sec. 13. From a standstill
// start (magnetised first) to rated torque at 1440 and 720 rpm: the torque follows T*, the
// plant's rotor flux is held at phi_r* (the d-axis current phi_r*/M), and two-phase SVM switches
// each leg for 2/3 of the carrier periods (Casadei's 2/3 of the carrier), fewer when the link
// forces the overmodulation (1440 rpm, as for the SFVC).
TEST(ImCasadei, Sec13DfocTorqueFollowsWithTwoPhaseModulation)
{
    for (double rpm : {1440.0, 720.0}) {
        Rig probe(torque_at_held_speed({"control.scheme=dfoc"}));
        ASSERT_TRUE(probe.ok);
        EXPECT_EQ(probe.sc.control.modulation, Modulation::TwoPhase);
        const double f_c = probe.sc.control.carrier_hz, tr = probe.sc.motor.rated_torque_nm;
        const double psir_ref = probe.sc.control.rotor_flux_ref_wb;
        PaperRig r(torque_at_held_speed({"control.scheme=dfoc"}));
        ASSERT_TRUE(r.ok);
        to_operating_point(r, rpm, tr);
        r.run(0.1);
        double psir = 0.0;
        long n = 0;
        r.run(0.1, [&] {
            psir += r.psir();
            ++n;
        });
        const CurrentRipple o = ripple_run({"control.scheme=dfoc"}, rpm, tr, f_c);
        std::printf("MEASURE Sec13 DFOC %.0f rpm: torque %.3f N*m (T* %.1f), |phi_r| %.4f Wb (phi_r* %.3f), i_a THD %.2f "
                    "%%, f_sw %.0f Hz (2/3 carrier %.0f Hz), periods with a clamped leg %.1f %%, fault %s\n",
                    rpm, o.te_mean, tr, psir / n, psir_ref, o.thd_pct, o.f_sw_hz, 2.0 / 3.0 * f_c, 100.0 * o.clamped_frac,
                    o.fault.c_str());
        EXPECT_EQ(o.fault, "none");
        EXPECT_NEAR(o.te_mean, tr, 0.03 * tr) << rpm;
        EXPECT_NEAR(psir / n, psir_ref, 0.03 * psir_ref) << rpm;
        if (rpm < 1000.0) {
            EXPECT_NEAR(o.f_sw_hz, 2.0 / 3.0 * f_c, 0.02 * f_c) << rpm;
        } else {
            EXPECT_LE(o.f_sw_hz, 2.0 / 3.0 * f_c * 1.01) << rpm;
        }
    }
}

// ---- Sec. 13, Casadei Figs. 33-34: the current spectra of DFOC and DTC at rated speed and torque ---------
// "the harmonic spectrum of DFOC shows only the harmonic component corresponding to the modulation
// cycle period, whereas with DTC the spectrum shows a series of harmonics with lower values,
// distributed all over the frequency range." Measured as the share of the current's ripple energy
// within +-6 f1 of the multiples of DFOC's carrier (ripple_run, phase A every 10 us), for DFOC
// and for basic DTC (40 us, zero bands) at the paper's point, 1440 rpm and 26.5 N*m, and at
// Casadei Table 5's 720 rpm, where the DFOC stays in its linear range on this 311 V link.
TEST(ImCasadei, Figs33And34DfocSpectrumAtTheCarrierDtcSpread)
{
    Rig probe(torque_at_held_speed({"control.scheme=dfoc"}));
    ASSERT_TRUE(probe.ok);
    const double f_c = probe.sc.control.carrier_hz, tr = probe.sc.motor.rated_torque_nm;
    for (double rpm : {1440.0, 720.0}) {
        const CurrentRipple f = ripple_run({"control.scheme=dfoc"}, rpm, tr, f_c, 0.2, "fig33_dfoc_" + std::to_string(static_cast<int>(rpm)));
        const CurrentRipple d = ripple_run({}, rpm, tr, f_c, 0.2, "fig34_dtc_" + std::to_string(static_cast<int>(rpm)));
        std::printf("MEASURE Figs33-34 %.0f rpm rated torque: share of the ripple energy at the %.0f Hz carrier's "
                    "multiples +-6 f1: DFOC %.3f (THD %.2f %%, f_sw %.0f Hz), DTC %.3f (THD %.2f %%, f_sw %.0f Hz)\n",
                    rpm, f_c, f.carrier_frac, f.thd_pct, f.f_sw_hz, d.carrier_frac, d.thd_pct, d.f_sw_hz);
        EXPECT_EQ(f.fault, "none");
        EXPECT_EQ(d.fault, "none");
        EXPECT_GT(f.carrier_frac, 0.5) << rpm;
        EXPECT_LT(d.carrier_frac, 0.5 * f.carrier_frac) << rpm;
    }
}

// ---- Sec. 13, Casadei Figs. 35-36: torque step at 100 rpm, DTC against DFOC ----------------------
// "using the DTC scheme a better torque response can be achieved in terms of settling time and
// maximum overshoot ... due to the PI regulators in the DFOC scheme". The paper gives no step
// size: 0 -> rated (26.5 N*m) at 100 rpm held by the dynamometer, from a standstill start. On the
// plant torque averaged over 0.48 ms (12 DTC periods, 3 DFOC periods: the switching ripple out):
// the settling time (the last entry into the band around the final mean that holds the scheme's
// own steady ripple, at least +-5 % of T*: DTC's zero-band ripple at 100 rpm leaves its 0.48 ms
// average +-1.4 N*m around the mean for good, which no response time can remove) and the overshoot
// (the largest average above that band, % of T*). Final mean and steady ripple from the last
// 10 ms of a 30 ms record.
struct Settle {
    double settle_ms = -1.0, overshoot_pct = 0.0, rise_ms = -1.0, ripple_ss = 0.0, final_nm = 0.0;
};
// The step response of te (one sample per period ts, the step at sample 0) averaged over avg_s.
static Settle settle_of(const std::vector<double>& te, double ts, double avg_s, double tr)
{
    Settle o;
    const auto n_avg = static_cast<std::size_t>(std::max(1L, std::lround(avg_s / ts)));
    std::vector<double> m; // m[k]: mean of te over the n_avg periods ending with period k
    for (std::size_t k = n_avg; k <= te.size(); ++k) {
        double a = 0.0;
        for (std::size_t j = k - n_avg; j < k; ++j) {
            a += te[j];
        }
        m.push_back(a / static_cast<double>(n_avg));
    }
    const auto n_ss = static_cast<std::size_t>(std::lround(0.01 / ts));
    double fin = 0.0;
    for (std::size_t k = m.size() - n_ss; k < m.size(); ++k) {
        fin += m[k];
    }
    fin /= static_cast<double>(n_ss);
    for (std::size_t k = m.size() - n_ss; k < m.size(); ++k) {
        o.ripple_ss = std::fmax(o.ripple_ss, std::fabs(m[k] - fin));
    }
    const double band = std::fmax(0.05 * tr, o.ripple_ss);
    auto t_ms = [&](std::size_t k) { return static_cast<double>(k + n_avg) * ts * 1e3; };
    for (std::size_t k = 0; k < m.size(); ++k) {
        if (std::fabs(m[k] - fin) > band) {
            o.settle_ms = t_ms(k);
        }
        o.overshoot_pct = std::fmax(o.overshoot_pct, 100.0 * (m[k] - fin - o.ripple_ss) / tr);
        if (o.rise_ms < 0.0 && m[k] >= 0.9 * fin) {
            o.rise_ms = t_ms(k);
        }
    }
    o.final_nm = fin;
    return o;
}

struct Step35 {
    Settle fast, slow; // the plant torque averaged over 0.48 ms and over 2 ms
    std::string fault;
};
static Step35 torque_step_100rpm(const std::vector<std::string>& sets, const std::string& name)
{
    PaperRig r(torque_at_held_speed(sets));
    Step35 o;
    if (!r.ok) {
        return o;
    }
    const double tr = r.sc.motor.rated_torque_nm;
    to_operating_point(r, 100.0, 0.0);
    r.record(name);
    r.run(0.005);
    r.refs(DTC_MODE_TORQUE, tr, 0.0);
    std::vector<double> te;
    r.run(0.03, [&] { te.push_back(r.st().te_nm); });
    o.fast = settle_of(te, r.ts(), 0.48e-3, tr);
    o.slow = settle_of(te, r.ts(), 2e-3, tr);
    o.fault = r.fault();
    return o;
}

TEST(ImCasadei, Figs35And36TorqueStepAt100RpmDtcRisesFasterThanDfoc)
{
    const Step35 dtc = torque_step_100rpm({}, "fig36_dtc"), dfoc = torque_step_100rpm({"control.scheme=dfoc"}, "fig35_dfoc");
    for (const auto* x : {&dtc.fast, &dtc.slow, &dfoc.fast, &dfoc.slow}) {
        std::printf("MEASURE Figs35-36 0 -> 26.5 N*m at 100 rpm, %s, plant torque averaged over %s: rise to 90 %% %.2f ms, "
                    "settling %.2f ms, overshoot %.1f %% (final %.2f N*m, steady ripple +-%.2f N*m)\n",
                    x == &dtc.fast || x == &dtc.slow ? "DTC" : "DFOC", x == &dtc.fast || x == &dfoc.fast ? "0.48 ms" : "2 ms",
                    x->rise_ms, x->settle_ms, x->overshoot_pct, x->final_nm, x->ripple_ss);
    }
    std::printf("MEASURE Figs35-36 faults %s / %s\n", dtc.fault.c_str(), dfoc.fault.c_str());
    EXPECT_EQ(dtc.fault, "none");
    EXPECT_EQ(dfoc.fault, "none");
    ASSERT_GT(dtc.fast.rise_ms, 0.0);
    ASSERT_GT(dfoc.fast.rise_ms, 0.0);
    // The paper's physical reason, the PI regulators' delay, shows in the rise: DTC is quicker.
    EXPECT_LT(dtc.fast.rise_ms, 0.6 * dfoc.fast.rise_ms);
    // Settling: DTC's transient is over within its rise, but its torque keeps a low-frequency
    // wander (the spread spectrum of Casadei Fig. 34: +-1.7 N*m on a 0.48 ms average, measured) whose
    // excursions beyond the +-5 % band set a late "settling" (12.7 ms) on the short average. On a
    // 2 ms average, which removes that wander, DTC settles before DFOC as in the paper.
    EXPECT_LT(dtc.slow.settle_ms, dfoc.slow.settle_ms);
    // Not reproduced (printed; a finding): the overshoot. The DFOC's current PIs are designed
    // from the machine with the zero on the stator pole (K_p = sigma L_s w_c, K_i = R_s w_c,
    // im_dfoc.c), so each current loop is first order: no overshoot. The paper's DFOC overshot
    // (its PI tuning is not printed).
    EXPECT_LT(dfoc.fast.overshoot_pct, 5.0);
    EXPECT_NEAR(dtc.fast.final_nm, PLANT_DEF_IM_RATED_TORQUE_NM, 0.05 * PLANT_DEF_IM_RATED_TORQUE_NM);
    EXPECT_NEAR(dfoc.fast.final_nm, PLANT_DEF_IM_RATED_TORQUE_NM, 0.05 * PLANT_DEF_IM_RATED_TORQUE_NM);
}

// Casadei sec. 13.1's criteria on the step of Figs. 35-36: the same mean switching frequency (the
// basic DTC at zero bands switches at 100 rpm below the DFOC's 2/3 of its 6.25 kHz carrier, so the
// DFOC's carrier is lowered to 3/2 of the DTC's measured frequency, a whole number of timer counts)
// and the DFOC's current loops at the tunings control.dfoc_bw_hz offers (the paper prints none):
// the zero on the stator pole with the derived w_c = 0.2 / Ts, the modulus optimum 1 / (3 Ts) (the
// loop delay 1.5 Ts) and 0.5 / Ts; and both closed-loop poles at the derived w_c with damping 0.7
// (control.dfoc_zeta). With the zero on the stator pole the paper's "maximum overshoot" of the DFOC
// appears only once w_c reaches 0.5 / Ts (phase margin 90 - 1.5 x 0.5 rad = 47 deg), and its
// settling is then as quick as the DTC's (printed; tools/report/casadei_items.py reports it). The
// placed poles reproduce all of the paper's statement: the PI's zero K_i / K_p, near w_c, overshoots
// and the pair's envelope settles later than the DTC.
TEST(ImCasadei, Figs35And36AtEqualSwitchingFrequencyDfocWithPlacedPolesOvershootsAndSettlesLater)
{
    Rig probe(torque_at_held_speed({}));
    ASSERT_TRUE(probe.ok);
    const double tr = probe.sc.motor.rated_torque_nm;
    const CurrentRipple d = ripple_run({}, 100.0, tr, PLANT_DEF_IM_CARRIER_HZ, 0.65); // two periods of 3.3 Hz
    ASSERT_GT(d.f_sw_hz, 0.0);
    ASSERT_LT(d.f_sw_hz, 2.0 / 3.0 * PLANT_DEF_IM_CARRIER_HZ); // the DTC cannot reach the DFOC's
    const double t1pr = std::round(PLANT_DEF_PWM_CLOCK_HZ / (2.0 * 1.5 * d.f_sw_hz));
    const double f_c = PLANT_DEF_PWM_CLOCK_HZ / (2.0 * t1pr), ts_c = 1.0 / f_c;
    char carrier[64];
    std::snprintf(carrier, sizeof carrier, "control.carrier_hz=%.10g", f_c);
    const std::vector<std::string> eq = {"control.scheme=dfoc", carrier, "control.speed_loop_divider=1"};
    const CurrentRipple f = ripple_run(eq, 100.0, tr, f_c, 0.65);
    const Step35 dtc = torque_step_100rpm({}, "fig36_dtc_eq");
    std::printf("MEASURE Figs35-36 equal f_sw: DTC %.0f Hz (zero bands), DFOC %.0f Hz (carrier %.1f Hz); DTC rise %.2f ms, "
                "settling %.2f / %.2f ms, overshoot %.1f %%\n", d.f_sw_hz, f.f_sw_hz, f_c, dtc.fast.rise_ms,
                dtc.fast.settle_ms, dtc.slow.settle_ms, dtc.fast.overshoot_pct);
    EXPECT_NEAR(f.f_sw_hz, d.f_sw_hz, 0.03 * d.f_sw_hz);
    const struct {
        const char* name;
        double wc_ts; // w_c Ts; 0: the derived key value
        double zeta;  // control.dfoc_zeta
    } tunings[] = {{"derived", 0.0, 0.0}, {"modulus optimum", 1.0 / 3.0, 0.0}, {"0.5/Ts", 0.5, 0.0},
                   {"poles at w_c, zeta 0.7", 0.0, 0.7}};
    for (const auto& t : tunings) {
        std::vector<std::string> sets = eq;
        char bw[64];
        std::snprintf(bw, sizeof bw, "control.dfoc_bw_hz=%.10g", t.wc_ts / ts_c / (2.0 * kPi));
        sets.push_back(bw);
        sets.push_back("control.dfoc_zeta=" + std::to_string(t.zeta));
        const Step35 x = torque_step_100rpm(sets, std::string("fig35_dfoc_eq_") +
                                                      (t.wc_ts > 0.0 ? bw + 19 : t.zeta > 0.0 ? "placed" : "derived"));
        std::printf("MEASURE Figs35-36 equal f_sw DFOC %s (w_c Ts %.3f): rise %.2f ms, settling %.2f / %.2f ms (0.48 / 2 ms "
                    "average), overshoot %.1f %%, final %.2f N*m, fault %s\n", t.name, t.wc_ts > 0.0 ? t.wc_ts : 0.2,
                    x.fast.rise_ms, x.fast.settle_ms, x.slow.settle_ms, x.fast.overshoot_pct, x.fast.final_nm, x.fault.c_str());
        EXPECT_EQ(x.fault, "none") << t.name;
        EXPECT_NEAR(x.fast.final_nm, tr, 0.05 * tr) << t.name;
        EXPECT_LT(dtc.fast.rise_ms, x.fast.rise_ms) << t.name; // the PIs delay the DFOC at every tuning
        if (t.wc_ts >= 0.5 || t.zeta > 0.0) {
            // the paper's overshoot: well above the DTC's and above 10 % of T*
            EXPECT_GT(x.fast.overshoot_pct, 10.0) << t.name;
            EXPECT_GT(x.fast.overshoot_pct, 3.0 * dtc.fast.overshoot_pct) << t.name;
        } else {
            EXPECT_LT(x.fast.overshoot_pct, 5.0) << t.name;
        }
        if (t.zeta > 0.0) {
            // placed poles: all three of the paper's statements on the 2 ms average (the DTC's 0.48 ms
            // average wanders, Figs35And36TorqueStepAt100RpmDtcRisesFasterThanDfoc): the DTC rises
            // faster, settles first and overshoots less
            EXPECT_LT(dtc.fast.rise_ms, 0.8 * x.fast.rise_ms);
            EXPECT_LT(dtc.slow.settle_ms, 0.8 * x.slow.settle_ms);
        }
    }
}
