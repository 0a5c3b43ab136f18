// controller_adapter.hpp - the control side of a SIL run, behind one small interface.
//
// The run loop (run.hpp) owns a hal_host::Harness and calls, once per control period k:
//     harness.sample();  controller.step(harness);  record;  harness.advance();
// Implementations:
//   * OpenLoopController (always built): control.voltage_csv held per period on the ideal inverter.
//   * FirmwareController (controller_firmware.cpp, built only when the firmware and the SI config
//     converter exist, see tools/sil/CMakeLists.txt): app_init(dtc_config_si(...)) at init and
//     app_isr() per period, so the unchanged firmware talks to hal_host through hal.h.
//   * ReferenceController (controller_reference.cpp, library sil_reference, built when
//     model/include/ref_dtc.h exists): model/'s double-precision reference DTC on the same
//     measurements, for the fixed-point vs double comparison (control.implementation = "reference").
#ifndef DTC_SIL_CONTROLLER_ADAPTER_HPP
#define DTC_SIL_CONTROLLER_ADAPTER_HPP

#include <memory>
#include <string>
#include <vector>

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
    /// True if the controller produces torque/flux estimates at all (open loop does not).
    virtual bool has_estimates() const = 0;
};

/// All SI values the firmware's configuration converter (tools/config, dtc_config_si) needs,
/// gathered from the scenario in one place, with the speed-PI gains already derived.
struct FirmwareSiConfig {
    // motor (Hoang Table VIII)
    double rs_ohm, ls_h, psi_m_wb;
    int pole_pairs;
    double rated_torque_nm, rated_current_a, rated_speed_rpm;
    // inverter (Table IV) and sensing
    int topology_fstp; // 0 = SSTP, 1 = FSTP
    double vdc_nominal_v, v_ce_v, v_d_v, r_on_ohm, v_f_v;
    double current_range_a, voltage_range_v; // ADC full scale (+-A, V)
    int vmid_fitted;
    int encoder_lines;
    double encoder_offset_rad;
    // control
    double ts_s;
    int speed_loop_divider;
    int mode_torque;      // 1 = torque mode (speed loop bypassed)
    int estimator_voltage; // 0 = current model, 1 = voltage model
    int compensation;     // 0 none, 1 simple, 2 proposed
    int table;            // 0 basic, 1..4 = ST-A..ST-D (SSTP)
    double speed_ref_rpm, torque_ref_nm, torque_limit_nm, flux_ref_wb;
    double torque_band_nm, flux_band_wb, lpf_cutoff_rad_s;
    int handover_given; // 0: the converter derives the hand-over speed
    double handover_rpm, handover_hyst_frac;
    int delay_comp;
    int deadtime_comp;
    double dead_time_s; // the gate driver's setting (inverter.dead_time_s, also when not modelled)
    double speed_kp_nm_per_rad_s, speed_ki_nm_per_rad;
    // protection
    double overcurrent_a, vdc_min_v, vdc_max_v, stall_time_s;
    // current limit and ripple-robust polarity (firmware ilim.h, dtc_config.h polarity_mid)
    int current_limit_given; // 0: the converter derives the limit from the trip level
    double current_limit_a;
    int polarity_mid;
    int vmid_cal;
    int lpf_comp;
    int dc_supp;
    double c_dc_f; // each split capacitor (inverter.c_dc_f)
};
FirmwareSiConfig firmware_si_config(const Scenario& sc);

/// Control side for a scenario, or nullptr with *err set (e.g. firmware not built in).
std::unique_ptr<Controller> make_controller(const Scenario& sc, std::string* err);

/// Open-loop voltage source: row r applies from t_s[r] until the next row's t_s; each control
/// period k uses the row in force at its start t_k (zero-order hold, no actuation delay).
std::unique_ptr<Controller> make_open_loop_controller(std::vector<VoltageRow> rows);
/// The built-in V/f source (control.vf_*) as a voltage table, one row per control period.
std::vector<VoltageRow> vf_voltage_rows(const Scenario& sc);

/// True when this build contains the firmware adapter (controller_firmware.cpp).
bool firmware_controller_available();

/// control.implementation = "reference": the adapter of model/'s double-precision reference
/// controller lives in its own library (sil_reference, it needs the plant library), so the
/// executables that have it register it (dtc-sil's main, the closed-loop tests).
using ControllerFactory = std::unique_ptr<Controller> (*)(const Scenario& sc, std::string* err);
void register_reference_controller(ControllerFactory factory);
/// Defined by sil_reference (controller_reference.cpp) when model/include/ref_dtc.h exists.
std::unique_ptr<Controller> make_reference_controller(const Scenario& sc, std::string* err);

} // namespace sil

#endif // DTC_SIL_CONTROLLER_ADAPTER_HPP
