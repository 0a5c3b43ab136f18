// test_im_casadei_runs.cpp - Casadei's figures measured through whole scenario runs (run_scenario,
// as dtc-sil runs them): Casadei Fig. 21, Figs. 6-7, Figs. 19-20.
//
// Casadei Fig. 21 (sec. 10.7) in the SIL: the sensorless stator-flux vector
// control with the improved estimator (control.scheme = "sfvc", tools/scenarios/im_dtc_speed.toml:
// the default IM on its rig) at a slip of 5 rad/s (Casadei Fig. 21's), speed held by the dynamometer,
// against the linearised model of eqs. 26-28 (tools/config/im_tau_check.h, computed here from the
// scenario's machine). Every run starts at standstill, magnetises at zero torque, takes the
// torque, and the dynamometer then takes the rotor to the point's speed (0.6 s to 0.9 s).
//
// Points: four regenerating speeds at low stator frequency (w_s = -40, -30, -20, -10 rad/s, the
// rotor turning against the torque), each with a tau the map calls stable and one it calls
// unstable, and one motoring point with the shortest tau. Only points at least 1.5 1/s from the
// map's boundary are asserted; a point closer to it is measured and printed.
//
// The plant's devices are ideal conductors here (inverter.drops = false, no compensation): eqs.
// 26-28 are linearised "without parameter mismatch", and the drops' voltage error, which the
// simple compensation leaves at low speed, moves the drive off the map's operating point. With
// the drops, the points w_s = -30 rad/s, tau = 2 ms and w_s = -10 rad/s, tau = 10 ms, stable on
// the map, lose their flux as well (the MEASURE line "with the drops" prints both).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

extern "C" {
#include "im_tau_check.h"
}

#include "run.hpp"
#include "scenario.hpp"

using namespace sil;

namespace {

const std::string kScenario = std::string(DTC_SOURCE_DIR) + "/tools/scenarios/im_dtc_speed.toml";
const std::string kScenario2 = std::string(DTC_SOURCE_DIR) + "/tools/scenarios/im_second_machine.toml";
constexpr double kPi = 3.14159265358979323846;
constexpr double kSlip = 5.0;   // rad/s, Casadei Fig. 21
constexpr double kWindowS = 2.0; // from 1.1 s (the held speed reached at 0.9 s) to the end

struct Point {
    double ws;  // estimated stator frequency, rad/s electrical
    double tau; // s
};

struct Outcome {
    double re = 0.0;       // the map's dominant real part, 1/s
    double rpm = 0.0;      // held speed
    double torque = 0.0;   // T* for the slip
    double te_mean = 0.0;  // plant torque over the window's last second
    double spread = 0.0;   // (max - min) of the plant's |phi_s| over the window / its first value
    std::string fault;
    bool ok = false;
};

// One run from standstill in torque mode, the dynamometer taking the rotor to rpm after the
// magnetisation (0.6 s to 0.9 s), then 0.2 s of settling and the metrics window. The paper's
// estimator, as in its figures: Casadei eq. 20's reference phi_r* e^{j theta} at every speed
// (control.current_model_ref = false; the product's default with the encoder pulls it towards a
// rotor-flux current model at low speed, firmware/dtc/im_sup.h, which the paper does not).
bool held_run(const std::string& scenario, double rpm, double torque, double window_s, std::vector<std::string> extra,
              RunResult* res)
{
    std::vector<std::string> sets = {"control.current_model_ref=false",
                                     "control.mode=torque", "control.torque_ref_nm=" + std::to_string(torque),
                                     "load.type=speed", "load.speed_rpm=" + std::to_string(rpm),
                                     "load.speed_ramp_start_s=0.6", "load.speed_ramp_s=0.3", "load.step_time_s=0",
                                     "metrics_window_s=" + std::to_string(window_s),
                                     "duration_s=" + std::to_string(1.1 + window_s)};
    sets.insert(sets.end(), extra.begin(), extra.end());
    Scenario sc;
    Diagnostics d;
    if (!load_scenario(scenario, sets, &sc, &d)) {
        ADD_FAILURE() << d.text();
        return false;
    }
    RunOptions opt;
    opt.write_trace = false;
    std::string err;
    if (!run_scenario(sc, opt, res, &err)) {
        ADD_FAILURE() << err;
        return false;
    }
    return true;
}

Scenario scenario_of(const std::string& path)
{
    Scenario sc;
    Diagnostics d;
    EXPECT_TRUE(load_scenario(path, {}, &sc, &d)) << d.text();
    return sc;
}

Outcome run_point(const Point& p, bool ideal_devices)
{
    Outcome o;
    const Scenario probe = scenario_of(kScenario);
    const MotorCfg& m = probe.motor;
    const im_lin_machine_t mach = {m.rr_ohm, m.lls_h, m.llr_h, m.lm_h};
    const double psir = probe.control.rotor_flux_ref_wb;
    const double pp = static_cast<double>(m.pole_pairs);
    // Casadei eq. 16 at constant rotor flux: T = 3/2 p phi_r^2 w_sl / R_r (amplitude-invariant)
    o.torque = 1.5 * pp * psir * psir * kSlip / m.rr_ohm;
    const double w0 = p.ws - kSlip;
    o.rpm = w0 * 30.0 / kPi / pp;
    o.re = im_lin_dominant_re(&mach, w0, kSlip, p.tau);
    std::vector<std::string> extra = {"control.scheme=sfvc", "control.observer_tau_s=" + std::to_string(p.tau)};
    if (ideal_devices) {
        extra.push_back("inverter.drops=false");
        extra.push_back("control.compensation=none");
    }
    RunResult res;
    if (!held_run(kScenario, o.rpm, o.torque, kWindowS, extra, &res)) {
        return o;
    }
    const Series& s = res.series;
    const std::size_t n = s.size();
    if (n < 10) {
        ADD_FAILURE() << "no window";
        return o;
    }
    double lo = 1e9, hi = 0.0, sum = 0.0;
    const double first = std::hypot(s.psi_a[0], s.psi_b[0]);
    std::size_t k = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double psi = std::hypot(s.psi_a[i], s.psi_b[i]);
        lo = std::min(lo, psi);
        hi = std::max(hi, psi);
        if (i >= n / 2) {
            sum += s.te[i];
            ++k;
        }
    }
    o.spread = (hi - lo) / first;
    o.te_mean = sum / static_cast<double>(k);
    o.fault = res.info.fault;
    o.ok = true;
    return o;
}

