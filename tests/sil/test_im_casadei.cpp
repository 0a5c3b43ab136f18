// test_im_casadei.cpp - the induction-machine drive (Casadei et al. 2006) under the conditions of
// the paper's figures, through the scenario API: tools/scenarios/im_dtc_speed.toml (the default
// IM on its rig: SSTP on 311 V with the plant's device drops and dead time, 40 us, improved
// estimator tau = 0.01 s) with --set overrides, the firmware as dtc-sil runs it
// (make_controller), the plant's true quantities read every period. References that change
// during a run (torque pulses and steps, speed profiles) go through the application's shadow set
// (app_set_refs), as the background loop of the DSP would publish them. Every run starts at
// standstill and magnetises the machine at zero torque (Fig. 17b) before anything else.
//
// Assertions are the papers' statements with a margin, on the plant: never the firmware's own
// estimate where the plant can say. Each test prints a MEASURE line (the figures of the report).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

extern "C" {
#include "app.h"
#include "dtc_config_si.h"
}

#include "controller_adapter.hpp"
#include "hal_host.hpp"
#include "run.hpp"
#include "scenario.hpp"

using namespace sil;

namespace {

const std::string kScenario = std::string(DTC_SOURCE_DIR) + "/tools/scenarios/im_dtc_speed.toml";
constexpr double kIqOne = 16777216.0; // 2^24, iq_t
constexpr double kPi = 3.14159265358979323846;

// One SIL rig from im_dtc_speed.toml plus overrides, stepped period by period.
struct Rig {
    Scenario sc;
    dtc_config_si_t si{};
    dtc_config_t cfg{};
    dtc_bases_t b{};
    std::unique_ptr<hal_host::Harness> h;
    std::unique_ptr<Controller> ctrl;
    bool ok = false;

