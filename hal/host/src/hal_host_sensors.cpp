// hal_host_sensors.cpp - see hal_host_sensors.hpp.
#include "hal_host_sensors.hpp"

#include <cmath>
#include <stdexcept>

namespace hal_host {

namespace {
constexpr double kTwoPi = 6.283185307179586476925286766559;
}

std::uint16_t adc_code(double v_in)
{
    const double code = std::nearbyint(kAdcMaxCode * v_in / kAdcFullScaleV);
    if (!(code > 0.0)) { // also catches NaN
        return 0u;
    }
    if (code >= kAdcMaxCode) {
        return 4095u;
    }
    return static_cast<std::uint16_t>(code);
}

double adc_code_to_volts(std::uint16_t code)
{
    return static_cast<double>(code) * kAdcFullScaleV / kAdcMaxCode;
}

double GaussianNoise::next()
{
    if (have_spare_) {
        have_spare_ = false;
        return spare_;
    }
    // Two uniforms in (0, 1] and [0, 1) from 53-bit mantissas; u1 > 0 keeps log() finite.
    const double scale = 1.0 / 9007199254740992.0; // 2^-53
    const double u1 = (static_cast<double>(rng_() >> 11) + 1.0) * scale;
    const double u2 = static_cast<double>(rng_() >> 11) * scale;
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(kTwoPi * u2);
    have_spare_ = true;
    return r * std::cos(kTwoPi * u2);
}

AnalogChannel current_channel(double range_a, double gain_error, double offset_a, double noise_a_rms)
{
    if (!(range_a > 0.0)) {
        throw std::invalid_argument("current sensor range must be > 0 A");
    }
    AnalogChannel ch;
    ch.volts_per_unit = 0.5 * kAdcFullScaleV / range_a;
    ch.v_bias = 0.5 * kAdcFullScaleV;
    ch.gain_error = gain_error;
    ch.offset = offset_a;
    ch.noise_rms = noise_a_rms;
    return ch;
}

AnalogChannel voltage_channel(double range_v, double gain_error, double offset_v, double noise_v_rms)
{
    if (!(range_v > 0.0)) {
        throw std::invalid_argument("voltage sensor range must be > 0 V");
    }
    AnalogChannel ch;
    ch.volts_per_unit = kAdcFullScaleV / range_v;
    ch.v_bias = 0.0;
    ch.gain_error = gain_error;
    ch.offset = offset_v;
    ch.noise_rms = noise_v_rms;
    return ch;
}

Encoder::Encoder(std::uint32_t lines, double offset_rad) : lines_(lines), offset_rad_(offset_rad)
{
    if (lines == 0u || lines > 16383u) { // 4 * lines must fit the 16-bit counter
        throw std::invalid_argument("encoder lines must be 1..16383");
    }
}

std::int64_t Encoder::turn(double theta_m_rad) const
{
    return static_cast<std::int64_t>(std::floor((theta_m_rad + offset_rad_) / kTwoPi));
}

std::uint16_t Encoder::count(double theta_m_rad) const
{
    const double turns = (theta_m_rad + offset_rad_) / kTwoPi;
    const double frac = turns - std::floor(turns); // [0, 1)
    auto c = static_cast<std::uint32_t>(std::floor(frac * static_cast<double>(counts_per_turn())));
    if (c >= counts_per_turn()) { // frac rounding up to 1.0
        c = 0u;
    }
    return static_cast<std::uint16_t>(c);
}

} // namespace hal_host