void print(const char* what, const Point& p, const Outcome& o)
{
    std::printf("MEASURE Fig21 %s: w_s %+.0f rad/s (%.1f rpm, T* %.2f N*m), tau %g s: map Re %+.2f 1/s; SIL |phi_s| "
                "spread %.1f %%, torque %.2f N*m, fault %s\n",
                what, p.ws, o.rpm, o.torque, p.tau, o.re, 100.0 * o.spread, o.te_mean, o.fault.c_str());
}

} // namespace

TEST(ImCasadeiRuns, Fig21MapStablePointsHoldUnstablePointsLoseTheOperatingPoint)
{
    const std::vector<Point> points = {{-40.0, 0.003}, {-40.0, 0.0005}, {-30.0, 0.002}, {-30.0, 0.001},
                                       {-20.0, 0.01},  {-20.0, 0.001},  {-10.0, 0.01},  {-10.0, 0.002},
                                       {20.0, 0.001}};
    int stable = 0, unstable = 0;
    for (const Point& p : points) {
        const Outcome o = run_point(p, true);
        ASSERT_TRUE(o.ok);
        print("ideal devices", p, o);
        ASSERT_GE(std::fabs(o.re), 1.5) << "a point too close to the map's boundary to assert";
        if (o.re < 0.0) {
            // stable: the flux held (|phi_s| within 5 %), the torque at T* within 5 %
            ++stable;
            EXPECT_EQ(o.fault, "none") << p.ws << " " << p.tau;
            EXPECT_LT(o.spread, 0.05) << p.ws << " " << p.tau;
            EXPECT_NEAR(o.te_mean, o.torque, 0.05 * o.torque) << p.ws << " " << p.tau;
        } else {
            // unstable: the flux leaves the operating point (swings by more than 30 %) or the drive trips
            ++unstable;
            EXPECT_TRUE(o.spread > 0.3 || o.fault != "none") << p.ws << " " << p.tau << " spread " << o.spread;
        }
    }
    EXPECT_GE(stable, 3);
    EXPECT_GE(unstable, 3);
    // Measured, not asserted: a point 1.07 1/s inside the unstable region (w_s = -5 rad/s, tau =
    // 5 ms), and the two stable points that the device drops push off the operating point.
    print("near the boundary, ideal devices", {-5.0, 0.005}, run_point({-5.0, 0.005}, true));
    for (const Point& p : {Point{-30.0, 0.002}, Point{-10.0, 0.01}}) {
        print("with the drops", p, run_point(p, false));
    }
}


