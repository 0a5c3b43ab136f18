// scenario_outcome.hpp - run a shipped scenario (tools/scenarios/) with key overrides and keep its
// metrics, run info and series: the helper the scenario-level SIL tests share.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "run.hpp"
#include "scenario.hpp"

namespace sil_test {

inline const std::string& scenarios_dir()
{
    static const std::string d = std::string(DTC_SOURCE_DIR) + "/tools/scenarios/";
    return d;
}

struct Outcome {
    sil::Metrics m;
    sil::RunInfo info;
    sil::Series series;
};

// Loads tools/scenarios/<file> with the --set style overrides and runs it (a failure to load or
// run is a test failure).
inline Outcome run_shipped(const std::string& file, const std::vector<std::string>& sets = {})
{
    sil::Scenario sc;
    sil::Diagnostics d;
    EXPECT_TRUE(sil::load_scenario(scenarios_dir() + file, sets, &sc, &d)) << d.text();
    sil::RunOptions opt;
    sil::RunResult r;
    std::string err;
    EXPECT_TRUE(sil::run_scenario(sc, opt, &r, &err)) << err;
    return Outcome{r.metrics, r.info, r.series};
}

// Loads tools/scenarios/<file> with the --set style overrides, which must refuse it (a scenario
// that loads is a test failure), and expects the diagnostics to contain `names` (a key, or a whole
// message).
inline void expect_refused(const std::string& file, const std::vector<std::string>& sets,
                           const std::string& names)
{
    sil::Scenario sc;
    sil::Diagnostics d;
    EXPECT_FALSE(sil::load_scenario(scenarios_dir() + file, sets, &sc, &d)) << file << " loaded";
    EXPECT_NE(d.text().find(names), std::string::npos) << d.text();
}

} // namespace sil_test
