// inverter.h - the inverter's legs: conduction paths per gate state (Hoang Table III, eq. 20), the
// gate timeline with dead time, and the switching instants within an advance (SSTP: six switches,
// Casadei eq. 2, Fig. A2; FSTP: four switches, phase A on the capacitor mid-point, Hoang Fig. 1b;
// ideal: the commanded alpha/beta voltages). SI units.
//
// Every conducting path is (rail voltage) - v_f - R_on i with v_f from Hoang Table III chosen by
// gate state and current sign. During dead time / gates off the current sign picks the diode. At
// i = 0 a leg's voltage is the whole interval between its two paths; circuit.h resolves which
// phases conduct (docs/plant.md, "Inverter legs").
#ifndef DTC_MODEL_INVERTER_H
#define DTC_MODEL_INVERTER_H

#include "plant.h"

namespace plant_model {

enum Rail : int { RAIL_ZERO = 0, RAIL_PLUS = 1, RAIL_MID = 2, RAIL_SRC = 3 };
enum Gate : int { GATE_LOWER = 0, GATE_UPPER = 1, GATE_OFF = 2 };
// How a phase conducts: through the path for positive or negative current, or not at all.
enum PhaseMode : int { PH_POS = 0, PH_NEG = 1, PH_BLOCKED = 2 };

struct Path {
    int rail;   // which node the phase terminal is tied to through the conducting device
    double d;   // forward drop v_f (Hoang Table III sign convention): v_x0 = rail - d - r*i
    double r;   // on-state resistance in the path
};

inline double path_v(const Path &p, const double *rail_v) { return rail_v[p.rail] - p.d; }

// Right-hand-side coefficients of one phase in one PhaseMode (built with the legs, so a mode
// change only copies three pointers).
struct PhaseCoef {
    double cond;          // 1 conducting, 0 blocked
    double a_lo, a_hi, c; // path voltage = a_lo vc_lo + a_hi vc_hi + c (c includes -v_f)
    double r;             // device resistance in the path
    double rtot;          // R (machine, circuit_resistance) + r
    double dev_d;         // v_f of the path, for the device loss term dev (d + r i) i
    double dev;           // 1 for a conducting device path
    double plus, mid, src;  // 1 if the conducting path is tied to that node
    double pd, pr;        // dev * dev_d, dev * r: device loss (pd + pr i) i
};

// One leg in one gate state.
struct Leg {
    Path pos, neg;  // path for i > 0 (out of the leg into the machine) and for i < 0
    PhaseCoef coef[3];  // per PhaseMode
    // same_as[g][m]: coef[m] (m = PH_POS, PH_NEG) equals the same leg's coef[m] in gate state g, so
    // with the current's sign fixed a change to or from g changes nothing in the right-hand side
    // (e.g. the lower device turning off while its diode carries i > 0).
    bool same_as[3][2];
    bool sign_dep;  // the two paths differ: the voltage jumps at i = 0
    bool device;    // a semiconductor path (losses accounted); false for mid-point / ideal source
};

// Faults of the legs and the reconfiguration relay's contacts (plant.h): what the leg
// table is built from beside the parameters.
struct LegFaults {
    int sw[3][2];      // [leg][upper]: plant_switch_fault_t
    int open[3];       // leg disconnected from its phase
    int relay_closed;  // phase on the mid-point through the relay (1..3), 0 = none
};

// Large enough that the zero-current interval of a disconnected phase contains every voltage the
// circuit can reach, small enough that 0 * it stays 0 (not NaN as with infinity).
constexpr double kOpenPathV = 1e30;

// Gate state the devices of leg x act as, for a commanded gate state g with switch faults: an open
// device never turns on (its gate as off), a shorted one is on whatever its gate says. A shorted
// device with its complement commanded on (shoot-through) keeps g: the plant trips at that
// instant (shoot_through()).
inline int effective_gate(const LegFaults &f, int x, int g) {
    const int up = f.sw[x][1], lo = f.sw[x][0];
    if (up == PLANT_SWITCH_OPEN && g == GATE_UPPER) return GATE_OFF;
    if (lo == PLANT_SWITCH_OPEN && g == GATE_LOWER) return GATE_OFF;
    if (up == PLANT_SWITCH_SHORT && g == GATE_OFF) return GATE_UPPER;
    if (lo == PLANT_SWITCH_SHORT && g == GATE_OFF) return GATE_LOWER;
    return g;
}

// Shoot-through in leg x at gate state g: a shorted device while the complement's gate is on.
inline bool shoot_through(const LegFaults &f, int x, int g) {
    return (f.sw[x][1] == PLANT_SWITCH_SHORT && g == GATE_LOWER) ||
           (f.sw[x][0] == PLANT_SWITCH_SHORT && g == GATE_UPPER);
}

// Paths and coefficients of every leg in every gate state, [leg][Gate]; r_circuit is the machine's
// circuit resistance, (v_alpha, v_beta) the ideal inverter's voltages, f the faults (nullptr: none).
// Each phase is on its leg (through the devices the faults leave), on the capacitor mid-point (the
// FSTP's phase A; a phase the relay ties there) or disconnected (an open leg). At creation,
// whenever the ideal inverter's voltages change and whenever a fault or the relay changes.
void build_leg_table(const plant_params_t &p, double r_circuit, double v_alpha, double v_beta, const LegFaults *f,
                     Leg tab[3][3]);

// Commands, gate states and switching instants of the three legs.
struct LegSchedule {
    int cmd[3];          // command, 1 = upper device on
    int enable;
    int override_mode[3];  // plant_leg_override_t
    int gate[3];         // gate state in force now
    int gate_target[3];  // gate state after the dead time
    double dead_end[3];  // absolute time the dead time ends (<= t: none)
    // Switching instants of the next advance (plant_set_leg_edges): leg x's command toggles at
    // edge_t[x][k], k < edge_n[x], seconds from the advance's start; during the advance
    // edge_abs[x][k] are absolute times and edge_k[x] the next one due.
    int edge_n[3];
    int edge_k[3];
    int hw_off;          // the gate drivers' desaturation latch holds every gate off
    double edge_t[3][PLANT_LEG_EDGES_MAX];
    double edge_abs[3][PLANT_LEG_EDGES_MAX];
};

// The gate state leg x's command asks for (override, enable, command cmd).
inline int wanted_gate(const LegSchedule &s, int cmd, int x) {
    if (s.hw_off) return GATE_OFF;
    if (s.override_mode[x] == PLANT_LEG_DIODE_ONLY) return GATE_OFF;
    if (s.override_mode[x] == PLANT_LEG_UPPER_ON) return GATE_UPPER;
    if (s.override_mode[x] == PLANT_LEG_LOWER_ON) return GATE_LOWER;
    if (!s.enable) return GATE_OFF;
    return cmd ? GATE_UPPER : GATE_LOWER;
}

// Gate timeline of one leg (gate in force, target, dead time's end) after its command asks for
// gate `want` at time t: the outgoing device turns off at once, the incoming one after the dead
// time; in between only the diodes conduct, the current sign picking which (Hoang/inverter
// practice).
inline void gate_timeline(int want, const plant_params_t &p, double t, int &gate, int &gate_target,
                          double &dead_end) {
    // Resolve a dead time still running from the previous command.
    if (dead_end > t) {
        // Still off; the new target replaces the old one, dead time keeps running.
        gate_target = want;
        if (want == GATE_OFF) dead_end = t;
        return;
    }
    const int cur = gate;
    if (want == cur) return;
    const bool both_on = (cur != GATE_OFF) && (want != GATE_OFF);
    if (both_on && p.dead_time_enabled && p.dead_time_s > 0.0) {
        gate = GATE_OFF;
        gate_target = want;
        dead_end = t + p.dead_time_s;
    } else {
        gate = want;
        gate_target = want;
    }
}

// Gate timeline of leg x after its command (cmd, enable, override) changed at time t. Used at the
// start of an advance and at every switching instant inside it (plant_set_leg_edges).
inline void command_leg(LegSchedule &s, const plant_params_t &p, double t, int x) {
    gate_timeline(wanted_gate(s, s.cmd[x], x), p, t, s.gate[x], s.gate_target[x], s.dead_end[x]);
}

// Parameters of the inverter and its devices (nullptr: valid).
const char *check_inverter(const plant_params_t &p);

}  // namespace plant_model

#endif  // DTC_MODEL_INVERTER_H
