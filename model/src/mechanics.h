// mechanics.h - shaft friction laws of the plant (docs/plant.md, "Mechanics and loads").
#ifndef DTC_MODEL_MECHANICS_H
#define DTC_MODEL_MECHANICS_H

#include <algorithm>

namespace mech {

// Coulomb friction torque (opposing the motion): +-tc while turning; at exactly zero speed the
// static friction that holds the rotor, i.e. the net driving torque td clamped to [-tc, tc] (the
// rotor stays stuck while |td| <= tc and breaks away with td - tc sign(td) otherwise).
inline double coulomb_torque(double tc, double omega, double td) {
    if (omega > 0.0) return tc;
    if (omega < 0.0) return -tc;
    return std::min(tc, std::max(-tc, td));
}

}  // namespace mech

#endif  // DTC_MODEL_MECHANICS_H
