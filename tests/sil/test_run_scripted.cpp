// The run loop and the dtc-sil command line against the scripted plant: the pipeline from plant
// state to metrics.json / trace.csv, the open-loop voltage hold, and all-or-nothing output.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli_capture.hpp"
#include "controller_adapter.hpp"
#include "hal_host.hpp"
#include "run.hpp"
#include "scripted_plant.hpp"

namespace fs = std::filesystem;
using sil::kPi;

namespace {

class RunScripted : public ::testing::Test {
protected:
    fs::path dir;
    void SetUp() override
    {
        scripted::reset();
        dir = fs::temp_directory_path() /
              ("dtc_sil_run_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir);
        fs::create_directories(dir);
        // 1500 rpm, p = 1: 25 Hz; phase amplitudes 2.0 / 2.1 / 2.2 A with a 4 % 5th harmonic;
        // torque 0.3 N*m +- 0.05 N*m square ripple at 1 kHz.
        scripted::set_script([](double t, plant_state_t* s) {
            const double th = 2.0 * kPi * 25.0 * t;
            const double amp[3] = {2.0, 2.1, 2.2};
            double i[3];
            for (int p = 0; p < 3; ++p) {
                const double a = th - p * 2.0 * kPi / 3.0;
                i[p] = amp[p] * (std::cos(a) + 0.04 * std::cos(5.0 * a));
            }
            s->i_a = i[0];
            s->i_b = i[1];
            s->i_c = i[2];
            s->theta_m_rad = th;
            s->theta_e_rad = std::fmod(th, 2.0 * kPi);
            s->speed_rpm = 1500.0;
            s->te_nm = 0.3 + ((static_cast<long>(std::floor(t * 2000.0 + 1e-6)) % 2) == 0 ? 0.05 : -0.05);
            s->vdc_v = 70.0;
            s->psi_alpha_wb = 0.0928 * std::cos(th);
            s->psi_beta_wb = 0.0928 * std::sin(th);
        });
        std::ofstream(dir / "v.csv") << "t_s,v_alpha_v,v_beta_v\n0,1,-1\n0.000125,2,-2\n0.01,3,-3\n";
        std::ofstream(dir / "ol.toml") << "duration_s = 0.25\nmetrics_window_s = 0.2\n"
                                          "[inverter]\ntopology = \"ideal\"\n"
                                          "[control]\nmode = \"open_loop\"\nvoltage_csv = \"v.csv\"\n";
    }
    void TearDown() override
    {
        scripted::reset();
        fs::remove_all(dir);
    }
    int cli(std::vector<std::string> args, std::string* out = nullptr, std::string* err = nullptr)
    {
        return sil_test::run_cli(std::move(args), out, err);
    }
};

nlohmann::json read_json(const fs::path& p)
{
    std::ifstream f(p);
    return nlohmann::json::parse(f);
}
} // namespace

TEST_F(RunScripted, OpenLoopRunWritesMetricsOfThePlantSignals)
{
    std::string out, err;
    ASSERT_EQ(cli({"run", (dir / "ol.toml").string(), "--out", (dir / "res").string()}, &out, &err), 0) << err;
    const auto j = read_json(dir / "res" / "metrics.json");
    for (const char* key : {"sim_time_s", "wall_time_s", "isr_count", "fundamental_a", "imbalance_pct", "thd_pct",
                            "thd_total_pct", "torque_mean_nm", "torque_est_mean_nm", "trf_pct", "trf_est_pct",
                            "speed_mean_rpm", "switching_freq_hz", "flux_est_error_rms_pct", "fault"}) {
        EXPECT_TRUE(j.contains(key)) << key;
    }
    EXPECT_EQ(j["isr_count"], 5000);
    EXPECT_NEAR(j["sim_time_s"].get<double>(), 0.25, 1e-12);
    EXPECT_NEAR(j["fundamental_a"][0].get<double>(), 2.0, 1e-6);
    EXPECT_NEAR(j["fundamental_a"][1].get<double>(), 2.1, 1e-6);
    EXPECT_NEAR(j["fundamental_a"][2].get<double>(), 2.2, 1e-6);
    EXPECT_NEAR(j["imbalance_pct"].get<double>(), 10.0, 1e-4);
    EXPECT_NEAR(j["thd_pct"][1].get<double>(), 4.0, 1e-6);
    EXPECT_NEAR(j["thd_total_pct"].get<double>(), 4.0, 1e-6);
    EXPECT_NEAR(j["torque_mean_nm"].get<double>(), 0.3, 1e-9);
    EXPECT_NEAR(j["trf_pct"].get<double>(), 100.0 * 0.1 / 0.3, 1e-9);
    EXPECT_NEAR(j["speed_mean_rpm"].get<double>(), 1500.0, 1e-9);
    EXPECT_EQ(j["metrics_window"]["electrical_periods"], 5);
    EXPECT_TRUE(j["torque_est_mean_nm"].is_null()); // open loop: no estimator
    EXPECT_TRUE(j["switching_freq_hz"].is_null());  // ideal inverter: no switches
    EXPECT_EQ(j["fault"], "none");
    EXPECT_NE(out.find("fundamental A/B/C 2.000 / 2.100 / 2.200 A"), std::string::npos) << out;

    // The voltage table is held per period: rows at 0 and 125 us -> periods 0-2 get row 0, 3.. row 1.
    const auto& adv = scripted::log().advances;
    ASSERT_EQ(adv.size(), 5000u);
    EXPECT_DOUBLE_EQ(adv[0].v_alpha_v, 1.0);
    EXPECT_DOUBLE_EQ(adv[2].v_alpha_v, 1.0);
    EXPECT_DOUBLE_EQ(adv[3].v_alpha_v, 2.0);
    EXPECT_DOUBLE_EQ(adv[199].v_beta_v, -2.0);
    EXPECT_DOUBLE_EQ(adv[200].v_beta_v, -3.0);
    EXPECT_DOUBLE_EQ(adv[4999].v_alpha_v, 3.0); // held after the last row
    // Plant parameters come from the scenario (defaults: Hoang Table VIII/IV, ideal inverter here).
    // Two plants: the validation pass that `check` also runs (refusals before any file exists),
    // then the run itself; both from the same scenario.
    ASSERT_EQ(scripted::log().created.size(), 2u);
    EXPECT_EQ(scripted::log().created[1].inverter, PLANT_INVERTER_IDEAL);
    EXPECT_DOUBLE_EQ(scripted::log().created[1].rs_ohm, 0.466);
}

TEST_F(RunScripted, TraceHasTheDocumentedColumnsOneRowPerDecimatedIsr)
{
    ASSERT_EQ(cli({"run", (dir / "ol.toml").string(), "--out", (dir / "res").string(), "--decimate", "10", "-q"}), 0);
    std::ifstream f(dir / "res" / "trace.csv");
    std::string header;
    std::getline(f, header);
    EXPECT_EQ(header.rfind("t_s,i_a_a,i_b_a,i_c_a,i_alpha_a,i_beta_a,torque_nm,torque_est_nm,psi_alpha_wb,psi_beta_wb,"
                           "psi_alpha_est_wb,psi_beta_est_wb,speed_rpm,sa,sb,sc,vdc_v",
                           0),
              0u);
    int rows = 0;
    std::string line, second;
    while (std::getline(f, line)) {
        if (rows == 1) {
            second = line;
        }
        ++rows;
    }
    EXPECT_EQ(rows, 500);
    // Row 1 = ISR 10 at 0.5 ms: the plant clock's own double (within an ulp or two of 0.0005),
    // written in its shortest round-trip form.
    EXPECT_NEAR(std::stod(second.substr(0, second.find(','))), 0.0005, 1e-15);
}

TEST_F(RunScripted, RerunWithoutTraceLeavesNoStaleTrace)
{
    ASSERT_EQ(cli({"run", (dir / "ol.toml").string(), "--out", (dir / "res").string(), "-q"}), 0);
    ASSERT_TRUE(fs::exists(dir / "res" / "trace.csv"));
    std::ofstream(dir / "res" / "notes.txt") << "user file";
    ASSERT_EQ(cli({"run", (dir / "ol.toml").string(), "--out", (dir / "res").string(), "-q", "--no-trace"}), 0);
    EXPECT_FALSE(fs::exists(dir / "res" / "trace.csv"));
    EXPECT_TRUE(fs::exists(dir / "res" / "metrics.json"));
    EXPECT_TRUE(fs::exists(dir / "res" / "notes.txt")); // only dtc-sil's own files are managed
}

TEST_F(RunScripted, SetOverridesReachThePlant)
{
    ASSERT_EQ(cli({"run", (dir / "ol.toml").string(), "--out", (dir / "res").string(), "--no-trace", "-q", "--set",
                   "motor.rs_ohm=0.5", "--set", "load.type=speed", "--set", "load.speed_rpm=700"}),
              0);
    EXPECT_FALSE(fs::exists(dir / "res" / "trace.csv"));
    EXPECT_TRUE(fs::exists(dir / "res" / "metrics.json"));
    const auto& p = scripted::log().created.at(0);
    EXPECT_DOUBLE_EQ(p.rs_ohm, 0.5);
    EXPECT_EQ(p.load, PLANT_LOAD_SPEED);
    EXPECT_DOUBLE_EQ(p.load_speed_rpm, 700.0);
}

TEST_F(RunScripted, BadScenarioExitsNonZeroNamingKeyAndWritesNothing)
{
    std::ofstream(dir / "bad.toml") << "duration_s = 0.25\n[motor]\nrs_ohm = -0.466\n";
    std::string out, err;
    EXPECT_EQ(cli({"run", (dir / "bad.toml").string(), "--out", (dir / "res").string()}, &out, &err), 1);
    EXPECT_NE(err.find("bad.toml:3:10: motor.rs_ohm"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(dir / "res"));
    EXPECT_EQ(fs::directory_iterator(dir) != fs::directory_iterator(), true);
    for (const auto& e : fs::directory_iterator(dir)) {
        EXPECT_EQ(e.path().filename().string().find(".partial"), std::string::npos);
    }
    EXPECT_EQ(cli({"run", (dir / "ol.toml").string(), "--out", (dir / "res").string(), "--set", "inverter.vdc=70"},
                  &out, &err),
              1);
    EXPECT_NE(err.find("inverter.vdc: unknown key"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(dir / "res"));
    EXPECT_TRUE(scripted::log().created.empty()); // nothing was even built
}

TEST_F(RunScripted, FailureAfterValidationLeavesPreviousResultsUntouched)
{
    ASSERT_EQ(cli({"run", (dir / "ol.toml").string(), "--out", (dir / "res").string(), "-q"}), 0);
    const auto before = fs::last_write_time(dir / "res" / "metrics.json");
    scripted::fail_next_create("psi_m_wb out of range");
    std::string err;
    // A plant refusal is found by the validation pass shared with `check`: exit 1, as a bad scenario.
    EXPECT_EQ(cli({"run", (dir / "ol.toml").string(), "--out", (dir / "res").string()}, nullptr, &err), 1);
    EXPECT_NE(err.find("plant: psi_m_wb out of range"), std::string::npos) << err;
    EXPECT_EQ(fs::last_write_time(dir / "res" / "metrics.json"), before);
    std::size_t entries = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
        (void)e;
        ++entries;
    }
    EXPECT_EQ(entries, 3u); // v.csv, ol.toml, res: no staging directory left behind
}

TEST_F(RunScripted, CheckAndKeysSubcommands)
{
    std::string out, err;
    EXPECT_EQ(cli({"check", (dir / "ol.toml").string()}, &out, &err), 0) << err;
    EXPECT_NE(out.find(": ok"), std::string::npos);
    EXPECT_EQ(cli({"keys"}, &out), 0);
    EXPECT_NE(out.find("| `control.lpf_cutoff_rad_s` | number | rad/s | 5 |"), std::string::npos) << out;
    EXPECT_EQ(cli({"run", (dir / "ol.toml").string()}, &out, &err), 1); // --out is required
    EXPECT_EQ(cli({}, &out, &err), 1);
}

TEST_F(RunScripted, LoadStepIsAppliedOnce)
{
    ASSERT_EQ(cli({"run", (dir / "ol.toml").string(), "--out", (dir / "res").string(), "-q", "--no-trace", "--set",
                   "load.step_time_s=0.1", "--set", "load.step_torque_nm=0.2", "--set", "load.type=torque"}),
              0);
    EXPECT_EQ(scripted::log().load_changes, 1);
    EXPECT_DOUBLE_EQ(scripted::log().last_load_torque_nm, 0.2);
}

namespace {
// Writes leg B = k % 2 (k = ISR count) with A = 1, C = 0, gates on, through hal.h.
class ToggleB final : public sil::Controller {
public:
    std::string init(hal_host::Harness&) override
    {
        hal_init();
        return "";
    }
    void step(hal_host::Harness&) override
    {
        hal_meas_t m;
        hal_read(&m);
        const hal_cmd_t c{1u, static_cast<std::uint16_t>(m.tick % 2u), 0u, 1u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 0u};
        hal_write(&c);
    }
    sil::ControllerEstimates estimates() const override { return {true, 0.31, 0.0928, 0.0}; }
    std::string fault() const override { return "none"; }
    bool has_estimates() const override { return true; }
};
} // namespace

TEST_F(RunScripted, AppliedLegsInTheTraceLagTheWritesByOnePeriodAndGiveTheSwitchingFrequency)
{
    sil::Scenario sc;
    sil::Diagnostics d;
    ASSERT_TRUE(sil::parse_scenario("duration_s = 0.25\nmetrics_window_s = 0.2\n[inverter]\ntopology = \"sstp\"\n"
                                    "[control]\nmode = \"torque\"\n",
                                    (dir / "t.toml").string(), {}, &sc, &d))
        << d.text();
    sil::RunOptions opt;
    opt.out_dir = (dir / "res").string();
    sil::RunResult r;
    std::string err;
    ASSERT_TRUE(sil::run_scenario_with(sc, std::make_unique<ToggleB>(), opt, &r, &err)) << err;
    // Leg B changes state every period: 1 turn-on per period shared by its 2 devices -> 10 kHz;
    // legs A and C never switch after the enabling edge: averaged over the 3 SSTP legs, 10/3 kHz.
    ASSERT_TRUE(r.metrics.switching_freq_hz.has_value());
    EXPECT_NEAR(*r.metrics.switching_freq_hz, 10000.0 / 3.0, 1e-6);
    ASSERT_TRUE(r.metrics.torque_est_mean_nm.has_value());
    EXPECT_NEAR(*r.metrics.torque_est_mean_nm, 0.31, 1e-12);
    EXPECT_TRUE(r.metrics.flux_est_error_rms_pct.has_value());
    std::ifstream f(dir / "res" / "trace.csv");
    std::string line;
    std::getline(f, line);
    for (int k = 0; k < 6 && std::getline(f, line); ++k) {
        // columns ..., speed_rpm (13), sa (14), sb (15), sc (16), vdc_v (17), en (18)
        std::vector<std::string> c;
        std::stringstream ss(line);
        for (std::string x; std::getline(ss, x, ',');) {
            c.push_back(x);
        }
        ASSERT_GE(c.size(), 18u);
        if (k == 0) {
            EXPECT_EQ(c[17], "0"); // nothing written before period 0: gates off
            continue;
        }
        EXPECT_EQ(c[13], "1") << k;
        EXPECT_EQ(c[14], std::to_string((k - 1) % 2)) << "row " << k << ": legs written in ISR " << k - 1;
        EXPECT_EQ(c[17], "1");
        EXPECT_EQ(c[7], "0.31");
    }
}
