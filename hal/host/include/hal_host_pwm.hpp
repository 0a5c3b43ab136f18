// hal_host_pwm.hpp - the whole-number rule of the PWM form's timer period (hal.h T1PR), the one
// place it is written: the host HAL's hal_pwm_period() (hal_host.cpp) and the scenario checks of
// the laws that command the PWM form (tools/sil scenario.cpp) both call it. Header-only, no plant.
#ifndef HAL_HOST_PWM_HPP
#define HAL_HOST_PWM_HPP

#include <cmath>
#include <cstdint>

namespace hal_host {

/// T1PR = ts_s * clock_hz / 2 (the up/down counter: one control period is 2 T1PR counts) when
/// that is a whole number of counts in 1..65534 (to 1e-9 relative: 40 us at 75 MHz is
/// 1500.0000000000002 in binary floating point; 65535 leaves no compare value above it, hal.h
/// T1PR + 1), else 0 (no PWM form).
inline std::uint16_t t1pr_counts(double ts_s, double clock_hz)
{
    const double n = ts_s * clock_hz * 0.5;
    const double r = std::nearbyint(n);
    if (!(std::isfinite(n) && r >= 1.0 && r <= 65534.0 && std::fabs(n - r) <= 1e-9 * r)) {
        return 0u;
    }
    return static_cast<std::uint16_t>(r);
}

} // namespace hal_host

#endif // HAL_HOST_PWM_HPP
