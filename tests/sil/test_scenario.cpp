// Scenario parsing: defaults, good files, --set, and every malformed case naming key and line.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <complex>
#include <random>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "controller_adapter.hpp"
#include "run.hpp"
#include "scenario.hpp"

using namespace sil;

namespace {

// Parses text as "case.toml"; returns the joined error text ("" if accepted).
std::string errors_of(const std::string& text, const std::vector<std::string>& sets = {}, Scenario* out = nullptr)
{
    Scenario s;
    Diagnostics d;
    const bool ok = parse_scenario(text, "case.toml", sets, &s, &d);
    if (out != nullptr) {
        *out = s;
    }
    std::string all;
    for (const auto& e : d.errors) {
        all += e + "\n";
    }
    EXPECT_EQ(ok, d.errors.empty());
    return all;
}

void expect_error(const std::string& text, const std::string& key, int line, const std::string& what = "",
                  const std::vector<std::string>& sets = {})
{
    const std::string e = errors_of(text, sets);
    ASSERT_FALSE(e.empty()) << "accepted:\n" << text;
    EXPECT_NE(e.find(key), std::string::npos) << "key '" << key << "' not named in: " << e;
    if (line > 0) {
        EXPECT_NE(e.find("case.toml:" + std::to_string(line) + ":"), std::string::npos)
            << "line " << line << " not named in: " << e;
    }
    if (!what.empty()) {
        EXPECT_NE(e.find(what), std::string::npos) << "'" << what << "' not in: " << e;
    }
}

std::filesystem::path temp_dir()
{
    auto d = std::filesystem::temp_directory_path() / ("dtc_sil_scn_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                                                       ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

const char* kGood = R"(# FSTP, voltage model, proposed compensation, full load
duration_s = 1.0
metrics_window_s = 0.4
[motor]
rs_ohm = 0.466
pole_pairs = 1
emf_gain = [0.98739, 1.00149, 1.01112]
[inverter]
topology = "fstp"
vdc_v = 70
[load]
type = "generator"
speed_rpm = 1500
torque_nm = 0.225
[control]
mode = "speed"
estimator = "voltage"
compensation = "proposed"
speed_ref_rpm = 1500
[sensors]
current_noise_a_rms = 0.01
seed = 7
)";

} // namespace

TEST(Scenario, EmptyScenarioIsRefused)
{
    EXPECT_NE(errors_of("").find("case.toml: the scenario sets no key"), std::string::npos);
    EXPECT_NE(errors_of("# only a comment\n\n").find("sets no key"), std::string::npos);
    // --set alone does not make an empty file a scenario.
    EXPECT_NE(errors_of("", {"duration_s=1"}).find("sets no key"), std::string::npos);
}

TEST(Scenario, UnsetKeysGiveTheDocumentedDefaults)
{
    Scenario s;
    EXPECT_EQ(errors_of("ts_s = 50e-6\n", {}, &s), "");
    // Hoang Table VIII machine, Table IV devices, 70 V, sec. IV control settings.
    EXPECT_DOUBLE_EQ(s.motor.rs_ohm, 0.466);
    EXPECT_DOUBLE_EQ(s.motor.ls_h, 3.19e-3);
    EXPECT_DOUBLE_EQ(s.motor.psi_m_wb, 0.0928);
    EXPECT_EQ(s.motor.pole_pairs, 1);
    EXPECT_DOUBLE_EQ(s.motor.rated_torque_nm, 0.3);
    EXPECT_DOUBLE_EQ(s.inverter.vdc_v, 70.0);
    EXPECT_DOUBLE_EQ(s.inverter.v_ce_v, 0.9);
    EXPECT_DOUBLE_EQ(s.inverter.v_d_v, 1.25);
    EXPECT_DOUBLE_EQ(s.inverter.r_on_ohm, 0.075);
    EXPECT_DOUBLE_EQ(s.ts_s, 50e-6);
    EXPECT_EQ(s.control.speed_loop_divider, 10);
    EXPECT_DOUBLE_EQ(s.control.lpf_cutoff_rad_s, 5.0);
    EXPECT_DOUBLE_EQ(s.control.flux_ref_wb, 0.0928);
    EXPECT_DOUBLE_EQ(s.control.torque_band_nm, 0.0);
    EXPECT_DOUBLE_EQ(s.control.flux_band_wb, 0.0);
    EXPECT_EQ(s.sensors.encoder_lines, 2000);
    // b_nm_s_per_rad: 25 % of the 0.3 N*m rated torque at 1500 rpm (Hoang sec. IV, inertial load).
    EXPECT_NEAR(s.motor.b_nm_s_per_rad * 1500.0 * 2.0 * 3.14159265358979 / 60.0, 0.075, 1e-5);
}

TEST(Scenario, GoodFileIsReadWithOriginsAndIntegersPromoted)
{
    Scenario s;
    ASSERT_EQ(errors_of(kGood, {}, &s), "");
    EXPECT_EQ(s.inverter.topology, Topology::Fstp);
    EXPECT_DOUBLE_EQ(s.inverter.vdc_v, 70.0); // TOML integer accepted for a number
    EXPECT_EQ(s.control.compensation, Compensation::Proposed);
    EXPECT_DOUBLE_EQ(s.load.torque_nm, 0.225);
    EXPECT_DOUBLE_EQ(s.motor.emf_gain[2], 1.01112);
    EXPECT_EQ(s.sensors.seed, 7);
    EXPECT_EQ(s.origin.at("load.torque_nm"), "case.toml:14:13");
    EXPECT_EQ(s.name, "case");
}

TEST(Scenario, SetOverridesWithDottedNamesAndTypeChecks)
{
    Scenario s;
    ASSERT_EQ(errors_of(kGood, {"load.speed_rpm=700", "control.estimator=current", "inverter.drops=false",
                                "motor.emf_gain=[1, 1, 1]", "sensors.seed=42", "control.mode=\"torque\""},
                        &s),
              "");
    EXPECT_DOUBLE_EQ(s.load.speed_rpm, 700.0);
    EXPECT_EQ(s.control.estimator, Estimator::Current);
    EXPECT_FALSE(s.inverter.drops);
    EXPECT_DOUBLE_EQ(s.motor.emf_gain[0], 1.0);
    EXPECT_EQ(s.sensors.seed, 42);
    EXPECT_EQ(s.control.mode, ControlMode::Torque);
    EXPECT_NE(s.origin.at("load.speed_rpm").find("--set"), std::string::npos);

    expect_error(kGood, "load.speed_rpm", 0, "expected a number", {"load.speed_rpm=fast"});
    expect_error(kGood, "load.spede_rpm", 0, "unknown key", {"load.spede_rpm=700"});
    expect_error(kGood, "sensors.seed", 0, "expected an integer", {"sensors.seed=1.5"});
    expect_error(kGood, "inverter.drops", 0, "true or false", {"inverter.drops=1"});
    expect_error(kGood, "motor.rs_ohm", 0, "impossible", {"motor.rs_ohm=-1"});
    expect_error(kGood, "control.estimator", 0, "expected one of", {"control.estimator=flux"});
    expect_error(kGood, "--set #1", 0, "key=value", {"load.speed_rpm"});
    expect_error(kGood, "motor.emf_gain", 0, "3 numbers", {"motor.emf_gain=[1,1]"});
}

// The dynamometer's speed ramp: held at initial_speed_rpm, then linear to load.speed_rpm.
TEST(Scenario, DynamometerSpeedRampAndItsValidation)
{
    Scenario s;
    ASSERT_EQ(errors_of(kGood, {"load.type=speed", "load.speed_rpm=1440", "initial_speed_rpm=0",
                                "load.speed_ramp_start_s=0.5", "load.speed_ramp_s=0.3"},
                        &s),
              "");
    EXPECT_DOUBLE_EQ(dyno_speed_rpm(s, 0.0), 0.0);
    EXPECT_DOUBLE_EQ(dyno_speed_rpm(s, 0.5), 0.0);
    EXPECT_NEAR(dyno_speed_rpm(s, 0.65), 720.0, 1e-9);
    EXPECT_DOUBLE_EQ(dyno_speed_rpm(s, 0.8), 1440.0);
    EXPECT_DOUBLE_EQ(dyno_speed_rpm(s, 2.0), 1440.0);
    ASSERT_EQ(errors_of(kGood, {"load.type=speed", "load.speed_rpm=900"}, &s), "");
    EXPECT_DOUBLE_EQ(dyno_speed_rpm(s, 0.0), 900.0); // no ramp: held from t = 0
    expect_error(kGood, "load.speed_ramp_s", 0, "needs load.type", {"load.type=torque", "load.speed_ramp_s=0.3"});
    expect_error(kGood, "load.speed_ramp_start_s", 0, "needs load.speed_ramp_s",
                 {"load.type=speed", "load.speed_ramp_start_s=0.3"});
    expect_error(kGood, "load.speed_ramp_s", 0, "impossible", {"load.speed_ramp_s=-1"});
}

TEST(Scenario, UnknownKeyNamesKeyAndLine)
{
    expect_error("duration_s = 1.0\n[motor]\nrs_ohm = 0.4\nls_mh = 3.19\n", "motor.ls_mh", 4, "unknown key");
    expect_error("duration = 1.0\n", "duration", 1, "unknown key");
    expect_error("[motr]\nrs_ohm = 0.4\n", "motr", 1, "unknown table");
    expect_error("[control.speed]\nkp = 1\n", "control.speed", 1, "unknown key");
}

TEST(Scenario, WrongTypeNamesKeyAndLine)
{
    expect_error("[motor]\nrs_ohm = \"0.466\"\n", "motor.rs_ohm", 2, "expected a number, got string");
    expect_error("[motor]\npole_pairs = 1.5\n", "motor.pole_pairs", 2, "expected an integer, got float");
    expect_error("[inverter]\ndrops = 1\n", "inverter.drops", 2, "expected true or false");
    expect_error("[control]\nmode = 1\n", "control.mode", 2, "expected a string");
    expect_error("[motor]\nemf_gain = [1.0, 1.0]\n", "motor.emf_gain", 2, "got 2 elements");
    expect_error("[motor]\nemf_gain = [1.0, \"x\", 1.0]\n", "motor.emf_gain", 2, "element 1");
    expect_error("motor = 3\n", "motor", 1, "expected a table");
}

// A salient PM: motor.ld_h is motor.ls_h's other name (L_d); motor.lq_h not given is L_d (a surface
// PM). Both L_d keys given and different: refused naming motor.ld_h and its line, and motor.ls_h's.
TEST(Scenario, SalientPmKeys)
{
    Scenario s;
    EXPECT_EQ(errors_of("[motor]\nls_h = 4e-3\n", {}, &s), "");
    EXPECT_DOUBLE_EQ(s.motor.ld_h, 4e-3);
    EXPECT_DOUBLE_EQ(s.motor.lq_h, 4e-3);
    EXPECT_EQ(errors_of("[motor]\nld_h = 2e-3\nlq_h = 5e-3\n", {}, &s), "");
    EXPECT_DOUBLE_EQ(s.motor.ls_h, 2e-3);
    EXPECT_DOUBLE_EQ(s.motor.lq_h, 5e-3);
    EXPECT_EQ(errors_of("[motor]\nls_h = 2e-3\nld_h = 2e-3\nlq_h = 3e-3\n", {}, &s), "");
    EXPECT_DOUBLE_EQ(s.motor.ls_h, 2e-3);
    expect_error("[motor]\nls_h = 2e-3\nld_h = 3e-3\n", "motor.ld_h", 3, "differs from motor.ls_h");
    EXPECT_NE(errors_of("[motor]\nls_h = 2e-3\nld_h = 3e-3\n").find("case.toml:2"), std::string::npos);
    expect_error("[motor]\nlq_h = -1e-3\n", "motor.lq_h", 2, "must be > 0");
    expect_error("[motor]\ntype = \"im\"\nlq_h = 1e-3\n", "motor.lq_h", 3, "not a parameter");
}

// The firmware's L_q (firmware.lq_h, converter member lq_h): not given, the plant's (as every
// firmware.* key); with the firmware's own L_d (firmware.ls_h) and no L_q, a surface PM's (0: the
// converter takes ls_h), so that no plant value joins what the firmware was told; given, its own.
// The converter writes L_q into the PM law's row; a surface PM's L_q row is its L_s row bit for bit
// (the laws' surface path).
TEST(Scenario, FirmwareLqFollowsThePlantOrTheFirmwaresOwnLd)
{
    Scenario s;
    ASSERT_EQ(errors_of("[motor]\nlq_h = 6.38e-3\n", {}, &s), "");
    EXPECT_DOUBLE_EQ(firmware_si_config(s).lq_h, 6.38e-3);
    ASSERT_EQ(errors_of("[motor]\nlq_h = 6.38e-3\n[firmware]\nls_h = 3.2e-3\n", {}, &s), "");
    EXPECT_DOUBLE_EQ(firmware_si_config(s).ls_h, 3.2e-3);
    EXPECT_DOUBLE_EQ(firmware_si_config(s).lq_h, 0.0);
    ASSERT_EQ(errors_of("[motor]\nlq_h = 6.38e-3\n[firmware]\nls_h = 3.2e-3\nlq_h = 6.4e-3\n", {}, &s), "");
    EXPECT_DOUBLE_EQ(firmware_si_config(s).lq_h, 6.4e-3);
    expect_error("[firmware]\nlq_h = -1e-3\n", "firmware.lq_h", 2, "");
    expect_error("[motor]\ntype = \"im\"\n[firmware]\nlq_h = 1e-3\n", "firmware.lq_h", 4, "");

    dtc_config_t cfg;
    ASSERT_EQ(errors_of("[motor]\nls_h = 3.19e-3\n", {}, &s), "");
    const dtc_config_si_t surface = firmware_si_config(s);
    ASSERT_EQ(dtc_config_from_si(&surface, &cfg, nullptr, 0), DTC_SI_OK);
    EXPECT_EQ(cfg.u.pm_dtc.machine.lq_iq, cfg.u.pm_dtc.machine.ls_iq);
    ASSERT_EQ(errors_of("[motor]\nls_h = 3.19e-3\nlq_h = 6.38e-3\n", {}, &s), "");
    const dtc_config_si_t si = firmware_si_config(s);
    ASSERT_EQ(dtc_config_from_si(&si, &cfg, nullptr, 0), DTC_SI_OK);
    EXPECT_NEAR(static_cast<double>(cfg.u.pm_dtc.machine.lq_iq) / cfg.u.pm_dtc.machine.ls_iq, 2.0, 1e-6);
}

TEST(Scenario, ImpossibleNumbersNameKeyAndLine)
{
    expect_error("\n[motor]\nrs_ohm = 0.0\n", "motor.rs_ohm", 3, "impossible");
    expect_error("[motor]\nls_h = -3.19e-3\n", "motor.ls_h", 2, "must be > 0");
    expect_error("[motor]\npsi_m_wb = nan\n", "motor.psi_m_wb", 2, "impossible");
    expect_error("[inverter]\nvdc_v = inf\n", "inverter.vdc_v", 2, "impossible");
    expect_error("[motor]\npole_pairs = 0\n", "motor.pole_pairs", 2, "impossible");
    expect_error("[control]\nlpf_cutoff_rad_s = -5\n", "control.lpf_cutoff_rad_s", 2, "impossible");
    expect_error("[control]\nmode = \"sped\"\n", "control.mode", 2, "expected one of \"speed\"");
    expect_error("[sensors]\nencoder_lines = 20000\n", "sensors.encoder_lines", 2, "impossible");
    expect_error("duration_s = 0.1\nmetrics_window_s = 0.2\n", "metrics_window_s", 2, "longer than duration_s");
    expect_error("[control]\nspeed_bw_hz = 500\n", "control.speed_bw_hz", 2, "too fast for the speed period");
    expect_error("[protection]\nvdc_min_v = 80\nvdc_max_v = 60\n", "protection.vdc_min_v", 2, "below");
}

// The stator-flux vector control runs one SVM carrier period per control period (hal.h, one pulse
// per leg): ts_s follows control.carrier_hz when not given, a disagreement names the carrier key,
// and so does a carrier whose timer period 75 MHz / (2 f) is not a whole number of counts.
TEST(Scenario, SfvcCarrierAndControlPeriod)
{
    const std::string im = "[motor]\ntype = \"im\"\n[inverter]\ntopology = \"sstp\"\n[control]\nscheme = \"sfvc\"\n"
                           "rotor_flux_ref_wb = 0.53\n";
    {
        Scenario sc;
        Diagnostics d;
        ASSERT_TRUE(parse_scenario(im, "case.toml", {}, &sc, &d)) << d.text();
        EXPECT_DOUBLE_EQ(sc.control.carrier_hz, 6250.0);
        EXPECT_NEAR(sc.ts_s, 160e-6, 1e-15);
        ASSERT_TRUE(parse_scenario(im + "carrier_hz = 5000.0\n", "case.toml", {}, &sc, &d)) << d.text();
        EXPECT_NEAR(sc.ts_s, 200e-6, 1e-15);
        // (at 250 us the derived current limit less one period's rise leaves the 4 kW IM no torque:
        // the converter then sets no current limit, the trip is the only protection)
        ASSERT_TRUE(parse_scenario("ts_s = 100e-6\n" + im, "case.toml", {}, &sc, &d)) << d.text();
        EXPECT_NEAR(sc.control.carrier_hz, 10000.0, 1e-9);
    }
    expect_error("ts_s = 50e-6\n" + im + "carrier_hz = 6250.0\n", "control.carrier_hz", 9, "control period");
    expect_error(im + "carrier_hz = 6100.0\n", "control.carrier_hz", 8, "whole number");
    expect_error("[motor]\ntype = \"im\"\n[inverter]\ntopology = \"sstp\"\n[control]\nscheme = \"sfvc\"\n",
                 "control.rotor_flux_ref_wb", 0, "eq. 18");
    expect_error(im + "sfvc_kp_per_s = 1e5\n", "control.sfvc_kp_per_s", 8, "deadbeat");
    expect_error("[control]\ncarrier_hz = 5000.0\n", "control.carrier_hz", 2, "not a setting of the PM drive");
}

TEST(Scenario, TomlSyntaxErrorNamesTheLine)
{
    expect_error("[motor]\nrs_ohm = 0.466\nls_h = \n", "", 3, "TOML syntax error");
    expect_error("[motor]\nrs_ohm = 0.466\nrs_ohm = 0.5\n", "", 3, "TOML syntax error");
}

TEST(Scenario, MissingValuesAndInconsistentCombinations)
{
    // open_loop needs a voltage table and the ideal inverter.
    expect_error("[inverter]\ntopology = \"ideal\"\n[control]\nmode = \"open_loop\"\n", "control.voltage_csv", 0,
                 "missing value");
    expect_error("[control]\nmode = \"open_loop\"\nvoltage_csv = \"v.csv\"\n", "inverter.topology", 0,
                 "\"ideal\"");
    expect_error("[inverter]\ntopology = \"ideal\"\n", "inverter.topology", 2, "open_loop");
    expect_error("[inverter]\ntopology = \"sstp\"\n[control]\nimplementation = \"reference\"\nestimator = \"voltage\"\n"
                 "compensation = \"proposed\"\n",
                 "control.compensation", 6, "reference controller");
    expect_error("[control]\nvoltage_csv = \"\"\n", "control.voltage_csv", 2, "missing value");
}

TEST(Scenario, OpenLoopCsvIsResolvedRelativeToTheScenarioAndChecked)
{
    const auto d = temp_dir();
    {
        std::ofstream(d / "v.csv") << "t_s,v_alpha_v,v_beta_v\n0,1,0\n0.001,0,1\n";
        std::ofstream(d / "ol.toml") << "[inverter]\ntopology = \"ideal\"\n[control]\nmode = \"open_loop\"\n"
                                        "voltage_csv = \"v.csv\"\n";
    }
    Scenario s;
    Diagnostics diag;
    ASSERT_TRUE(load_scenario((d / "ol.toml").string(), {}, &s, &diag)) << diag.text();
    EXPECT_EQ(std::filesystem::path(s.control.voltage_csv), (d / "v.csv").lexically_normal());

    // Bad tables: each error names the CSV file and line, under the key control.voltage_csv.
    auto bad = [&](const std::string& csv, const std::string& what) {
        std::ofstream(d / "v.csv") << csv;
        Scenario s2;
        Diagnostics d2;
        EXPECT_FALSE(load_scenario((d / "ol.toml").string(), {}, &s2, &d2)) << csv;
        const std::string t = d2.text();
        EXPECT_NE(t.find("control.voltage_csv"), std::string::npos) << t;
        EXPECT_NE(t.find("ol.toml:5:"), std::string::npos) << t;
        EXPECT_NE(t.find(what), std::string::npos) << t;
    };
    bad("t,va,vb\n0,1,0\n", "v.csv:1: expected the header");
    bad("t_s,v_alpha_v,v_beta_v\n0,1,0\n0,2,0\n", "v.csv:3: t_s must increase");
    bad("t_s,v_alpha_v,v_beta_v\n0,1,x\n", "v.csv:2: column 3");
    bad("t_s,v_alpha_v,v_beta_v\n0.5,1,0\n", "v.csv:2: the first row must start");
    bad("t_s,v_alpha_v,v_beta_v\n", "no data rows");
    std::vector<VoltageRow> rows;
    std::string e;
    EXPECT_FALSE(load_voltage_csv((d / "missing.csv").string(), &rows, &e));
    EXPECT_NE(e.find("missing.csv: cannot open"), std::string::npos) << e;
    std::filesystem::remove_all(d);
}

TEST(Scenario, MissingFileIsReported)
{
    Scenario s;
    Diagnostics d;
    EXPECT_FALSE(load_scenario("/nonexistent/x.toml", {}, &s, &d));
    EXPECT_NE(d.text().find("/nonexistent/x.toml: no such file"), std::string::npos) << d.text();
}

TEST(Scenario, DirectoryIsNotAScenario)
{
    Scenario s;
    Diagnostics d;
    const std::string dir = std::filesystem::temp_directory_path().string();
    EXPECT_FALSE(load_scenario(dir, {}, &s, &d));
    EXPECT_NE(d.text().find(dir + ": not a regular file"), std::string::npos) << d.text();
}

TEST(Scenario, WarningsDoNotReject)
{
    Scenario s;
    Diagnostics d;
    ASSERT_TRUE(parse_scenario("[inverter]\ntopology = \"fstp\"\n[control]\ntable = \"st-a\"\n", "w.toml", {}, &s, &d));
    ASSERT_EQ(d.warnings.size(), 1u);
    EXPECT_NE(d.warnings[0].find("control.table"), std::string::npos);
}

TEST(Scenario, EveryKeyIsDocumented)
{
    // docs/sil.md carries the key table; a key added to the schema but not documented fails here.
    std::ifstream f(std::string(DTC_SOURCE_DIR) + "/docs/sil.md");
    ASSERT_TRUE(f.good());
    std::stringstream ss;
    ss << f.rdbuf();
    const std::string doc = ss.str();
    const auto keys = scenario_keys();
    EXPECT_GT(keys.size(), 60u);
    // The table is the output of `dtc-sil keys`, verbatim (units, defaults and ranges included),
    // and so is every other copy of it in the file (found by its header line).
    const std::string md = scenario_keys_markdown();
    EXPECT_NE(doc.find(md), std::string::npos)
        << "docs/sil.md section 4 is out of date: paste the output of `dtc-sil keys`";
    const std::string header = md.substr(0, md.find('\n') + 1);
    int copies = 0;
    for (std::size_t at = doc.find(header); at != std::string::npos; at = doc.find(header, at + 1)) {
        ++copies;
        EXPECT_EQ(doc.compare(at, md.size(), md), 0)
            << "the key table at offset " << at << " of docs/sil.md is out of date: paste `dtc-sil keys`";
    }
    EXPECT_GE(copies, 1);
    for (const KeyDoc& k : keys) {
        EXPECT_NE(doc.find("`" + k.name + "`"), std::string::npos) << k.name << " missing from docs/sil.md";
    }
}

TEST(Scenario, SpeedPiGainsGiveTheRequestedBandwidth)
{
    // Plant 1/(J s); L(jw) = C(jw)/(J jw). At w = wc: |L| = sqrt(1 + 1/16), phase margin 76 deg.
    const double j = 1e-4, bw = 10.0, wc = 2.0 * 3.14159265358979 * bw;
    const SpeedPiGains g = speed_pi_gains(j, bw);
    const std::complex<double> s(0.0, wc);
    const std::complex<double> l = (g.kp_nm_per_rad_s + g.ki_nm_per_rad / s) / (j * s);
    EXPECT_NEAR(std::abs(l), std::sqrt(1.0 + 1.0 / 16.0), 1e-9);
    EXPECT_NEAR(180.0 + std::arg(l) * 180.0 / 3.14159265358979, 75.96, 0.01);
}

TEST(Scenario, FirmwareSiConfigCarriesTheScenario)
{
    Scenario s;
    ASSERT_EQ(errors_of(kGood, {}, &s), "");
    const dtc_config_si_t c = firmware_si_config(s);
    EXPECT_EQ(c.topology, DTC_TOPO_FSTP);
    EXPECT_EQ(c.estimator, DTC_EST_VOLTAGE);
    EXPECT_EQ(c.compensation, DTC_COMP_FSTP_PROPOSED);
    Scenario ss;
    ASSERT_EQ(errors_of(kGood, {"inverter.topology=sstp"}, &ss), "");
    EXPECT_EQ(firmware_si_config(ss).compensation, DTC_COMP_SSTP_PROPOSED); // Hoang Table III per leg
    EXPECT_EQ(c.mode, DTC_MODE_SPEED);
    EXPECT_DOUBLE_EQ(c.rs_ohm, 0.466);
    EXPECT_DOUBLE_EQ(c.v_ce_v, 0.9);
    EXPECT_DOUBLE_EQ(c.kp_nm_s_rad, speed_pi_gains(s.motor.j_kgm2, s.control.speed_bw_hz).kp_nm_per_rad_s);
}

TEST(Scenario, ShippedScenariosAreValid)
{
    int n = 0;
    for (const auto& e : std::filesystem::directory_iterator(std::string(DTC_SOURCE_DIR) + "/tools/scenarios")) {
        if (e.path().extension() != ".toml") {
            continue;
        }
        ++n;
        Scenario s;
        Diagnostics d;
        EXPECT_TRUE(load_scenario(e.path().string(), {}, &s, &d)) << d.text();
        EXPECT_TRUE(d.warnings.empty()) << d.text();
        if (s.control.mode != ControlMode::OpenLoop && s.motor.type == MotorType::Im) {
            // The IM drive's rig (plant_defaults.h): 311 V link (the second machine's: its rectified
            // 400 V, 565 V), 40 us, the improved estimator.
            const bool second = e.path().filename() == "im_second_machine.toml";
            EXPECT_DOUBLE_EQ(s.inverter.vdc_v, second ? 565.0 : 311.0) << e.path();
            EXPECT_DOUBLE_EQ(s.ts_s, 40e-6) << e.path();
            EXPECT_EQ(s.control.estimator, Estimator::Improved) << e.path();
        } else if (s.control.mode != ControlMode::OpenLoop) {
            // The paper's operating point: 1500 rpm, Hoang Table VIII/IV values, bands zero.
            EXPECT_DOUBLE_EQ(s.control.speed_ref_rpm, 1500.0) << e.path();
            EXPECT_DOUBLE_EQ(s.control.torque_band_nm, 0.0);
            EXPECT_DOUBLE_EQ(s.control.flux_band_wb, 0.0);
            EXPECT_DOUBLE_EQ(s.inverter.vdc_v, 70.0);
            // Total load at 1500 rpm: friction + generator = 0.075 + {0, 0.075, 0.225} N*m.
            const double friction = s.motor.b_nm_s_per_rad * 1500.0 * 2.0 * 3.14159265358979 / 60.0;
            const double total = friction + (s.load.type == LoadType::Generator ? s.load.torque_nm : 0.0);
            const std::string f = e.path().filename().string();
            const double expect = f.find("_full") != std::string::npos   ? 0.3
                                  : f.find("_half") != std::string::npos ? 0.15
                                                                         : 0.075;
            EXPECT_NEAR(total, expect, 1e-4) << f;
        }
    }
    EXPECT_EQ(n, 23); // 15 paper operating points, the mid-point study, the open-loop example, the IM
                      // start (open loop), the IM drive, the second IM, the IM on the four-switch
                      // inverter, the PM indirect torque control on both inverters
}

TEST(Scenario, FuzzedTomlAndSetNeverCrashOrHang)
{
    // Random byte strings, random TOML-ish fragments and random valid keys with extreme values:
    // every input is either accepted with finite numbers or refused with a message; bounded time.
    std::mt19937_64 rng(20261123);
    const auto t0 = std::chrono::steady_clock::now();
    const std::string alphabet = "[]=\".,#\n\t -+eE0123456789abcdefxyz_\\'{}:";
    for (int i = 0; i < 3000; ++i) {
        std::string text;
        const std::size_t n = rng() % 200;
        for (std::size_t k = 0; k < n; ++k) {
            text += (i % 2 == 0) ? static_cast<char>(rng() & 0xff) : alphabet[rng() % alphabet.size()];
        }
        Scenario s;
        Diagnostics d;
        const bool ok = parse_scenario(text, "fuzz.toml", {}, &s, &d);
        EXPECT_EQ(ok, d.errors.empty());
        if (!ok) {
            EXPECT_FALSE(d.text().empty());
        }
    }
    const std::vector<std::string> extremes = {"0",   "-0",  "1e-300", "-1e-300", "1e300", "-1e308", "1e309",
                                               "nan", "inf", "-inf",   "9e18",    "-9e18", "0x10",   "",
                                               "\"\"", "[1,2,3]", "[1e308, -1e308, 0]", "true", "1_000"};
    const auto keys = scenario_keys();
    for (int i = 0; i < 1000; ++i) {
        // Random bytes as --set, with and without a valid key in front.
        std::string junk;
        const std::size_t n = rng() % 40;
        for (std::size_t k = 0; k < n; ++k) {
            junk += static_cast<char>(rng() & 0xff);
        }
        const std::string o = (i % 2 == 0) ? junk : keys[rng() % keys.size()].name + "=" + junk;
        Scenario s;
        Diagnostics d;
        if (!parse_scenario("ts_s = 50e-6\n", "fuzz.toml", {o}, &s, &d)) {
            EXPECT_NE(d.text().find("--set #1"), std::string::npos) << o << ": " << d.text();
        }
    }
    for (int i = 0; i < 3000; ++i) {
        std::vector<std::string> sets;
        for (int k = 0; k < 3; ++k) {
            sets.push_back(keys[rng() % keys.size()].name + "=" + extremes[rng() % extremes.size()]);
        }
        Scenario s;
        Diagnostics d;
        const bool ok = parse_scenario("ts_s = 50e-6\n", "fuzz.toml", sets, &s, &d);
        if (ok) {
            // Accepted numbers are finite and inside the schema (the run loop relies on it).
            EXPECT_TRUE(std::isfinite(s.duration_s) && std::isfinite(s.ts_s) && std::isfinite(s.max_step_s) &&
                        std::isfinite(s.motor.rs_ohm) && std::isfinite(s.load.torque_nm))
                << ::testing::PrintToString(sets);
            EXPECT_GE(s.ts_s / s.max_step_s, 1.0);
            EXPECT_LE(s.ts_s / s.max_step_s, 1.0e4);
        } else {
            EXPECT_FALSE(d.text().empty());
        }
    }
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(30));
}

