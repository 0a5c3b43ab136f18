// DC-link balancing resistors and capacitor ESR, and Coulomb friction, against closed forms;
// energy balance with all of them on.
#include <string>

#include "model_test_util.h"

using namespace mt;

namespace {

// Finite link with the machine disconnected in effect: gates off, currents zero, rotor held.
plant_params_t link_only(plant_inverter_t inv) {
    plant_params_t p;
    plant_params_default(&p);
    p.inverter = inv;
    p.finite_dc_link = 1;
    p.load = PLANT_LOAD_SPEED;
    p.load_speed_rpm = 0.0;
    return p;
}

}  // namespace

// SSTP link (one capacitor C2 = 2 c_dc_f) with a balancing resistor R_b across it, fed by vdc
// through R_dc, starting at vdc: C2 dv/dt = (vdc - v)/R_dc - v/R_b, so
// v(t) = v_inf + (vdc - v_inf) exp(-t/tau), v_inf = vdc R_b/(R_b + R_dc), tau = C2/(1/R_dc + 1/R_b).
// Large R_dc and small R_b make it a visible exponential (70 V -> 6.4 V). RK4 at 50 us on
// tau = 92 ms: relative error ~ (h/tau)^4 / 120, far below the 1e-9 V asserted.
TEST(DcLink, SstpBalancingResistorExponential) {
    plant_params_t p = link_only(PLANT_INVERTER_SSTP);
    p.r_dc_ohm = 1000.0;
    p.r_bal_ohm = 100.0;
    p.c_dc_f = 0.5e-3;
    auto pl = make(p);
    const double c2 = 2.0 * p.c_dc_f;
    const double vinf = p.vdc_v * p.r_bal_ohm / (p.r_bal_ohm + p.r_dc_ohm);
    const double tau = c2 / (1.0 / p.r_dc_ohm + 1.0 / p.r_bal_ohm);
    double worst = 0.0;
    for (int k = 1; k <= 6000; ++k) {  // 0.3 s = 3.3 tau
        plant_advance(pl.get(), 50e-6);
        const double t = k * 50e-6;
        const double v = vinf + (p.vdc_v - vinf) * std::exp(-t / tau);
        worst = std::max(worst, std::fabs(state(pl).vdc_v - v));
    }
    std::printf("SSTP R_bal discharge: max |v - closed form| = %.3e V\n", worst);
    EXPECT_LT(worst, 1e-9);
    EXPECT_NEAR(state(pl).vdc_v, vinf, 0.04 * (p.vdc_v - vinf));  // it did move towards v_inf
}

// FSTP split link: drive phase A from the mid-point (legs B, C upper: current out of the plus
// rail, back through the mid-point) to unbalance the capacitors, then gates off. Once the currents
// are zero the difference d = v_lo - v_hi obeys, per capacitor C in series with its ESR and R_b
// across both: d(t) = d(t1) exp(-(t - t1)/((R_b + ESR) C)); the source feeds both capacitors alike
// and drops out of d. Checked with and without ESR to 1e-9 relative (RK4 at 50 us on tau >= 47 ms).
TEST(DcLink, FstpMidpointImbalanceDecaysThroughBalancingResistors) {
    for (double esr : {0.0, 0.5}) {
        plant_params_t p = link_only(PLANT_INVERTER_FSTP);
        p.r_bal_ohm = 10.0;
        p.esr_ohm = esr;
        auto pl = make(p);
        plant_set_legs(pl.get(), 0, 1, 1, 1);
        for (int k = 0; k < 400; ++k) plant_advance(pl.get(), 50e-6);  // 20 ms of mid-point current
        plant_set_legs(pl.get(), 0, 0, 0, 0);
        for (int k = 0; k < 400; ++k) plant_advance(pl.get(), 50e-6);  // currents decay to zero
        plant_state_t s1 = state(pl);
        ASSERT_EQ(s1.i_a, 0.0);
        ASSERT_EQ(s1.i_b, 0.0);
        const double d1 = s1.vc_lo_v - s1.vc_hi_v;
        ASSERT_GT(std::fabs(d1), 1.0) << "the drive phase did not unbalance the link";
        const double tau = (p.r_bal_ohm + esr) * p.c_dc_f;
        double worst = 0.0;
        for (int k = 1; k <= 2000; ++k) {
            plant_advance(pl.get(), 50e-6);
            const plant_state_t s = state(pl);
            const double d = d1 * std::exp(-k * 50e-6 / tau);
            worst = std::max(worst, std::fabs((s.vc_lo_v - s.vc_hi_v) - d) / std::fabs(d1));
        }
        std::printf("FSTP mid-point imbalance (ESR %.2f ohm): d1 = %.4f V, max relative deviation %.3e\n",
                    esr, d1, worst);
        EXPECT_LT(worst, 1e-9);
    }
}

