// Switching instants inside the control period (plant_set_leg_edges): volt-seconds per period
// against the commanded pulse widths, dead time moving each edge as the current sign dictates,
// and the 0/100 % leg-state form as the zero-instant case of the same mechanism.
#include "model_test_util.h"

#include <cstddef>
#include <cstring>

using namespace mt;

namespace {

constexpr double kTs = 50e-6;

// Time leg x's command is high (upper device commanded on) within [0, ts).
double on_time(const plant_leg_edges_t &e, double ts) {
    int s = e.state0 ? 1 : 0;
    double t = 0.0, on = 0.0;
    for (int k = 0; k < e.n; ++k) {
        const double tk = std::min(e.t_s[k], ts);
        if (s) on += tk - t;
        t = tk;
        s ^= 1;
    }
    if (s) on += ts - t;
    return on;
}

plant_leg_edges_t pulse(double t_on, double t_off) {
    plant_leg_edges_t e{};
    e.state0 = 0;
    e.n = 2;
    e.t_s[0] = t_on;
    e.t_s[1] = t_off;
    return e;
}

plant_leg_edges_t held(int s) {
    plant_leg_edges_t e{};
    e.state0 = s;
    return e;
}

}  // namespace

// Ideal devices, no dead time, stiff link: each leg's terminal voltage is Vdc while its upper
// device is on and 0 otherwise, so the volt-seconds per period are Vdc * (commanded on-time)
// whatever the machine does. The machine runs at 1500 rpm (speed-held) with currents of both
// signs; the patterns cover centred PWM at duties 0..1 (including pulses far shorter than the
// integration step), asymmetric pulses, a leg clamped for the period (two-phase modulation),
// DSVM's three equal sub-intervals, and four instants on one leg. Tolerance 1e-12 V*s.
TEST(Edges, VoltSecondsEqualCommandedForAnyDuty) {
    for (plant_inverter_t inv : {PLANT_INVERTER_SSTP, PLANT_INVERTER_FSTP}) {
        plant_params_t p = ideal_inverter(inv);
        p.load = PLANT_LOAD_SPEED;
        p.load_speed_rpm = 1500.0;
        auto pl = make(p);
        const double vdc = p.vdc_v;
        int period = 0;
        auto check = [&](const plant_leg_edges_t e[3]) {
            ASSERT_EQ(plant_set_leg_edges(pl.get(), e, 1), 0);
            plant_advance(pl.get(), kTs);
            const plant_state_t s = state(pl);
            const double vx0[3] = {s.v_a0_v, s.v_b0_v, s.v_c0_v};
            for (int x = (inv == PLANT_INVERTER_FSTP ? 1 : 0); x < 3; ++x) {
                EXPECT_NEAR(vx0[x] * kTs, vdc * on_time(e[x], kTs), 1e-12)
                    << "period " << period << " leg " << x;
            }
            ++period;
        };
        // Centred PWM, duty d on leg A, 1 - d on B, d/2 on C: the pulse [ (1-d) ts/2, (1+d) ts/2 ).
        const double duties[] = {0.0, 1e-4, 0.013, 0.25, 0.5, 0.5 + 1e-9, 0.77, 0.9999, 1.0};
        for (double d : duties) {
            auto centred = [](double dd) {
                if (dd <= 0.0) return held(0);
                if (dd >= 1.0) return held(1);
                return pulse(0.5 * (1.0 - dd) * kTs, 0.5 * (1.0 + dd) * kTs);
            };
            const plant_leg_edges_t e[3] = {centred(d), centred(1.0 - d), centred(0.5 * d)};
            check(e);
        }
        // Asymmetric pulses (the up-count and down-count halves differ).
        {
            const plant_leg_edges_t e[3] = {pulse(3e-6, 31e-6), pulse(24.9e-6, 25.1e-6), pulse(0.1e-6, 49.9e-6)};
            check(e);
        }
        // Two-phase modulation: leg A clamped high, leg B clamped low, leg C switching.
        {
            const plant_leg_edges_t e[3] = {held(1), held(0), pulse(11e-6, 39e-6)};
            check(e);
        }
        // DSVM: three equal sub-intervals V_a, V_b, V_c with asymmetric per-leg pulses.
        {
            const double t3 = kTs / 3.0;
            const plant_leg_edges_t e[3] = {pulse(0.0 + 1e-9, t3), pulse(t3, 2.0 * t3), pulse(t3, kTs - 1e-9)};
            check(e);
        }
        // Four instants on one leg, starting high; an instant at 0 and one at the period's end.
        {
            plant_leg_edges_t a{};
            a.state0 = 1;
            a.n = 4;
            a.t_s[0] = 5e-6;
            a.t_s[1] = 12e-6;
            a.t_s[2] = 30e-6;
            a.t_s[3] = 41e-6;
            plant_leg_edges_t b{};
            b.state0 = 1;
            b.n = 1;
            b.t_s[0] = 0.0;
            const plant_leg_edges_t c = pulse(20e-6, kTs);
            const plant_leg_edges_t e[3] = {a, b, c};
            check(e);
        }
        // With no new instants each leg holds its final command: A high (1,0,1,0,1), B low
        // (toggled at 0), C low (its second instant at the period end).
        plant_advance(pl.get(), kTs);
        const plant_state_t s = state(pl);
        if (inv == PLANT_INVERTER_SSTP) {
            EXPECT_NEAR(s.v_a0_v, vdc, 1e-12);
        }
        EXPECT_NEAR(s.v_b0_v, 0.0, 1e-12);
        EXPECT_NEAR(s.v_c0_v, 0.0, 1e-12);
    }
}

