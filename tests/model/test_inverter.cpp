// Inverters: voltage vectors (Casadei eq. 2 / Fig. A2, Hoang Table I), device drops (Hoang Table
// III, eq. 20) and their alpha-beta effect in the FSTP (Hoang Table VI), SSTP locked-rotor current
// with drops, DC-link mid-point drift, zero-current hold in dead time and with gates off.
#include "model_test_util.h"

using namespace mt;

namespace {
// Mean applied voltages over a short advance with currents held by a locked rotor.
plant_state_t apply(const PlantPtr &pl, int sa, int sb, int sc, double dt) {
    plant_set_legs(pl.get(), sa, sb, sc, 1);
    plant_advance(pl.get(), dt);
    return state(pl);
}
}  // namespace

// SSTP, ideal devices: the eight states give v = (2/3) Vdc e^{j(k-1)pi/3} for the active states
// V1..V6 (100,110,010,011,001,101) and 0 for V0/V7 (Casadei eq. 2, Fig. A2). Tolerance 1e-12 V.
TEST(Inverter, SstpEightVectorsCasadeiEq2) {
    plant_params_t p = locked(ideal_inverter(PLANT_INVERTER_SSTP));
    auto pl = make(p);
    const double vdc = p.vdc_v;
    const int states[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}};
    for (int k = 0; k < 8; ++k) {
        const plant_state_t s = apply(pl, states[k][0], states[k][1], states[k][2], 20e-6);
        double ea = 0.0, eb = 0.0;
        if (k >= 1 && k <= 6) {
            ea = 2.0 / 3.0 * vdc * std::cos((k - 1) * kPi / 3);
            eb = 2.0 / 3.0 * vdc * std::sin((k - 1) * kPi / 3);
            EXPECT_NEAR(std::hypot(s.v_alpha_v, s.v_beta_v), 2.0 / 3.0 * vdc, 1e-12) << "V" << k;
        }
        EXPECT_NEAR(s.v_alpha_v, ea, 1e-12) << "state " << k;
        EXPECT_NEAR(s.v_beta_v, eb, 1e-12) << "state " << k;
    }
}

// FSTP, ideal devices, stiff link: Hoang Table I, phase voltages and alpha-beta, exactly
// (tolerance 1e-12 V). Phase voltages from the terminal means with Hoang eqs. (1)-(3).
TEST(Inverter, FstpFourVectorsHoangTableI) {
    plant_params_t p = locked(ideal_inverter(PLANT_INVERTER_FSTP));
    auto pl = make(p);
    const double V = p.vdc_v;
    for (const HoangTableIRow &r : hoang_table_i(V)) {
        const plant_state_t s = apply(pl, 1 /* ignored: no leg A */, r.sb, r.sc, 20e-6);
        const double van = (2 * s.v_a0_v - s.v_b0_v - s.v_c0_v) / 3;  // Hoang eq. (1)
        const double vbn = (2 * s.v_b0_v - s.v_a0_v - s.v_c0_v) / 3;  // Hoang eq. (2)
        const double vcn = (2 * s.v_c0_v - s.v_a0_v - s.v_b0_v) / 3;  // Hoang eq. (3)
        EXPECT_NEAR(s.v_a0_v, V / 2, 1e-12);
        EXPECT_NEAR(van, r.van, 1e-12) << r.sb << r.sc;
        EXPECT_NEAR(vbn, r.vbn, 1e-12) << r.sb << r.sc;
        EXPECT_NEAR(vcn, r.vcn, 1e-12) << r.sb << r.sc;
        EXPECT_NEAR(s.v_alpha_v, r.va, 1e-12) << r.sb << r.sc;
        EXPECT_NEAR(s.v_beta_v, r.vb, 1e-12) << r.sb << r.sc;
    }
}

// Hoang Table III + eq. (20): for every (switch state, current sign) the leg voltage is
// S*Vdc - v_f - R_on*i with v_f = V_d, -V_CE (state 0, i>0 / i<0) and V_CE, -V_d (state 1).
// Locked rotor, stiff link, no dead time; the current is set to +-1.5 A and the leg voltage is the
// mean over 1 us, compared with the mean current (current moves < 0.02 A, linear to 1e-9 A).
// Tolerance 1e-7 V. Both SSTP legs and FSTP legs B/C are checked.
TEST(Inverter, DeviceDropsHoangTableIII) {
    for (plant_inverter_t inv : {PLANT_INVERTER_SSTP, PLANT_INVERTER_FSTP}) {
        plant_params_t p = locked(ideal_inverter(inv));
        p.drops_enabled = 1;
        const double vce = p.v_ce_v, vd = p.v_d_v, ron = p.r_on_ohm, V = p.vdc_v;
        for (int S = 0; S <= 1; ++S) {
            for (int sign : {+1, -1}) {
                auto pl = make(p);
                const double i0 = 1.5 * sign;
                ASSERT_EQ(plant_set_phase_currents(pl.get(), -i0, i0, 0.0), 0);  // leg B carries i0
                plant_set_legs(pl.get(), 0, S, 0, 1);
                plant_advance(pl.get(), 1e-6);
                const plant_state_t s = state(pl);
                const double imean = 0.5 * (i0 + s.i_b);
                const double vf = (S == 0) ? (sign > 0 ? vd : -vce) : (sign > 0 ? vce : -vd);
                EXPECT_NEAR(s.v_b0_v, S * V - vf - ron * imean, 1e-7)
                    << (inv == PLANT_INVERTER_SSTP ? "SSTP" : "FSTP") << " S=" << S << " sign=" << sign;
            }
        }
    }
}

