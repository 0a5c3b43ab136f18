// run_parts.hpp - the parts of one SIL run that run_scenario_with (run.cpp) puts together: the
// scheduled events (load step, dynamometer ramp, injected faults and the speed's response to them)
// and the recorder (the metrics window's series and trace.csv rows). Inside sil_run only.
#ifndef DTC_SIL_RUN_PARTS_HPP
#define DTC_SIL_RUN_PARTS_HPP

#include <cstdint>

#include "controller_adapter.hpp"
#include "hal_host.hpp"
#include "metrics.hpp"
#include "plant.h"
#include "scenario.hpp"
#include "sil_output.hpp"

namespace sil {

/// The [faults] table applied to the plant and the sensing emulation.
void inject_faults(const Scenario& sc, hal_host::Harness& h);

/// What the scenario schedules during a run, and the speed's response to an injected fault.
class RunEvents {
public:
    RunEvents(const Scenario& sc, plant_load_t load);
    /// At the start of each period, before the sample: the load step, the dynamometer's speed
    /// ramp and the fault injection at the first period at or after their times.
    void before_sample(hal_host::Harness& h);
    /// After the sample: the speed dip and the time back in the 1 % band after a fault (speed mode).
    void after_sample(const hal_host::Harness& h);
    /// After the controller's step: the time of the trip (the first period with the gates off
    /// and a controller fault, or the hardware comparator latched).
    void after_step(const hal_host::Harness& h, const Controller& ctrl);
    /// The injected fault's time, speed dip and recovery, and the trip's time, into info.
    void report(RunInfo* info) const;

private:
    const Scenario& sc_;
    plant_load_t load_;
    bool load_stepped_, dyno_ramp_, faults_pending_, speed_mode_;
    double fault_t_ = -1.0;
    double band_rpm_;
    double dip_rpm_ = 0.0, last_out_t_ = -1.0, last_t_ = -1.0;
    double dip_base_rpm_ = 0.0; // the speed the dip is measured from (set at the fault)
    bool last_in_ = false;
    bool legs_;
    bool ever_enabled_ = false, prev_enabled_ = false;
    double trip_t_ = -1.0, hw_trip_t_ = -1.0;
    double temp_next_t_ = 0.0;  // motor.temp_rise_k: when the resistances are next updated
};

/// The metrics window's samples (Series, sized once: no allocation in the loop) and trace.csv's rows.
class Recorder {
public:
    /// periods: the run's length; window_n: the metrics window's samples; est: the controller has
    /// estimates; trace: trace.csv is written (open() first), one row every `decimate` periods.
    Recorder(const Scenario& sc, std::uint64_t periods, std::uint64_t window_n, bool est, bool trace,
             unsigned decimate, Series* s);
    bool open_trace(const std::string& path, std::string* err);
    bool close_trace(std::string* err);
    std::uint64_t trace_bytes() const { return trace_.bytes_written(); }
    std::uint64_t trace_rows() const { return trace_.rows_written(); }
    /// True when period k is recorded or traced (otherwise neither the plant state nor the
    /// controller's estimates need be read).
    bool wants(std::uint64_t k) const { return k >= record_from_ || (trace_on_ && k % decimate_ == 0); }
    /// Records period k after the controller's step and before the plant advances.
    void record(std::uint64_t k, const hal_host::Harness& h, const Controller& ctrl);

private:
    void record_series(std::size_t i, const plant_state_t& st, const ControllerEstimates& e, const hal_cmd_t& cmd,
                       bool en, const hal_host::Harness& h);
    void trace_row(const plant_state_t& st, const ControllerEstimates& e, const hal_cmd_t& cmd, bool en,
                   const hal_host::Harness& h);

    Series& s_;
    TraceWriter trace_;
    std::uint64_t record_from_;
    bool est_, legs_, im_, trace_on_;
    unsigned decimate_;
    double pole_pairs_;
    double flux_angle_prev_ = 0.0; // induction machine: stator-flux angle of the last recorded sample
};

} // namespace sil

#endif // DTC_SIL_RUN_PARTS_HPP
