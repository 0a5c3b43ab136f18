// circuit.h - the shared per-phase circuit: the plant's right-hand side, assembled from the
// machine (machine.h), the inverter's conduction paths (inverter.h), the DC link (dc_link.h) and
// the shaft (mechanics.h), and the choice of conduction mode when a current is exactly zero.
//
//   L di_x/dt = v_x0 - v_n0 - (R + r_path) i_x - e_x,  star connection, isolated neutral:
//   sum(i_x) = 0 and v_n0 follows (Hoang eqs. 1-3). L, R, e_x: the machine's; v_x0 = the
//   conducting path's voltage (rail - v_f), r_path its resistance (Hoang Table III, eq. 20).
// A phase whose floating terminal voltage lies inside its leg's zero-current interval stays at
// exactly zero current (no chatter): a small complementarity problem solved by enumeration
// whenever a current sits at zero (select_mode). docs/plant.md, section 1.
#ifndef DTC_MODEL_CIRCUIT_H
#define DTC_MODEL_CIRCUIT_H

#include <algorithm>
#include <cmath>

#include "plant_impl.h"

namespace plant_model {

// Quantities of one right-hand-side evaluation beside the derivatives (event function).
struct RhsOutputs {
    double te, tload, vn0;
    double vx0[3];
    double e[3];
};

// Link terminal voltages at state y (the rail currents from the current signs; a zero current
// draws nothing whatever its path).
inline void dc_link_terminals(const plant_t *pl, const Vec &y, double &tv_lo, double &tv_hi) {
    double ip = 0.0, im = 0.0;
    for (int x = 0; x < 3; ++x) {
        const double i = y[S_IA + x];
        if (i == 0.0) continue;
        const Path &pa = (i > 0.0) ? pl->legs[x]->pos : pl->legs[x]->neg;
        if (pa.rail == RAIL_PLUS) ip += i;
        else if (pa.rail == RAIL_MID) im += i;
    }
    dclink::LinkNodes n;
    dclink::dc_link_nodes(pl->link.rc, y[S_VCLO], y[S_VCHI], ip, im, n);
    tv_lo = n.tv_lo;
    tv_hi = n.tv_hi;
}

// Voltages of the rails each phase can be tied to, at state y: rv[x] for phase x (the link's
// terminal voltages are formed once for the three).
inline void rails_all(const plant_t *pl, const Vec &y, double rv[3][4]) {
    double plus, mid;
    if (pl->link.rc.on) {
        double lo, hi;
        dc_link_terminals(pl, y, lo, hi);
        plus = lo + hi;
        mid = lo;
    } else {
        plus = y[S_VCLO] + y[S_VCHI];
        mid = y[S_VCLO];
    }
    double src[3] = {0.0, 0.0, 0.0};
    if (pl->p.inverter == PLANT_INVERTER_IDEAL) {
        // Ideal source: phase voltages from the inverse amplitude-invariant Clarke transform.
        const double va = pl->v_set_alpha, vb = pl->v_set_beta;
        src[0] = va;
        src[1] = -0.5 * va + 0.5 * kSqrt3 * vb;
        src[2] = -0.5 * va - 0.5 * kSqrt3 * vb;
    }
    for (int x = 0; x < 3; ++x) {
        rv[x][RAIL_ZERO] = 0.0;
        rv[x][RAIL_PLUS] = plus;
        rv[x][RAIL_MID] = mid;
        rv[x][RAIL_SRC] = src[x];
    }
}

// Voltages of the rails phase x can be tied to, at state y.
inline void rails(const plant_t *pl, const Vec &y, double rv[4], int x) {
    double all[3][4];
    rails_all(pl, y, all);
    for (int r = 0; r < 4; ++r) rv[r] = all[x][r];
}

inline void make_coefs(const plant_t *pl, const ConductionMode &m, ConductionCoefs &q) {
    q.nk = 0;
    for (int x = 0; x < 3; ++x) {
        q.ph[x] = &pl->legs[x]->coef[m.ph[x]];
        if (m.ph[x] != PH_BLOCKED) ++q.nk;
    }
    static const double inv_n[4] = {0.0, 1.0, 0.5, 1.0 / 3.0};
    q.inv_nk = inv_n[q.nk];
}

// Neutral voltage when every phase is blocked: centre of the feasible range.
inline double vn0_all_blocked(const plant_t *pl, const Vec &y, const double e[3]) {
    double lo = -1e300, hi = 1e300;
    double rvx[3][4];
    rails_all(pl, y, rvx);
    for (int x = 0; x < 3; ++x) {
        const double *rv = rvx[x];
        const double a = path_v(pl->legs[x]->pos, rv), b = path_v(pl->legs[x]->neg, rv);
        lo = std::max(lo, std::min(a, b) - e[x]);
        hi = std::min(hi, std::max(a, b) - e[x]);
    }
    return 0.5 * (lo + hi);
}

// Right-hand side for a fixed conduction mode (pl->coefs must match the mode) with machine m.
// Only the first ND entries of y are read. Branch-free apart from the all-blocked neutral
// (ConductionCoefs, dclink::LinearLink and mech::Shaft hold the linear forms of the paths, the DC
// link and the load). kAll: all three phases conduct (the common case; the blocked-phase terms
// drop out). kEnergy: the energy accounts' terms (plant_set_energy_accounts); without them their
// derivatives are 0 and nothing else changes. Every quantity is formed in locals and dy is written at the end: a store into dy
// may alias the coefficients (all doubles), so stores in between would make the compiler load
// them again.
template <class M, bool kAll, bool kEnergy>
inline void rhs_t(plant_t *pl, const M &m, const Vec &y, Vec &dy, RhsOutputs *aux) {
    ++pl->stats.evals;
    const ConductionCoefs &q = pl->coefs;
    const PhaseCoef *const *k = q.ph;
    const double omega = y[S_OMEGA];
    const double omega_e = pl->pp * omega;
    double e[3];
    typename M::Work work;
    m.emf(y, omega_e, e, work);
    const double vlo = y[S_VCLO], vhi = y[S_VCHI];
    const double ix[3] = {y[S_IA], y[S_IB], y[S_IC]};
    // Currents drawn from the plus rail and from the mid-point (the link's inputs).
    double i_plus = 0.0, i_mid = 0.0;
#pragma GCC unroll 3
    for (int x = 0; x < 3; ++x) {
        i_plus += k[x]->plus * ix[x];
        i_mid += k[x]->mid * ix[x];
    }
    // Rail voltages: the capacitor voltages, or with ESR / balancing resistors the link's node
    // voltages (dclink::LinkRC), which depend on the currents the inverter draws.
    const bool rc = pl->link.rc.on;
    double tvlo = vlo, tvhi = vhi;
    dclink::LinkNodes ln;
    if (rc) {
        dclink::dc_link_nodes(pl->link.rc, vlo, vhi, i_plus, i_mid, ln);
        tvlo = ln.tv_lo;
        tvhi = ln.tv_hi;
    }
    double vp[3], u[3];
#pragma GCC unroll 3
    for (int x = 0; x < 3; ++x) {
        vp[x] = k[x]->a_lo * tvlo + k[x]->a_hi * tvhi + k[x]->c;
        u[x] = vp[x] - k[x]->rtot * ix[x] - e[x];  // L di/dt + v_n0 of a conducting phase
    }
    double vn0;
    if (kAll) {
        vn0 = (u[0] + u[1] + u[2]) * (1.0 / 3.0);
    } else {
        const double sum = k[0]->cond * u[0] + k[1]->cond * u[1] + k[2]->cond * u[2];
        vn0 = (q.nk >= 2) ? sum * q.inv_nk : vn0_all_blocked(pl, y, e);
    }
    const double inv_l = pl->inv_l, inv_l_2_3 = pl->inv_l_2_3, inv_l_1_3 = pl->inv_l_1_3;
    // Only the ideal inverter's sources deliver power of their own (LinearLink::pdc_src = 1, every
    // other kind 0 with PhaseCoef::src = 0): the switching inverters skip the term.
    const dclink::LinearLink &g = pl->link.lin;
    const bool src = g.pdc_src != 0.0;
    double di[3], vx0[3];
    double p_cu = 0.0, p_dev = 0.0, p_src = 0.0;
#pragma GCC unroll 3
    for (int x = 0; x < 3; ++x) {
        const double i = ix[x];
        const double vc = vp[x] - k[x]->r * i;
        if (kAll) {
            // (u_x - vn0) / L with vn0 = mean(u), written so that u_x does not wait for the sum.
            di[x] = inv_l_2_3 * u[x] - inv_l_1_3 * (u[(x + 1) % 3] + u[(x + 2) % 3]);
            vx0[x] = vc;
        } else {
            di[x] = k[x]->cond * (u[x] - vn0) * inv_l;
            vx0[x] = k[x]->cond * vc + (1.0 - k[x]->cond) * (vn0 + e[x]);  // blocked: floating terminal
        }
        if (kEnergy) {
            p_dev += (k[x]->pd + k[x]->pr * i) * i;
            if (src) p_src += k[x]->src * vc * i;
        }
        p_cu += i * i;
    }
    if constexpr (M::kKind == PLANT_MACHINE_PM) {
        if (m.salient()) {
            const double cond[3] = {kAll ? 1.0 : k[0]->cond, kAll ? 1.0 : k[1]->cond, kAll ? 1.0 : k[2]->cond};
            m.salient_di(kAll ? 3 : q.nk, cond, ix, omega_e, work, e, di, vx0, vn0);
        }
    }
    // DC link.
    double i_s, dv_hi, dv_lo, p_link;
    if (!rc) {
        i_s = g.is_g * (pl->p.vdc_v - (vlo + vhi));
        dv_hi = g.hi_s * i_s - g.hi_p * i_plus;
        dv_lo = g.lo_s * i_s - g.lo_p * i_plus - g.lo_m * i_mid;
        p_link = 0.0;
    } else {
        i_s = ln.i_s;
        dv_hi = ln.dv_hi;
        dv_lo = ln.dv_lo;
        p_link = ln.p_loss;
    }
    double p_dc = 0.0, p_rdc = 0.0, p_cu_stator = 0.0;
    if (kEnergy) {
        p_dc = g.pdc_s * i_s + g.pdc_st * ((vlo + vhi) * i_plus + vlo * i_mid);
        if (src) p_dc += g.pdc_src * p_src;
        p_rdc = g.r_dc * i_s * i_s;
        p_cu_stator = m.stator_resistance() * p_cu;
    }
    // The machine's torque and own states (it writes dy[S_MACH0..1]), then the shaft.
    double te, p_machine;
    m.torque_and_states(y, ix, omega_e, work, dy, te, p_machine);
    double tl, p_fric, domega;
    mech::shaft_derivatives(pl->shaft, omega, pl->y[S_OMEGA], te, tl, domega, p_fric);
#pragma GCC unroll 3
    for (int x = 0; x < 3; ++x) dy[S_IA + x] = di[x];
    dy[S_THETA] = omega;
    dy[S_OMEGA] = domega;
    dy[S_EFRIC] = p_fric;
    dy[S_VCHI] = dv_hi;
    dy[S_VCLO] = dv_lo;
    dy[S_ELINK] = kEnergy ? p_link : 0.0;
    dy[S_EDC] = p_dc;
    dy[S_ECU] = kEnergy ? p_cu_stator + p_machine : 0.0;
    dy[S_EDEV] = p_dev;
    dy[S_ELOAD] = kEnergy ? tl * omega : 0.0;
    dy[S_ERDC] = p_rdc;
    dy[S_I2] = p_cu;
    dy[S_QA] = ix[0];
    dy[S_QB] = ix[1];
    dy[S_IVA0] = vx0[0];
    dy[S_IVB0] = vx0[1];
    dy[S_IVC0] = vx0[2];
    if (aux) {
        aux->te = te;
        aux->tload = tl;
        aux->vn0 = vn0;
        for (int x = 0; x < 3; ++x) {
            aux->vx0[x] = vx0[x];
            aux->e[x] = e[x];
        }
    }
}

template <class M>
inline void rhs(plant_t *pl, const M &m, const Vec &y, Vec &dy, RhsOutputs *aux) {
    if (pl->coefs.nk == 3) {
        if (pl->energy) rhs_t<M, true, true>(pl, m, y, dy, aux);
        else rhs_t<M, true, false>(pl, m, y, dy, aux);
    } else {
        if (pl->energy) rhs_t<M, false, true>(pl, m, y, dy, aux);
        else rhs_t<M, false, false>(pl, m, y, dy, aux);
    }
}

// Conduction mode at state y. Currents that are exactly zero on a sign-dependent leg are resolved
// by enumerating {blocked, +, -} and keeping the consistent assignment (Filippov / linear
// complementarity; the leg characteristics are monotone so the consistent one is unique up to
// ties, which are broken towards "blocked" so a zero current never chatters).
template <class M>
ConductionMode select_mode(plant_t *pl, const M &mach, const Vec &y) {
    ConductionMode m;
    int zl[3], nz = 0;
    for (int x = 0; x < 3; ++x) {
        const double i = y[S_IA + x];
        if (i > 0.0) m.ph[x] = PH_POS;
        else if (i < 0.0) m.ph[x] = PH_NEG;
        else { m.ph[x] = PH_POS; zl[nz++] = x; }
    }
    if (nz == 0) return m;
    ++pl->stats.mode_selects;
    double e[3], rv[3][4];
    mach.emf_exact(y, e);
    rails_all(pl, y, rv);
    int ncand = 1;
    for (int k = 0; k < nz; ++k) ncand *= 3;
    double best_v = 1e300;
    ConductionMode best = m;
    for (int c = 0; c < ncand; ++c) {
        ConductionMode t = m;
        int code = c;
        bool skip = false;
        for (int k = 0; k < nz; ++k) {
            const int digit = code % 3;
            code /= 3;
            const int x = zl[k];
            if (digit == 0) t.ph[x] = PH_BLOCKED;
            else if (digit == 1) t.ph[x] = PH_POS;
            else {
                if (!pl->legs[x]->sign_dep) { skip = true; }  // same as PH_POS
                t.ph[x] = PH_NEG;
            }
        }
        if (skip) continue;
        int nk = 0;
        double sum = 0.0, vp[3] = {0, 0, 0}, rr[3] = {0, 0, 0};
        for (int x = 0; x < 3; ++x) {
            if (t.ph[x] == PH_BLOCKED) continue;
            const Path &pa = (t.ph[x] == PH_POS) ? pl->legs[x]->pos : pl->legs[x]->neg;
            vp[x] = path_v(pa, rv[x]);
            rr[x] = pa.r;
            sum += vp[x] - (pl->r_ph + rr[x]) * y[S_IA + x] - e[x];
            ++nk;
        }
        if (nk == 1) continue;
        double viol = 0.0;
        if (nk == 0) {
            double lo = -1e300, hi = 1e300;
            for (int x = 0; x < 3; ++x) {
                const double a = path_v(pl->legs[x]->pos, rv[x]), b = path_v(pl->legs[x]->neg, rv[x]);
                lo = std::max(lo, std::min(a, b) - e[x]);
                hi = std::min(hi, std::max(a, b) - e[x]);
            }
            viol = std::max(0.0, lo - hi);
        } else {
            double vn0 = sum / nk;
            // L di/dt of each phase and a blocked phase's floating voltage (the circuit's scalar L;
            // a salient PM's from its inductance matrix, as in rhs_t)
            double ldi[3], vfl[3];
            for (int x = 0; x < 3; ++x) {
                const bool on = t.ph[x] != PH_BLOCKED;
                ldi[x] = on ? vp[x] - (pl->r_ph + rr[x]) * y[S_IA + x] - e[x] - vn0 : 0.0;
                vfl[x] = vn0 + e[x];
            }
            if constexpr (M::kKind == PLANT_MACHINE_PM) {
                if (mach.salient()) {
                    const double cond[3] = {t.ph[0] != PH_BLOCKED ? 1.0 : 0.0, t.ph[1] != PH_BLOCKED ? 1.0 : 0.0,
                                            t.ph[2] != PH_BLOCKED ? 1.0 : 0.0};
                    const double lc = mach.circuit_inductance();
                    double di[3] = {ldi[0] / lc, ldi[1] / lc, ldi[2] / lc};
                    const double ix[3] = {y[S_IA], y[S_IB], y[S_IC]};
                    typename M::Work w;
                    mach.salient_work(y, w);
                    mach.salient_di(nk, cond, ix, pl->pp * y[S_OMEGA], w, e, di, vfl, vn0);
                    for (int x = 0; x < 3; ++x) ldi[x] = lc * di[x];
                }
            }
            for (int k = 0; k < nz; ++k) {
                const int x = zl[k];
                if (t.ph[x] == PH_BLOCKED) {
                    const double vf = vfl[x];
                    const double a = path_v(pl->legs[x]->pos, rv[x]), b = path_v(pl->legs[x]->neg, rv[x]);
                    viol += std::max(0.0, std::min(a, b) - vf) + std::max(0.0, vf - std::max(a, b));
                } else if (pl->legs[x]->sign_dep) {
                    const double di = ldi[x];
                    if (t.ph[x] == PH_POS) viol += std::max(0.0, -di);
                    else viol += std::max(0.0, di);
                }
            }
        }
        if (viol < best_v) {
            best_v = viol;
            best = t;
            if (viol == 0.0) break;
        }
    }
    return best;
}

}  // namespace plant_model

#endif  // DTC_MODEL_CIRCUIT_H
