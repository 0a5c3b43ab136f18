// scenario_schema.hpp - the scenario loader's internals shared by its parts: the schema's types and
// table (scenario_schema.cpp), the value checks, and the cross-checks run after loading
// (scenario_checks.cpp). Not for the loader's users (scenario.hpp).
#pragma once

#include "scenario.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace sil::detail {

constexpr double kInf = std::numeric_limits<double>::infinity();

enum class Kind { Number, Integer, Bool, String, Number3, Path };

struct Value {
    double num = 0.0;
    std::int64_t integer = 0;
    bool boolean = false;
    std::string str;
    std::array<double, 3> arr{};
};

struct Range {
    double lo = -kInf, hi = kInf;
    bool lo_open = false, hi_open = false;
    bool contains(double x) const
    {
        if (!std::isfinite(x)) {
            return false;
        }
        const bool lo_ok = lo_open ? x > lo : x >= lo;
        const bool hi_ok = hi_open ? x < hi : x <= hi;
        return lo_ok && hi_ok;
    }
    std::string text() const
    {
        std::ostringstream o;
        o.precision(6);
        if (lo == -kInf && hi == kInf) {
            return "any finite value";
        }
        if (hi == kInf) {
            o << (lo_open ? "> " : ">= ") << lo;
        } else if (lo == -kInf) {
            o << (hi_open ? "< " : "<= ") << hi;
        } else {
            o << (lo_open ? "(" : "[") << lo << ", " << hi << (hi_open ? ")" : "]");
        }
        return o.str();
    }
};
inline Range positive() { return Range{0.0, kInf, true, false}; }
inline Range nonneg() { return Range{0.0, kInf, false, false}; }
inline Range closed(double lo, double hi) { return Range{lo, hi, false, false}; }
inline Range any() { return Range{}; }

struct Spec {
    std::string name;
    Kind kind;
    std::string unit;
    std::string doc;
    Range range;
    std::vector<std::string> choices; // String only
    std::function<void(Scenario&, const Value&)> set;
    std::function<std::string(const Scenario&)> show;
};

std::string fmt_double(double x);
/// Every key of a scenario, in the order of the docs' key table.
const std::vector<Spec>& schema();
const Spec* find_spec(const std::string& name);
std::string kind_name(Kind k);
/// "" when v is allowed for spec, else why not.
std::string check_value(const Spec& spec, const Value& v);
void reduce_angle(const Spec& spec, Value* v);
/// Where key was set ("file:line:col", "--set #n ..."), or "(default)".
std::string origin_of(const Scenario& s, const std::string& key);

// scenario_checks.cpp: run in this order once every key is read.
void apply_machine_defaults(Scenario& s, Diagnostics* d);
void check_law_keys(const Scenario& s, Diagnostics* d);
void cross_validate(Scenario& s, Diagnostics* d);
void check_sizes(const Scenario& s, Diagnostics* d);

} // namespace sil::detail
