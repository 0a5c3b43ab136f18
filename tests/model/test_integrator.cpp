// Integrator accuracy of the default configuration against a fine reference.
//
// At the default 50 us step a switching period is a dead-time segment (1 us) integrated with the
// midpoint rule (plant_advance uses it for a segment ending at a dead-time end and no longer than
// max_step/16) plus an RK4 step for the rest, or one RK4 step when the dead-time end changes
// nothing for the current's sign. At max_step 3.125 us every segment, including the
// dead-time one (longer than 3.125/16 us), is RK4, and the RK4 error there is ~(3.125/50)^4 = 1.5e-5 of the default
// one, so that run is the reference. The test bounds the whole error of the default run: RK4 on the
// long steps plus the midpoint dead-time segments (docs/plant.md, section 2).
#include "model_test_util.h"

using namespace mt;

// Default step vs the 3.125 us all-RK4 reference over a 20 ms full-fidelity FSTP switching run,
// sampled every 50 us: < 1e-5 A in the phase currents (1/500 of one LSB of a 12-bit +-10 A
// channel), < 1.2e-5 V on the lower capacitor, < 5e-5 rad/s in speed.
TEST(Integrator, DefaultStepAgainstFineReference) {
    plant_params_t def;
    plant_params_default(&def);
    ASSERT_EQ(def.max_step_s, 50e-6);
    // The two integration rules the comment above describes: midpoint on the dead-time segment
    // at the default step, RK4 everywhere in the reference.
    ASSERT_LE(def.dead_time_s, def.max_step_s / 16.0);
    ASSERT_GT(def.dead_time_s, 3.125e-6 / 16.0);
    const Traj a = run_fixed_pattern(def.max_step_s);
    const Traj ref = run_fixed_pattern(3.125e-6);
    const double di = std::max(maxdiff(a.ia, ref.ia), maxdiff(a.ib, ref.ib));
    const double dv = maxdiff(a.vlo, ref.vlo);
    const double dw = maxdiff(a.w, ref.w);
    std::printf("default step vs 3.125 us reference: max |di| = %.3e A, |dv_lo| = %.3e V, |dw| = %.3e rad/s\n",
                di, dv, dw);
    EXPECT_LT(di, 1e-5);
    EXPECT_LT(dv, 1.2e-5);
    EXPECT_LT(dw, 5e-5);
}

namespace {

// Locked rotor (no back-EMF), stiff link, Hoang Table IV drops: leg A upper, legs B and C lower,
// i_b = i_c = -i_a / 2, so the three terminals give L di_a/dt = (2/3) (c_a - c_b) - (R_s + R_on) i_a
// with c_x the conducting path's voltage less its R_on term (Hoang Table III): a first-order
// circuit with the closed form i_a(t) = K + (i_a(0) - K) e^{-t/tau}, K = (2/3)(c_a - c_b)/(R_s + R_on),
// tau = L_s / (R_s + R_on).
struct LockedLoop {
    double r, tau;
    double k(double ca, double cb) const { return (2.0 / 3.0) * (ca - cb) / r; }
    double at(double i0, double kk, double t) const { return kk + (i0 - kk) * std::exp(-t / tau); }
};
LockedLoop locked_loop(const plant_params_t &p) {
    const double r = p.rs_ohm + p.r_on_ohm;
    return {r, p.ls_h / r};
}

}  // namespace

// A current crossing zero inside a 50 us step, every phase conducting. i_a = -i0 flows through the
// upper diode of A (c_a = Vdc + V_d) and returns through the lower diodes of B and C (c_b = -V_d);
// it reaches zero at t0 = tau ln((i0 + K1) / K1), the three currents together. From t0 the upper
// device of A (c_a = Vdc - V_CE) and the lower devices of B and C (c_b = V_CE) carry it:
// i_a = K2 (1 - e^{-(t - t0)/tau}). The crossing is located to 1e-12 s (docs/plant.md, section 2),
// so each later sample lies within 1e-12 s times di_a/dt of the closed form (RK4's own error on
// this tau is ~(h/tau)^5/120 |i - K| < 1e-13 A); the offset is reported as the located instant's
// error against t0, and exactly one event is located.
TEST(Integrator, CurrentZeroInsideAStepAtTheClosedFormInstant) {
    plant_params_t p = locked(ideal_inverter(PLANT_INVERTER_SSTP));
    p.drops_enabled = 1;
    ASSERT_EQ(p.max_step_s, 50e-6);
    const LockedLoop c = locked_loop(p);
    const double k1 = c.k(p.vdc_v + p.v_d_v, -p.v_d_v), k2 = c.k(p.vdc_v - p.v_ce_v, p.v_ce_v);
    // i0 chosen so that the zero falls at 37 % of the first step.
    const double t0_want = 0.37 * p.max_step_s;
    const double i0 = k1 * (std::exp(t0_want / c.tau) - 1.0);
    const double t0 = c.tau * std::log((i0 + k1) / k1);
    auto pl = make(p);
    ASSERT_EQ(plant_set_phase_currents(pl.get(), -i0, 0.5 * i0, 0.5 * i0), 0);
    plant_set_legs(pl.get(), 1, 0, 0, 1);
    double worst_dt = 0.0;
    for (int k = 1; k <= 6; ++k) {
        plant_advance(pl.get(), 50e-6);
        const plant_state_t s = state(pl);
        ASSERT_GT(s.t_s, t0);
        const double expect = k2 * (1.0 - std::exp(-(s.t_s - t0) / c.tau));
        const double slope = (k2 - expect) / c.tau;  // di_a/dt there
        // A located instant t0 + dt shifts the later current by -slope dt.
        const double dt = -(s.i_a - expect) / slope;
        worst_dt = std::max(worst_dt, std::fabs(dt));
        EXPECT_NEAR(s.i_b, -0.5 * s.i_a, 1e-12);
        EXPECT_NEAR(s.i_c, -0.5 * s.i_a, 1e-12);
    }
    plant_stats_t st;
    plant_get_stats(pl.get(), &st);
    std::printf("zero crossing: t0 = %.9e s, located within %.3e s, events %llu, evaluations %llu\n", t0,
                worst_dt, st.events, st.evals);
    EXPECT_LT(worst_dt, 1e-12);
    EXPECT_EQ(st.events, 1u);
}

