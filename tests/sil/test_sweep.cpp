// dtc-sil sweep: plan expansion (grid, samples, seeds, shards), refusal of bad specifications
// before any run, and local sweeps end to end (rows, refused runs, time limit, resume, merge,
// --assert) on short runs of a shipped scenario through the real plant and firmware.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "cli_capture.hpp"
#include "sweep.hpp"

namespace fs = std::filesystem;
using namespace sil::sweep;
using nlohmann::json;

namespace {

const std::string kScenario = std::string(DTC_SOURCE_DIR) + "/tools/scenarios/fstp_current_full.toml";

int sweep(std::vector<std::string> args, std::string* out_text = nullptr, std::string* err_text = nullptr)
{
    return sil_test::run_cli(std::move(args), out_text, err_text, sweep_main);
}

std::string read(const fs::path& p)
{
    std::ifstream f(p);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

fs::path fresh_dir(const std::string& name)
{
    const fs::path d = fs::temp_directory_path() / ("dtc_sweep_test_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    return d;
}

// A sweep of the test scenario, no axes yet.
Spec scenario_spec()
{
    Spec s;
    s.scenario_path = kScenario;
    s.scenario_text = read(kScenario);
    return s;
}

// The axis of a --grid (opt "--zip": of a --zip) argument; a refused one fails the test.
Axis grid(const std::string& arg, const char* opt = "--grid")
{
    Axis a;
    std::string e;
    EXPECT_TRUE(parse_grid_axis(arg, &a, &e, opt)) << e;
    return a;
}

// The axis of a --sample argument; a refused one fails the test.
Axis sample(const std::string& arg)
{
    Axis a;
    std::string e;
    EXPECT_TRUE(parse_sample_axis(arg, &a, &e)) << e;
    return a;
}

Spec two_axis_spec()
{
    Spec s = scenario_spec();
    s.axes = {grid("control.speed_ref_rpm=300,700,1500"), grid("control.estimator=current,voltage"),
              sample("motor.rs_ohm=normal:0.466:0.05")};
    s.n = 4;
    s.seed = 7;
    return s;
}

// Short runs: enough for calibration, start-up and a few speed-loop periods.
const std::vector<std::string> kShort = {"--set", "duration_s=0.06", "--set", "metrics_window_s=0.02"};

std::vector<std::string> with_short(std::vector<std::string> a)
{
    a.insert(a.end(), kShort.begin(), kShort.end());
    return a;
}

} // namespace

TEST(Sweep, GridIsTheCartesianProductLastAxisFastest)
{
    const Spec s = two_axis_spec();
    ASSERT_EQ(run_count(s), 3u * 2u * 4u);
    const auto runs = expand(s);
    ASSERT_EQ(runs.size(), 24u);
    for (std::uint64_t r = 0; r < 24; ++r) {
        EXPECT_EQ(runs[r].index, r);
        const std::uint64_t g = r / 4;
        EXPECT_EQ(runs[r].values[0], (std::vector<std::string>{"300", "700", "1500"})[g / 2]);
        EXPECT_EQ(runs[r].values[1], (std::vector<std::string>{"\"current\"", "\"voltage\""})[g % 2]);
    }
    const auto o = run_overrides(s, runs[5]);
    ASSERT_EQ(o.size(), 3u);
    EXPECT_EQ(o[0], "control.speed_ref_rpm=300");
    EXPECT_EQ(o[1], "control.estimator=\"voltage\"");
}

TEST(Sweep, ZipAxesAreCasesCrossedWithTheGrid)
{
    Spec s = scenario_spec();
    s.axes = {grid("control.speed_ref_rpm=700,1500"), grid("inverter.topology=sstp,fstp,fstp", "--zip"),
              grid("control.compensation=simple,simple,proposed", "--zip")};
    ASSERT_EQ(run_count(s), 6u);
    const auto runs = expand(s);
    // Cases slowest, then the grid: (sstp, simple) x {700, 1500}, (fstp, simple) x ..., ...
    const char* topo[6] = {"\"sstp\"", "\"sstp\"", "\"fstp\"", "\"fstp\"", "\"fstp\"", "\"fstp\""};
    const char* comp[6] = {"\"simple\"", "\"simple\"", "\"simple\"", "\"simple\"", "\"proposed\"", "\"proposed\""};
    for (std::size_t r = 0; r < 6; ++r) {
        EXPECT_EQ(runs[r].values[0], r % 2 == 0 ? "700" : "1500");
        EXPECT_EQ(runs[r].values[1], topo[r]);
        EXPECT_EQ(runs[r].values[2], comp[r]);
    }
}

TEST(Sweep, GridValuesSplitOnlyAtTopLevelCommas)
{
    Axis a;
    std::string e;
    ASSERT_TRUE(parse_grid_axis("motor.emf_gain=[1, 1, 1],[0.98, 1.0, 1.02]", &a, &e)) << e;
    ASSERT_EQ(a.values.size(), 2u);
    EXPECT_EQ(a.values[1], "[0.98, 1.0, 1.02]");
    ASSERT_TRUE(parse_grid_axis("control.compensation=\"none\",simple", &a, &e)) << e;
    EXPECT_EQ(a.values, (std::vector<std::string>{"\"none\"", "\"simple\""}));
}

TEST(Sweep, SamplesDependOnlyOnSeedRunAndAxis)
{
    Spec s = two_axis_spec();
    const auto all = expand(s);
    // Every shard gives run r the same values as the whole plan, so shards, resumed sweeps and
    // Dask workers agree.
    std::set<std::uint64_t> seen;
    for (std::uint64_t i = 0; i < 5; ++i) {
        for (const PlannedRun& p : expand(s, i, 5)) {
            EXPECT_EQ(p.index % 5, i);
            EXPECT_EQ(p.values, all[p.index].values);
            EXPECT_TRUE(seen.insert(p.index).second) << "run in two shards";
        }
    }
    EXPECT_EQ(seen.size(), all.size()); // the shards partition the plan exactly
    const auto again = expand(s);
    for (std::size_t r = 0; r < all.size(); ++r) {
        EXPECT_EQ(again[r].values, all[r].values);
    }
    s.seed = 8;
    const auto other = expand(s);
    int same = 0;
    for (std::size_t r = 0; r < all.size(); ++r) {
        same += other[r].values[2] == all[r].values[2] ? 1 : 0;
    }
    EXPECT_EQ(same, 0);
}

TEST(Sweep, PerPhaseArraysAreDrawnElementByElement)
{
    Spec s;
    s.axes = {sample("sensors.current_offset_a=uniform:-0.01:0.01")};
    s.n = 3;
    for (const PlannedRun& p : expand(s)) {
        double x[3];
        ASSERT_EQ(std::sscanf(p.values[0].c_str(), "[%lf, %lf, %lf]", &x[0], &x[1], &x[2]), 3) << p.values[0];
        EXPECT_NE(x[0], x[1]);
        EXPECT_NE(x[1], x[2]);
        for (double v : x) {
            EXPECT_GE(v, -0.01);
            EXPECT_LE(v, 0.01);
        }
    }
}

TEST(Sweep, NormalAndUniformSamplesHaveTheirMoments)
{
    Spec s;
    s.axes = {sample("motor.rs_ohm=normal:0.5:0.1"), sample("motor.ls_h=uniform:2e-3:4e-3")};
    s.n = 40000;
    s.seed = 3;
    double sn = 0, sn2 = 0, su = 0, lo = 1, hi = 0;
    const auto runs = expand(s);
    for (const PlannedRun& p : runs) {
        const double x = std::stod(p.values[0]);
        const double u = std::stod(p.values[1]);
        sn += x;
        sn2 += x * x;
        su += u;
        lo = std::min(lo, u);
        hi = std::max(hi, u);
    }
    const double n = static_cast<double>(runs.size());
    const double mean = sn / n, sd = std::sqrt(sn2 / n - mean * mean);
    // Standard errors: mean 0.1/200 = 5e-4, sd 0.1/sqrt(2n) = 3.5e-4, uniform mean 5.8e-4/200.
    EXPECT_NEAR(mean, 0.5, 4 * 5e-4);
    EXPECT_NEAR(sd, 0.1, 4 * 3.6e-4);
    EXPECT_NEAR(su / n, 3e-3, 4 * 2.9e-6);
    EXPECT_GE(lo, 2e-3);
    EXPECT_LE(hi, 4e-3);
}

TEST(Sweep, BadSpecificationsAreRefusedBeforeAnyRunNamingTheArgument)
{
    struct Case {
        std::vector<std::string> args;
        std::string says;
    };
    const fs::path d = fresh_dir("bad");
    const std::vector<Case> cases = {
        {{"--grid", "motor.nonsense=1,2"}, "--grid motor.nonsense=1,2: unknown scenario key"},
        {{"--grid", "motor.rs_ohm="}, "--grid motor.rs_ohm=: empty value"},
        {{"--grid", "motor.rs_ohm=0.4,,0.5"}, "empty value"},
        {{"--grid", "control.estimator=current,magic"}, "--grid control.estimator: value \"magic\" is rejected"},
        {{"--sample", "motor.rs_ohm=gauss:1:2", "--n", "3"}, "unknown distribution 'gauss'"},
        {{"--sample", "motor.rs_ohm=normal:1", "--n", "3"}, "expected normal:MEAN:SD"},
        {{"--sample", "motor.rs_ohm=uniform:2:1", "--n", "3"}, "LO <= HI"},
        {{"--sample", "control.estimator=uniform:0:1", "--n", "3"}, "only number keys"},
        {{"--sample", "motor.rs_ohm=normal:0.5:0.1"}, "--sample needs --n"},
        {{"--grid", "motor.rs_ohm=0.4", "--n", "3"}, "--n 3"},
        {{"--grid", "motor.rs_ohm=0.4", "--shard", "2/2"}, "--shard 2/2: I must be below N"},
        {{"--grid", "motor.rs_ohm=0.4", "--shard", "x"}, "--shard x"},
        {{"--grid", "motor.rs_ohm=0.4", "--assert", "no_such_metric<3"}, "unknown metric 'no_such_metric'"},
        {{"--grid", "motor.rs_ohm=0.4", "--assert", "imbalance_pct~3"}, "expected METRIC OP NUMBER"},
        {{"--grid", "motor.rs_ohm=0.4", "--dask", "localhost"}, "--dask localhost"},
        {{}, "nothing to sweep"},
        {{"--zip", "inverter.topology=sstp,fstp", "--zip", "control.compensation=none"},
         "--zip control.compensation=none: 1 values, but the other --zip axes have 2"},
        // Each value is valid alone; the case (the reference controller on the SSTP with the proposed
        // scheme, which only the firmware has there) is not.
        {{"--zip", "inverter.topology=fstp,sstp", "--zip", "control.compensation=proposed,proposed", "--set",
          "control.estimator=\"voltage\"", "--set", "control.implementation=\"reference\""},
         "--zip case 2 (inverter.topology=\"sstp\", control.compensation=\"proposed\") is rejected"},
        {{"--zip", "inverter.topology=fstp", "--keep-runs", "--dask", "tcp://127.0.0.1:1"}, "--keep-runs with --dask"},
    };
    for (const Case& c : cases) {
        std::vector<std::string> a = {"sweep", kScenario, "--out", d.string()};
        a.insert(a.end(), c.args.begin(), c.args.end());
        std::string err;
        EXPECT_EQ(sweep(a, nullptr, &err), 1) << c.says;
        EXPECT_NE(err.find(c.says), std::string::npos) << "expected '" << c.says << "' in: " << err;
        EXPECT_FALSE(fs::exists(d)) << c.says << ": output written for a refused sweep";
    }
    std::string err;
    EXPECT_EQ(sweep({"sweep", "/nonexistent.toml", "--out", d.string(), "--grid", "motor.rs_ohm=1"}, nullptr, &err), 1);
    EXPECT_NE(err.find("/nonexistent.toml"), std::string::npos);
}

TEST(Sweep, LocalSweepWritesOneRowPerRunRefusedRunsIncluded)
{
    const fs::path d = fresh_dir("local");
    std::string out, err;
    // rs_ohm drawn from [-0.2, 0.8]: the negative draws are refused by the scenario and must be
    // rows with the reason, not an aborted sweep.
    const int rc = sweep(with_short({"sweep", kScenario, "--out", d.string(), "--jobs", "2", "--grid",
                                     "control.speed_ref_rpm=300,600", "--sample", "motor.rs_ohm=uniform:-0.2:0.8",
                                     "--n", "6", "--seed", "11"}),
                         &out, &err);
    EXPECT_EQ(rc, 0) << err;
    const json sj = json::parse(read(d / "summary.json"));
    const auto& rows = sj.at("rows");
    ASSERT_EQ(rows.size(), 12u);
    int refused = 0, ok = 0;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const json& r = rows[i];
        EXPECT_EQ(r.at("run").get<std::uint64_t>(), i);
        const double rs = std::stod(r.at("values").at("motor.rs_ohm").get<std::string>());
        const std::string st = r.at("status");
        if (rs <= 0.0) {
            EXPECT_EQ(st, "refused");
            EXPECT_NE(r.at("error").get<std::string>().find("motor.rs_ohm"), std::string::npos);
            ++refused;
        } else {
            EXPECT_TRUE(st == "ok" || st == "fault") << st;
            EXPECT_TRUE(r.at("metrics").contains("speed_mean_rpm"));
            EXPECT_EQ(r.at("metrics").at("isr_count").get<std::uint64_t>(), 1200u);
            ok += st == "ok" ? 1 : 0;
        }
    }
    EXPECT_GT(refused, 0);
    EXPECT_GT(ok, 0);
    const std::string csv = read(d / "summary.csv");
    EXPECT_EQ(csv.substr(0, csv.find('\n')).find("run,control.speed_ref_rpm,motor.rs_ohm,status,fault,error,"), 0u);
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 13);
    // The same folder again without --resume is refused; nothing is lost.
    EXPECT_EQ(sweep(with_short({"sweep", kScenario, "--out", d.string(), "--grid", "control.speed_ref_rpm=300,600",
                                "--sample", "motor.rs_ohm=uniform:-0.2:0.8", "--n", "6", "--seed", "11"}),
                    nullptr, &err),
              1);
    EXPECT_NE(err.find("--resume"), std::string::npos);
    EXPECT_EQ(read(d / "summary.csv"), csv);
    fs::remove_all(d);
}