namespace {
// Every name of a variant's to-string table parses back to the same enum value, and the key's
// allowed values in `dtc-sil keys` are exactly that table.
template <typename E> void expect_variant_table(const char* key)
{
    const auto& names = VariantNames<E>::names;
    std::string allowed;
    for (std::size_t i = 0; i < names.size(); ++i) {
        E e{};
        ASSERT_TRUE(parse_variant(names[i], &e)) << names[i];
        EXPECT_EQ(static_cast<std::size_t>(e), i);
        EXPECT_EQ(to_string(e), names[i]);
        allowed += (allowed.empty() ? "" : " \\| ") + ("\"" + std::string(names[i]) + "\"");
    }
    E untouched = static_cast<E>(0);
    EXPECT_FALSE(parse_variant("no-such-variant", &untouched));
    bool found = false;
    for (const KeyDoc& k : scenario_keys()) {
        if (k.name == key) {
            found = true;
            EXPECT_EQ(k.range, allowed) << key;
        }
    }
    EXPECT_TRUE(found) << key;
}
} // namespace

TEST(Scenario, VariantsHaveOneToStringTable)
{
    expect_variant_table<MotorType>("motor.type");
    expect_variant_table<Topology>("inverter.topology");
    expect_variant_table<LoadType>("load.type");
    expect_variant_table<ControlMode>("control.mode");
    expect_variant_table<Implementation>("control.implementation");
    expect_variant_table<Estimator>("control.estimator");
    expect_variant_table<Compensation>("control.compensation");
    expect_variant_table<SwitchingTable>("control.table");
    expect_variant_table<Scheme>("control.scheme");
    expect_variant_table<SpeedSensor>("control.speed_sensor");
    // Parsed once at load, with the key and line named when the text names no variant.
    Scenario s;
    const std::string e = errors_of("duration_s = 0.1\n[inverter]\ntopology = \"sixstep\"\n", {}, &s);
    EXPECT_NE(e.find(":3:"), std::string::npos) << e;
    EXPECT_NE(e.find("inverter.topology: expected one of \"ideal\", \"sstp\", \"fstp\", got \"sixstep\""),
              std::string::npos)
        << e;
}