// Coulomb friction, ideal inverter at zero voltage and no magnet flux (no electrical torque).
// (a) A constant active load torque below T_c leaves a stopped rotor exactly where it is; (b)
// above T_c it breaks away: omega(t) = -(T_L - T_c)/b (1 - exp(-b t/J)); (c) coasting from
// omega0: omega(t) = (omega0 + T_c/b) exp(-b t/J) - T_c/b until it stops at
// t_stop = (J/b) ln(1 + b omega0/T_c), then stays exactly at zero (no chatter).
TEST(Mechanics, CoulombStallBreakawayAndStop) {
    plant_params_t base = ideal_inverter(PLANT_INVERTER_IDEAL);
    base.psi_m_wb = 0.0;
    base.coulomb_nm = 0.05;
    base.j_kgm2 = 1e-4;
    base.b_nm_s_per_rad = 4.8e-4;
    const double J = base.j_kgm2, b = base.b_nm_s_per_rad, tc = base.coulomb_nm;
    {  // (a) stall
        plant_params_t p = base;
        p.load = PLANT_LOAD_TORQUE;
        p.load_torque_nm = 0.049;
        p.theta_m0_rad = 0.3;
        auto pl = make(p);
        for (int k = 0; k < 20000; ++k) plant_advance(pl.get(), 50e-6);
        const plant_state_t s = state(pl);
        EXPECT_EQ(s.omega_m_rad_s, 0.0);
        EXPECT_EQ(s.theta_m_rad, 0.3);
    }
    {  // (b) breakaway
        plant_params_t p = base;
        p.load = PLANT_LOAD_TORQUE;
        p.load_torque_nm = 0.06;
        auto pl = make(p);
        double worst = 0.0;
        for (int k = 1; k <= 4000; ++k) {
            plant_advance(pl.get(), 50e-6);
            const double t = k * 50e-6;
            const double w = -(p.load_torque_nm - tc) / b * (1.0 - std::exp(-b * t / J));
            worst = std::max(worst, std::fabs(state(pl).omega_m_rad_s - w));
        }
        std::printf("Coulomb breakaway: max |omega - closed form| = %.3e rad/s\n", worst);
        EXPECT_LT(worst, 1e-9);
        EXPECT_LT(state(pl).omega_m_rad_s, -10.0);
    }
    {  // (c) coast to a stop
        plant_params_t p = base;
        p.load = PLANT_LOAD_INERTIA;
        p.speed0_rpm = 600.0;
        auto pl = make(p);
        const double w0 = 600.0 * kRpm;
        const double t_stop = J / b * std::log(1.0 + b * w0 / tc);
        double worst = 0.0, t_zero = -1.0;
        for (int k = 1; k <= 40000; ++k) {
            plant_advance(pl.get(), 50e-6);
            const double t = k * 50e-6;
            const double w = state(pl).omega_m_rad_s;
            if (t < t_stop - 50e-6) worst = std::max(worst, std::fabs(w - ((w0 + tc / b) * std::exp(-b * t / J) - tc / b)));
            if (w == 0.0 && t_zero < 0.0) t_zero = t;
            if (t_zero >= 0.0) {
                ASSERT_EQ(w, 0.0) << "rotor moved again at t = " << t;
            }
        }
        std::printf("Coulomb coast-down: t_stop closed form %.6f s, plant %.6f s, max |omega err| %.3e\n",
                    t_stop, t_zero, worst);
        EXPECT_LT(worst, 1e-9);
        // The step that crosses zero ends at exactly zero: the plant stops within one 50 us step.
        EXPECT_GE(t_zero, t_stop - 1e-12);
        EXPECT_LT(t_zero, t_stop + 50e-6);
    }
}

