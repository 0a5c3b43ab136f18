// scenario.cpp - schema-driven scenario loading (toml++, --set), see scenario.hpp; the schema is
// scenario_schema.cpp, the whole-scenario checks scenario_checks.cpp.
#include "scenario.hpp"
#include "scenario_schema.hpp"
#include "toml_limits.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>


namespace sil {


using namespace detail;

namespace {

std::string where(const std::string& file, const toml::source_region& r)
{
    return file + ":" + std::to_string(r.begin.line) + ":" + std::to_string(r.begin.column);
}

std::string node_type_name(const toml::node& n)
{
    switch (n.type()) {
    case toml::node_type::table: return "table";
    case toml::node_type::array: return "array";
    case toml::node_type::string: return "string";
    case toml::node_type::integer: return "integer";
    case toml::node_type::floating_point: return "float";
    case toml::node_type::boolean: return "boolean";
    case toml::node_type::date: return "date";
    case toml::node_type::time: return "time";
    case toml::node_type::date_time: return "date-time";
    default: return "nothing";
    }
}

// Converts a TOML node to a Value of the spec's kind; returns "" or the reason it cannot.
std::string from_node(const Spec& spec, const toml::node& n, Value* v)
{
    auto as_number = [](const toml::node& x, double* out) {
        if (auto i = x.as_integer()) {
            *out = static_cast<double>(i->get());
            return true;
        }
        if (auto f = x.as_floating_point()) {
            *out = f->get();
            return true;
        }
        return false;
    };
    switch (spec.kind) {
    case Kind::Number:
        if (!as_number(n, &v->num)) {
            return "expected a number, got " + node_type_name(n);
        }
        return "";
    case Kind::Integer:
        if (auto i = n.as_integer()) {
            v->integer = i->get();
            v->num = static_cast<double>(v->integer);
            return "";
        }
        return "expected an integer, got " + node_type_name(n);
    case Kind::Bool:
        if (auto b = n.as_boolean()) {
            v->boolean = b->get();
            return "";
        }
        return "expected true or false, got " + node_type_name(n);
    case Kind::String:
    case Kind::Path:
        if (auto s = n.as_string()) {
            v->str = s->get();
            return "";
        }
        return "expected a string, got " + node_type_name(n);
    case Kind::Number3: {
        const toml::array* a = n.as_array();
        if (a == nullptr) {
            return "expected an array of 3 numbers, got " + node_type_name(n);
        }
        if (a->size() != 3) {
            return "expected an array of 3 numbers, got " + std::to_string(a->size()) + " elements";
        }
        for (std::size_t i = 0; i < 3; ++i) {
            if (!as_number(*a->get(i), &v->arr[i])) {
                return "expected an array of 3 numbers, element " + std::to_string(i) + " is " +
                       node_type_name(*a->get(i));
            }
        }
        return "";
    }
    }
    return "unsupported kind";
}

// Converts --set text to a Value of the spec's kind (strict: the whole text must be consumed).
std::string from_text(const Spec& spec, const std::string& text, Value* v)
{
    auto parse_double = [](std::string t, double* out) {
        while (!t.empty() && t.back() == ' ') {
            t.pop_back();
        }
        while (!t.empty() && t.front() == ' ') {
            t.erase(t.begin());
        }
        if (t.empty()) {
            return false;
        }
        std::string no_us;
        for (char c : t) {
            if (c != '_') {
                no_us += c; // TOML allows 1_000
            }
        }
        const char* b = no_us.c_str();
        const char* e = b + no_us.size();
        if (*b == '+') {
            ++b;
        }
        auto r = std::from_chars(b, e, *out);
        return r.ec == std::errc() && r.ptr == e;
    };
    switch (spec.kind) {
    case Kind::Number:
        if (!parse_double(text, &v->num)) {
            return "expected a number, got '" + echo(text) + "'";
        }
        return "";
    case Kind::Integer: {
        double d = 0.0;
        if (!parse_double(text, &d) || d != std::floor(d) || std::fabs(d) > 9.0e18 ||
            text.find_first_of(".eE") != std::string::npos) {
            return "expected an integer, got '" + echo(text) + "'";
        }
        v->integer = static_cast<std::int64_t>(d);
        v->num = d;
        return "";
    }
    case Kind::Bool:
        if (text == "true" || text == "false") {
            v->boolean = text == "true";
            return "";
        }
        return "expected true or false, got '" + echo(text) + "'";
    case Kind::String:
    case Kind::Path: {
        std::string t = text;
        if (t.size() >= 2 && (t.front() == '"' || t.front() == '\'') && t.back() == t.front()) {
            t = t.substr(1, t.size() - 2);
        }
        v->str = t;
        return "";
    }
    case Kind::Number3: {
        std::string t = text;
        if (t.size() < 2 || t.front() != '[' || t.back() != ']') {
            return "expected [x, y, z], got '" + echo(text) + "'";
        }
        t = t.substr(1, t.size() - 2);
        std::vector<std::string> parts;
        std::string cur;
        for (char c : t) {
            if (c == ',') {
                parts.push_back(cur);
                cur.clear();
            } else {
                cur += c;
            }
        }
        parts.push_back(cur);
        if (parts.size() != 3) {
            return "expected [x, y, z] with 3 numbers, got '" + echo(text) + "'";
        }
        for (std::size_t i = 0; i < 3; ++i) {
            if (!parse_double(parts[i], &v->arr[i])) {
                return "expected [x, y, z] with 3 numbers, got '" + echo(text) + "'";
            }
        }
        return "";
    }
    }
    return "unsupported kind";
}


} // namespace

std::string Diagnostics::text() const
{
    std::string t;
    for (std::size_t i = 0; i < errors.size() && i < kMaxShown; ++i) {
        t += "error: " + errors[i] + "\n";
    }
    if (errors.size() > kMaxShown) {
        t += "error: ... and " + std::to_string(errors.size() - kMaxShown) + " more errors (" +
             std::to_string(errors.size()) + " in all)\n";
    }
    for (std::size_t i = 0; i < warnings.size() && i < kMaxShown; ++i) {
        t += "warning: " + warnings[i] + "\n";
    }
    if (warnings.size() > kMaxShown) {
        t += "warning: ... and " + std::to_string(warnings.size() - kMaxShown) + " more warnings\n";
    }
    return t;
}


bool parse_scenario(const std::string& toml_text, const std::string& source_name,
                    const std::vector<std::string>& overrides, Scenario* out, Diagnostics* diag,
                    const std::vector<OverlayText>& overlays)
{
    Scenario s;
    s.path = source_name;
    s.name = std::filesystem::path(source_name).stem().string();
    if (std::string why = check_toml_limits(toml_text, source_name); !why.empty()) {
        diag->errors.push_back(why + "; refused before parsing");
        return false;
    }
    toml::table root;
    try {
        root = toml::parse(toml_text, source_name);
    } catch (const toml::parse_error& e) {
        diag->errors.push_back(where(source_name, e.source()) + ": TOML syntax error: " +
                               std::string(e.description()));
        return false;
    }

    if (root.empty()) {
        diag->errors.push_back(source_name + ": the scenario sets no key (empty file?); a scenario names at "
                                             "least the settings it is about, e.g. duration_s");
        return false;
    }

    // part: one TOML key as written (a quoted key is one key, whatever it holds); name: the dotted
    // scenario key it makes under its table.
    auto apply_node = [&](const std::string& file, const std::string& name, const std::string& part,
                          const toml::node& n, const toml::source_region& key_src) {
        const Spec* spec = part.find('.') == std::string::npos ? find_spec(name) : nullptr;
        const std::string loc = where(file, n.source().begin.line != 0 ? n.source() : key_src);
        if (spec == nullptr) {
            std::string shown = echo(name) + ": unknown key";
            if (part.find('.') != std::string::npos) {
                // TOML: "a.b" = 1 is one key named a.b, not the key b of table a.
                shown = (name == part ? "" : echo(name.substr(0, name.size() - part.size()))) + "\"" + echo(part) +
                        "\": unknown key (quoted, it is one TOML key whose name holds a dot, not a dotted key; "
                        "write " + echo(part) + " without the quotes)";
            }
            diag->errors.push_back(where(file, key_src) + ": " + shown);
            return;
        }
        Value v;
        std::string why = from_node(*spec, n, &v);
        if (why.empty()) {
            if (spec->kind == Kind::Path && !v.str.empty()) {
                std::filesystem::path p(v.str);
                if (p.is_relative()) {
                    v.str = (std::filesystem::path(file).parent_path() / p).lexically_normal().string();
                }
            }
            reduce_angle(*spec, &v);
            why = check_value(*spec, v);
        }
        if (!why.empty()) {
            diag->errors.push_back(loc + ": " + name + ": " + why);
            return;
        }
        spec->set(s, v);
        s.origin[name] = loc;
    };

    std::vector<std::string> empty_tables;
    static const char* const sections[] = {"motor",      "inverter", "load",    "control",
                                           "sensors",    "protection", "firmware", "metrics", "faults"};
    // The scenario's tables, then each overlay's over them (dtc-sil --overlay), key by key.
    auto apply_table = [&](const toml::table& doc, const std::string& file) {
        for (auto&& [key, node] : doc) {
            const std::string k(key.str());
            bool is_section = false;
            for (const char* sec : sections) {
                is_section = is_section || k == sec;
            }
            if (is_section) {
                const toml::table* t = node.as_table();
                if (t == nullptr) {
                    diag->errors.push_back(where(file, key.source()) + ": " + k + ": expected a table [" + k +
                                           "], got " + node_type_name(node));
                    continue;
                }
                if (t->empty()) {
                    empty_tables.push_back(where(file, key.source()) + ": [" + k + "]");
                }
                for (auto&& [sub, sn] : *t) {
                    apply_node(file, k + "." + std::string(sub.str()), std::string(sub.str()), sn, sub.source());
                }
            } else if (node.is_table()) {
                diag->errors.push_back(where(file, key.source()) + ": [" + echo(k) + "]: unknown table");
            } else {
                apply_node(file, k, k, node, key.source());
            }
        }
    };
    apply_table(root, source_name);
    if (s.origin.empty() && diag->ok()) {
        // Only empty tables: a file that sets nothing is not a scenario (the defaults would run
        // under its name).
        std::string tables;
        for (const std::string& t : empty_tables) {
            tables += (tables.empty() ? "" : ", ") + t;
        }
        diag->errors.push_back(source_name + ": the scenario sets no key (" + tables +
                               " empty); a scenario names at least the settings it is about, e.g. duration_s "
                               "and the [motor] keys");
        return false;
    }
    for (const std::string& t : empty_tables) {
        diag->warnings.push_back(t + ": empty table: sets nothing");
    }

    for (const OverlayText& ov : overlays) {
        if (std::string why = check_toml_limits(ov.text, ov.path); !why.empty()) {
            diag->errors.push_back(why + "; overlay refused before parsing");
            continue;
        }
        try {
            const toml::table doc = toml::parse(ov.text, ov.path);
            if (doc.empty()) {
                diag->warnings.push_back(ov.path + ": the overlay sets no key");
            }
            apply_table(doc, ov.path);
        } catch (const toml::parse_error& e) {
            diag->errors.push_back(where(ov.path, e.source()) + ": TOML syntax error: " +
                                   std::string(e.description()));
        }
    }

    int n_set = 0;
    for (const std::string& o : overrides) {
        ++n_set;
        const std::string loc = "--set #" + std::to_string(n_set) + " '" + echo(o) + "'";
        const auto eq = o.find('=');
        if (eq == std::string::npos || eq == 0) {
            diag->errors.push_back(loc + ": expected key=value");
            continue;
        }
        const std::string name = o.substr(0, eq);
        const std::string text = o.substr(eq + 1);
        const Spec* spec = find_spec(name);
        if (spec == nullptr) {
            diag->errors.push_back(loc + ": " + echo(name) + ": unknown key");
            continue;
        }
        Value v;
        std::string why = from_text(*spec, text, &v);
        if (why.empty()) {
            reduce_angle(*spec, &v);
            why = check_value(*spec, v); // relative paths on the command line are relative to the cwd
        }
        if (!why.empty()) {
            diag->errors.push_back(loc + ": " + name + ": " + why);
            continue;
        }
        spec->set(s, v);
        s.origin[name] = loc;
    }

    if (diag->ok()) {
        apply_machine_defaults(s, diag);
        check_law_keys(s, diag);
    }
    if (diag->ok()) {
        cross_validate(s, diag);
    }
    if (diag->ok()) {
        check_sizes(s, diag);
    }
    if (!diag->ok()) {
        return false;
    }
    *out = std::move(s);
    return true;
}

namespace {
// A whole file's text; false with an error "PATH: TAG..." that says what to give instead.
bool read_toml_text(const std::string& path, const std::string& tag, const std::string& give,
                    const std::string& unreadable, std::string* text, Diagnostics* diag)
{
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        diag->errors.push_back(path + ": " + tag +
                               (std::filesystem::exists(path, ec) ? "not a regular file (a directory?)"
                                                                  : "no such file") +
                               ": give " + give);
        return false;
    }
    std::ifstream f(path, std::ios::binary);
    if (!f) {
        diag->errors.push_back(path + ": " + tag + unreadable);
        return false;
    }
    std::ostringstream ss;
    ss << f.rdbuf(); // an empty file sets ss's failbit: its text is "" (refused or warned by the parser)
    *text = ss.str();
    return true;
}
} // namespace

