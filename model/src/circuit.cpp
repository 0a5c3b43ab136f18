// circuit.cpp - the circuit's queries for the reported state (circuit.h).
#include "circuit.h"

#include <variant>

namespace plant_model {

int blocked_mask(plant_t *pl) {
    const Vec &y = pl->y;
    int mask = 0;
    if (y[S_IA] == 0.0 || y[S_IB] == 0.0 || y[S_IC] == 0.0) {
        const ConductionMode m = std::visit([&](const auto &mach) { return select_mode(pl, mach, y); }, pl->machine);
        for (int x = 0; x < 3; ++x)
            if (m.ph[x] == PH_BLOCKED) mask |= 1 << x;
    }
    return mask;
}

void link_terminals(const plant_t *pl, double &tv_lo, double &tv_hi) { dc_link_terminals(pl, pl->y, tv_lo, tv_hi); }

}  // namespace plant_model
