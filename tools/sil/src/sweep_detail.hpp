// sweep_detail.hpp - what the sweep's parts (plan, execution, rows, command line) share inside
// sil_run; not an interface of the library (sweep.hpp is).
#ifndef DTC_SIL_SWEEP_DETAIL_HPP
#define DTC_SIL_SWEEP_DETAIL_HPP

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sweep.hpp"

namespace sil::sweep::detail {

// ---- sweep_plan.cpp ----
/// The shortest decimal text that reads back as x.
std::string shortest(double x);
std::string trim(const std::string& s);
/// A finite number, the whole of s (leading '+' allowed); false otherwise.
bool parse_double(const std::string& s, double* x);
/// Length of the zip axes (0 without any).
std::size_t zip_length(const Spec& spec);
/// Run r of the plan (r < run_count(spec)).
PlannedRun planned_run(const Spec& spec, std::uint64_t r);
/// "I/N" of --shard.
bool parse_shard(const std::string& s, std::uint64_t* i, std::uint64_t* n, std::string* err);
/// Checks every axis value and zip case against the scenario before anything runs.
bool check_axes(const Spec& spec, std::string* err);

// ---- sweep_rows.cpp ----
/// metrics.json flattened to a row's "metrics" (without the wall-clock figures).
nlohmann::json metrics_row(const nlohmann::json& metrics);
nlohmann::json make_row(std::uint64_t run, const Spec& spec, const PlannedRun& p, const std::string& status,
                        const nlohmann::json& fault, const nlohmann::json& error, const nlohmann::json& metrics);
/// Empty when the row satisfies the assertion, else why not.
std::string violation(const Assertion& a, const nlohmann::json& row);
/// Writes p through p.tmp and a rename.
bool write_text_file(const std::filesystem::path& p, const std::string& text, std::string* err);
std::string read_file(const std::string& path, std::string* err);

// ---- sweep_exec.cpp ----
/// This executable's path (for the Dask workers), argv0 when /proc is not there.
std::string self_exe(const std::string& argv0);
/// The cluster path: tools/sweep/dask_sweep.py (DTC_SIL_DASK_SCRIPT overrides) hands chunks of the
/// pending runs to the scheduler and appends each chunk's rows to dir/rows.jsonl.
struct DaskJob {
    std::string scheduler; // tcp://HOST:PORT
    unsigned chunk = 0;    // runs per task (0: the script chooses)
    double timeout_s = 600.0;
    std::string exe;       // this executable, run by the workers as `sweep-exec`
    bool progress = false;
};
/// 0 when every chunk ran; else the sweep's exit status (1 or 2), with the reason on err.
int run_on_dask(const Spec& spec, const std::vector<PlannedRun>& todo, const std::filesystem::path& dir,
                const DaskJob& job, std::ostream& err);
/// `dtc-sil sweep-exec`: a chunk of runs read from `in`, one row per line on `out`.
int cmd_exec(std::istream& in, std::ostream& out, std::ostream& err, unsigned jobs);

} // namespace sil::sweep::detail

#endif // DTC_SIL_SWEEP_DETAIL_HPP
