// sweep.cpp - dtc-sil sweep / sweep-merge / sweep-exec (see sweep.hpp).
//
// Row layout (one JSON object per run, rows.jsonl and summary.json):
//   run      run index in the plan
//   values   {axis key: TOML value text} of the swept axes
//   status   ok | fault (the drive tripped; metrics are still those of the run) | refused (the
//            scenario with these values is invalid) | error (the run could not be completed) |
//            timeout (killed after the per-run limit) | crashed (the run's process died)
//   fault    the drive's fault name, or null
//   error    why a run is refused / error / timeout / crashed, or null
//   metrics  metrics.json of the run, flattened: nested objects as "a.b", per-phase arrays as
//            "name[A]", "name[B]", "name[C]"; without the wall-clock figures, so the same run gives
//            the same row wherever it executes.
#include "sweep.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <thread>

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include "run.hpp"
#include "scenario.hpp"
#include "sil_output.hpp"

#ifndef DTC_SWEEP_DASK_SCRIPT
#define DTC_SWEEP_DASK_SCRIPT ""
#endif

namespace sil::sweep {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string shortest(double x)
{
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    return std::string(buf, r.ptr);
}

const std::map<std::string, std::string>& key_types()
{
    static const std::map<std::string, std::string> types = [] {
        std::map<std::string, std::string> m;
        for (const KeyDoc& k : scenario_keys()) {
            m[k.name] = k.type;
        }
        return m;
    }();
    return types;
}

bool is_string_type(const std::string& t) { return t.find("string") != std::string::npos; }

std::string trim(const std::string& s)
{
    const auto b = s.find_first_not_of(" \t");
    if (b == std::string::npos) {
        return "";
    }
    const auto e = s.find_last_not_of(" \t");
    return s.substr(b, e - b + 1);
}

// "key=rest" with a known key.
bool split_key(const std::string& arg, const char* opt, std::string* key, std::string* rest, std::string* type,
               std::string* err)
{
    const auto eq = arg.find('=');
    if (eq == std::string::npos) {
        *err = std::string(opt) + " " + arg + ": expected KEY=...";
        return false;
    }
    *key = trim(arg.substr(0, eq));
    *rest = arg.substr(eq + 1);
    const auto it = key_types().find(*key);
    if (it == key_types().end()) {
        *err = std::string(opt) + " " + arg + ": unknown scenario key '" + *key + "' (dtc-sil keys lists them)";
        return false;
    }
    *type = it->second;
    return true;
}

// Splits at commas that are not inside [...] or quotes.
std::vector<std::string> split_top_level(const std::string& s)
{
    std::vector<std::string> parts;
    std::string cur;
    int depth = 0;
    char quote = 0;
    for (char c : s) {
        if (quote != 0) {
            cur += c;
            if (c == quote) {
                quote = 0;
            }
            continue;
        }
        if (c == '"' || c == '\'') {
            quote = c;
        } else if (c == '[') {
            ++depth;
        } else if (c == ']') {
            --depth;
        } else if (c == ',' && depth == 0) {
            parts.push_back(trim(cur));
            cur.clear();
            continue;
        }
        cur += c;
    }
    parts.push_back(trim(cur));
    return parts;
}

bool parse_double(const std::string& s, double* x)
{
    const std::string t = trim(s);
    if (t.empty()) {
        return false;
    }
    const char* b = t.data();
    const char* e = b + t.size();
    if (*b == '+') {
        ++b;
    }
    const auto r = std::from_chars(b, e, *x);
    return r.ec == std::errc() && r.ptr == e && std::isfinite(*x);
}

std::uint64_t splitmix64(std::uint64_t x)
{
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

// A uniform number in (0, 1) that depends only on (seed, run, axis, stream).
double unit_uniform(std::uint64_t seed, std::uint64_t run, std::uint64_t axis, std::uint64_t stream)
{
    std::uint64_t h = splitmix64(seed);
    h = splitmix64(h ^ run);
    h = splitmix64(h ^ (axis * 16u + stream));
    return (static_cast<double>(h >> 11) + 0.5) * 0x1.0p-53;
}

double draw(const Spec& spec, const Axis& ax, std::size_t axis_i, std::uint64_t run, std::uint64_t element)
{
    if (ax.kind == Axis::Kind::Uniform) {
        return ax.a + (ax.b - ax.a) * unit_uniform(spec.seed, run, axis_i, 2 * element);
    }
    const double u1 = unit_uniform(spec.seed, run, axis_i, 2 * element); // Box-Muller
    const double u2 = unit_uniform(spec.seed, run, axis_i, 2 * element + 1);
    return ax.a + ax.b * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

// A sampled value as TOML text: a number, a whole number for integer keys, or for a per-phase
// array key three independent draws.
std::string sampled_value(const Spec& spec, const Axis& ax, std::size_t axis_i, std::uint64_t run)
{
    if (ax.key_type == "integer") {
        return std::to_string(std::llround(draw(spec, ax, axis_i, run, 0)));
    }
    if (ax.key_type.rfind("array", 0) == 0) {
        return "[" + shortest(draw(spec, ax, axis_i, run, 0)) + ", " + shortest(draw(spec, ax, axis_i, run, 1)) + ", " +
               shortest(draw(spec, ax, axis_i, run, 2)) + "]";
    }
    return shortest(draw(spec, ax, axis_i, run, 0));
}

std::size_t zip_length(const Spec& spec)
{
    for (const Axis& a : spec.axes) {
        if (a.kind == Axis::Kind::Zip) {
            return a.values.size();
        }
    }
    return 0;
}

PlannedRun planned_run(const Spec& spec, std::uint64_t r)
{
    // Dimensions of the product, slowest first: the zip cases (if any), then each grid axis in
    // order, the last varying fastest; the n samples of a point are consecutive runs.
    PlannedRun p;
    p.index = r;
    std::uint64_t g = r / spec.n;
    std::vector<std::size_t> pick(spec.axes.size(), 0);
    for (std::size_t i = spec.axes.size(); i-- > 0;) {
        const Axis& a = spec.axes[i];
        if (a.kind == Axis::Kind::Grid) {
            pick[i] = static_cast<std::size_t>(g % a.values.size());
            g /= a.values.size();
        }
    }
    const std::size_t zip_case = static_cast<std::size_t>(g); // < zip_length (or 0 without zips)
    for (std::size_t i = 0; i < spec.axes.size(); ++i) {
        const Axis& a = spec.axes[i];
        if (a.kind == Axis::Kind::Grid) {
            p.values.push_back(a.values[pick[i]]);
        } else if (a.kind == Axis::Kind::Zip) {
            p.values.push_back(a.values[zip_case]);
        } else {
            p.values.push_back(sampled_value(spec, a, i, r));
        }
    }
    return p;
}

void flatten(const std::string& prefix, const json& j, json& out)
{
    static const char* phase[3] = {"A", "B", "C"};
    if (j.is_object()) {
        for (auto it = j.begin(); it != j.end(); ++it) {
            flatten(prefix.empty() ? it.key() : prefix + "." + it.key(), it.value(), out);
        }
    } else if (j.is_array()) {
        for (std::size_t i = 0; i < j.size(); ++i) {
            const std::string idx = j.size() == 3 ? phase[i] : std::to_string(i);
            flatten(prefix + "[" + idx + "]", j[i], out);
        }
    } else {
        out[prefix] = j;
    }
}

json metrics_row(const json& metrics)
{
    json m = metrics;
    for (const char* k : {"scenario", "wall_time_s", "realtime_factor", "config", "fault"}) {
        m.erase(k);
    }
    json flat = json::object();
    flatten("", m, flat);
    return flat;
}

json make_row(std::uint64_t run, const Spec& spec, const PlannedRun& p, const std::string& status,
              const json& fault, const json& error, const json& metrics)
{
    // Swept values as a reader wants them: strings without their TOML quotes.
    json values = json::object();
    for (std::size_t i = 0; i < spec.axes.size(); ++i) {
        const std::string& v = p.values[i];
        const bool quoted = v.size() >= 2 && (v.front() == '"' || v.front() == '\'') && v.back() == v.front();
        std::string shown = quoted ? v.substr(1, v.size() - 2) : v;
        if (quoted && v.front() == '"') {
            std::string u;
            for (std::size_t k = 0; k < shown.size(); ++k) {
                if (shown[k] == '\\' && k + 1 < shown.size()) {
                    ++k;
                }
                u += shown[k];
            }
            shown = u;
        }
        values[spec.axes[i].key] = shown;
    }
    return json{{"run", run}, {"values", values}, {"status", status}, {"fault", fault}, {"error", error},
                {"metrics", metrics}};
}

// The body of one run's child process: the row as JSON text.
std::string child_run(const Spec& spec, const PlannedRun& p, const std::string& runs_dir)
{
    Scenario sc;
    Diagnostics diag;
    if (!parse_scenario(spec.scenario_text, spec.scenario_path, run_overrides(spec, p), &sc, &diag)) {
        std::string e;
        for (const std::string& s : diag.errors) {
            e += (e.empty() ? "" : "; ") + s;
        }
        return make_row(p.index, spec, p, "refused", nullptr, e, json::object()).dump();
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
    const json mj = metrics_json(sc, res.metrics, res.info);
    const std::string fault = res.info.fault;
    return make_row(p.index, spec, p, fault == "none" ? "ok" : "fault", fault, nullptr, metrics_row(mj)).dump();
}

std::string signal_text(int sig)
{
    const char* d = strsignal(sig);
    return "signal " + std::to_string(sig) + " (" + (d ? d : "?") + ")";
}

std::string csv_cell(const json& v)
{
    if (v.is_null()) {
        return "";
    }
    if (v.is_boolean()) {
        return v.get<bool>() ? "true" : "false";
    }
    if (v.is_number_integer() || v.is_number_unsigned()) {
        return v.dump();
    }
    if (v.is_number_float()) {
        return shortest(v.get<double>());
    }
    std::string s = v.is_string() ? v.get<std::string>() : v.dump();
    if (s.find_first_of(",\"\n\r") != std::string::npos) {
        std::string q = "\"";
        for (char c : s) {
            q += c == '"' ? std::string("\"\"") : std::string(1, c);
        }
        return q + "\"";
    }
    return s;
}

bool write_text_file(const fs::path& p, const std::string& text, std::string* err)
{
    const fs::path tmp = p.string() + ".tmp";
    {
        std::ofstream f(tmp, std::ios::binary);
        f << text;
        f.close();
        if (!f) {
            *err = tmp.string() + ": write failed";
            return false;
        }
    }
    std::error_code ec;
    fs::rename(tmp, p, ec);
    if (ec) {
        *err = p.string() + ": " + ec.message();
        return false;
    }
    return true;
}

std::string read_file(const std::string& path, std::string* err)
{
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
        *err = path + ": not a readable file";
        return {};
    }
    std::ifstream f(path, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    if (!f) {
        *err = path + ": cannot be read";
        return {};
    }
    return ss.str();
}

} // namespace

bool parse_grid_axis(const std::string& arg, Axis* out, std::string* err, const char* opt)
{
    Axis a;
    std::string rest;
    if (!split_key(arg, opt, &a.key, &rest, &a.key_type, err)) {
        return false;
    }
    a.kind = std::string(opt) == "--zip" ? Axis::Kind::Zip : Axis::Kind::Grid;
    for (std::string v : split_top_level(rest)) {
        if (v.empty()) {
            *err = std::string(opt) + " " + arg + ": empty value (the axis needs one or more values, comma-separated)";
            return false;
        }
        if (is_string_type(a.key_type) && v.front() != '"' && v.front() != '\'') {
            std::string q = "\"";
            for (char c : v) {
                q += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
            }
            v = q + "\"";
        }
        a.values.push_back(v);
    }
    *out = a;
    return true;
}

bool parse_sample_axis(const std::string& arg, Axis* out, std::string* err)
{
    Axis a;
    std::string rest;
    if (!split_key(arg, "--sample", &a.key, &rest, &a.key_type, err)) {
        return false;
    }
    if (a.key_type != "number" && a.key_type != "integer" && a.key_type != "array of 3 numbers") {
        *err = "--sample " + arg + ": '" + a.key + "' is a " + a.key_type +
               " key; only number keys (and per-phase arrays, drawn element by element) can be sampled";
        return false;
    }
    const auto c1 = rest.find(':');
    const auto c2 = c1 == std::string::npos ? std::string::npos : rest.find(':', c1 + 1);
    if (c2 == std::string::npos || rest.find(':', c2 + 1) != std::string::npos) {
        *err = "--sample " + arg + ": expected normal:MEAN:SD or uniform:LO:HI";
        return false;
    }
    const std::string dist = trim(rest.substr(0, c1));
    if (!parse_double(rest.substr(c1 + 1, c2 - c1 - 1), &a.a) || !parse_double(rest.substr(c2 + 1), &a.b)) {
        *err = "--sample " + arg + ": the two parameters must be finite numbers";
        return false;
    }
    if (dist == "normal") {
        a.kind = Axis::Kind::Normal;
        if (!(a.b >= 0.0)) {
            *err = "--sample " + arg + ": the standard deviation must be >= 0";
            return false;
        }
    } else if (dist == "uniform") {
        a.kind = Axis::Kind::Uniform;
        if (!(a.b >= a.a)) {
            *err = "--sample " + arg + ": uniform:LO:HI needs LO <= HI";
            return false;
        }
    } else {
        *err = "--sample " + arg + ": unknown distribution '" + dist + "' (normal or uniform)";
        return false;
    }
    *out = a;
    return true;
}

std::uint64_t run_count(const Spec& spec)
{
    std::uint64_t n = spec.n;
    for (const Axis& a : spec.axes) {
        if (a.kind == Axis::Kind::Grid) {
            n *= a.values.size();
        }
    }
    const std::size_t z = zip_length(spec);
    return z > 0 ? n * z : n;
}

std::vector<PlannedRun> expand(const Spec& spec, std::uint64_t shard_i, std::uint64_t shard_n)
{
    std::vector<PlannedRun> runs;
    const std::uint64_t total = run_count(spec);
    for (std::uint64_t r = shard_i; r < total; r += shard_n) {
        runs.push_back(planned_run(spec, r));
    }
    return runs;
}

json spec_json(const Spec& spec)
{
    json axes = json::array();
    for (const Axis& a : spec.axes) {
        json j{{"key", a.key}, {"type", a.key_type}};
        if (a.kind == Axis::Kind::Grid || a.kind == Axis::Kind::Zip) {
            j["kind"] = a.kind == Axis::Kind::Grid ? "grid" : "zip";
            j["values"] = a.values;
        } else {
            j["kind"] = a.kind == Axis::Kind::Normal ? "normal" : "uniform";
            j["a"] = a.a;
            j["b"] = a.b;
        }
        axes.push_back(j);
    }
    return json{{"scenario_path", spec.scenario_path}, {"scenario_text", spec.scenario_text}, {"sets", spec.sets},
                {"axes", axes}, {"n", spec.n}, {"seed", spec.seed}};
}

bool spec_from_json(const json& j, Spec* out, std::string* err)
{
    try {
        Spec s;
        s.scenario_path = j.at("scenario_path").get<std::string>();
        s.scenario_text = j.at("scenario_text").get<std::string>();
        s.sets = j.at("sets").get<std::vector<std::string>>();
        s.n = j.at("n").get<std::uint64_t>();
        s.seed = j.at("seed").get<std::uint64_t>();
        for (const json& a : j.at("axes")) {
            Axis ax;
            ax.key = a.at("key").get<std::string>();
            ax.key_type = a.at("type").get<std::string>();
            const std::string kind = a.at("kind").get<std::string>();
            if (kind == "grid" || kind == "zip") {
                ax.kind = kind == "grid" ? Axis::Kind::Grid : Axis::Kind::Zip;
                ax.values = a.at("values").get<std::vector<std::string>>();
                if (ax.values.empty()) {
                    throw std::runtime_error("empty grid axis " + ax.key);
                }
            } else {
                ax.kind = kind == "normal" ? Axis::Kind::Normal : Axis::Kind::Uniform;
                ax.a = a.at("a").get<double>();
                ax.b = a.at("b").get<double>();
            }
            s.axes.push_back(ax);
        }
        if (s.n == 0) {
            throw std::runtime_error("n = 0");
        }
        for (const Axis& ax : s.axes) {
            if (ax.kind == Axis::Kind::Zip && ax.values.size() != zip_length(s)) {
                throw std::runtime_error("zip axes of different lengths");
            }
        }
        *out = s;
        return true;
    } catch (const std::exception& e) {
        *err = std::string("sweep plan: ") + e.what();
        return false;
    }
}

std::string plan_id(const Spec& spec)
{
    std::uint64_t h = 0xcbf29ce484222325ull; // FNV-1a 64
    for (unsigned char c : spec_json(spec).dump()) {
        h = (h ^ c) * 0x100000001b3ull;
    }
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    return buf;
}

std::vector<std::string> run_overrides(const Spec& spec, const PlannedRun& run)
{
    std::vector<std::string> o = spec.sets;
    for (std::size_t i = 0; i < spec.axes.size(); ++i) {
        o.push_back(spec.axes[i].key + "=" + run.values[i]);
    }
    return o;
}

void execute(const Spec& spec, const std::vector<PlannedRun>& runs, const ExecOptions& opt,
             const std::function<void(const json& row)>& on_row)
{
    struct Child {
        pid_t pid;
        int fd;
        std::string buf;
        std::chrono::steady_clock::time_point start;
        const PlannedRun* run;
        bool timed_out = false;
    };
    std::vector<Child> active;
    std::size_t next = 0;
    const unsigned jobs = std::max(1u, opt.jobs);
    const auto limit = std::chrono::duration<double>(opt.timeout_s);

    auto finish = [&](Child& c) {
        int status = 0;
        while (waitpid(c.pid, &status, 0) < 0 && errno == EINTR) {
        }
        close(c.fd);
        const PlannedRun& p = *c.run;
        if (c.timed_out) {
            on_row(make_row(p.index, spec, p, "timeout", nullptr,
                            "killed after the per-run limit of " + shortest(opt.timeout_s) + " s", json::object()));
            return;
        }
        if (WIFSIGNALED(status)) {
            on_row(make_row(p.index, spec, p, "crashed", nullptr, "run process died: " + signal_text(WTERMSIG(status)),
                            json::object()));
            return;
        }
        json row = json::parse(c.buf, nullptr, false);
        if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || row.is_discarded() || !row.is_object()) {
            on_row(make_row(p.index, spec, p, "crashed", nullptr,
                            "run process exited with status " +
                                std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                                " and no result",
                            json::object()));
            return;
        }
        on_row(row);
    };

    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    while (next < runs.size() || !active.empty()) {
        while (active.size() < jobs && next < runs.size()) {
            int fds[2];
            if (pipe(fds) != 0) {
                const PlannedRun& p = runs[next++];
                on_row(make_row(p.index, spec, p, "error", nullptr, std::string("pipe: ") + std::strerror(errno),
                                json::object()));
                continue;
            }
            const pid_t pid = fork();
            if (pid == 0) {
                close(fds[0]);
                for (const Child& c : active) {
                    close(c.fd);
                }
                const int devnull = open("/dev/null", O_WRONLY);
                if (devnull >= 0) {
                    dup2(devnull, 1);
                    dup2(devnull, 2);
                }
                const std::string text = child_run(spec, runs[next], opt.runs_dir);
                const char* b = text.data();
                std::size_t left = text.size();
                while (left > 0) {
                    const ssize_t w = write(fds[1], b, left);
                    if (w < 0 && errno == EINTR) {
                        continue;
                    }
                    if (w <= 0) {
                        _exit(3);
                    }
                    b += w;
                    left -= static_cast<std::size_t>(w);
                }
                _exit(0);
            }
            close(fds[1]);
            if (pid < 0) {
                close(fds[0]);
                const PlannedRun& p = runs[next++];
                on_row(make_row(p.index, spec, p, "error", nullptr, std::string("fork: ") + std::strerror(errno),
                                json::object()));
                continue;
            }
            active.push_back(Child{pid, fds[0], {}, std::chrono::steady_clock::now(), &runs[next], false});
            ++next;
        }
        if (active.empty()) {
            continue;
        }
        // Wait for output, an exit, or the nearest per-run deadline.
        const auto now = std::chrono::steady_clock::now();
        double wait_s = opt.timeout_s;
        for (const Child& c : active) {
            wait_s = std::min(wait_s, (limit - (now - c.start)).count());
        }
        std::vector<pollfd> pfd;
        for (const Child& c : active) {
            pfd.push_back(pollfd{c.fd, POLLIN, 0});
        }
        const int ms = static_cast<int>(std::clamp(std::ceil(wait_s * 1000.0), 0.0, 1000.0));
        if (poll(pfd.data(), pfd.size(), ms) < 0 && errno != EINTR) {
            continue;
        }
        std::vector<std::size_t> done;
        for (std::size_t i = 0; i < active.size(); ++i) {
            Child& c = active[i];
            if ((pfd[i].revents & (POLLIN | POLLHUP | POLLERR)) != 0) {
                char buf[65536];
                const ssize_t r = read(c.fd, buf, sizeof buf);
                if (r > 0) {
                    c.buf.append(buf, static_cast<std::size_t>(r));
                } else if (r == 0 || errno != EINTR) {
                    done.push_back(i);
                    continue;
                }
            }
            if (std::chrono::steady_clock::now() - c.start > limit) {
                kill(c.pid, SIGKILL);
                c.timed_out = true;
                done.push_back(i);
            }
        }
        for (std::size_t k = done.size(); k-- > 0;) {
            finish(active[done[k]]);
            active.erase(active.begin() + static_cast<std::ptrdiff_t>(done[k]));
        }
    }
}

std::vector<std::string> metric_columns()
{
    json flat = metrics_row(metrics_json(Scenario{}, Metrics{}, RunInfo{}));
    std::vector<std::string> cols;
    for (auto it = flat.begin(); it != flat.end(); ++it) {
        cols.push_back(it.key());
    }
    return cols;
}

bool parse_assertion(const std::string& text, Assertion* out, std::string* err)
{
    static const char* ops[] = {"<=", ">=", "==", "!=", "<", ">"};
    for (const char* op : ops) {
        const auto at = text.find(op);
        if (at == std::string::npos) {
            continue;
        }
        Assertion a;
        a.text = text;
        a.op = op;
        a.metric = trim(text.substr(0, at));
        if (!parse_double(text.substr(at + std::strlen(op)), &a.value)) {
            *err = "--assert " + text + ": the right-hand side must be a finite number";
            return false;
        }
        const std::vector<std::string> cols = metric_columns();
        const std::string base = a.metric.substr(0, a.metric.find('['));
        const bool known = std::find(cols.begin(), cols.end(), a.metric) != cols.end() ||
                           (base != a.metric && std::find(cols.begin(), cols.end(), base) != cols.end());
        if (!known) {
            std::string list;
            for (const std::string& c : cols) {
                list += (list.empty() ? "" : ", ") + c;
            }
            *err = "--assert " + text + ": unknown metric '" + a.metric + "' (one of: " + list + ")";
            return false;
        }
        *out = a;
        return true;
    }
    *err = "--assert " + text + ": expected METRIC OP NUMBER with OP one of < <= > >= == !=";
    return false;
}

namespace {
// Returns an empty string when the row satisfies the assertion, else why not.
std::string violation(const Assertion& a, const json& row)
{
    const json& m = row.at("metrics");
    const auto it = m.find(a.metric);
    if (it == m.end() || !(it->is_number() || it->is_boolean())) {
        return "no value (status " + row.at("status").get<std::string>() + ")";
    }
    const double x = it->is_boolean() ? (it->get<bool>() ? 1.0 : 0.0) : it->get<double>();
    bool ok = false;
    if (a.op == "<") {
        ok = x < a.value;
    } else if (a.op == "<=") {
        ok = x <= a.value;
    } else if (a.op == ">") {
        ok = x > a.value;
    } else if (a.op == ">=") {
        ok = x >= a.value;
    } else if (a.op == "==") {
        ok = x == a.value;
    } else {
        ok = x != a.value;
    }
    return ok ? std::string() : a.metric + " = " + shortest(x);
}
} // namespace

bool write_summary(const std::string& dir, const Spec& spec, std::vector<json> rows, std::string* err)
{
    std::sort(rows.begin(), rows.end(),
              [](const json& a, const json& b) { return a.at("run").get<std::uint64_t>() < b.at("run").get<std::uint64_t>(); });
    // Metric columns: those of the metrics record, then any other a row has, in name order; a
    // per-phase metric that is null in the record is shown by its [A]/[B]/[C] columns.
    std::vector<std::string> cols;
    std::set<std::string> seen;
    std::set<std::string> present;
    for (const json& r : rows) {
        for (auto it = r.at("metrics").begin(); it != r.at("metrics").end(); ++it) {
            present.insert(it.key());
        }
    }
    auto add = [&](const std::string& c) {
        if (seen.insert(c).second) {
            cols.push_back(c);
        }
    };
    for (const std::string& c : metric_columns()) {
        if (present.count(c + "[A]") != 0) {
            for (const char* ph : {"[A]", "[B]", "[C]"}) {
                add(c + ph);
            }
        } else {
            add(c);
        }
    }
    for (const std::string& c : present) {
        add(c);
    }
    std::ostringstream csv;
    csv << "run";
    for (const Axis& a : spec.axes) {
        csv << "," << csv_cell(a.key);
    }
    csv << ",status,fault,error";
    for (const std::string& c : cols) {
        csv << "," << csv_cell(c);
    }
    csv << "\n";
    for (const json& r : rows) {
        csv << r.at("run").get<std::uint64_t>();
        for (const Axis& a : spec.axes) {
            const json& v = r.at("values");
            csv << "," << (v.contains(a.key) ? csv_cell(v.at(a.key)) : std::string());
        }
        csv << "," << csv_cell(r.at("status")) << "," << csv_cell(r.at("fault")) << "," << csv_cell(r.at("error"));
        const json& m = r.at("metrics");
        for (const std::string& c : cols) {
            csv << "," << (m.contains(c) ? csv_cell(m.at(c)) : std::string());
        }
        csv << "\n";
    }
    json sj{{"plan", spec_json(spec)}, {"plan_id", plan_id(spec)}, {"runs_planned", run_count(spec)}, {"rows", rows}};
    sj["plan"].erase("scenario_text");
    return write_text_file(fs::path(dir) / "summary.csv", csv.str(), err) &&
           write_text_file(fs::path(dir) / "summary.json", sj.dump(1) + "\n", err);
}

std::vector<json> read_rows(const std::string& dir)
{
    std::vector<json> rows;
    std::ifstream f(fs::path(dir) / "rows.jsonl");
    std::string line;
    while (std::getline(f, line)) {
        json r = json::parse(line, nullptr, false);
        if (!r.is_discarded() && r.is_object() && r.contains("run") && r.contains("metrics")) {
            rows.push_back(std::move(r));
        }
    }
    return rows;
}

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

bool parse_shard(const std::string& s, std::uint64_t* i, std::uint64_t* n, std::string* err)
{
    const auto slash = s.find('/');
    double a, b;
    if (slash == std::string::npos || !parse_double(s.substr(0, slash), &a) || !parse_double(s.substr(slash + 1), &b) ||
        a < 0 || b < 1 || a != std::floor(a) || b != std::floor(b)) {
        *err = "--shard " + s + ": expected I/N with whole numbers, 0 <= I < N";
        return false;
    }
    if (a >= b) {
        *err = "--shard " + s + ": I must be below N (shards are numbered 0 .. N-1)";
        return false;
    }
    *i = static_cast<std::uint64_t>(a);
    *n = static_cast<std::uint64_t>(b);
    return true;
}

// Checks every axis value and sampled range against the scenario before anything runs.
bool check_axes(const Spec& spec, std::string* err)
{
    Scenario sc;
    Diagnostics d;
    if (!parse_scenario(spec.scenario_text, spec.scenario_path, spec.sets, &sc, &d)) {
        *err = d.text() + "dtc-sil sweep: " + spec.scenario_path + ": the scenario (with --set) is rejected";
        return false;
    }
    for (std::size_t c = 0; c < zip_length(spec); ++c) { // each case with all its zipped values
        std::vector<std::string> o = spec.sets;
        std::string row;
        for (const Axis& a : spec.axes) {
            if (a.kind == Axis::Kind::Zip) {
                o.push_back(a.key + "=" + a.values[c]);
                row += (row.empty() ? "" : ", ") + a.key + "=" + a.values[c];
            }
        }
        Diagnostics dv;
        if (!parse_scenario(spec.scenario_text, spec.scenario_path, o, &sc, &dv)) {
            *err = "--zip case " + std::to_string(c + 1) + " (" + row + ") is rejected: " +
                   (dv.errors.empty() ? std::string("?") : dv.errors.front());
            return false;
        }
    }
    for (const Axis& a : spec.axes) {
        if (a.kind != Axis::Kind::Grid) {
            continue;
        }
        for (const std::string& v : a.values) {
            std::vector<std::string> o = spec.sets;
            o.push_back(a.key + "=" + v);
            Diagnostics dv;
            if (!parse_scenario(spec.scenario_text, spec.scenario_path, o, &sc, &dv)) {
                *err = "--grid " + a.key + ": value " + v + " is rejected: " +
                       (dv.errors.empty() ? std::string("?") : dv.errors.front());
                return false;
            }
        }
    }
    return true;
}

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
    for (const json& r : j.at("runs")) {
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
        opt.timeout_s = j.at("timeout_s").get<double>();
    }
    execute(spec, runs, opt, [&](const json& row) { out << row.dump() << "\n" << std::flush; });
    return 0;
}

} // namespace