TEST(Sweep, ResumeAfterAKillShardsAndMergeGiveTheSameSummary)
{
    const std::vector<std::string> axes = {"--grid", "control.speed_ref_rpm=400,800,1200", "--sample",
                                           "sensors.current_noise_a_rms=uniform:0:0.02", "--n", "3"};
    auto cmd = [&](const fs::path& d, std::vector<std::string> extra) {
        std::vector<std::string> a = {"sweep", kScenario, "--out", d.string(), "--jobs", "2"};
        a.insert(a.end(), axes.begin(), axes.end());
        a.insert(a.end(), extra.begin(), extra.end());
        return with_short(a);
    };
    const fs::path whole = fresh_dir("whole");
    std::string err;
    ASSERT_EQ(sweep(cmd(whole, {}), nullptr, &err), 0) << err;
    const std::string ref_csv = read(whole / "summary.csv");
    ASSERT_EQ(std::count(ref_csv.begin(), ref_csv.end(), '\n'), 10);

    // A sweep killed after 4 rows, the last one torn mid-write: --resume runs the other 5.
    const fs::path killed = fresh_dir("killed");
    ASSERT_EQ(sweep(cmd(killed, {}), nullptr, &err), 0) << err;
    {
        std::istringstream in(read(killed / "rows.jsonl"));
        std::string line, kept;
        for (int i = 0; i < 4 && std::getline(in, line); ++i) {
            kept += line + "\n";
        }
        std::getline(in, line);
        kept += line.substr(0, line.size() / 2);
        std::ofstream(killed / "rows.jsonl") << kept;
        fs::remove(killed / "summary.csv");
    }
    std::string out;
    ASSERT_EQ(sweep(cmd(killed, {"--resume"}), &out, &err), 0) << err;
    EXPECT_EQ(read(killed / "summary.csv"), ref_csv);
    // Resuming with another plan is refused.
    EXPECT_EQ(sweep(cmd(killed, {"--resume", "--seed", "2"}), nullptr, &err), 1);
    EXPECT_NE(err.find("different sweep plan"), std::string::npos) << err;

    // Two shards, merged.
    const fs::path s0 = fresh_dir("s0"), s1 = fresh_dir("s1"), merged = fresh_dir("merged");
    ASSERT_EQ(sweep(cmd(s0, {"--shard", "0/2"}), nullptr, &err), 0) << err;
    ASSERT_EQ(sweep(cmd(s1, {"--shard", "1/2"}), nullptr, &err), 0) << err;
    const std::string shard0 = read(s0 / "summary.csv");
    EXPECT_EQ(std::count(shard0.begin(), shard0.end(), '\n'), 6); // runs 0, 2, 4, 6, 8
    ASSERT_EQ(sweep({"sweep-merge", "--out", merged.string(), s0.string(), s1.string()}, &out, &err), 0) << err;
    EXPECT_EQ(read(merged / "summary.csv"), ref_csv);
    EXPECT_NE(out.find("9 of 9 runs"), std::string::npos) << out;
    // A shard of a different sweep is refused.
    const fs::path other = fresh_dir("other");
    ASSERT_EQ(sweep(with_short({"sweep", kScenario, "--out", other.string(), "--grid", "control.speed_ref_rpm=500"}),
                    nullptr, &err),
              0)
        << err;
    EXPECT_EQ(sweep({"sweep-merge", "--out", merged.string(), s0.string(), other.string()}, nullptr, &err), 1);
    EXPECT_NE(err.find("a different sweep plan"), std::string::npos) << err;
    for (const fs::path& d : {whole, killed, s0, s1, merged, other}) {
        fs::remove_all(d);
    }
}

