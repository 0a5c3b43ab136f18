// Closed-loop SIL tests: the fixed-point firmware + hal_host + the plant.
//
// Assertions are envelopes over the metrics window (never single samples) and the orderings
// Hoang 2011 reports for physical reasons. Thresholds marked "measured:" are measured values
// with a margin; README.md compares them with Hoang Tables IX/X.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "controller_adapter.hpp"
#include "run.hpp"
#include "trace_csv.hpp"

namespace fs = std::filesystem;
using namespace sil;

namespace {
const std::string kScenarios = std::string(DTC_SOURCE_DIR) + "/tools/scenarios/";

struct Outcome {
    Metrics m;
    RunInfo info;
    Series series;
};

Outcome run(const std::string& file, const std::vector<std::string>& sets = {}, const std::string& out_dir = "")
{
    Scenario sc;
    Diagnostics d;
    EXPECT_TRUE(load_scenario(kScenarios + file, sets, &sc, &d)) << d.text();
    RunOptions opt;
    opt.out_dir = out_dir;
    RunResult r;
    std::string err;
    EXPECT_TRUE(run_scenario(sc, opt, &r, &err)) << err;
    return Outcome{r.metrics, r.info, r.series};
}

// trace.csv as columns.
using sil_test::read_trace;

fs::path tmp(const std::string& name)
{
    const fs::path p = fs::temp_directory_path() / ("dtc_sil_closed_" + name);
    fs::remove_all(p);
    return p;
}
} // namespace

TEST(SilClosedLoop, SpeedModeSettlesWithinOnePercentAtFullLoadAndStaysThere)
{
    // From standstill: 1500 rpm, 0.3 N*m total load. The speed averaged over each electrical
    // period (40 ms at 25 Hz) stays within 1 % over the whole 0.4 s window; the instantaneous
    // speed, which carries the torque ripple through the inertia, within 2 %.
    // Trial run (app + dtc branches, plant branch, 2026-11-22): period means within 0.5 %,
    // instantaneous 1479..1510 rpm (1.4 %).
    const Outcome o = run("fstp_current_full.toml", {"initial_speed_rpm=0"});
    EXPECT_EQ(o.info.fault, "none");
    const auto& v = o.series.speed_rpm;
    ASSERT_GT(v.size(), 1600u);
    const std::size_t per = 800; // samples per electrical period at 1500 rpm, p = 1
    for (std::size_t b = v.size() % per; b + per <= v.size(); b += per) {
        double mean = 0.0;
        for (std::size_t k = b; k < b + per; ++k) {
            mean += v[k];
        }
        mean /= static_cast<double>(per);
        EXPECT_NEAR(mean, 1500.0, 15.0) << "period starting at sample " << b;
    }
    const auto mm = std::minmax_element(v.begin(), v.end());
    EXPECT_GT(*mm.first, 1500.0 * 0.98);
    EXPECT_LT(*mm.second, 1500.0 * 1.02);
    EXPECT_NEAR(o.m.torque_mean_nm, 0.3, 0.01); // the load it carries: friction + generator
}

TEST(SilClosedLoop, TorqueModeTracksTheReference)
{
    // Dynamometer holds 1500 rpm; torque reference 0.3 N*m: mean plant torque within 2 %.
    for (const char* topo : {"sstp", "fstp"}) {
        const Outcome o = run("fstp_current_full.toml", {std::string("inverter.topology=") + topo, "control.mode=torque",
                                                         "control.torque_ref_nm=0.3", "load.type=speed"});
        EXPECT_EQ(o.info.fault, "none") << topo;
        EXPECT_NEAR(o.m.torque_mean_nm, 0.3, 0.02 * 0.3) << topo;
    }
}

