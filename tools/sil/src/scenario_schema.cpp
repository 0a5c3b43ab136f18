// scenario_schema.cpp - the scenario schema: every key with its kind, unit, range, default and
// meaning (the docs' key table, `dtc-sil keys`), and the checks of one value against it.
#include "scenario_schema.hpp"
#include "toml_limits.hpp"

#include <optional>

extern "C" {
#include "dtc_si_params.h"
}

namespace sil {
namespace detail {

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

// The firmware.* keys: one per belief row of tools/config/dtc_si_params.h, with its unit, plain
// range and meaning; not given, the firmware takes the plant's value (the row's plant key).
std::vector<Spec> belief_specs()
{
    std::vector<Spec> out;
    for (std::size_t i = 0; i < dtc_si_param_count; ++i) {
        const dtc_si_param_t& p = dtc_si_params[i];
        if (p.belief == nullptr) {
            continue;
        }
        const std::string member = p.name;
        const bool lo_open = p.bounds == DTC_SIP_LO_OPEN || p.bounds == DTC_SIP_OPEN;
        const bool hi_open = p.bounds == DTC_SIP_HI_OPEN || p.bounds == DTC_SIP_OPEN;
        const Range r{p.lo <= -DTC_SIP_INF ? -kInf : p.lo, p.hi >= DTC_SIP_INF ? kInf : p.hi, lo_open, hi_open};
        out.push_back(Spec{"firmware." + member, Kind::Number, p.unit, std::string(p.meaning) + "; not given: " + p.belief,
                           r, {},
                           [member](Scenario& s, const Value& v) { s.firmware.value[member] = v.num; },
                           [member](const Scenario& s) {
                               const auto it = s.firmware.value.find(member);
                               return it != s.firmware.value.end() ? fmt_double(it->second) : std::string("the plant's");
                           }});
    }
    return out;
}

const std::vector<Spec>& schema()
{
    static const std::vector<Spec> before_beliefs = {
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
        num("motor.ls_h", "H", positive(), "synchronous inductance, Ld = Lq (Table VIII); of a salient PM its L_d",
            ACC(motor.ls_h)),
        num("motor.ld_h", "H", positive(),
            "d-axis inductance (along the magnet); not set: motor.ls_h; given with motor.ls_h it must equal it",
            ACC(motor.ld_h)),
        num("motor.lq_h", "H", positive(),
            "q-axis inductance (across the magnet); not set: L_d (a surface PM); another value makes the plant a "
            "salient (interior) PM: psi_d = L_d i_d + psi_m, psi_q = L_q i_q, T = 1.5 p (psi_m i_q + (L_d - L_q) "
            "i_d i_q)",
            ACC(motor.lq_h)),
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
        num("motor.temp_rise_k", "K", Range{-100.0, 300.0, false, false},
            "the windings' temperature rise over the run, linear from 0 at t = 0 to this value at duration_s: the "
            "plant's motor.rs_ohm and (im) motor.rr_ohm are multiplied by 1 + 0.0039/K * rise(t) (copper, 0.39 %/K; "
            "both windings at one temperature), updated every millisecond; the firmware keeps its configured "
            "values (firmware.*); 0 = resistances constant",
            ACC(motor.temp_rise_k)),
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
        boolean("inverter.phases_swapped",
                "two motor leads exchanged: the machine's phases B and C on the inverter's legs C and B (the phase "
                "sensors sit on the legs); the inverter's forward field turns the machine backward",
                ACC(inverter.phases_swapped)),
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
               "proposed = Table VI + eqs. 37-38 (FSTP) / Table III per leg with V_CE and V_d + eqs. 24-25 (SSTP)",
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
               "locus (sec. 9) above control.table_speed_rpm, ST-D's circular locus below it; sfvc = stator-flux vector control with SVM at the constant switching frequency "
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
        boolean("control.rr_tracking",
                 "IM with the encoder and control.fault_detect: the firmware's rotor resistance tracked on line (the "
                 "improved estimator's rotor-flux speed less the encoder's is the measured slip, Casadei eq. 16's "
                 "the model's: MRAS, firmware/dtc/im_sup.h) is used in the slip (sensorless speed, SFVC) and the "
                 "stator resistance of the estimator follows it by the same ratio (one winding temperature); "
                 "false: tracked and reported (warning im_model_mismatch) only",
                 ACC(control.rr_tracking)),
        boolean("control.current_model_ref",
                 "IM with the encoder and the improved estimator (not DSVM): below the speed at which Casadei eq. "
                 "20's slow pole w^2 tau / k_r passes 1/tau_r, the estimator's correction pulls towards the rotor "
                 "flux of a current model turned by the encoder's angle (T model, Casadei eqs. A7, A9), blended out "
                 "by 4/tau_r (firmware/dtc/im_sup.h); the rotor-flux trim's ring at low speed gone and the voltage's "
                 "errors kept out of the flux angle there (the torque target at 5 % speed needs it); false: Casadei "
                 "eq. 20's phi_r* e^{j theta} at every speed, the paper's estimator (its figures)",
                 ACC(control.current_model_ref)),
        num("control.table_speed_rpm", "rpm", nonneg(),
            "IM speed-dependent table: ST-D below, ST-A above; DSC: ST-D's circle below, the hexagon above (a "
            "hysteresis of 1/16 of it either side); 0 = derived (half the speed where the back-EMF "
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
                 "firmware: the drop compensation of a period takes each leg's forward drop averaged over the "
                 "current's line from the previous to the present sample (a current that crosses zero inside the "
                 "period has both polarities in it) and its on-resistance terms at the period's mean current, and "
                 "the dead-time compensation from the current at the switching instant (the previous sample); "
                 "false: all from the present sample",
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
                 "leg, phase or device; PM laws also a phase whose current keeps one direction over 420 deg while the "
                 "other two alternate: an open device), the lost-encoder check (the count still for 32 periods above a "
                 "speed derived from the encoder, control.torque_limit_nm and motor.j_kgm2) and, IM laws with the "
                 "encoder, the encoder's speed against the estimated rotor flux's less its slip (tolerance from the "
                 "slip at control.torque_limit_nm: trip encoder_speed); firmware/app/app_fault.c, app_enc.c",
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
        boolean("sensors.encoder_reversed",
                "the encoder counts down for positive rotation (its A and B exchanged); the electrical angle at "
                "count 0 is then +pole_pairs times sensors.encoder_offset_rad",
                ACC(sensors.encoder_reversed)),
        choice<FaultPhase>("sensors.current_reversed",
                           "that phase's current sensor mounted the wrong way round: it reads minus the phase current",
                           ACC(sensors.current_reversed)),
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
        // ---- firmware.*: its own parameter values (mismatch studies); unset = the plant's; the
        // belief rows of tools/config/dtc_si_params.h (belief_specs) ----
    };
    static const std::vector<Spec> after_beliefs = {
        // ---- firmware: the machine's sensors as the firmware believes them (dtc-sil identify writes them) ----
        Spec{"firmware.pole_pairs", Kind::Integer, "", "pole pairs the firmware uses (encoder angle, per-unit speed "
             "base); not given: motor.pole_pairs", closed(1, 16), {},
             [](Scenario& s, const Value& v) { s.firmware.pole_pairs = v.integer; },
             [](const Scenario& s) {
                 return s.firmware.pole_pairs ? std::to_string(*s.firmware.pole_pairs) : std::string("the plant's");
             }},
        Spec{"firmware.encoder_offset_rad", Kind::Number, "rad",
             "encoder mounting offset the firmware assumes, in sensors.encoder_offset_rad's sense (mechanical; the "
             "electrical angle at count 0 is -pole_pairs times it); not given: sensors.encoder_offset_rad",
             any(), {}, [](Scenario& s, const Value& v) { s.firmware.encoder_offset_rad = v.num; },
             [](const Scenario& s) {
                 return s.firmware.encoder_offset_rad ? fmt_double(*s.firmware.encoder_offset_rad)
                                                      : std::string("the plant's");
             }},
        Spec{"firmware.encoder_reversed", Kind::Bool, "", "true: the firmware reads the count reversed (counts - 1 - "
             "count: dtc_board_cfg_t.enc_reversed), for an encoder that counts down when the inverter's field turns "
             "forward (a reversed encoder, or two motor leads exchanged); firmware.encoder_offset_rad is then in the "
             "reversed sense (the electrical angle at count 0 is +pole_pairs times it); not given: "
             "sensors.encoder_reversed", any(), {},
             [](Scenario& s, const Value& v) { s.firmware.encoder_reversed = v.boolean; },
             [](const Scenario& s) {
                 return s.firmware.encoder_reversed ? std::string(*s.firmware.encoder_reversed ? "true" : "false")
                                                    : std::string("the plant's");
             }},
        Spec{"firmware.encoder_lines", Kind::Integer, "", "encoder lines in the firmware's board data (a wrong line "
             "count: the plant's encoder has sensors.encoder_lines); not given: sensors.encoder_lines",
             closed(1, 16383), {}, [](Scenario& s, const Value& v) { s.firmware.encoder_lines = v.integer; },
             [](const Scenario& s) {
                 return s.firmware.encoder_lines ? std::to_string(*s.firmware.encoder_lines) : std::string("the plant's");
             }},
        Spec{"firmware.j_kgm2", Kind::Number, "kg*m^2",
             "inertia the firmware's speed PI and lost-encoder level derive from; not given: motor.j_kgm2", positive(), {},
             [](Scenario& s, const Value& v) { s.firmware.j_kgm2 = v.num; },
             [](const Scenario& s) { return s.firmware.j_kgm2 ? fmt_double(*s.firmware.j_kgm2) : std::string("the plant's"); }},
        Spec{"firmware.b_nm_s_per_rad", Kind::Number, "N*m*s/rad",
             "viscous friction as identified (recorded: the firmware's configuration has no friction term)", nonneg(), {},
             [](Scenario& s, const Value& v) { s.firmware.b_nm_s_per_rad = v.num; },
             [](const Scenario& s) {
                 return s.firmware.b_nm_s_per_rad ? fmt_double(*s.firmware.b_nm_s_per_rad) : std::string("not given");
             }},
        Spec{"firmware.coulomb_nm", Kind::Number, "N*m",
             "Coulomb friction as identified (recorded: the firmware's configuration has no friction term)", nonneg(), {},
             [](Scenario& s, const Value& v) { s.firmware.coulomb_nm = v.num; },
             [](const Scenario& s) {
                 return s.firmware.coulomb_nm ? fmt_double(*s.firmware.coulomb_nm) : std::string("not given");
             }},
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
    static const std::vector<Spec> specs = [] {
        std::vector<Spec> v = before_beliefs;
        for (Spec& b : belief_specs()) {
            v.push_back(std::move(b));
        }
        v.insert(v.end(), after_beliefs.begin(), after_beliefs.end());
        return v;
    }();
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


} // namespace detail

using namespace detail;

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


} // namespace sil
