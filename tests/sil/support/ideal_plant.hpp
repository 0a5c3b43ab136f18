// ideal_plant.hpp - the plant the PWM and SVM tests measure volt-seconds on: ideal devices (no
// forward drops, no dead time), a stiff DC link, the rotor held at a constant speed by the
// dynamometer, so every leg's terminal voltage is exactly Vdc times its switch state.
#ifndef DTC_TESTS_SIL_IDEAL_PLANT_HPP
#define DTC_TESTS_SIL_IDEAL_PLANT_HPP

#include "model_test_util.h" // tests/model: the plant tests' presets
#include "plant.h"

namespace sil_test {

/// The default plant's six-switch inverter, ideal (mt::ideal_inverter), the rotor held at speed_rpm.
inline plant_params_t ideal_plant_held_at(double speed_rpm)
{
    return mt::held_at(mt::ideal_inverter(PLANT_INVERTER_SSTP), speed_rpm);
}

} // namespace sil_test

#endif // DTC_TESTS_SIL_IDEAL_PLANT_HPP
