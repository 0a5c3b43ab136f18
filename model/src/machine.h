// machine.h - the seam between the electrical machines and the rest of the plant.
//
// Every machine is seen by the shared per-phase circuit (circuit.h: star connection, isolated
// neutral, the inverter's conduction paths, the DC link) as
//   L di_x/dt = v_x0 - v_n0 - (R + r_path,x) i_x - e_x,   x = a, b, c,   sum_x i_x = 0,
// and by the shaft (mechanics.h) as an electromagnetic torque. A machine is a class that supplies:
//   kKind                        its plant_machine_t value (plant.h);
//   check(params)                message for the first invalid parameter it reads, or nullptr;
//   Machine(params)              constants derived from the parameters;
//   circuit_inductance(), circuit_resistance()   L and R of the circuit above;
//   stator_resistance()          R_s of the copper loss R_s sum i_x^2;
//   begin_step(theta_m, omega_m, h)   once before each integration step (caches);
//   emf(y, omega_e, e, work)     phase EMFs e_x at state y (the right-hand side's first half);
//   torque_and_states(y, i, omega_e, work, dy, te, p_internal)   the torque, the derivatives of its
//                                own states (at most kMachineStates, in y[S_MACH0..]) and any loss
//                                beyond R_s sum i^2 (second half, after the currents are known);
//   emf_exact(y, e)              phase EMFs for conduction-mode selection;
//   report(y, i_alpha, i_beta, r)   flux, torque and magnetic energy for plant_get_state.
// The integrator and the circuit are templates on the machine, so each machine's right-hand side
// is compiled without branches on the machine kind. A further machine is one new header with
// such a class, added to MachineList below (and its plant_machine_t value and parameters in plant.h).
#ifndef DTC_MODEL_MACHINE_H
#define DTC_MODEL_MACHINE_H

#include <variant>

#include "machine_im.h"
#include "machine_pm.h"
#include "plant.h"

namespace plant_model {

template <class... Ms>
struct MachineList {
    using Variant = std::variant<Ms...>;
    // The selected machine's parameter check (nullptr: valid).
    static const char *check(const plant_params_t &p) {
        const char *msg = "machine must be PLANT_MACHINE_PM or PLANT_MACHINE_IM";
        (void)((p.machine == Ms::kKind ? (msg = Ms::check(p), true) : false) || ...);
        return msg;
    }
    // Constructs the selected machine in m (p already checked).
    static void make(const plant_params_t &p, Variant &m) {
        (void)((p.machine == Ms::kKind ? (m.template emplace<Ms>(p), true) : false) || ...);
    }
};

using Machines = MachineList<PmMachine, ImMachine>;
using Machine = Machines::Variant;

}  // namespace plant_model

#endif  // DTC_MODEL_MACHINE_H
