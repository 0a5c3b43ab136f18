// hal_host_sensors.hpp - sensing-chain emulation for the SIL HAL (no plant, no global state).
//
// What the DSP sees of the plant, modelled as the board's analogue front end and the F2812's
// peripherals (reference: ../shared/reference/f2812-facts.md, section 3):
//   * ADC: 12 bits, 0..3 V input; code = round(4095 * v / 3 V) (ties to even), clamped to 0..4095.
//   * Phase currents: closed-loop Hall sensor + level shift to mid-scale (Hoang sec. IV uses
//     closed-loop Hall-effect current sensors): v = 1.5 V + (1.5 V / range) * i_measured,
//     so +-range amperes span the ADC input range.
//   * DC-link and mid-point voltages: resistive divider, v = (3 V / range) * v_measured.
//   * Each chain has a gain error g, an offset o (referred to the measured quantity, SI units)
//     and white Gaussian noise n of a given RMS: measured = x * (1 + g) + o + n.
//   * Encoder: `lines` lines, quadrature decoding = 4 * lines counts per mechanical turn, counting
//     up for positive speed; an index pulse once per turn at mechanical angle -offset.
//
// The noise generator is std::mt19937_64 (output fully specified by the C++ standard) with our
// own Box-Muller transform, so a given seed gives the same noise on every standard library
// (std::normal_distribution is implementation-defined).
#ifndef HAL_HOST_SENSORS_HPP
#define HAL_HOST_SENSORS_HPP

#include <cstdint>
#include <random>

namespace hal_host {

constexpr double kAdcFullScaleV = 3.0;
constexpr double kAdcMaxCode = 4095.0;

/// 12-bit conversion of an input voltage: round(4095 * v / 3), clamped to 0..4095 (the F2812
/// ADC saturates at its rails; NaN reads as 0).
std::uint16_t adc_code(double v_in);

/// Inverse of the ideal transfer (centre of the code's bin), for tests and for the firmware-side
/// expectations: v = code * 3 / 4095.
double adc_code_to_volts(std::uint16_t code);

/// Deterministic white Gaussian noise (mt19937_64 + Box-Muller), zero mean, unit variance.
class GaussianNoise {
public:
    explicit GaussianNoise(std::uint64_t seed) : rng_(seed) {}
    double next();
    void reseed(std::uint64_t seed) { rng_.seed(seed); have_spare_ = false; }

private:
    std::mt19937_64 rng_;
    double spare_ = 0.0;
    bool have_spare_ = false;
};

/// One analogue channel: measured = x * (1 + gain_error) + offset + noise_rms * N(0,1);
/// v_adc = v_bias + volts_per_unit * measured.
struct AnalogChannel {
    double volts_per_unit = 0.0; // sensor + conditioning gain, V per A (or V per V)
    double v_bias = 0.0;         // level shift at the ADC input, V (1.5 V for bipolar currents)
    double gain_error = 0.0;     // relative, 0.01 = +1 %
    double offset = 0.0;         // in the measured quantity's unit (A or V)
    double noise_rms = 0.0;      // in the measured quantity's unit

    /// ADC input voltage for a true value x and one unit-variance noise draw.
    double volts(double x, double unit_noise) const
    {
        const double measured = x * (1.0 + gain_error) + offset + noise_rms * unit_noise;
        return v_bias + volts_per_unit * measured;
    }
    std::uint16_t code(double x, double unit_noise) const { return adc_code(volts(x, unit_noise)); }
};

/// Bipolar current channel: +-range_a maps onto 0..3 V around 1.5 V.
AnalogChannel current_channel(double range_a, double gain_error, double offset_a, double noise_a_rms);
/// Unipolar voltage divider: 0..range_v maps onto 0..3 V.
AnalogChannel voltage_channel(double range_v, double gain_error, double offset_v, double noise_v_rms);

/// Quadrature encoder on the rotor shaft.
class Encoder {
public:
    Encoder(std::uint32_t lines, double offset_rad);
    std::uint32_t counts_per_turn() const { return 4u * lines_; }
    /// Counter value for an unwrapped mechanical angle: floor((theta + offset) / 2pi * 4 lines),
    /// reduced modulo 4 * lines (what the QEP counter holds when its index resets it each turn).
    std::uint16_t count(double theta_m_rad) const;
    /// Whole turns of (theta + offset): the index pulse fires whenever this changes.
    std::int64_t turn(double theta_m_rad) const;

private:
    std::uint32_t lines_;
    double offset_rad_;
};

} // namespace hal_host

#endif // HAL_HOST_SENSORS_HPP
