// scenario_checks.cpp - the checks of a whole scenario once its keys are read: the machine type's
// defaults and key ownership, the rules about the scenario, the plant and the harness, and the
// firmware configuration the scenario makes, refused by the converter's and the firmware's own
// checks (dtc_config_from_si_err) with the scenario key named.
#include "firmware_si.hpp"
#include "dtc_si_params.h"
#include "scenario_schema.hpp"
#include "sil_constants.hpp"

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "hal_host_pwm.hpp"
#include "plant_defaults.h"

namespace sil::detail {

// Machine-type defaults and key ownership: the motor.* defaults of the schema are the PM machine's;
// with motor.type = "im" every shared key left unset takes the default induction machine's value
// (ImDefaults), and a key of the other machine is refused by name.
void apply_machine_defaults(Scenario& s, Diagnostics* d)
{
    static const std::vector<std::string> pm_only = {"motor.ls_h",       "motor.ld_h",       "motor.lq_h",
                                                     "motor.psi_m_wb",   "motor.emf_gain",
                                                     "motor.emf_harm_a", "motor.emf_harm_b", "motor.emf_harm_c"};
    static const std::vector<std::string> im_only = {"motor.rr_ohm", "motor.lls_h", "motor.llr_h", "motor.lm_h"};
    const bool im = s.motor.type == MotorType::Im;
    for (const std::string& k : im ? pm_only : im_only) {
        if (s.origin.count(k) != 0) {
            d->errors.push_back(origin_of(s, k) + ": " + k + ": not a parameter of motor.type = \"" + to_string(s.motor.type) +
                                "\" (" + origin_of(s, "motor.type") + ")");
        }
    }
    if (s.origin.count("sensors.current_sensors") == 0 && s.inverter.reconfig_relay) {
        s.sensors.current_sensors = 3; // a board built for reconfiguration measures every phase
    }
    if (!im) {
        // A salient PM: motor.ld_h is motor.ls_h's other name (L_d); both given, they must agree.
        // motor.lq_h not given: L_q = L_d (a surface PM).
        if (s.origin.count("motor.ld_h") != 0) {
            if (s.origin.count("motor.ls_h") != 0 && s.motor.ld_h != s.motor.ls_h) {
                d->errors.push_back(origin_of(s, "motor.ld_h") + ": motor.ld_h: " + std::to_string(s.motor.ld_h) +
                                    " H differs from motor.ls_h = " + std::to_string(s.motor.ls_h) + " H (" +
                                    origin_of(s, "motor.ls_h") +
                                    "): motor.ls_h is a salient PM's L_d; give one of the two, or the same value");
            }
            s.motor.ls_h = s.motor.ld_h;
        }
        s.motor.ld_h = s.motor.ls_h;
        if (s.origin.count("motor.lq_h") == 0) {
            s.motor.lq_h = s.motor.ls_h;
        }
        return;
    }
    const ImDefaults q;
    auto unset = [&](const char* k) { return s.origin.count(k) == 0; };
    if (unset("motor.rs_ohm")) s.motor.rs_ohm = q.rs_ohm;
    if (unset("motor.rr_ohm")) s.motor.rr_ohm = q.rr_ohm;
    if (unset("motor.lls_h")) s.motor.lls_h = q.lls_h;
    if (unset("motor.llr_h")) s.motor.llr_h = q.llr_h;
    if (unset("motor.lm_h")) s.motor.lm_h = q.lm_h;
    if (unset("motor.pole_pairs")) s.motor.pole_pairs = q.pole_pairs;
    if (unset("motor.j_kgm2")) s.motor.j_kgm2 = q.j_kgm2;
    if (unset("motor.b_nm_s_per_rad")) s.motor.b_nm_s_per_rad = q.b_nm_s_per_rad;
    if (unset("motor.rated_torque_nm")) s.motor.rated_torque_nm = q.rated_torque_nm;
    if (unset("motor.rated_current_a")) s.motor.rated_current_a = q.rated_current_a;
    if (unset("motor.rated_speed_rpm")) s.motor.rated_speed_rpm = q.rated_speed_rpm;
    // The IM drive rig (plant_defaults.h), closed loop: Casadei's period, a rectified 220 V link,
    // sensing and protection sized for the 300 % torque steps.
    if (s.control.mode == ControlMode::OpenLoop) {
        return;
    }
    if (unset("ts_s")) {
        // the stator-flux vector control runs one control period per SVM carrier period
        s.ts_s = s.control.scheme == Scheme::Sfvc || s.control.scheme == Scheme::Dfoc ? 1.0 / s.control.carrier_hz
                                                                                          : PLANT_DEF_IM_TS_S;
    }
    if (unset("control.modulation") && s.control.scheme == Scheme::Dfoc) {
        s.control.modulation = Modulation::TwoPhase; // Casadei sec. 13's DFOC
    }
    if (unset("inverter.vdc_v")) s.inverter.vdc_v = PLANT_DEF_IM_VDC_V;
    if (unset("control.flux_ref_wb")) s.control.flux_ref_wb = PLANT_DEF_IM_FLUX_REF_WB;
    if (unset("control.torque_limit_nm")) s.control.torque_limit_nm = PLANT_DEF_IM_TORQUE_LIMIT_NM;
    if (unset("control.torque_ref_nm")) s.control.torque_ref_nm = PLANT_DEF_IM_RATED_TORQUE_NM;
    if (unset("control.estimator")) s.control.estimator = Estimator::Improved;
    if (unset("sensors.current_range_a")) s.sensors.current_range_a = PLANT_DEF_IM_CURRENT_RANGE_A;
    if (unset("sensors.voltage_range_v")) s.sensors.voltage_range_v = PLANT_DEF_IM_VOLTAGE_RANGE_V;
    if (unset("protection.overcurrent_a")) s.protection.overcurrent_a = PLANT_DEF_IM_OVERCURRENT_A;
    if (unset("protection.hw_trip_current_a")) s.protection.hw_trip_current_a = PLANT_DEF_IM_HW_TRIP_CURRENT_A;
    if (unset("protection.vdc_min_v")) s.protection.vdc_min_v = PLANT_DEF_IM_VDC_MIN_V;
    if (unset("protection.vdc_max_v")) s.protection.vdc_max_v = PLANT_DEF_IM_VDC_MAX_V;
}

// Keys of the IM law and of the PM law: set for the other machine they are refused by name.
void check_law_keys(const Scenario& s, Diagnostics* d)
{
    static const std::vector<std::string> im_law = {
        "control.carrier_hz", "control.modulation", "control.sfvc_kp_per_s", "control.dfoc_bw_hz", "control.dfoc_zeta",
        "control.dsvm_torque_band2_nm",
        "control.speed_sensor", "control.flux_weakening", "control.rotor_flux_ref_wb",
        "control.observer_tau_s", "control.observer_tau_high_s", "control.observer_tau_lo_rpm",
        "control.observer_tau_hi_rpm", "control.magnetise_frac", "control.table_speed_rpm", "control.rr_tracking",
        "control.current_model_ref",
        "firmware.rr_ohm", "firmware.lls_h", "firmware.llr_h", "firmware.lm_h"};
    static const std::vector<std::string> pm_law = {"firmware.ls_h", "firmware.lq_h", "firmware.psi_m_wb", "control.handover_rpm",
                                                    "control.handover_hyst_frac", "control.delay_comp"};
    const bool im = s.motor.type == MotorType::Im;
    for (const std::string& k : im ? pm_law : im_law) {
        if (s.origin.count(k) != 0) {
            d->errors.push_back(origin_of(s, k) + ": " + k + ": not a setting of the " +
                                (im ? "induction-machine" : "PM") + " drive (motor.type = \"" +
                                to_string(s.motor.type) + "\", " + origin_of(s, "motor.type") + ")");
        }
    }
}

// The [faults] table and the relay (inverter.reconfig_relay).
template <typename Err, typename Warn> void check_faults(const Scenario& s, Err err, Warn warn)
{
    const FaultsCfg& f = s.faults;
    if (s.inverter.reconfig_relay && s.inverter.topology != Topology::Sstp) {
        err("inverter.reconfig_relay", "the relay reconfigures the six-switch inverter \"sstp\"; got \"" +
                                           to_string(s.inverter.topology) + "\"");
    }
    if (s.inverter.reconfig_relay && s.control.implementation == Implementation::Firmware && s.sensors.current_sensors != 3) {
        err("inverter.reconfig_relay", "the firmware reconfigures only with sensors.current_sensors = 3 (with two "
                                       "sensors a sensor stuck at zero and an open phase read the same); got " +
                                           std::to_string(s.sensors.current_sensors));
    }
    if (!f.any()) {
        for (const char* k : {"faults.time_s", "faults.current_sensor_code"}) {
            if (s.origin.count(k) != 0) {
                warn(k, "no fault is configured: ignored");
            }
        }
        return;
    }
    if (f.current_sensor_stuck != FaultPhase::None && s.control.implementation == Implementation::Firmware &&
        s.sensors.current_sensors == 2) {
        const FaultPhase derived = s.inverter.topology == Topology::Fstp ? FaultPhase::A : FaultPhase::C;
        if (f.current_sensor_stuck == derived) {
            warn("faults.current_sensor_stuck", "phase " + to_string(derived) +
                                                    " has no sensor the firmware reads (two sensors: it derives that "
                                                    "phase from the other two): the fault changes nothing");
        }
    }
    if (s.origin.count("faults.time_s") == 0) {
        // named with the fault's own key and where it was set (a --set of a fault without its time)
        std::string by;
        for (const auto& o : s.origin) {
            if (by.empty() && o.first.rfind("faults.", 0) == 0 && o.first != "faults.current_sensor_code") {
                by = " (" + o.first + ", " + origin_of(s, o.first) + ")";
            }
        }
        err("faults.time_s", "missing value: required when a fault is configured" + by);
    } else if (f.time_s >= s.duration_s) {
        warn("faults.time_s", "at or after the end of the run (duration_s = " + fmt_double(s.duration_s) + " s)");
    }
    if (f.switch_open != FaultSwitch::None && f.switch_short != FaultSwitch::None) {
        err("faults.switch_short", "one switch fault at a time: faults.switch_open is \"" + to_string(f.switch_open) +
                                       "\" (" + origin_of(s, "faults.switch_open") + ")");
    }
    const bool inverter_fault = f.leg_open != FaultPhase::None || f.switch_open != FaultSwitch::None ||
                                f.switch_short != FaultSwitch::None;
    if (inverter_fault && s.inverter.topology == Topology::Ideal) {
        const char* k = f.leg_open != FaultPhase::None ? "faults.leg_open"
                        : f.switch_open != FaultSwitch::None ? "faults.switch_open" : "faults.switch_short";
        err(k, "the \"ideal\" inverter has no legs");
    }
    if (s.inverter.topology == Topology::Fstp) {
        if (f.leg_open == FaultPhase::A) {
            err("faults.leg_open", "the FSTP has no leg A (phase A is on the capacitor mid-point)");
        }
        for (auto [k, v] : {std::pair{"faults.switch_open", f.switch_open}, std::pair{"faults.switch_short", f.switch_short}}) {
            if (v == FaultSwitch::AUpper || v == FaultSwitch::ALower) {
                err(k, "the FSTP has no leg A (phase A is on the capacitor mid-point)");
            }
        }
    }
    if (f.dc_sag != 1.0 && s.inverter.topology == Topology::Ideal) {
        err("faults.dc_sag", "the \"ideal\" inverter has no DC link");
    }
}

// Of the scenario keys listed in keys (dtc_si_params.h), the first the scenario sets (only_first:
// the first listed, set or not), else the first that exists; "" when none does.
static std::string first_key_set(const Scenario& s, const std::string& keys, bool only_first = false)
{
    std::string key;
    std::string word;
    for (const char ch : keys + " ") {
        if ((ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '_' || ch == '.') {
            word += ch;
            continue;
        }
        if (find_spec(word) != nullptr &&
            (key.empty() || (!only_first && s.origin.count(key) == 0 && s.origin.count(word) != 0))) {
            key = word;
        }
        word.clear();
    }
    return key;
}

// The scenario key that sets converter member p: its firmware.* key when given (the firmware's
// own value, firmware_si_config), else the first of the row's keys the scenario sets (only_first:
// the first listed, the member's own key).
static std::string key_of_member(const Scenario& s, const dtc_si_param_t& p, bool only_first = false)
{
    if (p.belief != nullptr && s.firmware.value.count(p.name) != 0) {
        return std::string("firmware.") + p.name;
    }
    return first_key_set(s, p.keys, only_first);
}

// The firmware configuration the scenario makes (firmware_si_config, as the run hands it to the
// converter), refused by the converter's and the firmware's own checks, named by the scenario key
// that causes the refusal. A key causes it when its member (dtc_si_params.h), put back to the
// converter's default, lets the conversion pass or refuse another member. In this order: a key
// given with --set that causes it (the refused member's first); the refused member's own key when
// the scenario sets it (its value is the one refused); a key of the file that causes it; else the
// first of the refused member's keys the scenario sets.
void check_firmware_config(const Scenario& s, Diagnostics* d)
{
    const dtc_config_si_t si = firmware_si_config(s);
    dtc_config_t cfg;
    dtc_si_error_t e;
    if (dtc_config_from_si_err(&si, &cfg, &e) == DTC_SI_OK) {
        return;
    }
    const std::string keys = keys_of_refusal(e);
    std::string key = first_key_set(s, keys);
    std::string cause;
    dtc_config_si_t def;
    if (dtc_law_is_im(static_cast<uint16_t>(si.law)) != 0U) {
        dtc_config_si_im_defaults(&def);
    } else {
        dtc_config_si_defaults(&def);
    }
    auto causes = [&](const dtc_si_param_t& p) {
        const std::size_t n = p.type == DTC_SIP_DOUBLE ? sizeof(double) : p.type == DTC_SIP_INT3 ? 3 * sizeof(int) : sizeof(int);
        const char* at_def = reinterpret_cast<const char*>(&def) + p.offset;
        if (std::memcmp(reinterpret_cast<const char*>(&si) + p.offset, at_def, n) == 0) {
            return false;
        }
        dtc_config_si_t trial = si;
        std::memcpy(reinterpret_cast<char*>(&trial) + p.offset, at_def, n);
        dtc_config_t tcfg;
        dtc_si_error_t te;
        return dtc_config_from_si_err(&trial, &tcfg, &te) == DTC_SI_OK || std::strcmp(te.field, e.field) != 0;
    };
    // The first member (the refused one first) whose key the scenario sets from_set (--set or
    // not) and causes the refusal; "" when none.
    auto search = [&](bool from_set) {
        for (std::size_t pass = 0; pass < 2; ++pass) {
            for (std::size_t r = 0; r < dtc_si_param_count; ++r) {
                const dtc_si_param_t& p = dtc_si_params[r];
                const bool own = std::strcmp(p.name, e.field) == 0;
                const std::string k = key_of_member(s, p);
                const auto o = s.origin.find(k);
                if (own != (pass == 0) || o == s.origin.end() || (o->second.rfind("--set", 0) == 0) != from_set ||
                    !causes(p)) {
                    continue;
                }
                if (!own) {
                    cause = " (" + (keys.empty() ? std::string(e.field) : keys) + ": follows from " + k +
                            ", converter field " + p.name + ")";
                }
                return k;
            }
        }
        return std::string();
    };
    const dtc_si_param_t* refused = dtc_si_param_find(e.field);
    const std::string own_key = refused != nullptr ? key_of_member(s, *refused, true) : std::string();
    if (std::string k = search(true); !k.empty()) {
        key = k;
    } else if (!own_key.empty() && s.origin.count(own_key) != 0) {
        key = own_key;
    } else if (std::string kf = search(false); !kf.empty()) {
        key = kf;
    }
    const std::string what = std::string(e.msg) + cause + " (firmware configuration refused, " +
                             (e.field[0] != '\0' ? std::string("converter field ") + e.field + ", " : "") +
                             "error " + std::to_string(e.code) + ")";
    d->errors.push_back(key.empty() ? s.path + ": firmware configuration: " + what
                                    : origin_of(s, key) + ": " + key + ": " + what);
}

void cross_validate(Scenario& s, Diagnostics* d)
{
    auto err = [&](const std::string& key, const std::string& msg) {
        d->errors.push_back(origin_of(s, key) + ": " + key + ": " + msg);
    };
    auto warn = [&](const std::string& key, const std::string& msg) {
        d->warnings.push_back(origin_of(s, key) + ": " + key + ": " + msg);
    };
    // The wiring faults act on the board's signals, which only the firmware reads through the HAL.
    if (s.control.implementation != Implementation::Firmware) {
        for (const char* k : {"sensors.encoder_reversed", "sensors.current_reversed", "inverter.phases_swapped",
                              "firmware.encoder_reversed", "firmware.encoder_lines"}) {
            if (s.origin.count(k) != 0) {
                err(k, "needs control.implementation = \"firmware\" (the reference controller reads the plant's "
                       "wiring as it should be)");
            }
        }
    }
    if (s.inverter.phases_swapped && s.inverter.topology == Topology::Ideal) {
        err("inverter.phases_swapped", "the ideal inverter has no legs (inverter.topology = \"sstp\" or \"fstp\")");
    }
    if (s.metrics_window_s > s.duration_s) {
        err("metrics_window_s", "is " + fmt_double(s.metrics_window_s) + " s, longer than duration_s = " +
                                    fmt_double(s.duration_s) + " s");
    }
    if (s.origin.count("max_step_s") == 0 && s.max_step_s > s.ts_s) {
        s.max_step_s = s.ts_s; // the default follows a shorter control period
    }
    if (s.max_step_s > s.ts_s) {
        err("max_step_s", "must not exceed the control period ts_s = " + fmt_double(s.ts_s) + " s (" +
                              origin_of(s, "ts_s") + ")");
    }
    if (s.ts_s / s.max_step_s > 1.0e4) {
        err("max_step_s", "is " + fmt_double(s.max_step_s) + " s: more than 10000 sub-steps per control period "
                              "ts_s = " + fmt_double(s.ts_s) + " s (step-size floor: ts_s / 10000)");
    }
    if (s.duration_s / s.ts_s > 2.0e9) {
        err("duration_s", "more than 2e9 control periods");
    }
    if (std::llround(s.duration_s / s.ts_s) < 1) {
        err("duration_s", "is " + fmt_double(s.duration_s) + " s: shorter than one control period ts_s = " +
                              fmt_double(s.ts_s) + " s, nothing would be simulated");
    } else if (std::llround(s.metrics_window_s / s.ts_s) < 1) {
        err("metrics_window_s", "is " + fmt_double(s.metrics_window_s) +
                                    " s: shorter than one control period ts_s = " + fmt_double(s.ts_s) + " s");
    }
    const bool open_loop = s.control.mode == ControlMode::OpenLoop;
    const bool im = s.motor.type == MotorType::Im;
    // The PWM form's timer period (hal.h T1PR = ts_s f_clock / 2, hal_host::t1pr_counts) for the
    // laws that place edges within the period: whole counts, at least min_counts.
    auto check_t1pr = [&](const char* key, unsigned min_counts, const std::string& law) {
        if (hal_host::t1pr_counts(s.ts_s, PLANT_DEF_PWM_CLOCK_HZ) < min_counts) {
            err(key, "the PWM timer period 75 MHz ts_s / 2 = " + fmt_double(s.ts_s * PLANT_DEF_PWM_CLOCK_HZ * 0.5) +
                         " counts is not a whole number in " + std::to_string(min_counts) + "..65534 (hal.h T1PR; " +
                         law + ")");
        }
    };
    // The machine type, the law and the implementation that runs it; the values of the law's
    // part are the converter's to check (check_firmware_config).
    if (im && !open_loop) {
        if (s.control.implementation != Implementation::Firmware) {
            err("control.implementation", "\"" + to_string(s.control.implementation) + "\" has no induction-machine "
                "law: motor.type = \"im\" (" + origin_of(s, "motor.type") + ") runs on \"firmware\"");
        }
        if (s.control.scheme == Scheme::Itc) {
            err("control.scheme", "\"itc\" is the PM machine's indirect torque control; motor.type is \"im\"");
        }
        if (s.control.scheme == Scheme::Dsvm) {
            check_t1pr("ts_s", 3u, "dsvm's thirds, firmware/dtc/dsvm.h");
        }
        if (s.control.scheme == Scheme::Sfvc || s.control.scheme == Scheme::Dfoc) {
            // One SVM carrier period per control period (firmware/dtc/im_sfvc.c, hal.h).
            if (s.origin.count("control.carrier_hz") == 0) {
                s.control.carrier_hz = 1.0 / s.ts_s;
            }
            check_t1pr(s.origin.count("control.carrier_hz") != 0 ? "control.carrier_hz" : "ts_s", 1u,
                       "one SVM carrier period per control period");
        }
        if (s.control.observer_tau_high_s > 0.0 && s.control.observer_tau_hi_rpm <= 0.0) {
            err("control.observer_tau_hi_rpm", "a speed-dependent tau (control.observer_tau_high_s, " +
                                                   origin_of(s, "control.observer_tau_high_s") +
                                                   ") needs the speed from which it applies (> 0)");
        }
    } else if (!open_loop) {
        if (s.control.scheme != Scheme::Dtc && s.control.scheme != Scheme::Itc) {
            err("control.scheme", "\"" + to_string(s.control.scheme) + "\" is an induction-machine scheme; the PM "
                                  "machine takes \"dtc\" or \"itc\"");
        }
        if (s.control.scheme == Scheme::Itc) {
            if (s.control.implementation != Implementation::Firmware) {
                err("control.implementation", "\"" + to_string(s.control.implementation) + "\" has no indirect "
                    "torque control: control.scheme = \"itc\" (" + origin_of(s, "control.scheme") + ") runs on \"firmware\"");
            }
            check_t1pr("ts_s", 1u, "control.scheme = \"itc\", firmware/dtc/itc.h");
        }
    }
    const bool vf = s.control.vf_freq_hz > 0.0;
    if (open_loop && vf && !s.control.voltage_csv.empty()) {
        err("control.vf_freq_hz", "both the V/f source and control.voltage_csv are set: choose one");
    }
    if (open_loop && vf) {
        if (s.control.vf_v_per_hz <= 0.0 && s.control.vf_boost_v <= 0.0) {
            err("control.vf_v_per_hz", "the V/f source needs control.vf_v_per_hz > 0 (or a boost)");
        }
        if (s.inverter.topology != Topology::Ideal) {
            err("inverter.topology", "control.mode = \"open_loop\" applies alpha/beta voltages to the \"ideal\" "
                                     "inverter; got \"" + to_string(s.inverter.topology) + "\"");
        }
    }
    if (open_loop && !vf) {
        if (s.inverter.topology != Topology::Ideal) {
            err("inverter.topology", "control.mode = \"open_loop\" applies alpha/beta voltages to the \"ideal\" "
                                     "inverter; got \"" + to_string(s.inverter.topology) + "\"");
        }
        if (s.control.voltage_csv.empty()) {
            err("control.voltage_csv", "missing value: required when control.mode = \"open_loop\" (" +
                                           origin_of(s, "control.mode") + ")");
        } else {
            std::vector<VoltageRow> rows;
            std::string e;
            if (!load_voltage_csv(s.control.voltage_csv, &rows, &e)) {
                err("control.voltage_csv", e);
            }
        }
    } else if (!open_loop) {
        if (s.inverter.topology == Topology::Ideal) {
            err("inverter.topology", "the \"ideal\" inverter takes voltages, not switch states: use it with "
                                     "control.mode = \"open_loop\"");
        }
        if (s.control.estimator == Estimator::Current && s.control.compensation != Compensation::None) {
            warn("control.compensation", "ignored by the current-model estimator");
        }
        if (s.control.implementation == Implementation::Reference && s.inverter.topology == Topology::Sstp &&
            s.control.compensation == Compensation::Proposed) {
            err("control.compensation", "\"proposed\" on the SSTP (Hoang Table III per leg) is the firmware's only: "
                                        "the reference controller takes \"none\" or \"simple\" there");
        }
        if (s.inverter.topology == Topology::Fstp && s.control.table != SwitchingTable::Basic) {
            warn("control.table", "ignored: the FSTP always uses Hoang Table II");
        }
    }
    if (!open_loop && !s.protection.allow_unsafe && s.control.implementation == Implementation::Firmware &&
        s.protection.hw_trip_current_a == 0.0) {
        // Without the hardware comparator only the firmware can see an over-current, and it sees
        // it through the current sensors: a failed sensor must be found, by the current sum of
        // three sensors or by the plausibility against the law's prediction (the PM law with
        // the delay compensation, the PM indirect torque control, every IM law;
        // firmware/app/app_plaus.h, law.h law_i_pred), both with the fault detection on.
        const bool sum = s.sensors.current_sensors == 3;
        const bool pred = (s.motor.type == MotorType::Pmsm && (s.control.delay_comp || s.control.scheme == Scheme::Itc)) ||
                          s.motor.type == MotorType::Im;
        if (!s.control.fault_detect || !(sum || pred)) {
            err("protection.hw_trip_current_a",
                "0 (no hardware comparator) needs a firmware path that sees a failed current sensor: "
                "control.fault_detect = true with sensors.current_sensors = 3, the PM DTC with "
                "control.delay_comp = true, the PM ITC, or an IM law; otherwise a stuck sensor hides an over-current. Fit the "
                "comparator or set protection.allow_unsafe = true");
        }
    }
    if (!open_loop && !s.protection.allow_unsafe) {
        // The current the drive can carry before something trips: the firmware limit, or the
        // hardware comparator when it is fitted and lower.
        const bool hw_lower = s.protection.hw_trip_current_a > 0.0 &&
                              s.protection.hw_trip_current_a < s.protection.overcurrent_a;
        const double limit = hw_lower ? s.protection.hw_trip_current_a : s.protection.overcurrent_a;
        const double safe = 3.0 * s.motor.rated_current_a;
        if (limit > safe) {
            err(hw_lower ? "protection.hw_trip_current_a" : "protection.overcurrent_a",
                "lets the phase current reach " + fmt_double(limit) + " A before any trip, more than 3x "
                "motor.rated_current_a = " + fmt_double(safe) + " A (" + origin_of(s, "motor.rated_current_a") +
                "); lower it or set protection.allow_unsafe = true");
        }
    }
    if (!open_loop && (s.inverter.vdc_v <= s.protection.vdc_min_v || s.inverter.vdc_v >= s.protection.vdc_max_v)) {
        warn("inverter.vdc_v", "outside the protection window [vdc_min_v, vdc_max_v]: the firmware will trip");
    }
    if (s.inverter.vdc_v * (1.0 + s.sensors.vdc_gain_error) + s.sensors.vdc_offset_v >= s.sensors.voltage_range_v) {
        warn("sensors.voltage_range_v", "the DC-link voltage is at or above the divider's full scale; the ADC clamps");
    }
    if (!open_loop) {
        // The trips the firmware refuses because the ADC cannot see them (dtc_config.c
        // dtc_range_check): the largest current reading is 2047 counts from the mid-scale offset,
        // less the offset calibration's tolerance, at 2 range / 4095 per count; the link's is the
        // full scale. A trip fires above its level, so the level must stay below the reading.
        const double i_max = (2047.0 - kAdcOffsetTolCounts) * 2.0 * s.sensors.current_range_a /
                             PLANT_DEF_ADC_FULL_SCALE_CODES;
        if (s.protection.overcurrent_a >= i_max) {
            err("protection.overcurrent_a", "must be below " + fmt_double(i_max) +
                                                " A, the largest current the ADC reads with sensors.current_range_a = " +
                                                fmt_double(s.sensors.current_range_a) +
                                                " A (offset tolerance included): the trip could never fire");
        }
        if (s.protection.vdc_max_v >= s.sensors.voltage_range_v) {
            err("protection.vdc_max_v", "must be below the DC-link divider's full scale sensors.voltage_range_v = " +
                                            fmt_double(s.sensors.voltage_range_v) + " V: the trip could never fire");
        }
    }
    if (s.load.step_time_s > s.duration_s) {
        warn("load.step_time_s", "after the end of the run");
    }
    if (s.load.speed_ramp_s > 0.0 && s.load.type != LoadType::Speed) {
        err("load.speed_ramp_s", "needs load.type = \"speed\" (the dynamometer ramps the held speed)");
    }
    if (s.load.speed_ramp_start_s > 0.0 && !(s.load.speed_ramp_s > 0.0)) {
        err("load.speed_ramp_start_s", "needs load.speed_ramp_s > 0");
    }
    if (s.load.type == LoadType::Generator && s.load.speed_rpm == 0.0) {
        err("load.speed_rpm", "the generator load needs a non-zero reference speed");
    }
    if (s.load.type == LoadType::Fan && s.load.speed_rpm == 0.0) {
        err("load.speed_rpm", "the fan load needs a non-zero reference speed");
    }
    check_faults(s, err, warn);
    if (!open_loop) {
        check_firmware_config(s, d);
    }
}


// Numbers that become sizes: the metrics window is held in memory sample by sample.
void check_sizes(const Scenario& s, Diagnostics* d)
{
    const double window_n = std::floor(s.metrics_window_s / s.ts_s + 0.5) + 1.0;
    if (window_n > static_cast<double>(kMaxWindowSamples)) {
        d->errors.push_back(origin_of(s, "metrics_window_s") + ": metrics_window_s: is " +
                            fmt_double(s.metrics_window_s) + " s, " + fmt_double(window_n) +
                            " samples of ts_s = " + fmt_double(s.ts_s) + " s; the metrics window holds at most " +
                            std::to_string(kMaxWindowSamples) + " (" + fmt_double(kMaxWindowSamples * s.ts_s) +
                            " s): shorten it (the metrics need a few electrical periods)");
    }
}

} // namespace sil::detail