TEST(Scenario, ImLawKeysSelectTheImLawAndAreRefusedByName)
{
    // motor.type = "im" in speed/torque mode selects the IM law with the IM rig's defaults; every
    // IM-law key reaches the converter's struct.
    const std::string im = "duration_s = 0.1\nmetrics_window_s = 0.05\n[motor]\ntype = \"im\"\n[control]\nmode = \"torque\"\n";
    Scenario s;
    ASSERT_EQ(errors_of(im + "table = \"speed-dependent\"\nscheme = \"dsc\"\nspeed_sensor = \"none\"\n"
                             "flux_weakening = true\nrotor_flux_ref_wb = 0.5\nobserver_tau_s = 0.02\n"
                             "observer_tau_high_s = 0.1\nobserver_tau_lo_rpm = 100\nobserver_tau_hi_rpm = 300\n"
                             "[firmware]\nrs_ohm = 0.5\nrr_ohm = 0.45\nlm_h = 0.05\n",
                        {}, &s),
              "");
    EXPECT_EQ(s.control.estimator, Estimator::Improved); // the IM's default estimator
    EXPECT_DOUBLE_EQ(s.ts_s, PLANT_DEF_IM_TS_S);
    EXPECT_DOUBLE_EQ(s.inverter.vdc_v, PLANT_DEF_IM_VDC_V);
    const dtc_config_si_t c = firmware_si_config(s);
    EXPECT_EQ(c.law, DTC_LAW_IM_DSC); // motor.type = "im" with control.scheme = "dsc"
    EXPECT_EQ(c.estimator, DTC_EST_IMPROVED);
    EXPECT_EQ(c.sstp_table, DTC_ST_SPEED);
    EXPECT_EQ(c.speed_sensor, DTC_SPEED_NONE);
    EXPECT_EQ(c.flux_weakening, 1);
    EXPECT_DOUBLE_EQ(c.psir_ref_wb, 0.5);
    EXPECT_DOUBLE_EQ(c.tau_lo_s, 0.02);
    EXPECT_DOUBLE_EQ(c.tau_hi_s, 0.1);
    EXPECT_DOUBLE_EQ(c.tau_w_lo_rpm, 100.0);
    EXPECT_DOUBLE_EQ(c.tau_w_hi_rpm, 300.0);
    EXPECT_DOUBLE_EQ(c.rs_ohm, 0.5);  // firmware.rs_ohm applies to the IM
    EXPECT_DOUBLE_EQ(c.rr_ohm, 0.45);
    EXPECT_DOUBLE_EQ(c.lm_h, 0.05);
    EXPECT_DOUBLE_EQ(c.lls_h, PLANT_DEF_IM_LLS_H); // not given: the plant's
    dtc_config_t cfg;
    char msg[256] = {0};
    EXPECT_EQ(dtc_config_from_si(&c, &cfg, msg, sizeof msg), DTC_SI_OK) << msg;
    Scenario d;
    ASSERT_EQ(errors_of(im, {}, &d), "");
    EXPECT_DOUBLE_EQ(firmware_si_config(d).rs_ohm, PLANT_DEF_IM_RS_OHM);
    EXPECT_DOUBLE_EQ(firmware_si_config(d).tau_lo_s, PLANT_DEF_IM_OBSERVER_TAU_S);

    // Refusals name the key and the line.
    expect_error(im + "estimator = \"current\"\n", "control.estimator", 7, "needs a magnet");
    expect_error(im + "implementation = \"reference\"\n", "control.implementation", 7);
    // the four-switch inverter runs the switching-table DTC only (Hoang Table II, im_dtc_fstp.c)
    ASSERT_EQ(errors_of(im + "[inverter]\ntopology = \"fstp\"\n", {}, &d), "");
    expect_error(im + "scheme = \"dsc\"\n[inverter]\ntopology = \"fstp\"\n", "inverter.topology", 9, "six-switch");
    expect_error(im + "table = \"st-e\"\n", "control.table", 7, "expected one of");
    expect_error(im + "scheme = \"dtcx\"\n", "control.scheme", 7, "expected one of");
    expect_error(im + "speed_sensor = \"resolver\"\n", "control.speed_sensor", 7, "expected one of");
    expect_error(im + "observer_tau_s = 1e-5\n", "control.observer_tau_s", 7, "longer than the control period");
    expect_error(im + "rotor_flux_ref_wb = -0.1\n", "control.rotor_flux_ref_wb", 7, "impossible");
    expect_error(im + "delay_comp = true\n", "control.delay_comp", 7, "not a setting of the induction-machine");
    expect_error(im + "[firmware]\nls_h = 0.01\n", "firmware.ls_h", 8, "not a setting");
    // The IM-law keys are refused for the PM machine.
    const std::string pm = "duration_s = 0.1\n[control]\n";
    expect_error(pm + "estimator = \"improved\"\n", "control.estimator", 3, "induction machine");
    expect_error(pm + "table = \"speed-dependent\"\n", "control.table", 3, "induction-machine table");
    expect_error(pm + "scheme = \"dsc\"\n", "control.scheme", 3, "is an induction-machine scheme");
    // and the PM machine's indirect torque control for the IM
    expect_error(im + "scheme = \"itc\"\n", "control.scheme", 7, "PM machine's indirect torque control");
    expect_error(pm + "rotor_flux_ref_wb = 0.5\n", "control.rotor_flux_ref_wb", 3, "not a setting of the PM");
    expect_error("duration_s = 0.1\n[firmware]\nrr_ohm = 0.5\n", "firmware.rr_ohm", 3, "not a setting of the PM");
}

