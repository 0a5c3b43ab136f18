// Shared helpers for the plant tests: RAII plant, parameter presets. SI units throughout.
#ifndef MODEL_TEST_UTIL_H
#define MODEL_TEST_UTIL_H

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>
#include <algorithm>
#include <cstdio>
#include <memory>

#include "plant.h"
#include "ref_dtc.h"

namespace mt {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSqrt3 = 1.73205080756887729353;

// Hoang Table I, transcribed once: the FSTP's four vectors (S_B, S_C), their phase voltages and
// their alpha/beta components for the link voltage V split equally about the mid-point.
struct HoangTableIRow {
    int sb, sc;
    double van, vbn, vcn, va, vb;
};
inline std::array<HoangTableIRow, 4> hoang_table_i(double V) {
    return {{{0, 0, V / 3, -V / 6, -V / 6, V / 3, 0.0},
             {1, 0, 0.0, V / 2, -V / 2, 0.0, V / kSqrt3},
             {1, 1, -V / 3, V / 6, V / 6, -V / 3, 0.0},
             {0, 1, 0.0, -V / 2, V / 2, 0.0, -V / kSqrt3}}};
}

// Hoang Table VI (proposed FSTP drop compensation), transcribed once, row by row: S_B, S_C,
// sign(i_b), sign(i_c), v_f_alpha, v_f_beta, for device drops V_CE and V_d.
struct HoangTableVIRow {
    int sb, sc, sign_ib, sign_ic;
    double fa, fb;
};
inline std::array<HoangTableVIRow, 16> hoang_table_vi(double Vce, double Vd) {
    return {{
        {0, 0, -1, -1, -2 * Vce / 3, 0.0},
        {0, 1, -1, -1, -(Vd + Vce) / 3, -(Vd - Vce) / kSqrt3},
        {1, 0, -1, -1, -(Vd + Vce) / 3, (Vd - Vce) / kSqrt3},
        {1, 1, -1, -1, -2 * Vd / 3, 0.0},
        {0, 0, -1, +1, (Vd - Vce) / 3, (Vd + Vce) / kSqrt3},
        {0, 1, -1, +1, 0.0, 2 * Vce / kSqrt3},
        {1, 0, -1, +1, 0.0, 2 * Vd / kSqrt3},
        {1, 1, -1, +1, -(Vd - Vce) / 3, (Vd + Vce) / kSqrt3},
        {0, 0, +1, -1, (Vd - Vce) / 3, -(Vd + Vce) / kSqrt3},
        {0, 1, +1, -1, 0.0, -2 * Vd / kSqrt3},
        {1, 0, +1, -1, 0.0, -2 * Vce / kSqrt3},
        {1, 1, +1, -1, -(Vd - Vce) / 3, -(Vd + Vce) / kSqrt3},
        {0, 0, +1, +1, 2 * Vd / 3, 0.0},
        {0, 1, +1, +1, (Vd + Vce) / 3, -(Vd - Vce) / kSqrt3},
        {1, 0, +1, +1, (Vd + Vce) / 3, (Vd - Vce) / kSqrt3},
        {1, 1, +1, +1, 2 * Vce / 3, 0.0},
    }};
}
constexpr double kRpm = 2.0 * kPi / 60.0;

struct PlantDeleter {
    void operator()(plant_t *p) const { plant_destroy(p); }
};
using PlantPtr = std::unique_ptr<plant_t, PlantDeleter>;

inline PlantPtr make(const plant_params_t &p) {
    char err[256] = {0};
    plant_t *pl = plant_create(&p, err, sizeof err);
    EXPECT_NE(pl, nullptr) << err;
    return PlantPtr(pl);
}

inline plant_state_t state(const PlantPtr &pl) {
    plant_state_t s;
    plant_get_state(pl.get(), &s);
    return s;
}
// The fault-side state (relay, desaturation) of pl now.
inline plant_fault_state_t fault_state(const PlantPtr &pl) {
    plant_fault_state_t f;
    plant_get_fault_state(pl.get(), &f);
    return f;
}

// Energy balance between two states: DC input against every loss (copper, devices, friction,
// load, source resistance, link ESR and balancing resistors) plus the change of magnetic, kinetic
// and capacitor energy. rel = |in - out| / |in|.
struct Balance {
    double in, out, rel;
};
inline Balance balance(const plant_state_t &s0, const plant_state_t &s) {
    const double in = s.e_dc_in_j - s0.e_dc_in_j;
    const double out = (s.e_copper_j - s0.e_copper_j) + (s.e_device_j - s0.e_device_j) +
                       (s.e_friction_j - s0.e_friction_j) + (s.e_load_j - s0.e_load_j) +
                       (s.e_rdc_j - s0.e_rdc_j) + (s.e_link_j - s0.e_link_j) +
                       (s.e_magnetic_j - s0.e_magnetic_j) + (s.e_kinetic_j - s0.e_kinetic_j) +
                       (s.e_capacitor_j - s0.e_capacitor_j);
    return {in, out, std::fabs(in - out) / std::fabs(in)};
}

// Ideal devices, no dead time, stiff DC link: isolates the machine and the vector geometry.
inline plant_params_t ideal_inverter(plant_inverter_t inv) {
    plant_params_t p;
    plant_params_default(&p);
    p.inverter = inv;
    p.drops_enabled = 0;
    p.dead_time_enabled = 0;
    p.finite_dc_link = 0;
    return p;
}

// The full-fidelity FSTP of the energy balances: the default plant (Hoang Table IV drops, dead
// time, finite split link) with Table VII's back-EMF, into a generator load of torque_nm that
// reaches it at 1500 rpm.
inline plant_params_t fstp_generator(double torque_nm) {
    plant_params_t p;
    plant_params_fstp_generator(&p, torque_nm);
    return p;
}

// p with the rotor held at speed_rpm by the dynamometer (the speed load).
inline plant_params_t held_at(plant_params_t p, double speed_rpm) {
    p.load = PLANT_LOAD_SPEED;
    p.load_speed_rpm = speed_rpm;
    return p;
}
inline plant_params_t locked(plant_params_t p) { return held_at(p, 0.0); }
// p with a constant load torque of torque_nm (the torque load).
inline plant_params_t torque_load(plant_params_t p, double torque_nm) {
    p.load = PLANT_LOAD_TORQUE;
    p.load_torque_nm = torque_nm;
    return p;
}
// The default plant (plant_params_default).
inline plant_params_t default_plant() {
    plant_params_t p;
    plant_params_default(&p);
    return p;
}


// FSTP vector (S_B, S_C) whose direction is nearest to an angle (Hoang Table I; ref_dtc.h).
using dtc_ref::fstp_vector_towards;

// n periods of 50 us motoring on the FSTP: each period the vector 90 deg ahead of the rotor's
// electrical angle (the drive of the energy balances).
inline void drive_fstp_ahead(const PlantPtr &pl, int n) {
    for (int k = 0; k < n; ++k) {
        const plant_state_t s = state(pl);
        int sb, sc;
        fstp_vector_towards(s.theta_e_rad + kPi / 2, sb, sc);
        plant_set_legs(pl.get(), 0, sb, sc, 1);
        plant_advance(pl.get(), 50e-6);
    }
}

// The fixed switching run shared by the convergence and integrator tests: sampled every 50 us.
struct Traj {
    std::vector<double> ia, ib, vlo, w;
};

// Fixed switching pattern (independent of the state, so every step size sees the same gate
// sequence): FSTP vectors rotating at 25 Hz with a 3-of-4 duty, one decision per 50 us period.
inline Traj run_fixed_pattern(double h) {
    plant_params_t p;
    plant_params_default(&p);
    p.inverter = PLANT_INVERTER_FSTP;
    plant_params_emf_table_vii(&p);
    p.speed0_rpm = 1500.0;
    p.max_step_s = h;
    auto pl = make(p);
    Traj tr;
    for (int k = 0; k < 400; ++k) {  // 20 ms
        const double ang = 2 * kPi * 25.0 * k * 50e-6 + kPi / 2;
        int sb, sc;
        fstp_vector_towards(ang, sb, sc);
        if (k % 4 == 3) fstp_vector_towards(ang + kPi, sb, sc);
        plant_set_legs(pl.get(), 0, sb, sc, 1);
        plant_advance(pl.get(), 50e-6);
        const plant_state_t s = state(pl);
        tr.ia.push_back(s.i_a);
        tr.ib.push_back(s.i_b);
        tr.vlo.push_back(s.vc_lo_v);
        tr.w.push_back(s.omega_m_rad_s);
    }
    return tr;
}

inline double maxdiff(const std::vector<double> &a, const std::vector<double> &b) {
    double m = 0.0;
    for (size_t i = 0; i < a.size(); ++i) m = std::max(m, std::fabs(a[i] - b[i]));
    return m;
}

}  // namespace mt

#endif
