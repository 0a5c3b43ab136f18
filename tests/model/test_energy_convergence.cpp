// Energy balance over inverter runs and step-size convergence of a switching run.
#include <cstring>
#include <vector>

#include "model_test_util.h"

using namespace mt;

namespace {

// SSTP vector nearest to angle a (V1..V6 at (k-1) 60 deg).
void sstp_vector_towards(double a, int leg[3]) {
    double x = std::fmod(a, 2 * kPi);
    if (x < 0) x += 2 * kPi;
    const int k = static_cast<int>(std::floor((x + kPi / 6) / (kPi / 3))) % 6;
    static const int tab[6][3] = {{1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}, {1, 0, 1}};
    for (int i = 0; i < 3; ++i) leg[i] = tab[k][i];
}

}  // namespace

// DC input energy = copper + device + friction + load + source-resistance losses + change of
// magnetic, kinetic and capacitor energy. FSTP, full fidelity (Hoang Table IV drops, 2 us dead time,
// finite capacitors, Table VII back-EMF), accelerating from rest into a generator load under
// angle-commutated switching at 50 us, then gates off (freewheel into the link) for 20 ms.
// Tolerance 1e-6 of the input energy (RK4 integrates the power terms with the state).
TEST(Energy, FstpFullFidelityBalance) {
    plant_params_t p = fstp_generator(0.15);
    auto pl = make(p);
    const plant_state_t s0 = state(pl);
    drive_fstp_ahead(pl, 6000);  // 0.3 s
    plant_set_legs(pl.get(), 0, 0, 0, 0);
    for (int k = 0; k < 400; ++k) plant_advance(pl.get(), 50e-6);
    const plant_state_t s = state(pl);
    const Balance b = balance(s0, s);
    std::printf("FSTP energy: in %.6f J, accounted %.6f J, relative error %.3e; copper %.4f device %.4f"
                " friction %.4f load %.4f rdc %.4f kinetic %.4f (speed %.1f rpm)\n",
                b.in, b.out, b.rel, s.e_copper_j, s.e_device_j, s.e_friction_j, s.e_load_j, s.e_rdc_j,
                s.e_kinetic_j, s.speed_rpm);
    EXPECT_GT(s.speed_rpm, 300.0);
    EXPECT_GT(s.e_device_j, 0.0);
    EXPECT_LT(b.rel, 1e-6);
    // The integral of the squared phase currents (the ripple metric's source) is the PM machine's
    // copper loss over R_s: the same quadrature, so equal to rounding.
    EXPECT_NEAR(s.i2_int_a2s * p.rs_ohm, s.e_copper_j, 1e-12 * s.e_copper_j);
    EXPECT_GT(s.i2_int_a2s, 0.0);
}

// Same balance for the SSTP with a constant-torque load and a stiff link; then a dynamometer
// (speed load) run where the load energy is the shaft work. Tolerance 1e-6.
TEST(Energy, SstpBalanceTorqueAndSpeedLoads) {
    for (plant_load_t load : {PLANT_LOAD_TORQUE, PLANT_LOAD_SPEED}) {
        plant_params_t p;
        plant_params_default(&p);
        p.inverter = PLANT_INVERTER_SSTP;
        p.finite_dc_link = (load == PLANT_LOAD_SPEED);
        p.load = load;
        p.load_torque_nm = 0.1;
        p.load_speed_rpm = 1000.0;
        auto pl = make(p);
        const plant_state_t s0 = state(pl);
        for (int k = 0; k < 4000; ++k) {
            const plant_state_t s = state(pl);
            int leg[3];
            sstp_vector_towards(s.theta_e_rad + kPi / 2, leg);
            // Every 4th period a null vector, to exercise the zero states and dead time on all legs.
            if (k % 4 == 3) leg[0] = leg[1] = leg[2] = 0;
            plant_set_legs(pl.get(), leg[0], leg[1], leg[2], 1);
            plant_advance(pl.get(), 50e-6);
        }
        const plant_state_t s = state(pl);
        const Balance b = balance(s0, s);
        std::printf("SSTP energy (%s load): in %.6f J, accounted %.6f J, relative error %.3e\n",
                    load == PLANT_LOAD_TORQUE ? "torque" : "speed", b.in, b.out, b.rel);
        EXPECT_LT(b.rel, 1e-6);
    }
}


