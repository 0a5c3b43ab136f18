// Shared helpers for the plant tests: RAII plant, parameter presets. SI units throughout.
#ifndef MODEL_TEST_UTIL_H
#define MODEL_TEST_UTIL_H

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <memory>

#include "plant.h"

namespace mt {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSqrt3 = 1.73205080756887729353;

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

inline plant_params_t locked(plant_params_t p) {
    p.load = PLANT_LOAD_SPEED;
    p.load_speed_rpm = 0.0;
    return p;
}

}  // namespace mt

#endif
