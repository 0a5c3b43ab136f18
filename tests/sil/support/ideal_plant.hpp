// ideal_plant.hpp - the plant the PWM and SVM tests measure volt-seconds on: ideal devices (no
// forward drops, no dead time), a stiff DC link, the rotor held at a constant speed by the
// dynamometer, so every leg's terminal voltage is exactly Vdc times its switch state.
#ifndef DTC_TESTS_SIL_IDEAL_PLANT_HPP
#define DTC_TESTS_SIL_IDEAL_PLANT_HPP

#include "plant.h"

namespace sil_test {

inline plant_params_t ideal_plant_held_at(double speed_rpm)
{
    plant_params_t p;
    plant_params_default(&p);
    p.drops_enabled = 0;
    p.dead_time_enabled = 0;
    p.finite_dc_link = 0;
    p.load = PLANT_LOAD_SPEED;
    p.load_speed_rpm = speed_rpm;
    return p;
}

} // namespace sil_test

#endif // DTC_TESTS_SIL_IDEAL_PLANT_HPP