// Halving the step changes a 20 ms full-fidelity FSTP switching run (sampled every 50 us) by less
// than 2e-5 A in the phase currents, 2e-5 V in the capacitor voltage and 1e-4 rad/s in speed at the
// default step (50 us) - about 1/250 of one LSB of a 12-bit, +-10 A current channel - and the
// differences fall by >= 8x per halving (fourth order expected: RK4 between exactly located events).
TEST(Convergence, HalvingStepFstpSwitchingRun) {
    const double hs[4] = {50e-6, 25e-6, 12.5e-6, 6.25e-6};
    Traj t[4];
    for (int i = 0; i < 4; ++i) t[i] = run_fixed_pattern(hs[i]);
    double di[3], dv[3], dw[3];
    for (int i = 0; i < 3; ++i) {
        di[i] = std::max(maxdiff(t[i].ia, t[i + 1].ia), maxdiff(t[i].ib, t[i + 1].ib));
        dv[i] = maxdiff(t[i].vlo, t[i + 1].vlo);
        dw[i] = maxdiff(t[i].w, t[i + 1].w);
        std::printf("h = %.4g us -> h/2: max |di| = %.3e A, |dv_lo| = %.3e V, |dw| = %.3e rad/s\n",
                    hs[i] * 1e6, di[i], dv[i], dw[i]);
    }
    plant_params_t def;
    plant_params_default(&def);
    EXPECT_EQ(def.max_step_s, hs[0]);
    EXPECT_LT(di[0], 2e-5);
    EXPECT_LT(dv[0], 2e-5);
    EXPECT_LT(dw[0], 1e-4);
    EXPECT_GT(di[0] / di[1], 8.0);
    EXPECT_GT(di[1] / di[2], 8.0);
}

namespace {

// plant_get_state with the padding zeroed (so two states compare byte for byte).
plant_state_t state_bytes(const PlantPtr &pl) {
    plant_state_t s;
    std::memset(&s, 0, sizeof s);
    plant_get_state(pl.get(), &s);
    return s;
}

// The six accounts plant_set_energy_accounts(0) holds (plant.h).
void zero_accounts(plant_state_t &s) {
    s.e_dc_in_j = s.e_copper_j = s.e_device_j = s.e_load_j = s.e_rdc_j = s.e_link_j = 0.0;
}

}  // namespace

// plant_set_energy_accounts(0) (what the SIL run loop sets) skips the accounts' terms only: on
// three plants that exercise every term (the FSTP with drops, dead time, a link with ESR and
// balancing resistors into a generator load; the SSTP with a stiff link and a Coulomb torque load;
// the induction machine on the ideal inverter, whose rotor copper loss is the machine's own term),
// driven by the same commands, every other field of the state is the same to the last bit after
// every period, the held accounts stay 0 and the integrated ones move.
TEST(Energy, AccountsOffChangeNoOtherStateBit) {
    plant_params_t fstp = fstp_generator(0.15);
    fstp.esr_ohm = 0.025;
    fstp.r_bal_ohm = 3300.0;
    plant_params_t sstp = default_plant();
    sstp.inverter = PLANT_INVERTER_SSTP;
    sstp.finite_dc_link = 0;
    sstp.coulomb_nm = 0.02;
    sstp = torque_load(sstp, 0.1);
    plant_params_t im = ideal_inverter(PLANT_INVERTER_IDEAL);
    plant_params_im_default(&im);
    im = torque_load(im, 1.0);
    for (const plant_params_t &p : {fstp, sstp, im}) {
        auto on = make(p), off = make(p);
        plant_set_energy_accounts(off.get(), 0);
        for (int k = 0; k < 4000; ++k) {
            const plant_state_t s = state_bytes(on);
            if (p.inverter == PLANT_INVERTER_IDEAL) {
                const double a = 2.0 * kPi * 50.0 * k * 50e-6;  // 50 Hz, 100 V
                plant_set_voltage(on.get(), 100.0 * std::cos(a), 100.0 * std::sin(a));
                plant_set_voltage(off.get(), 100.0 * std::cos(a), 100.0 * std::sin(a));
            } else if (p.inverter == PLANT_INVERTER_FSTP) {
                int sb, sc;
                fstp_vector_towards(s.theta_e_rad + kPi / 2, sb, sc);
                plant_set_legs(on.get(), 0, sb, sc, 1);
                plant_set_legs(off.get(), 0, sb, sc, 1);
            } else {
                int leg[3];
                sstp_vector_towards(s.theta_e_rad + kPi / 2, leg);
                plant_set_legs(on.get(), leg[0], leg[1], leg[2], 1);
                plant_set_legs(off.get(), leg[0], leg[1], leg[2], 1);
            }
            plant_advance(on.get(), 50e-6);
            plant_advance(off.get(), 50e-6);
            plant_state_t a = state_bytes(on), b = state_bytes(off);
            ASSERT_EQ(b.e_dc_in_j, 0.0);
            ASSERT_EQ(b.e_copper_j, 0.0);
            ASSERT_EQ(b.e_device_j, 0.0);
            ASSERT_EQ(b.e_load_j, 0.0);
            ASSERT_EQ(b.e_rdc_j, 0.0);
            ASSERT_EQ(b.e_link_j, 0.0);
            zero_accounts(a);
            ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0) << "inverter " << p.inverter << ", period " << k;
        }
        const plant_state_t a = state_bytes(on);
        EXPECT_NE(a.e_dc_in_j, 0.0);
        EXPECT_GT(a.e_copper_j, 0.0);
        EXPECT_NE(a.e_load_j, 0.0);
        if (p.inverter != PLANT_INVERTER_IDEAL) {
            EXPECT_GT(a.e_device_j, 0.0);
        }
        if (p.inverter == PLANT_INVERTER_FSTP) {
            EXPECT_GT(a.e_link_j, 0.0);
            EXPECT_GT(a.e_rdc_j, 0.0);
        }
    }
}
