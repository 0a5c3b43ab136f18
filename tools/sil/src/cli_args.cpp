// cli_args.cpp - dtc-sil's command line, parsed (CLI11): the commands' options, their types and
// ranges. Nothing here reads a file or runs anything (cli.cpp and sweep.cpp act on the result), so
// the fuzz preset can drive it alone (tests/fuzz/fuzz_sil_cli.cpp).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <ostream>
#include <string>
#include <thread>
#include <vector>

#include "cli_parse.hpp"
#include "run.hpp"
#include "sweep.hpp"
#include "sweep_detail.hpp"
#include "toml_limits.hpp"

namespace sil {

namespace {

/// A directory option's value: refused when empty (an empty DIR would write into the working
/// directory).
CLI::Validator non_empty_dir()
{
    return CLI::Validator([](std::string& v) { return v.empty() ? std::string("empty directory name") : std::string(); },
                          "DIR", "non-empty");
}

/// A real option's value: finite and within [lo, hi] (CLI::Range lets NaN through: every
/// comparison with it is false).
CLI::Validator finite_range(double lo, double hi, const std::string& unit)
{
    const std::string range = sweep::detail::shortest(lo) + " to " + sweep::detail::shortest(hi);
    return CLI::Validator(
        [lo, hi, range, unit](std::string& v) {
            double x = 0.0;
            return sweep::detail::parse_double(v, &x) && x >= lo && x <= hi
                       ? std::string()
                       : echo(v) + ": expected a number from " + range + (unit.empty() ? "" : " " + unit);
        },
        "NUMBER", "finite, " + range);
}

} // namespace

int parse_sil_args(const std::vector<std::string>& args, SilArgs* a, std::ostream& out, std::ostream& err)
{
    *a = SilArgs{};
    // Sweeps have their own command line (sweep.cpp); listed here for --help.
    if (args.size() > 1 && (args[1] == "sweep" || args[1] == "sweep-merge" || args[1] == "sweep-exec")) {
        a->cmd = SilArgs::Command::Sweep;
        return -1;
    }
    CLI::App app{"dtc-sil: runs the DTC firmware against the plant model (software in the loop)"};
    app.require_subcommand(1);
    app.add_subcommand("sweep", "many runs over grid / Monte Carlo axes, local cores or Dask (dtc-sil sweep --help)");
    app.add_subcommand("sweep-merge", "join the shards of one sweep (dtc-sil sweep-merge --help)");


    CLI::App* run = app.add_subcommand("run", "run a scenario and write DIR/metrics.json and DIR/trace.csv");
    run->add_option("scenario", a->scenario_path, "scenario TOML file")->required();
    run->add_option("--out,-o", a->out_dir, "output directory (created; files replaced only when the run succeeds)")
        ->required()
        ->check(non_empty_dir());
    run->add_option("--set,-s", a->sets, "override a scenario key: --set load.speed_rpm=700 (repeatable)");
    run->add_option("--overlay", a->overlays,
                    "TOML fragment applied over the scenario before --set, e.g. identified.toml (repeatable)");
    run->add_option("--decimate", a->decimate, "write every N-th ISR to trace.csv (default 1)")
        ->check(CLI::Range(1u, 1000000u));
    run->add_flag("--no-trace", a->no_trace, "do not write trace.csv (metrics only)");
    run->add_flag("--quiet,-q", a->quiet, "no summary on stdout");
    run->add_flag("--force", a->force, "run even when trace.csv would exceed 1 GB");
    run->add_option("--record-isr", a->record_isr,
                    "write what the firmware saw and commanded in every ISR to FILE (docs/pil.md)");

    CLI::App* check = app.add_subcommand("check", "validate a scenario (and --set overrides) without running it");
    check->add_option("scenario", a->scenario_path, "scenario TOML file")->required();
    check->add_option("--set,-s", a->sets, "override a scenario key (repeatable)");
    check->add_option("--overlay", a->overlays, "TOML fragment applied over the scenario before --set (repeatable)");

    CLI::App* ident = app.add_subcommand(
        "identify", "self-commissioning on the scenario's rig: writes DIR/identified.toml ([firmware] overlay) and "
                    "DIR/identification.json (docs/commissioning.md)");
    ident->add_option("scenario", a->scenario_path, "scenario TOML file")->required();
    ident->add_option("--out,-o", a->out_dir, "output directory (created)")->required()->check(non_empty_dir());
    ident->add_option("--set,-s", a->sets, "override a scenario key (repeatable)");
    ident->add_option("--overlay", a->overlays, "TOML fragment applied over the scenario before --set (repeatable)");
    ident->add_option("--max-time", a->ident_max_s, "simulated time limit of the whole sequence, s (default 10)")
        ->check(finite_range(0.01, 1000.0, "s"));

    CLI::App* serve = app.add_subcommand(
        "serve", "run a scenario with the firmware's serial line on a pseudo-terminal (docs/operate.md): the drive "
                 "starts disarmed and is operated by a host (tools/console/dtc_console.py)");
    serve->add_option("scenario", a->scenario_path, "scenario TOML file")->required();
    serve->add_option("--serial", a->serial_link, "path to link the pseudo-terminal at (the console's --port)")
        ->required()
        ->check(CLI::Validator([](std::string& v) { return v.empty() ? std::string("empty path") : std::string(); },
                               "PATH", "non-empty"));
    serve->add_option("--pace", a->pace, "simulated time per wall-clock time (default 1: real time; 0: as fast as it goes)")
        ->check(finite_range(0.0, 1000.0, ""));
    serve->add_option("--duration-s", a->serve_duration_s, "stop after T s of simulated time (default: at SIGINT/SIGTERM)")
        ->check(finite_range(0.0, 1.0e6, "s"));
    serve->add_option("--out,-o", a->out_dir, "write DIR/trace.csv and DIR/metrics.json on exit, as run does")
        ->check(non_empty_dir());
    serve->add_option("--set,-s", a->sets, "override a scenario key (repeatable)");
    serve->add_option("--decimate", a->decimate, "write every N-th ISR to trace.csv (default 1)")
        ->check(CLI::Range(1u, 1000000u));
    serve->add_flag("--quiet,-q", a->quiet, "no summary on stdout");

    CLI::App* keys = app.add_subcommand("keys", "print every scenario key with unit, default and range (markdown)");

    if (int rc = 0; !cli_parse(app, args, out, err, &rc)) {
        return rc;
    }
    a->cmd = keys->parsed()    ? SilArgs::Command::Keys
             : ident->parsed() ? SilArgs::Command::Identify
             : serve->parsed() ? SilArgs::Command::Serve
             : check->parsed() ? SilArgs::Command::Check
                               : SilArgs::Command::Run;
    return -1;
}

} // namespace sil