// FSTP alpha-beta drop (Hoang eqs. 31-34 and Table VI): with drops on, the applied mean voltage is
// the Table I vector plus (v_f_alpha, v_f_beta) from Table VI, plus the R_on terms. The R_on terms
// of a star-connected machine with phase A on the mid-point are -R_on i_alpha/3 and -R_on i_beta
// (a passive resistance; Hoang eq. 26 prints +R_on i_alpha/3, see docs/plant.md). All 16 rows,
// tolerance 1e-7 V.
TEST(Inverter, FstpAlphaBetaDropHoangTableVI) {
    plant_params_t p = locked(ideal_inverter(PLANT_INVERTER_FSTP));
    p.drops_enabled = 1;
    const double Vce = p.v_ce_v, Vd = p.v_d_v, ron = p.r_on_ohm, V = p.vdc_v;
    const auto rows = hoang_table_vi(Vce, Vd);
    double worst = 0.0;
    for (const HoangTableVIRow &r : rows) {
        auto pl = make(p);
        const double ib = 1.2 * r.sign_ib, ic = 0.8 * r.sign_ic;
        ASSERT_EQ(plant_set_phase_currents(pl.get(), -(ib + ic), ib, ic), 0);
        const plant_state_t s0 = state(pl);
        plant_set_legs(pl.get(), 0, r.sb, r.sc, 1);
        plant_advance(pl.get(), 1e-6);
        const plant_state_t s = state(pl);
        const double ia_m = 0.5 * (s0.i_alpha_a + s.i_alpha_a), ib_m = 0.5 * (s0.i_beta_a + s.i_beta_a);
        // Ideal vector (Hoang Table I / eqs. 17-19 and 4-5).
        const double va = V * (1.0 - r.sb - r.sc) / 3.0;
        const double vb = V * (r.sb - r.sc) / kSqrt3;
        const double da = s.v_alpha_v - va + ron * ia_m / 3.0;
        const double db = s.v_beta_v - vb + ron * ib_m;
        worst = std::max({worst, std::fabs(da - r.fa), std::fabs(db - r.fb)});
        EXPECT_NEAR(da, r.fa, 1e-7) << "SB SC=" << r.sb << r.sc << " signs " << r.sign_ib << r.sign_ic;
        EXPECT_NEAR(db, r.fb, 1e-7) << "SB SC=" << r.sb << r.sc << " signs " << r.sign_ib << r.sign_ic;
    }
    std::printf("Table VI: worst |drop - table| = %.3e V\n", worst);
}

// SSTP locked rotor, vector V1 (100), drops on: phase A through the upper IGBT, B and C through the
// lower IGBTs (negative current): v_alpha = 2/3 (Vdc - 2 V_CE) - R_on i_alpha, so
// i_alpha(t) = I_inf (1 - e^{-t/tau}), I_inf = 2/3 (Vdc - 2 V_CE) / (R_s + R_on), tau = L/(R_s+R_on).
// Tolerance 1e-9 A.
TEST(Inverter, SstpLockedRotorWithDrops) {
    plant_params_t p = locked(ideal_inverter(PLANT_INVERTER_SSTP));
    p.drops_enabled = 1;
    p.vdc_v = 5.0;  // keep the current within the rated range
    auto pl = make(p);
    const double R = p.rs_ohm + p.r_on_ohm, tau = p.ls_h / R;
    const double iinf = 2.0 / 3.0 * (p.vdc_v - 2 * p.v_ce_v) / R;
    double worst = 0.0;
    plant_set_legs(pl.get(), 1, 0, 0, 1);
    for (int k = 0; k < 600; ++k) {
        plant_advance(pl.get(), 50e-6);
        const plant_state_t s = state(pl);
        worst = std::max(worst, std::fabs(s.i_alpha_a - iinf * (1 - std::exp(-s.t_s / tau))));
        ASSERT_NEAR(s.i_beta_a, 0.0, 1e-12);
    }
    std::printf("SSTP locked rotor with drops: I_inf = %.6f A, max error %.3e A\n", iinf, worst);
    EXPECT_LT(worst, 1e-9);
}

