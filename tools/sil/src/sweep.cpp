// sweep.cpp - the command line of dtc-sil sweep / sweep-merge / sweep-exec (see sweep.hpp): the
// options, every refusal before a run starts, the output folder, progress and the exit status. The
// plan is sweep_plan.cpp's, the execution sweep_exec.cpp's, the rows and summary sweep_rows.cpp's.
#include "sweep.hpp"


#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <set>
#include <thread>

#include <sys/wait.h>
#include <unistd.h>

#include "run.hpp"
#include "sweep_detail.hpp"
#include "toml_limits.hpp"


namespace sil::sweep {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace detail;

namespace {

struct Progress {
    bool tty = false;
    std::uint64_t total = 0, done = 0, failed = 0;
    std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now(), last{};
    void tick(std::ostream& err, bool final_line = false)
    {
        if (!tty) {
            return;
        }
        const auto now = std::chrono::steady_clock::now();
        if (!final_line && now - last < std::chrono::milliseconds(200)) {
            return;
        }
        last = now;
        const double el = std::chrono::duration<double>(now - t0).count();
        const double rate = el > 0.0 ? static_cast<double>(done) / el : 0.0;
        const double eta = rate > 0.0 ? static_cast<double>(total - done) / rate : 0.0;
        char line[160];
        std::snprintf(line, sizeof line, "\rsweep: %llu/%llu runs (%llu not ok), %.1f runs/s, ETA %.0f s   ",
                      static_cast<unsigned long long>(done), static_cast<unsigned long long>(total),
                      static_cast<unsigned long long>(failed), rate, eta);
        err << line << (final_line ? "\n" : "") << std::flush;
    }
};


/// `dtc-sil sweep-merge`: the rows of the shards' folders, checked to be of one plan, into out_dir.
int cmd_merge(const std::vector<std::string>& dirs, const std::string& out_dir, std::ostream& out, std::ostream& err)
{
    std::string e;
    Spec spec;
    std::string id;
    std::map<std::uint64_t, json> rows;
    for (const std::string& d : dirs) {
        const std::string text = read_file((fs::path(d) / "plan.json").string(), &e);
        const json pj = json::parse(text, nullptr, false);
        Spec s;
        if (!e.empty() || pj.is_discarded() || !spec_from_json(pj.value("spec", json::object()), &s, &e)) {
            err << "dtc-sil sweep-merge: " << d << ": not a sweep folder (" << (e.empty() ? "bad plan.json" : e)
                << ")\n";
            return 1;
        }
        if (id.empty()) {
            id = plan_id(s);
            spec = s;
        } else if (plan_id(s) != id) {
            err << "dtc-sil sweep-merge: " << d << ": a different sweep plan (" << plan_id(s) << ", expected " << id
                << ")\n";
            return 1;
        }
        for (json& r : read_rows(d)) {
            rows.emplace(r.at("run").get<std::uint64_t>(), std::move(r));
        }
    }
    std::error_code ec;
    fs::create_directories(out_dir, ec);
    std::vector<json> all;
    std::string jsonl;
    for (auto& [k, r] : rows) {
        jsonl += r.dump() + "\n";
        all.push_back(r);
    }
    json plan{{"plan_id", id}, {"spec", spec_json(spec)}, {"shard", "0/1"}};
    if (!write_text_file(fs::path(out_dir) / "plan.json", plan.dump(1) + "\n", &e) ||
        !write_text_file(fs::path(out_dir) / "rows.jsonl", jsonl, &e) || !write_summary(out_dir, spec, all, &e)) {
        err << "dtc-sil sweep-merge: " << e << "\n";
        return 2;
    }
    const std::uint64_t total = run_count(spec);
    out << "sweep-merge: " << all.size() << " of " << total << " runs";
    if (all.size() < total) {
        out << " (" << total - all.size() << " missing: run the missing shards, or --resume them)";
    }
    out << "; wrote " << (fs::path(out_dir) / "summary.csv").string() << "\n";
    if (all.size() < total) {
        err << "dtc-sil sweep-merge: " << total - all.size() << " of " << total
            << " runs have no row (a shard missing or incomplete)\n";
        return 2;
    }
    return 0;
}

} // namespace

int sweep_main(const std::vector<std::string>& args, std::ostream& out, std::ostream& err)
{
    SweepArgs cl;
    if (const int rc = parse_sweep_args(args, &cl, out, err); rc >= 0) {
        return rc;
    }
    const std::string& scenario_path = cl.scenario_path;
    const std::string& out_dir = cl.out_dir;
    const std::string& shard_text = cl.shard_text;
    const std::string& dask_addr = cl.dask_addr;
    const std::vector<std::string>& sets = cl.sets;
    const std::vector<std::string>& overlays = cl.overlays;
    const std::vector<std::string>& grids = cl.grids;
    const std::vector<std::string>& zips = cl.zips;
    const std::vector<std::string>& samples = cl.samples;
    const std::vector<std::string>& asserts = cl.asserts;
    const std::vector<std::string>& merge_dirs = cl.merge_dirs;
    const std::uint64_t& n = cl.n;
    const std::uint64_t& seed = cl.seed;
    const unsigned& jobs = cl.jobs;
    const unsigned& chunk = cl.chunk;
    const unsigned& exec_jobs = cl.exec_jobs;
    const double& timeout_s = cl.timeout_s;
    const bool& resume = cl.resume;
    const bool& quiet = cl.quiet;
    const bool& keep_runs = cl.keep_runs;
    const bool& allow_failed = cl.allow_failed;

    if (cl.cmd == SweepArgs::Command::Exec) {
        return cmd_exec(std::cin, out, err, exec_jobs);
    }

    std::string e;
    if (cl.cmd == SweepArgs::Command::Merge) {
        return cmd_merge(merge_dirs, out_dir, out, err);
    }

    // ---- sweep: everything that can be refused is refused before any run starts. ----
    Spec spec;
    spec.scenario_path = scenario_path;
    spec.scenario_text = read_file(scenario_path, &e);
    if (!e.empty()) {
        err << "dtc-sil sweep: " << e << "\n";
        return 1;
    }
    for (const std::string& o : overlays) {
        Diagnostics od;
        OverlayText ot;
        if (!read_overlay(o, &ot, &od)) {
            err << "dtc-sil sweep: " << od.text();
            return 1;
        }
        spec.overlays.push_back(ot);
    }
    spec.sets = sets;
    spec.seed = seed;
    spec.identify = cl.identify;
    // The axes in the order of their options: --grid, then --zip, then --sample.
    const std::vector<std::string>* const axis_args[3] = {&grids, &zips, &samples};
    for (const std::vector<std::string>* args_of_kind : axis_args) {
        for (const std::string& arg : *args_of_kind) {
            Axis a;
            const bool ok = args_of_kind == &samples ? parse_sample_axis(arg, &a, &e)
                            : args_of_kind == &zips  ? parse_grid_axis(arg, &a, &e, "--zip")
                                                     : parse_grid_axis(arg, &a, &e);
            if (!ok) {
                err << "dtc-sil sweep: " << e << "\n";
                return 1;
            }
            if (a.kind == Axis::Kind::Zip && !spec.axes.empty() && spec.axes.back().kind == Axis::Kind::Zip &&
                a.values.size() != spec.axes.back().values.size()) {
                err << "dtc-sil sweep: --zip " << arg << ": " << a.values.size()
                    << " values, but the other --zip axes have " << spec.axes.back().values.size()
                    << " (zipped axes go together value by value)\n";
                return 1;
            }
            spec.axes.push_back(a);
        }
    }
    if (samples.empty() && n != 0) {
        err << "dtc-sil sweep: --n " << n << ": --n counts samples of the --sample axes, and there is none\n";
        return 1;
    }
    if (!samples.empty() && n == 0) {
        err << "dtc-sil sweep: --sample needs --n N (samples per grid point, N >= 1)\n";
        return 1;
    }
    spec.n = samples.empty() ? 1 : n;
    if (spec.axes.empty()) {
        err << "dtc-sil sweep: nothing to sweep: give at least one --grid, --zip or --sample axis\n";
        return 1;
    }
    if (!check_plan_size(spec, &e)) {
        err << "dtc-sil sweep: " << (samples.empty() ? "" : "--n " + std::to_string(n) + ": ") << e << "\n";
        return 1;
    }
    std::set<std::string> axis_keys;
    for (const Axis& a : spec.axes) {
        if (!axis_keys.insert(a.key).second) {
            err << "dtc-sil sweep: axis key " << a.key << " is given twice\n";
            return 1;
        }
    }
    std::uint64_t shard_i = 0, shard_n = 1;
    if (!shard_text.empty() && !parse_shard(shard_text, &shard_i, &shard_n, &e)) {
        err << "dtc-sil sweep: " << e << "\n";
        return 1;
    }
    std::vector<Assertion> checks;
    for (const std::string& a : asserts) {
        Assertion as;
        if (!parse_assertion(a, &as, &e, spec.identify)) {
            err << "dtc-sil sweep: " << e << "\n";
            return 1;
        }
        checks.push_back(as);
    }
    if (keep_runs && !dask_addr.empty()) {
        err << "dtc-sil sweep: --keep-runs with --dask: the runs would be written on the workers' disks; "
               "sweep without --keep-runs, or run the cases to keep locally\n";
        return 1;
    }
    if (!dask_addr.empty() && dask_addr.find("://") == std::string::npos) {
        err << "dtc-sil sweep: --dask " << dask_addr << ": expected a scheduler address like tcp://HOST:PORT\n";
        return 1;
    }
    if (!check_axes(spec, &e)) {
        err << "dtc-sil sweep: " << e << "\n";
        return 1;
    }
    const std::string id = plan_id(spec);
    const fs::path dir(out_dir);
    std::error_code ec;
    const bool has_rows = fs::exists(dir / "rows.jsonl", ec);
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
        err << "dtc-sil sweep: --out " << out_dir << ": exists and is not a directory\n";
        return 1;
    }
    if (has_rows && !resume) {
        err << "dtc-sil sweep: --out " << out_dir << ": holds a sweep already (--resume continues it)\n";
        return 1;
    }
    if (resume && has_rows) {
        const json pj = json::parse(read_file((dir / "plan.json").string(), &e), nullptr, false);
        if (pj.is_discarded() || pj.value("plan_id", std::string()) != id ||
            pj.value("shard", std::string()) != std::to_string(shard_i) + "/" + std::to_string(shard_n)) {
            err << "dtc-sil sweep: --resume: " << out_dir << " holds a different sweep plan or shard\n";
            return 1;
        }
    }
    fs::create_directories(dir, ec);
    if (ec) {
        err << "dtc-sil sweep: --out " << out_dir << ": " << ec.message() << "\n";
        return 1;
    }
    json plan{{"plan_id", id},
              {"spec", spec_json(spec)},
              {"shard", std::to_string(shard_i) + "/" + std::to_string(shard_n)}};
    if (!write_text_file(dir / "plan.json", plan.dump(1) + "\n", &e)) {
        err << "dtc-sil sweep: " << e << "\n";
        return 2;
    }