// Dead time, ideal devices otherwise, stiff link, locked rotor, leg B and C lower devices on.
// At each command edge the outgoing device turns off at once and the incoming one after t_d;
// in between the current's diode conducts: i_a > 0 flows in the lower diode (terminal at 0), so
// the rising edge (lower -> upper) moves late by t_d and the falling edge stays; i_a < 0 flows
// in the upper diode (terminal at Vdc), so the falling edge moves late by t_d and the rising edge
// stays. One edge per advance pins each edge's position: the volt-seconds of the advance are
// Vdc times the time from the (moved) edge to the period end / from the start to the edge.
TEST(Edges, DeadTimeMovesEachEdgeByItsLengthAsTheCurrentSignDictates) {
    plant_params_t p = locked(ideal_inverter(PLANT_INVERTER_SSTP));
    p.dead_time_enabled = 1;
    p.dead_time_s = 2e-6;
    const double td = p.dead_time_s, vdc = p.vdc_v;
    const double t_rise = 17e-6, t_fall = 29e-6;
    for (double sign : {+1.0, -1.0}) {
        auto pl = make(p);
        plant_set_legs(pl.get(), 0, 0, 0, 1);  // settle the lower devices on (no dead time pending)
        plant_advance(pl.get(), kTs);
        // 8 A: the current moves < 1 A in a period (L_s = 3.19 mH), so its sign holds.
        ASSERT_EQ(plant_set_phase_currents(pl.get(), 8.0 * sign, -4.0 * sign, -4.0 * sign), 0);
        plant_leg_edges_t rise{};
        rise.state0 = 0;
        rise.n = 1;
        rise.t_s[0] = t_rise;
        const plant_leg_edges_t e1[3] = {rise, held(0), held(0)};
        ASSERT_EQ(plant_set_leg_edges(pl.get(), e1, 1), 0);
        plant_advance(pl.get(), kTs);
        plant_state_t s = state(pl);
        const double rise_at = t_rise + (sign > 0 ? td : 0.0);
        EXPECT_NEAR(s.v_a0_v * kTs, vdc * (kTs - rise_at), 1e-12) << "rising edge, sign " << sign;
        EXPECT_GT(s.i_a * sign, 0.0);
        plant_leg_edges_t fall{};
        fall.state0 = 1;
        fall.n = 1;
        fall.t_s[0] = t_fall;
        const plant_leg_edges_t e2[3] = {fall, held(0), held(0)};
        ASSERT_EQ(plant_set_leg_edges(pl.get(), e2, 1), 0);
        plant_advance(pl.get(), kTs);
        s = state(pl);
        const double fall_at = t_fall + (sign < 0 ? td : 0.0);
        EXPECT_NEAR(s.v_a0_v * kTs, vdc * fall_at, 1e-12) << "falling edge, sign " << sign;
        EXPECT_GT(s.i_a * sign, 0.0);
        // Legs B and C never switched: their terminals stayed at 0.
        EXPECT_NEAR(s.v_b0_v, 0.0, 1e-12);
        EXPECT_NEAR(s.v_c0_v, 0.0, 1e-12);
    }
}

