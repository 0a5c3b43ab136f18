// Inverter and DC-link faults of the plant (plant.h) against closed forms: an open leg
// (series R-L of the two remaining phases), the relay tying a phase to the capacitor mid-point (the
// FSTP plant; the mid-point's charge balance), a shorted switch (desaturation trip at the instant
// its complement turns on, then the phase on the rail), an open switch (the diode's voltage) and a
// DC-source sag (the link's RC response).
#include "model_test_util.h"

namespace {

using mt::PlantPtr;

// PM machine at standstill held by the dynamometer (no EMF), ideal or real devices.
plant_params_t held(bool drops, bool dead, bool finite) {
    plant_params_t p;
    plant_params_default(&p);
    p.load = PLANT_LOAD_SPEED;
    p.load_speed_rpm = 0.0;
    p.drops_enabled = drops ? 1 : 0;
    p.dead_time_enabled = dead ? 1 : 0;
    p.finite_dc_link = finite ? 1 : 0;
    return p;
}

TEST(Faults, OpenLegLeavesTheSeriesRlOfTheOtherTwoPhases) {
    // Leg A open, B upper, C lower, rotor held: 2 L di_b/dt = V_dc - 2 R i_b, i_c = -i_b, i_a = 0:
    // i_b = V_dc / (2 R) (1 - exp(-t R / L)).
    plant_params_t p = held(false, false, false);
    PlantPtr pl = mt::make(p);
    ASSERT_EQ(plant_set_leg_open(pl.get(), 0, 1), 0);
    plant_set_legs(pl.get(), 1, 1, 0, 1);
    const double tau = p.ls_h / p.rs_ohm, i_inf = p.vdc_v / (2.0 * p.rs_ohm);
    const double ts = 50e-6;
    const int n = static_cast<int>(std::lround(3.0 * tau / ts));
    double worst = 0.0;
    for (int k = 1; k <= n; ++k) {
        plant_advance(pl.get(), ts);
        const plant_state_t s = mt::state(pl);
        ASSERT_EQ(s.i_a, 0.0) << "k = " << k;
        ASSERT_NEAR(s.i_b + s.i_c, 0.0, 1e-12 * i_inf) << "k = " << k;  // rounding of the two sums
        worst = std::max(worst, std::fabs(s.i_b - i_inf * (1.0 - std::exp(-s.t_s / tau))));
    }
    // RK4 on 50 us steps with tau = L/R of a few ms: local error ~ (h/tau)^5 / 120 of i_inf.
    EXPECT_LT(worst, 1e-6 * i_inf);
    EXPECT_EQ(mt::state(pl).blocked_mask, 1);
}

TEST(Faults, OpenLegCutsItsCurrentKeepingTheSumZero) {
    plant_params_t p = held(true, true, true);
    PlantPtr pl = mt::make(p);
    ASSERT_EQ(plant_set_phase_currents(pl.get(), 2.0, -0.5, -1.5), 0);
    ASSERT_EQ(plant_set_leg_open(pl.get(), 0, 1), 0);
    const plant_state_t s = mt::state(pl);
    EXPECT_EQ(s.i_a, 0.0);
    EXPECT_DOUBLE_EQ(s.i_b, 0.5);
    EXPECT_DOUBLE_EQ(s.i_c, -0.5);
}

// SSTP with the relay, leg x open and gated off, relay on x (closing at once) against the plant
// given, driven by the same B/C (or A/C) leg pattern from standstill under an inertia load.
void drive_pattern(plant_t *a, plant_t *b, int periods, double *worst, int skip_leg) {
    *worst = 0.0;
    for (int k = 0; k < periods; ++k) {
        // A rotating two-leg pattern (the FSTP's four vectors) with every fourth period reversed.
        const int v = (k / 40 + ((k % 4) == 3 ? 2 : 0)) % 4;
        static const int tab[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        int s[3] = {0, 0, 0};
        int j = 0;
        for (int x = 0; x < 3; ++x)
            if (x != skip_leg) s[x] = tab[v][j++];
        plant_set_legs(a, s[0], s[1], s[2], 1);
        if (b) plant_set_legs(b, s[0], s[1], s[2], 1);
        plant_advance(a, 50e-6);
        if (b) {
            plant_advance(b, 50e-6);
            plant_state_t sa, sb;
            plant_get_state(a, &sa);
            plant_get_state(b, &sb);
            *worst = std::max({*worst, std::fabs(sa.i_a - sb.i_a), std::fabs(sa.i_b - sb.i_b),
                               std::fabs(sa.i_c - sb.i_c)});
        }
    }
}

TEST(Faults, RelayOnPhaseAWithLegAOpenIsTheFstp) {
    plant_params_t p;
    plant_params_default(&p);
    p.r_bal_ohm = 3300.0;
    p.esr_ohm = 0.025;
    p.relay_delay_s = 0.0;
    plant_params_t q = p;
    p.reconfig_relay = 1;
    q.inverter = PLANT_INVERTER_FSTP;
    PlantPtr s = mt::make(p), f = mt::make(q);
    ASSERT_EQ(plant_set_leg_open(s.get(), 0, 1), 0);
    ASSERT_EQ(plant_set_leg_override(s.get(), 0, PLANT_LEG_DIODE_ONLY), 0);
    ASSERT_EQ(plant_set_relay(s.get(), 1), 0);
    double worst = 0.0;
    drive_pattern(s.get(), f.get(), 4000, &worst, 0);
    EXPECT_LE(worst, 1e-9);
    const plant_state_t ss = mt::state(s), sf = mt::state(f);
    EXPECT_GT(std::fabs(sf.i_a), 0.1);  // the comparison is not between two idle plants
    EXPECT_NEAR(ss.vc_lo_v, sf.vc_lo_v, 1e-9);
    plant_fault_state_t fs = mt::fault_state(s);
    EXPECT_EQ(fs.relay_closed, 1);
    EXPECT_EQ(fs.desat_mask, 0);
}

TEST(Faults, RelayOnPhaseBCarriesTheMidPointCurrent) {
    // Link without ESR or balancing resistors: C dvc_hi/dt = i_s - i_plus, C dvc_lo/dt = i_s -
    // i_plus - i_mid, so C (delta vc_hi - delta vc_lo) = integral of i_mid = integral of i_b when
    // phase B is on the mid-point.
    plant_params_t p;
    plant_params_default(&p);
    p.reconfig_relay = 1;
    p.relay_delay_s = 2e-3;
    PlantPtr pl = mt::make(p);
    ASSERT_EQ(plant_set_leg_open(pl.get(), 1, 1), 0);
    ASSERT_EQ(plant_set_leg_override(pl.get(), 1, PLANT_LEG_DIODE_ONLY), 0);
    ASSERT_EQ(plant_set_relay(pl.get(), 2), 0);
    double w = 0.0;
    drive_pattern(pl.get(), nullptr, 40, &w, 1);  // 2 ms: exactly the delay
    plant_fault_state_t fs = mt::fault_state(pl);
    EXPECT_EQ(fs.relay_closed, 2);
    const plant_state_t s0 = mt::state(pl);
    EXPECT_EQ(s0.i_b, 0.0);  // open leg, the relay not closed before now
    drive_pattern(pl.get(), nullptr, 4000, &w, 1);
    const plant_state_t s1 = mt::state(pl);
    const double dq = s1.q_b_as - s0.q_b_as;
    const double dc = p.c_dc_f * ((s1.vc_hi_v - s0.vc_hi_v) - (s1.vc_lo_v - s0.vc_lo_v));
    EXPECT_GT(std::fabs(s1.i_b), 0.1);
    EXPECT_GT(std::fabs(dq), 1e-4);
    EXPECT_NEAR(dc, dq, 1e-9 + 1e-6 * std::fabs(dq));
}

TEST(Faults, ShortedSwitchTripsWhenItsComplementTurnsOnAndHoldsThePhaseAtTheRail) {
    plant_params_t p = held(false, true, false);  // ideal devices, 1 us dead time, stiff link
    PlantPtr pl = mt::make(p);
    ASSERT_EQ(plant_set_switch_fault(pl.get(), 0, 1, PLANT_SWITCH_SHORT), 0);
    // Upper gated (the short changes nothing), B and C lower: current builds up.
    plant_set_legs(pl.get(), 1, 0, 0, 1);
    for (int k = 0; k < 20; ++k) plant_advance(pl.get(), 50e-6);
    plant_fault_state_t fs = mt::fault_state(pl);
    EXPECT_EQ(fs.desat_mask, 0);
    const double t_cmd = mt::state(pl).t_s;
    // Lower commanded: the upper turns off (it stays shorted), the lower turns on after the dead time.
    plant_set_legs(pl.get(), 0, 0, 0, 1);
    plant_advance(pl.get(), 50e-6);
    fs = mt::fault_state(pl);
    EXPECT_EQ(fs.desat_mask, 1);
    EXPECT_NEAR(fs.desat_t_s, t_cmd + p.dead_time_s, 1e-15);
    // Every gate off; the shorted device keeps phase A on the plus rail, B and C on their diodes.
    plant_set_legs(pl.get(), 0, 1, 1, 1);
    plant_advance(pl.get(), 50e-6);
    const plant_state_t s = mt::state(pl);
    EXPECT_NEAR(s.v_a0_v, p.vdc_v, 1e-12 * p.vdc_v);  // mean of the advance: rounding only
    EXPECT_GT(s.i_a, 0.0);
    EXPECT_LT(s.i_b, 0.0);
    EXPECT_NEAR(s.v_b0_v, p.vdc_v, 1e-12 * p.vdc_v);  // i_b < 0: the upper diode (gates off)
    plant_clear_desat(pl.get());
    fs = mt::fault_state(pl);
    EXPECT_EQ(fs.desat_mask, 0);
}

TEST(Faults, ShortedSwitchWithoutDeadTimeTripsAtTheCommand) {
    plant_params_t p = held(true, false, true);
    PlantPtr pl = mt::make(p);
    ASSERT_EQ(plant_set_switch_fault(pl.get(), 2, 0, PLANT_SWITCH_SHORT), 0);
    plant_set_legs(pl.get(), 1, 0, 0, 1);
    plant_advance(pl.get(), 50e-6);
    plant_leg_edges_t e[3] = {{1, 0, {0}}, {0, 0, {0}}, {0, 1, {17e-6}}};
    ASSERT_EQ(plant_set_leg_edges(pl.get(), e, 1), 0);
    plant_advance(pl.get(), 50e-6);
    plant_fault_state_t fs = mt::fault_state(pl);
    EXPECT_EQ(fs.desat_mask, 4);
    EXPECT_NEAR(fs.desat_t_s, 67e-6, 1e-15);
}

TEST(Faults, OpenUpperSwitchLeavesTheLowerDiode) {
    // Upper of leg A open and gated on, i_a > 0: the current takes the lower diode,
    // v_a0 = -V_d - R_on i_a (Hoang Table III, state 0, i > 0), not V_dc - V_CE - R_on i_a.
    plant_params_t p = held(true, false, false);
    PlantPtr pl = mt::make(p);
    ASSERT_EQ(plant_set_switch_fault(pl.get(), 0, 1, PLANT_SWITCH_OPEN), 0);
    ASSERT_EQ(plant_set_phase_currents(pl.get(), 2.0, -1.0, -1.0), 0);
    plant_set_legs(pl.get(), 1, 0, 0, 1);
    const double dt = 1e-6;
    plant_advance(pl.get(), dt);
    const plant_state_t s = mt::state(pl);
    ASSERT_GT(s.i_a, 0.0);
    // Mean over the advance: i_a moves by < 1 %, so R_on times the mean current within that.
    const double i_mid = 0.5 * (2.0 + s.i_a);
    EXPECT_NEAR(s.v_a0_v, -p.v_d_v - p.r_on_ohm * i_mid, p.r_on_ohm * std::fabs(2.0 - s.i_a) + 1e-9);
}

TEST(Faults, DcSourceSagFollowsTheLinkRc) {
    // Gates off, no current: the SSTP link (one capacitor of 2 c_dc_f) charges through r_dc:
    // v(t) = V1 + (V0 - V1) exp(-t / (r_dc 2 C)).
    plant_params_t p = held(true, true, true);
    PlantPtr pl = mt::make(p);
    const double v0 = p.vdc_v, v1 = 0.6 * p.vdc_v, tau = p.r_dc_ohm * 2.0 * p.c_dc_f;
    ASSERT_EQ(plant_set_source_voltage(pl.get(), v1), 0);
    double worst = 0.0;
    for (int k = 0; k < 200; ++k) {
        plant_advance(pl.get(), 25e-6);
        const plant_state_t s = mt::state(pl);
        worst = std::max(worst, std::fabs(s.vdc_v - (v1 + (v0 - v1) * std::exp(-s.t_s / tau))));
    }
    // RK4 with h / tau = 0.027: relative local error ~ (h/tau)^5 / 120.
    EXPECT_LT(worst, 1e-9 * v0);
    EXPECT_EQ(plant_set_source_voltage(pl.get(), -1.0), -1);
}

TEST(Faults, RelayClosingOnAGatedLegTripsAndOnAGatedOffLegDoesNot) {
    plant_params_t p;
    plant_params_default(&p);
    p.reconfig_relay = 1;
    p.relay_delay_s = 0.0;
    // Leg B upper on and the coil energised with the leg left on: the capacitor half through the
    // device: desaturation at the closing instant (the next advance's start).
    PlantPtr a = mt::make(p);
    plant_set_legs(a.get(), 0, 1, 0, 1);
    plant_advance(a.get(), 50e-6);
    ASSERT_EQ(plant_set_relay(a.get(), 2), 0);
    plant_advance(a.get(), 50e-6);
    plant_fault_state_t fs = mt::fault_state(a);
    EXPECT_EQ(fs.relay_closed, 2);
    EXPECT_EQ(fs.desat_mask, 2);
    EXPECT_NEAR(fs.desat_t_s, 50e-6, 1e-15);
    // The same with leg B gated off by the same period's command (hal_host's order): no trip.
    PlantPtr b = mt::make(p);
    plant_set_legs(b.get(), 0, 1, 0, 1);
    plant_advance(b.get(), 50e-6);
    ASSERT_EQ(plant_set_relay(b.get(), 2), 0);
    ASSERT_EQ(plant_set_leg_override(b.get(), 1, PLANT_LEG_DIODE_ONLY), 0);
    plant_advance(b.get(), 50e-6);
    fs = mt::fault_state(b);
    EXPECT_EQ(fs.relay_closed, 2);
    EXPECT_EQ(fs.desat_mask, 0);
}

TEST(Faults, BadArgumentsAreRefused) {
    plant_params_t p;
    plant_params_default(&p);
    PlantPtr pl = mt::make(p);
    EXPECT_EQ(plant_set_relay(pl.get(), 1), -1);  // no relay fitted
    EXPECT_EQ(plant_set_switch_fault(pl.get(), 3, 1, PLANT_SWITCH_OPEN), -1);
    EXPECT_EQ(plant_set_leg_open(pl.get(), -1, 1), -1);
    p.inverter = PLANT_INVERTER_FSTP;
    PlantPtr f = mt::make(p);
    EXPECT_EQ(plant_set_switch_fault(f.get(), 0, 1, PLANT_SWITCH_SHORT), -1);  // no leg A devices
    p.reconfig_relay = 1;
    char err[200] = {0};
    EXPECT_EQ(plant_create(&p, err, sizeof err), nullptr);
    EXPECT_NE(std::string(err).find("reconfig_relay"), std::string::npos);
}

}  // namespace
