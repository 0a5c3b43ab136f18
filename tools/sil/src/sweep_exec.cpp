// sweep_exec.cpp - a sweep's execution: the local process pool (forked workers that run one run
// after another, with a per-run limit) and the `sweep-exec` side of the Dask hand-off (see sweep.hpp).
#include "sweep.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <set>
#include <sstream>

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include "identify.hpp"
#include "metrics.hpp"
#include "run.hpp"
#include "scenario.hpp"
#include "sil_output.hpp"
#include "sweep_detail.hpp"
#include "toml_limits.hpp"

#ifndef DTC_SWEEP_DASK_SCRIPT
#define DTC_SWEEP_DASK_SCRIPT ""
#endif

namespace sil::sweep {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace detail;

namespace {

// The body of one run's child process: the row as JSON text, and in *spectrum_n the length of the
// metrics' spectra (0: none).
std::string child_run(const Spec& spec, const PlannedRun& p, const std::string& runs_dir, std::size_t* spectrum_n)
{
    *spectrum_n = 0;
    Scenario sc;
    Diagnostics diag;
    if (!parse_scenario(spec.scenario_text, spec.scenario_path, run_overrides(spec, p), &sc, &diag, spec.overlays)) {
        std::string e;
        for (const std::string& s : diag.errors) {
            e += (e.empty() ? "" : "; ") + s;
        }
        return make_row(p.index, spec, p, "refused", nullptr, e, json::object()).dump();
    }
    if (spec.identify) {
        // The identification (dtc-sil identify): its errors against the plant's values as the metrics,
        // status ok when it succeeded, fault naming the reason when it stopped.
        IdentifyReport rep;
        std::string e;
        const std::string dir = runs_dir.empty() ? std::string() : (fs::path(runs_dir) / std::to_string(p.index)).string();
        if (!identify(sc, dir, &rep, &e)) {
            return make_row(p.index, spec, p, "error", nullptr, e, json::object()).dump();
        }
        const json rj = json::parse(rep.json);
        const std::string code = rep.reason.substr(0, rep.reason.find(':'));
        return make_row(p.index, spec, p, rep.ok ? "ok" : "fault", rep.ok ? json(nullptr) : json(rep.failed_step + ": " + code),
                        rep.ok ? json(nullptr) : json(rep.reason), identify_metrics(rj))
            .dump();
    }
    RunOptions opt; // no output folder (metrics only), unless the sweep keeps its runs
    if (!runs_dir.empty()) {
        opt.out_dir = (fs::path(runs_dir) / std::to_string(p.index)).string();
    }
    RunResult res;
    std::string e;
    if (!run_scenario(sc, opt, &res, &e)) {
        return make_row(p.index, spec, p, "error", nullptr, e, json::object()).dump();
    }
    if (res.metrics.window.periods >= 1) {
        *spectrum_n = res.metrics.window.n;
    }
    const json mj = metrics_json(sc, res.metrics, res.info);
    const std::string fault = res.info.fault;
    // A plant that left physics (or a metric that is not finite) is not a drive trip.
    const char* status = run_failed_physically(res.info) ? "diverged" : fault == "none" ? "ok" : "fault";
    return make_row(p.index, spec, p, status, fault, run_failed_physically(res.info) ? json(res.info.fault_detail) : json(nullptr),
                    metrics_row(mj))
        .dump();
}

std::string signal_text(int sig)
{
    const char* d = strsignal(sig);
    return "signal " + std::to_string(sig) + " (" + (d ? d : "?") + ")";
}


} // namespace

void execute(const Spec& spec, const std::vector<PlannedRun>& runs, const ExecOptions& opt,
             const std::function<void(const json& row)>& on_row)
{
    // A worker is a forked child that runs one run after another: the parent hands it the next
    // run's position in `runs` (8 bytes on its socket) when it has sent the previous run's result,
    // and shuts the socket's sending side when none is left, which ends the worker. A worker pays
    // its process's start (the page faults of the code it runs and of the memory a run fills) once
    // for all its runs instead of once per run. A run's result is two lines: the row (JSON, no
    // newline inside) and the length of its metrics' spectra (0: none).
    constexpr std::size_t kIdle = static_cast<std::size_t>(-1);
    struct Worker {
        pid_t pid;
        int fd;
        std::string buf;
        std::chrono::steady_clock::time_point start; // of the run in flight
        std::size_t run = kIdle;                      // position in `runs` of the run in flight
        bool timed_out = false;
    };
    std::vector<Worker> active;
    std::size_t next = 0;
    // Spectrum lengths the runs reported, planned here once each: the workers forked after it
    // inherit FFTW's planner memory (prepare_spectrum()); a worker's own planner memory is warm from
    // its first run on.
    std::set<std::size_t> spectra;
    const unsigned jobs = std::max(1u, opt.jobs);
    const auto limit = std::chrono::duration<double>(opt.timeout_s);

    // The run in flight on w gets its row from what w sent, or the reason it has none.
    auto take_result = [&](Worker& w) {
        // Complete results only: the row's line and the spectrum line.
        const std::size_t eol = w.buf.find('\n');
        if (eol == std::string::npos) {
            return false;
        }
        const std::size_t eol2 = w.buf.find('\n', eol + 1);
        if (eol2 == std::string::npos) {
            return false;
        }
        const PlannedRun& p = runs[w.run];
        const std::uint64_t spectrum_n = std::strtoull(w.buf.c_str() + eol + 1, nullptr, 10);
        json row = json::parse(w.buf.begin(), w.buf.begin() + static_cast<std::ptrdiff_t>(eol), nullptr, false);
        w.buf.erase(0, eol2 + 1);
        w.run = kIdle;
        if (row.is_discarded() || !row.is_object()) {
            on_row(make_row(p.index, spec, p, "crashed", nullptr, "run process sent no readable result",
                            json::object()));
            return true;
        }
        if (spectrum_n != 0 && spectrum_n <= kMaxWindowSamples && spectra.insert(spectrum_n).second) {
            prepare_spectrum(static_cast<std::size_t>(spectrum_n));
        }
        on_row(row);
        return true;
    };
    // Hands w the next run, or ends it when there is none. False: the worker is gone (the run
    // is then its run in flight, reported by finish()).
    auto dispatch = [&](Worker& w) {
        if (next >= runs.size()) {
            shutdown(w.fd, SHUT_WR);
            return true;
        }
        const std::uint64_t pos = next++;
        w.run = static_cast<std::size_t>(pos);
        w.start = std::chrono::steady_clock::now();
        return send(w.fd, &pos, sizeof pos, MSG_NOSIGNAL) == static_cast<ssize_t>(sizeof pos);
    };
    // A worker that ended: its run in flight, if any, gets a row saying why it has no result.
    auto finish = [&](Worker& w) {
        int status = 0;
        while (waitpid(w.pid, &status, 0) < 0 && errno == EINTR) {
        }
        close(w.fd);
        if (w.run == kIdle) {
            return;
        }
        const PlannedRun& p = runs[w.run];
        if (w.timed_out) {
            on_row(make_row(p.index, spec, p, "timeout", nullptr,
                            "killed after the per-run limit of " + shortest(opt.timeout_s) + " s", json::object()));
            return;
        }
        if (WIFSIGNALED(status) && g_stop_signal != 0 &&
            (WTERMSIG(status) == SIGINT || WTERMSIG(status) == SIGTERM)) {
            return; // the sweep's interruption reached the run too: no row, --resume runs it
        }
        if (WIFSIGNALED(status)) {
            on_row(make_row(p.index, spec, p, "crashed", nullptr, "run process died: " + signal_text(WTERMSIG(status)),
                            json::object()));
            return;
        }
        on_row(make_row(p.index, spec, p, "crashed", nullptr,
                        "run process exited with status " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                            " and no result",
                        json::object()));
    };

    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    while (next < runs.size() || !active.empty()) {
        if (g_stop_signal != 0) {
            // Interrupted: the runs in flight are killed and have no row (--resume runs them).
            for (Worker& w : active) {
                kill(w.pid, SIGKILL);
                int status = 0;
                while (waitpid(w.pid, &status, 0) < 0 && errno == EINTR) {
                }
                close(w.fd);
            }
            active.clear();
            return;
        }
        while (active.size() < jobs && next < runs.size()) {
            int fds[2];
            if (socketpair(AF_UNIX, SOCK_STREAM, 0, fds) != 0) {
                const PlannedRun& p = runs[next++];
                on_row(make_row(p.index, spec, p, "error", nullptr, std::string("socketpair: ") + std::strerror(errno),
                                json::object()));
                continue;
            }
            const pid_t parent = getpid();
            const pid_t pid = fork();
            if (pid == 0) {
                // The worker stays in the parent's process group (a terminal's ^C reaches it), dies
                // on SIGINT/SIGTERM instead of finishing its run, and is killed when the parent
                // dies, whatever kills it.
                std::signal(SIGINT, SIG_DFL);
                std::signal(SIGTERM, SIG_DFL);
                prctl(PR_SET_PDEATHSIG, SIGKILL);
                if (getppid() != parent) {
                    _exit(4); // the parent died before the line above
                }
                close(fds[0]);
                for (const Worker& w : active) {
                    close(w.fd); // else another worker would not see its socket shut
                }
                const int devnull = open("/dev/null", O_WRONLY);
                if (devnull >= 0) {
                    dup2(devnull, 1);
                    dup2(devnull, 2);
                }
                for (;;) {
                    std::uint64_t pos = 0;
                    std::size_t got = 0;
                    while (got < sizeof pos) {
                        const ssize_t r = read(fds[1], reinterpret_cast<char*>(&pos) + got, sizeof pos - got);
                        if (r < 0 && errno == EINTR) {
                            continue;
                        }
                        if (r <= 0) {
                            _exit(got == 0 ? 0 : 3); // no run left (or a torn command)
                        }
                        got += static_cast<std::size_t>(r);
                    }
                    if (pos >= runs.size()) {
                        _exit(3);
                    }
                    std::size_t spectrum_n = 0;
                    std::string text = child_run(spec, runs[static_cast<std::size_t>(pos)], opt.runs_dir, &spectrum_n);
                    text += "\n" + std::to_string(spectrum_n) + "\n";
                    const char* b = text.data();
                    std::size_t left = text.size();
                    while (left > 0) {
                        const ssize_t wr = write(fds[1], b, left);
                        if (wr < 0 && errno == EINTR) {
                            continue;
                        }
                        if (wr <= 0) {
                            _exit(3);
                        }
                        b += wr;
                        left -= static_cast<std::size_t>(wr);
                    }
                }
            }
            close(fds[1]);
            if (pid < 0) {
                close(fds[0]);
                const PlannedRun& p = runs[next++];
                on_row(make_row(p.index, spec, p, "error", nullptr, std::string("fork: ") + std::strerror(errno),
                                json::object()));
                continue;
            }
            active.push_back(Worker{pid, fds[0], {}, std::chrono::steady_clock::now()});
            if (!dispatch(active.back())) {
                kill(pid, SIGKILL);
                finish(active.back());
                active.pop_back();
            }
        }
        if (active.empty()) {
            continue;
        }
        // Wait for output, an exit, or the nearest per-run deadline.
        const auto now = std::chrono::steady_clock::now();
        double wait_s = opt.timeout_s;
        for (const Worker& w : active) {
            if (w.run != kIdle) {
                wait_s = std::min(wait_s, (limit - (now - w.start)).count());
            }
        }
        std::vector<pollfd> pfd;
        for (const Worker& w : active) {
            pfd.push_back(pollfd{w.fd, POLLIN, 0});
        }
        const int ms = static_cast<int>(std::clamp(std::ceil(wait_s * 1000.0), 0.0, 1000.0));
        if (poll(pfd.data(), pfd.size(), ms) < 0 && errno != EINTR) {
            continue;
        }
        std::vector<std::size_t> done;
        for (std::size_t i = 0; i < active.size(); ++i) {
            Worker& w = active[i];
            if ((pfd[i].revents & (POLLIN | POLLHUP | POLLERR)) != 0) {
                char buf[65536];
                const ssize_t r = read(w.fd, buf, sizeof buf);
                if (r > 0) {
                    w.buf.append(buf, static_cast<std::size_t>(r));
                    if (w.run != kIdle && take_result(w) && !dispatch(w)) {
                        kill(w.pid, SIGKILL);
                        done.push_back(i);
                    }
                    continue;
                }
                if (r == 0 || errno != EINTR) {
                    done.push_back(i);
                    continue;
                }
            }
            if (w.run != kIdle && std::chrono::steady_clock::now() - w.start > limit) {
                kill(w.pid, SIGKILL);
                w.timed_out = true;
                done.push_back(i);
            }
        }
        for (std::size_t k = done.size(); k-- > 0;) {
            finish(active[done[k]]);
            active.erase(active.begin() + static_cast<std::ptrdiff_t>(done[k]));
        }
    }
}

namespace detail {

std::string self_exe(const std::string& argv0)
{
    std::error_code ec;
    const fs::path p = fs::read_symlink("/proc/self/exe", ec);
    return ec ? argv0 : p.string();
}

int cmd_exec(std::istream& in, std::ostream& out, std::ostream& err, unsigned jobs)
{
    std::stringstream ss;
    ss << in.rdbuf();
    const json j = json::parse(ss.str(), nullptr, false);
    Spec spec;
    std::string e;
    if (j.is_discarded() || !j.contains("spec") || !j.contains("runs") || !spec_from_json(j.at("spec"), &spec, &e)) {
        err << "dtc-sil sweep-exec: standard input is not a sweep chunk" << (e.empty() ? "" : ": " + e) << "\n";
        return 1;
    }
    std::vector<PlannedRun> runs;
    const std::uint64_t total = run_count(spec);
    if (!j.at("runs").is_array()) {
        err << "dtc-sil sweep-exec: \"runs\" is not an array of run numbers\n";
        return 1;
    }
    for (const json& r : j.at("runs")) {
        if (!r.is_number_unsigned()) {
            err << "dtc-sil sweep-exec: run " << echo(r.dump()) << " is not a run number\n";
            return 1;
        }
        const std::uint64_t idx = r.get<std::uint64_t>();
        if (idx >= total) {
            err << "dtc-sil sweep-exec: run " << idx << " is not in the plan (" << total << " runs)\n";
            return 1;
        }
        runs.push_back(planned_run(spec, idx));
    }
    ExecOptions opt;
    opt.jobs = jobs;
    if (j.contains("timeout_s")) {
        opt.timeout_s = j.at("timeout_s").is_number() ? j.at("timeout_s").get<double>() : 0.0;
        if (!(opt.timeout_s > 0.0 && opt.timeout_s <= 1e7)) { // also false for NaN
            err << "dtc-sil sweep-exec: timeout_s must be a number in (0, 1e7]\n";
            return 1;
        }
    }
    execute(spec, runs, opt, [&](const json& row) { out << row.dump() << "\n" << std::flush; });
    return 0;
}

int run_on_dask(const Spec& spec, const std::vector<PlannedRun>& todo, const fs::path& dir, const DaskJob& dj,
                std::ostream& err)
{
    const char* env_script = std::getenv("DTC_SIL_DASK_SCRIPT");
    const std::string script = env_script != nullptr ? env_script : DTC_SWEEP_DASK_SCRIPT;
    json pending = json::array();
    for (const PlannedRun& p : todo) {
        pending.push_back(p.index);
    }
    json job{{"spec", spec_json(spec)}, {"pending", pending}, {"chunk", dj.chunk}, {"timeout_s", dj.timeout_s},
             {"exe", dj.exe}, {"scheduler", dj.scheduler}, {"rows", (dir / "rows.jsonl").string()},
             {"progress", dj.progress}};
    std::string e;
    if (!write_text_file(dir / "dask_job.json", job.dump() + "\n", &e)) {
        err << "dtc-sil sweep: " << e << "\n";
        return 2;
    }
    const std::string cmd = "/usr/bin/python3 '" + script + "' '" + (dir / "dask_job.json").string() + "'";
    const int rc = std::system(cmd.c_str());
    std::error_code ec;
    fs::remove(dir / "dask_job.json", ec);
    if (rc != 0) {
        const int code = WIFEXITED(rc) ? WEXITSTATUS(rc) : 2;
        err << "dtc-sil sweep: the Dask run did not complete (rows so far are kept; --resume continues)\n";
        return code == 1 ? 1 : 2;
    }
    return 0;
}

} // namespace detail

} // namespace sil::sweep
