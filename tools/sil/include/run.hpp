// run.hpp - one SIL run: scenario -> plant parameters -> hal_host -> controller -> metrics.
#ifndef DTC_SIL_RUN_HPP
#define DTC_SIL_RUN_HPP

#include <csignal>
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

/// The scenario's plant and sensing chain (plant_params_from, harness_config_from), created and
/// made the active harness of hal.h; deactivated when this object goes.
class ActiveHarness {
public:
    /// The scenario's plant (plant_params_from) in an activated harness; nullptr with *err when
    /// the plant or harness refuses the scenario.
    hal_host::Harness* open(const Scenario& sc, std::string* err);
    /// The plant parameters of the last open().
    const plant_params_t& params() const { return pp_; }
    ~ActiveHarness();

private:
    plant_params_t pp_{};
    std::unique_ptr<hal_host::Harness> h_;
};

struct RunOptions {
    std::string out_dir;     // empty: write nothing (benchmarks, tests)
    unsigned decimate = 1;   // trace.csv: every N-th ISR
    bool write_trace = true;
    bool check_only = false; // build the plant, harness and controller (all refusals), run nothing
    bool force = false;      // run even when the trace estimate exceeds max_trace_bytes
    std::string record_isr;  // non-empty: write the ISR recording (docs/pil.md) to this file
    double max_trace_bytes = 1.0e9;
    std::ostream* progress = nullptr; // progress line with ETA ("\r", for a terminal); nullptr: none
    // dtc-sil serve: the firmware's serial line on a pseudo-terminal linked at serial_link, the
    // run paced at `pace` times real time (0: as fast as it goes), until SIGINT/SIGTERM or
    // duration_s (the scenario's duration_s is replaced; 0: until a signal). A signal ends a
    // served run normally: trace and metrics of what ran.
    std::string serial_link;
    double pace = 1.0;
    double serve_duration_s = 0.0;
};

/// Bytes per trace.csv row used for the estimate before the run (rows take 371-376 bytes on the
/// shipped scenarios). During the run the guard measures the rows written and stops a run whose
/// trace would exceed RunOptions::max_trace_bytes.
constexpr double kTraceBytesPerRow = 380.0;

/// Physical bounds of the plant state for this scenario; outside them (or non-finite) the run
/// stops with fault "plant_diverged".
struct PlantBounds {
    double current_a = 0.0;   // |i_a|, |i_b|, |i_c|
    double omega_rad_s = 0.0; // |omega_m|
    double voltage_v = 0.0;   // |vdc|, |vc_lo|, |vc_hi|
};
PlantBounds plant_bounds(const Scenario& sc);
/// Empty when s is within b; otherwise what is out of bounds ("i_b = nan A").
std::string plant_out_of_bounds(const plant_sensed_t& s, const PlantBounds& b);

/// Set by a SIGINT/SIGTERM handler (dtc_sil_main installs one during a run): the run loop stops
/// at its next check (every 4096 periods), fails with "interrupted", and removes its staging folder.
extern volatile std::sig_atomic_t g_stop_signal;

/// SIGINT/SIGTERM set g_stop_signal for the lifetime of this object (a run then stops and removes
/// its staging folder; a sweep kills its runs in flight); the previous handlers come back afterwards.
class StopSignals {
public:
    StopSignals();
    ~StopSignals();
    StopSignals(const StopSignals&) = delete;
    StopSignals& operator=(const StopSignals&) = delete;

private:
    struct sigaction old_int_ {}, old_term_ {};
};

struct RunResult {
    Metrics metrics;
    RunInfo info;
    Series series;           // the metrics window's samples (plus nothing before it)
    bool output_touched = false; // a failed run changed out_dir after all (see StagedOutput::commit)
};

/// Runs the scenario. Returns false with *err when anything fails before the results are complete
/// (nothing is then left in out_dir). A controller fault is a result, not a failure.
bool run_scenario(const Scenario& sc, const RunOptions& opt, RunResult* res, std::string* err);

/// True when the run finished but its result is not physics (plant_diverged, non_finite_metric).
bool run_failed_physically(const RunInfo& info);

/// Same with a given control side instead of make_controller(sc) (tests, alternative controllers).
bool run_scenario_with(const Scenario& sc, std::unique_ptr<Controller> ctrl, const RunOptions& opt, RunResult* res,
                       std::string* err);

/// The dtc-sil command line, as parsed (nothing read, nothing checked beyond each option's own
/// type and range). A sweep command is only recognised here: its line is sweep::parse_sweep_args's.
struct SilArgs {
    enum class Command { None, Run, Check, Identify, Serve, Keys, Sweep } cmd = Command::None;
    std::string scenario_path, out_dir, record_isr, serial_link;
    std::vector<std::string> sets, overlays;
    unsigned decimate = 1;     ///< run, serve: every N-th ISR to trace.csv, 1..10^6
    bool no_trace = false, quiet = false, force = false;
    double ident_max_s = 10.0; ///< identify --max-time, s, 0.01..1000
    double pace = 1.0;         ///< serve --pace, 0..1000
    double serve_duration_s = 0.0; ///< serve --duration-s, 0..10^6 (0: until a signal)
};

/// Parses dtc-sil's line (args[0] the program) into *a. Returns -1 when accepted, else the exit
/// status with CLI11's text written: 0 after --help or --version on out, 1 after a usage error on err.
int parse_sil_args(const std::vector<std::string>& args, SilArgs* a, std::ostream& out, std::ostream& err);

/// The dtc-sil command line (main() is a one-line call; tests call it directly).
/// Exit status: 0 done (a firmware trip is a result), 1 bad usage or scenario, 2 run failed,
/// 3 plant diverged or a metric is not finite, 128 + N interrupted by signal N.
int dtc_sil_main(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

} // namespace sil

#endif // DTC_SIL_RUN_HPP
