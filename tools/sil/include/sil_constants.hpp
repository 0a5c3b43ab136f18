// sil_constants.hpp - mathematical constants shared by the SIL runner and its tests.
#ifndef DTC_SIL_CONSTANTS_HPP
#define DTC_SIL_CONSTANTS_HPP

#include "plant_defaults.h"

namespace sil {

/// pi (C++17 has no std::numbers): rpm <-> rad/s, angles, the Nyquist rate.
inline constexpr double kPi = PLANT_DEF_PI;

} // namespace sil

#endif // DTC_SIL_CONSTANTS_HPP
