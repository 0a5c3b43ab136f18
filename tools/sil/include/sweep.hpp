// sweep.hpp - many runs of one scenario: grid and Monte Carlo axes, executed on local cores (forked
// worker processes), sliced into shards for batch systems, or sent to a Dask cluster.
//
// A sweep is a plan (the scenario text, fixed --set overrides, the axes, n and seed) expanded into
// a numbered list of runs. The expansion is deterministic: run r's sampled values depend only on
// (seed, r, axis), so every shard, every resumed sweep and every Dask worker sees the same run r.
// Each finished run is one JSON row appended to DIR/rows.jsonl as it completes (a killed sweep
// loses at most the runs in flight); summary.csv and summary.json are written from the rows, sorted
// by run index, by one writer whatever executed them (local, shards merged, Dask).
#ifndef DTC_SIL_SWEEP_HPP
#define DTC_SIL_SWEEP_HPP

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scenario.hpp"

namespace sil::sweep {

struct Axis {
    // Grid: one dimension of the Cartesian product. Zip: all zip axes together form one dimension
    // (their i-th values go together: a list of cases). Normal, Uniform: drawn per run.
    enum class Kind { Grid, Zip, Normal, Uniform };
    Kind kind = Kind::Grid;
    std::string key;                 // dotted scenario key
    std::string key_type;            // the schema's type text (number, integer, string, ...)
    std::vector<std::string> values; // Grid, Zip: TOML value texts, as --set takes them
    double a = 0.0, b = 0.0;         // Normal: mean, sd; Uniform: lo, hi
};

struct Spec {
    std::string scenario_path;       // as given (messages, relative paths inside the scenario)
    std::string scenario_text;       // the file's text, so workers need not read it
    std::vector<OverlayText> overlays; // --overlay fragments, applied over the scenario before the sets
    std::vector<std::string> sets;   // fixed --set overrides, applied before the axes
    std::vector<Axis> axes;          // grid axes first, then sampled ones, in the order given
    std::uint64_t n = 1;             // samples per grid point (1 when there is no sampled axis)
    std::uint64_t seed = 1;
    bool identify = false;           // each run is `dtc-sil identify` (identify_metric_columns), not `run`
};

struct PlannedRun {
    std::uint64_t index = 0;
    std::vector<std::string> values; // one TOML value text per axis, in Spec::axes order
};

/// Parses "key=v1,v2,..." (commas inside [] or quotes do not split). String keys may be given
/// unquoted. Errors name the argument. `opt` is the option's name for messages and decides the
/// kind: "--zip" gives a Zip axis, anything else a Grid axis.
bool parse_grid_axis(const std::string& arg, Axis* out, std::string* err, const char* opt = "--grid");
/// Parses "key=normal:MEAN:SD" or "key=uniform:LO:HI" (number keys only).
bool parse_sample_axis(const std::string& arg, Axis* out, std::string* err);

/// The most runs a plan may have: the plan is expanded in memory (a few hundred bytes a run) and
/// its summary holds a row per run.
inline constexpr std::uint64_t kMaxPlanRuns = 1000000;
/// The number of runs (call check_plan_size first: the product is not checked here).
std::uint64_t run_count(const Spec& spec);
/// False, with why, when the plan has more than kMaxPlanRuns runs.
bool check_plan_size(const Spec& spec, std::string* err);
/// The runs of shard i of n (run r belongs to shard r mod n), expanded.
std::vector<PlannedRun> expand(const Spec& spec, std::uint64_t shard_i = 0, std::uint64_t shard_n = 1);
/// A hash of everything that defines the runs (resume and merge refuse a different plan).
std::string plan_id(const Spec& spec);
nlohmann::json spec_json(const Spec& spec);
bool spec_from_json(const nlohmann::json& j, Spec* out, std::string* err);

/// One run's overrides: the spec's --set list followed by "key=value" for each axis.
std::vector<std::string> run_overrides(const Spec& spec, const PlannedRun& run);

/// Executes runs in at most `jobs` forked worker processes, each running one run after another (the
/// next handed to it when it reports the last); a run that has not finished after timeout_s seconds
/// is killed with its worker and reported as "timeout"; a run whose worker dies is "crashed"; a new
/// worker takes the runs left.
/// on_row is called in the parent, in completion order, with the row (see the row layout in sweep_rows.cpp).
struct ExecOptions {
    unsigned jobs = 1;
    double timeout_s = 600.0;
    std::string runs_dir; // not empty: each run also writes metrics.json and trace.csv to runs_dir/RUN
};
void execute(const Spec& spec, const std::vector<PlannedRun>& runs, const ExecOptions& opt,
             const std::function<void(const nlohmann::json& row)>& on_row);

/// "metric<8", "speed_mean_rpm>=1485": a metric column of the summary, an operator, a number.
struct Assertion {
    std::string text, metric, op;
    double value = 0.0;
};
bool parse_assertion(const std::string& text, Assertion* out, std::string* err, bool identify = false);
/// Every metric column name a row can have (for checking --assert before any run).
std::vector<std::string> metric_columns();
/// The columns of an identification's row (--identify): per quantity of identification.json its
/// error ("Q.error_pct" and "Q.abs_error_pct" for relative ones, "Q.error" and "Q.abs_error" for
/// the others), "ok" (1: the identification succeeded), standstill_s, spin_s, duration_s.
std::vector<std::string> identify_metric_columns();
/// An identification's row metrics from identification.json (quantities whose step ran).
nlohmann::json identify_metrics(const nlohmann::json& report);

/// Writes summary.csv and summary.json in dir from the rows (sorted by "run").
bool write_summary(const std::string& dir, const Spec& spec, std::vector<nlohmann::json> rows, std::string* err);

/// Reads dir/rows.jsonl (a torn last line, from a killed sweep, is ignored).
std::vector<nlohmann::json> read_rows(const std::string& dir);

/// The command line of `dtc-sil sweep`, `sweep-merge` and `sweep-exec`, as parsed (no file read,
/// nothing checked beyond each option's own type and range).
struct SweepArgs {
    enum class Command { None, Sweep, Merge, Exec } cmd = Command::None;
    std::string scenario_path, out_dir, shard_text, dask_addr;
    std::vector<std::string> sets, overlays, grids, zips, samples, asserts, merge_dirs;
    std::uint64_t n = 0, seed = 1;
    unsigned jobs = 1;      ///< --jobs; the cores present unless given
    unsigned chunk = 0;     ///< --chunk; 0: chosen from the workers
    unsigned exec_jobs = 1; ///< sweep-exec --jobs
    double timeout_s = 600.0;
    bool resume = false, quiet = false, keep_runs = false, allow_failed = false;
    bool identify = false;  ///< --identify: each run is dtc-sil identify
};

/// Parses the sweep commands' line (args[0] the program, args[1] the subcommand) into *a.
/// Returns -1 when accepted, else the exit status with CLI11's text written: 0 after --help on
/// out, 1 after a usage error on err.
int parse_sweep_args(const std::vector<std::string>& args, SweepArgs* a, std::ostream& out, std::ostream& err);

/// The `dtc-sil sweep`, `sweep-merge` and `sweep-exec` commands (args[0] is the program, args[1]
/// the subcommand). Exit status: 0 done, 1 bad specification (nothing run), 2 a run could not be
/// executed at all, output failed or runs have no row (sweep-merge: a shard is missing), 3 an
/// --assert was violated, 4 a run crashed, timed out, diverged or could not be completed (0 with
/// --allow-failed-runs), 128 + N interrupted by signal N (the rows so far are kept).
int sweep_main(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

} // namespace sil::sweep

#endif // DTC_SIL_SWEEP_HPP
