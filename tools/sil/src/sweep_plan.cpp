// sweep_plan.cpp - a sweep's plan: the axes as given on the command line, the deterministic random
// draws, the expansion of the plan into numbered runs, and the plan's identity (see sweep.hpp).
#include "sweep.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "scenario.hpp"
#include "sweep_detail.hpp"

namespace sil::sweep {

using nlohmann::json;

namespace detail {

std::string shortest(double x)
{
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    return std::string(buf, r.ptr);
}

std::string trim(const std::string& s)
{
    const auto b = s.find_first_not_of(" \t");
    if (b == std::string::npos) {
        return "";
    }
    const auto e = s.find_last_not_of(" \t");
    return s.substr(b, e - b + 1);
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

std::size_t zip_length(const Spec& spec)
{
    for (const Axis& a : spec.axes) {
        if (a.kind == Axis::Kind::Zip) {
            return a.values.size();
        }
    }
    return 0;
}


} // namespace detail

using namespace detail;

namespace {

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

} // namespace

namespace detail {

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

} // namespace detail

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

bool check_plan_size(const Spec& spec, std::string* err)
{
    // The product is formed in floating point: it cannot wrap, and any value above the limit is
    // refused whatever its size.
    double n = static_cast<double>(spec.n);
    std::string how = std::to_string(spec.n) + (spec.n == 1 ? " sample" : " samples");
    for (const Axis& a : spec.axes) {
        if (a.kind == Axis::Kind::Grid) {
            n *= static_cast<double>(a.values.size());
            how += " x " + std::to_string(a.values.size()) + " (" + a.key + ")";
        }
    }
    if (const std::size_t z = zip_length(spec); z > 0) {
        n *= static_cast<double>(z);
        how += " x " + std::to_string(z) + " zip cases";
    }
    if (n > static_cast<double>(kMaxPlanRuns)) {
        char total[32];
        std::snprintf(total, sizeof total, "%.4g", n);
        *err = "the plan has " + std::string(total) + " runs (" + how + "), above the " +
               std::to_string(kMaxPlanRuns) +
               " a sweep may hold: sweep fewer points, or split the samples into sweeps with different --seed";
        return false;
    }
    return true;
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
    json j{{"scenario_path", spec.scenario_path}, {"scenario_text", spec.scenario_text}, {"sets", spec.sets},
           {"axes", axes}, {"n", spec.n}, {"seed", spec.seed}};
    // only when given: a plan without overlays or --identify keeps its text (and plan id) as before
    if (spec.identify) {
        j["mode"] = "identify";
    }
    for (const OverlayText& o : spec.overlays) {
        j["overlays"].push_back(json{{"path", o.path}, {"text", o.text}});
    }
    return j;
}

bool spec_from_json(const json& j, Spec* out, std::string* err)
{
    try {
        Spec s;
        s.scenario_path = j.at("scenario_path").get<std::string>();
        s.scenario_text = j.at("scenario_text").get<std::string>();
        s.sets = j.at("sets").get<std::vector<std::string>>();
        s.identify = j.value("mode", std::string("run")) == "identify";
        if (j.contains("overlays")) {
            for (const json& o : j.at("overlays")) {
                s.overlays.push_back(OverlayText{o.at("path").get<std::string>(), o.at("text").get<std::string>()});
            }
        }
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
        std::string why;
        if (!check_plan_size(s, &why)) {
            throw std::runtime_error(why);
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

namespace detail {

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
    if (!parse_scenario(spec.scenario_text, spec.scenario_path, spec.sets, &sc, &d, spec.overlays)) {
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
        if (!parse_scenario(spec.scenario_text, spec.scenario_path, o, &sc, &dv, spec.overlays)) {
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
            if (!parse_scenario(spec.scenario_text, spec.scenario_path, o, &sc, &dv, spec.overlays)) {
                *err = "--grid " + a.key + ": value " + v + " is rejected: " +
                       (dv.errors.empty() ? std::string("?") : dv.errors.front());
                return false;
            }
        }
    }
    return true;
}

} // namespace detail

} // namespace sil::sweep
