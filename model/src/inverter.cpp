// inverter.cpp - leg paths per gate state and the inverter's parameter check (inverter.h).
#include "inverter.h"

#include <cmath>
#include <cstring>

#include "plant_state.h"

namespace plant_model {
namespace {

// Coefficients of a phase for one path (conducting) or blocked.
PhaseCoef phase_coef(double r_circuit, const Leg &L, const Path &pa, bool blk, double vsrc) {
    PhaseCoef k;
    k.cond = blk ? 0.0 : 1.0;
    k.a_lo = (pa.rail == RAIL_PLUS || pa.rail == RAIL_MID) ? 1.0 : 0.0;
    k.a_hi = (pa.rail == RAIL_PLUS) ? 1.0 : 0.0;
    k.c = ((pa.rail == RAIL_SRC) ? vsrc : 0.0) - pa.d;
    k.r = pa.r;
    k.rtot = r_circuit + pa.r;
    k.dev = (L.device && !blk) ? 1.0 : 0.0;
    k.dev_d = pa.d;
    k.plus = (!blk && pa.rail == RAIL_PLUS) ? 1.0 : 0.0;
    k.mid = (!blk && pa.rail == RAIL_MID) ? 1.0 : 0.0;
    k.src = (!blk && pa.rail == RAIL_SRC) ? 1.0 : 0.0;
    k.pd = k.dev * k.dev_d;
    k.pr = k.dev * k.r;
    return k;
}

}  // namespace

void build_leg_table(const plant_params_t &p, double r_circuit, double v_alpha, double v_beta, const LegFaults *f,
                     Leg tab[3][3]) {
    const double vce = p.drops_enabled ? p.v_ce_v : 0.0;
    const double vd = p.drops_enabled ? p.v_d_v : 0.0;
    const double ron = p.drops_enabled ? p.r_on_ohm : 0.0;
    double vsrc[3] = {0.0, 0.0, 0.0};
    if (p.inverter == PLANT_INVERTER_IDEAL) {
        // Ideal source: phase voltages from the inverse amplitude-invariant Clarke transform.
        const double va = v_alpha, vb = v_beta;
        vsrc[0] = va;
        vsrc[1] = -0.5 * va + 0.5 * kSqrt3 * vb;
        vsrc[2] = -0.5 * va - 0.5 * kSqrt3 * vb;
    }
    for (int x = 0; x < 3; ++x)
    for (int gate = 0; gate < 3; ++gate) {
        Leg &L = tab[x][gate];
        if (p.inverter == PLANT_INVERTER_IDEAL) {
            L.pos = L.neg = Path{RAIL_SRC, 0.0, 0.0};
            L.sign_dep = false;
            L.device = false;
        } else if ((p.inverter == PLANT_INVERTER_FSTP && x == 0) || (f && f->relay_closed == x + 1)) {
            // Hoang Fig. 1(b): no device in phase A; a phase the relay ties to the mid-point is the
            // same circuit (the relay's contact resistance is neglected).
            L.pos = L.neg = Path{RAIL_MID, 0.0, 0.0};
            L.sign_dep = false;
            L.device = false;
        } else if (f && f->open[x]) {
            // Disconnected: at zero current the terminal may float anywhere (circuit.h keeps the
            // phase blocked); no path conducts.
            L.pos = Path{RAIL_ZERO, kOpenPathV, 0.0};
            L.neg = Path{RAIL_ZERO, -kOpenPathV, 0.0};
            L.sign_dep = true;
            L.device = false;
        } else {
            L.device = true;
            switch (f ? effective_gate(*f, x, gate) : gate) {
                case GATE_UPPER:  // Hoang Table III state 1: + -> V_CE, - -> -V_d
                    L.pos = Path{RAIL_PLUS, vce, ron};
                    L.neg = Path{RAIL_PLUS, -vd, ron};
                    break;
                case GATE_LOWER:  // Hoang Table III state 0: + -> V_d, - -> -V_CE
                    L.pos = Path{RAIL_ZERO, vd, ron};
                    L.neg = Path{RAIL_ZERO, -vce, ron};
                    break;
                default:  // both gates off: the current sign picks the diode
                    L.pos = Path{RAIL_ZERO, vd, ron};
                    L.neg = Path{RAIL_PLUS, -vd, ron};
                    break;
            }
            L.sign_dep = !(L.pos.rail == L.neg.rail && L.pos.d == L.neg.d && L.pos.r == L.neg.r);
        }
        L.coef[PH_POS] = phase_coef(r_circuit, L, L.pos, false, vsrc[x]);
        L.coef[PH_NEG] = phase_coef(r_circuit, L, L.neg, false, vsrc[x]);
        L.coef[PH_BLOCKED] = phase_coef(r_circuit, L, L.pos, true, vsrc[x]);
    }
    for (int x = 0; x < 3; ++x)
        for (int g = 0; g < 3; ++g)
            for (int g2 = 0; g2 < 3; ++g2)
                for (int m = 0; m < 2; ++m)
                    tab[x][g].same_as[g2][m] =
                        std::memcmp(&tab[x][g].coef[m], &tab[x][g2].coef[m], sizeof(PhaseCoef)) == 0;
}

const char *check_inverter(const plant_params_t &p) {
    auto bad = [](double v) { return !std::isfinite(v); };
    if (p.inverter != PLANT_INVERTER_IDEAL && p.inverter != PLANT_INVERTER_SSTP && p.inverter != PLANT_INVERTER_FSTP)
        return "inverter must be PLANT_INVERTER_IDEAL, _SSTP or _FSTP";
    if (bad(p.vdc_v) || p.vdc_v <= 0.0) return "vdc_v must be finite and > 0";
    if (bad(p.v_ce_v) || p.v_ce_v < 0.0) return "v_ce_v must be finite and >= 0";
    if (bad(p.v_d_v) || p.v_d_v < 0.0) return "v_d_v must be finite and >= 0";
    if (bad(p.r_on_ohm) || p.r_on_ohm < 0.0) return "r_on_ohm must be finite and >= 0";
    if (bad(p.dead_time_s) || p.dead_time_s < 0.0 || p.dead_time_s > 20e-6)
        return "dead_time_s must be in [0, 20e-6]";
    return nullptr;
}

}  // namespace plant_model
