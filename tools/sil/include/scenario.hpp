// scenario.hpp - SIL scenario: the SI description of one run (TOML file + --set overrides).
//
// Every key, its type, unit, default and allowed range lives in one schema table
// (scenario_schema()); parsing, --set, validation, `dtc-sil keys` and the key table of docs/sil.md
// all come from it. Defaults: Hoang 2011 Table VIII machine, Table IV devices, 70 V, SSTP.
// Errors always name the key and where its value came from ("file:line:col" or "--set").
#ifndef DTC_SIL_SCENARIO_HPP
#define DTC_SIL_SCENARIO_HPP

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace sil {

/// The default induction machine's values for the shared motor keys (motor.type = "im", keys left
/// unset): model/'s plant_params_im_default (tests/sil checks they agree; sil_core does not link the
/// plant). Rated values: Casadei Tables 4-5, 26.5 N*m at 1440 rpm, where this machine draws
/// 13.6 A rms = 19.2 A peak (docs/plant.md).
struct ImDefaults {
    double rs_ohm = 1.405 * 0.3025;   // Modelica Buildings IM_5HP_400V_50Hz x (220/400)^2
    double rr_ohm = 1.395 * 0.3025;
    double lls_h = 5.839e-3 * 0.3025;
    double llr_h = 5.839e-3 * 0.3025;
    double lm_h = 172.2e-3 * 0.3025;
    std::int64_t pole_pairs = 2;
    double j_kgm2 = 0.0131;
    double b_nms = 0.0;
    double rated_torque_nm = 26.5;
    double rated_current_a = 19.2;
    double rated_speed_rpm = 1440.0;
};

struct MotorCfg {
    std::string type = "pmsm";
    double rs_ohm = 0.466;      // Hoang Table VIII
    double ls_h = 3.19e-3;      // Table VIII (dq inductance, surface PM: Ld = Lq)
    double psi_m_wb = 0.0928;   // Table VIII
    std::int64_t pole_pairs = 1;
    double j_kgm2 = 1.0e-4;     // not in the paper: small servo motor + coupled DC generator
    double b_nms = 4.7746e-4;   // 0.075 N*m at 1500 rpm: Hoang sec. IV, inertial load = 25 % of 0.3 N*m
    std::array<double, 3> emf_gain{1.0, 1.0, 1.0};
    std::array<double, 3> emf_harm_a{}; // 3rd, 5th, 7th relative to the fundamental
    std::array<double, 3> emf_harm_b{};
    std::array<double, 3> emf_harm_c{};
    double rated_torque_nm = 0.3;  // Table VIII, the T_rated of eq. 40
    // Induction machine only (motor.type = "im"): T-model, stator-referred. Defaults: the 220 V
    // rescaling of Modelica Buildings IM_5HP_400V_50Hz (plant_params_im_default, docs/plant.md);
    // with motor.type = "im" the shared keys left unset take that machine's values too.
    double rr_ohm = ImDefaults{}.rr_ohm;
    double lls_h = ImDefaults{}.lls_h;
    double llr_h = ImDefaults{}.llr_h;
    double lm_h = ImDefaults{}.lm_h;
    double rated_current_a = 2.2;
    double rated_speed_rpm = 3000.0;
};

struct InverterCfg {
    std::string topology = "sstp"; // ideal | sstp | fstp
    double vdc_v = 70.0;           // Table VIII
    double v_ce_v = 0.9;           // Table IV
    double v_d_v = 1.25;           // Table IV
    double r_on_ohm = 0.075;       // Table IV
    double dead_time_s = 1.0e-6;
    double c_dc_f = 4.7e-3;        // FSTP mid-point ripple at 2.2 A, 25 Hz: +-1.5 V (see docs/sil.md)
    double r_dc_ohm = 0.1;
    double r_bal_ohm = 0.0;        // balancing resistor across each capacitor; 0 = not fitted
    double esr_ohm = 0.0;          // capacitor ESR; 0 = ideal capacitor (docs/plant.md gives typical values)
    bool drops = true;
    bool dead_time = true;
    bool finite_dc_link = true;
};

struct LoadCfg {
    std::string type = "inertia"; // speed | torque | generator | inertia
    double speed_rpm = 1500.0;
    double torque_nm = 0.0;
    double step_time_s = 0.0;     // 0 = no step
    double step_torque_nm = 0.0;
    double coulomb_nm = 0.0;      // Coulomb (dry) friction of the coupled load; 0 = none
};

struct ControlCfg {
    std::string mode = "speed";          // speed | torque | open_loop
    std::string implementation = "firmware"; // firmware | reference
    std::string estimator = "current";   // current | voltage
    std::string compensation = "none";   // none | simple | proposed
    std::string table = "basic";         // basic | st-a | st-b | st-c | st-d (SSTP)
    double speed_ref_rpm = 1500.0;
    double speed_bw_hz = 10.0;
    std::int64_t speed_loop_divider = 10; // Hoang sec. IV: speed loop 10x slower than 50 us
    double torque_limit_nm = 0.6;
    double torque_ref_nm = 0.3;
    double flux_ref_wb = 0.0928;         // Hoang sec. IV: |psi_s*| = psi_m
    double torque_band_nm = 0.0;         // Hoang sec. IV: bands set to zero
    double flux_band_wb = 0.0;
    double lpf_cutoff_rad_s = 5.0;       // Hoang sec. IV
    double handover_rpm = 0.0;           // voltage model: current model below it; see handover_given
    bool handover_given = false;         // false: derived from the machine (dtc_handover_default_rpm)
    double handover_hyst_frac = 0.2;     // back to the current model below (1 - frac) * handover_rpm
    bool delay_comp = true;              // firmware: comparators on the flux/torque predicted for k+1
    bool deadtime_comp = true;           // firmware: dead time in the voltage reconstruction
    double current_limit_a = 0.0;        // firmware current limit; see current_limit_given
    bool current_limit_given = false;    // false: derived from the trip level (dtc_ilim_default_a)
    bool polarity_mid = true;            // firmware: ripple-robust polarity of the compensations
    bool dc_supp = true;                 // firmware: DC-current suppression (voltage model)
    bool lpf_comp = true;                // firmware: low-pass gain/phase correction (voltage model)
    bool vmid_cal = true;                // firmware: FSTP mid-point calibrated against V_dc/2
    double v_f_v = 0.9;                  // simple compensation V_f (Hoang sec. III-B)
    std::string voltage_csv;             // open_loop: t_s,v_alpha_v,v_beta_v (resolved path)
    double vf_freq_hz = 0.0;             // open_loop built-in V/f source: final frequency (0 = off)
    double vf_v_per_hz = 0.0;            // voltage-vector amplitude per Hz
    double vf_boost_v = 0.0;             // amplitude at 0 Hz (low-speed boost)
    double vf_ramp_s = 0.0;              // frequency ramp time 0 -> vf_freq_hz (0 = step)
};

struct SensorsCfg {
    double current_range_a = 10.0;
    std::array<double, 3> current_offset_a{};
    std::array<double, 3> current_gain_error{};
    double current_noise_a_rms = 0.0;
    double voltage_range_v = 100.0;
    double vdc_offset_v = 0.0;
    double vdc_gain_error = 0.0;
    double vmid_offset_v = 0.0;
    double vmid_gain_error = 0.0;
    double voltage_noise_v_rms = 0.0;
    bool vmid_fitted = true;
    std::int64_t encoder_lines = 2000;   // Hoang Fig. 9(b)
    double encoder_offset_rad = 0.0;
    std::int64_t seed = 1;
};

struct ProtectionCfg {
    double overcurrent_a = 6.0;   // firmware trip on any phase current
    double vdc_min_v = 40.0;      // firmware DC-link under-voltage trip
    double vdc_max_v = 90.0;      // firmware DC-link over-voltage trip
    double hw_trip_current_a = 8.0; // hardware comparator (PDPINTA), in hal_host
    double stall_time_s = 0.0;      // firmware stall fault time; 0 = derived, max(0.1 s, 20 speed periods)
    bool allow_unsafe = false;    // accept trip settings that let the current exceed 3x rated
};

/// The firmware's own values of machine and inverter parameters (parameter mismatch without code
/// changes). Unset: the firmware is given the plant's value (motor.*, inverter.*).
struct FirmwareCfg {
    std::optional<double> rs_ohm, ls_h, psi_m_wb; // PM machine as the firmware believes it
    std::optional<double> v_ce_v, v_d_v, r_on_ohm; // device drops its compensation assumes
    std::optional<double> dead_time_s;             // dead time its compensation assumes
};

struct MetricsCfg {
    double torque_sensor_hz = 0.0; // trf_filtered_pct: torque transducer bandwidth, 0 = unfiltered
};

struct Scenario {
    std::string name;            // file stem
    std::string path;            // scenario file as given
    double duration_s = 0.5;
    double metrics_window_s = 0.2;
    double ts_s = 50e-6;         // control period (Hoang sec. IV: 50 us)
    double max_step_s = 50e-6;   // plant integration sub-step (RK4 on event-landing steps; docs/sil.md);
                                 // when not set it is min(50 us, ts_s)
    double initial_speed_rpm = 0.0;
    double initial_theta_m_rad = 0.0;
    MotorCfg motor;
    InverterCfg inverter;
    LoadCfg load;
    ControlCfg control;
    SensorsCfg sensors;
    ProtectionCfg protection;
    FirmwareCfg firmware;
    MetricsCfg metrics;
    std::map<std::string, std::string> origin; // key -> "file:line:col" or "--set"
};

/// One documented scenario key (for the schema table, `dtc-sil keys` and docs/sil.md).
struct KeyDoc {
    std::string name;     // dotted
    std::string type;     // number, integer, boolean, string, array of 3 numbers, path
    std::string unit;
    std::string default_text;
    std::string range;    // allowed values
    std::string doc;
};
std::vector<KeyDoc> scenario_keys();

/// Parse errors and warnings; each error names the key and where its value came from.
struct Diagnostics {
    std::vector<std::string> errors;
    std::vector<std::string> warnings;
    bool ok() const { return errors.empty(); }
    /// The first kMaxShown errors (and warnings), then a count of the rest.
    std::string text() const;
    static constexpr std::size_t kMaxShown = 50;
};

/// Loads a scenario file and applies "key=value" overrides. Returns false (and fills diag) when
/// the file cannot be read or parsed, a key is unknown, a type is wrong, a value is impossible or
/// required values are missing. Nothing is run or written by this function.
bool load_scenario(const std::string& path, const std::vector<std::string>& overrides, Scenario* out,
                   Diagnostics* diag);
/// Same, from TOML text (source_name is used in messages and to resolve relative paths).
bool parse_scenario(const std::string& toml_text, const std::string& source_name,
                    const std::vector<std::string>& overrides, Scenario* out, Diagnostics* diag);

/// Markdown table of every key (the text of `dtc-sil keys`).
std::string scenario_keys_markdown();

/// One row of an open-loop voltage table.
struct VoltageRow {
    double t_s, v_alpha_v, v_beta_v;
};
/// Reads a `t_s,v_alpha_v,v_beta_v` CSV (header required, t strictly increasing from <= 0,
/// finite values). Errors name the file and line.
bool load_voltage_csv(const std::string& path, std::vector<VoltageRow>* rows, std::string* err);

/// Speed PI gains from the inertia and the wanted bandwidth (see scenario.cpp for the design).
struct SpeedPiGains {
    double kp_nm_per_rad_s;
    double ki_nm_per_rad;
};
SpeedPiGains speed_pi_gains(double j_kgm2, double bw_hz);

} // namespace sil

#endif // DTC_SIL_SCENARIO_HPP