namespace sil::sweep {

using detail::parse_double;

int parse_sweep_args(const std::vector<std::string>& args, SweepArgs* a, std::ostream& out, std::ostream& err)
{
    CLI::App app{"dtc-sil sweeps"};
    app.require_subcommand(1);
    *a = SweepArgs{};
    a->jobs = std::max(1u, std::thread::hardware_concurrency());

    CLI::App* sw = app.add_subcommand("sweep", "run a scenario over grid and Monte Carlo axes; write DIR/summary.csv");
    sw->add_option("scenario", a->scenario_path, "scenario TOML file")->required();
    sw->add_option("--out,-o", a->out_dir, "output directory (summary.csv, summary.json, rows.jsonl, plan.json)")
        ->required()
        ->check(non_empty_dir());
    sw->add_option("--set,-s", a->sets, "fixed override of a scenario key for every run (repeatable)");
    sw->add_option("--overlay", a->overlays,
                   "TOML fragment applied over the scenario before --set for every run, e.g. identified.toml "
                   "(repeatable)");
    sw->add_option("--grid", a->grids, "grid axis KEY=V1,V2,... (repeatable; Cartesian product)");
    sw->add_option("--zip", a->zips,
                   "case axis KEY=V1,V2,... (repeatable): all --zip axes have the same length and their i-th "
                   "values go together, as one dimension of the product");
    sw->add_option("--sample", a->samples, "random axis KEY=normal:MEAN:SD or KEY=uniform:LO:HI (repeatable)");
    sw->add_option("--n", a->n, "samples per grid point (with --sample)");
    sw->add_option("--seed", a->seed, "seed of the sampled axes (same seed, same runs)");
    sw->add_option("--jobs,-j", a->jobs, "runs at once (default: the cores present)")->check(CLI::Range(1u, 4096u));
    sw->add_option("--timeout-s", a->timeout_s, "per-run wall-clock limit; a run over it is killed and reported")
        ->check(finite_range(0.001, 1e7, "s"));
    sw->add_flag("--resume", a->resume, "continue the sweep in DIR: skip the runs it already has");
    sw->add_option("--shard", a->shard_text, "run only shard I of N (runs r with r mod N = I), e.g. 0/4");
    sw->add_option("--assert", a->asserts, "envelope METRIC OP NUMBER every run must meet, e.g. imbalance_pct<8");
    sw->add_option("--dask", a->dask_addr, "run on a dask.distributed scheduler, e.g. tcp://10.0.0.1:8786");
    sw->add_option("--chunk", a->chunk, "runs per Dask task (default: about 4 tasks per worker, at most 50 runs)")
        ->check(CLI::Range(1u, 100000u));
    sw->add_flag("--quiet,-q", a->quiet, "no closing summary line");
    sw->add_flag("--allow-failed-runs", a->allow_failed,
                 "exit 0 even when runs crashed, timed out, diverged or could not be completed (their rows "
                 "say so)");
    sw->add_flag("--identify", a->identify,
                 "each run is the self-commissioning (dtc-sil identify) instead of a drive run: its metrics are the "
                 "identification's errors against the plant (Q.error_pct, Q.abs_error_pct, ...: docs/commissioning.md), "
                 "status fault naming the step and reason when it stopped; with --keep-runs DIR/runs/RUN holds "
                 "identified.toml and identification.json");
    sw->add_flag("--keep-runs", a->keep_runs, "also write every run's metrics.json and trace.csv to DIR/runs/RUN");

    CLI::App* mg = app.add_subcommand("sweep-merge", "join the shards of one sweep into DIR/summary.csv");
    mg->add_option("--out,-o", a->out_dir, "output directory")->required()->check(non_empty_dir());
    mg->add_option("shards", a->merge_dirs, "the shards' output directories")->required();

    CLI::App* ex = app.add_subcommand("sweep-exec", "(for Dask workers) run a chunk read from stdin, rows on stdout");
    ex->add_option("--jobs,-j", a->exec_jobs, "runs at once")->check(CLI::Range(1u, 4096u));
    ex->group(""); // not listed in --help: an internal interface

    if (int rc = 0; !cli_parse(app, args, out, err, &rc)) {
        return rc;
    }
    a->cmd = ex->parsed() ? SweepArgs::Command::Exec : mg->parsed() ? SweepArgs::Command::Merge : SweepArgs::Command::Sweep;
    return -1;
}

} // namespace sil::sweep
