// run.hpp - one SIL run: scenario -> plant parameters -> hal_host -> controller -> metrics.
#ifndef DTC_SIL_RUN_HPP
#define DTC_SIL_RUN_HPP

#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "controller_adapter.hpp"
#include "hal_host.hpp"
#include "metrics.hpp"
#include "plant.h"
#include "scenario.hpp"
#include "sil_output.hpp"

namespace sil {

plant_params_t plant_params_from(const Scenario& sc);
hal_host::HarnessConfig harness_config_from(const Scenario& sc);
unsigned switched_legs(const Scenario& sc); // bit mask of the legs the topology switches

struct RunOptions {
    std::string out_dir;     // empty: write nothing (benchmarks, tests)
    unsigned decimate = 1;   // trace.csv: every N-th ISR
    bool write_trace = true;
};

struct RunResult {
    Metrics metrics;
    RunInfo info;
    Series series;           // the metrics window's samples (plus nothing before it)
};

/// Runs the scenario. Returns false with *err when anything fails before the results are complete
/// (nothing is then left in out_dir). A controller fault is a result, not a failure.
bool run_scenario(const Scenario& sc, const RunOptions& opt, RunResult* res, std::string* err);

/// Same with a given control side instead of make_controller(sc) (tests, alternative controllers).
bool run_scenario_with(const Scenario& sc, std::unique_ptr<Controller> ctrl, const RunOptions& opt, RunResult* res,
                       std::string* err);

/// The dtc-sil command line (main() is a one-line call; tests call it directly).
/// Exit status: 0 done, 1 bad usage or scenario, 2 run failed.
int dtc_sil_main(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

} // namespace sil

#endif // DTC_SIL_RUN_HPP