// FSTP mid-point: a DC phase-A current drawn from the capacitor junction moves the capacitor
// voltages at dVc/dt = -+ i_a/(2C) (stiff source) and, exactly, d(vc_hi - vc_lo)/dt = i_a / C.
// A 10 H winding makes the current practically DC (it moves under 0.5 % in the window). Legs B, C
// on the lower devices; the source transient (tau = R_dc C/2) is waited out for 12 tau (e^-12).
// Tolerances: difference charge balance 1e-9 relative; i/(2C) slope 1e-3 relative.
TEST(Inverter, FstpMidpointDrift) {
    plant_params_t p;
    plant_params_default(&p);
    p = locked(p);
    p.inverter = PLANT_INVERTER_FSTP;
    p.ls_h = 10.0;
    p.dead_time_enabled = 0;
    auto pl = make(p);
    const double C = p.c_dc_f;
    ASSERT_EQ(plant_set_phase_currents(pl.get(), 2.0, -1.0, -1.0), 0);
    plant_set_legs(pl.get(), 0, 0, 0, 1);
    plant_advance(pl.get(), 12.0 * p.r_dc_ohm * C / 2.0);
    const plant_state_t s1 = state(pl);
    double q = 0.0, iprev = s1.i_a;
    const double dt = 10e-6;
    for (int k = 0; k < 400; ++k) {
        plant_advance(pl.get(), dt);
        const plant_state_t s = state(pl);
        q += 0.5 * (iprev + s.i_a) * dt;  // trapezoid (current is a slow exponential: error ~1e-12)
        iprev = s.i_a;
    }
    const plant_state_t s2 = state(pl);
    const double T = s2.t_s - s1.t_s;
    const double dD = (s2.vc_hi_v - s2.vc_lo_v) - (s1.vc_hi_v - s1.vc_lo_v);
    EXPECT_NEAR(dD, q / C, 1e-9 * std::fabs(q / C));
    const double i_mean = q / T;
    const double slope_lo = (s2.vc_lo_v - s1.vc_lo_v) / T, slope_hi = (s2.vc_hi_v - s1.vc_hi_v) / T;
    std::printf("mid-point drift: i_a = %.4f A, dVlo/dt = %.3f V/s, dVhi/dt = %.3f V/s, i/(2C) = %.3f V/s\n",
                i_mean, slope_lo, slope_hi, i_mean / (2 * C));
    EXPECT_NEAR(slope_lo, -i_mean / (2 * C), 1e-3 * i_mean / (2 * C));
    EXPECT_NEAR(slope_hi, +i_mean / (2 * C), 1e-3 * i_mean / (2 * C));
}

// Gates off at locked rotor: i_a > 0 freewheels through the lower diode of A and the upper diode of
// B into the link (C stays blocked). 2 L di/dt = -(Vdc + 2 V_d) - 2 (R_s + R_on) i, so
// i(t) = (i0 + K) e^{-t/tau} - K, K = (Vdc + 2V_d) / (2 (R_s + R_on)), tau = L / (R_s + R_on), zero at
// t0 = tau ln((i0 + K) / K). After t0 all currents must be exactly 0.0 for the rest of the run (no
// chatter), with at most one located event. Tolerances: 1e-9 A on the trajectory, 1e-9 s on t0.
TEST(Inverter, FreewheelToZeroAndHold) {
    plant_params_t p = locked(ideal_inverter(PLANT_INVERTER_SSTP));
    p.drops_enabled = 1;
    auto pl = make(p);
    const double i0 = 3.0;
    ASSERT_EQ(plant_set_phase_currents(pl.get(), i0, -i0, 0.0), 0);
    plant_set_legs(pl.get(), 0, 0, 0, 0);
    const double Rl = p.rs_ohm + p.r_on_ohm, tau = p.ls_h / Rl;
    const double K = (p.vdc_v + 2 * p.v_d_v) / (2 * Rl);
    const double t0 = tau * std::log((i0 + K) / K);
    double worst = 0.0;
    for (int k = 0; k < 400; ++k) {
        plant_advance(pl.get(), 1e-6);
        const plant_state_t s = state(pl);
        ASSERT_EQ(s.i_c, 0.0);
        if (s.t_s < t0 - 1e-9) {
            worst = std::max(worst, std::fabs(s.i_a - ((i0 + K) * std::exp(-s.t_s / tau) - K)));
        } else if (s.t_s > t0 + 1e-9) {
            ASSERT_EQ(s.i_a, 0.0) << "t=" << s.t_s;
            ASSERT_EQ(s.i_b, 0.0);
            ASSERT_EQ(s.blocked_mask, 7);
        }
    }
    plant_stats_t st;
    plant_get_stats(pl.get(), &st);
    std::printf("freewheel: t0 = %.6e s, max trajectory error %.3e A, events %llu\n", t0, worst, st.events);
    EXPECT_LT(worst, 1e-9);
    EXPECT_LE(st.events, 1u);
}