TEST(Scenario, BadImFirmwareConfigurationIsRefusedNamingTheKey)
{
    // A value the schema accepts but the converter cannot represent (a magnetisation longer than
    // 65535 periods): the scenario check calls the converter, which refuses it; the refused
    // member's row (dtc_si_params.h) names the scenario key, found with its line.
    expect_error("duration_s = 0.01\nmetrics_window_s = 0.005\n[motor]\ntype = \"im\"\n[control]\nmode = \"torque\"\n"
                 "magnetise_frac = 0.999999999\n",
                 "control.magnetise_frac", 7, "converter field magn_frac");
    // A member set from several keys names the one the scenario sets.
    expect_error("duration_s = 0.01\nmetrics_window_s = 0.005\n[motor]\ntype = \"im\"\n[control]\n"
                 "observer_tau_lo_rpm = 300\nobserver_tau_hi_rpm = 100\n",
                 "control.observer_tau_hi_rpm", 7, "must not be below tau_w_lo_rpm");
}

TEST(Scenario, FaultKeysAreParsedAndBadValuesNameKeyAndLine)
{
    Scenario s;
    EXPECT_EQ(errors_of("ts_s = 50e-6\n[inverter]\nreconfig_relay = true\nrelay_delay_s = 0.01\n[faults]\n"
                        "time_s = 0.3\nleg_open = \"b\"\nswitch_short = \"c_lower\"\nencoder_lost = true\n"
                        "current_sensor_stuck = \"a\"\ncurrent_sensor_code = 100\ndc_sag = 0.5\n",
                        {}, &s),
              "");
    EXPECT_TRUE(s.inverter.reconfig_relay);
    EXPECT_DOUBLE_EQ(s.inverter.relay_delay_s, 0.01);
    EXPECT_DOUBLE_EQ(s.faults.time_s, 0.3);
    EXPECT_EQ(s.faults.leg_open, sil::FaultPhase::B);
    EXPECT_EQ(s.faults.switch_short, sil::FaultSwitch::CLower);
    EXPECT_TRUE(s.faults.encoder_lost);
    EXPECT_EQ(s.faults.current_sensor_stuck, sil::FaultPhase::A);
    EXPECT_EQ(s.faults.current_sensor_code, 100);
    EXPECT_DOUBLE_EQ(s.faults.dc_sag, 0.5);
    EXPECT_TRUE(s.faults.any());
    // Defaults: no fault, the relay not fitted, its delay the datasheet's operate time.
    Scenario d;
    EXPECT_EQ(errors_of("ts_s = 50e-6\n", {}, &d), "");
    EXPECT_FALSE(d.faults.any());
    EXPECT_FALSE(d.inverter.reconfig_relay);
    EXPECT_DOUBLE_EQ(d.inverter.relay_delay_s, 15e-3);
    EXPECT_EQ(d.faults.current_sensor_code, 2048);

    expect_error("ts_s = 50e-6\n[faults]\ntime_s = 0.3\nleg_open = \"d\"\n", "faults.leg_open", 4);
    expect_error("ts_s = 50e-6\n[faults]\ntime_s = 0.3\nswitch_open = \"a_middle\"\n", "faults.switch_open", 4);
    expect_error("ts_s = 50e-6\n[faults]\ntime_s = 0.3\ncurrent_sensor_stuck = \"a\"\ncurrent_sensor_code = 4096\n",
                 "faults.current_sensor_code", 5);
    expect_error("ts_s = 50e-6\n[faults]\ntime_s = 0.3\ndc_sag = 0\n", "faults.dc_sag", 4);
    expect_error("ts_s = 50e-6\n[faults]\ntime_s = -1\nencoder_lost = true\n", "faults.time_s", 3);
    expect_error("ts_s = 50e-6\n[faults]\nencoder_lost = 1\n", "faults.encoder_lost", 3);
    expect_error("ts_s = 50e-6\n[faults]\nencoder_lost = true\n", "faults.time_s", 0, "missing value");
    expect_error("ts_s = 50e-6\n[inverter]\nrelay_delay_s = 2\n", "inverter.relay_delay_s", 3);
    expect_error("ts_s = 50e-6\n[inverter]\ntopology = \"fstp\"\nreconfig_relay = true\n", "inverter.reconfig_relay",
                 4, "six-switch");
    expect_error("ts_s = 50e-6\n[inverter]\ntopology = \"fstp\"\n[faults]\ntime_s = 0.2\nswitch_short = \"a_upper\"\n",
                 "faults.switch_short", 6, "no leg A");
    expect_error("ts_s = 50e-6\n[faults]\ntime_s = 0.2\nswitch_short = \"a_upper\"\nswitch_open = \"b_upper\"\n",
                 "faults.switch_short", 4, "one switch fault");
}

