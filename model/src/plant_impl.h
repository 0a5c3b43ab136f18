// plant_impl.h - the plant object behind the C ABI (plant.h): the parts it is made of (machine,
// inverter legs, DC link, shaft) and the integrator's state.
#ifndef DTC_MODEL_PLANT_IMPL_H
#define DTC_MODEL_PLANT_IMPL_H

#include "dc_link.h"
#include "inverter.h"
#include "machine.h"
#include "mechanics.h"
#include "plant.h"
#include "plant_state.h"

namespace plant_model {

// Integrator of one sub-step: classical RK4, the explicit midpoint rule (short segments) or
// Ralston's third-order rule (medium segments between switching instants).
enum StepMethod : int { STEP_RK4 = 0, STEP_MIDPOINT = 1, STEP_RK3 = 2 };

// Which phases conduct, and how (PhaseMode per phase).
struct ConductionMode {
    int ph[3];
};

// The right-hand side's coefficients for one conduction mode, so the right-hand side is
// branch-light.
struct ConductionCoefs {
    int nk;             // conducting phases
    double inv_nk;
    const PhaseCoef *ph[3];  // into the legs in force (valid until the next set_legs_in_force)
};

}  // namespace plant_model

struct plant {
    plant_params_t p;
    double pp;  // pole pairs as a double
    // The machine (machine.h) and the per-phase circuit's constants it sets: 1/L, (2/3)/L, (1/3)/L
    // for L = circuit_inductance(), and R = circuit_resistance().
    plant_model::Machine machine;
    double inv_l, inv_l_2_3, inv_l_1_3;
    double r_ph;
    // Inverter: commands and gate timeline, the ideal inverter's voltages, the leg overrides.
    plant_model::LegSchedule schedule;
    double v_set_alpha, v_set_beta;
    plant_model::Leg leg_tab[3][3];     // [leg][Gate]: paths and coefficients, built at creation
    const plant_model::Leg *legs[3];    // legs in force: &leg_tab[x][gate[x]]
    // DC link and shaft.
    dclink::DcLink link;
    mech::Shaft shaft;
    // Integrator.
    double t;
    plant_model::Vec y;
    double last_dt;
    plant_model::ConductionMode mode;
    plant_model::ConductionCoefs coefs;
    bool coefs_valid;  // coefs match coefs_mode and the legs in force
    plant_model::ConductionMode coefs_mode;
    plant_model::StepMethod step_method;  // the integrator of the step being taken (integrator.cpp)
    plant_stats_t stats;
    bool energy;  // the energy accounts are integrated (plant_set_energy_accounts; circuit.h rhs_t)
    // Faults and the reconfiguration relay (plant.h). any_fault: a switch fault, an open
    // leg, a relay command or a desaturation latch exists (without one the fault checks are skipped).
    plant_model::LegFaults faults;
    bool any_fault;
    int relay_cmd;            // coil command 0..3
    double relay_due;         // absolute time the contacts reach relay_cmd (relay_pending)
    bool relay_pending;
    int desat_mask;
    double desat_t;
};

namespace plant_model {

// The gate drivers' desaturation detection (plant.h, PLANT_SWITCH_SHORT): latched on leg x at the
// present time; every gate off at once, whatever dead time was running.
inline void latch_desat(plant_t *pl, int x) {
    if (pl->desat_mask == 0) pl->desat_t = pl->t;
    pl->desat_mask |= 1 << x;
    LegSchedule &ls = pl->schedule;
    ls.hw_off = 1;
    for (int j = 0; j < 3; ++j) {
        ls.gate[j] = ls.gate_target[j] = GATE_OFF;
        ls.dead_end[j] = pl->t;
    }
}

// Legs in force from the gate states. With faults: a shoot-through (a shorted device with its
// complement's gate on) or a gated device in a leg whose phase the relay ties to the mid-point
// latches the desaturation trip first, at this instant (the gate states change only at the
// breakpoints the integrator lands on, so this is the instant the complement turns on).
inline void set_legs_in_force(plant_t *pl) {
    pl->coefs_valid = false;
    if (pl->any_fault) {
        const LegSchedule &ls = pl->schedule;
        for (int x = 0; x < 3; ++x) {
            const bool relay_short = pl->faults.relay_closed == x + 1 && ls.gate[x] != GATE_OFF &&
                                     !(pl->p.inverter == PLANT_INVERTER_FSTP && x == 0);
            if (shoot_through(pl->faults, x, ls.gate[x]) || relay_short) latch_desat(pl, x);
        }
    }
    for (int x = 0; x < 3; ++x) pl->legs[x] = &pl->leg_tab[x][pl->schedule.gate[x]];
}

// Integrator (integrator.cpp): advances the plant by dt_s (plant_advance).
void advance(plant_t *pl, double dt_s);
// Circuit (circuit.cpp): the phases held at zero current at the present state (bit x: phase x),
// and the link's terminal voltages.
int blocked_mask(plant_t *pl);
void link_terminals(const plant_t *pl, double &tv_lo, double &tv_hi);

}  // namespace plant_model

#endif  // DTC_MODEL_PLANT_IMPL_H
