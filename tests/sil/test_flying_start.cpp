// test_flying_start.cpp - starting into a turning rotor (flying start), PM drive: every shipped PM
// scenario started at 0, 50 % and 100 % of its speed reference reaches the reference with no trip,
// and the rotor hold of the FSTP mid-point calibration (app_hold.h) never engages on a rotor that
// turns.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <dirent.h>
#include <string>
#include <vector>

#include "run.hpp"
#include "scenario.hpp"
#include "scenario_outcome.hpp"

using namespace sil;

namespace {

// The shipped scenarios of a PM machine in speed mode (tools/scenarios/*.toml), by file name.
std::vector<std::string> pm_speed_scenarios()
{
    std::vector<std::string> out;
    DIR* d = opendir(sil_test::scenarios_dir().c_str());
    if (d == nullptr) {
        return out;
    }
    for (const dirent* e = readdir(d); e != nullptr; e = readdir(d)) {
        const std::string f = e->d_name;
        if (f.size() < 5 || f.compare(f.size() - 5, 5, ".toml") != 0) {
            continue;
        }
        Scenario sc;
        Diagnostics diag;
        if (!load_scenario(sil_test::scenarios_dir() + f, {}, &sc, &diag)) {
            ADD_FAILURE() << f << ": " << diag.text();
            continue;
        }
        if (sc.motor.type == MotorType::Pmsm && sc.control.mode == ControlMode::Speed &&
            sc.control.implementation == Implementation::Firmware) {
            out.push_back(f);
        }
    }
    closedir(d);
    std::sort(out.begin(), out.end());
    return out;
}

} // namespace

TEST(FlyingStart, EveryShippedPmScenarioStartsAtRestHalfAndFullSpeedReference)
{
    // Issue target: every shipped PM scenario (both topologies, every estimator) started at 0, 50 %
    // and 100 % of its speed reference reaches it with no trip; the rotor hold never engages on a
    // turning rotor. Reached: mean speed over the metrics window within 1 % of the reference
    // (measured 1499.7-1500.0 rpm at 750 and 1500 rpm). The hold: on the FSTP with the mid-point
    // calibrated the gates stay off for the whole 2^10-period calibration when the rotor turns
    // (the hold on a rotor at 1000 rpm tripped on a phase-B over-current within 33 periods), so
    // the plant's phase currents stay zero there: the line back-EMF at 1500 rpm (sqrt(3) psi_m w,
    // 25 V for Hoang Table VIII) is below V_dc/2 = 35 V, no diode conducts.
    const std::vector<std::string> files = pm_speed_scenarios();
    ASSERT_GE(files.size(), 18u); // 13 FSTP, 5 SSTP
    for (const std::string& f : files) {
        Scenario sc;
        Diagnostics diag;
        ASSERT_TRUE(load_scenario(sil_test::scenarios_dir() + f, {}, &sc, &diag)) << diag.text();
        const double ref = sc.control.speed_ref_rpm;
        // the mid-point calibration (and its hold) runs on the FSTP's voltage model with the
        // mid-point measured (dtc_config_si.c board.vmid_cal)
        const bool hold = sc.inverter.topology == Topology::Fstp && sc.control.estimator == Estimator::Voltage &&
                          sc.sensors.vmid_fitted && sc.control.vmid_cal && sc.control.cal_hold;
        for (double frac : {0.0, 0.5, 1.0}) {
            const std::string what = f + " from " + std::to_string(frac * ref) + " rpm";
            const sil_test::Outcome o =
                sil_test::run_shipped(f, {"initial_speed_rpm=" + std::to_string(frac * ref)});
            ASSERT_EQ(o.info.fault, "none") << what;
            EXPECT_NEAR(o.m.speed_mean_rpm, ref, 0.01 * ref) << what;
            if (!hold || frac == 0.0) {
                continue;
            }
            // the calibration's first 50 ms (of 51.2) recorded whole: the metrics window keeps the series
            const sil_test::Outcome c = sil_test::run_shipped(
                f, {"initial_speed_rpm=" + std::to_string(frac * ref), "duration_s=0.05", "metrics_window_s=0.05"});
            ASSERT_EQ(c.info.fault, "none") << what;
            ASSERT_EQ(c.series.en.size(), c.series.size()) << what;
            ASSERT_GE(c.series.size(), 1000u) << what;
            double i_max = 0.0;
            for (std::size_t k = 0; k < c.series.size(); ++k) {
                i_max = std::max({i_max, std::fabs(c.series.ia[k]), std::fabs(c.series.ib[k]),
                                  std::fabs(c.series.ic[k])});
                ASSERT_EQ(c.series.en[k], 0u) << what << ": gates on at period " << k;
            }
            EXPECT_LT(i_max, 0.01) << what;
        }
    }
}

TEST(FlyingStart, HoldStillEngagesOnARotorAnActiveLoadStartsDuringTheOffsetWindow)
{
    // The rest test (app_hold.h APP_HOLD_REST_COUNTS) measures the speed the rotor had when the
    // calibration began, whatever the load accelerates it by: an active 0.3 N*m on J = 5e-4 from
    // rest (600 rad/s^2, 4 counts in the 3.2 ms window) is still held (gates on during the
    // calibration, speed within 30 rpm, as ActiveLoadIsHeldWhileTheMidPointIsCalibrated), and a
    // rotor turning backwards at -287 rpm under the same load is not held (gates off throughout).
    const std::vector<std::string> base = {"load.type=torque", "load.torque_nm=0.3", "duration_s=0.05",
                                           "metrics_window_s=0.05"};
    const sil_test::Outcome held = sil_test::run_shipped("fstp_voltage_proposed_full.toml", base);
    ASSERT_EQ(held.info.fault, "none");
    ASSERT_FALSE(held.series.en.empty());
    std::size_t on = 0;
    for (std::size_t k = 0; k < held.series.size(); ++k) {
        on += held.series.en[k];
        ASSERT_LT(std::fabs(held.series.speed_rpm[k]), 30.0);
    }
    EXPECT_GT(on, 900u); // periods 64..1023 of the calibration
    std::vector<std::string> turning = base;
    turning.push_back("initial_speed_rpm=-287");
    const sil_test::Outcome free = sil_test::run_shipped("fstp_voltage_proposed_full.toml", turning);
    ASSERT_EQ(free.info.fault, "none");
    for (std::size_t k = 0; k < free.series.size(); ++k) {
        ASSERT_EQ(free.series.en[k], 0u) << "gates on at period " << k;
    }
}
