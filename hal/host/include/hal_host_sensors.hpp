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
// The noise generator is xoshiro256++ (Blackman & Vigna 2021, seeded through splitmix64) with our
// own ziggurat transform (Marsaglia & Tsang 2000, 256 layers), both fully specified here, so a
// given seed gives the same noise on every standard library (std::normal_distribution is
// implementation-defined). It replaced std::mt19937_64 + Box-Muller (one log, one sqrt, one
// sin/cos per two draws), which cost more than the rest of the sensor emulation together.
#ifndef HAL_HOST_SENSORS_HPP
#define HAL_HOST_SENSORS_HPP

#include <cstdint>

#include "plant_defaults.h"

namespace hal_host {

constexpr double kAdcFullScaleV = 3.0;
constexpr double kAdcMaxCode = PLANT_DEF_ADC_FULL_SCALE_CODES; // 12 bits

/// 12-bit conversion of an input voltage: round(4095 * v / 3), clamped to 0..4095 (the F2812
/// ADC saturates at its rails; NaN reads as 0).
inline std::uint16_t adc_code(double v_in)
{
    const double y = kAdcMaxCode * v_in / kAdcFullScaleV;
    if (!(y > 0.0)) { // also catches NaN; round(y) <= 0 for every such y
        return 0u;
    }
    if (y >= kAdcMaxCode) {
        return 4095u;
    }
    // Round to nearest, ties to even, exactly as std::nearbyint in the default rounding mode but
    // without the library call: for 0 < y < 2^51, y + 1.5 * 2^52 has no fraction bits left, so the
    // addition rounds y to an integer (IEEE 754 round-to-nearest-even) and the subtraction is exact.
    // (Needs IEEE semantics: no -ffast-math, which would fold the two operations away; the project
    // never builds with it, and AdcQuantisesAndClampsAtTheRails checks a tie.)
    constexpr double kRound = 0x1.8p52;
    return static_cast<std::uint16_t>((y + kRound) - kRound);
}

/// Inverse of the ideal transfer (centre of the code's bin), for tests and for the firmware-side
/// expectations: v = code * 3 / 4095.
double adc_code_to_volts(std::uint16_t code);

/// xoshiro256++ (D. Blackman, S. Vigna, "Scrambled linear pseudorandom number generators", ACM
/// TOMS 47(4), 2021): period 2^256 - 1, all 64 output bits pass BigCrush. The 256-bit state is
/// filled from the 64-bit seed by splitmix64 (the seeding the authors recommend; any seed,
/// including 0, gives a valid non-zero state).
class Xoshiro256pp {
public:
    explicit Xoshiro256pp(std::uint64_t seed) { seed_with(seed); }
    void seed_with(std::uint64_t seed);
    std::uint64_t operator()()
    {
        const std::uint64_t result = rotl(s_[0] + s_[3], 23) + s_[0];
        const std::uint64_t t = s_[1] << 17;
        s_[2] ^= s_[0];
        s_[3] ^= s_[1];
        s_[1] ^= s_[2];
        s_[0] ^= s_[3];
        s_[2] ^= t;
        s_[3] = rotl(s_[3], 45);
        return result;
    }

private:
    static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
    std::uint64_t s_[4];
};

/// Deterministic white Gaussian noise, zero mean, unit variance: ziggurat method (G. Marsaglia,
/// W. W. Tsang, "The ziggurat method for generating random variables", J. Stat. Softw. 5(8),
/// 2000) with 256 layers of equal area under f(x) = exp(-x^2/2), one xoshiro256++ word per try:
/// bits 0-7 pick the layer, bit 8 the sign and bits 11-63 the 53-bit abscissa (disjoint bits, so
/// layer and abscissa are independent; J. A. Doornik, "An improved ziggurat method to generate
/// normal random samples", 2005). 98.5 % of draws are one word, one table lookup and one compare;
/// the rest take the exact wedge test (one exp) or Marsaglia's exact tail beyond r = 3.654.
/// The method is exact: the only approximation is the 53-bit resolution of the uniforms.
class GaussianNoise {
public:
    explicit GaussianNoise(std::uint64_t seed);
    /// Draws come from a block of kBatch made ahead in one tight loop (the generator state stays
    /// in registers); the sequence is the same as drawing them one at a time.
    double next()
    {
        if (pos_ == kBatch) {
            refill();
        }
        return buf_[pos_++];
    }
    void reseed(std::uint64_t seed)
    {
        rng_.seed_with(seed);
        pos_ = kBatch;
    }

    /// Ziggurat tables (built once per process): x[0] = v / f(r) (the base layer's equivalent
    /// width), x[1] = r, f(x[i+1]) = f(x[i]) + v / x[i], x[256] = 0; ratio[i] = x[i+1] / x[i],
    /// fx[i] = f(x[i]). v = r f(r) + integral_r^inf f = the area of each layer.
    struct Tables {
        double x[257];
        double fx[257];
        double ratio[256];
    };
    static constexpr double kR = 3.6541528853610088; // r for 256 layers (Marsaglia & Tsang)

private:
    static constexpr unsigned kBatch = 64;
    void refill();
    double slow(unsigned i, double u, bool negative);
    Xoshiro256pp rng_;
    const Tables* t_;
    unsigned pos_ = kBatch;
    double buf_[kBatch];
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
    /// count() and turn() from one division (what hal_host samples every period).
    std::uint16_t read(double theta_m_rad, std::int64_t* turn) const;

private:
    std::uint32_t lines_;
    double offset_rad_;
};

} // namespace hal_host

#endif // HAL_HOST_SENSORS_HPP