    const std::vector<PlannedRun> all = expand(spec, shard_i, shard_n);
    // Rows kept from an interrupted sweep, rewritten without a torn last line so that new rows
    // start on a line of their own.
    std::set<std::uint64_t> have;
    std::string kept;
    for (const json& r : read_rows(out_dir)) {
        have.insert(r.at("run").get<std::uint64_t>());
        kept += r.dump() + "\n";
    }
    if (!write_text_file(dir / "rows.jsonl", kept, &e)) {
        err << "dtc-sil sweep: " << e << "\n";
        return 2;
    }
    std::vector<PlannedRun> todo;
    for (const PlannedRun& p : all) {
        if (have.count(p.index) == 0) {
            todo.push_back(p);
        }
    }

    Progress prog;
    prog.tty = isatty(2) != 0 && !quiet;
    prog.total = todo.size();
    if (!dask_addr.empty()) {
        DaskJob job{dask_addr, chunk, timeout_s, self_exe(args.empty() ? "dtc-sil" : args[0]), prog.tty};
        out.flush();
        err.flush();
        if (const int rc = run_on_dask(spec, todo, dir, job, err); rc != 0) {
            return rc;
        }
    } else {
        std::FILE* rows_f = std::fopen((dir / "rows.jsonl").string().c_str(), "ab");
        if (rows_f == nullptr) {
            err << "dtc-sil sweep: " << (dir / "rows.jsonl").string() << ": " << std::strerror(errno) << "\n";
            return 2;
        }
        ExecOptions opt;
        opt.jobs = jobs;
        opt.timeout_s = timeout_s;
        if (keep_runs) {
            opt.runs_dir = (dir / "runs").string();
        }
        StopSignals stop_signals;
        execute(spec, todo, opt, [&](const json& row) {
            const std::string line = row.dump() + "\n";
            std::fwrite(line.data(), 1, line.size(), rows_f);
            std::fflush(rows_f);
            ++prog.done;
            prog.failed += row.at("status") == "ok" ? 0u : 1u;
            prog.tick(err);
        });
        std::fclose(rows_f);
        prog.tick(err, true);
        if (g_stop_signal != 0) {
            err << "dtc-sil sweep: interrupted by signal " << static_cast<int>(g_stop_signal)
                << ": the runs in flight were killed; the " << prog.done << " rows so far are kept in "
                << (dir / "rows.jsonl").string() << " (--resume continues)\n";
            return 128 + static_cast<int>(g_stop_signal);
        }
    }

