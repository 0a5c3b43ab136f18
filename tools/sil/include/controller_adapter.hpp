// controller_adapter.hpp - the control side of a SIL run, behind one small interface.
//
// The run loop (run.hpp) owns a hal_host::Harness and calls, once per control period k:
//     harness.sample();  controller.step(harness);  record;  harness.advance();
// Implementations:
//   * OpenLoopController: control.voltage_csv (or the V/f source) held per period on the ideal
//     inverter.
//   * FirmwareController (controller_firmware.cpp): app_init(dtc_config_si(...)) at init and
//     app_isr() per period, so the unchanged firmware talks to hal_host through hal.h.
//   * ReferenceController (controller_reference.cpp, library sil_reference): model/'s
//     double-precision reference DTC on the same measurements, for the fixed-point vs double
//     comparison (control.implementation = "reference").
#ifndef DTC_SIL_CONTROLLER_ADAPTER_HPP
#define DTC_SIL_CONTROLLER_ADAPTER_HPP

#include <memory>
#include <string>
#include <vector>

#include "dtc_config_si.h"
#include "firmware_si.hpp"
#include "scenario.hpp"

namespace hal_host {
class Harness;
}

namespace sil {

/// What the controller estimated in this period (for trace.csv and the estimate metrics).
struct ControllerEstimates {
    bool valid = false;
    double te_nm = 0.0;
    double psi_alpha_wb = 0.0;
    double psi_beta_wb = 0.0;
};

class Controller {
public:
    virtual ~Controller() = default;
    /// Once, with the harness active and the plant at t = 0, before the first period.
    /// Returns "" or an error message (the run then writes nothing).
    virtual std::string init(hal_host::Harness& h) = 0;
    /// Period k: runs between Harness::sample() and Harness::advance().
    virtual void step(hal_host::Harness& h) = 0;
    /// Estimates made in the last step (valid = false if the controller has none). The run loop
    /// calls it only in periods it records (metrics window, trace rows), between step() and the
    /// next step(), with the harness active.
    virtual ControllerEstimates estimates() const = 0;
    /// "none" or the controller's fault reason code (called after the last step, harness active).
    virtual std::string fault() const = 0;
    /// What the fault means, in words, with when it latched ("" without a fault or a meaning).
    virtual std::string fault_detail() const { return ""; }
    /// The phase the controller moved onto the capacitor mid-point after a leg failure (enum
    /// hal_relay: 1..3 = A..C), 0 = none, -1 = the controller has no such status (called after
    /// the last step, harness active).
    virtual int reconfigured() const { return -1; }
    /// The names of the warnings the controller raised during the run (firmware/app/app_warn.h),
    /// empty when none, and the time of the first (-1: none); after the last step, harness active.
    virtual std::vector<std::string> warnings() const { return {}; }
    virtual double warning_time_s() const { return -1.0; }
    /// True if the controller produces torque/flux estimates at all (open loop does not).
    virtual bool has_estimates() const = 0;
    /// ISR recording (dtc-sil run --record-isr, docs/pil.md): only the firmware runs an ISR.
    virtual bool can_record_isr() const { return false; }
    /// After init(): start writing the recording to path. "" or why not.
    virtual std::string start_isr_record(const std::string& path)
    {
        (void)path;
        return "--record-isr: only control.implementation = \"firmware\" runs the firmware's ISR";
    }
    /// After the last step(): complete the recording (ISR count in its header). "" or why not.
    virtual std::string end_isr_record() { return ""; }
    /// After init(): the drive is operated over its serial line (dtc-sil serve): it starts
    /// disarmed with zero references and arms only on the host's command; ts_s is the control
    /// period the protocol reports. "" or why not.
    virtual std::string serve(double ts_s)
    {
        (void)ts_s;
        return "serve: only control.implementation = \"firmware\" has a serial line";
    }
};

/// Control side for a scenario, or nullptr with *err set (e.g. firmware not built in).
std::unique_ptr<Controller> make_controller(const Scenario& sc, std::string* err);

/// Open-loop voltage source: row r applies from t_s[r] until the next row's t_s; each control
/// period k uses the row in force at its start t_k (zero-order hold, no actuation delay).
std::unique_ptr<Controller> make_open_loop_controller(std::vector<VoltageRow> rows);
/// The built-in V/f source (control.vf_*) as a voltage table, one row per control period.
std::vector<VoltageRow> vf_voltage_rows(const Scenario& sc);

/// control.implementation = "reference": the adapter of model/'s double-precision reference
/// controller lives in its own library (sil_reference, it needs the plant library), so the
/// executables that have it register it (dtc-sil's main, the closed-loop tests).
using ControllerFactory = std::unique_ptr<Controller> (*)(const Scenario& sc, std::string* err);
void register_reference_controller(ControllerFactory factory);
/// Defined by sil_reference (controller_reference.cpp).
std::unique_ptr<Controller> make_reference_controller(const Scenario& sc, std::string* err);

} // namespace sil

#endif // DTC_SIL_CONTROLLER_ADAPTER_HPP
