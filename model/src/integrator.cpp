// integrator.cpp - time integration of the plant (docs/plant.md, section 2): classical RK4 on
// sub-steps that land exactly on every switching instant and dead-time end at which the right-hand
// side changes (a breakpoint that changes nothing for the present current signs is run through:
// first_change) and on every located current zero crossing / zero-current release (the zero of
// the step's Hermite interpolant as the first trial, then Illinois root finding on the step's own
// solution); the explicit midpoint rule on a
// segment ending at a breakpoint and no longer than max_step/16; with switching instants,
// Ralston's third-order rule on the other segments up to max_step/2. Between events and changing
// breakpoints the right-hand side (circuit.h) is smooth. The functions are templates on the
// machine (machine.h); advance() picks the instance once per call.
#include <algorithm>
#include <cmath>
#include <variant>

#include "circuit.h"




namespace plant_model {
namespace {

// Stage state y0 + c k on the ND dynamic entries, as a scalar loop on purpose: the right-hand
// side stores its outputs one double at a time, and a 16-byte SIMD load spanning two such fresh
// stores cannot be forwarded from the store buffer (a stall on the critical path of every stage;
// ~10 ns per period measured).
#if defined(__GNUC__) && !defined(__clang__)
#define DTC_NO_AUTOVEC __attribute__((optimize("no-tree-vectorize")))
#else
#define DTC_NO_AUTOVEC
#endif
DTC_NO_AUTOVEC inline void stage_state(const Vec &y0, double c, const Vec &k, Vec &yt) {
    for (int j = 0; j < ND; ++j) yt[j] = y0[j] + c * k[j];
}

// Classical RK4 over h from y0 with k1 = f(y0). The stage states carry only the ND dynamic
// entries (the quadratures do not enter f); the result is the full RK4 combination.
template <class M>
inline void rk4(plant_t *pl, const M &m, const Vec &y0, double h, const Vec &k1, Vec &out) {
    Vec k2, k3, k4, yt;
    stage_state(y0, 0.5 * h, k1, yt);
    rhs(pl, m, yt, k2, nullptr);
    stage_state(y0, 0.5 * h, k2, yt);
    rhs(pl, m, yt, k3, nullptr);
    stage_state(y0, h, k3, yt);
    rhs(pl, m, yt, k4, nullptr);
    out.noalias() = y0 + (h / 6.0) * (k1 + 2.0 * (k2 + k3) + k4);
}

// Explicit midpoint rule (second order, two evaluations) for short dead-time segments; same
// stage-state convention as rk4().
template <class M>
inline void midpoint(plant_t *pl, const M &m, const Vec &y0, double h, const Vec &k1, Vec &out) {
    Vec k2, yt;
    stage_state(y0, 0.5 * h, k1, yt);
    rhs(pl, m, yt, k2, nullptr);
    out.noalias() = y0 + h * k2;
}

// Ralston's third-order method (three evaluations, the smallest error bound of the explicit
// three-stage third-order family); same stage-state convention as rk4().
template <class M>
inline void ralston3(plant_t *pl, const M &m, const Vec &y0, double h, const Vec &k1, Vec &out) {
    Vec k2, k3, yt;
    stage_state(y0, 0.5 * h, k1, yt);
    rhs(pl, m, yt, k2, nullptr);
    stage_state(y0, 0.75 * h, k2, yt);
    rhs(pl, m, yt, k3, nullptr);
    out.noalias() = y0 + (h / 9.0) * (2.0 * k1 + 3.0 * k2 + 4.0 * k3);
}

// The step's integrator: RK4, the midpoint rule on a short segment or Ralston's rule on a
// medium one with switching instants (advance() sets pl->step_method; docs/plant.md section 2
// gives the rule and its error); then the Coulomb stop
// (mech::stop_at_zero_crossing).
template <class M>
inline void integrate(plant_t *pl, const M &m, const Vec &y0, double h, const Vec &k1, Vec &out) {
    if (pl->step_method == STEP_MIDPOINT) midpoint(pl, m, y0, h, k1, out);
    else if (pl->step_method == STEP_RK3) ralston3(pl, m, y0, h, k1, out);
    else rk4(pl, m, y0, h, k1, out);
    mech::stop_at_zero_crossing(pl->shaft, y0[S_OMEGA], out[S_OMEGA], out[S_EFRIC]);
}

// Event function: the most negative of (a) dir * i for conducting sign-dependent phases (the
// current must not change sign inside a step with its path fixed) and (b) the margin of a
// blocked phase's floating voltage inside its zero-current interval (volts, scaled by 1e-3 A/V so
// the two kinds are of similar size; the root finder needs only sign and continuity).
template <class M>
double event_g(plant_t *pl, const M &mach, const Vec &y, const ConductionMode &m, const bool active[3]) {
    double g = 1e300;
    bool any_blocked = false;
    for (int x = 0; x < 3; ++x) {
        if (!active[x]) continue;
        if (m.ph[x] == PH_BLOCKED) { any_blocked = true; continue; }
        const double v = (m.ph[x] == PH_POS) ? y[S_IA + x] : -y[S_IA + x];
        g = std::min(g, v);
    }
    if (any_blocked) {
        Vec dy;
        RhsOutputs aux;
        rhs(pl, mach, y, dy, &aux);
        for (int x = 0; x < 3; ++x) {
            if (!active[x] || m.ph[x] != PH_BLOCKED) continue;
            double rv[4];
            rails(pl, y, rv, x);
            const double a = path_v(pl->legs[x]->pos, rv), b = path_v(pl->legs[x]->neg, rv);
            const double vf = aux.vx0[x];
            const double margin = std::min(vf - std::min(a, b), std::max(a, b) - vf);
            g = std::min(g, margin * 1e-3);
        }
    }
    return g;
}

// Earliest s in (0, 1] at which a current of an active conducting phase reaches zero on the step's
// cubic Hermite interpolant (values y0, y1, derivatives k0, k1 at the step's ends, length h), its
// derivative there in A/s in slope; 2 when none does. The interpolant's error is h^4/384 times the
// current's fourth derivative (docs/plant.md, section 2).
double hermite_first_zero(const Vec &y0, const Vec &y1, const Vec &k0, const Vec &k1, double h,
                          const ConductionMode &m, const bool active[3], double &slope) {
    double best = 2.0;
    for (int x = 0; x < 3; ++x) {
        if (!active[x]) continue;
        const double dir = (m.ph[x] == PH_POS) ? 1.0 : -1.0;
        const double p0 = dir * y0[S_IA + x], p1 = dir * y1[S_IA + x];
        const double m0 = dir * k0[S_IA + x] * h, m1 = dir * k1[S_IA + x] * h;
        // p(s) = p0 + m0 s + c2 s^2 + c3 s^3 (the Hermite cubic in power form).
        const double c2 = 3.0 * (p1 - p0) - 2.0 * m0 - m1, c3 = 2.0 * (p0 - p1) + m0 + m1;
        auto p = [&](double t) { return p0 + t * (m0 + t * (c2 + t * c3)); };
        auto dp = [&](double t) { return m0 + t * (2.0 * c2 + 3.0 * t * c3); };
        // First sign change on a grid of 8 (a cubic has at most 3 zeros), then Newton's method
        // kept inside that bracket (bisection when a Newton step leaves it) to 1e-15.
        double lo = 0.0, plo = p0, hi = -1.0, phi = 0.0;
        for (int j = 1; j <= 8 && lo < best; ++j) {
            const double t = j * 0.125, pt = p(t);
            if (pt <= 0.0) { hi = t; phi = pt; break; }
            lo = t; plo = pt;
        }
        if (hi < 0.0 || !(plo > 0.0) || lo >= best) continue;
        double t = lo + (hi - lo) * plo / (plo - phi);
        for (int it = 0; it < 60; ++it) {
            const double pt = p(t);
            if (pt > 0.0) lo = t;
            else hi = t;
            double tn = t - pt / dp(t);
            if (!(tn > lo && tn < hi)) tn = 0.5 * (lo + hi);
            const bool done = std::fabs(tn - t) <= 1e-15;
            t = tn;
            if (done) break;
        }
        if (t < best) {
            best = t;
            slope = dp(t) / h;
        }
    }
    return best;
}

// After forcing the currents in snapped[] to zero, restore sum(i) = 0 on the others: with one other
// conducting phase left, it must be zero too; with two, they share the removed amount.
void snap_currents(Vec &y, bool snapped[3]) {
    double removed = 0.0;
    for (int x = 0; x < 3; ++x)
        if (snapped[x]) { removed += y[S_IA + x]; y[S_IA + x] = 0.0; }
    int nrest = 0;
    for (int x = 0; x < 3; ++x)
        if (!snapped[x] && y[S_IA + x] != 0.0) ++nrest;
    if (nrest <= 1) {
        for (int x = 0; x < 3; ++x) y[S_IA + x] = 0.0;
    } else {
        for (int x = 0; x < 3; ++x)
            if (!snapped[x] && y[S_IA + x] != 0.0) y[S_IA + x] += removed / nrest;
    }
}

// One step of at most h with mode selection and event location. Returns the time advanced.
template <class M>
double step(plant_t *pl, M &mach, double h) {
    Vec &y = pl->y;
    mach.begin_step(y[S_THETA], y[S_OMEGA], h);
    // Fast path: no current exactly zero (the usual case), the mode follows the current signs.
    const bool nonzero = y[S_IA] != 0.0 && y[S_IB] != 0.0 && y[S_IC] != 0.0;
    // (Written in place, element by element: a struct copy of the freshly stored ints would stall
    // on store forwarding.)
    ConductionMode &m = pl->mode;
    if (nonzero) {
        for (int x = 0; x < 3; ++x) m.ph[x] = (y[S_IA + x] > 0.0) ? PH_POS : PH_NEG;
    } else {
        const ConductionMode ms = select_mode(pl, mach, y);
        for (int x = 0; x < 3; ++x) m.ph[x] = ms.ph[x];
    }
    if (!pl->coefs_valid || m.ph[0] != pl->coefs_mode.ph[0] || m.ph[1] != pl->coefs_mode.ph[1] ||
        m.ph[2] != pl->coefs_mode.ph[2]) {
        make_coefs(pl, m, pl->coefs);
        for (int x = 0; x < 3; ++x) pl->coefs_mode.ph[x] = m.ph[x];
        pl->coefs_valid = true;
    }
    Vec k1, y1;
    rhs(pl, mach, y, k1, nullptr);
    integrate(pl, mach, y, h, k1, y1);
    ++pl->stats.steps;
    if (nonzero) {
        // No blocked phase and none starting at zero: the only events are sign changes of the
        // currents on sign-dependent legs (event_g's first kind).
        double g1 = 1e300;
        for (int x = 0; x < 3; ++x)
            if (pl->legs[x]->sign_dep) g1 = std::min(g1, (m.ph[x] == PH_POS) ? y1[S_IA + x] : -y1[S_IA + x]);
        if (g1 >= -1e-12) {
            y = y1;
            return h;
        }
    }
    // Which phases can produce an event?
    bool active[3] = {false, false, false};
    bool any = false;
    for (int x = 0; x < 3; ++x) {
        if (m.ph[x] == PH_BLOCKED) { active[x] = true; any = true; }
        else if (pl->legs[x]->sign_dep) {
            const double i0 = (m.ph[x] == PH_POS) ? y[S_IA + x] : -y[S_IA + x];
            if (i0 > 0.0) { active[x] = true; any = true; }
        }
    }
    if (!any) { y = y1; return h; }
    // Blocked phases: is the margin >= 0 at the end? (Cheap test first for currents.)
    double g1 = event_g(pl, mach, y1, m, active);
    if (g1 >= -1e-12) {
        // Currents of phases that started exactly at zero and were released may have come back
        // through zero within the step; snap them (second-order small, see docs/plant.md).
        bool snapped[3] = {false, false, false};
        bool any_snap = false;
        for (int x = 0; x < 3; ++x) {
            if (m.ph[x] != PH_BLOCKED && pl->legs[x]->sign_dep && y[S_IA + x] == 0.0) {
                const double v = (m.ph[x] == PH_POS) ? y1[S_IA + x] : -y1[S_IA + x];
                if (v < 0.0) snapped[x] = any_snap = true;
            }
        }
        if (any_snap) snap_currents(y1, snapped);
        y = y1;
        return h;
    }
    // Locate the earliest sign change on s in (0, 1]: first from the step's cubic Hermite
    // interpolant (currents only), then with the Illinois method on the step's own solution.
    ++pl->stats.events;
    double a = 0.0, b = 1.0;
    double ga = event_g(pl, mach, y, m, active), gb = g1;
    if (ga < 0.0) ga = 0.0;
    int side = 0;
    Vec ys = y1;
    double sb_keep = 1.0;
    Vec yb = y1;
    double snap_tol = 1e-9;  // a current this close to zero (A) counts as crossed
    if (m.ph[0] != PH_BLOCKED && m.ph[1] != PH_BLOCKED && m.ph[2] != PH_BLOCKED) {
        // Every active phase is a conducting current (event_g's first kind only): the earliest
        // zero of the currents' interpolant is the first trial; the step's solution there is
        // accepted when its current lies within the location tolerance of zero (its rate of
        // change times 1e-12 s), else it narrows the Illinois bracket.
        Vec k2;
        rhs(pl, mach, y1, k2, nullptr);
        double slope = 0.0;
        const double s = hermite_first_zero(y, y1, k1, k2, h, m, active, slope);
        if (s > 0.0 && s < 1.0) {
            integrate(pl, mach, y, s * h, k1, ys);
            const double gs = event_g(pl, mach, ys, m, active);
            const double tol = std::fabs(slope) * 1e-12;
            if (std::fabs(gs) <= tol) {
                a = b = s; yb = ys; sb_keep = s;
                snap_tol = std::max(snap_tol, tol);
            } else if (gs < 0.0) {
                b = s; gb = gs; yb = ys; sb_keep = s;
            } else {
                a = s; ga = gs;
            }
        }
    }
    for (int it = 0; it < 40 && (b - a) * h > 1e-12; ++it) {
        double s = (a * gb - b * ga) / (gb - ga);
        if (!(s > a && s < b)) s = 0.5 * (a + b);
        integrate(pl, mach, y, s * h, k1, ys);
        const double gs = event_g(pl, mach, ys, m, active);
        if (gs < 0.0) {
            b = s; gb = gs; yb = ys; sb_keep = s;
            if (side == -1) ga *= 0.5;
            side = -1;
        } else {
            a = s; ga = gs;
            if (side == +1) gb *= 0.5;
            side = +1;
        }
    }
    y1 = yb;
    // Snap the currents that crossed zero to exactly zero, keeping sum(i) = 0.
    bool snapped[3] = {false, false, false};
    for (int x = 0; x < 3; ++x) {
        if (!active[x] || m.ph[x] == PH_BLOCKED) continue;
        const double v = (m.ph[x] == PH_POS) ? y1[S_IA + x] : -y1[S_IA + x];
        if (v <= snap_tol) snapped[x] = true;
    }
    snap_currents(y1, snapped);
    y = y1;
    return sb_keep * h;
}

// Leg x's breakpoints (dead-time end, switching instant) due by now, applied in time order, a
// switching instant at its own time: dead-time ends at or before dead_limit, instants at or
// before edge_limit (or strictly before both when strict). Returns whether the gate or the command
// changed.
bool apply_due(plant_t *pl, int x, double dead_limit, double edge_limit, double eps, bool strict) {
    LegSchedule &ls = pl->schedule;
    bool changed = false;
    for (;;) {
        const bool dead = ls.gate[x] != ls.gate_target[x];
        const double td = ls.dead_end[x];
        const bool edge = ls.edge_k[x] < ls.edge_n[x];
        const double te = edge ? ls.edge_abs[x][ls.edge_k[x]] : 1e300;
        const bool dead_due = dead && (strict ? td < dead_limit : td <= dead_limit);
        const bool edge_due = edge && (strict ? te < edge_limit : te <= edge_limit);
        // A dead-time end first unless the instant lies clearly (by more than eps) before it.
        if (dead_due && !(edge_due && te < td - eps)) {
            ls.gate[x] = ls.gate_target[x];
            changed = true;
        } else if (edge_due) {
            ls.cmd[x] ^= 1;
            ++ls.edge_k[x];
            command_leg(ls, pl->p, te, x);
            changed = true;
        } else {
            return changed;
        }
    }
}

// Where the sub-step from now may end when a breakpoint lies inside the advance and every current
// is non-zero: at the first breakpoint after which some leg's path for its current's sign differs
// (Leg::same_as), the breakpoints before it changing nothing in the right-hand side (with drops
// and dead time half of them: a device turning off while the diode of the same side carries the
// current, or the dead time ending into the device that was already carrying it). The step watches
// the sign of every sign-dependent leg's current, and a sign change inside the step ends it there
// (step()), before the breakpoints that would then matter; a leg that is not sign-dependent now
// is looked through only where its paths for both signs stay the same (the FSTP's mid-point
// leg). Returns the sub-step's end.
double first_change(const plant_t *pl, double t_end, double eps) {
    const LegSchedule &ls = pl->schedule;
    int gate[3], target[3], cmd[3], k[3], ph[3];
    double dead_end[3];
    for (int x = 0; x < 3; ++x) {
        gate[x] = ls.gate[x];
        target[x] = ls.gate_target[x];
        cmd[x] = ls.cmd[x];
        k[x] = ls.edge_k[x];
        dead_end[x] = ls.dead_end[x];
        // A leg whose paths do not depend on the sign now: its sign is not watched, so only a
        // breakpoint that changes nothing for either sign is looked through (-1).
        ph[x] = !pl->legs[x]->sign_dep ? -1 : pl->y[S_IA + x] > 0.0 ? PH_POS : PH_NEG;
    }
    const double t_lim = std::min(t_end - eps, pl->t + pl->p.max_step_s);
    for (;;) {
        // Earliest breakpoint among the three legs; within a leg the order of apply_due.
        int xb = -1;
        bool is_dead = false;
        double tb = 1e300;
        for (int x = 0; x < 3; ++x) {
            const bool dead = gate[x] != target[x];
            const bool edge = k[x] < ls.edge_n[x];
            const double te = edge ? ls.edge_abs[x][k[x]] : 1e300;
            const bool dead_first = dead && !(edge && te < dead_end[x] - eps);
            const double tx = dead_first ? dead_end[x] : te;
            if ((dead || edge) && tx < tb) { tb = tx; xb = x; is_dead = dead_first; }
        }
        if (xb < 0 || !(tb < t_lim)) return std::min(tb, t_end);
        const int x = xb;
        const int g0 = gate[x];
        if (is_dead) {
            gate[x] = target[x];
        } else {
            cmd[x] ^= 1;
            ++k[x];
            gate_timeline(wanted_gate(ls, cmd[x], x), pl->p, tb, gate[x], target[x], dead_end[x]);
        }
        const bool *same = pl->leg_tab[x][g0].same_as[gate[x]];
        if (ph[x] < 0 ? !(same[PH_POS] && same[PH_NEG]) : !same[ph[x]]) return tb;
    }
}

// The reconfiguration relay's contacts reach the coil command (plant_set_relay): the legs' paths
// change (the caller puts them in force).
void relay_contacts_move(plant_t *pl) {
    pl->relay_pending = false;
    pl->faults.relay_closed = pl->relay_cmd;
    build_leg_table(pl->p, pl->r_ph, pl->v_set_alpha, pl->v_set_beta, &pl->faults, pl->leg_tab);
}

// One advance of dt_s: sub-steps that end at every switching instant (the legs' commands toggle
// there and their dead times start), every dead-time end and the advance's end, each at most
// max_step_s - except that a sub-step runs through the breakpoints that change nothing for the
// present current signs (first_change; in the leg-state form the dead-time ends into the device
// whose diode already carries the current).
template <class M>
void advance_with(plant_t *pl, M &mach, double dt_s) {
    LegSchedule &ls = pl->schedule;
    // Terminal-voltage integrals restart every advance (their mean over it is reported).
    pl->y[S_IVA0] = pl->y[S_IVB0] = pl->y[S_IVC0] = 0.0;
    pl->last_dt = dt_s;
    // Switching instants inside the advance: an instant at 0 acts at once, one at or beyond
    // dt_s at the end (the leg then holds its last command into the next advance).
    const bool has_edges = (ls.edge_n[0] | ls.edge_n[1] | ls.edge_n[2]) != 0;
    for (int x = 0; has_edges && x < 3; ++x) {
        ls.edge_k[x] = 0;
        for (int k = 0; k < ls.edge_n[x]; ++k) ls.edge_abs[x][k] = pl->t + ls.edge_t[x][k];
        while (ls.edge_k[x] < ls.edge_n[x] && ls.edge_t[x][ls.edge_k[x]] <= 0.0) {
            ls.cmd[x] ^= 1;
            ++ls.edge_k[x];
        }
    }
    for (int x = 0; x < 3; ++x) command_leg(ls, pl->p, pl->t, x);
    const double t_end = pl->t + dt_s;
    const double eps = 1e-12 * (1.0 + std::fabs(t_end));
    int guard = 0;  // a runaway cap (never reached in the tests): 1e6 sub-steps per advance
    while (pl->t < t_end - eps && guard < 1000000) {
        ++guard;
        double next = t_end;
        bool changed = false;
        // Breakpoints reached (the sub-steps land on them exactly, or ran through them when they
        // change nothing): dead-time ends and switching instants, the dead times they start.
        if (!has_edges) {
            // Leg-state form: only dead-time ends.
            for (int x = 0; x < 3; ++x) {
                if (ls.gate[x] != ls.gate_target[x]) {
                    if (ls.dead_end[x] <= pl->t + eps) {
                        ls.gate[x] = ls.gate_target[x];
                        changed = true;
                    } else {
                        next = std::min(next, ls.dead_end[x]);
                    }
                }
            }
        } else {
            for (int x = 0; x < 3; ++x) {
                if (ls.gate[x] != ls.gate_target[x] || ls.edge_k[x] < ls.edge_n[x])
                    changed |= apply_due(pl, x, pl->t + eps, pl->t, eps, false);
                if (ls.gate[x] != ls.gate_target[x]) next = std::min(next, ls.dead_end[x]);
                if (ls.edge_k[x] < ls.edge_n[x]) next = std::min(next, ls.edge_abs[x][ls.edge_k[x]]);
            }
        }
        if (pl->relay_pending) {
            // The relay's contacts move at relay_due: a breakpoint like a switching instant.
            if (pl->relay_due <= pl->t + eps) {
                relay_contacts_move(pl);
                changed = true;
            } else {
                next = std::min(next, pl->relay_due);
            }
        }
        if (changed || guard == 1) set_legs_in_force(pl);
        if (next < t_end && next - pl->t < pl->p.max_step_s && pl->y[S_IA] != 0.0 &&
            pl->y[S_IB] != 0.0 && pl->y[S_IC] != 0.0)
            next = first_change(pl, t_end, eps);
        if (pl->relay_pending) next = std::min(next, pl->relay_due);
        const double h = std::min(pl->p.max_step_s, next - pl->t);
        // A sub-step that ends at a breakpoint inside the advance (a dead-time end or a switching
        // instant) and is at most max_step/16 long (default: the 2 us dead-time segment at the
        // 50 us step, a PWM pulse's short segments) uses the midpoint rule: its local error is
        // O(h^3) on a tiny h, well below the RK4 error of a full step. With switching instants in
        // the advance, the other sub-steps of at most max_step/2 (the segments between a pulse's
        // voltage changes) use Ralston's third-order rule (docs/plant.md, section 2).
        if (next < t_end && h == next - pl->t && h <= pl->p.max_step_s * (1.0 / 16.0)) pl->step_method = STEP_MIDPOINT;
        else if (has_edges && h <= pl->p.max_step_s * 0.5) pl->step_method = STEP_RK3;
        else pl->step_method = STEP_RK4;
        const double taken = step(pl, mach, h);
        // Land exactly on breakpoints to avoid drift.
        if (taken == h) pl->t = (h == next - pl->t) ? next : pl->t + h;
        else pl->t += taken;
    }
    // Breakpoints a sub-step ran through before the end (only then are any left before t_end - eps).
    // (A leg with neither a dead time running nor an instant left has nothing due: not called.)
    for (int x = 0; x < 3; ++x)
        if (ls.gate[x] != ls.gate_target[x] || ls.edge_k[x] < ls.edge_n[x])
            apply_due(pl, x, t_end - eps, t_end - eps, eps, true);
    // Instants left (at or within eps of the end, or beyond it) set the command held from now.
    for (int x = 0; has_edges && x < 3; ++x) {
        for (; ls.edge_k[x] < ls.edge_n[x]; ++ls.edge_k[x]) ls.cmd[x] ^= 1;
        ls.edge_n[x] = 0;
    }
    pl->t = t_end;
    if (pl->relay_pending && pl->relay_due <= t_end + eps) {
        // Contacts due at the advance's end: closed in the state reported at t_end.
        relay_contacts_move(pl);
        set_legs_in_force(pl);
    }
    if (pl->p.load == PLANT_LOAD_SPEED) pl->y[S_OMEGA] = pl->p.load_speed_rpm * kRpmToRadS;
}

}  // namespace

void advance(plant_t *pl, double dt_s) {
    std::visit([&](auto &mach) { advance_with(pl, mach, dt_s); }, pl->machine);
}

}  // namespace plant_model
