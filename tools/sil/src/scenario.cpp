// scenario.cpp - schema-driven scenario parsing and validation (toml++), see scenario.hpp.
#include "scenario.hpp"
#include "toml_limits.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>

#include "hal_host_pwm.hpp"

namespace sil {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

enum class Kind { Number, Integer, Bool, String, Number3, Path };

struct Value {
    double num = 0.0;
    std::int64_t integer = 0;
    bool boolean = false;
    std::string str;
    std::array<double, 3> arr{};
};

struct Range {
    double lo = -kInf, hi = kInf;
    bool lo_open = false, hi_open = false;
    bool contains(double x) const
    {
        if (!std::isfinite(x)) {
            return false;
        }
        const bool lo_ok = lo_open ? x > lo : x >= lo;
        const bool hi_ok = hi_open ? x < hi : x <= hi;
        return lo_ok && hi_ok;
    }
    std::string text() const
    {
        std::ostringstream o;
        o.precision(6);
        if (lo == -kInf && hi == kInf) {
            return "any finite value";
        }
        if (hi == kInf) {
            o << (lo_open ? "> " : ">= ") << lo;
        } else if (lo == -kInf) {
            o << (hi_open ? "< " : "<= ") << hi;
        } else {
            o << (lo_open ? "(" : "[") << lo << ", " << hi << (hi_open ? ")" : "]");
        }
        return o.str();
    }
};
Range positive() { return Range{0.0, kInf, true, false}; }
Range nonneg() { return Range{0.0, kInf, false, false}; }
Range closed(double lo, double hi) { return Range{lo, hi, false, false}; }
Range any() { return Range{}; }

struct Spec {
    std::string name;
    Kind kind;
    std::string unit;
    std::string doc;
    Range range;
    std::vector<std::string> choices; // String only
    std::function<void(Scenario&, const Value&)> set;
    std::function<std::string(const Scenario&)> show;
};

std::string fmt_double(double x)
{
    std::ostringstream o;
    o.precision(6);
    o << x;
    return o.str();
}

using NumAcc = double& (*)(Scenario&);
using IntAcc = std::int64_t& (*)(Scenario&);
using BoolAcc = bool& (*)(Scenario&);
using StrAcc = std::string& (*)(Scenario&);
using ArrAcc = std::array<double, 3>& (*)(Scenario&);

Spec num(const char* name, const char* unit, Range r, const char* doc, NumAcc acc)
{
    return Spec{name, Kind::Number, unit, doc, r, {},
                [acc](Scenario& s, const Value& v) { acc(s) = v.num; },
                [acc](const Scenario& s) { return fmt_double(acc(const_cast<Scenario&>(s))); }};
}
using OptAcc = std::optional<double>& (*)(Scenario&);
// A number whose absence means "the plant's value" (the firmware.* keys).
Spec opt_num(const char* name, const char* unit, Range r, const char* doc, OptAcc acc)
{
    return Spec{name, Kind::Number, unit, doc, r, {},
                [acc](Scenario& s, const Value& v) { acc(s) = v.num; },
                [acc](const Scenario& s) {
                    const auto& x = acc(const_cast<Scenario&>(s));
                    return x ? fmt_double(*x) : std::string("the plant's");
                }};
}
Spec integer(const char* name, const char* unit, Range r, const char* doc, IntAcc acc)
{
    return Spec{name, Kind::Integer, unit, doc, r, {},
                [acc](Scenario& s, const Value& v) { acc(s) = v.integer; },
                [acc](const Scenario& s) { return std::to_string(acc(const_cast<Scenario&>(s))); }};
}
Spec boolean(const char* name, const char* doc, BoolAcc acc)
{
    return Spec{name, Kind::Bool, "", doc, any(), {},
                [acc](Scenario& s, const Value& v) { acc(s) = v.boolean; },
                [acc](const Scenario& s) { return std::string(acc(const_cast<Scenario&>(s)) ? "true" : "false"); }};
}
// A variant key: its text is checked against VariantNames<E> (check_value) and parsed into the
// enum once, here.
template <typename E> Spec choice(const char* name, const char* doc, E& (*acc)(Scenario&))
{
    std::vector<std::string> choices(VariantNames<E>::names.begin(), VariantNames<E>::names.end());
    return Spec{name, Kind::String, "", doc, any(), std::move(choices),
                [acc](Scenario& s, const Value& v) { parse_variant(v.str, &acc(s)); },
                [acc](const Scenario& s) { return "\"" + to_string(acc(const_cast<Scenario&>(s))) + "\""; }};
}
Spec path(const char* name, const char* doc, StrAcc acc)
{
    return Spec{name, Kind::Path, "", doc, any(), {},
                [acc](Scenario& s, const Value& v) { acc(s) = v.str; },
                [acc](const Scenario& s) {
                    const std::string& p = acc(const_cast<Scenario&>(s));
                    return p.empty() ? std::string("(none)") : "\"" + p + "\"";
                }};
}
Spec num3(const char* name, const char* unit, Range r, const char* doc, ArrAcc acc)
{
    return Spec{name, Kind::Number3, unit, doc, r, {},
                [acc](Scenario& s, const Value& v) { acc(s) = v.arr; },
                [acc](const Scenario& s) {
                    const auto& a = acc(const_cast<Scenario&>(s));
                    return "[" + fmt_double(a[0]) + ", " + fmt_double(a[1]) + ", " + fmt_double(a[2]) + "]";
                }};
}

#define ACC(field) [](Scenario& s) -> auto& { return s.field; }

const std::vector<Spec>& schema()
{
    static const std::vector<Spec> specs = {
        // ---- run ----
        num("duration_s", "s", positive(), "simulated time", ACC(duration_s)),
        num("metrics_window_s", "s", positive(),
            "metrics use the last metrics_window_s, trimmed to whole electrical periods", ACC(metrics_window_s)),
        num("ts_s", "s", closed(1e-6, 1e-3), "control period = one ISR = one plant advance (Hoang sec. IV: 50 us)",
            ACC(ts_s)),
        num("max_step_s", "s", closed(1e-8, 1e-3),
            "largest plant integration sub-step (<= ts_s, >= ts_s / 10000; not set: min(50 us, ts_s))",
            ACC(max_step_s)),
        num("initial_speed_rpm", "rpm", any(), "rotor speed at t = 0", ACC(initial_speed_rpm)),
        num("initial_theta_m_rad", "rad", any(), "mechanical rotor angle at t = 0", ACC(initial_theta_m_rad)),
        // ---- motor ----
        choice<MotorType>("motor.type",
               "pmsm = surface PM brushless AC machine (Hoang eqs. 6-10); im = squirrel-cage induction machine "
               "(Casadei eqs. A6-A10) driven open loop or by the IM law (Casadei DTC/DSC); with \"im\" the shared "
               "motor keys left unset take the default IM's values (Modelica Buildings IM_5HP_400V_50Hz at 220 V: "
               "rs_ohm 0.425, pole_pairs 2, j_kgm2 0.0131, b_nm_s_per_rad 0, rated 26.5 N*m, 19.2 A peak, "
               "1440 rpm) and these rig keys left unset the IM rig's (plant_defaults.h): ts_s 40 us, "
               "inverter.vdc_v 311 V, control.flux_ref_wb 0.55 Wb, control.torque_limit_nm and "
               "control.torque_ref_nm 300 % / 100 % rated, control.estimator \"improved\", sensors ranges "
               "100 A / 500 V, protection 55 A (hardware 57 A), DC-link window 200..400 V",
               ACC(motor.type)),
        num("motor.rs_ohm", "ohm", positive(), "phase resistance (Hoang Table VIII)", ACC(motor.rs_ohm)),
        num("motor.ls_h", "H", positive(), "synchronous inductance, Ld = Lq (Table VIII)", ACC(motor.ls_h)),
        num("motor.psi_m_wb", "Wb", positive(), "PM flux linkage, peak (Table VIII)", ACC(motor.psi_m_wb)),
        integer("motor.pole_pairs", "", closed(1, 16), "pole pairs (Table VIII; the firmware converter's range)", ACC(motor.pole_pairs)),
        num("motor.j_kgm2", "kg*m^2", positive(),
            "rotor + coupled load inertia (not in the paper: small servo motor with a DC generator)", ACC(motor.j_kgm2)),
        num("motor.b_nm_s_per_rad", "N*m*s/rad", nonneg(),
            "viscous friction; default gives 0.075 N*m at 1500 rpm = Hoang's inertial load (25 % of 0.3 N*m)",
            ACC(motor.b_nm_s_per_rad)),
        num3("motor.emf_gain", "", closed(0.5, 1.5), "per-phase back-EMF scale [A, B, C] (Table VII: measured)",
             ACC(motor.emf_gain)),
        num3("motor.emf_harm_a", "", closed(-0.5, 0.5), "phase A back-EMF 3rd, 5th, 7th / fundamental",
             ACC(motor.emf_harm_a)),
        num3("motor.emf_harm_b", "", closed(-0.5, 0.5), "phase B back-EMF 3rd, 5th, 7th / fundamental",
             ACC(motor.emf_harm_b)),
        num3("motor.emf_harm_c", "", closed(-0.5, 0.5), "phase C back-EMF 3rd, 5th, 7th / fundamental",
             ACC(motor.emf_harm_c)),
        num("motor.rated_torque_nm", "N*m", positive(), "rated torque, the T_rated of TRF (Hoang eq. 40)",
            ACC(motor.rated_torque_nm)),
        num("motor.rated_current_a", "A", positive(), "rated current, peak (Table VIII)", ACC(motor.rated_current_a)),
        num("motor.rated_speed_rpm", "rpm", positive(), "rated speed (Table VIII)", ACC(motor.rated_speed_rpm)),
        num("motor.rr_ohm", "ohm", positive(),
            "im: rotor resistance, stator-referred T model (Modelica Buildings IM_5HP_400V_50Hz x (220/400)^2)",
            ACC(motor.rr_ohm)),
        num("motor.lls_h", "H", nonneg(), "im: stator leakage inductance (same source)", ACC(motor.lls_h)),
        num("motor.llr_h", "H", nonneg(), "im: rotor leakage inductance, stator-referred (same source)",
            ACC(motor.llr_h)),
        num("motor.lm_h", "H", positive(), "im: magnetising inductance (same source)", ACC(motor.lm_h)),
        // ---- inverter ----
        choice<Topology>("inverter.topology",
               "ideal = alpha/beta voltage source (open loop only); sstp = six switches; fstp = four switches, "
               "phase A on the DC-link mid-point (Hoang Fig. 1)",
               ACC(inverter.topology)),
        num("inverter.vdc_v", "V", positive(), "DC source voltage (Table VIII: 70 V)", ACC(inverter.vdc_v)),
        num("inverter.v_ce_v", "V", nonneg(), "transistor forward drop (Table IV)", ACC(inverter.v_ce_v)),
        num("inverter.v_d_v", "V", nonneg(), "diode forward drop (Table IV)", ACC(inverter.v_d_v)),
        num("inverter.r_on_ohm", "ohm", nonneg(), "on-state resistance (Table IV)", ACC(inverter.r_on_ohm)),
        num("inverter.dead_time_s", "s", closed(0.0, 10e-6), "dead time per leg transition (not in the paper)",
            ACC(inverter.dead_time_s)),
        num("inverter.c_dc_f", "F", positive(), "each DC-link capacitor (FSTP: two in series)", ACC(inverter.c_dc_f)),
        num("inverter.r_dc_ohm", "ohm", nonneg(), "DC source internal resistance", ACC(inverter.r_dc_ohm)),
        num("inverter.r_bal_ohm", "ohm", nonneg(),
            "balancing resistor across each DC-link capacitor (SSTP: across its one capacitor), finite link "
            "only; 0 = not fitted (docs/plant.md: 3.3 kohm for 2 x 4.7 mF on a 70 V split link)",
            ACC(inverter.r_bal_ohm)),
        num("inverter.esr_ohm", "ohm", nonneg(),
            "equivalent series resistance of each DC-link capacitor, finite link only; 0 = ideal "
            "(docs/plant.md: 25 mohm for a 4.7 mF / 63 V electrolytic)",
            ACC(inverter.esr_ohm)),
        boolean("inverter.drops", "device forward drops and R_on (false: ideal devices)", ACC(inverter.drops)),
        boolean("inverter.dead_time", "dead time modelled", ACC(inverter.dead_time)),
        boolean("inverter.finite_dc_link", "capacitor voltages move (false: stiff DC link)",
                ACC(inverter.finite_dc_link)),
        boolean("inverter.reconfig_relay",
                "sstp: a relay per phase ties that phase to the DC link's capacitor mid-point (the four-switch "
                "topology after a leg failure, Hoang sec. I ref. [9]); the link is then two inverter.c_dc_f in "
                "series with the mid-point brought out (the FSTP's), and the mid-point sensor is read",
                ACC(inverter.reconfig_relay)),
        num("inverter.relay_delay_s", "s", closed(0.0, 1.0),
            "relay contact delay after a coil command, closing and opening (default: the operate time of a PCB "
            "power relay, Omron G2RG datasheet, 15 ms max.)",
            ACC(inverter.relay_delay_s)),
        // ---- load ----
        choice<LoadType>("load.type",
               "speed = dynamometer holds load.speed_rpm; torque = constant load.torque_nm; generator = "
               "load.torque_nm * speed / load.speed_rpm (DC generator, Hoang sec. IV); inertia = J and B only; "
               "fan = load.torque_nm * (speed / load.speed_rpm)^2, opposing the motion (fan or pump)",
               ACC(load.type)),
        num("load.speed_rpm", "rpm", any(), "held speed (speed load) or the speed where the generator gives "
            "load.torque_nm", ACC(load.speed_rpm)),
        num("load.torque_nm", "N*m", any(), "load torque (torque, generator loads)", ACC(load.torque_nm)),
        num("load.step_time_s", "s", nonneg(), "time of a load-torque step (0 = none)", ACC(load.step_time_s)),
        num("load.step_torque_nm", "N*m", any(), "load.torque_nm after the step", ACC(load.step_torque_nm)),
        num("load.speed_ramp_start_s", "s", nonneg(),
            "speed load with load.speed_ramp_s > 0: the dynamometer holds initial_speed_rpm until this time",
            ACC(load.speed_ramp_start_s)),
        num("load.speed_ramp_s", "s", nonneg(),
            "speed load: the dynamometer ramps linearly from initial_speed_rpm to load.speed_rpm over this time, "
            "from load.speed_ramp_start_s (a drive started at standstill, then taken to the test speed); 0 = "
            "load.speed_rpm held from t = 0", ACC(load.speed_ramp_s)),
        num("load.coulomb_nm", "N*m", nonneg(),
            "Coulomb (dry) friction of the shaft and coupled load (DC generator brushes and bearings, "
            "Hoang sec. IV rig), opposes the motion and holds a stopped rotor while the other torques sum to no more; 0 = none",
            ACC(load.coulomb_nm)),
        // ---- control ----
        choice<ControlMode>("control.mode",
               "speed = speed PI -> torque reference; torque = fixed torque reference; open_loop = "
               "control.voltage_csv on the ideal inverter, no firmware",
               ACC(control.mode)),
        choice<Implementation>("control.implementation",
               "firmware = the fixed-point firmware through hal_host; reference = the double-precision "
               "reference controller of model/",
               ACC(control.implementation)),
        choice<Estimator>("control.estimator",
               "stator-flux estimator: current model (PM only, Hoang eqs. 8-9), voltage model (Hoang eqs. 15-16 / "
               "Casadei eq. 1, with LPF) or improved (IM only, Casadei eqs. 20-22, tau = control.observer_tau_s); "
               "motor.type = \"im\" not given: improved",
               ACC(control.estimator)),
        choice<Compensation>("control.compensation",
               "voltage-model drop compensation: simple = Hoang Table V (FSTP) / ref. [29] (SSTP); "
               "proposed = Table VI + eqs. 37-38 (FSTP only)",
               ACC(control.compensation)),
        choice<SwitchingTable>("control.table",
               "SSTP switching table (Casadei Tables 1, 3); speed-dependent = Casadei sec. 8, ST-D below "
               "control.table_speed_rpm and ST-A above (IM only); the FSTP always uses Hoang Table II",
               ACC(control.table)),
        choice<Scheme>("control.scheme",
               "control law. PM machine: dtc = Hoang's switching-table DTC; itc = indirect torque control, the "
               "current-controlled drive Hoang et al. set beside DTC (Figs. 5-8 (a)): rotor-frame PI current "
               "regulators (i_d* = 0, i_q* from the speed loop, gains derived from the machine) and SVM of the "
               "six- or four-switch inverter at one carrier period per control period ts_s, the configured "
               "estimator running as an observer (firmware/dtc/itc.h). IM machine: dtc = switching table (Casadei secs. 4-8); dsc = Direct Self Control, hexagonal flux "
               "locus (sec. 9); sfvc = stator-flux vector control with SVM at the constant switching frequency "
               "control.carrier_hz (secs. 10.3-10.5, Fig. 18, eqs. 18, 23, 24); dfoc = direct rotor-flux-oriented control, PI current "
               "regulators in the rotor-flux frame, SVM at control.carrier_hz (sec. 13, the baseline); dsvm = DTC with "
               "discrete space vector modulation, three equal sub-intervals per control period ts_s, switching tables "
               "derived from sec. 8 (sec. 11, firmware/dtc/dsvm.h); sfvc and dfoc need control.rotor_flux_ref_wb > 0",
               ACC(control.scheme)),
        num("control.carrier_hz", "Hz", positive(),
            "IM sfvc, dfoc: SVM carrier frequency; one PWM period per control period, so ts_s = 1 / carrier_hz (ts_s not "
            "given: set from it; both given: must agree); 75 MHz / (2 carrier_hz) must be a whole number of timer "
            "counts (hal.h T1PR); default: Casadei sec. 13's 160 us cycle",
            ACC(control.carrier_hz)),
        choice<Modulation>("control.modulation",
               "IM sfvc, dfoc: symmetric = seven-segment SVM, centred pulses, min-max zero-sequence injection (mean "
               "switching frequency = the carrier); two_phase = discontinuous, the leg of the largest phase voltage "
               "clamped for 60 deg (2/3 of the carrier) (firmware/dtc/svm.h); not given: symmetric for sfvc, two_phase for "
               "dfoc (Casadei sec. 13)",
               ACC(control.modulation)),
        num("control.sfvc_kp_per_s", "1/s", nonneg(),
            "IM sfvc: flux-regulator gain K_p of Casadei eq. 24, at most 1/ts_s (deadbeat); 0 = derived, "
            "1 / (2 ts_s)",
            ACC(control.sfvc_kp_per_s)),
        num("control.dfoc_bw_hz", "Hz", nonneg(),
            "IM dfoc: crossover of the rotor-flux-frame current PIs (K_p = sigma L_s w_c, K_i = R_s w_c, the zero on "
            "the stator transient pole), below 1 / (6 ts_s) where the loop's 1.5 ts_s delay leaves no phase margin; "
            "0 = derived, w_c = 0.2 / ts_s (199 Hz at 160 us: no overshoot)",
            ACC(control.dfoc_bw_hz)),
        num("control.dfoc_zeta", "", nonneg(),
            "IM dfoc: placement of the current PIs; 0 = the zero on the stator transient pole (first-order loops, no "
            "overshoot); > 0 = both closed-loop poles at w_c with this damping, K_p = 2 zeta w_c sigma L_s - R_s, K_i = "
            "sigma L_s w_c^2 (the PI's zero near w_c: the step overshoots), at most 10",
            ACC(control.dfoc_zeta)),
        num("control.dsvm_torque_band2_nm", "N*m", nonneg(),
            "IM dsvm: outer band (full width) of the five-level torque comparator: beyond +-band2/2 the tables' "
            "levels +-2, between +-control.torque_band_nm/2 and +-band2/2 the levels +-1; at least "
            "control.torque_band_nm; 0 = derived: twice the torque a whole active vector changes in one period "
            "at standstill, (3/2) p M / (sigma L_s L_r) (2/3 V_dc) |phi_r| ts_s (Casadei eqs. 12, 15), at least "
            "control.torque_band_nm",
            ACC(control.dsvm_torque_band2_nm)),
        choice<SpeedSensor>("control.speed_sensor",
               "IM only: encoder = speed from the encoder; none = sensorless, the stator-flux angular speed minus "
               "the slip of Casadei eq. 16",
               ACC(control.speed_sensor)),
        boolean("control.flux_weakening",
                "IM only: Casadei sec. 12 flux weakening (null-vector monitor on the torque comparator, T* scaled by eq. 33 and limited by "
                "eq. 34)",
                ACC(control.flux_weakening)),
        num("control.rotor_flux_ref_wb", "Wb", nonneg(),
            "IM only: > 0 = constant rotor flux, the stator-flux reference follows T* by Casadei eq. 19; 0 = "
            "the stator-flux reference control.flux_ref_wb",
            ACC(control.rotor_flux_ref_wb)),
        num("control.observer_tau_s", "s", positive(),
            "IM improved estimator (Casadei eq. 20): time constant tau at low speed, or fixed (sec. 10.2, Fig. 17: "
            "0.01 s); must exceed ts_s",
            ACC(control.observer_tau_s)),
        num("control.observer_tau_high_s", "s", nonneg(),
            "IM improved estimator: tau at high speed (sec. 10.2, speed-dependent tau, linear between "
            "control.observer_tau_lo_rpm and control.observer_tau_hi_rpm); 0 = control.observer_tau_s (fixed tau)",
            ACC(control.observer_tau_high_s)),
        num("control.observer_tau_lo_rpm", "rpm", nonneg(), "IM improved estimator: speed magnitude up to which "
            "control.observer_tau_s applies", ACC(control.observer_tau_lo_rpm)),
        num("control.observer_tau_hi_rpm", "rpm", nonneg(), "IM improved estimator: speed magnitude from which "
            "control.observer_tau_high_s applies (>= control.observer_tau_lo_rpm)", ACC(control.observer_tau_hi_rpm)),
        num("control.magnetise_frac", "", Range{0.0, 1.0, true, true},
            "IM start-up (Casadei Fig. 17b): zero torque during the stator-flux ramp (magnetising current below "
            "motor.rated_current_a) and until the rotor flux has reached this fraction of its reference, "
            "tau_r ln(1/(1 - frac)) more",
            ACC(control.magnetise_frac)),
        num("control.table_speed_rpm", "rpm", nonneg(),
            "IM speed-dependent table: ST-D below, ST-A above; 0 = derived (half the speed where the back-EMF "
            "reaches V_dc/sqrt(3))",
            ACC(control.table_speed_rpm)),
        num("control.speed_ref_rpm", "rpm", any(), "speed reference (speed mode)", ACC(control.speed_ref_rpm)),
        num("control.speed_bw_hz", "Hz", positive(),
            "speed-loop bandwidth; PI gains derived from motor.j_kgm2 (Kp = J*wc, Ki = Kp*wc/4)",
            ACC(control.speed_bw_hz)),
        integer("control.speed_loop_divider", "", closed(1, 1000),
                "speed loop runs every N-th ISR (Hoang sec. IV: 10)", ACC(control.speed_loop_divider)),
        num("control.torque_limit_nm", "N*m", positive(), "speed-PI output limit", ACC(control.torque_limit_nm)),
        num("control.torque_ref_nm", "N*m", any(), "torque reference (torque mode)", ACC(control.torque_ref_nm)),
        num("control.flux_ref_wb", "Wb", positive(), "stator flux reference (Hoang sec. IV: psi_m)",
            ACC(control.flux_ref_wb)),
        num("control.torque_band_nm", "N*m", nonneg(), "torque hysteresis band (Hoang sec. IV: 0)",
            ACC(control.torque_band_nm)),
        num("control.flux_band_wb", "Wb", nonneg(), "flux hysteresis band (Hoang sec. IV: 0)",
            ACC(control.flux_band_wb)),
        num("control.lpf_cutoff_rad_s", "rad/s", positive(),
            "voltage-model low-pass cutoff in place of the integrator (Hoang sec. IV: 5 rad/s)",
            ACC(control.lpf_cutoff_rad_s)),
        Spec{"control.handover_rpm", Kind::Number, "rpm", "voltage model: start on the current model (encoder, "
             "Hoang eqs. 8-9) and hand over to the voltage model above this speed, bumplessly; 0 = voltage "
             "model from standstill; not given = derived from the machine, the devices and the compensation "
             "(tools/config dtc_handover_default_rpm; Table VIII: 477 rpm compensated, 941 / 1441 rpm "
             "uncompensated on the FSTP / SSTP)", nonneg(), {},
             [](Scenario& s, const Value& v) { s.control.handover_rpm = v.num; s.control.handover_given = true; },
             [](const Scenario& s) {
                 return s.control.handover_given ? fmt_double(s.control.handover_rpm) : std::string("derived");
             }},
        num("control.handover_hyst_frac", "", closed(0.0, 1.0),
            "back to the current model below (1 - frac) * control.handover_rpm", ACC(control.handover_hyst_frac)),
        boolean("control.delay_comp",
                 "firmware: actuation-delay compensation, the comparators and the sector work on the flux and "
                 "torque predicted for the period the chosen vector acts in (false: on the estimate)",
                 ACC(control.delay_comp)),
        boolean("control.deadtime_comp",
                 "firmware: compensate the dead time (inverter.dead_time_s, the gate driver's setting) in the "
                 "voltage reconstruction (Casadei sec. 10.5)",
                 ACC(control.deadtime_comp)),
        Spec{"control.current_limit_a", Kind::Number, "A", "firmware current limit below the over-current trip: "
             "when the current predicted for the next period exceeds it, the vector that reduces |i| fastest "
             "replaces the table's (firmware/dtc/ilim.h); 0 = off; not given = derived from the trip level and "
             "the machine (tools/config dtc_ilim_default_a: protection.overcurrent_a minus one period's largest "
             "current change, two without control.delay_comp; 4.87 A for Table VIII, FSTP, 6 A trip; 0 when the trip "
             "level leaves no room for that change; the induction machine: its transient inductance, 45 A for the "
             "4 kW IM's table laws at 40 us, 55 A trip, and the IM laws' torque limit is held at the torque this "
             "current allows, tools/config dtc_im_torque_at_current_nm)",
             nonneg(), {},
             [](Scenario& s, const Value& v) { s.control.current_limit_a = v.num; s.control.current_limit_given = true; },
             [](const Scenario& s) {
                 return s.control.current_limit_given ? fmt_double(s.control.current_limit_a) : std::string("derived");
             }},
        boolean("control.polarity_mid",
                 "firmware: the drop compensation of a period takes the current polarity from the period's mean "
                 "current (previous and present sample) and the dead-time compensation from the current at the "
                 "switching instant (the previous sample); false: both from the present sample",
                 ACC(control.polarity_mid)),
        boolean("control.lpf_comp",
                 "firmware, voltage model: undo the low-pass's gain and phase lead at the measured speed by "
                 "filtering (1 - j w_c/w)(v - r_s i) instead of v - r_s i, |w| floored at 2 w_c: the estimate "
                 "is then the flux at every speed and through speed changes (firmware/dtc/lpfcorr.h); false: "
                 "the plain low-pass",
                 ACC(control.lpf_comp)),
        boolean("control.dc_supp",
                 "firmware, voltage model: DC-current suppression, the estimate is shifted by the integral of "
                 "(|w|/20) l_s i until the stator currents carry no DC (a DC flux error of the estimate is a DC current "
                 "in the machine and, on the FSTP, a mid-point drift; firmware/dtc/dtc.c dtc_dcsupp); false: off",
                 ACC(control.dc_supp)),
        boolean("control.vmid_cal",
                 "firmware, FSTP with the mid-point measured (sensors.vmid_fitted): during the "
                 "calibration (gates off, or the rotor hold: control.cal_hold) the app takes the mean of (mid-point - V_dc/2), which the balancing resistors make "
                 "zero, as the two voltage sensors' inconsistency and subtracts it from every mid-point sample "
                 "(firmware/app/app_core.c); false: the mid-point as measured",
                 ACC(control.vmid_cal)),
        boolean("control.cal_hold",
                 "firmware, PM law, with control.vmid_cal: after the 3.2 ms gates-off current-offset calibration "
                 "the app holds the rotor at its position with a current in phases B and C only (none through the "
                 "mid-point) for the rest of the mid-point calibration, so an active load cannot turn it back "
                 "before the drive starts (firmware/app/app_hold.c app_hold_step); false: the gates stay off for the "
                 "whole calibration",
                 ACC(control.cal_hold)),
        boolean("control.fault_detect",
                 "firmware: the open-phase check (a phase inside a zero band of a quarter of a quarter of "
                 "motor.rated_current_a over 60 deg of electrical angle while |i| is above a quarter of it: an open "
                 "leg, phase or device) and the lost-encoder check (the count still for 32 periods above a speed "
                 "derived from the encoder, control.torque_limit_nm and motor.j_kgm2); firmware/app/app_fault.c, app_enc.c",
                 ACC(control.fault_detect)),
        num("control.v_f_v", "V", nonneg(), "forward drop V_f of the simple compensation (Hoang sec. III-B: 0.9 V)",
            ACC(control.v_f_v)),
        path("control.voltage_csv",
             "open_loop: CSV with header t_s,v_alpha_v,v_beta_v, held per period (path relative to the "
             "scenario file)",
             ACC(control.voltage_csv)),
        num("control.vf_freq_hz", "Hz", nonneg(),
            "open_loop without voltage_csv: built-in V/f source, final stator frequency (0 = not used)",
            ACC(control.vf_freq_hz)),
        num("control.vf_v_per_hz", "V/Hz", nonneg(),
            "V/f source: voltage-vector amplitude (peak phase volts) per Hz (220 V, 50 Hz: 3.592)",
            ACC(control.vf_v_per_hz)),
        num("control.vf_boost_v", "V", nonneg(), "V/f source: amplitude at 0 Hz (low-frequency boost)",
            ACC(control.vf_boost_v)),
        num("control.vf_ramp_s", "s", nonneg(), "V/f source: frequency ramp time from 0 to vf_freq_hz (0 = step)",
            ACC(control.vf_ramp_s)),
        // ---- sensors ----
        num("sensors.current_range_a", "A", positive(), "Hall sensor: +-range maps onto the 0..3 V ADC input",
            ACC(sensors.current_range_a)),
        num3("sensors.current_offset_a", "A", closed(-1e3, 1e3), "current sensor offsets [A, B, C]",
             ACC(sensors.current_offset_a)),
        num3("sensors.current_gain_error", "", closed(-0.5, 0.5), "relative gain errors [A, B, C] (0.01 = +1 %)",
             ACC(sensors.current_gain_error)),
        num("sensors.current_noise_a_rms", "A", nonneg(), "white Gaussian noise per sample",
            ACC(sensors.current_noise_a_rms)),
        num("sensors.voltage_range_v", "V", positive(), "divider: 0..range maps onto 0..3 V",
            ACC(sensors.voltage_range_v)),
        num("sensors.vdc_offset_v", "V", closed(-1e3, 1e3), "DC-link sensor offset", ACC(sensors.vdc_offset_v)),
        num("sensors.vdc_gain_error", "", closed(-0.5, 0.5), "DC-link sensor relative gain error",
            ACC(sensors.vdc_gain_error)),
        num("sensors.vmid_offset_v", "V", closed(-1e3, 1e3), "mid-point sensor offset", ACC(sensors.vmid_offset_v)),
        num("sensors.vmid_gain_error", "", closed(-0.5, 0.5), "mid-point sensor relative gain error",
            ACC(sensors.vmid_gain_error)),
        num("sensors.voltage_noise_v_rms", "V", nonneg(), "white Gaussian noise on both voltage channels",
            ACC(sensors.voltage_noise_v_rms)),
        boolean("sensors.vmid_fitted", "mid-point voltage sensor fitted, FSTP or SSTP with inverter.reconfig_relay (false: channel reads 0)",
                ACC(sensors.vmid_fitted)),
        integer("sensors.encoder_lines", "", closed(1, 16383), "encoder lines; 4x quadrature counts (Fig. 9(b))",
                ACC(sensors.encoder_lines)),
        num("sensors.encoder_offset_rad", "rad", any(), "mechanical angle offset of the encoder index",
            ACC(sensors.encoder_offset_rad)),
        integer("sensors.seed", "", closed(0, 9.0e18), "noise generator seed (same seed, same run)",
                ACC(sensors.seed)),
        integer("sensors.current_sensors", "", closed(2, 3),
                "phase-current sensors the firmware reads: 2 (SSTP A and B, FSTP B and C; the third phase "
                "derived) or 3 (all measured: the firmware checks their sum, which tells a failed sensor from an "
                "open phase; needed by inverter.reconfig_relay). Default 2, 3 with inverter.reconfig_relay",
                ACC(sensors.current_sensors)),
        // ---- protection ----
        num("protection.overcurrent_a", "A", positive(), "firmware phase over-current trip",
            ACC(protection.overcurrent_a)),
        num("protection.vdc_min_v", "V", nonneg(), "firmware DC-link under-voltage trip", ACC(protection.vdc_min_v)),
        num("protection.vdc_max_v", "V", positive(), "firmware DC-link over-voltage trip", ACC(protection.vdc_max_v)),
        num("protection.stall_time_s", "s", nonneg(),
            "firmware stall fault (speed mode): the torque reference at its limit while the speed error does "
            "not shrink for this long (at least 20 speed-loop periods); 0 = max(0.1 s, 20 speed-loop periods)",
            ACC(protection.stall_time_s)),
        num("protection.overspeed_rpm", "rpm", any(),
            "firmware overspeed trip on the measured speed (either direction), above control.speed_limit_rpm; "
            "0 = derived: 10 % above the larger of motor.rated_speed_rpm and control.speed_limit_rpm "
            "(tools/config dtc_overspeed_default_rpm; 3300 rpm for Table VIII); negative = off",
            ACC(protection.overspeed_rpm)),
        num("protection.hw_trip_current_a", "A", nonneg(),
            "hardware comparator on each phase-current magnitude (PDPINTA), latching, gates off; 0 = not fitted",
            ACC(protection.hw_trip_current_a)),
        // ---- metrics ----
        // ---- firmware: its own parameter values (mismatch studies); unset = the plant's ----
        opt_num("firmware.rs_ohm", "ohm", positive(),
                "stator resistance the firmware uses (PM: voltage model, prediction; IM: both estimators); not "
                "given: motor.rs_ohm",
                ACC(firmware.rs_ohm)),
        opt_num("firmware.rr_ohm", "ohm", positive(),
                "IM: rotor resistance the firmware uses (the slip of Casadei eq. 16: sensorless speed, SFVC; the "
                "start-up's rotor time constant); not given: motor.rr_ohm",
                ACC(firmware.rr_ohm)),
        opt_num("firmware.lls_h", "H", positive(), "IM: stator leakage inductance the firmware uses; not given: "
                "motor.lls_h", ACC(firmware.lls_h)),
        opt_num("firmware.llr_h", "H", positive(), "IM: rotor leakage inductance the firmware uses; not given: "
                "motor.llr_h", ACC(firmware.llr_h)),
        opt_num("firmware.lm_h", "H", positive(), "IM: magnetising inductance the firmware uses; not given: "
                "motor.lm_h", ACC(firmware.lm_h)),
        opt_num("firmware.ls_h", "H", positive(),
                "inductance the firmware uses (current model, prediction); not given: motor.ls_h", ACC(firmware.ls_h)),
        opt_num("firmware.psi_m_wb", "Wb", positive(),
                "PM flux linkage the firmware uses (current model, hand-over); not given: motor.psi_m_wb",
                ACC(firmware.psi_m_wb)),
        opt_num("firmware.v_ce_v", "V", nonneg(), "transistor drop the compensation assumes; not given: inverter.v_ce_v",
                ACC(firmware.v_ce_v)),
        opt_num("firmware.v_d_v", "V", nonneg(), "diode drop the compensation assumes; not given: inverter.v_d_v",
                ACC(firmware.v_d_v)),
        opt_num("firmware.r_on_ohm", "ohm", nonneg(),
                "on-state resistance the compensation assumes; not given: inverter.r_on_ohm", ACC(firmware.r_on_ohm)),
        opt_num("firmware.dead_time_s", "s", closed(0.0, 1e-5),
                "dead time the dead-time compensation assumes; not given: inverter.dead_time_s",
                ACC(firmware.dead_time_s)),
        // ---- firmware: the machine's sensors as the firmware believes them (dtc-sil identify writes them) ----
        Spec{"firmware.pole_pairs", Kind::Integer, "", "pole pairs the firmware uses (encoder angle, per-unit speed "
             "base); not given: motor.pole_pairs", closed(1, 16), {},
             [](Scenario& s, const Value& v) { s.firmware.pole_pairs = v.integer; },
             [](const Scenario& s) {
                 return s.firmware.pole_pairs ? std::to_string(*s.firmware.pole_pairs) : std::string("the plant's");
             }},
        opt_num("firmware.encoder_offset_rad", "rad", any(),
                "encoder mounting offset the firmware assumes, in sensors.encoder_offset_rad's sense (mechanical; "
                "the electrical angle at count 0 is -pole_pairs times it); not given: sensors.encoder_offset_rad",
                ACC(firmware.encoder_offset_rad)),
        Spec{"firmware.encoder_reversed", Kind::Bool, "", "true: the encoder counts down for positive rotation; the "
             "firmware has no reversed count, so true is refused (swap the encoder's A and B)", any(), {},
             [](Scenario& s, const Value& v) { s.firmware.encoder_reversed = v.boolean; },
             [](const Scenario& s) { return std::string(s.firmware.encoder_reversed ? "true" : "false"); }},
        // ---- faults: every one configured occurs at faults.time_s ----
        num("faults.time_s", "s", positive(), "when the configured faults occur (first control period at or after it)",
            ACC(faults.time_s)),
        choice<FaultPhase>("faults.leg_open",
                           "leg disconnected from its phase: no device or diode conducts into it (its current is "
                           "cut to zero) unless the relay ties the phase to the mid-point",
                           ACC(faults.leg_open)),
        choice<FaultSwitch>("faults.switch_open",
                            "device stuck open: its gate forced off, its anti-parallel diode still conducts",
                            ACC(faults.switch_open)),
        choice<FaultSwitch>("faults.switch_short",
                            "device shorted: conducts whatever its gate says; when its complement turns on the gate "
                            "drivers' desaturation detection turns every gate off and raises desat for the leg and "
                            "the hardware trip",
                            ACC(faults.switch_short)),
        boolean("faults.encoder_lost", "encoder signal lost: the QEP count freezes, no index pulses",
                ACC(faults.encoder_lost)),
        choice<FaultPhase>("faults.current_sensor_stuck",
                           "that phase's current-sensor ADC channel reads faults.current_sensor_code, without noise",
                           ACC(faults.current_sensor_stuck)),
        integer("faults.current_sensor_code", "", closed(0, 4095),
                "the stuck sensor's ADC code (2048 = mid-scale, zero current)", ACC(faults.current_sensor_code)),
        num("faults.dc_sag", "", Range{0.0, 1.0, true, false},
            "DC source voltage steps to this fraction of inverter.vdc_v (1 = no sag)", ACC(faults.dc_sag)),
        num("metrics.torque_sensor_hz", "Hz", nonneg(),
            "trf_filtered_pct: TRF of the plant torque after a first-order low-pass of this cutoff (a torque "
            "transducer's bandwidth); 0 = unfiltered",
            ACC(metrics.torque_sensor_hz)),
        boolean("protection.allow_unsafe",
                "accept trip settings that let the phase current exceed 3x motor.rated_current_a, or a board whose "
                "over-current only the firmware can see without a way to find a failed current sensor (refused "
                "otherwise)",
                ACC(protection.allow_unsafe)),
    };
    return specs;
}

#undef ACC

const Spec* find_spec(const std::string& name)
{
    for (const Spec& s : schema()) {
        if (s.name == name) {
            return &s;
        }
    }
    return nullptr;
}

std::string kind_name(Kind k)
{
    switch (k) {
    case Kind::Number: return "number";
    case Kind::Integer: return "integer";
    case Kind::Bool: return "boolean";
    case Kind::String: return "string";
    case Kind::Number3: return "array of 3 numbers";
    case Kind::Path: return "path (string)";
    }
    return "?";
}

std::string where(const std::string& file, const toml::source_region& r)
{
    return file + ":" + std::to_string(r.begin.line) + ":" + std::to_string(r.begin.column);
}

std::string node_type_name(const toml::node& n)
{
    switch (n.type()) {
    case toml::node_type::table: return "table";
    case toml::node_type::array: return "array";
    case toml::node_type::string: return "string";
    case toml::node_type::integer: return "integer";
    case toml::node_type::floating_point: return "float";
    case toml::node_type::boolean: return "boolean";
    case toml::node_type::date: return "date";
    case toml::node_type::time: return "time";
    case toml::node_type::date_time: return "date-time";
    default: return "nothing";
    }
}

// Converts a TOML node to a Value of the spec's kind; returns "" or the reason it cannot.
std::string from_node(const Spec& spec, const toml::node& n, Value* v)
{
    auto as_number = [](const toml::node& x, double* out) {
        if (auto i = x.as_integer()) {
            *out = static_cast<double>(i->get());
            return true;
        }
        if (auto f = x.as_floating_point()) {
            *out = f->get();
            return true;
        }
        return false;
    };
    switch (spec.kind) {
    case Kind::Number:
        if (!as_number(n, &v->num)) {
            return "expected a number, got " + node_type_name(n);
        }
        return "";
    case Kind::Integer:
        if (auto i = n.as_integer()) {
            v->integer = i->get();
            v->num = static_cast<double>(v->integer);
            return "";
        }
        return "expected an integer, got " + node_type_name(n);
    case Kind::Bool:
        if (auto b = n.as_boolean()) {
            v->boolean = b->get();
            return "";
        }
        return "expected true or false, got " + node_type_name(n);
    case Kind::String:
    case Kind::Path:
        if (auto s = n.as_string()) {
            v->str = s->get();
            return "";
        }
        return "expected a string, got " + node_type_name(n);
    case Kind::Number3: {
        const toml::array* a = n.as_array();
        if (a == nullptr) {
            return "expected an array of 3 numbers, got " + node_type_name(n);
        }
        if (a->size() != 3) {
            return "expected an array of 3 numbers, got " + std::to_string(a->size()) + " elements";
        }
        for (std::size_t i = 0; i < 3; ++i) {
            if (!as_number(*a->get(i), &v->arr[i])) {
                return "expected an array of 3 numbers, element " + std::to_string(i) + " is " +
                       node_type_name(*a->get(i));
            }
        }
        return "";
    }
    }
    return "unsupported kind";
}

// Converts --set text to a Value of the spec's kind (strict: the whole text must be consumed).
std::string from_text(const Spec& spec, const std::string& text, Value* v)
{
    auto parse_double = [](std::string t, double* out) {
        while (!t.empty() && t.back() == ' ') {
            t.pop_back();
        }
        while (!t.empty() && t.front() == ' ') {
            t.erase(t.begin());
        }
        if (t.empty()) {
            return false;
        }
        std::string no_us;
        for (char c : t) {
            if (c != '_') {
                no_us += c; // TOML allows 1_000
            }
        }
        const char* b = no_us.c_str();
        const char* e = b + no_us.size();
        if (*b == '+') {
            ++b;
        }
        auto r = std::from_chars(b, e, *out);
        return r.ec == std::errc() && r.ptr == e;
    };
    switch (spec.kind) {
    case Kind::Number:
        if (!parse_double(text, &v->num)) {
            return "expected a number, got '" + echo(text) + "'";
        }
        return "";
    case Kind::Integer: {
        double d = 0.0;
        if (!parse_double(text, &d) || d != std::floor(d) || std::fabs(d) > 9.0e18 ||
            text.find_first_of(".eE") != std::string::npos) {
            return "expected an integer, got '" + echo(text) + "'";
        }
        v->integer = static_cast<std::int64_t>(d);
        v->num = d;
        return "";
    }
    case Kind::Bool:
        if (text == "true" || text == "false") {
            v->boolean = text == "true";
            return "";
        }
        return "expected true or false, got '" + echo(text) + "'";
    case Kind::String:
    case Kind::Path: {
        std::string t = text;
        if (t.size() >= 2 && (t.front() == '"' || t.front() == '\'') && t.back() == t.front()) {
            t = t.substr(1, t.size() - 2);
        }
        v->str = t;
        return "";
    }
    case Kind::Number3: {
        std::string t = text;
        if (t.size() < 2 || t.front() != '[' || t.back() != ']') {
            return "expected [x, y, z], got '" + echo(text) + "'";
        }
        t = t.substr(1, t.size() - 2);
        std::vector<std::string> parts;
        std::string cur;
        for (char c : t) {
            if (c == ',') {
                parts.push_back(cur);
                cur.clear();
            } else {
                cur += c;
            }
        }
        parts.push_back(cur);
        if (parts.size() != 3) {
            return "expected [x, y, z] with 3 numbers, got '" + echo(text) + "'";
        }
        for (std::size_t i = 0; i < 3; ++i) {
            if (!parse_double(parts[i], &v->arr[i])) {
                return "expected [x, y, z] with 3 numbers, got '" + echo(text) + "'";
            }
        }
        return "";
    }
    }
    return "unsupported kind";
}

std::string check_value(const Spec& spec, const Value& v)
{
    switch (spec.kind) {
    case Kind::Number:
    case Kind::Integer:
        if (!spec.range.contains(v.num)) {
            return "value " + fmt_double(v.num) + " is impossible: must be " + spec.range.text() +
                   (spec.unit.empty() ? "" : " " + spec.unit);
        }
        return "";
    case Kind::Number3:
        for (std::size_t i = 0; i < 3; ++i) {
            if (!spec.range.contains(v.arr[i])) {
                return "element " + std::to_string(i) + " = " + fmt_double(v.arr[i]) +
                       " is impossible: each must be " + spec.range.text();
            }
        }
        return "";
    case Kind::String: {
        for (const std::string& c : spec.choices) {
            if (c == v.str) {
                return "";
            }
        }
        std::string list;
        for (const std::string& c : spec.choices) {
            list += (list.empty() ? "" : ", ") + ("\"" + c + "\"");
        }
        return "expected one of " + list + ", got \"" + echo(v.str) + "\"";
    }
    case Kind::Path:
        if (v.str.empty()) {
            return "missing value: the path is empty";
        }
        return "";
    case Kind::Bool: return "";
    }
    return "";
}

// An angle is kept as its remainder in one turn, [-pi, pi]: the plant and the encoder emulation
// integrate from it, and a large value would lose the precision of every later angle.
void reduce_angle(const Spec& spec, Value* v)
{
    if (spec.kind == Kind::Number && spec.unit == "rad" && std::isfinite(v->num)) {
        v->num = std::remainder(v->num, 2.0 * kPi);
    }
}

std::string origin_of(const Scenario& s, const std::string& key)
{
    auto it = s.origin.find(key);
    return it == s.origin.end() ? std::string("(default)") : it->second;
}

// Machine-type defaults and key ownership: the motor.* defaults of the schema are the PM machine's;
// with motor.type = "im" every shared key left unset takes the default induction machine's value
// (ImDefaults), and a key of the other machine is refused by name.
void apply_machine_defaults(Scenario& s, Diagnostics* d)
{
    static const std::vector<std::string> pm_only = {"motor.ls_h",        "motor.psi_m_wb",    "motor.emf_gain",
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
        "control.observer_tau_hi_rpm", "control.magnetise_frac", "control.table_speed_rpm",
        "firmware.rr_ohm", "firmware.lls_h", "firmware.llr_h", "firmware.lm_h"};
    static const std::vector<std::string> pm_law = {"firmware.ls_h", "firmware.psi_m_wb", "control.handover_rpm",
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
        err("faults.time_s", "missing value: required when a fault is configured");
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

void cross_validate(Scenario& s, Diagnostics* d)
{
    auto err = [&](const std::string& key, const std::string& msg) {
        d->errors.push_back(origin_of(s, key) + ": " + key + ": " + msg);
    };
    auto warn = [&](const std::string& key, const std::string& msg) {
        d->warnings.push_back(origin_of(s, key) + ": " + key + ": " + msg);
    };
    if (s.firmware.encoder_reversed) {
        err("firmware.encoder_reversed", "true: the firmware has no reversed count (dtc_board_cfg_t); swap the "
                                         "encoder's A and B channels so that it counts up for positive rotation");
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
    if (im && !open_loop) {
        // The IM law (Casadei): firmware only, six switches, voltage or improved estimator.
        if (s.control.implementation != Implementation::Firmware) {
            err("control.implementation", "\"" + to_string(s.control.implementation) + "\" has no induction-machine "
                "law: motor.type = \"im\" (" + origin_of(s, "motor.type") + ") runs on \"firmware\"");
        }
        if (s.inverter.topology != Topology::Sstp && s.inverter.topology != Topology::Ideal) {
            err("inverter.topology", "the induction-machine law needs the six-switch inverter \"sstp\"; got \"" +
                                         to_string(s.inverter.topology) + "\"");
        }
        if (s.control.estimator == Estimator::Current) {
            err("control.estimator", "\"current\" (Hoang eqs. 8-9) needs a magnet: the PM drive only; the "
                                     "induction machine takes \"voltage\" or \"improved\"");
        }
        const double tau_hi = s.control.observer_tau_high_s > 0.0 ? s.control.observer_tau_high_s
                                                                  : s.control.observer_tau_s;
        if (s.control.observer_tau_s <= s.ts_s || tau_hi <= s.ts_s) {
            err(s.control.observer_tau_s <= s.ts_s ? "control.observer_tau_s" : "control.observer_tau_high_s",
                "must be longer than the control period ts_s = " + fmt_double(s.ts_s) + " s");
        }
        if (s.control.scheme == Scheme::Itc) {
            err("control.scheme", "\"itc\" is the PM machine's indirect torque control; motor.type is \"im\"");
        }
        const bool svm = s.control.scheme == Scheme::Sfvc || s.control.scheme == Scheme::Dfoc;
        if (s.control.scheme == Scheme::Dsvm) {
            // The PWM form's thirds (firmware/dtc/dsvm.h, hal.h): T1PR whole counts, at least 3.
            const double n = s.ts_s * PLANT_DEF_PWM_CLOCK_HZ * 0.5;
            if (hal_host::t1pr_counts(s.ts_s, PLANT_DEF_PWM_CLOCK_HZ) < 3u) {
                err("ts_s", "the PWM timer period 75 MHz ts_s / 2 = " + fmt_double(n) +
                                " counts is not a whole number in 3..65534 (hal.h T1PR; dsvm's thirds)");
            }
            if (s.control.flux_weakening) {
                err("control.flux_weakening", "section 12's flux weakening watches the three-level torque comparator; "
                                              "not with control.scheme = \"dsvm\"");
            }
            if (s.control.dsvm_torque_band2_nm != 0.0 && s.control.dsvm_torque_band2_nm < s.control.torque_band_nm) {
                err("control.dsvm_torque_band2_nm", "must be 0 (derived) or at least control.torque_band_nm = " +
                                                        fmt_double(s.control.torque_band_nm));
            }
        }
        if (svm) {
            // One PWM period per control period (firmware/dtc/im_sfvc.c, hal.h): ts_s = 1 / carrier_hz,
            // T1PR = ts_s f_clock / 2 a whole number of counts (hal_host::t1pr_counts).
            if (s.origin.count("control.carrier_hz") != 0 && s.origin.count("ts_s") != 0 &&
                std::fabs(s.control.carrier_hz * s.ts_s - 1.0) > 1e-9) {
                err("control.carrier_hz", "is " + fmt_double(s.control.carrier_hz) + " Hz: the SVM carrier period must "
                    "equal the control period ts_s = " + fmt_double(s.ts_s) + " s (" + origin_of(s, "ts_s") + ")");
            } else if (s.origin.count("control.carrier_hz") == 0) {
                s.control.carrier_hz = 1.0 / s.ts_s;
            }
            const double n = s.ts_s * PLANT_DEF_PWM_CLOCK_HZ * 0.5;
            if (hal_host::t1pr_counts(s.ts_s, PLANT_DEF_PWM_CLOCK_HZ) == 0u) {
                err(s.origin.count("control.carrier_hz") != 0 ? "control.carrier_hz" : "ts_s",
                    "the PWM timer period 75 MHz / (2 carrier) = " + fmt_double(n) +
                        " counts is not a whole number in 1..65534 (hal.h T1PR)");
            }
            if (!(s.control.rotor_flux_ref_wb > 0.0)) {
                err("control.rotor_flux_ref_wb", "the stator-flux vector control (Casadei eq. 18) and the "
                                                 "rotor-flux-oriented control take the rotor-flux command: must be > 0");
            }
            if (s.control.flux_weakening) {
                err("control.flux_weakening", "section 12's flux weakening watches the DTC torque comparator; not "
                                              "with control.scheme = \"" + to_string(s.control.scheme) + "\"");
            }
            if (s.control.sfvc_kp_per_s * s.ts_s > 1.0) {
                err("control.sfvc_kp_per_s", "must be at most 1/ts_s = " + fmt_double(1.0 / s.ts_s) +
                                                 " 1/s (the deadbeat gain)");
            }
        }
        if (s.control.observer_tau_hi_rpm < s.control.observer_tau_lo_rpm) {
            err("control.observer_tau_hi_rpm", "must not be below control.observer_tau_lo_rpm = " +
                                                   fmt_double(s.control.observer_tau_lo_rpm));
        }
        if (s.control.observer_tau_high_s > 0.0 && s.control.observer_tau_hi_rpm <= 0.0) {
            err("control.observer_tau_hi_rpm", "a speed-dependent tau (control.observer_tau_high_s, " +
                                                   origin_of(s, "control.observer_tau_high_s") +
                                                   ") needs the speed from which it applies (> 0)");
        }
    } else if (!open_loop) {
        if (s.control.estimator == Estimator::Improved) {
            err("control.estimator", "\"improved\" (Casadei eqs. 20-22) is the induction machine's estimator; "
                                     "motor.type is \"pmsm\"");
        }
        if (s.control.table == SwitchingTable::SpeedDependent) {
            err("control.table", "\"speed-dependent\" (Casadei sec. 8) is an induction-machine table; "
                                 "motor.type is \"pmsm\"");
        }
        if (s.control.scheme != Scheme::Dtc && s.control.scheme != Scheme::Itc) {
            err("control.scheme", "\"" + to_string(s.control.scheme) + "\" is an induction-machine scheme; the PM "
                                  "machine takes \"dtc\" or \"itc\"");
        }
        if (s.control.scheme == Scheme::Itc) {
            if (s.control.implementation != Implementation::Firmware) {
                err("control.implementation", "\"" + to_string(s.control.implementation) + "\" has no indirect "
                    "torque control: control.scheme = \"itc\" (" + origin_of(s, "control.scheme") + ") runs on \"firmware\"");
            }
            // One PWM period per control period (firmware/dtc/itc.h, hal.h): T1PR = ts_s f_clock / 2
            // a whole number of counts (hal_host::t1pr_counts).
            const double n = s.ts_s * PLANT_DEF_PWM_CLOCK_HZ * 0.5;
            if (hal_host::t1pr_counts(s.ts_s, PLANT_DEF_PWM_CLOCK_HZ) == 0u) {
                err("ts_s", "the PWM timer period 75 MHz ts_s / 2 = " + fmt_double(n) +
                                " counts is not a whole number in 1..65534 (hal.h T1PR; control.scheme = \"itc\")");
            }
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
        if (s.control.compensation == Compensation::Proposed && s.inverter.topology == Topology::Sstp) {
            err("control.compensation", "\"proposed\" (Hoang Table VI) is defined for the FSTP only; use "
                                        "\"simple\" for the SSTP (Hoang ref. [29])");
        }
        if (s.control.estimator == Estimator::Current && s.control.compensation != Compensation::None) {
            warn("control.compensation", "ignored by the current-model estimator");
        }
        if (s.inverter.topology == Topology::Fstp && s.control.table != SwitchingTable::Basic) {
            warn("control.table", "ignored: the FSTP always uses Hoang Table II");
        }
        const double f_speed_hz = 1.0 / (s.ts_s * static_cast<double>(s.control.speed_loop_divider));
        if (s.control.speed_bw_hz > f_speed_hz / 20.0) {
            err("control.speed_bw_hz", "is " + fmt_double(s.control.speed_bw_hz) +
                                           " Hz; must be <= 1/20 of the speed-loop rate (" +
                                           fmt_double(f_speed_hz / 20.0) + " Hz)");
        }
        if (s.control.lpf_cutoff_rad_s >= kPi / s.ts_s) {
            err("control.lpf_cutoff_rad_s", "must be below the Nyquist rate pi/ts_s = " +
                                                fmt_double(kPi / s.ts_s) + " rad/s");
        }
    }
    if (!open_loop && !s.protection.allow_unsafe && s.control.implementation == Implementation::Firmware &&
        s.protection.hw_trip_current_a == 0.0) {
        // Without the hardware comparator only the firmware can see an over-current, and it sees
        // it through the current sensors: a failed sensor must be found, by the current sum of
        // three sensors or by the plausibility against the law's prediction (the PM law with
        // the delay compensation; firmware/app/app_plaus.h), both with the fault detection on.
        const bool sum = s.sensors.current_sensors == 3;
        const bool pred = s.motor.type == MotorType::Pmsm && s.control.delay_comp;
        if (!s.control.fault_detect || !(sum || pred)) {
            err("protection.hw_trip_current_a",
                "0 (no hardware comparator) needs a firmware path that sees a failed current sensor: "
                "control.fault_detect = true with sensors.current_sensors = 3, or the PM law with "
                "control.delay_comp = true; otherwise a stuck sensor hides an over-current. Fit the comparator "
                "or set protection.allow_unsafe = true");
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
    if (s.protection.vdc_min_v >= s.protection.vdc_max_v) {
        err("protection.vdc_min_v", "must be below protection.vdc_max_v = " + fmt_double(s.protection.vdc_max_v));
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
}

} // namespace

std::vector<KeyDoc> scenario_keys()
{
    const Scenario defaults;
    std::vector<KeyDoc> out;
    for (const Spec& s : schema()) {
        std::string range;
        if (s.kind == Kind::String) {
            for (const std::string& c : s.choices) {
                range += (range.empty() ? "" : " \\| ") + ("\"" + c + "\"");
            }
        } else if (s.kind == Kind::Number || s.kind == Kind::Integer || s.kind == Kind::Number3) {
            range = s.range.text();
        } else if (s.kind == Kind::Bool) {
            range = "true \\| false";
        } else {
            range = "readable file";
        }
        out.push_back(KeyDoc{s.name, kind_name(s.kind), s.unit, s.show(defaults), range, s.doc});
    }
    return out;
}

std::string scenario_keys_markdown()
{
    std::ostringstream o;
    o << "| key | type | unit | default | allowed | meaning |\n|---|---|---|---|---|---|\n";
    for (const KeyDoc& k : scenario_keys()) {
        o << "| `" << k.name << "` | " << k.type << " | " << k.unit << " | " << k.default_text << " | " << k.range
          << " | " << k.doc << " |\n";
    }
    return o.str();
}

std::string Diagnostics::text() const
{
    std::string t;
    for (std::size_t i = 0; i < errors.size() && i < kMaxShown; ++i) {
        t += "error: " + errors[i] + "\n";
    }
    if (errors.size() > kMaxShown) {
        t += "error: ... and " + std::to_string(errors.size() - kMaxShown) + " more errors (" +
             std::to_string(errors.size()) + " in all)\n";
    }
    for (std::size_t i = 0; i < warnings.size() && i < kMaxShown; ++i) {
        t += "warning: " + warnings[i] + "\n";
    }
    if (warnings.size() > kMaxShown) {
        t += "warning: ... and " + std::to_string(warnings.size() - kMaxShown) + " more warnings\n";
    }
    return t;
}

namespace {
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
} // namespace

bool parse_scenario(const std::string& toml_text, const std::string& source_name,
                    const std::vector<std::string>& overrides, Scenario* out, Diagnostics* diag,
                    const std::vector<OverlayText>& overlays)
{
    Scenario s;
    s.path = source_name;
    s.name = std::filesystem::path(source_name).stem().string();
    if (std::string why = check_toml_limits(toml_text, source_name); !why.empty()) {
        diag->errors.push_back(why + "; refused before parsing");
        return false;
    }
    toml::table root;
    try {
        root = toml::parse(toml_text, source_name);
    } catch (const toml::parse_error& e) {
        diag->errors.push_back(where(source_name, e.source()) + ": TOML syntax error: " +
                               std::string(e.description()));
        return false;
    }

    if (root.empty()) {
        diag->errors.push_back(source_name + ": the scenario sets no key (empty file?); a scenario names at "
                                             "least the settings it is about, e.g. duration_s");
        return false;
    }

    // part: one TOML key as written (a quoted key is one key, whatever it holds); name: the dotted
    // scenario key it makes under its table.
    auto apply_node = [&](const std::string& file, const std::string& name, const std::string& part,
                          const toml::node& n, const toml::source_region& key_src) {
        const Spec* spec = part.find('.') == std::string::npos ? find_spec(name) : nullptr;
        const std::string loc = where(file, n.source().begin.line != 0 ? n.source() : key_src);
        if (spec == nullptr) {
            std::string shown = echo(name) + ": unknown key";
            if (part.find('.') != std::string::npos) {
                // TOML: "a.b" = 1 is one key named a.b, not the key b of table a.
                shown = (name == part ? "" : echo(name.substr(0, name.size() - part.size()))) + "\"" + echo(part) +
                        "\": unknown key (quoted, it is one TOML key whose name holds a dot, not a dotted key; "
                        "write " + echo(part) + " without the quotes)";
            }
            diag->errors.push_back(where(file, key_src) + ": " + shown);
            return;
        }
        Value v;
        std::string why = from_node(*spec, n, &v);
        if (why.empty()) {
            if (spec->kind == Kind::Path && !v.str.empty()) {
                std::filesystem::path p(v.str);
                if (p.is_relative()) {
                    v.str = (std::filesystem::path(file).parent_path() / p).lexically_normal().string();
                }
            }
            reduce_angle(*spec, &v);
            why = check_value(*spec, v);
        }
        if (!why.empty()) {
            diag->errors.push_back(loc + ": " + name + ": " + why);
            return;
        }
        spec->set(s, v);
        s.origin[name] = loc;
    };

    std::vector<std::string> empty_tables;
    static const char* const sections[] = {"motor",      "inverter", "load",    "control",
                                           "sensors",    "protection", "firmware", "metrics", "faults"};
    // The scenario's tables, then each overlay's over them (dtc-sil --overlay), key by key.
    auto apply_table = [&](const toml::table& doc, const std::string& file) {
        for (auto&& [key, node] : doc) {
            const std::string k(key.str());
            bool is_section = false;
            for (const char* sec : sections) {
                is_section = is_section || k == sec;
            }
            if (is_section) {
                const toml::table* t = node.as_table();
                if (t == nullptr) {
                    diag->errors.push_back(where(file, key.source()) + ": " + k + ": expected a table [" + k +
                                           "], got " + node_type_name(node));
                    continue;
                }
                if (t->empty()) {
                    empty_tables.push_back(where(file, key.source()) + ": [" + k + "]");
                }
                for (auto&& [sub, sn] : *t) {
                    apply_node(file, k + "." + std::string(sub.str()), std::string(sub.str()), sn, sub.source());
                }
            } else if (node.is_table()) {
                diag->errors.push_back(where(file, key.source()) + ": [" + echo(k) + "]: unknown table");
            } else {
                apply_node(file, k, k, node, key.source());
            }
        }
    };
    apply_table(root, source_name);
    if (s.origin.empty() && diag->ok()) {
        // Only empty tables: a file that sets nothing is not a scenario (the defaults would run
        // under its name).
        std::string tables;
        for (const std::string& t : empty_tables) {
            tables += (tables.empty() ? "" : ", ") + t;
        }
        diag->errors.push_back(source_name + ": the scenario sets no key (" + tables +
                               " empty); a scenario names at least the settings it is about, e.g. duration_s "
                               "and the [motor] keys");
        return false;
    }
    for (const std::string& t : empty_tables) {
        diag->warnings.push_back(t + ": empty table: sets nothing");
    }

    for (const OverlayText& ov : overlays) {
        if (std::string why = check_toml_limits(ov.text, ov.path); !why.empty()) {
            diag->errors.push_back(why + "; overlay refused before parsing");
            continue;
        }
        try {
            const toml::table doc = toml::parse(ov.text, ov.path);
            if (doc.empty()) {
                diag->warnings.push_back(ov.path + ": the overlay sets no key");
            }
            apply_table(doc, ov.path);
        } catch (const toml::parse_error& e) {
            diag->errors.push_back(where(ov.path, e.source()) + ": TOML syntax error: " +
                                   std::string(e.description()));
        }
    }

    int n_set = 0;
    for (const std::string& o : overrides) {
        ++n_set;
        const std::string loc = "--set #" + std::to_string(n_set) + " '" + echo(o) + "'";
        const auto eq = o.find('=');
        if (eq == std::string::npos || eq == 0) {
            diag->errors.push_back(loc + ": expected key=value");
            continue;
        }
        const std::string name = o.substr(0, eq);
        const std::string text = o.substr(eq + 1);
        const Spec* spec = find_spec(name);
        if (spec == nullptr) {
            diag->errors.push_back(loc + ": " + echo(name) + ": unknown key");
            continue;
        }
        Value v;
        std::string why = from_text(*spec, text, &v);
        if (why.empty()) {
            reduce_angle(*spec, &v);
            why = check_value(*spec, v); // relative paths on the command line are relative to the cwd
        }
        if (!why.empty()) {
            diag->errors.push_back(loc + ": " + name + ": " + why);
            continue;
        }
        spec->set(s, v);
        s.origin[name] = loc;
    }

    if (diag->ok()) {
        apply_machine_defaults(s, diag);
        check_law_keys(s, diag);
    }
    if (diag->ok()) {
        cross_validate(s, diag);
    }
    if (diag->ok()) {
        check_sizes(s, diag);
    }
    if (!diag->ok()) {
        return false;
    }
    *out = std::move(s);
    return true;
}

namespace {
// A whole file's text; false with an error "PATH: TAG..." that says what to give instead.
bool read_toml_text(const std::string& path, const std::string& tag, const std::string& give,
                    const std::string& unreadable, std::string* text, Diagnostics* diag)
{
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        diag->errors.push_back(path + ": " + tag +
                               (std::filesystem::exists(path, ec) ? "not a regular file (a directory?)"
                                                                  : "no such file") +
                               ": give " + give);
        return false;
    }
    std::ifstream f(path, std::ios::binary);
    if (!f) {
        diag->errors.push_back(path + ": " + tag + unreadable);
        return false;
    }
    std::ostringstream ss;
    ss << f.rdbuf(); // an empty file sets ss's failbit: its text is "" (refused or warned by the parser)
    *text = ss.str();
    return true;
}
} // namespace

bool read_overlay(const std::string& path, OverlayText* out, Diagnostics* diag)
{
    out->path = path;
    return read_toml_text(path, "--overlay: ", "a TOML fragment (e.g. identified.toml of dtc-sil identify)",
                          "cannot read the file", &out->text, diag);
}

bool load_scenario(const std::string& path, const std::vector<std::string>& overrides, Scenario* out,
                   Diagnostics* diag, const std::vector<std::string>& overlay_paths)
{
    std::vector<OverlayText> overlays(overlay_paths.size());
    bool overlays_ok = true;
    for (std::size_t i = 0; i < overlay_paths.size(); ++i) {
        overlays_ok = read_overlay(overlay_paths[i], &overlays[i], diag) && overlays_ok;
    }
    if (!overlays_ok) {
        return false;
    }
    std::string text;
    if (!read_toml_text(path, "", "a scenario TOML file", "cannot open the scenario file", &text, diag)) {
        return false;
    }
    return parse_scenario(text, path, overrides, out, diag, overlays);
}

bool load_voltage_csv(const std::string& path, std::vector<VoltageRow>* rows, std::string* err)
{
    std::ifstream f(path);
    if (!f) {
        *err = path + ": cannot open the voltage table";
        return false;
    }
    rows->clear();
    std::string line;
    int lineno = 0;
    bool header = false;
    while (std::getline(f, line)) {
        ++lineno;
        if (!line.empty() && line.back() == '\r') {
            line.pop_back();
        }
        if (line.empty() || line[0] == '#') {
            continue;
        }
        if (!header) {
            std::string h;
            for (char c : line) {
                if (c != ' ') {
                    h += c;
                }
            }
            if (h != "t_s,v_alpha_v,v_beta_v") {
                *err = path + ":" + std::to_string(lineno) + ": expected the header t_s,v_alpha_v,v_beta_v";
                return false;
            }
            header = true;
            continue;
        }
        VoltageRow r{};
        double* dst[3] = {&r.t_s, &r.v_alpha_v, &r.v_beta_v};
        std::size_t pos = 0;
        for (int i = 0; i < 3; ++i) {
            const std::size_t comma = i < 2 ? line.find(',', pos) : line.size();
            if (comma == std::string::npos) {
                *err = path + ":" + std::to_string(lineno) + ": expected 3 comma-separated numbers";
                return false;
            }
            std::string cell = line.substr(pos, comma - pos);
            while (!cell.empty() && cell.front() == ' ') {
                cell.erase(cell.begin());
            }
            while (!cell.empty() && cell.back() == ' ') {
                cell.pop_back();
            }
            const char* b = cell.c_str();
            auto res = std::from_chars(b, b + cell.size(), *dst[i]);
            if (cell.empty() || res.ec != std::errc() || res.ptr != b + cell.size() || !std::isfinite(*dst[i])) {
                *err = path + ":" + std::to_string(lineno) + ": column " + std::to_string(i + 1) +
                       " is not a finite number: '" + cell + "'";
                return false;
            }
            pos = comma + 1;
        }
        if (rows->empty() && r.t_s > 0.0) {
            *err = path + ":" + std::to_string(lineno) + ": the first row must start at t_s <= 0";
            return false;
        }
        if (!rows->empty() && !(r.t_s > rows->back().t_s)) {
            *err = path + ":" + std::to_string(lineno) + ": t_s must increase strictly";
            return false;
        }
        rows->push_back(r);
    }
    if (!header || rows->empty()) {
        *err = path + ": no data rows";
        return false;
    }
    return true;
}

SpeedPiGains speed_pi_gains(double j_kgm2, double bw_hz)
{
    // The inner DTC torque loop is fast against the speed loop, so the speed plant is 1/(J s)
    // (friction B only adds damping). PI: C(s) = Kp (1 + wc / (4 s)), Kp = J wc. Open loop
    // L(jw) = (wc/w) (1 - j wc/(4 w)): |L(j wc)| = sqrt(1 + 1/16) = 1.03 (crossover ~ wc), phase
    // margin = 90 deg - atan(1/4) = 76 deg.
    const double wc = 2.0 * kPi * bw_hz;
    const double kp = j_kgm2 * wc;
    return SpeedPiGains{kp, kp * wc / 4.0};
}

double dyno_speed_rpm(const Scenario& sc, double t_s)
{
    const LoadCfg& l = sc.load;
    if (!(l.speed_ramp_s > 0.0) || t_s >= l.speed_ramp_start_s + l.speed_ramp_s) {
        return l.speed_rpm;
    }
    const double x = std::max(0.0, t_s - l.speed_ramp_start_s) / l.speed_ramp_s;
    return sc.initial_speed_rpm + (l.speed_rpm - sc.initial_speed_rpm) * x;
}

} // namespace sil
