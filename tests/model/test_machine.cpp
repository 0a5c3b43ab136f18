// Machine alone (ideal voltage source): Hoang eqs. (6)-(10) against closed-form solutions.
#include <complex>

#include "model_test_util.h"

using namespace mt;
using cd = std::complex<double>;

// Locked rotor, voltage step on the alpha axis: i_alpha(t) = V/R (1 - exp(-t R/L)), i_beta = 0.
// Tolerance 1e-9 A (the RK4 local error at 25 us is ~(h R/L)^5/120 * V/R ~ 1e-13 A; measured error
// is printed).
TEST(Machine, LockedRotorVoltageStep) {
    plant_params_t p = locked(ideal_inverter(PLANT_INVERTER_IDEAL));
    p.theta_m0_rad = 0.3;  // any angle: at zero speed there is no back-EMF
    auto pl = make(p);
    const double v = 5.0, R = p.rs_ohm, L = p.ls_h;
    plant_set_voltage(pl.get(), v, 0.0);
    double max_err = 0.0;
    for (int k = 1; k <= 800; ++k) {  // 40 ms = 5.8 time constants
        plant_advance(pl.get(), 50e-6);
        const plant_state_t s = state(pl);
        const double expect = v / R * (1.0 - std::exp(-s.t_s * R / L));
        max_err = std::max(max_err, std::fabs(s.i_alpha_a - expect));
        ASSERT_NEAR(s.i_beta_a, 0.0, 1e-12);
        ASSERT_NEAR(s.i_a + s.i_b + s.i_c, 0.0, 1e-12);
        ASSERT_NEAR(s.te_nm, 1.5 * p.pole_pairs * (s.psi_alpha_wb * s.i_beta_a - s.psi_beta_wb * s.i_alpha_a), 1e-12);
    }
    std::printf("locked-rotor RL step: max |i - V/R(1-e^-tR/L)| = %.3e A\n", max_err);
    EXPECT_LT(max_err, 1e-9);
}

// Constant speed, sinusoidal alpha/beta voltages: after the transient the current is the phasor
// solution I = (V e^{j delta} - j w psi_m e^{j theta0}) / (R + j w L) of the SPM equations, and the
// torque is 1.5 p (psi_alpha i_beta - psi_beta i_alpha) = 1.5 p psi_m Im(conj(e^{j theta}) i).
// The source is a 5 us staircase sampled at interval mid-points and scaled by 1/sinc(w dt/2), which
// makes its fundamental exactly V; sampled at the staircase edges the current carries the known
// offset -dv/dt dt^2/(12 L) (1.6e-6 A here), which the expected value includes. Tolerance 1e-7 A,
// 1e-7 N*m (RK4 at 25 us: measured error printed).
TEST(Machine, SinusoidalSteadyStateMatchesPhasor) {
    for (int pp : {1, 2}) {
        plant_params_t p = ideal_inverter(PLANT_INVERTER_IDEAL);
        p.pole_pairs = pp;
        p.load = PLANT_LOAD_SPEED;
        p.load_speed_rpm = 1500.0 / pp;
        p.theta_m0_rad = 0.2;
        auto pl = make(p);
        const double we = 1500.0 * kRpm;  // electrical rad/s in both cases
        const double V = 16.0, delta = 0.2 + kPi / 2;
        const double R = p.rs_ohm, L = p.ls_h;
        const double theta0 = pp * p.theta_m0_rad;
        const cd I = (V * std::polar(1.0, delta) - cd(0, we * p.psi_m_wb) * std::polar(1.0, theta0)) / cd(R, we * L);
        const double dt = 5e-6;
        const double sinc = std::sin(we * dt / 2) / (we * dt / 2);
        double max_ierr = 0.0, max_terr = 0.0, max_teq = 0.0;
        const int n = static_cast<int>(0.3 / dt);  // 0.3 s = 44 electrical time constants
        for (int k = 0; k < n; ++k) {
            const double tm = (k + 0.5) * dt;
            const cd vv = V / sinc * std::polar(1.0, we * tm + delta);
            plant_set_voltage(pl.get(), vv.real(), vv.imag());
            plant_advance(pl.get(), dt);
            if (k * dt > 0.26) {
                const plant_state_t s = state(pl);
                // Sampled at staircase edges the current sits dv/dt dt^2 / (12 L) below its ripple-free
                // value (the sawtooth v_stair - v = -dv/dt (t - t_mid) integrated through L).
                const cd dvdt = cd(0, we) * V * std::polar(1.0, we * s.t_s + delta);
                const cd i_exp = I * std::polar(1.0, we * s.t_s) - dvdt * (dt * dt / (12.0 * L));
                max_ierr = std::max({max_ierr, std::fabs(s.i_alpha_a - i_exp.real()), std::fabs(s.i_beta_a - i_exp.imag())});
                const double te_exp = 1.5 * pp * p.psi_m_wb * (std::conj(std::polar(1.0, theta0 + we * s.t_s)) * i_exp).imag();
                max_terr = std::max(max_terr, std::fabs(s.te_nm - te_exp));
                const double te10 = 1.5 * pp * (s.psi_alpha_wb * s.i_beta_a - s.psi_beta_wb * s.i_alpha_a);
                max_teq = std::max(max_teq, std::fabs(s.te_nm - te10));
            }
        }
        std::printf("p=%d phasor steady state: |I|=%.4f A, max current error %.3e A, torque error %.3e N*m,"
                    " |Te - eq.10| %.3e N*m\n", pp, std::abs(I), max_ierr, max_terr, max_teq);
        EXPECT_LT(max_ierr, 1e-7);
        EXPECT_LT(max_terr, 1e-7);
        EXPECT_LT(max_teq, 1e-12);
    }
}

