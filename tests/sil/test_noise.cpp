// The sensor-noise generator of hal_host (hal_host_sensors.hpp): xoshiro256++ seeded by
// splitmix64, and the ziggurat normal transform. The generator's own bits are checked against an
// independent implementation of the published algorithms; the normal variates against the
// standard normal law with bounds of 5 standard errors of each statistic (fixed seeds, so every
// run draws the same numbers; a correct generator fails a 5-sigma bound with probability ~1e-6).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "hal_host_sensors.hpp"

namespace {

using hal_host::GaussianNoise;
using hal_host::Xoshiro256pp;

double phi(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); } // standard normal CDF

std::vector<double> draws(std::uint64_t seed, std::size_t n)
{
    GaussianNoise g(seed);
    std::vector<double> v(n);
    for (double& x : v) {
        x = g.next();
    }
    return v;
}

} // namespace

// Expected words from a separate (Python, arbitrary-precision integer) transcription of
// splitmix64 and xoshiro256++ as published by Blackman & Vigna; splitmix64(0)'s first output,
// 0xe220a8397b1dcdaf, is the value given with the reference code.
TEST(SensorNoise, Xoshiro256ppMatchesTheReferenceAlgorithm)
{
    Xoshiro256pp a(0);
    EXPECT_EQ(a(), 0x53175d61490b23dfu);
    EXPECT_EQ(a(), 0x61da6f3dc380d507u);
    EXPECT_EQ(a(), 0x5c0fdf91ec9a7bfcu);
    Xoshiro256pp b(1234);
    EXPECT_EQ(b(), 0xc1cdea79b61cd477u);
    EXPECT_EQ(b(), 0x6c9f3f8e08767fd5u);
    EXPECT_EQ(b(), 0xf42e33f9cec8c13du);
}

TEST(SensorNoise, MomentsAreThoseOfTheStandardNormal)
{
    const std::size_t n = 1000000;
    for (std::uint64_t seed : {0u, 1u, 1234u}) {
        const auto v = draws(seed, n);
        double m1 = 0.0, m2 = 0.0, m3 = 0.0, m4 = 0.0;
        for (double x : v) {
            const double x2 = x * x;
            m1 += x;
            m2 += x2;
            m3 += x2 * x;
            m4 += x2 * x2;
        }
        const double dn = static_cast<double>(n);
        m1 /= dn;
        m2 /= dn;
        m3 /= dn;
        m4 /= dn;
        // Standard errors for N(0,1): mean 1/sqrt(n), E[x^2] sqrt(2/n), E[x^3] sqrt(15/n),
        // E[x^4] sqrt(96/n).
        EXPECT_NEAR(m1, 0.0, 5.0 * std::sqrt(1.0 / dn)) << "seed " << seed;
        EXPECT_NEAR(m2, 1.0, 5.0 * std::sqrt(2.0 / dn)) << "seed " << seed;
        EXPECT_NEAR(m3, 0.0, 5.0 * std::sqrt(15.0 / dn)) << "seed " << seed;
        EXPECT_NEAR(m4, 3.0, 5.0 * std::sqrt(96.0 / dn)) << "seed " << seed;
    }
}

// The shape, wedges included: a chi-square test on 0.1-wide bins over [-4, 4] (wedges of the
// 256 layers are narrower than that from |x| ~ 0.5 outwards, so a wrong wedge test or table
// shows), plus a Kolmogorov-Smirnov distance against the exact CDF.
TEST(SensorNoise, DistributionMatchesTheNormalCdf)
{
    const std::size_t n = 1000000;
    auto v = draws(7, n);
    const int bins = 80;
    std::vector<double> count(bins + 2, 0.0); // [0] below -4, [bins + 1] above 4
    for (double x : v) {
        const int b = x < -4.0 ? 0 : (x >= 4.0 ? bins + 1 : 1 + static_cast<int>(std::floor((x + 4.0) / 0.1)));
        count[static_cast<std::size_t>(std::min(b, bins + 1))] += 1.0;
    }
    double chi2 = 0.0;
    for (int b = 0; b < bins + 2; ++b) {
        const double lo = b == 0 ? -INFINITY : -4.0 + 0.1 * (b - 1);
        const double hi = b == bins + 1 ? INFINITY : -4.0 + 0.1 * b;
        const double e = static_cast<double>(n) * (phi(hi) - phi(lo));
        chi2 += (count[static_cast<std::size_t>(b)] - e) * (count[static_cast<std::size_t>(b)] - e) / e;
    }
    const double dof = bins + 1;
    EXPECT_LT(chi2, dof + 5.0 * std::sqrt(2.0 * dof)) << "chi-square over " << bins + 2 << " bins";

    std::sort(v.begin(), v.end());
    double d = 0.0;
    for (std::size_t i = 0; i < n; i += 37) { // every 37th order statistic: plenty for the sup
        const double f = phi(v[i]);
        d = std::max({d, std::fabs(f - static_cast<double>(i) / static_cast<double>(n)),
                      std::fabs(f - static_cast<double>(i + 1) / static_cast<double>(n))});
    }
    // Kolmogorov distribution: P(sqrt(n) D > 1.95) = 0.001.
    EXPECT_LT(d * std::sqrt(static_cast<double>(n)), 1.95);
}