// A dead-time end inside a 50 us step (leg-state form, 2 us dead time, leg A commanded from lower
// to upper at the period's start; legs B and C stay lower). Positive i_a: the lower diode of A
// carries it in the dead time (c_a = -V_d), the upper device from its end (c_a = Vdc - V_CE); B
// and C conduct through their lower devices (c_b = V_CE): two exponentials joined at td. Negative
// i_a: the upper diode of A carries it from the period's start (c_a = Vdc + V_d, with B and C's
// lower diodes, c_b = -V_d) and the dead-time end changes nothing: one exponential over the whole
// period, which the plant integrates as one sub-step. Bound: the local errors of the midpoint rule
// on the dead time, (td/tau)^3/6 |i - K_d|, and of RK4 on the rest, (h/tau)^5/120 |i - K|, at
// most 2e-10 A together here; asserted to 1e-9 A.
TEST(Integrator, DeadTimeEndInsideAStepAtTheClosedFormCurrent) {
    plant_params_t p = locked(ideal_inverter(PLANT_INVERTER_SSTP));
    p.drops_enabled = 1;
    p.dead_time_enabled = 1;
    p.dead_time_s = 2e-6;
    ASSERT_LE(p.dead_time_s, p.max_step_s / 16.0);
    const LockedLoop c = locked_loop(p);
    const double ts = 50e-6, td = p.dead_time_s, i0 = 2.0;
    for (double sign : {+1.0, -1.0}) {
        auto pl = make(p);
        plant_set_legs(pl.get(), 0, 0, 0, 1);
        plant_advance(pl.get(), 1e-6);  // gates in force, no current yet
        ASSERT_EQ(plant_set_phase_currents(pl.get(), sign * i0, -0.5 * sign * i0, -0.5 * sign * i0), 0);
        plant_stats_t st0;
        plant_get_stats(pl.get(), &st0);
        plant_set_legs(pl.get(), 1, 0, 0, 1);
        plant_advance(pl.get(), ts);
        const plant_state_t s = state(pl);
        plant_stats_t st;
        plant_get_stats(pl.get(), &st);
        double expect, bound;
        if (sign > 0) {
            const double kd = c.k(-p.v_d_v, p.v_ce_v), ka = c.k(p.vdc_v - p.v_ce_v, p.v_ce_v);
            const double i_td = c.at(i0, kd, td);
            expect = c.at(i_td, ka, ts - td);
            bound = std::pow(td / c.tau, 3) / 6.0 * std::fabs(i0 - kd) +
                    std::pow((ts - td) / c.tau, 5) / 120.0 * std::fabs(i_td - ka);
        } else {
            const double k = c.k(p.vdc_v + p.v_d_v, -p.v_d_v);
            expect = c.at(-i0, k, ts);
            bound = std::pow(ts / c.tau, 5) / 120.0 * std::fabs(-i0 - k);
        }
        std::printf("dead-time end, i_a %+g A: i_a(50 us) = %.12f A, closed form %.12f A, error %.3e A (bound %.3e A), "
                    "sub-steps %llu\n",
                    sign * i0, s.i_a, expect, s.i_a - expect, bound, st.steps - st0.steps);
        EXPECT_LT(bound, 2e-10);
        EXPECT_NEAR(s.i_a, expect, 1e-9) << "sign " << sign;
        EXPECT_NEAR(s.i_b, -0.5 * s.i_a, 1e-12);
        EXPECT_EQ(st.events, st0.events);
        // The dead-time end ends a sub-step only where it changes the circuit.
        EXPECT_EQ(st.steps - st0.steps, sign > 0 ? 2u : 1u) << "sign " << sign;
    }
}
