// fuzz_scenario.cpp - libFuzzer harness of dtc-sil's input side (docs/fuzzing.md): the scenario
// reader (check_toml_limits, parse_scenario with --set overrides) and the sweep's command-line
// parsers (--grid / --zip / --sample axes, --assert, the plan size).
//
// Input: the first byte picks the target, the rest is split at '\n' into its pieces.
//   0, 1  TOML text -> parse_scenario (byte 1: the last lines are --set overrides instead)
//   2     each line -> parse_grid_axis / parse_sample_axis / parse_assertion, and a plan of the
//         parsed axes -> check_plan_size (and run_count when it passes)
// Invariants (each a crash): no undefined behaviour, memory error or escaping exception; every
// message is short (at most 4 KB: nothing the user gave is echoed back whole); an accepted
// scenario has finite run settings and a metrics window within kMaxWindowSamples.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "scenario.hpp"
#include "sweep.hpp"
#include "toml_limits.hpp"

namespace {

constexpr std::size_t kMaxMessage = 4096;

void check_message(const std::string& m)
{
    if (m.size() > kMaxMessage) {
        std::abort();
    }
}

std::vector<std::string> lines(const std::string& s)
{
    std::vector<std::string> out;
    std::size_t b = 0;
    for (std::size_t i = 0; i <= s.size(); ++i) {
        if (i == s.size() || s[i] == '\n') {
            out.push_back(s.substr(b, i - b));
            b = i + 1;
        }
    }
    return out;
}

void fuzz_scenario(const std::string& text, bool with_sets)
{
    std::string toml = text;
    std::vector<std::string> sets;
    if (with_sets) {
        // The lines after the first empty line are --set overrides.
        const auto cut = text.find("\n\n");
        if (cut != std::string::npos) {
            toml = text.substr(0, cut);
            sets = lines(text.substr(cut + 2));
        }
    }
    sil::Scenario sc;
    sil::Diagnostics d;
    const bool ok = sil::parse_scenario(toml, "fuzz.toml", sets, &sc, &d);
    for (const std::string& e : d.errors) {
        check_message(e);
    }
    for (const std::string& w : d.warnings) {
        check_message(w);
    }
    if (ok) {
        if (!(std::isfinite(sc.duration_s) && sc.duration_s > 0.0 && std::isfinite(sc.ts_s) &&
              std::isfinite(sc.metrics_window_s) && sc.metrics_window_s <= sc.duration_s &&
              std::fabs(sc.initial_theta_m_rad) <= 3.1415926535897932 + 1e-12)) {
            std::abort();
        }
        if (sc.metrics_window_s / sc.ts_s + 1.0 > static_cast<double>(sil::kMaxWindowSamples) + 1.0) {
            std::abort();
        }
    }
}

void fuzz_sweep_parsers(const std::string& text)
{
    sil::sweep::Spec spec;
    for (const std::string& l : lines(text)) {
        if (l.empty()) {
            continue;
        }
        std::string err;
        sil::sweep::Axis a;
        sil::sweep::Assertion as;
        bool ok = false;
        switch (static_cast<unsigned char>(l[0]) % 4u) {
        case 0: ok = sil::sweep::parse_grid_axis(l.substr(1), &a, &err); break;
        case 1: ok = sil::sweep::parse_grid_axis(l.substr(1), &a, &err, "--zip"); break;
        case 2: ok = sil::sweep::parse_sample_axis(l.substr(1), &a, &err); break;
        default:
            ok = sil::sweep::parse_assertion(l.substr(1), &as, &err);
            check_message(err);
            continue;
        }
        check_message(err);
        if (ok) {
            if (a.kind == sil::sweep::Axis::Kind::Zip && !spec.axes.empty() &&
                spec.axes.back().kind == sil::sweep::Axis::Kind::Zip &&
                spec.axes.back().values.size() != a.values.size()) {
                continue; // the command line refuses zips of different lengths before the plan
            }
            spec.axes.push_back(a);
        }
    }
    spec.n = 1 + (text.size() % 7 == 0 ? (std::uint64_t{1} << 63) : text.size());
    std::string err;
    if (sil::sweep::check_plan_size(spec, &err)) {
        if (sil::sweep::run_count(spec) > sil::sweep::kMaxPlanRuns) {
            std::abort();
        }
    }
    check_message(err);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t n)
{
    if (n == 0) {
        return 0;
    }
    const std::string text(reinterpret_cast<const char*>(data) + 1, n - 1);
    switch (data[0] % 3u) {
    case 0: fuzz_scenario(text, false); break;
    case 1: fuzz_scenario(text, true); break;
    default: fuzz_sweep_parsers(text); break;
    }
    return 0;
}
