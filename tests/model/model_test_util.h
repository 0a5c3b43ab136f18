// Shared helpers for the plant tests: RAII plant, parameter presets. SI units throughout.
#ifndef MODEL_TEST_UTIL_H
#define MODEL_TEST_UTIL_H

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "plant.h"

namespace mt {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSqrt3 = 1.73205080756887729353;
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
