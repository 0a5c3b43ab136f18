// cli.cpp - the dtc-sil command line (CLI11).
#include <CLI/CLI.hpp>

#include <filesystem>
#include <ostream>

#include "run.hpp"
#include "sweep.hpp"

namespace sil {

int dtc_sil_main(const std::vector<std::string>& args, std::ostream& out, std::ostream& err)
{
    // Sweeps have their own command line (sweep.cpp); listed here for --help.
    if (args.size() > 1 && (args[1] == "sweep" || args[1] == "sweep-merge" || args[1] == "sweep-exec")) {
        return sweep::sweep_main(args, out, err);
    }
    CLI::App app{"dtc-sil: runs the DTC firmware against the plant model (software in the loop)"};
    app.require_subcommand(1);
    app.add_subcommand("sweep", "many runs over grid / Monte Carlo axes, local cores or Dask (dtc-sil sweep --help)");
    app.add_subcommand("sweep-merge", "join the shards of one sweep (dtc-sil sweep-merge --help)");

    std::string scenario_path, out_dir;
    std::vector<std::string> sets;
    unsigned decimate = 1;
    bool no_trace = false, quiet = false;

    CLI::App* run = app.add_subcommand("run", "run a scenario and write DIR/metrics.json and DIR/trace.csv");
    run->add_option("scenario", scenario_path, "scenario TOML file")->required();
    run->add_option("--out,-o", out_dir, "output directory (created; files replaced only when the run succeeds)")
        ->required();
    run->add_option("--set,-s", sets, "override a scenario key: --set load.speed_rpm=700 (repeatable)");
    run->add_option("--decimate", decimate, "write every N-th ISR to trace.csv (default 1)")
        ->check(CLI::Range(1u, 1000000u));
    run->add_flag("--no-trace", no_trace, "do not write trace.csv (metrics only)");
    run->add_flag("--quiet,-q", quiet, "no summary on stdout");

    CLI::App* check = app.add_subcommand("check", "validate a scenario (and --set overrides) without running it");
    check->add_option("scenario", scenario_path, "scenario TOML file")->required();
    check->add_option("--set,-s", sets, "override a scenario key (repeatable)");

    CLI::App* keys = app.add_subcommand("keys", "print every scenario key with unit, default and range (markdown)");

    std::vector<std::string> argv_rev(args.rbegin(), args.rend()); // CLI11 parses a reversed vector
    if (!argv_rev.empty()) {
        argv_rev.pop_back(); // program name
    }
    try {
        app.parse(argv_rev);
    } catch (const CLI::ParseError& e) {
        const int rc = app.exit(e, out, err);
        return rc == 0 ? 0 : 1;
    }

    if (keys->parsed()) {
        out << scenario_keys_markdown();
        return 0;
    }

    Scenario sc;
    Diagnostics diag;
    const bool ok = load_scenario(scenario_path, sets, &sc, &diag);
    err << diag.text();
    if (!ok) {
        err << "dtc-sil: " << scenario_path << ": scenario rejected, nothing run or written\n";
        return 1;
    }
    if (check->parsed()) {
        out << scenario_path << ": ok\n";
        return 0;
    }

    RunOptions opt;
    opt.out_dir = out_dir;
    opt.decimate = decimate;
    opt.write_trace = !no_trace;
    RunResult res;
    std::string e;
    if (!run_scenario(sc, opt, &res, &e)) {
        err << "dtc-sil: " << scenario_path << ": " << e << "\n";
        err << "dtc-sil: nothing written to " << out_dir << "\n";
        return 2;
    }
    if (!quiet) {
        out << summary_text(sc, res.metrics, res.info);
        out << "  wrote " << (std::filesystem::path(out_dir) / "metrics.json").string();
        if (opt.write_trace) {
            out << ", " << (std::filesystem::path(out_dir) / "trace.csv").string();
        }
        out << "\n";
    }
    return 0;
}

} // namespace sil