bool read_overlay(const std::string& path, OverlayText* out, Diagnostics* diag)
{
    out->path = path;
    return read_toml_text(path, "--overlay: ", "a TOML fragment (e.g. identified.toml of dtc-sil identify)",
                          "cannot read the file", &out->text, diag);
}

bool load_scenario(const std::string& path, const std::vector<std::string>& overrides, Scenario* out,
                   Diagnostics* diag, const std::vector<std::string>& overlay_paths)
{
    std::vector<OverlayText> overlays(overlay_paths.size());
    bool overlays_ok = true;
    for (std::size_t i = 0; i < overlay_paths.size(); ++i) {
        overlays_ok = read_overlay(overlay_paths[i], &overlays[i], diag) && overlays_ok;
    }
    if (!overlays_ok) {
        return false;
    }
    std::string text;
    if (!read_toml_text(path, "", "a scenario TOML file", "cannot open the scenario file", &text, diag)) {
        return false;
    }
    return parse_scenario(text, path, overrides, out, diag, overlays);
}

bool load_voltage_csv(const std::string& path, std::vector<VoltageRow>* rows, std::string* err)
{
    std::ifstream f(path);
    if (!f) {
        *err = path + ": cannot open the voltage table";
        return false;
    }
    rows->clear();
    std::string line;
    int lineno = 0;
    bool header = false;
    while (std::getline(f, line)) {
        ++lineno;
        if (!line.empty() && line.back() == '\r') {
            line.pop_back();
        }
        if (line.empty() || line[0] == '#') {
            continue;
        }
        if (!header) {
            std::string h;
            for (char c : line) {
                if (c != ' ') {
                    h += c;
                }
            }
            if (h != "t_s,v_alpha_v,v_beta_v") {
                *err = path + ":" + std::to_string(lineno) + ": expected the header t_s,v_alpha_v,v_beta_v";
                return false;
            }
            header = true;
            continue;
        }
        VoltageRow r{};
        double* dst[3] = {&r.t_s, &r.v_alpha_v, &r.v_beta_v};
        std::size_t pos = 0;
        for (int i = 0; i < 3; ++i) {
            const std::size_t comma = i < 2 ? line.find(',', pos) : line.size();
            if (comma == std::string::npos) {
                *err = path + ":" + std::to_string(lineno) + ": expected 3 comma-separated numbers";
                return false;
            }
            std::string cell = line.substr(pos, comma - pos);
            while (!cell.empty() && cell.front() == ' ') {
                cell.erase(cell.begin());
            }
            while (!cell.empty() && cell.back() == ' ') {
                cell.pop_back();
            }
            const char* b = cell.c_str();
            auto res = std::from_chars(b, b + cell.size(), *dst[i]);
            if (cell.empty() || res.ec != std::errc() || res.ptr != b + cell.size() || !std::isfinite(*dst[i])) {
                *err = path + ":" + std::to_string(lineno) + ": column " + std::to_string(i + 1) +
                       " is not a finite number: '" + cell + "'";
                return false;
            }
            pos = comma + 1;
        }
        if (rows->empty() && r.t_s > 0.0) {
            *err = path + ":" + std::to_string(lineno) + ": the first row must start at t_s <= 0";
            return false;
        }
        if (!rows->empty() && !(r.t_s > rows->back().t_s)) {
            *err = path + ":" + std::to_string(lineno) + ": t_s must increase strictly";
            return false;
        }
        rows->push_back(r);
    }
    if (!header || rows->empty()) {
        *err = path + ": no data rows";
        return false;
    }
    return true;
}

SpeedPiGains speed_pi_gains(double j_kgm2, double bw_hz)
{
    // The inner DTC torque loop is fast against the speed loop, so the speed plant is 1/(J s)
    // (friction B only adds damping). PI: C(s) = Kp (1 + wc / (4 s)), Kp = J wc. Open loop
    // L(jw) = (wc/w) (1 - j wc/(4 w)): |L(j wc)| = sqrt(1 + 1/16) = 1.03 (crossover ~ wc), phase
    // margin = 90 deg - atan(1/4) = 76 deg.
    const double wc = 2.0 * kPi * bw_hz;
    const double kp = j_kgm2 * wc;
    return SpeedPiGains{kp, kp * wc / 4.0};
}

double dyno_speed_rpm(const Scenario& sc, double t_s)
{
    const LoadCfg& l = sc.load;
    if (!(l.speed_ramp_s > 0.0) || t_s >= l.speed_ramp_start_s + l.speed_ramp_s) {
        return l.speed_rpm;
    }
    const double x = std::max(0.0, t_s - l.speed_ramp_start_s) / l.speed_ramp_s;
    return sc.initial_speed_rpm + (l.speed_rpm - sc.initial_speed_rpm) * x;
}

} // namespace sil