// Fan (quadratic) load, no electrical torque, b = 0: J domega/dt = -k omega |omega|, k = T_ref /
// omega_ref^2, so omega(t) = omega0 / (1 + k omega0 t / J). 1e-9 rad/s (RK4 at 50 us on a 0.2 s
// time scale); the reported load torque is k omega^2.
TEST(Mechanics, FanLoadCoastDown) {
    plant_params_t p = ideal_inverter(PLANT_INVERTER_IDEAL);
    p.psi_m_wb = 0.0;
    p.b_nm_s_per_rad = 0.0;
    p.load = PLANT_LOAD_FAN;
    p.load_speed_rpm = 1500.0;
    p.load_torque_nm = 0.3;
    p.speed0_rpm = 3000.0;
    auto pl = make(p);
    const double wref = 1500.0 * kRpm, k = p.load_torque_nm / (wref * wref), w0 = 3000.0 * kRpm;
    double worst = 0.0;
    for (int n = 1; n <= 20000; ++n) {
        plant_advance(pl.get(), 50e-6);
        const double w = w0 / (1.0 + k * w0 * n * 50e-6 / p.j_kgm2);
        worst = std::max(worst, std::fabs(state(pl).omega_m_rad_s - w));
    }
    const plant_state_t s = state(pl);
    std::printf("fan coast-down: max |omega - closed form| = %.3e rad/s; T_load %.6f N*m at %.2f rpm\n", worst,
                s.tload_nm, s.speed_rpm);
    EXPECT_LT(worst, 1e-9);
    EXPECT_NEAR(s.tload_nm, k * s.omega_m_rad_s * s.omega_m_rad_s, 1e-15);
    EXPECT_LT(s.speed_rpm, 300.0);
}

// Energy balance with Coulomb friction, balancing resistors and ESR on: FSTP full fidelity,
// accelerating into a generator load, then gates off until the rotor has stopped (friction
// snaps). DC input = copper + device + friction + load + R_dc + link (ESR, R_bal) losses + change
// of magnetic, kinetic and capacitor energy, to 1e-6 of the input.
TEST(Energy, BalanceWithCoulombAndLinkResistors) {
    plant_params_t p = fstp_generator(0.1);
    p.coulomb_nm = 0.05;
    p.r_bal_ohm = 100.0;
    p.esr_ohm = 0.02;
    auto pl = make(p);
    const plant_state_t s0 = state(pl);
    drive_fstp_ahead(pl, 6000);
    const double w_run = state(pl).speed_rpm;
    plant_set_legs(pl.get(), 0, 0, 0, 0);
    for (int k = 0; k < 10000; ++k) plant_advance(pl.get(), 50e-6);
    const plant_state_t s = state(pl);
    const Balance b = balance(s0, s);
    const double in = b.in, out = b.out;
    std::printf("energy with Coulomb + R_bal + ESR: in %.6f J, out %.6f J, rel %.3e; link loss %.4f J; "
                "speed %.1f rpm -> %.3f rpm\n", in, out, std::fabs(in - out) / in, s.e_link_j, w_run, s.speed_rpm);
    EXPECT_GT(w_run, 300.0);
    EXPECT_EQ(s.omega_m_rad_s, 0.0);
    EXPECT_GT(s.e_link_j, 0.0);
    EXPECT_LT(std::fabs(in - out) / std::fabs(in), 1e-6);
}

// Bad values are refused with the parameter named.
TEST(DcLink, RejectsNegativeValues) {
    for (int which = 0; which < 3; ++which) {
        plant_params_t p;
        plant_params_default(&p);
        const char *name = which == 0 ? "r_bal_ohm" : which == 1 ? "esr_ohm" : "coulomb_nm";
        (which == 0 ? p.r_bal_ohm : which == 1 ? p.esr_ohm : p.coulomb_nm) = -1.0;
        char err[256] = {0};
        plant_t *pl = plant_create(&p, err, sizeof err);
        EXPECT_EQ(pl, nullptr);
        EXPECT_NE(std::string(err).find(name), std::string::npos) << err;
        plant_destroy(pl);
    }
}
