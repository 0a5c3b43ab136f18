// Self-commissioning (firmware/app/app_ident.h, docs/commissioning.md) through `dtc-sil identify`:
// each standstill step against the targets of the self-commissioning issue (R_s 5 %, L_s 5 %, the
// inverter's drop at rated current 10 %, encoder offset 3 degrees electrical, direction and pole
// pairs exact), failures named with their step, and the drive run on the identified values
// (`dtc-sil run --overlay identified.toml`).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "cli_capture.hpp"
#include "identify_fixture.hpp"
#include "run.hpp"
#include "scenario.hpp"

namespace fs = std::filesystem;
using namespace sil;

namespace {
const std::string kScenarios = std::string(DTC_SOURCE_DIR) + "/tools/scenarios/";
const std::string kFstp = kScenarios + "fstp_voltage_proposed_full.toml"; // Hoang Table VIII rig, FSTP
const std::string kSstp = kScenarios + "sstp_voltage_simple_full.toml";   // the same rig, SSTP
constexpr double kPi = 3.14159265358979323846;

// Hoang Table IV devices, the 70 V link and 1 us dead time of the rig, 50 us period, 2.2 A rated.
constexpr double kVce = 0.9, kVd = 1.25, kRon = 0.075, kVdc = 70.0, kTd = 1e-6, kTs = 50e-6, kIr = 2.2;

class Identify : public sil_test::IdentifyFixture {};
using sil_test::id_of;

// The standstill steps against the targets. g: the injection axis's share of the drop
// (docs/commissioning.md: 1/sqrt(3) on the FSTP's beta axis, 2/3 on the SSTP's alpha axis), so the
// inverter's drop at rated current is g (V_CE + V_d + 2 V_dc T_d / T_s) + R_on I_rated (Hoang
// Table III: R_on in series in every state).
void expect_targets(const nlohmann::json& j, double g, int pole_pairs, double enc_offset_mech_rad)
{
    ASSERT_EQ(j["status"], "ok") << j.dump(2);
    EXPECT_NEAR(id_of(j, "rs_ohm"), 0.466, 0.05 * 0.466);                     // Hoang Table VIII R_s
    EXPECT_NEAR(id_of(j, "ls_h"), 3.19e-3, 0.05 * 3.19e-3);                   // Hoang Table VIII L_s
    const double drop = g * (kVce + kVd + 2.0 * kVdc * kTd / kTs) + kRon * kIr;
    EXPECT_NEAR(id_of(j, "drop_at_rated_v"), drop, 0.10 * drop);
    EXPECT_EQ(id_of(j, "pole_pairs"), pole_pairs);
    EXPECT_EQ(id_of(j, "encoder_reversed"), 0.0);
    // hal_host: the electrical angle at count 0 is -p * sensors.encoder_offset_rad
    const double want_deg = -pole_pairs * enc_offset_mech_rad * 180.0 / kPi;
    const double err_deg = std::remainder(id_of(j, "encoder_offset_el_deg") - want_deg, 360.0);
    EXPECT_LT(std::fabs(err_deg), 3.0) << "encoder offset " << id_of(j, "encoder_offset_el_deg") << " deg el.";
    for (const auto& [k, v] : j["quantities"].items()) {
        EXPECT_EQ(v["status"], "ok") << k;
    }
    // Spinning: psi_m 3 %, J 10 % (the targets), the viscous friction (the coupled DC
    // generator's torque over speed included) 10 %; the whole sequence within 10 s.
    const auto rel = [&](const char* q) { return std::fabs(j["quantities"][q]["error_pct"].get<double>()); };
    EXPECT_LT(rel("psi_m_wb"), 3.0) << id_of(j, "psi_m_wb");
    EXPECT_LT(rel("j_kgm2"), 10.0) << id_of(j, "j_kgm2");
    EXPECT_LT(rel("b_nm_s_per_rad"), 10.0) << id_of(j, "b_nm_s_per_rad");
    EXPECT_LE(j["duration_s"].get<double>(), 10.0);
}

TEST_F(Identify, FstpTableViiiRigMeetsTheTargets)
{
    std::string err;
    ASSERT_EQ(identify(kFstp, {}, &err), 0) << err;
    expect_targets(report(), 1.0 / std::sqrt(3.0), 1, 0.0);
}

TEST_F(Identify, SstpFourPolePairsOffsetEncoderAndLightRotorMeetTheTargets)
{
    // Another machine on the same inverter: 4 pole pairs, a 500-line encoder mounted 2.5 rad off,
    // a rotor alone (J = 1e-4 kg m^2, lightly damped by its friction).
    const std::vector<std::string> sets = {"motor.pole_pairs=4", "sensors.encoder_lines=500",
                                           "sensors.encoder_offset_rad=-2.5", "motor.j_kgm2=1e-4"};
    std::string err;
    ASSERT_EQ(identify(kSstp, sets, &err), 0) << err;
    expect_targets(report(), 2.0 / 3.0, 4, -2.5);
}

TEST_F(Identify, FstpTwoPolePairsOffsetEncoderMeetTheTargets)
{
    const std::vector<std::string> sets = {"motor.pole_pairs=2", "sensors.encoder_lines=1024",
                                           "sensors.encoder_offset_rad=1.0"};
    std::string err;
    ASSERT_EQ(identify(kFstp, sets, &err), 0) << err;
    expect_targets(report(), 1.0 / std::sqrt(3.0), 2, 1.0);
}

// The self-commissioning issue's time target for the standstill steps: at most 3 s (simulated) on
// the Table VIII rig, on both topologies, with the accuracy targets still met; the report's
// standstill time is the sum of the steps' durations.
TEST_F(Identify, StandstillStepsWithinThreeSecondsOnTheTableViiiRig)
{
    for (const std::string& s : {kFstp, kSstp}) {
        ASSERT_EQ(identify(s, {}), 0) << s;
        const nlohmann::json j = report();
        const auto& q = j["quantities"];
        const double sum = q["rs_ohm"]["duration_s"].get<double>() + q["ls_h"]["duration_s"].get<double>() +
                           q["pole_pairs"]["duration_s"].get<double>();
        EXPECT_NEAR(j["standstill_s"].get<double>(), sum, 1e-9) << s;
        EXPECT_LE(j["standstill_s"].get<double>(), 3.0) << s;
        expect_targets(j, s == kFstp ? 1.0 / std::sqrt(3.0) : 2.0 / 3.0, 1, 0.0);
    }
}

TEST_F(Identify, CoupledLoadThatStopsTheSpinIsNamed)
{
    // The DC generator loaded to 0.225 N.m at 100 rpm (0.0215 N.m.s/rad): at the spin's half rated
    // q current (0.15 N.m) the rotor settles at 67 rpm, below an eighth of the spin speed (94 rpm);
    // the standstill steps pass (the load only damps the rotor's swing).
    std::string err;
    EXPECT_EQ(identify(kFstp, {"load.speed_rpm=100"}, &err), 3);
    EXPECT_NE(err.find("identification failed in step spin: blocked"), std::string::npos) << err;
    const nlohmann::json j = report();
    EXPECT_EQ(j["quantities"]["rs_ohm"]["status"], "ok");
    EXPECT_EQ(j["quantities"]["j_kgm2"]["status"], "failed");
    EXPECT_EQ(toml().find("\nj_kgm2 ="), std::string::npos);
    // and a rotor held by a dry friction above the aligning torque never moves: named in the encoder step
    EXPECT_EQ(identify(kFstp, {"load.coulomb_nm=0.6"}, &err), 3);
    EXPECT_NE(err.find("identification failed in step encoder: encoder_not_counting"), std::string::npos) << err;
}

TEST_F(Identify, OpenPhaseIsNamedAndNothingIsIdentified)
{
    std::string err;
    EXPECT_EQ(identify(kFstp, {"faults.leg_open=b", "faults.time_s=1e-3"}, &err), 3);
    EXPECT_NE(err.find("identification failed in step rs: open_phase"), std::string::npos) << err;
    const nlohmann::json j = report();
    EXPECT_EQ(j["status"], "failed");
    EXPECT_EQ(j["failed_step"], "rs");
    EXPECT_EQ(j["quantities"]["rs_ohm"]["status"], "failed");
    EXPECT_EQ(j["quantities"]["ls_h"]["status"], "not_run");
    const std::string t = toml();
    EXPECT_NE(t.find("# FAILED in step rs"), std::string::npos);
    EXPECT_EQ(t.find("\nrs_ohm ="), std::string::npos) << "a failed step writes no value";
}

TEST_F(Identify, EncoderNotCountingIsNamedAfterTheElectricalSteps)
{
    std::string err;
    EXPECT_EQ(identify(kSstp, {"faults.encoder_lost=true", "faults.time_s=1e-3"}, &err), 3);
    EXPECT_NE(err.find("identification failed in step encoder: encoder_not_counting"), std::string::npos) << err;
    const nlohmann::json j = report();
    EXPECT_EQ(j["quantities"]["rs_ohm"]["status"], "ok");
    EXPECT_EQ(j["quantities"]["pole_pairs"]["status"], "failed");
    const std::string t = toml();
    EXPECT_NE(t.find("\nrs_ohm ="), std::string::npos);
    EXPECT_EQ(t.find("\npole_pairs ="), std::string::npos);
}

TEST_F(Identify, DriveRunsOnIdentifiedValuesFromStandstillTo1500RpmUnderFullLoad)
{
    std::string err;
    ASSERT_EQ(identify(kFstp, {}, &err), 0) << err;
    // The overlay is a scenario fragment the loader accepts, and it sets what was identified.
    Scenario sc;
    Diagnostics d;
    ASSERT_TRUE(load_scenario(kFstp, {}, &sc, &d, {(dir / "id" / "identified.toml").string()})) << d.text();
    ASSERT_TRUE(sc.firmware.value.count("rs_ohm") != 0 && sc.firmware.value.count("ls_h") != 0 &&
                sc.firmware.value.count("psi_m_wb") != 0 && sc.firmware.pole_pairs && sc.firmware.encoder_offset_rad &&
                sc.firmware.j_kgm2);
    EXPECT_EQ(*sc.firmware.pole_pairs, 1);
    // Standstill to 1500 rpm under 0.3 N.m (0.225 N.m generator + 0.075 N.m friction at 1500 rpm).
    ASSERT_EQ(cli({"run", kFstp, "--overlay", (dir / "id" / "identified.toml").string(), "--out",
                   (dir / "run").string(), "--no-trace", "-q"},
                  &err),
              0)
        << err;
    std::ifstream f(dir / "run" / "metrics.json");
    const nlohmann::json m = nlohmann::json::parse(f);
    EXPECT_EQ(m["fault"], "none");
    EXPECT_EQ(m["hw_trip"], false);
    EXPECT_NEAR(m["speed_mean_rpm"].get<double>(), 1500.0, 15.0);
    EXPECT_NEAR(m["torque_mean_nm"].get<double>(), 0.3, 0.03);
    EXPECT_LE(m["imbalance_pct"].get<double>(), 8.0); // the FSTP proposed compensation's target
}

TEST_F(Identify, SweepAppliesTheOverlayToEveryRun)
{
    // 0.01 s = 200 periods of 50 us: the overlay's duration, over the scenario's 1.5 s
    std::ofstream(dir / "short.toml") << "duration_s = 0.01\nmetrics_window_s = 0.005\n";
    std::string err;
    ASSERT_EQ(cli({"sweep", kFstp, "--overlay", (dir / "short.toml").string(), "--out", (dir / "sw").string(),
                   "--grid", "control.speed_ref_rpm=500,1000", "--jobs", "1", "-q"},
                  &err),
              0)
        << err;
    std::ifstream f(dir / "sw" / "summary.json");
    const nlohmann::json j = nlohmann::json::parse(f);
    ASSERT_EQ(j["rows"].size(), 2u);
    for (const auto& r : j["rows"]) {
        EXPECT_EQ(r["metrics"]["isr_count"], 200) << r.dump();
    }
    EXPECT_EQ(cli({"sweep", kFstp, "--overlay", (dir / "none.toml").string(), "--out", (dir / "sw2").string(),
                   "--grid", "control.speed_ref_rpm=500", "-q"},
                  &err),
              1);
    EXPECT_NE(err.find("none.toml: --overlay: no such file"), std::string::npos) << err;
}

TEST_F(Identify, OverlayKeysAreRefusedWithTheirLine)
{
    std::ofstream(dir / "bad.toml") << "[firmware]\npole_pairs = 0\nencoder_reversed = true\n";
    std::string err;
    EXPECT_EQ(cli({"check", kFstp, "--overlay", (dir / "bad.toml").string()}, &err), 1);
    EXPECT_NE(err.find("bad.toml:2:14: firmware.pole_pairs"), std::string::npos) << err;
    std::ofstream(dir / "rev.toml") << "[firmware]\nencoder_reversed = true\n";
    EXPECT_EQ(cli({"check", kFstp, "--overlay", (dir / "rev.toml").string()}, &err), 1);
    EXPECT_NE(err.find("rev.toml:2:20: firmware.encoder_reversed"), std::string::npos) << err;
}

} // namespace