// Open-circuit (zero current) back-EMF with Hoang Table VII data: at 1500 rpm the phase flux
// derivative reproduces the table's fundamental and harmonic amplitudes. The plant reports the
// stator flux (Hoang eqs. 8-9 generalised), so psi - L_s i must equal the Clarke transform of the
// per-phase PM flux at the reported angle; the dynamometer keeps speed exactly. Tol. 1e-12 Wb.
TEST(Machine, TableVIIEmfData) {
    plant_params_t p = ideal_inverter(PLANT_INVERTER_IDEAL);
    plant_params_emf_table_vii(&p);
    const double fund[3] = {14.0868, 14.2880, 14.4254};
    const double we = 1500.0 * kRpm;
    for (int x = 0; x < 3; ++x) EXPECT_NEAR(p.emf_gain[x] * we * p.psi_m_wb, fund[x], 1e-12);
    EXPECT_NEAR(p.emf_harm[1][1] * fund[1], 0.2483, 1e-12);
    p.load = PLANT_LOAD_SPEED;
    p.load_speed_rpm = 1500.0;
    auto pl = make(p);
    for (int k = 0; k < 100; ++k) {
        plant_advance(pl.get(), 50e-6);
        const plant_state_t s = state(pl);
        const double th = s.theta_e_rad;
        double psi[3];
        const double phi[3] = {0.0, 2 * kPi / 3, 4 * kPi / 3};
        for (int x = 0; x < 3; ++x) {
            const double g = p.psi_m_wb * p.emf_gain[x];
            psi[x] = g * (std::cos(th - phi[x]) + p.emf_harm[x][0] / 3 * std::cos(3 * (th - phi[x])) +
                          p.emf_harm[x][1] / 5 * std::cos(5 * (th - phi[x])) +
                          p.emf_harm[x][2] / 7 * std::cos(7 * (th - phi[x])));
        }
        ASSERT_NEAR(s.psi_alpha_wb - p.ls_h * s.i_alpha_a, (2 * psi[0] - psi[1] - psi[2]) / 3, 1e-12);
        ASSERT_NEAR(s.psi_beta_wb - p.ls_h * s.i_beta_a, (psi[1] - psi[2]) / kSqrt3, 1e-12);
        ASSERT_DOUBLE_EQ(s.speed_rpm, 1500.0);
    }
}

// Bad configuration is rejected at creation with a message that names the key.
TEST(Machine, RejectsBadParameters) {
    plant_params_t p;
    plant_params_default(&p);
    char err[256];
    p.ls_h = 0.0;
    EXPECT_EQ(plant_create(&p, err, sizeof err), nullptr);
    EXPECT_NE(std::string(err).find("ls_h"), std::string::npos) << err;
    plant_params_default(&p);
    p.max_step_s = 1e-3;
    EXPECT_EQ(plant_create(&p, err, sizeof err), nullptr);
    EXPECT_NE(std::string(err).find("max_step_s"), std::string::npos) << err;
    plant_params_default(&p);
    p.inverter = PLANT_INVERTER_FSTP;
    p.r_dc_ohm = 0.001;  // tau = R C / 2 = 0.5 us < 25 us step
    EXPECT_EQ(plant_create(&p, err, sizeof err), nullptr);
    EXPECT_NE(std::string(err).find("r_dc_ohm"), std::string::npos) << err;
    plant_params_default(&p);
    p.load = PLANT_LOAD_GENERATOR;
    p.load_speed_rpm = 0.0;
    EXPECT_EQ(plant_create(&p, err, sizeof err), nullptr);
    EXPECT_NE(std::string(err).find("load_speed_rpm"), std::string::npos) << err;
}
