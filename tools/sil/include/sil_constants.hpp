// sil_constants.hpp - mathematical constants shared by the SIL runner and its tests.
#ifndef DTC_SIL_CONSTANTS_HPP
#define DTC_SIL_CONSTANTS_HPP

#include "plant_defaults.h"

namespace sil {

/// pi (C++17 has no std::numbers): rpm <-> rad/s, angles, the Nyquist rate.
inline constexpr double kPi = PLANT_DEF_PI;

/// The firmware's current-offset calibration tolerance, ADC counts (firmware/dtc/dtc_config.h
/// DTC_ADC_OFFSET_TOL_COUNTS; controller_firmware.cpp asserts they agree): the scenario check
/// refuses the trip levels the firmware's dtc_range_check refuses.
inline constexpr int kAdcOffsetTolCounts = 205;

} // namespace sil

#endif // DTC_SIL_CONSTANTS_HPP
