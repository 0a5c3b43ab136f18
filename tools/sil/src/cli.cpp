// cli.cpp - the dtc-sil command line (CLI11).
#include <CLI/CLI.hpp>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <ostream>
#include <unistd.h>

#include "cli_parse.hpp"
#include "controller_adapter.hpp"
#include "identify.hpp"
#include "im_tau_check.h"
#include "run.hpp"
#include "sweep.hpp"

namespace sil {

namespace {
extern "C" void on_stop_signal(int sig) { g_stop_signal = sig; }
} // namespace

StopSignals::StopSignals()
{
    g_stop_signal = 0;
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
}

StopSignals::~StopSignals()
{
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
}

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

    std::string scenario_path, out_dir, record_isr;
    std::vector<std::string> sets, overlays;
    unsigned decimate = 1;
    bool no_trace = false, quiet = false, force = false;

    CLI::App* run = app.add_subcommand("run", "run a scenario and write DIR/metrics.json and DIR/trace.csv");
    run->add_option("scenario", scenario_path, "scenario TOML file")->required();
    run->add_option("--out,-o", out_dir, "output directory (created; files replaced only when the run succeeds)")
        ->required()
        ->check(CLI::Validator(
            [](std::string& v) { return v.empty() ? std::string("empty directory name") : std::string(); },
            "DIR", "non-empty"));
    run->add_option("--set,-s", sets, "override a scenario key: --set load.speed_rpm=700 (repeatable)");
    run->add_option("--overlay", overlays,
                    "TOML fragment applied over the scenario before --set, e.g. identified.toml (repeatable)");
    run->add_option("--decimate", decimate, "write every N-th ISR to trace.csv (default 1)")
        ->check(CLI::Range(1u, 1000000u));
    run->add_flag("--no-trace", no_trace, "do not write trace.csv (metrics only)");
    run->add_flag("--quiet,-q", quiet, "no summary on stdout");
    run->add_flag("--force", force, "run even when trace.csv would exceed 1 GB");
    run->add_option("--record-isr", record_isr,
                    "write what the firmware saw and commanded in every ISR to FILE (docs/pil.md)");

    CLI::App* check = app.add_subcommand("check", "validate a scenario (and --set overrides) without running it");
    check->add_option("scenario", scenario_path, "scenario TOML file")->required();
    check->add_option("--set,-s", sets, "override a scenario key (repeatable)");
    check->add_option("--overlay", overlays, "TOML fragment applied over the scenario before --set (repeatable)");

    double ident_max_s = 10.0;
    CLI::App* ident = app.add_subcommand(
        "identify", "self-commissioning on the scenario's rig: writes DIR/identified.toml ([firmware] overlay) and "
                    "DIR/identification.json (docs/commissioning.md)");
    ident->add_option("scenario", scenario_path, "scenario TOML file")->required();
    ident->add_option("--out,-o", out_dir, "output directory (created)")->required();
    ident->add_option("--set,-s", sets, "override a scenario key (repeatable)");
    ident->add_option("--overlay", overlays, "TOML fragment applied over the scenario before --set (repeatable)");
    ident->add_option("--max-time", ident_max_s, "simulated time limit of the whole sequence, s (default 10)")
        ->check(CLI::Range(0.01, 1000.0));

    std::string serial_link;
    double pace = 1.0, serve_duration_s = 0.0;
    CLI::App* serve = app.add_subcommand(
        "serve", "run a scenario with the firmware's serial line on a pseudo-terminal (docs/operate.md): the drive "
                 "starts disarmed and is operated by a host (tools/console/dtc_console.py)");
    serve->add_option("scenario", scenario_path, "scenario TOML file")->required();
    serve->add_option("--serial", serial_link, "path to link the pseudo-terminal at (the console's --port)")
        ->required();
    serve->add_option("--pace", pace, "simulated time per wall-clock time (default 1: real time; 0: as fast as it goes)")
        ->check(CLI::Range(0.0, 1000.0));
    serve->add_option("--duration-s", serve_duration_s, "stop after T s of simulated time (default: at SIGINT/SIGTERM)")
        ->check(CLI::Range(0.0, 1.0e6));
    serve->add_option("--out,-o", out_dir, "write DIR/trace.csv and DIR/metrics.json on exit, as run does");
    serve->add_option("--set,-s", sets, "override a scenario key (repeatable)");
    serve->add_option("--decimate", decimate, "write every N-th ISR to trace.csv (default 1)")
        ->check(CLI::Range(1u, 1000000u));
    serve->add_flag("--quiet,-q", quiet, "no summary on stdout");

    CLI::App* keys = app.add_subcommand("keys", "print every scenario key with unit, default and range (markdown)");

    if (int rc = 0; !cli_parse(app, args, out, err, &rc)) {
        return rc;
    }

    if (keys->parsed()) {
        out << scenario_keys_markdown();
        return 0;
    }