TEST(SilClosedLoop, HoangFindingsFstpVoltageModelImbalanceOrdering)
{
    // Hoang Tables IX/X: FSTP voltage model without compensation -> the largest imbalance and an
    // estimated torque above the true torque; simple -> smaller; proposed -> the smallest, close
    // to the current model's; current model balanced. Stiff split link (see the scenarios).
    // Measured (firmware, 1.5 s runs, 0.4 s window), paper values in brackets:
    //   imbalance %     none 61.1 [26.6]  simple 30.0 [6.8]  proposed 16.8 [4.6]  current 2.7 [3.4]
    //   est. torque N*m none 0.334 [0.3345] simple 0.307 [0.3046] proposed 0.302 [0.2989]
    //                   current 0.300 [0.2973], true torque 0.300 in every run
    //   none: phase B carries the smallest fundamental, 2.04 A vs 2.95 / 3.28 [2.37 vs 2.97 / 3.00].
    // The thresholds below keep a margin of about a third around those figures.
    const Outcome none = run("fstp_voltage_none_full.toml");
    const Outcome simple = run("fstp_voltage_simple_full.toml");
    const Outcome proposed = run("fstp_voltage_proposed_full.toml");
    const Outcome current = run("fstp_current_full.toml");
    for (const Outcome* o : {&none, &simple, &proposed, &current}) {
        ASSERT_TRUE(o->m.imbalance_pct.has_value()) << o->info.fault;
        ASSERT_TRUE(o->m.torque_est_mean_nm.has_value());
        EXPECT_EQ(o->info.fault, "none");
        EXPECT_NEAR(o->m.torque_mean_nm, 0.3, 0.006); // the speed loop holds the load in every case
    }
    // Imbalance ordering and levels.
    EXPECT_GT(*none.m.imbalance_pct, 40.0);
    EXPECT_GT(*none.m.imbalance_pct, *simple.m.imbalance_pct + 15.0);
    EXPECT_GT(*simple.m.imbalance_pct, *proposed.m.imbalance_pct + 5.0);
    EXPECT_GT(*proposed.m.imbalance_pct, *current.m.imbalance_pct);
    EXPECT_LT(*proposed.m.imbalance_pct, 25.0);
    EXPECT_LT(*current.m.imbalance_pct, 5.0);
    // Without compensation the mid-point phase's neighbour B is the smallest (Hoang Table IX).
    const auto& fn = *none.m.fundamental_a;
    EXPECT_LT(fn[1], fn[0]);
    EXPECT_LT(fn[1], fn[2]);
    // Estimated torque: the uncompensated estimate is ~11 % high (paper 11.5 %), the compensation
    // removes most of it, the current model none of consequence.
    const double t = 0.3;
    EXPECT_GT(*none.m.torque_est_mean_nm, t * 1.08);
    EXPECT_GT(*none.m.torque_est_mean_nm, *simple.m.torque_est_mean_nm + 0.015);
    EXPECT_GT(*simple.m.torque_est_mean_nm, *proposed.m.torque_est_mean_nm);
    EXPECT_NEAR(*proposed.m.torque_est_mean_nm, proposed.m.torque_mean_nm, 0.01);
    EXPECT_NEAR(*current.m.torque_est_mean_nm, current.m.torque_mean_nm, 0.003);
}

TEST(SilClosedLoop, HoangFindingsSstpVoltageModel)
{
    // Hoang Tables IX/X, SSTP: without compensation the voltage model over-estimates the torque
    // (0.3296 vs 0.3 N*m) and the currents rise above the current model's (2.74-2.89 vs 2.2 A), but
    // stay balanced because all three legs carry the drops; with the equal-drop compensation of
    // [29] the estimate comes back (0.2984). Measured: none 0.366 N*m, 3.25-3.46 A, 6.3 %;
    // compensated 0.311 N*m, 2.19-2.36 A; current model 2.16 A, 0.4 %.
    const Outcome none = run("sstp_voltage_none_full.toml");
    const Outcome comp = run("sstp_voltage_simple_full.toml");
    const Outcome current = run("sstp_current_full.toml");
    for (const Outcome* o : {&none, &comp, &current}) {
        ASSERT_TRUE(o->m.fundamental_a.has_value()) << o->info.fault;
        EXPECT_EQ(o->info.fault, "none");
    }
    EXPECT_GT(*none.m.torque_est_mean_nm, 0.3 * 1.1);
    EXPECT_LT(std::fabs(*comp.m.torque_est_mean_nm - 0.3), 0.5 * std::fabs(*none.m.torque_est_mean_nm - 0.3));
    const auto mean3 = [](const std::array<double, 3>& a) { return (a[0] + a[1] + a[2]) / 3.0; };
    EXPECT_GT(mean3(*none.m.fundamental_a), 1.3 * mean3(*current.m.fundamental_a));
    EXPECT_LT(*none.m.imbalance_pct, 10.0);
    EXPECT_LT(*current.m.imbalance_pct, 2.0);
}

