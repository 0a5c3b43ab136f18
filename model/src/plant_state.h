// plant_state.h - the plant's state vector (layout shared by the machine, the circuit and the
// integrator) and the constants every unit uses. SI units.
#ifndef DTC_MODEL_PLANT_STATE_H
#define DTC_MODEL_PLANT_STATE_H

#include <Eigen/Core>

namespace plant_model {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSqrt3 = 1.73205080756887729353;
constexpr double kRpmToRadS = 2.0 * kPi / 60.0;

// State vector layout. S_MACH0, S_MACH1: the machine's own states (induction machine: rotor flux
// alpha / beta; unused by the PM machine, held at 0).
enum : int {
    S_IA = 0, S_IB, S_IC, S_THETA, S_OMEGA, S_VCLO, S_VCHI, S_MACH0, S_MACH1,
    S_EDC, S_ECU, S_EDEV, S_EFRIC, S_ELOAD, S_ERDC, S_IVA0, S_IVB0, S_IVC0, S_ELINK, S_I2, S_QA, S_QB,
    NS
};
// The first ND states are dynamic (they enter the right-hand side); the rest are quadratures
// (energy accounts, terminal-voltage integrals, the integrals of the phase currents A and B and of
// the squared phase currents) that RK4 integrates with the same weights, so
// the intermediate stage states only need their first ND entries.
constexpr int ND = S_MACH1 + 1;
constexpr int kMachineStates = S_MACH1 - S_MACH0 + 1;  // state slots a machine may use
using Vec = Eigen::Matrix<double, NS, 1>;

// What a machine reports with the state (plant_get_state; machine.h).
struct MachineReport {
    double psi_alpha, psi_beta;      // stator flux linkage, Wb
    double psi_r_alpha, psi_r_beta;  // rotor flux linkage (induction machine), Wb; else 0
    double te;                       // electromagnetic torque, N*m
    double e_magnetic;               // stored magnetic energy, J
};

}  // namespace plant_model

#endif  // DTC_MODEL_PLANT_STATE_H