    Scenario sc;
    Diagnostics diag;
    const bool ok = load_scenario(scenario_path, sets, &sc, &diag, overlays);
    err << diag.text();
    if (!ok) {
        err << "dtc-sil: " << scenario_path << ": scenario rejected, nothing run or written\n";
        return 1;
    }
    if (ident->parsed()) {
        IdentifyReport rep;
        rep.max_time_s = ident_max_s;
        std::string e;
        if (!identify(sc, out_dir, &rep, &e)) {
            err << "dtc-sil: " << scenario_path << ": " << e << "\n";
            return 2;
        }
        out << "identify " << scenario_path << ": " << (rep.ok ? "ok" : "FAILED") << " after " << rep.duration_s
            << " s; wrote " << (std::filesystem::path(out_dir) / "identified.toml").string() << ", "
            << (std::filesystem::path(out_dir) / "identification.json").string() << "\n";
        if (!rep.ok) {
            err << "dtc-sil: " << scenario_path << ": identification failed in step " << rep.failed_step << ": "
                << rep.reason << "\n";
            return 3;
        }
        return 0;
    }
    RunOptions opt;
    opt.out_dir = out_dir;
    opt.decimate = decimate;
    opt.write_trace = !no_trace;
    opt.force = force;
    opt.record_isr = record_isr;
    if (serve->parsed()) {
        opt.serial_link = serial_link;
        opt.pace = pace;
        opt.serve_duration_s = serve_duration_s;
        opt.write_trace = !out_dir.empty();
    }
    RunResult res;
    std::string e;
    if (check->parsed()) {
        // The same path as run up to the first period: plant, harness and firmware configuration.
        opt.check_only = true;
        opt.out_dir.clear();
        if (!run_scenario(sc, opt, &res, &e)) {
            err << "dtc-sil: " << scenario_path << ": " << e << "\n";
            err << "dtc-sil: " << scenario_path << ": scenario rejected\n";
            return 1;
        }
        // run's only extra refusal depends on its options: say when a traced run would meet it.
        const double rows = std::floor(sc.duration_s / sc.ts_s + 0.5);
        if (rows * kTraceBytesPerRow > opt.max_trace_bytes) {
            err << "warning: a traced run writes about " << rows * kTraceBytesPerRow / 1e9
                << " GB of trace.csv: `run` refuses it without --decimate, --no-trace or --force\n";
        }
        // Casadei eqs. 26-28: the configured improved-estimator tau against the operating range.
        const dtc_config_si_t tau_si = firmware_si_config(sc);
        im_tau_report_t tau_report;
        char tau_msg[600];
        if (im_tau_check(&tau_si, &tau_report, tau_msg, sizeof tau_msg) != 0) {
            err << "warning: control.observer_tau_s: " << tau_msg << "\n";
        }
        out << scenario_path << ": ok\n";
        return 0;
    }
    if (std::error_code ec; !out_dir.empty() && std::filesystem::exists(out_dir, ec) && !std::filesystem::is_directory(out_dir, ec)) {
        err << "dtc-sil: --out " << out_dir << ": exists and is not a directory; nothing run or written\n";
        return 1;
    }
    {
        opt.check_only = true; // refusals first (exit 1), before anything is created
        if (!run_scenario(sc, opt, &res, &e)) {
            err << "dtc-sil: " << scenario_path << ": " << e << "\n";
            err << "dtc-sil: " << scenario_path << ": scenario rejected, nothing run or written\n";
            return 1;
        }
        opt.check_only = false;
    }
    if (&err == &std::cerr && ::isatty(STDERR_FILENO) != 0) {
        opt.progress = &err;
    }
    StopSignals stop_signals;
    if (!run_scenario(sc, opt, &res, &e)) {
        err << "dtc-sil: " << scenario_path << ": " << e << "\n";
        if (!res.output_touched) {
            err << "dtc-sil: nothing written to " << out_dir
                << (record_isr.empty() ? std::string() : " or " + record_isr) << "\n";
        }
        return g_stop_signal != 0 ? 128 + static_cast<int>(g_stop_signal) : 2;
    }
    if (!quiet && out_dir.empty()) {
        out << "dtc-sil serve: " << res.info.sim_time_s << " s simulated, fault " << res.info.fault << "\n";
    } else if (!quiet) {
        out << summary_text(sc, res.metrics, res.info);
        out << "  wrote " << (std::filesystem::path(out_dir) / "metrics.json").string();
        if (opt.write_trace) {
            out << ", " << (std::filesystem::path(out_dir) / "trace.csv").string();
        }
        out << "\n";
    }
    if (run_failed_physically(res.info)) {
        err << "dtc-sil: " << scenario_path << ": " << res.info.fault << ": " << res.info.fault_detail << "\n";
        return 3;
    }
    return 0;
}

} // namespace sil