// --overlay: a TOML fragment over the scenario, before --set; its errors name the overlay's line.
TEST(Scenario, OverlayAppliesOverTheScenarioAndUnderSet)
{
    const std::string base = "duration_s = 0.5\n[firmware]\nrs_ohm = 0.4\nls_h = 3e-3\n";
    const OverlayText ov{"identified.toml", "[firmware]\n# identified\nrs_ohm = 0.47\npsi_m_wb = 0.09\n"};
    Scenario s;
    Diagnostics d;
    ASSERT_TRUE(parse_scenario(base, "case.toml", {}, &s, &d, {ov})) << d.text();
    EXPECT_EQ(s.firmware.value.at("rs_ohm"), 0.47);      // overlay over the scenario
    EXPECT_EQ(s.firmware.value.at("ls_h"), 3e-3);      // the scenario's where the overlay says nothing
    EXPECT_EQ(s.firmware.value.at("psi_m_wb"), 0.09);
    EXPECT_EQ(s.origin.at("firmware.rs_ohm"), "identified.toml:3:10");
    Scenario s2;
    Diagnostics d2;
    ASSERT_TRUE(parse_scenario(base, "case.toml", {"firmware.rs_ohm=0.5"}, &s2, &d2, {ov})) << d2.text();
    EXPECT_EQ(s2.firmware.value.at("rs_ohm"), 0.5);    // --set last
}

TEST(Scenario, OverlayErrorsNameTheOverlayFileAndLine)
{
    const std::string base = "duration_s = 0.1\n";
    auto errs = [&](const std::string& text) {
        Scenario s;
        Diagnostics d;
        EXPECT_FALSE(parse_scenario(base, "case.toml", {}, &s, &d, {OverlayText{"ov.toml", text}}));
        return d.text();
    };
    EXPECT_NE(errs("[firmware]\n\nbogus_key = 1\n").find("ov.toml:3:1: firmware.bogus_key: unknown key"),
              std::string::npos);
    EXPECT_NE(errs("[firmware]\nrs_ohm = -1\n").find("ov.toml:2:10: firmware.rs_ohm"), std::string::npos);
    EXPECT_NE(errs("[firmware\n").find("ov.toml:1:"), std::string::npos);
    Diagnostics d;
    OverlayText o;
    EXPECT_FALSE(read_overlay("/nonexistent/identified.toml", &o, &d));
    EXPECT_NE(d.text().find("/nonexistent/identified.toml: --overlay: no such file"), std::string::npos);
}