TEST(Sweep, KeepRunsWritesEveryRunsOutputs)
{
    const fs::path d = fresh_dir("keep");
    std::string err;
    ASSERT_EQ(sweep(with_short({"sweep", kScenario, "--out", d.string(), "--keep-runs", "--zip",
                                "control.speed_ref_rpm=300,600"}),
                    nullptr, &err),
              0)
        << err;
    for (int r = 0; r < 2; ++r) {
        const fs::path run = d / "runs" / std::to_string(r);
        EXPECT_TRUE(fs::is_regular_file(run / "trace.csv")) << run;
        const json m = json::parse(read(run / "metrics.json"));
        EXPECT_EQ(m.at("isr_count").get<std::uint64_t>(), 1200u);
    }
    fs::remove_all(d);
}

TEST(Sweep, OneWorkerRunsEveryRunAndAKilledOneIsReplaced)
{
    // --jobs 1: the runs go one after another through a worker process. A run over the per-run
    // limit is killed with its worker; a new worker takes the runs after it. Every run has its
    // row, and a run's row is the one a sweep of that run alone gives (nothing carried over from
    // the runs before it in the same worker).
    const fs::path d = fresh_dir("worker");
    std::string err;
    EXPECT_EQ(sweep({"sweep", kScenario, "--out", d.string(), "--zip", "duration_s=600,0.06,600,0.06", "--zip",
                     "control.speed_ref_rpm=100,300,200,700", "--set", "metrics_window_s=0.02", "--timeout-s", "1.5",
                     "--jobs", "1", "--allow-failed-runs"},
                    nullptr, &err),
              0)
        << err;
    const json rows = json::parse(read(d / "summary.json")).at("rows");
    ASSERT_EQ(rows.size(), 4u);
    EXPECT_EQ(rows[0].at("status"), "timeout");
    EXPECT_EQ(rows[2].at("status"), "timeout");
    EXPECT_EQ(rows[1].at("status"), "ok");
    EXPECT_EQ(rows[3].at("status"), "ok");
    // The same two short runs, each alone in a sweep: the same metrics.
    const fs::path alone = fresh_dir("worker_alone");
    for (int r : {1, 3}) {
        fs::remove_all(alone);
        const std::string rpm = r == 1 ? "300" : "700";
        ASSERT_EQ(sweep(with_short({"sweep", kScenario, "--out", alone.string(), "--grid", "control.speed_ref_rpm=" + rpm,
                                    "--jobs", "1"}),
                        nullptr, &err),
                  0)
            << err;
        const json one = json::parse(read(alone / "summary.json")).at("rows").at(0);
        EXPECT_EQ(one.at("metrics"), rows[static_cast<std::size_t>(r)].at("metrics")) << "run " << r;
    }
    // Several runs through one worker give the rows of runs in a worker each (--jobs 3, 3 runs).
    const fs::path many = fresh_dir("worker_many");
    const fs::path each = fresh_dir("worker_each");
    const std::vector<std::string> axes = {"--grid", "control.speed_ref_rpm=300,700,1500"};
    std::vector<std::string> a1 = with_short({"sweep", kScenario, "--out", many.string(), "--jobs", "1"});
    std::vector<std::string> a3 = with_short({"sweep", kScenario, "--out", each.string(), "--jobs", "3"});
    a1.insert(a1.end(), axes.begin(), axes.end());
    a3.insert(a3.end(), axes.begin(), axes.end());
    ASSERT_EQ(sweep(a1, nullptr, &err), 0) << err;
    ASSERT_EQ(sweep(a3, nullptr, &err), 0) << err;
    EXPECT_EQ(read(many / "summary.csv"), read(each / "summary.csv"));
    for (const fs::path& x : {d, alone, many, each}) {
        fs::remove_all(x);
    }
}