    // Summary of this shard's runs (rows of other plans or shards cannot be in this folder).
    std::vector<json> rows;
    std::set<std::uint64_t> mine;
    for (const PlannedRun& p : all) {
        mine.insert(p.index);
    }
    std::map<std::uint64_t, json> by_run;
    for (json& r : read_rows(out_dir)) {
        const auto k = r.at("run").get<std::uint64_t>();
        if (mine.count(k) != 0) {
            by_run.emplace(k, std::move(r));
        }
    }
    std::map<std::string, std::uint64_t> status_count;
    std::vector<std::string> violations, failed;
    for (auto& [k, r] : by_run) {
        const std::string status = r.at("status").is_string() ? r.at("status").get<std::string>() : "?";
        ++status_count[status];
        if (status == "crashed" || status == "timeout" || status == "diverged" || status == "error") {
            const json& why = r.at("error");
            failed.push_back("run " + std::to_string(k) + ": " + status +
                             (why.is_string() ? ": " + echo(why.get<std::string>()) : std::string()));
        }
        for (const Assertion& a : checks) {
            const std::string v = violation(a, r);
            if (!v.empty()) {
                violations.push_back("run " + std::to_string(k) + ": " + a.text + " violated: " + v);
            }
        }
        rows.push_back(std::move(r));
    }
    if (!write_summary(out_dir, spec, rows, &e)) {
        err << "dtc-sil sweep: " << e << "\n";
        return 2;
    }
    if (!quiet) {
        out << "sweep: " << rows.size() << " of " << all.size() << " runs";
        for (const auto& [s, c] : status_count) {
            out << ", " << c << " " << s;
        }
        out << "; wrote " << (dir / "summary.csv").string() << "\n";
    }
    if (rows.size() < all.size()) {
        err << "dtc-sil sweep: " << all.size() - rows.size() << " runs have no row\n";
        return 2;
    }
    auto list = [&err](const std::vector<std::string>& lines, const char* what) {
        const std::size_t shown = std::min<std::size_t>(lines.size(), 50);
        for (std::size_t i = 0; i < shown; ++i) {
            err << "dtc-sil sweep: " << lines[i] << "\n";
        }
        if (shown < lines.size()) {
            err << "dtc-sil sweep: ... and " << lines.size() - shown << " more " << what << "\n";
        }
    };
    if (!failed.empty() && !allow_failed) {
        list(failed, "failed runs");
        err << "dtc-sil sweep: " << failed.size() << " of " << rows.size()
            << " runs crashed, timed out, diverged or could not be completed (--allow-failed-runs accepts "
               "that)\n";
        return 4;
    }
    if (!violations.empty()) {
        const std::size_t shown = std::min<std::size_t>(violations.size(), 50);
        for (std::size_t i = 0; i < shown; ++i) {
            err << "dtc-sil sweep: " << violations[i] << "\n";
        }
        if (shown < violations.size()) {
            err << "dtc-sil sweep: ... and " << violations.size() - shown << " more violations\n";
        }
        return 3;
    }
    return 0;
}

} // namespace sil::sweep
