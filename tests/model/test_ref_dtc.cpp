// Reference DTC controller: every row of Hoang Tables I, II, III, V, VI and Casadei Tables 1, 3,
// sectors, comparators, estimators, speed PI; then the reference closed around the plant.
#include <vector>

#include "model_test_util.h"
#include "ref_dtc.h"

using namespace mt;
using namespace dtc_ref;

namespace {
const double Vce = 0.9, Vd = 1.25;
}

// Hoang Table I through eqs. (17)-(19) and (4)-(5); exact (1e-12 V). The measured-capacitor form
// equals Hoang eqs. (17)-(19) with equal capacitor voltages.
TEST(RefTables, HoangTableIReconstruction) {
    const double V = 70.0;
    for (const HoangTableIRow &r : hoang_table_i(V)) {
        double vn[3], vm[3], a, b;
        fstp_phase_voltages(r.sb, r.sc, V, vn);
        fstp_phase_voltages_mid(r.sb, r.sc, V / 2, V / 2, vm);
        clarke(vn[0], vn[1], vn[2], a, b);
        EXPECT_NEAR(vn[0], r.van, 1e-12);
        EXPECT_NEAR(vn[1], r.vbn, 1e-12);
        EXPECT_NEAR(vn[2], r.vcn, 1e-12);
        for (int x = 0; x < 3; ++x) EXPECT_NEAR(vm[x], vn[x], 1e-12);
        EXPECT_NEAR(a, r.va, 1e-12);
        EXPECT_NEAR(b, r.vb, 1e-12);
    }
    // SSTP: Casadei eq. 2, |v| = 2/3 Vdc at (k-1) 60 deg for V1..V6, 0 for V0/V7.
    for (int v = 0; v < 8; ++v) {
        int lg[3];
        sstp_vector_legs(v, lg);
        double vn[3], a, b;
        sstp_phase_voltages(lg[0], lg[1], lg[2], V, vn);
        clarke(vn[0], vn[1], vn[2], a, b);
        const double mag = (v >= 1 && v <= 6) ? 2.0 / 3.0 * V : 0.0;
        EXPECT_NEAR(a, mag * std::cos((v - 1) * kPi / 3), 1e-12) << v;
        EXPECT_NEAR(b, mag * std::sin((v - 1) * kPi / 3), 1e-12) << v;
    }
}