// The base layer's tail beyond r = 3.654 takes its own exact path (Marsaglia's tail method).
TEST(SensorNoise, TailBeyondTheZigguratBaseHasTheNormalProbability)
{
    const std::size_t n = 4000000;
    const double r = GaussianNoise::kR;
    GaussianNoise g(99);
    double pos = 0.0, neg = 0.0, far = 0.0, sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const double x = g.next();
        pos += x > r ? 1.0 : 0.0;
        neg += x < -r ? 1.0 : 0.0;
        far += std::fabs(x) > 4.5 ? 1.0 : 0.0;
        sum += std::fabs(x) > r ? std::fabs(x) : 0.0;
    }
    const double p = phi(-r);                    // 1.29e-4 per side
    const double e = static_cast<double>(n) * p; // ~516
    EXPECT_NEAR(pos, e, 5.0 * std::sqrt(e));
    EXPECT_NEAR(neg, e, 5.0 * std::sqrt(e));
    const double e_far = static_cast<double>(n) * 2.0 * phi(-4.5); // ~27
    EXPECT_NEAR(far, e_far, 5.0 * std::sqrt(e_far));
    // Shape of the tail: for the normal law truncated to x > r, the mean is lambda = pdf(r) / Q(r)
    // and the variance 1 + r lambda - lambda^2 (3.897 and 0.053 at r = 3.654).
    const double pdf_r = std::exp(-0.5 * r * r) / std::sqrt(2.0 * 3.14159265358979323846);
    const double lambda = pdf_r / p;
    const double var = 1.0 + r * lambda - lambda * lambda;
    const double m = pos + neg;
    EXPECT_NEAR(sum / m, lambda, 5.0 * std::sqrt(var / m));
}

// Successive draws are independent: no correlation of values, magnitudes or signs at lags 1-3
// (the layer, the sign and the abscissa come from disjoint bits of one word).
TEST(SensorNoise, SuccessiveDrawsAreUncorrelated)
{
    const std::size_t n = 1000000;
    const auto v = draws(3, n);
    for (std::size_t lag = 1; lag <= 3; ++lag) {
        double c = 0.0, c2 = 0.0, cs = 0.0;
        for (std::size_t i = lag; i < n; ++i) {
            c += v[i] * v[i - lag];
            c2 += (v[i] * v[i] - 1.0) * (v[i - lag] * v[i - lag] - 1.0);
            cs += ((v[i] > 0.0) == (v[i - lag] > 0.0)) ? 1.0 : -1.0;
        }
        const double m = static_cast<double>(n - lag);
        EXPECT_NEAR(c / m, 0.0, 5.0 / std::sqrt(m)) << "lag " << lag;
        EXPECT_NEAR(c2 / (2.0 * m), 0.0, 5.0 / std::sqrt(m)) << "lag " << lag; // var(x^2 - 1) = 2
        EXPECT_NEAR(cs / m, 0.0, 5.0 / std::sqrt(m)) << "lag " << lag;
    }
}

TEST(SensorNoise, SameSeedSameSequenceAcrossReseedAndBatchBoundaries)
{
    const auto a = draws(42, 1000);
    GaussianNoise g(7);
    for (int i = 0; i < 10; ++i) {
        (void)g.next(); // leave a partly used batch behind
    }
    g.reseed(42);
    for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(g.next(), a[i]) << "draw " << i;
    }
    EXPECT_NE(draws(43, 1000), a);
}