int sweep_main(const std::vector<std::string>& args, std::ostream& out, std::ostream& err)
{
    CLI::App app{"dtc-sil sweeps"};
    app.require_subcommand(1);
    std::string scenario_path, out_dir, shard_text, dask_addr;
    std::vector<std::string> sets, grids, zips, samples, asserts, merge_dirs;
    std::uint64_t n = 0, seed = 1;
    unsigned jobs = std::max(1u, std::thread::hardware_concurrency());
    unsigned chunk = 0, exec_jobs = 1;
    double timeout_s = 600.0;
    bool resume = false, quiet = false, keep_runs = false;

    CLI::App* sw = app.add_subcommand("sweep", "run a scenario over grid and Monte Carlo axes; write DIR/summary.csv");
    sw->add_option("scenario", scenario_path, "scenario TOML file")->required();
    sw->add_option("--out,-o", out_dir, "output directory (summary.csv, summary.json, rows.jsonl, plan.json)")
        ->required();
    sw->add_option("--set,-s", sets, "fixed override of a scenario key for every run (repeatable)");
    sw->add_option("--grid", grids, "grid axis KEY=V1,V2,... (repeatable; Cartesian product)");
    sw->add_option("--zip", zips,
                   "case axis KEY=V1,V2,... (repeatable): all --zip axes have the same length and their i-th "
                   "values go together, as one dimension of the product");
    sw->add_option("--sample", samples, "random axis KEY=normal:MEAN:SD or KEY=uniform:LO:HI (repeatable)");
    sw->add_option("--n", n, "samples per grid point (with --sample)");
    sw->add_option("--seed", seed, "seed of the sampled axes (same seed, same runs)");
    sw->add_option("--jobs,-j", jobs, "runs at once (default: the cores present)")->check(CLI::Range(1u, 4096u));
    sw->add_option("--timeout-s", timeout_s, "per-run wall-clock limit; a run over it is killed and reported")
        ->check(CLI::Range(0.001, 1e7));
    sw->add_flag("--resume", resume, "continue the sweep in DIR: skip the runs it already has");
    sw->add_option("--shard", shard_text, "run only shard I of N (runs r with r mod N = I), e.g. 0/4");
    sw->add_option("--assert", asserts, "envelope METRIC OP NUMBER every run must meet, e.g. imbalance_pct<8");
    sw->add_option("--dask", dask_addr, "run on a dask.distributed scheduler, e.g. tcp://10.0.0.1:8786");
    sw->add_option("--chunk", chunk, "runs per Dask task (default: about 4 tasks per worker, at most 50 runs)")
        ->check(CLI::Range(1u, 100000u));
    sw->add_flag("--quiet,-q", quiet, "no closing summary line");
    sw->add_flag("--keep-runs", keep_runs, "also write every run's metrics.json and trace.csv to DIR/runs/RUN");

    CLI::App* mg = app.add_subcommand("sweep-merge", "join the shards of one sweep into DIR/summary.csv");
    mg->add_option("--out,-o", out_dir, "output directory")->required();
    mg->add_option("shards", merge_dirs, "the shards' output directories")->required();

    CLI::App* ex = app.add_subcommand("sweep-exec", "(for Dask workers) run a chunk read from stdin, rows on stdout");
    ex->add_option("--jobs,-j", exec_jobs, "runs at once")->check(CLI::Range(1u, 4096u));
    ex->group(""); // not listed in --help: an internal interface

    std::vector<std::string> argv_rev(args.rbegin(), args.rend());
    if (!argv_rev.empty()) {
        argv_rev.pop_back();
    }
    try {
        app.parse(argv_rev);
    } catch (const CLI::ParseError& e) {
        const int rc = app.exit(e, out, err);
        return rc == 0 ? 0 : 1;
    }

    if (ex->parsed()) {
        return cmd_exec(std::cin, out, err, exec_jobs);
    }

    std::string e;
    if (mg->parsed()) {
        Spec spec;
        std::string id;
        std::map<std::uint64_t, json> rows;
        for (const std::string& d : merge_dirs) {
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
        return 0;
    }

    // ---- sweep: everything that can be refused is refused before any run starts. ----
    Spec spec;
    spec.scenario_path = scenario_path;
    spec.scenario_text = read_file(scenario_path, &e);
    if (!e.empty()) {
        err << "dtc-sil sweep: " << e << "\n";
        return 1;
    }
    spec.sets = sets;
    spec.seed = seed;
    for (const std::string& g : grids) {
        Axis a;
        if (!parse_grid_axis(g, &a, &e)) {
            err << "dtc-sil sweep: " << e << "\n";
            return 1;
        }
        spec.axes.push_back(a);
    }
    for (const std::string& z : zips) {
        Axis a;
        if (!parse_grid_axis(z, &a, &e, "--zip")) {
            err << "dtc-sil sweep: " << e << "\n";
            return 1;
        }
        if (!spec.axes.empty() && spec.axes.back().kind == Axis::Kind::Zip &&
            a.values.size() != spec.axes.back().values.size()) {
            err << "dtc-sil sweep: --zip " << z << ": " << a.values.size() << " values, but the other --zip axes have "
                << spec.axes.back().values.size() << " (zipped axes go together value by value)\n";
            return 1;
        }
        spec.axes.push_back(a);
    }
    for (const std::string& s : samples) {
        Axis a;
        if (!parse_sample_axis(s, &a, &e)) {
            err << "dtc-sil sweep: " << e << "\n";
            return 1;
        }
        spec.axes.push_back(a);
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
        if (!parse_assertion(a, &as, &e)) {
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
    if (out_dir.empty()) {
        err << "dtc-sil sweep: --out is empty\n";
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
        // The cluster path: tools/sweep/dask_sweep.py hands chunks to the scheduler and appends
        // each chunk's rows to rows.jsonl; the summary below is written by the same code as locally.
        const char* env_script = std::getenv("DTC_SIL_DASK_SCRIPT");
        const std::string script = env_script != nullptr ? env_script : DTC_SWEEP_DASK_SCRIPT;
        json pending = json::array();
        for (const PlannedRun& p : todo) {
            pending.push_back(p.index);
        }
        json job{{"spec", spec_json(spec)}, {"pending", pending}, {"chunk", chunk}, {"timeout_s", timeout_s},
                 {"exe", self_exe(args.empty() ? "dtc-sil" : args[0])}, {"scheduler", dask_addr},
                 {"rows", (dir / "rows.jsonl").string()}, {"progress", prog.tty}};
        if (!write_text_file(dir / "dask_job.json", job.dump() + "\n", &e)) {
            err << "dtc-sil sweep: " << e << "\n";
            return 2;
        }
        out.flush();
        err.flush();
        const std::string cmd = "/usr/bin/python3 '" + script + "' '" + (dir / "dask_job.json").string() + "'";
        const int rc = std::system(cmd.c_str());
        fs::remove(dir / "dask_job.json", ec);
        if (rc != 0) {
            const int code = WIFEXITED(rc) ? WEXITSTATUS(rc) : 2;
            err << "dtc-sil sweep: the Dask run did not complete (rows so far are kept; --resume continues)\n";
            return code == 1 ? 1 : 2;
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
    std::vector<std::string> violations;
    for (auto& [k, r] : by_run) {
        ++status_count[r.at("status").get<std::string>()];
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