// Hoang Table II, all 16 entries (rows d|psi|, dTe; columns sectors I..IV).
TEST(RefTables, HoangTableII) {
    const int expect[4][4] = {
        {2, 3, 4, 1},  // dpsi 1, dTe 1
        {1, 2, 3, 4},  // dpsi 1, dTe 0
        {3, 4, 1, 2},  // dpsi 0, dTe 1
        {4, 1, 2, 3},  // dpsi 0, dTe 0
    };
    const int dps[4] = {1, 1, 0, 0}, dts[4] = {1, 0, 1, 0};
    for (int r = 0; r < 4; ++r)
        for (int s = 1; s <= 4; ++s) EXPECT_EQ(table_hoang2(s, dps[r], dts[r]), expect[r][s - 1]) << r << s;
    // Vector -> (S_B, S_C) of Hoang Table I.
    const int sbsc[5][2] = {{0, 0}, {0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int v = 1; v <= 4; ++v) {
        int sb, sc;
        fstp_vector_legs(v, sb, sc);
        EXPECT_EQ(sb, sbsc[v][0]);
        EXPECT_EQ(sc, sbsc[v][1]);
    }
}

// Hoang Table III (all four entries) and Table V (all four rows), exact.
TEST(RefTables, HoangTablesIIIandV) {
    EXPECT_EQ(leg_forward_drop(0, +1.0, Vce, Vd), Vd);
    EXPECT_EQ(leg_forward_drop(0, -1.0, Vce, Vd), -Vce);
    EXPECT_EQ(leg_forward_drop(1, +1.0, Vce, Vd), Vce);
    EXPECT_EQ(leg_forward_drop(1, -1.0, Vce, Vd), -Vd);
    const double Vf = 0.9;
    struct Row { double ib, ic, fa, fb; };
    const Row rows[4] = {{-1, -1, -2 * Vf / 3, 0.0},
                         {-1, +1, 0.0, 2 * Vf / kSqrt3},
                         {+1, -1, 0.0, -2 * Vf / kSqrt3},
                         {+1, +1, 2 * Vf / 3, 0.0}};
    for (const Row &r : rows) {
        double fa, fb;
        fstp_drop_simple(r.ib, r.ic, Vf, fa, fb);
        EXPECT_NEAR(fa, r.fa, 1e-15);
        EXPECT_NEAR(fb, r.fb, 1e-15);
    }
}

// Hoang Table VI, all 16 rows, exact.
TEST(RefTables, HoangTableVI) {
    const auto rows = hoang_table_vi(Vce, Vd);
    for (const HoangTableVIRow &r : rows) {
        double fa, fb;
        fstp_drop_proposed(r.sb, r.sc, r.sign_ib, r.sign_ic, Vce, Vd, fa, fb);
        EXPECT_NEAR(fa, r.fa, 1e-15) << r.sb << r.sc << r.sign_ib << r.sign_ic;
        EXPECT_NEAR(fb, r.fb, 1e-15) << r.sb << r.sc << r.sign_ib << r.sign_ic;
    }
    // With V_CE = V_d the proposed scheme reduces to the simple one (Hoang Table V).
    for (const HoangTableVIRow &r : rows) {
        double fa, fb, sa, sbb;
        fstp_drop_proposed(r.sb, r.sc, r.sign_ib, r.sign_ic, 1.0, 1.0, fa, fb);
        fstp_drop_simple(r.sign_ib, r.sign_ic, 1.0, sa, sbb);
        EXPECT_NEAR(fa, sa, 1e-15);
        EXPECT_NEAR(fb, sbb, 1e-15);
    }
}

// Casadei Table 1: c_phi = +1 -> k+1 / null / k-1, c_phi = -1 -> k+2 / null / k-2 for c_T = +1, 0,
// -1, every sector; the null is 0 or 7 by the fewer leg transitions from the previous state.
TEST(RefTables, CasadeiTable1) {
    const int from000[3] = {0, 0, 0}, from110[3] = {1, 1, 0}, from100[3] = {1, 0, 0}, from011[3] = {0, 1, 1};
    for (int k = 1; k <= 6; ++k) {
        auto w = [](int v) { return ((v - 1) % 6 + 6) % 6 + 1; };
        EXPECT_EQ(table_casadei1(k, 1, +1, from000), w(k + 1));
        EXPECT_EQ(table_casadei1(k, 1, -1, from000), w(k - 1));
        EXPECT_EQ(table_casadei1(k, 0, +1, from000), w(k + 2));
        EXPECT_EQ(table_casadei1(k, 0, -1, from000), w(k - 2));
        EXPECT_EQ(table_casadei1(k, 1, 0, from000), 0);
        EXPECT_EQ(table_casadei1(k, 0, 0, from100), 0);
        EXPECT_EQ(table_casadei1(k, 1, 0, from110), 7);
        EXPECT_EQ(table_casadei1(k, 0, 0, from011), 7);
    }
}

// Casadei Table 3, ST-A..ST-D, every sector and demand.
TEST(RefTables, CasadeiTable3) {
    const int prev[3] = {1, 1, 0};  // null -> V7
    auto w = [](int v) { return ((v - 1) % 6 + 6) % 6 + 1; };
    for (int k = 1; k <= 6; ++k) {
        for (SwitchingTable st : {SwitchingTable::ST_A, SwitchingTable::ST_B, SwitchingTable::ST_C, SwitchingTable::ST_D}) {
            EXPECT_EQ(table_casadei3(st, k, 1, 1, prev), w(k + 1));  // T up, psi up
            EXPECT_EQ(table_casadei3(st, k, 0, 1, prev), w(k + 2));  // T up, psi down
        }
        EXPECT_EQ(table_casadei3(SwitchingTable::ST_A, k, 1, 0, prev), 7);
        EXPECT_EQ(table_casadei3(SwitchingTable::ST_A, k, 0, 0, prev), 7);
        EXPECT_EQ(table_casadei3(SwitchingTable::ST_B, k, 1, 0, prev), k);
        EXPECT_EQ(table_casadei3(SwitchingTable::ST_B, k, 0, 0, prev), 7);
        EXPECT_EQ(table_casadei3(SwitchingTable::ST_C, k, 1, 0, prev), k);
        EXPECT_EQ(table_casadei3(SwitchingTable::ST_C, k, 0, 0, prev), w(k + 3));
        EXPECT_EQ(table_casadei3(SwitchingTable::ST_D, k, 1, 0, prev), w(k - 1));
        EXPECT_EQ(table_casadei3(SwitchingTable::ST_D, k, 0, 0, prev), w(k - 2));
    }
}

// Sectors: SSTP sector k centred on V_k ((k-1) 60 deg +- 30); FSTP quadrants from 0 deg.
TEST(RefTables, Sectors) {
    for (int k = 1; k <= 6; ++k) {
        for (double off : {-29.9, 0.0, 29.9}) {
            const double a = ((k - 1) * 60.0 + off) * kPi / 180.0;
            EXPECT_EQ(sector_sstp(std::cos(a), std::sin(a)), k) << k << " " << off;
        }
    }
    for (int s = 1; s <= 4; ++s) {
        for (double off : {0.1, 45.0, 89.9}) {
            const double a = ((s - 1) * 90.0 + off) * kPi / 180.0;
            EXPECT_EQ(sector_fstp(std::cos(a), std::sin(a)), s) << s << " " << off;
        }
    }
}

// Hoang eqs. (13)-(14): switch at +-band/2, hold inside. Three-level comparator levels.
TEST(RefTables, Hysteresis) {
    EXPECT_EQ(hysteresis2(0.011, 0.02, 0), 1);
    EXPECT_EQ(hysteresis2(0.009, 0.02, 0), 0);
    EXPECT_EQ(hysteresis2(-0.009, 0.02, 1), 1);
    EXPECT_EQ(hysteresis2(-0.011, 0.02, 1), 0);
    EXPECT_EQ(hysteresis2(1e-9, 0.0, 0), 1);
    EXPECT_EQ(hysteresis2(-1e-9, 0.0, 1), 0);
    EXPECT_EQ(hysteresis3(0.011, 0.02, 0), 1);
    EXPECT_EQ(hysteresis3(0.005, 0.02, 1), 1);
    EXPECT_EQ(hysteresis3(-0.001, 0.02, 1), 0);
    EXPECT_EQ(hysteresis3(-0.005, 0.02, 0), 0);
    EXPECT_EQ(hysteresis3(-0.011, 0.02, 0), -1);
    EXPECT_EQ(hysteresis3(0.001, 0.02, -1), 0);
}

namespace {
Meas meas_from(const plant_state_t &s) {
    Meas m;
    m.i_a = s.i_a;
    m.i_b = s.i_b;
    m.i_c = s.i_c;
    m.vdc_v = s.vdc_v;
    m.have_vc = true;
    m.vc_lo_v = s.vc_lo_v;
    m.vc_hi_v = s.vc_hi_v;
    m.theta_e_rad = s.theta_e_rad;
    m.omega_m_rad_s = s.omega_m_rad_s;
    return m;
}
}  // namespace

// The reconstructed, compensated voltage of the reference equals the plant's true mean applied
// voltage: FSTP with Hoang Table IV drops (no dead time), proposed compensation (Table VI + R_on with
// the physical sign), measured capacitor voltages, closed loop at 1500 rpm. Tolerance 5e-3 V: the
// reference can only average the link voltage between samples (trapezoid), and the link voltage
// bends inside a period after every switching edge (source/capacitor time constant R_dc C / 2 =
// 220 us): error ~ T^2/12 * dI/(C tau) ~ 1e-3..3e-3 V. Periods with a current zero crossing are
// excluded (the sign is ambiguous there). With the sign of Hoang eq. (37) as printed the error is larger
// by (2/3) R_on |i_alpha|, i.e. > 10x.
TEST(RefController, FstpProposedCompensationMatchesPlantVoltage) {
    plant_params_t pp;
    plant_params_default(&pp);
    pp.inverter = PLANT_INVERTER_FSTP;
    pp.dead_time_enabled = 0;
    pp.load = PLANT_LOAD_SPEED;
    pp.load_speed_rpm = 1500.0;
    auto pl = make(pp);
    Params rp;
    rp.topology = Topology::FSTP;
    rp.table = SwitchingTable::HOANG_FSTP;
    rp.estimator = FluxEstimator::VOLTAGE_MODEL;
    rp.comp = DropComp::FSTP_PROPOSED;
    rp.mode = ControlMode::TORQUE;
    rp.voltage_delay_periods = 1;  // this loop applies the output to the very next period
    Controller c;
    ASSERT_EQ(c.init(rp), 0) << c.message();
    c.reset(0.0);
    c.set_torque_ref(0.3);
    plant_state_t prev = state(pl);
    double worst = 0.0, worst_printed = 0.0;
    int n = 0;
    for (int k = 0; k < 4000; ++k) {
        const plant_state_t s = state(pl);
        const Out o = c.step(meas_from(s));
        if (k > 2000) {
            bool crossing = false;
            const double ic0[3] = {prev.i_a, prev.i_b, prev.i_c}, ic1[3] = {s.i_a, s.i_b, s.i_c};
            for (int x = 0; x < 3; ++x) crossing |= (ic0[x] >= 0) != (ic1[x] >= 0);
            if (!crossing) {
                worst = std::max({worst, std::fabs(o.v_alpha - s.v_alpha_v), std::fabs(o.v_beta - s.v_beta_v)});
                const double ia = 0.5 * (s.i_alpha_a + prev.i_alpha_a);
                worst_printed = std::max(worst_printed, std::fabs(o.v_alpha + 2.0 / 3.0 * pp.r_on_ohm * ia - s.v_alpha_v));
                ++n;
            }
        }
        prev = s;
        plant_set_legs(pl.get(), o.sa, o.sb, o.sc, 1);
        plant_advance(pl.get(), 50e-6);
    }
    std::printf("reference vs plant voltage (%d periods): worst %.3e V; with eq. (37) sign as printed %.3e V\n",
                n, worst, worst_printed);
    EXPECT_GT(n, 1000);
    EXPECT_LT(worst, 5e-3);
    EXPECT_GT(worst_printed, 10 * worst);
}

// The low-pass estimator: for a constant input u the flux is u/wc (1 - e^{-wc t}) (exact ZOH
// discretisation; tolerance 1e-12 Wb) - checked with zero current, no drops, a fixed vector.
TEST(RefController, LowPassEstimatorStepResponse) {
    Params rp;
    rp.estimator = FluxEstimator::VOLTAGE_MODEL;
    rp.mode = ControlMode::TORQUE;
    rp.voltage_delay_periods = 1;
    rp.psi_ref_wb = 1e6;  // keep demanding flux: vector V_{k+1} or V_{k+2} keeps changing, so use
                          // the estimator directly through a controller with psi_m = 0 instead:
    rp.psi_m_wb = 0.0;
    Controller c;
    ASSERT_EQ(c.init(rp), 0) << c.message();
    c.reset(0.0);
    c.set_torque_ref(0.0);
    Meas m;
    m.vdc_v = 1.0;
    // The first call has no elapsed period; afterwards the legs output one step earlier drive it.
    Out o = c.step(m);
    double pa = 0.0, pb = 0.0;
    const double a = std::exp(-rp.lpf_wc_rad_s * rp.ts_s), g = (1 - a) / rp.lpf_wc_rad_s;
    for (int k = 0; k < 2000; ++k) {
        int lg[3];
        sstp_vector_legs(o.vector, lg);
        double vn[3], va, vb;
        sstp_phase_voltages(lg[0], lg[1], lg[2], 1.0, vn);
        clarke(vn[0], vn[1], vn[2], va, vb);
        pa = a * pa + g * va;
        pb = a * pb + g * vb;
        o = c.step(m);
        ASSERT_NEAR(o.psi_alpha, pa, 1e-12);
        ASSERT_NEAR(o.psi_beta, pb, 1e-12);
    }
    // Closed form for a constant input: after N steps of u, psi = u/wc (1 - a^N).
    Params r2 = rp;
    Controller c2;
    ASSERT_EQ(c2.init(r2), 0);
    EXPECT_NEAR(g * (1 - std::pow(a, 100)) / (1 - a), (1 - std::exp(-rp.lpf_wc_rad_s * 100 * rp.ts_s)) / rp.lpf_wc_rad_s, 1e-15);
}

// Current model (Hoang eqs. 8-9) equals the plant's true flux for a sinusoidal-EMF machine; torque eq. 10
// equals the plant's torque. Tolerance 1e-12.
TEST(RefController, CurrentModelEqualsPlantFlux) {
    auto pl = make(held_at(default_plant(), 1500.0));
    Params rp;
    rp.mode = ControlMode::TORQUE;
    Controller c;
    ASSERT_EQ(c.init(rp), 0);
    c.set_torque_ref(0.2);
    for (int k = 0; k < 2000; ++k) {
        const plant_state_t s = state(pl);
        const Out o = c.step(meas_from(s));
        ASSERT_NEAR(o.psi_alpha, s.psi_alpha_wb, 1e-12);
        ASSERT_NEAR(o.psi_beta, s.psi_beta_wb, 1e-12);
        ASSERT_NEAR(o.te_nm, s.te_nm, 1e-12);
        plant_set_legs(pl.get(), o.sa, o.sb, o.sc, 1);
        plant_advance(pl.get(), 50e-6);
    }
}

// Speed PI: runs every 10th step; output limited to te_max; conditional-integration anti-windup
// keeps the integrator from winding up during a long saturation (after the error reverses, the
// output leaves the limit within one speed period).
TEST(RefController, SpeedPiRateLimitAndAntiWindup) {
    Params rp;
    rp.kp_nm_s_rad = 0.01;
    rp.ki_nm_rad = 0.2;
    rp.te_max_nm = 0.3;
    Controller c;
    ASSERT_EQ(c.init(rp), 0);
    c.set_speed_ref(100.0);
    Meas m;
    m.vdc_v = 70;
    std::vector<double> te;
    for (int k = 0; k < 20000; ++k) te.push_back(c.step(m).te_ref_nm);  // 1 s saturated
    for (int k = 0; k < 20000; ++k) {
        if (k % 10 != 0) {
            EXPECT_EQ(te[k], te[k - k % 10]) << k;
        }
        EXPECT_LE(te[k], 0.3 + 1e-15);
    }
    EXPECT_EQ(te.back(), 0.3);
    // Error reverses: 100 rad/s above the reference. Without anti-windup the integrator would hold
    // ki * 1 s * 100 = 20 N*m; with it, it is at most te_max and the output drops at once.
    m.omega_m_rad_s = 200.0;
    double t1 = 0.0;
    for (int k = 0; k < 10; ++k) t1 = c.step(m).te_ref_nm;
    EXPECT_LT(t1, 0.3 - 0.5);  // kp * (-100) = -1 N*m plus an integrator <= 0.3: clamps at -0.3
    EXPECT_EQ(t1, -0.3);
}

// Bad configuration is rejected with a message naming the parameter.
TEST(RefController, RejectsBadConfig) {
    Controller c;
    Params rp;
    rp.topology = Topology::FSTP;  // table still CASADEI_T1
    EXPECT_NE(c.init(rp), 0);
    EXPECT_NE(c.message().find("table"), std::string::npos);
    rp = Params{};
    rp.comp = DropComp::FSTP_PROPOSED;
    EXPECT_NE(c.init(rp), 0);
    EXPECT_NE(c.message().find("comp"), std::string::npos);
    rp = Params{};
    rp.voltage_delay_periods = 0;
    EXPECT_NE(c.init(rp), 0);
    EXPECT_NE(c.message().find("voltage_delay_periods"), std::string::npos);
}

// Closed loop with the plant (physics sanity, not a paper number): SSTP current-model DTC in torque
// mode at 1500 rpm (dynamometer) holds the mean true torque within half of the largest torque
// change one 50 us period can make, 1.5 p psi_m (2/3 Vdc + E) / L_s * Ts / 2 = 0.067 N*m, of
// 0.3 N*m; FSTP DTC in speed mode reaches 1000 rpm from rest against a generator load and holds it
// within 3 % (current model with the finite split link; voltage model + Hoang Table VI with a stiff link;
// the band is the speed ripple that the zero-band DTC torque ripple makes on the 1e-4 kg m^2 shaft).
// The voltage model with the finite split link loses synchronism after ~0.35 s: see docs/plant.md.
TEST(RefController, ClosedLoopWithPlant) {
    {
        const plant_params_t pp = held_at(default_plant(), 1500.0);
        auto pl = make(pp);
        Params rp;
        rp.mode = ControlMode::TORQUE;
        Controller c;
        ASSERT_EQ(c.init(rp), 0);
        c.set_torque_ref(0.3);
        double sum = 0.0;
        int n = 0;
        for (int k = 0; k < 8000; ++k) {
            const plant_state_t s = state(pl);
            const Out o = c.step(meas_from(s));
            plant_set_legs(pl.get(), o.sa, o.sb, o.sc, 1);
            plant_advance(pl.get(), 50e-6);
            if (k > 4000) { sum += state(pl).te_nm; ++n; }
        }
        std::printf("SSTP current-model DTC, 1500 rpm: mean torque %.4f N*m (ref 0.3)\n", sum / n);
        const double dte = 1.5 * pp.psi_m_wb * (2.0 / 3.0 * pp.vdc_v + 1500 * kRpm * pp.psi_m_wb) / pp.ls_h * 50e-6;
        EXPECT_NEAR(sum / n, 0.3, 0.5 * dte);
    }
    for (int variant = 0; variant < 2; ++variant) {
        // 0: current model, finite split link; 1: voltage model + proposed compensation, stiff link.
        plant_params_t pp;
        plant_params_default(&pp);
        pp.inverter = PLANT_INVERTER_FSTP;
        pp.finite_dc_link = (variant == 0);
        pp.load = PLANT_LOAD_GENERATOR;
        pp.load_speed_rpm = 1000.0;
        pp.load_torque_nm = 0.2;
        auto pl = make(pp);
        Params rp;
        rp.topology = Topology::FSTP;
        rp.table = SwitchingTable::HOANG_FSTP;
        rp.estimator = variant == 0 ? FluxEstimator::CURRENT_MODEL : FluxEstimator::VOLTAGE_MODEL;
        rp.comp = variant == 0 ? DropComp::NONE : DropComp::FSTP_PROPOSED;
        rp.voltage_delay_periods = 1;
        Controller c;
        ASSERT_EQ(c.init(rp), 0);
        c.reset(0.0);
        c.set_speed_ref(1000.0 * kRpm);
        double wmin = 1e9, wmax = -1e9;
        for (int k = 0; k < 40000; ++k) {  // 2 s
            const plant_state_t s = state(pl);
            const Out o = c.step(meas_from(s));
            plant_set_legs(pl.get(), o.sa, o.sb, o.sc, 1);
            plant_advance(pl.get(), 50e-6);
            if (k > 30000) {
                wmin = std::min(wmin, s.speed_rpm);
                wmax = std::max(wmax, s.speed_rpm);
            }
        }
        std::printf("FSTP %s DTC, speed loop: %.1f .. %.1f rpm (ref 1000)\n",
                    variant == 0 ? "current-model (finite link)" : "voltage-model + Table VI (stiff link)", wmin, wmax);
        EXPECT_NEAR(wmin, 1000.0, 30.0);
        EXPECT_NEAR(wmax, 1000.0, 30.0);
    }
}