// A pulse and its dead time in one period: i_a > 0 loses t_d of on-time, i_a < 0 gains it
// (Vdc * t_d volt-seconds per pulse, the classical dead-time error). Tolerance 1e-12 V*s.
TEST(Edges, DeadTimeVoltSecondErrorPerPulse) {
    plant_params_t p = locked(ideal_inverter(PLANT_INVERTER_SSTP));
    p.dead_time_enabled = 1;
    p.dead_time_s = 1.5e-6;
    for (double sign : {+1.0, -1.0}) {
        auto pl = make(p);
        plant_set_legs(pl.get(), 0, 0, 0, 1);
        plant_advance(pl.get(), kTs);
        ASSERT_EQ(plant_set_phase_currents(pl.get(), 6.0 * sign, -3.0 * sign, -3.0 * sign), 0);
        const plant_leg_edges_t e[3] = {pulse(10e-6, 35e-6), held(0), held(0)};
        ASSERT_EQ(plant_set_leg_edges(pl.get(), e, 1), 0);
        plant_advance(pl.get(), kTs);
        const plant_state_t s = state(pl);
        EXPECT_NEAR(s.v_a0_v * kTs, p.vdc_v * (25e-6 - sign * p.dead_time_s), 1e-12) << sign;
    }
}

// With device drops the path of a leg depends on the current's sign, so with that sign fixed
// half of a pulse's breakpoints change nothing: for i > 0 the lower diode conducts before the
// rising edge and through its dead time (the voltage steps up at t_on + t_d), for i < 0 the
// upper diode conducts from the falling edge through its dead time (the voltage steps down at
// t_off + t_d). Stiff link, locked rotor, 8 A of fixed sign in the pulsed leg (SSTP: leg A; FSTP:
// leg B, phase A sitting on the capacitor mid-point, whose path never depends on the sign): the
// volt-seconds of the pulsed leg are (rail - v_f) times each path's time minus R_on times its
// charge, to 1e-12 V*s, and the advance takes one sub-step per voltage change plus one (3), not
// one per breakpoint (5).
TEST(Edges, WithDropsTheSubStepsRunThroughBreakpointsThatChangeNothing) {
    for (plant_inverter_t inv : {PLANT_INVERTER_SSTP, PLANT_INVERTER_FSTP}) {
        plant_params_t p = locked(ideal_inverter(inv));
        p.drops_enabled = 1;
        p.dead_time_enabled = 1;
        p.dead_time_s = 2e-6;
        ASSERT_GT(p.v_ce_v, 0.0);
        ASSERT_GT(p.v_d_v, 0.0);
        ASSERT_NE(p.v_ce_v, p.v_d_v);
        const double td = p.dead_time_s, vdc = p.vdc_v, t_on = 12e-6, t_off = 33e-6;
        const int leg = (inv == PLANT_INVERTER_FSTP) ? 1 : 0;
        for (double sign : {+1.0, -1.0}) {
            auto pl = make(p);
            plant_set_legs(pl.get(), 0, 0, 0, 1);
            plant_advance(pl.get(), kTs);
            double i0[3] = {-4.0 * sign, -4.0 * sign, -4.0 * sign};
            i0[leg] = 8.0 * sign;
            ASSERT_EQ(plant_set_phase_currents(pl.get(), i0[0], i0[1], i0[2]), 0);
            const plant_state_t s0 = state(pl);
            plant_stats_t st0;
            plant_get_stats(pl.get(), &st0);
            plant_leg_edges_t e[3] = {held(0), held(0), held(0)};
            e[leg] = pulse(t_on, t_off);
            ASSERT_EQ(plant_set_leg_edges(pl.get(), e, 1), 0);
            plant_advance(pl.get(), kTs);
            const plant_state_t s = state(pl);
            plant_stats_t st;
            plant_get_stats(pl.get(), &st);
            const double i_end = (leg == 0) ? s.i_a : s.i_b;
            const double dq = (leg == 0) ? s.q_a_as - s0.q_a_as : s.q_b_as - s0.q_b_as;
            const double v_leg = (leg == 0) ? s.v_a0_v : s.v_b0_v;
            ASSERT_GT(i_end * sign, 0.0);
            // Upper path: i > 0 through the upper device (Vdc - v_ce), i < 0 through the upper
            // diode (Vdc + v_d); lower path: i > 0 through the lower diode (-v_d), i < 0 through the
            // lower device (+v_ce) (Hoang Table III).
            const double t_up = (sign > 0) ? (t_off - t_on - td) : (t_off + td - t_on);
            const double v_up = (sign > 0) ? vdc - p.v_ce_v : vdc + p.v_d_v;
            const double v_lo = (sign > 0) ? -p.v_d_v : p.v_ce_v;
            const double expect = v_up * t_up + v_lo * (kTs - t_up) - p.r_on_ohm * dq;
            EXPECT_NEAR(v_leg * kTs, expect, 1e-12) << "inverter " << inv << " sign " << sign;
            EXPECT_EQ(st.steps - st0.steps, 3u) << "inverter " << inv << " sign " << sign;
        }
    }
}