    explicit Rig(const std::vector<std::string>& sets)
    {
        Diagnostics d;
        if (!load_scenario(kScenario, sets, &sc, &d)) {
            ADD_FAILURE() << d.text();
            return;
        }
        si = firmware_si_config(sc);
        char msg[256] = {0};
        if (dtc_config_from_si(&si, &cfg, msg, sizeof msg) != DTC_SI_OK) {
            ADD_FAILURE() << msg;
            return;
        }
        dtc_bases_from_si(&si, &b);
        std::string err;
        h = hal_host::Harness::create(plant_params_from(sc), harness_config_from(sc), &err);
        if (!h) {
            ADD_FAILURE() << err;
            return;
        }
        h->activate();
        ctrl = make_controller(sc, &err);
        if (!ctrl) {
            ADD_FAILURE() << err;
            return;
        }
        const std::string e = ctrl->init(*h);
        if (!e.empty()) {
            ADD_FAILURE() << e;
            return;
        }
        ok = true;
    }
    ~Rig()
    {
        if (h) {
            h->deactivate();
        }
    }
    double ts() const { return sc.ts_s; }
    long periods(double t_s) const { return static_cast<long>(std::llround(t_s / sc.ts_s)); }
    void period()
    {
        h->run_period([this] { ctrl->step(*h); });
    }
    // Runs t_s, calling f after every period.
    void run(double t_s, const std::function<void()>& f = {})
    {
        for (long k = 0, n = periods(t_s); k < n; ++k) {
            period();
            if (f) {
                f();
            }
        }
    }
    const plant_state_t& st() const { return h->state(); }
    double psir() const { return std::hypot(st().psi_r_alpha_wb, st().psi_r_beta_wb); }
    double psis() const { return std::hypot(st().psi_alpha_wb, st().psi_beta_wb); }
    double imag() const { return std::hypot(st().i_alpha_a, st().i_beta_a); }
    app_status_t status() const
    {
        app_status_t s;
        app_get_status(&s);
        return s;
    }
    std::string fault() const { return ctrl->fault(); }
    iq_t torque_iq(double nm) const { return static_cast<iq_t>(std::lround(nm / b.t_base_nm * kIqOne)); }
    iq_t speed_iq(double rpm) const
    {
        return static_cast<iq_t>(std::lround(rpm * kPi / 30.0 * static_cast<double>(si.pole_pairs) / b.w_base_rad_s * kIqOne));
    }
    double speed_est_rpm() const
    {
        return static_cast<double>(status().out.speed_iq) / kIqOne * b.w_base_rad_s * 30.0 / kPi /
               static_cast<double>(si.pole_pairs);
    }
    // Publishes a new reference set through the shadow (app_set_refs).
    void refs(int mode, double torque_nm, double speed_rpm)
    {
        dtc_refs_t r{};
        r.mode = static_cast<std::uint16_t>(mode);
        r.flux_ref_iq = cfg.speed.flux_ref_iq;
        r.kp_iq = cfg.speed.kp_iq;
        r.ki_ts_iq = cfg.speed.ki_ts_iq;
        r.torque_ref_iq = torque_iq(torque_nm);
        r.speed_ref_iq = speed_iq(speed_rpm);
        EXPECT_EQ(app_set_refs(&r), DTC_OK);
    }
    // Start-up: calibration and the magnetisation at zero torque, then settle_s more.
    void magnetise(double settle_s)
    {
        const double t_magn = static_cast<double>(cfg.speed.im_magn_periods) * ts();
        run(t_magn + 64.0 * ts() + settle_s);
    }
    // Moves the dynamometer's held speed linearly to rpm over t_s.
    void ramp_held_speed(double rpm, double t_s)
    {
        const double from = st().speed_rpm;
        const long n = periods(t_s);
        for (long k = 1; k <= n; ++k) {
            plant_set_load(h->plant(), PLANT_LOAD_SPEED, from + (rpm - from) * static_cast<double>(k) / static_cast<double>(n), 0.0);
            period();
        }
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

// ---- Fig. 17: start-up at zero torque, then a rated torque step --------------------------------
// Casadei sec. 10.2: with a pure integrator the machine cannot be magnetised at zero torque and
// the torque then rises slowly; with the improved estimator (tau = 0.01 s) the phase current
// settles to the magnetising current at zero torque and the torque reaches its reference within
// a few ms. Rotor held at standstill (the dynamometer), torque mode, T* = 0, then rated.
struct StartUp {
    double psir_before = 0.0, i_dc = 0.0, i_drift = 0.0, rise_ms = -1.0, te_worst_magn = 0.0;
    double trip_t = -1.0, psir_at_trip = 0.0, psis_at_trip = 0.0; // first fault: time, plant fluxes
    std::string fault;
};
static StartUp start_up(const std::string& estimator, std::vector<std::string> extra = {})
{
    std::vector<std::string> sets = {"control.mode=torque", "control.torque_ref_nm=0", "load.type=speed",
                                     "load.speed_rpm=0", "control.estimator=" + estimator, "duration_s=2"};
    sets.insert(sets.end(), extra.begin(), extra.end());
    Rig r(sets);
    StartUp o;
    if (!r.ok) {
        return o;
    }
    const double t_magn = static_cast<double>(r.cfg.speed.im_magn_periods) * r.ts();
    r.run(64.0 * r.ts() + t_magn, [&] {
        o.te_worst_magn = std::fmax(o.te_worst_magn, std::fabs(r.st().te_nm));
        if (o.trip_t < 0.0 && r.fault() != "none") {
            o.trip_t = r.h->time_s();
            o.psir_at_trip = r.psir();
            o.psis_at_trip = r.psis();
        }
    });
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
    const StartUp vol_hi = start_up("voltage", {"sensors.current_range_a=1000", "protection.overcurrent_a=900",
                                                "protection.hw_trip_current_a=0"});
    std::printf("MEASURE Fig17 voltage, no trip: DC current %.2f A (spread %.2f %%), rotor flux %.3f Wb, rise %.2f ms, fault %s\n",
                vol_hi.i_dc, 100.0 * vol_hi.i_drift, vol_hi.psir_before, vol_hi.rise_ms, vol_hi.fault.c_str());
    std::printf("MEASURE Fig17 improved: DC current %.2f A (5 ms means spread %.2f %%), rotor flux %.3f Wb, max |T| "
                "while magnetising %.2f N*m, rise to 90 %% rated %.2f ms, fault %s\n",
                imp.i_dc, 100.0 * imp.i_drift, imp.psir_before, imp.te_worst_magn, imp.rise_ms, imp.fault.c_str());
    std::printf("MEASURE Fig17 voltage: fault %s at %.4f s, plant stator flux then %.3f Wb, rotor flux %.3f Wb\n",
                vol.fault.c_str(), vol.trip_t, vol.psis_at_trip, vol.psir_at_trip);
    // Improved estimator: a steady DC current vector, the machine's magnetising current (plant
    // rotor flux / M), the rotor flux at its reference within 10 % (measured 8 % low: the residual
    // voltage error at DC, docs/firmware-core.md), no torque; then the rated torque within 5 ms.
    const double psir_ref = 0.53; // im_dtc_speed.toml control.rotor_flux_ref_wb
    EXPECT_EQ(imp.fault, "none");
    EXPECT_NEAR(imp.i_dc, imp.psir_before / PLANT_DEF_IM_LM_H, 0.05 * imp.i_dc);
    EXPECT_LT(imp.i_drift, 0.05);
    EXPECT_LT(imp.te_worst_magn, 0.05 * PLANT_DEF_IM_RATED_TORQUE_NM);
    EXPECT_NEAR(imp.psir_before, psir_ref, 0.10 * psir_ref);
    ASSERT_GT(imp.rise_ms, 0.0);
    EXPECT_LE(imp.rise_ms, 5.0);
    // Voltage model (Casadei eq. 1, a low-pass for the integrator), Fig. 17a. On the rig's trips
    // it stops on over-current in the start-up current peak (the finding of im_dtc_speed.toml,
    // printed above, not asserted). With the trips out of the way (sensors and trip at 1 kA) the
    // estimator's own behaviour shows: the DC flux it is asked to hold decays out of its estimate
    // (5 rad/s low-pass), so the machine is not magnetised at zero torque (rotor flux below 80 %
    // of the reference, the current not a steady DC) and the torque then rises far slower than
    // with the improved estimator (not at 90 % of rated within 10x its rise time).
    EXPECT_EQ(vol_hi.fault, "none");
    EXPECT_LT(vol_hi.psir_before, 0.8 * psir_ref);
    EXPECT_GT(vol_hi.i_drift, 0.05);
    EXPECT_TRUE(vol_hi.rise_ms < 0.0 || vol_hi.rise_ms > 10.0 * imp.rise_ms) << vol_hi.rise_ms;
}