TEST(SilClosedLoop, FstpMidPointDriftsOnAFiniteLinkWithTheVoltageModel)
{
    // Not in the paper: on a finite split link (2 x 4.7 mF) the voltage-model FSTP drive with the
    // simple compensation lets the mid-point walk away from vdc/2 (a DC voltage error b gives a
    // flux offset b/w_c and a DC phase-A current, which charges the capacitors); the current-model
    // drive on the same link keeps the mid-point near vdc/2. Measured: voltage model 18 V off
    // after the acceleration (the firmware's current limit keeps it running, its mid-point
    // regulation pulls the mid-point back slowly: 40.6 V mean in the metrics window); current
    // model: mid-point within 35 +- 4 V once settled.
    const fs::path dir_v = fs::temp_directory_path() / "sil_midpoint_voltage";
    const fs::path dir_c = fs::temp_directory_path() / "sil_midpoint_current";
    const Outcome v = run("fstp_voltage_simple_full_midpoint.toml", {}, dir_v.string());
    const Outcome c = run("fstp_voltage_simple_full_midpoint.toml", {"control.estimator=current"}, dir_c.string());
    const auto tv = read_trace(dir_v / "trace.csv");
    const auto tc = read_trace(dir_c / "trace.csv");
    // From standstill the current-model drive also moves the mid-point during the acceleration:
    // phase A's fundamental charges the split link by i_a/(w_e*2C) peak, 11 V for 3.3 A at 5 Hz
    // with 2 x 4.7 mF (measured: 12.5 V at 0.15 s). So its excursion is judged once settled, in
    // the metrics window (last 0.4 s): measured 3.7 V there (phase A's 25 Hz fundamental alone
    // moves it by 2.2 A/(w_e 2C) = 1.5 V peak).
    const auto excursion = [](const std::map<std::string, std::vector<double>>& tr, double t_from) {
        const std::vector<double>& vlo = tr.at("vc_lo_v");
        const std::vector<double>& t = tr.at("t_s");
        double e = 0.0;
        for (std::size_t k = 0; k < vlo.size(); ++k) {
            if (t[k] >= t_from) {
                e = std::max(e, std::fabs(vlo[k] - 35.0));
            }
        }
        return e;
    };
    EXPECT_GT(excursion(tv, 0.0), 8.0);
    EXPECT_LT(excursion(tc, 1.1), 5.0);
    EXPECT_EQ(c.info.fault, "none");
    ASSERT_TRUE(c.m.imbalance_pct.has_value());
    EXPECT_LT(*c.m.imbalance_pct, 5.0);
    (void)v;
}

