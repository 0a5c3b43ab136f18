// mechanics.h - the shaft: inertia, viscous and Coulomb friction and the load laws (docs/plant.md,
// "Mechanics and loads"). SI units.
//   J domega_m/dt = T_e - b omega_m - T_load - T_coulomb   (a speed load holds omega_m instead)
#ifndef DTC_MODEL_MECHANICS_H
#define DTC_MODEL_MECHANICS_H

#include <algorithm>
#include <cmath>

#include "plant.h"

namespace mech {

// Coulomb friction torque (opposing the motion): +-tc while turning; at exactly zero speed the
// static friction that holds the rotor, i.e. the net driving torque td clamped to [-tc, tc] (the
// rotor stays stuck while |td| <= tc and breaks away with td - tc sign(td) otherwise).
inline double coulomb_torque(double tc, double omega, double td) {
    if (omega > 0.0) return tc;
    if (omega < 0.0) return -tc;
    return std::min(tc, std::max(-tc, td));
}

// Shaft constants and the load law as a linear form, so the right-hand side has no branch on the
// load kind:  T_load = c0 + cw omega + cte T_e (+ cq omega |omega| for the fan load);
// domega/dt = w_on (T_e - b omega - T_load) / J (w_on = 0: the speed load holds the speed).
struct Shaft {
    double c0, cw, cte, w_on;
    double cq;         // fan load: used only when fan_on
    bool fan_on;       // PLANT_LOAD_FAN
    bool coulomb_on;   // coulomb_nm > 0
    double b, coulomb_nm, j, inv_j;
    double omega_load_ref;  // rad/s of load_speed_rpm (generator and fan laws)
};

// Inertia and friction from the parameters.
inline void setup(const plant_params_t &p, Shaft &s) {
    s.b = p.b_nm_s_per_rad;
    s.coulomb_nm = p.coulomb_nm;
    s.coulomb_on = p.coulomb_nm > 0.0;
    s.j = p.j_kgm2;
    s.inv_j = 1.0 / p.j_kgm2;
}

// The load law for (p.load, p.load_speed_rpm, p.load_torque_nm) with the generator / fan
// reference speed omega_ref (rad/s).
void set_load_law(const plant_params_t &p, double omega_ref, Shaft &s);

// Load torque (T_load, including what a speed load supplies) and the shaft's derivatives at speed
// omega with torque te: domega/dt and the friction power. With Coulomb friction its direction is
// that of omega0, the speed at the start of the integration step (every evaluation within a step
// starts from it), so a step's stages never see the jump; the integrator stops the rotor where
// the speed crosses zero (stop_at_zero_crossing). A held speed (speed load) makes the dynamometer
// supply the friction (cte = 1 there).
inline void shaft_derivatives(const Shaft &s, double omega, double omega0, double te, double &tl, double &domega,
                              double &p_friction) {
    const double b = s.b;
    tl = s.c0 + s.cw * omega + s.cte * te;
    if (s.fan_on) tl += s.cq * omega * std::fabs(omega);
    if (!s.coulomb_on) {
        domega = s.w_on * (te - b * omega - tl) * s.inv_j;
        p_friction = b * omega * omega;
    } else {
        const double tf = coulomb_torque(s.coulomb_nm, omega0, te - b * omega - tl);
        tl -= s.cte * tf;
        domega = s.w_on * (te - b * omega - tl - tf) * s.inv_j;
        p_friction = (b * omega + tf) * omega;
    }
}

// Load torque at speed omega with torque te, as shaft_derivatives() computes it (reported state).
inline double load_torque(const Shaft &s, double omega, double te) {
    double tl = s.c0 + s.cw * omega + s.cte * te;
    if (s.fan_on) tl += s.cq * omega * std::fabs(omega);
    if (s.coulomb_on) tl -= s.cte * coulomb_torque(s.coulomb_nm, omega, te - s.b * omega - tl);
    return tl;
}

// With Coulomb friction (direction frozen over the step, see shaft_derivatives) a speed that
// changes sign within the step from w0 is set to exactly zero at the step's end (w1); the next
// step then either holds the rotor or breaks away (coulomb_torque). The kinetic energy removed
// goes to the friction account e_fric, so the energy balance stays closed; the local error is one
// step's worth of the zero crossing (docs/plant.md, "Mechanics").
inline void stop_at_zero_crossing(const Shaft &s, double w0, double &w1, double &e_fric) {
    if (s.coulomb_on && s.w_on != 0.0) {
        if ((w0 > 0.0 && w1 < 0.0) || (w0 < 0.0 && w1 > 0.0)) {
            e_fric += 0.5 * s.j * w1 * w1;
            w1 = 0.0;
        }
    }
}

// Parameters of the shaft and the load (nullptr: valid); the load's after the link's, as
// plant_create reports them.
const char *check_shaft(const plant_params_t &p);
const char *check_load(const plant_params_t &p);

}  // namespace mech

#endif  // DTC_MODEL_MECHANICS_H