// Dead time: a small current reaches zero inside the dead time and stays exactly zero until the
// incoming device turns on at 2 us; then it grows the other way. SSTP, all legs lower on, i_a =
// +5 mA; command 011: legs B, C go through dead time, leg A stays on.
TEST(Inverter, DeadTimeZeroCurrentHold) {
    plant_params_t p = locked(ideal_inverter(PLANT_INVERTER_SSTP));
    p.drops_enabled = 1;
    p.dead_time_enabled = 1;
    p.dead_time_s = 2e-6;
    auto pl = make(p);
    plant_set_legs(pl.get(), 0, 0, 0, 1);
    plant_advance(pl.get(), 1e-6);  // gates in force, no current yet
    ASSERT_EQ(plant_set_phase_currents(pl.get(), 0.005, -0.005, 0.0), 0);
    plant_set_legs(pl.get(), 0, 1, 1, 1);
    // During dead time: A lower IGBT (i>0 -> lower diode: -V_d - R_on i), B off with i<0 -> upper
    // diode (Vdc + V_d): the loop voltage drives the current to zero in ~0.5 us.
    for (int k = 0; k < 15; ++k) {
        plant_advance(pl.get(), 0.1e-6);
    }
    plant_state_t s = state(pl);
    EXPECT_EQ(s.i_a, 0.0);
    EXPECT_EQ(s.i_b, 0.0);
    EXPECT_EQ(s.i_c, 0.0);
    EXPECT_EQ(s.blocked_mask, 7);
    for (int k = 0; k < 4; ++k) plant_advance(pl.get(), 0.1e-6);  // to 1.9 us of dead time
    s = state(pl);
    EXPECT_EQ(s.i_a, 0.0);
    plant_advance(pl.get(), 3e-6);  // B, C on at 2 us: vector V4 drives i_a negative
    s = state(pl);
    EXPECT_LT(s.i_a, -1e-3);
    EXPECT_NEAR(s.i_a + s.i_b + s.i_c, 0.0, 1e-15);
}

// Leg overrides: DIODE_ONLY on every leg gives exactly the same trajectory as enable = 0 (both are
// "all gates off"); a stuck UPPER_ON leg B behaves exactly like commanding S_B = 1. SSTP at
// 1500 rpm (dynamometer) with currents flowing; compared sample by sample, bit-identical.
TEST(Inverter, LegOverridesMatchEquivalentCommands) {
    plant_params_t p;
    plant_params_default(&p);
    p.load = PLANT_LOAD_SPEED;
    p.load_speed_rpm = 1500.0;
    auto a = make(p), b = make(p);
    for (int k = 0; k < 200; ++k) {  // same start: drive both with V2 for 10 ms
        plant_set_legs(a.get(), 1, 1, 0, 1);
        plant_set_legs(b.get(), 1, 1, 0, 1);
        plant_advance(a.get(), 50e-6);
        plant_advance(b.get(), 50e-6);
    }
    for (int x = 0; x < 3; ++x) ASSERT_EQ(plant_set_leg_override(b.get(), x, PLANT_LEG_DIODE_ONLY), 0);
    for (int k = 0; k < 100; ++k) {
        plant_set_legs(a.get(), 0, 0, 0, 0);
        plant_set_legs(b.get(), 1, 0, 1, 1);  // ignored: every leg is forced off
        plant_advance(a.get(), 50e-6);
        plant_advance(b.get(), 50e-6);
        const plant_state_t sa = state(a), sb = state(b);
        ASSERT_EQ(sa.i_a, sb.i_a);
        ASSERT_EQ(sa.i_b, sb.i_b);
        ASSERT_EQ(sa.vdc_v, sb.vdc_v);
    }
    for (int x = 0; x < 3; ++x) ASSERT_EQ(plant_set_leg_override(b.get(), x, PLANT_LEG_NORMAL), 0);
    ASSERT_EQ(plant_set_leg_override(b.get(), 1, PLANT_LEG_UPPER_ON), 0);
    for (int k = 0; k < 100; ++k) {
        plant_set_legs(a.get(), 0, 1, 0, 1);
        plant_set_legs(b.get(), 0, 0, 0, 1);  // leg B stuck on the upper device
        plant_advance(a.get(), 50e-6);
        plant_advance(b.get(), 50e-6);
        const plant_state_t sa = state(a), sb = state(b);
        ASSERT_EQ(sa.i_a, sb.i_a);
        ASSERT_EQ(sa.i_c, sb.i_c);
    }
    EXPECT_EQ(plant_set_leg_override(b.get(), 3, PLANT_LEG_NORMAL), -1);
}
