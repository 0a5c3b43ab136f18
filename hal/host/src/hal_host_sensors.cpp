// hal_host_sensors.cpp - see hal_host_sensors.hpp.
#include "hal_host_sensors.hpp"

#include <cmath>
#include <cstring>
#include <stdexcept>

namespace hal_host {

namespace {
constexpr double kTwoPi = 6.283185307179586476925286766559;
}

double adc_code_to_volts(std::uint16_t code)
{
    return static_cast<double>(code) * kAdcFullScaleV / kAdcMaxCode;
}

void Xoshiro256pp::seed_with(std::uint64_t seed)
{
    // splitmix64 (S. Vigna, public-domain reference): a bijective mix of a Weyl sequence.
    std::uint64_t z = seed;
    for (std::uint64_t& w : s_) {
        z += 0x9E3779B97F4A7C15u;
        std::uint64_t m = z;
        m = (m ^ (m >> 30)) * 0xBF58476D1CE4E5B9u;
        m = (m ^ (m >> 27)) * 0x94D049BB133111EBu;
        w = m ^ (m >> 31);
    }
}

namespace {

double gauss_f(double x) { return std::exp(-0.5 * x * x); }

GaussianNoise::Tables make_ziggurat_tables()
{
    GaussianNoise::Tables t{};
    constexpr int n = 256;
    const double r = GaussianNoise::kR;
    // Area of each layer: the base layer is the rectangle [0, r] x [0, f(r)] plus the tail.
    // v = r f(r) + sqrt(pi/2) erfc(r / sqrt(2)).
    const double v = r * gauss_f(r) + std::sqrt(0.25 * kTwoPi) * std::erfc(r / std::sqrt(2.0));
    t.x[0] = v / gauss_f(r);
    t.x[1] = r;
    for (int i = 1; i < n - 1; ++i) {
        t.x[i + 1] = std::sqrt(-2.0 * std::log(v / t.x[i] + gauss_f(t.x[i])));
    }
    t.x[n] = 0.0; // the top layer closes at f = 1 (residual area mismatch ~1e-15 of v)
    for (int i = 0; i <= n; ++i) {
        t.fx[i] = gauss_f(t.x[i]);
    }
    for (int i = 0; i < n; ++i) {
        t.ratio[i] = t.x[i + 1] / t.x[i];
    }
    return t;
}

const GaussianNoise::Tables& ziggurat_tables()
{
    static const GaussianNoise::Tables t = make_ziggurat_tables();
    return t;
}

} // namespace

GaussianNoise::GaussianNoise(std::uint64_t seed) : rng_(seed), t_(&ziggurat_tables()) {}

void GaussianNoise::refill()
{
    Xoshiro256pp r = rng_; // a local copy: its address never escapes, so it lives in registers
    const Tables& t = *t_;
    for (unsigned j = 0; j < kBatch; ++j) {
        const std::uint64_t b = r();
        const unsigned i = static_cast<unsigned>(b & 0xFFu);
        const double u = static_cast<double>(b >> 11) * 0x1.0p-53; // [0, 1)
        const bool negative = (b & 0x100u) != 0u;
        if (u < t.ratio[i]) { // inside the layer's rectangle, wholly under the curve
            // The sign without a branch (a random sign mispredicts half the time): bit 8 of the
            // word moved onto the IEEE sign bit.
            std::uint64_t bits = 0;
            const double x = u * t.x[i];
            std::memcpy(&bits, &x, sizeof bits);
            bits ^= (b & 0x100u) << 55;
            std::memcpy(&buf_[j], &bits, sizeof bits);
        } else { // wedge or tail (1.5 %): the exact tests draw more words from the member state
            rng_ = r;
            buf_[j] = slow(i, u, negative);
            r = rng_;
        }
    }
    rng_ = r;
    pos_ = 0;
}

double GaussianNoise::slow(unsigned i, double u, bool negative)
{
    for (;;) {
        if (i == 0u) {
            // Base layer outside [0, r): the tail x > r, exactly (Marsaglia 1964): x = r + a with
            // a = -ln(u1) / r accepted when -2 ln(u2) > a^2. u1, u2 in (0, 1] keep ln() finite.
            double a = 0.0;
            double e = 0.0;
            do {
                a = -std::log((static_cast<double>(rng_() >> 11) + 1.0) * 0x1.0p-53) / kR;
                e = -std::log((static_cast<double>(rng_() >> 11) + 1.0) * 0x1.0p-53);
            } while (e + e < a * a);
            return negative ? -(kR + a) : kR + a;
        }
        // Wedge of layer i (between x[i+1] and x[i]): accept the point if a uniform height in
        // [f(x[i]), f(x[i+1])] lies under the curve.
        const double x = u * t_->x[i];
        const double y = t_->fx[i] + (static_cast<double>(rng_() >> 11) * 0x1.0p-53) * (t_->fx[i + 1] - t_->fx[i]);
        if (y < gauss_f(x)) {
            return negative ? -x : x;
        }
        // Rejected: a fresh try from the start (layer, sign and abscissa all redrawn).
        const std::uint64_t b = rng_();
        i = static_cast<unsigned>(b & 0xFFu);
        u = static_cast<double>(b >> 11) * 0x1.0p-53;
        negative = (b & 0x100u) != 0u;
        if (u < t_->ratio[i]) {
            const double xr = u * t_->x[i];
            return negative ? -xr : xr;
        }
    }
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
    std::int64_t t = 0;
    return read(theta_m_rad, &t);
}

std::uint16_t Encoder::read(double theta_m_rad, std::int64_t* turn) const
{
    const double turns = (theta_m_rad + offset_rad_) / kTwoPi;
    const double whole = std::floor(turns);
    *turn = static_cast<std::int64_t>(whole);
    const double frac = turns - whole; // [0, 1)
    auto c = static_cast<std::uint32_t>(std::floor(frac * static_cast<double>(counts_per_turn())));
    if (c >= counts_per_turn()) { // frac rounding up to 1.0
        c = 0u;
    }
    return static_cast<std::uint16_t>(c);
}

} // namespace hal_host