// ---- Casadei Figs. 6-7: THD and switching frequency against the two hysteresis bands, ST-A --------
// Casadei sec. 7: the flux band mainly sets the stator current's THD (a significant increase when
// enlarging it), the torque band mainly the switching frequency. Both bands at 0 and at a wide
// value (flux 10 % of phi_s*, torque 20 % of rated), ST-A at rated torque and half the rated
// speed, on the default IM and on the second machine (tools/scenarios/im_second_machine.toml):
// narrowing either band lowers the THD and raises the switching frequency, and each band moves
// "its" quantity more than the other band does (the flux band the THD by far, the torque band the
// switching frequency by a smaller margin).
TEST(ImCasadeiRuns, Figs6And7NarrowerBandsLowerThdAndRaiseTheSwitchingFrequency)
{
    for (const std::string& path : {kScenario, kScenario2}) {
        const Scenario sc = scenario_of(path);
        const double rated = sc.motor.rated_torque_nm, flux = sc.control.flux_ref_wb;
        double thd[2][2], fsw[2][2];
        for (int i = 0; i < 2; ++i) {
            for (int j = 0; j < 2; ++j) {
                RunResult r;
                ASSERT_TRUE(held_run(path, 0.5 * sc.motor.rated_speed_rpm, rated, 0.2,
                                     {"control.table=st-a", "control.flux_band_wb=" + std::to_string(0.10 * flux * i),
                                      "control.torque_band_nm=" + std::to_string(0.20 * rated * j)},
                                     &r));
                ASSERT_EQ(r.info.fault, "none") << path;
                ASSERT_TRUE(r.metrics.thd_total_pct.has_value()) << path;
                thd[i][j] = *r.metrics.thd_total_pct;
                fsw[i][j] = r.metrics.switching_freq_hz.value_or(0.0);
            }
        }
        std::printf("MEASURE Figs6-7 %s: THD %% [flux band 0 / 10 %%][torque band 0 / 20 %%] = %.1f %.1f / %.1f %.1f; "
                    "f_sw Hz = %.0f %.0f / %.0f %.0f\n",
                    path.substr(path.rfind('/') + 1).c_str(), thd[0][0], thd[0][1], thd[1][0], thd[1][1], fsw[0][0],
                    fsw[0][1], fsw[1][0], fsw[1][1]);
        for (int k = 0; k < 2; ++k) {
            // narrower flux band (i = 0 against 1) and narrower torque band (j = 0 against 1): lower
            // THD by at least 2 % of its value, higher f_sw by at least 5 %
            EXPECT_LT(thd[0][k], 0.98 * thd[1][k]) << path;
            EXPECT_LT(thd[k][0], 0.98 * thd[k][1]) << path;
            EXPECT_GT(fsw[0][k], 1.05 * fsw[1][k]) << path;
            EXPECT_GT(fsw[k][0], 1.05 * fsw[k][1]) << path;
        }
        EXPECT_GT(thd[1][0] - thd[0][0], 2.0 * (thd[0][1] - thd[0][0])) << path; // flux band: mainly THD
        // torque band: mainly f_sw, less markedly (measured 762 Hz against 574 Hz on the default IM over
        // these ranges; the ranges of the paper's axes are not printed)
        EXPECT_GT(fsw[0][0] - fsw[0][1], 1.1 * (fsw[0][0] - fsw[1][0])) << path;
    }
}

// ---- Casadei Figs. 19-20: SFVC locked rotor and 1120 rpm at rated current -------------------------
// Casadei sec. 10.5: the current practically sinusoidal, the estimated torque matching the measured
// and the reference. Rated torque (26.5 N*m) with the rotor held at 0 (Casadei Fig. 19; a window of 1 s,
// the slip frequency's 2.4 Hz) and at 1120 rpm (Casadei Fig. 20, where rated torque takes the rated
// current): the plant's mean torque within 5 % of T*, the firmware's estimate within 5 % of the
// plant's (measured 2.8 % at standstill: the device drops' voltage residual at 2.4 Hz; 0.03 % at
// 1120 rpm), the current's THD below 3 % and the current magnitude within 10 % of rated.
TEST(ImCasadeiRuns, Figs19And20SfvcLockedRotorAnd1120RpmEstimatedTorqueMatchesThePlant)
{
    const Scenario sc = scenario_of(kScenario);
    const double rated = sc.motor.rated_torque_nm;
    for (double rpm : {0.0, 1120.0}) {
        RunResult r;
        const double window = rpm == 0.0 ? 1.0 : 0.4;
        ASSERT_TRUE(held_run(kScenario, rpm, rated, window, {"control.scheme=sfvc"}, &r));
        const Series& s = r.series;
        ASSERT_FALSE(s.te_est.empty());
        double te = 0.0, est = 0.0, imag = 0.0;
        for (std::size_t i = 0; i < s.size(); ++i) {
            te += s.te[i];
            est += s.te_est[i];
            // amplitude-invariant Clarke of the three phase currents
            const double ia = s.ia[i], ib = (s.ib[i] - s.ic[i]) / std::sqrt(3.0);
            imag += std::hypot(ia, ib);
        }
        const double n = static_cast<double>(s.size());
        te /= n;
        est /= n;
        imag /= n;
        const double thd = r.metrics.thd_total_pct.value_or(1e9);
        std::printf("MEASURE Figs19-20 SFVC %.0f rpm, T* %.1f N*m: plant %.2f N*m, estimated %.2f N*m (%+.2f %%), |i_s| "
                    "%.1f A (rated %.1f), THD %.2f %%, f_sw %.0f Hz, fault %s\n",
                    rpm, rated, te, est, 100.0 * (est / te - 1.0), imag, sc.motor.rated_current_a, thd,
                    r.metrics.switching_freq_hz.value_or(0.0), r.info.fault.c_str());
        EXPECT_EQ(r.info.fault, "none");
        EXPECT_NEAR(te, rated, 0.05 * rated) << rpm;
        EXPECT_NEAR(est, te, 0.05 * te) << rpm;
        EXPECT_LT(thd, 3.0) << rpm;
        EXPECT_NEAR(imag, sc.motor.rated_current_a, 0.10 * sc.motor.rated_current_a) << rpm;
    }
}