// The induction machine on the SSTP with drops, dead time and a finite link, driven by centred
// PWM edges (50 Hz, rated 220 V, min-max injection, 40 us periods, 0.2 s from the rated point):
// the default step, whose sub-steps run through the breakpoints that change nothing, agrees with
// a 0.5 us step (which lands on nearly every breakpoint) to 2e-5 A at every period end (RK4's
// error at the default step is ~3e-6 A here), and the energy balance closes to 1e-6.
TEST(Edges, ImPwmRunAgreesWithAFineStepAndBalancesEnergy) {
    plant_params_t p;
    plant_params_default(&p);
    plant_params_im_default(&p);
    p.inverter = PLANT_INVERTER_SSTP;
    p.vdc_v = 311.0;
    p.load = PLANT_LOAD_TORQUE;
    p.load_torque_nm = 26.5;
    p.speed0_rpm = 1440.0;
    ASSERT_TRUE(p.drops_enabled && p.dead_time_enabled && p.finite_dc_link);
    plant_params_t fine = p;
    fine.max_step_s = 0.5e-6;
    auto a = make(p);
    auto b = make(fine);
    const double ts = 40e-6, vpk = 220.0 * std::sqrt(2.0 / 3.0);
    const plant_state_t a0 = state(a);
    double worst = 0.0;
    for (int k = 0; k < 5000; ++k) {
        const double an = 2 * kPi * 50.0 * (k + 0.5) * ts;
        double v[3];
        for (int x = 0; x < 3; ++x) v[x] = vpk * std::cos(an - 2 * kPi / 3 * x);
        const double v0 = -0.5 * (std::fmax(v[0], std::fmax(v[1], v[2])) + std::fmin(v[0], std::fmin(v[1], v[2])));
        plant_leg_edges_t e[3];
        for (int x = 0; x < 3; ++x) {
            const double d = std::fmin(1.0, std::fmax(0.0, 0.5 + (v[x] + v0) / p.vdc_v));
            e[x] = pulse(0.5 * ts * (1.0 - d), 0.5 * ts * (1.0 + d));
        }
        ASSERT_EQ(plant_set_leg_edges(a.get(), e, 1), 0);
        ASSERT_EQ(plant_set_leg_edges(b.get(), e, 1), 0);
        plant_advance(a.get(), ts);
        plant_advance(b.get(), ts);
        const plant_state_t sa = state(a), sb = state(b);
        worst = std::max({worst, std::fabs(sa.i_a - sb.i_a), std::fabs(sa.i_b - sb.i_b), std::fabs(sa.i_c - sb.i_c)});
    }
    const plant_state_t s = state(a);
    const Balance bal = balance(a0, s);
    std::printf("IM PWM edges: max |i - fine| %.3e A; energy in %.3f J, rel %.3e; %.1f rpm\n", worst, bal.in,
                std::fabs(bal.in - bal.out) / bal.in, s.speed_rpm);
    EXPECT_LT(worst, 2e-5);
    EXPECT_LT(std::fabs(bal.in - bal.out) / std::fabs(bal.in), 1e-6);
    EXPECT_GT(s.speed_rpm, 1300.0);
}

