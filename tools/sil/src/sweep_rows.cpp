// sweep_rows.cpp - a sweep's results: one JSON row per run, the assertion language that checks them,
// and the summary written from them (see sweep.hpp).
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

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "run.hpp"
#include "sil_output.hpp"
#include "sweep_detail.hpp"
#include "toml_limits.hpp"

namespace sil::sweep {

namespace fs = std::filesystem;
using nlohmann::json;

namespace detail {

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

} // namespace detail

using namespace detail;

namespace {

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


} // namespace

std::vector<std::string> metric_columns()
{
    json flat = metrics_row(metrics_json(Scenario{}, Metrics{}, RunInfo{}));
    std::vector<std::string> cols;
    for (auto it = flat.begin(); it != flat.end(); ++it) {
        cols.push_back(it.key());
    }
    return cols;
}

namespace {
// identification.json's quantities (tools/sil/src/identify.cpp): true = a relative error (error_pct).
const std::vector<std::pair<const char*, bool>>& identify_quantities()
{
    static const std::vector<std::pair<const char*, bool>> q = {
        {"rs_ohm", true},         {"r_slope_ohm", true},   {"v0_v", true},     {"drop_at_rated_v", true},
        {"dead_time_s", true},    {"ls_h", true},          {"lq_h", true},     {"pole_pairs", false},
        {"encoder_reversed", false},
        {"encoder_offset_el_deg", false}, {"psi_m_wb", true}, {"j_kgm2", true}, {"b_nm_s_per_rad", true},
        {"coulomb_nm", false}};
    return q;
}
} // namespace

std::vector<std::string> identify_metric_columns()
{
    std::vector<std::string> cols = {"ok", "standstill_s", "spin_s", "duration_s"};
    for (const auto& [q, rel] : identify_quantities()) {
        cols.push_back(std::string(q) + (rel ? ".error_pct" : ".error"));
        cols.push_back(std::string(q) + (rel ? ".abs_error_pct" : ".abs_error"));
    }
    return cols;
}

json identify_metrics(const json& report)
{
    json m = json::object();
    m["ok"] = report.value("status", std::string()) == "ok" ? 1 : 0;
    for (const char* k : {"standstill_s", "spin_s", "duration_s"}) {
        m[k] = report.value(k, 0.0);
    }
    const json& q = report.at("quantities");
    for (const auto& [name, rel] : identify_quantities()) {
        if (!q.contains(name) || q.at(name).value("status", std::string()) != "ok") {
            continue; // a step that failed or did not run has no error
        }
        const char* key = rel ? "error_pct" : "error";
        const double e = q.at(name).value(key, 0.0);
        m[std::string(name) + "." + key] = e;
        m[std::string(name) + (rel ? ".abs_error_pct" : ".abs_error")] = std::fabs(e);
    }
    return m;
}

bool parse_assertion(const std::string& text, Assertion* out, std::string* err, bool identify)
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
            *err = "--assert " + echo(text) + ": the right-hand side must be a finite number";
            return false;
        }
        const std::vector<std::string> cols = identify ? identify_metric_columns() : metric_columns();
        const std::string base = a.metric.substr(0, a.metric.find('['));
        const std::string index = base == a.metric ? std::string() : a.metric.substr(base.size());
        // A per-phase metric (null in the record) is asserted on one phase: [A], [B] or [C].
        const bool per_phase = std::find(cols.begin(), cols.end(), base) != cols.end() &&
                               (index == "[A]" || index == "[B]" || index == "[C]");
        const bool known = std::find(cols.begin(), cols.end(), a.metric) != cols.end() || per_phase;
        if (!known && base != a.metric && std::find(cols.begin(), cols.end(), base) != cols.end()) {
            *err = "--assert " + echo(text) + ": " + echo(base) + " has no element " + echo(index) +
                   " (a per-phase metric: " + base + "[A], " + base + "[B] or " + base + "[C])";
            return false;
        }
        if (!known) {
            std::string list;
            for (const std::string& c : cols) {
                list += (list.empty() ? "" : ", ") + c;
            }
            *err = "--assert " + echo(text) + ": unknown metric '" + echo(a.metric) + "' (one of: " + list + ")";
            return false;
        }
        *out = a;
        return true;
    }
    *err = "--assert " + echo(text) + ": expected METRIC OP NUMBER with OP one of < <= > >= == !=";
    return false;
}

namespace detail {
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
} // namespace detail

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
    for (const std::string& c : spec.identify ? identify_metric_columns() : metric_columns()) {
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
    if (sj["plan"].contains("overlays")) {
        for (json& o : sj["plan"]["overlays"]) {
            o.erase("text");
        }
    }
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
        if (!r.is_discarded() && r.is_object() && r.contains("run") && r.at("run").is_number_unsigned() &&
            r.contains("metrics") && r.at("metrics").is_object() && r.contains("status") && r.contains("error") &&
            r.contains("fault") && r.contains("values")) {
            rows.push_back(std::move(r));
        }
    }
    return rows;
}

} // namespace sil::sweep