TEST(Sweep, AssertSetsTheExitCodeAndTimedOutRunsAreRows)
{
    const fs::path d = fresh_dir("assert");
    std::string err;
    // Envelopes that hold give exit 0; a violated one exits 3 and names the run and the value.
    ASSERT_EQ(sweep(with_short({"sweep", kScenario, "--out", d.string(), "--grid", "control.speed_ref_rpm=0,10",
                                "--assert", "isr_count==1200", "--assert", "hw_trip==0"}),
                    nullptr, &err),
              0)
        << err;
    fs::remove_all(d);
    EXPECT_EQ(sweep(with_short({"sweep", kScenario, "--out", d.string(), "--grid", "control.speed_ref_rpm=0,10",
                                "--assert", "isr_count<1000"}),
                    nullptr, &err),
              3);
    EXPECT_NE(err.find("run 0: isr_count<1000 violated: isr_count = 1200"), std::string::npos) << err;
    fs::remove_all(d);
    // A run longer than the per-run limit is killed and becomes a "timeout" row; the sweep exits 4
    // naming each, or 0 with --allow-failed-runs.
    EXPECT_EQ(sweep({"sweep", kScenario, "--out", d.string(), "--grid", "control.speed_ref_rpm=100,200", "--set",
                     "duration_s=30", "--timeout-s", "0.05"},
                    nullptr, &err),
              4)
        << err;
    EXPECT_NE(err.find("run 0: timeout"), std::string::npos) << err;
    EXPECT_NE(err.find("run 1: timeout"), std::string::npos) << err;
    fs::remove_all(d);
    EXPECT_EQ(sweep({"sweep", kScenario, "--out", d.string(), "--grid", "control.speed_ref_rpm=100,200", "--set",
                     "duration_s=30", "--timeout-s", "0.05", "--allow-failed-runs"},
                    nullptr, &err),
              0)
        << err;
    const json sj = json::parse(read(d / "summary.json"));
    for (const json& r : sj.at("rows")) {
        EXPECT_EQ(r.at("status"), "timeout");
        EXPECT_NE(r.at("error").get<std::string>().find("per-run limit"), std::string::npos);
    }
    fs::remove_all(d);
}