// The leg-state form is the zero-instant case: a switched run (drops, dead time, finite link,
// the default machine accelerating) through plant_set_legs and through plant_set_leg_edges with
// n = 0 gives the same state bit for bit.
TEST(Edges, LegStateFormIsTheZeroInstantCaseBitForBit) {
    const plant_params_t p = mt::torque_load(mt::default_plant(), 0.1);
    auto a = make(p);
    auto b = make(p);
    for (int k = 0; k < 4000; ++k) {
        const int sa = (k / 3) % 2, sb = (k / 5) % 2, sc = (k / 7) % 2;
        plant_set_legs(a.get(), sa, sb, sc, 1);
        const plant_leg_edges_t e[3] = {held(sa), held(sb), held(sc)};
        ASSERT_EQ(plant_set_leg_edges(b.get(), e, 1), 0);
        plant_advance(a.get(), kTs);
        plant_advance(b.get(), kTs);
    }
    const plant_state_t sa = state(a), sb = state(b);
    // Every double of plant_state_t (up to blocked_mask; the tail may hold padding).
    const std::size_t nd = offsetof(plant_state_t, blocked_mask) / sizeof(double);
    const double *da = &sa.t_s, *db = &sb.t_s;
    for (std::size_t k = 0; k < nd; ++k) EXPECT_EQ(std::memcmp(da + k, db + k, sizeof(double)), 0) << k;
    EXPECT_EQ(sa.blocked_mask, sb.blocked_mask);
    EXPECT_GT(std::fabs(sa.omega_m_rad_s), 1.0);  // the run did something
}

TEST(Edges, RejectsBadInstants) {
    plant_params_t p;
    plant_params_default(&p);
    auto pl = make(p);
    plant_leg_edges_t e[3] = {pulse(10e-6, 5e-6), held(0), held(0)};
    EXPECT_EQ(plant_set_leg_edges(pl.get(), e, 1), -1);  // decreasing
    e[0] = pulse(-1e-6, 5e-6);
    EXPECT_EQ(plant_set_leg_edges(pl.get(), e, 1), -1);  // negative
    e[0] = pulse(1e-6, std::nan(""));
    EXPECT_EQ(plant_set_leg_edges(pl.get(), e, 1), -1);  // not finite
    e[0] = held(0);
    e[0].n = PLANT_LEG_EDGES_MAX + 1;
    EXPECT_EQ(plant_set_leg_edges(pl.get(), e, 1), -1);
    e[0].n = 0;
    EXPECT_EQ(plant_set_leg_edges(pl.get(), e, 1), 0);
}
