// scenario.hpp - SIL scenario: the SI description of one run (TOML file + --set overrides).
//
// Every key, its type, unit, default and allowed range lives in one schema table
// (scenario_schema()); parsing, --set, validation, `dtc-sil keys` and the key table of docs/sil.md
// all come from it. Default values: model/include/plant_defaults.h (one table with sources);
// the variant defaults (SSTP, current model, speed mode) are set here.
// Errors always name the key and where its value came from ("file:line:col" or "--set").
#ifndef DTC_SIL_SCENARIO_HPP
#define DTC_SIL_SCENARIO_HPP

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "plant_defaults.h"
#include "sil_constants.hpp"

namespace sil {

// ---- Variants: parsed once from their key's text (scenario load), enums everywhere after. ----
enum class MotorType { Pmsm, Im };
enum class Topology { Ideal, Sstp, Fstp };
enum class LoadType { Speed, Torque, Generator, Inertia, Fan };
enum class ControlMode { Speed, Torque, OpenLoop };
enum class Implementation { Firmware, Reference };
enum class Estimator { Current, Voltage, Improved };
enum class Compensation { None, Simple, Proposed };
enum class SwitchingTable { Basic, StA, StB, StC, StD, SpeedDependent };
enum class Scheme { Dtc, Dsc, Sfvc, Dfoc, Dsvm, Itc };
enum class Modulation { Symmetric, TwoPhase };
enum class SpeedSensor { Encoder, None };
enum class FaultPhase { None, A, B, C };
enum class FaultSwitch { None, AUpper, ALower, BUpper, BLower, CUpper, CLower };

/// The one to-string table of each variant: names[i] is the key text of enum value i.
template <typename E> struct VariantNames;
template <> struct VariantNames<MotorType> {
    static constexpr std::array<const char*, 2> names{"pmsm", "im"};
};
template <> struct VariantNames<Topology> {
    static constexpr std::array<const char*, 3> names{"ideal", "sstp", "fstp"};
};
template <> struct VariantNames<LoadType> {
    static constexpr std::array<const char*, 5> names{"speed", "torque", "generator", "inertia", "fan"};
};
template <> struct VariantNames<ControlMode> {
    static constexpr std::array<const char*, 3> names{"speed", "torque", "open_loop"};
};
template <> struct VariantNames<Implementation> {
    static constexpr std::array<const char*, 2> names{"firmware", "reference"};
};
template <> struct VariantNames<Estimator> {
    static constexpr std::array<const char*, 3> names{"current", "voltage", "improved"};
};
template <> struct VariantNames<Compensation> {
    static constexpr std::array<const char*, 3> names{"none", "simple", "proposed"};
};
template <> struct VariantNames<SwitchingTable> {
    static constexpr std::array<const char*, 6> names{"basic", "st-a", "st-b", "st-c", "st-d", "speed-dependent"};
};
template <> struct VariantNames<Scheme> {
    static constexpr std::array<const char*, 6> names{"dtc", "dsc", "sfvc", "dfoc", "dsvm", "itc"};
};
template <> struct VariantNames<Modulation> {
    static constexpr std::array<const char*, 2> names{"symmetric", "two_phase"};
};
template <> struct VariantNames<SpeedSensor> {
    static constexpr std::array<const char*, 2> names{"encoder", "none"};
};

template <> struct VariantNames<FaultPhase> {
    static constexpr std::array<const char*, 4> names{"none", "a", "b", "c"};
};
template <> struct VariantNames<FaultSwitch> {
    static constexpr std::array<const char*, 7> names{"none", "a_upper", "a_lower", "b_upper", "b_lower",
                                                      "c_upper", "c_lower"};
};

/// The key text of a variant ("fstp", "open_loop", ...).
template <typename E> std::string to_string(E e)
{
    return VariantNames<E>::names[static_cast<std::size_t>(e)];
}
/// Parses a variant's key text; false (and *out unchanged) when it names none.
template <typename E> bool parse_variant(const std::string& text, E* out)
{
    const auto& n = VariantNames<E>::names;
    for (std::size_t i = 0; i < n.size(); ++i) {
        if (text == n[i]) {
            *out = static_cast<E>(i);
            return true;
        }
    }
    return false;
}

/// The default induction machine's values for the shared motor keys (motor.type = "im", keys left
/// unset), from plant_defaults.h as plant_params_im_default (tests/sil checks they agree).
struct ImDefaults {
    double rs_ohm = PLANT_DEF_IM_RS_OHM;
    double rr_ohm = PLANT_DEF_IM_RR_OHM;
    double lls_h = PLANT_DEF_IM_LLS_H;
    double llr_h = PLANT_DEF_IM_LLR_H;
    double lm_h = PLANT_DEF_IM_LM_H;
    std::int64_t pole_pairs = PLANT_DEF_IM_POLE_PAIRS;
    double j_kgm2 = PLANT_DEF_IM_J_KGM2;
    double b_nm_s_per_rad = PLANT_DEF_IM_B_NM_S_PER_RAD;
    double rated_torque_nm = PLANT_DEF_IM_RATED_TORQUE_NM;
    double rated_current_a = PLANT_DEF_IM_RATED_CURRENT_A;
    double rated_speed_rpm = PLANT_DEF_IM_RATED_SPEED_RPM;
};

struct MotorCfg {
    MotorType type = MotorType::Pmsm;
    double rs_ohm = PLANT_DEF_PM_RS_OHM;
    double ls_h = PLANT_DEF_PM_LS_H;  // L_d of a salient PM
    double ld_h = PLANT_DEF_PM_LS_H;  // = ls_h once the scenario is read
    double lq_h = PLANT_DEF_PM_LS_H;  // not set: ls_h (a surface PM)
    double psi_m_wb = PLANT_DEF_PM_PSI_M_WB;
    std::int64_t pole_pairs = PLANT_DEF_PM_POLE_PAIRS;
    double j_kgm2 = PLANT_DEF_PM_J_KGM2;
    double b_nm_s_per_rad = PLANT_DEF_PM_B_NM_S_PER_RAD;
    std::array<double, 3> emf_gain{1.0, 1.0, 1.0};
    std::array<double, 3> emf_harm_a{}; // 3rd, 5th, 7th relative to the fundamental
    std::array<double, 3> emf_harm_b{};
    std::array<double, 3> emf_harm_c{};
    double rated_torque_nm = PLANT_DEF_PM_RATED_TORQUE_NM; // the T_rated of Hoang eq. 40
    // Induction machine only (motor.type = "im"): T-model, stator-referred; with motor.type = "im"
    // the shared keys left unset take that machine's values too (ImDefaults).
    double rr_ohm = ImDefaults{}.rr_ohm;
    double lls_h = ImDefaults{}.lls_h;
    double llr_h = ImDefaults{}.llr_h;
    double lm_h = ImDefaults{}.lm_h;
    double rated_current_a = PLANT_DEF_PM_RATED_CURRENT_A;
    double rated_speed_rpm = PLANT_DEF_PM_RATED_SPEED_RPM;
    // The windings' temperature rise over the run, linear from 0 at t = 0 to this at duration_s:
    // R_s and R_r (im) times 1 + 0.39 %/K * rise(t) (copper, PLANT_DEF_CU_TEMPCO_PER_K); 0 = none.
    double temp_rise_k = 0.0;
};

struct InverterCfg {
    Topology topology = Topology::Sstp;
    double vdc_v = PLANT_DEF_VDC_V;
    double v_ce_v = PLANT_DEF_V_CE_V;
    double v_d_v = PLANT_DEF_V_D_V;
    double r_on_ohm = PLANT_DEF_R_ON_OHM;
    double dead_time_s = PLANT_DEF_DEAD_TIME_S;
    double c_dc_f = PLANT_DEF_C_DC_F;
    double r_dc_ohm = PLANT_DEF_R_DC_OHM;
    double r_bal_ohm = 0.0;        // balancing resistor across each capacitor; 0 = not fitted
    double esr_ohm = 0.0;          // capacitor ESR; 0 = ideal capacitor (docs/plant.md gives typical values)
    bool drops = true;
    bool phases_swapped = false;   // the machine's phases B and C on the inverter's legs C and B
    bool dead_time = true;
    bool finite_dc_link = true;
    bool reconfig_relay = false;   // a relay per phase ties it to the capacitor mid-point (fault tolerance)
    double relay_delay_s = PLANT_DEF_RELAY_DELAY_S; // relay contact delay after a coil command
};

struct LoadCfg {
    LoadType type = LoadType::Inertia;
    double speed_rpm = PLANT_DEF_SPEED_REF_RPM;
    double torque_nm = 0.0;
    double step_time_s = 0.0;     // 0 = no step
    double step_torque_nm = 0.0;
    double coulomb_nm = 0.0;      // Coulomb (dry) friction of the coupled load; 0 = none
    double speed_ramp_start_s = 0.0; // speed load: hold initial_speed_rpm until then, ...
    double speed_ramp_s = 0.0;       // ... then ramp to speed_rpm over this time (0 = hold speed_rpm from t = 0)
};

struct ControlCfg {
    ControlMode mode = ControlMode::Speed;
    Implementation implementation = Implementation::Firmware;
    Estimator estimator = Estimator::Current;
    Compensation compensation = Compensation::None;
    SwitchingTable table = SwitchingTable::Basic; // SSTP only
    double speed_ref_rpm = PLANT_DEF_SPEED_REF_RPM;
    double speed_bw_hz = PLANT_DEF_SPEED_BW_HZ;
    std::int64_t speed_loop_divider = PLANT_DEF_SPEED_LOOP_DIVIDER;
    double torque_limit_nm = PLANT_DEF_TORQUE_LIMIT_NM;
    double torque_ref_nm = PLANT_DEF_PM_RATED_TORQUE_NM;
    double flux_ref_wb = PLANT_DEF_FLUX_REF_WB;
    double torque_band_nm = 0.0;         // Hoang sec. IV: bands set to zero
    double flux_band_wb = 0.0;
    double lpf_cutoff_rad_s = PLANT_DEF_LPF_CUTOFF_RAD_S;
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
    bool cal_hold = true;                // firmware: rotor held (phases B, C) during that calibration
    bool fault_detect = true;            // firmware: open-phase and lost-encoder detection
    double v_f_v = PLANT_DEF_V_F_V;      // simple compensation V_f (Hoang sec. III-B)
    std::string voltage_csv;             // open_loop: t_s,v_alpha_v,v_beta_v (resolved path)
    double vf_freq_hz = 0.0;             // open_loop built-in V/f source: final frequency (0 = off)
    double vf_v_per_hz = 0.0;            // voltage-vector amplitude per Hz
    double vf_boost_v = 0.0;             // amplitude at 0 Hz (low-speed boost)
    double vf_ramp_s = 0.0;              // frequency ramp time 0 -> vf_freq_hz (0 = step)
    // Induction-machine law (motor.type = "im", Casadei 2006); refused by name for the PM machine.
    Scheme scheme = Scheme::Dtc;         // switching table (sections 4-8) or DSC (section 9); PM: dtc or itc
    SpeedSensor speed_sensor = SpeedSensor::Encoder; // none: speed from the flux speed and Casadei eq. 16
    bool flux_weakening = false;         // section 12
    double rotor_flux_ref_wb = 0.0;      // > 0: constant rotor flux, phi_s* by Casadei eq. 19; 0: flux_ref_wb
    double observer_tau_s = PLANT_DEF_IM_OBSERVER_TAU_S;  // Casadei eq. 20's tau, low speed / fixed
    double observer_tau_high_s = 0.0;    // tau at high speed (section 10.2); 0 = observer_tau_s (fixed)
    double observer_tau_lo_rpm = 0.0;    // |speed| up to which observer_tau_s applies
    double observer_tau_hi_rpm = 0.0;    // |speed| from which observer_tau_high_s applies
    double magnetise_frac = PLANT_DEF_IM_MAGN_FRAC; // start-up: torque allowed at this rotor-flux fraction
    bool rr_tracking = false;            // IM, encoder: the tracked rotor resistance in use (im_sup.h)
    bool current_model_ref = true;       // IM, encoder: eq. 20's reference from the current model at low speed
    double table_speed_rpm = 0.0;        // speed-dependent table: ST-D below, ST-A above; 0 = derived
    // Stator-flux vector control (scheme sfvc, Casadei secs. 10.3-10.5).
    double carrier_hz = PLANT_DEF_IM_CARRIER_HZ; // SVM carrier; the control period ts_s = 1 / carrier_hz
    Modulation modulation = Modulation::Symmetric; // dfoc with the key unset: two_phase (Casadei sec. 13)
    double sfvc_kp_per_s = 0.0;          // flux-regulator gain K_p (Casadei eq. 24); 0 = derived, 1 / (2 ts_s)
    double dfoc_bw_hz = 0.0;             // DFOC current-loop crossover, Hz; 0 = derived, 0.2 / (2 pi ts_s)
    double dfoc_zeta = 0.0;              // DFOC PI placement: 0 = zero on the stator pole; > 0 = poles at w_c, damping
    double dsvm_torque_band2_nm = 0.0;   // DSVM five-level torque comparator's outer band; 0 = derived
};

struct SensorsCfg {
    double current_range_a = PLANT_DEF_CURRENT_RANGE_A;
    std::array<double, 3> current_offset_a{};
    std::array<double, 3> current_gain_error{};
    double current_noise_a_rms = 0.0;
    double voltage_range_v = PLANT_DEF_VOLTAGE_RANGE_V;
    double vdc_offset_v = 0.0;
    double vdc_gain_error = 0.0;
    double vmid_offset_v = 0.0;
    double vmid_gain_error = 0.0;
    double voltage_noise_v_rms = 0.0;
    bool vmid_fitted = true;
    std::int64_t encoder_lines = PLANT_DEF_ENCODER_LINES;
    double encoder_offset_rad = 0.0;
    bool encoder_reversed = false;       // the count runs down for positive rotation (A and B swapped)
    FaultPhase current_reversed = FaultPhase::None; // that phase's current sensor mounted the wrong way round
    std::int64_t seed = 1;
    std::int64_t current_sensors = 2;    // 2: the firmware derives the third phase; 3: all measured
};

struct ProtectionCfg {
    double overcurrent_a = PLANT_DEF_OVERCURRENT_A;         // firmware trip on any phase current
    double vdc_min_v = PLANT_DEF_VDC_MIN_V;                 // firmware DC-link under-voltage trip
    double vdc_max_v = PLANT_DEF_VDC_MAX_V;                 // firmware DC-link over-voltage trip
    double hw_trip_current_a = PLANT_DEF_HW_TRIP_CURRENT_A; // hardware comparator (PDPINTA), in hal_host
    double overspeed_rpm = 0.0;     // firmware overspeed trip; 0 = derived (10 % above rated / limit), < 0 = off
    double stall_time_s = 0.0;      // firmware stall fault time; 0 = derived, max(0.1 s, 20 speed periods)
    bool allow_unsafe = false;    // accept trip settings that let the current exceed 3x rated
};

/// The firmware's own values of machine and inverter parameters (parameter mismatch without code
/// changes). Unset: the firmware is given the plant's value (motor.*, inverter.*).
struct FirmwareCfg {
    /// The firmware.* keys given, by converter member (rs_ohm, ls_h, ...: the belief rows of
    /// tools/config/dtc_si_params.h); a member not given takes the plant's value.
    std::map<std::string, double> value;
    /// The machine's sensors as the firmware believes them (dtc-sil identify writes them); unset:
    /// the plant's (motor.pole_pairs, sensors.encoder_offset_rad).
    std::optional<std::int64_t> pole_pairs;
    std::optional<double> encoder_offset_rad;
    std::optional<bool> encoder_reversed;     // unset: sensors.encoder_reversed
    std::optional<std::int64_t> encoder_lines; // the board data's line count; unset: sensors.encoder_lines
    /// The mechanics as identified (dtc-sil identify's spin step): the inertia the speed PI and the
    /// lost-encoder level derive from (unset: motor.j_kgm2); the friction is recorded (the
    /// firmware's configuration has no friction term).
    std::optional<double> j_kgm2;
    std::optional<double> b_nm_s_per_rad;
    std::optional<double> coulomb_nm;
};

/// Faults injected from faults.time_s on (docs/sil.md). Each is off by default.
struct FaultsCfg {
    double time_s = 0.0;                       // when every configured fault occurs
    FaultPhase leg_open = FaultPhase::None;    // leg disconnected from its phase
    FaultSwitch switch_open = FaultSwitch::None;  // device never conducts (its diode does)
    FaultSwitch switch_short = FaultSwitch::None; // device always conducts
    bool encoder_lost = false;                 // QEP count frozen, no index pulses
    FaultPhase current_sensor_stuck = FaultPhase::None; // that phase's ADC channel stuck at a code
    std::int64_t current_sensor_code = 2048;   // the stuck code (mid-scale: zero current)
    double dc_sag = 1.0;                       // DC source voltage becomes this fraction of inverter.vdc_v
    /// True if any fault is configured.
    bool any() const
    {
        return leg_open != FaultPhase::None || switch_open != FaultSwitch::None ||
               switch_short != FaultSwitch::None || encoder_lost || current_sensor_stuck != FaultPhase::None ||
               dc_sag != 1.0;
    }
};

struct MetricsCfg {
    double torque_sensor_hz = 0.0; // trf_filtered_pct: torque transducer bandwidth, 0 = unfiltered
};

/// The most samples the metrics window may hold (metrics_window_s / ts_s + 1): its series take
/// about 120 bytes a sample, so 2e7 samples (1000 s at 50 us) are 2.4 GB.
inline constexpr std::uint64_t kMaxWindowSamples = 20000000;

struct Scenario {
    std::string name;            // file stem
    std::string path;            // scenario file as given
    double duration_s = 0.5;
    double metrics_window_s = 0.2;
    double ts_s = PLANT_DEF_TS_S;             // control period
    double max_step_s = PLANT_DEF_MAX_STEP_S; // plant integration sub-step (RK4 on event-landing steps; docs/sil.md);
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
    FaultsCfg faults;
    MetricsCfg metrics;
    std::map<std::string, std::string> origin; // key -> "file:line:col" or "--set"
};

/// The dynamometer's held speed at time t (speed load): load.speed_rpm, or the ramp from
/// initial_speed_rpm when load.speed_ramp_s > 0.
double dyno_speed_rpm(const Scenario& sc, double t_s);

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

/// A TOML fragment applied over a scenario (dtc-sil --overlay FILE): its keys are scenario keys,
/// checked and reported (file:line:col) as the scenario's are, applied after the scenario's own
/// and before --set.
struct OverlayText {
    std::string path; // as given; names the overlay in messages and resolves its relative paths
    std::string text;
};
/// Reads an overlay file; false (and an error naming it) when it is not a readable regular file.
bool read_overlay(const std::string& path, OverlayText* out, Diagnostics* diag);

/// Loads a scenario file and applies "key=value" overrides. Returns false (and fills diag) when
/// the file cannot be read or parsed, a key is unknown, a type is wrong, a value is impossible or
/// required values are missing. Nothing is run or written by this function.
bool load_scenario(const std::string& path, const std::vector<std::string>& overrides, Scenario* out,
                   Diagnostics* diag, const std::vector<std::string>& overlay_paths = {});
/// Same, from TOML text (source_name is used in messages and to resolve relative paths).
bool parse_scenario(const std::string& toml_text, const std::string& source_name,
                    const std::vector<std::string>& overrides, Scenario* out, Diagnostics* diag,
                    const std::vector<OverlayText>& overlays = {});

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