TEST(SilClosedLoop, FixedPointFirmwareAgreesWithTheDoubleReference)
{
    // model/'s double-precision reference DTC on the same plant and the same measurements
    // (controller_reference.cpp). Measured (FSTP, voltage model, proposed compensation, 1500 rpm,
    // full load): fundamentals 2.193/2.000/2.335 A vs 2.188/2.011/2.331 A (0.6 %), THD 31.88 vs
    // 31.63 %, estimated torque 0.3021 vs 0.3022 N*m, imbalance 16.8 vs 15.9 %. Both are chaotic
    // bang-bang loops, so they are compared as envelopes, with about 3x the measured gaps.
    register_reference_controller(&make_reference_controller);
    Scenario sc;
    Diagnostics d;
    ASSERT_TRUE(load_scenario(kScenarios + "fstp_voltage_proposed_full.toml", {"control.implementation=reference"},
                              &sc, &d));
    std::string err;
    if (!make_controller(sc, &err)) {
        GTEST_SKIP() << err;
    }
    // The reference implements the paper's algorithm only: the firmware's delay and dead-time
    // compensations are off for this comparison, and both run on the stiff link (the reference
    // has no mid-point regulation; the shipped scenario's finite split link needs it).
    const Outcome fx = run("fstp_voltage_proposed_full.toml", {"control.delay_comp=false", "control.deadtime_comp=false",
                                                               "inverter.finite_dc_link=false"});
    const Outcome ref = run("fstp_voltage_proposed_full.toml", {"control.implementation=reference",
                                                                "inverter.finite_dc_link=false"});
    ASSERT_TRUE(fx.m.fundamental_a.has_value()) << fx.info.fault;
    ASSERT_TRUE(ref.m.fundamental_a.has_value());
    for (int ph = 0; ph < 3; ++ph) {
        EXPECT_NEAR((*fx.m.fundamental_a)[static_cast<std::size_t>(ph)], (*ref.m.fundamental_a)[static_cast<std::size_t>(ph)],
                    0.02 * (*ref.m.fundamental_a)[static_cast<std::size_t>(ph)]);
    }
    EXPECT_NEAR(fx.m.torque_mean_nm, ref.m.torque_mean_nm, 0.002);
    EXPECT_NEAR(*fx.m.torque_est_mean_nm, *ref.m.torque_est_mean_nm, 0.002);
    EXPECT_NEAR(*fx.m.thd_total_pct, *ref.m.thd_total_pct, 0.05 * *ref.m.thd_total_pct);
    EXPECT_NEAR(*fx.m.imbalance_pct, *ref.m.imbalance_pct, 3.0);
}

TEST(SilClosedLoop, OverCurrentTripsWithinOneIsrPeriodAndGatesStayOff)
{
    // A trip level below the running current: the first sample above it must see the gates off
    // in that very period (trip decided in the ISR that sees the sample) and forever after. The
    // firmware's current limit (ilim.h) is off here: it exists to keep the current below the
    // trip, and this test checks the trip itself.
    const fs::path out = tmp("overcurrent");
    const Outcome o = run("sstp_current_full.toml", {"protection.overcurrent_a=1.5", "control.current_limit_a=0", "duration_s=0.3",
                                                     "metrics_window_s=0.1", "initial_speed_rpm=0"},
                          out.string());
    EXPECT_NE(o.info.fault, "none");
    const auto tr = read_trace(out / "trace.csv");
    const auto& ia = tr.at("i_a_a");
    const auto& ib = tr.at("i_b_a");
    const auto& ic = tr.at("i_c_a");
    const auto& en = tr.at("en");
    std::size_t first = ia.size();
    for (std::size_t k = 0; k < ia.size(); ++k) {
        if (std::max({std::fabs(ia[k]), std::fabs(ib[k]), std::fabs(ic[k])}) > 1.5 * 1.02) { // + ADC gain margin
            first = k;
            break;
        }
    }
    ASSERT_LT(first, ia.size()) << "the current never exceeded the trip level";
    for (std::size_t k = first; k < en.size(); ++k) {
        ASSERT_EQ(en[k], 0.0) << "gates on at row " << k << " after the over-current at row " << first;
    }
    fs::remove_all(out);
}

TEST(SilClosedLoop, DcLinkOutOfRangeTrips)
{
    const Outcome over = run("sstp_current_full.toml", {"protection.vdc_max_v=60", "duration_s=0.1", "metrics_window_s=0.05"});
    EXPECT_NE(over.info.fault, "none");
    const Outcome under = run("sstp_current_full.toml", {"protection.vdc_min_v=75", "duration_s=0.1", "metrics_window_s=0.05"});
    EXPECT_NE(under.info.fault, "none");
    EXPECT_NE(over.info.fault, under.info.fault);
}

TEST(SilClosedLoop, FirmwareNeverCommandsAStateOutsideItsTable)
{
    for (const char* f : {"sstp_current_full.toml", "fstp_voltage_proposed_full.toml"}) {
        const Outcome o = run(f, {"duration_s=0.5", "metrics_window_s=0.2"});
        EXPECT_EQ(o.info.invalid_commands, 0u) << f;
    }
}
