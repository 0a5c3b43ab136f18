// trace.csv: every value reads back (strtod, as numpy.loadtxt) to the identical double, and is
// the text std::to_chars writes.
#include <gtest/gtest.h>

#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <unistd.h>

#include "sil_output.hpp"

using namespace sil;

TEST(TraceWriter, EveryValueReadsBackToTheSameDouble)
{
    const std::string path =
        (std::filesystem::temp_directory_path() / ("trace_rt_" + std::to_string(::getpid()) + ".csv")).string();
    std::mt19937_64 rng(18);
    std::normal_distribution<double> g(0.0, 1.0);
    const double special[] = {0.0,
                              -0.0,
                              1.0,
                              70.0,
                              5e-05,
                              1e-4,
                              std::numeric_limits<double>::denorm_min(),
                              std::numeric_limits<double>::min(),
                              std::numeric_limits<double>::max(),
                              -std::numeric_limits<double>::max(),
                              0.1 + 0.2,
                              1.0 / 3.0,
                              1500.0000000000002,
                              std::nan(""),
                              std::numeric_limits<double>::infinity(),
                              -std::numeric_limits<double>::infinity()};
    constexpr int n = 20000; // many batches, the last one partial
    constexpr std::size_t nd = 20; // 18 columns of every trace + the IM's two rotor-flux columns
                                   // (then the three integer fault columns)
    std::vector<std::array<double, nd>> rows(n);
    std::vector<std::array<int, 7>> ints(n);
    TraceWriter w;
    w.set_rotor_flux_columns(true);
    w.set_fault_columns(true);
    std::string err;
    ASSERT_TRUE(w.open(path, &err)) << err;
    for (std::size_t k = 0; k < rows.size(); ++k) {
        auto& v = rows[k];
        for (double& x : v) {
            const auto pick = rng() % 4;
            if (pick == 0) {
                x = special[rng() % (sizeof special / sizeof special[0])];
            } else if (pick == 1) {
                x = std::ldexp(g(rng), static_cast<int>(rng() % 200) - 100);
            } else if (pick == 2) {
                x = g(rng) * 3.0;
            } else {
                const std::uint64_t bits = rng();
                std::memcpy(&x, &bits, sizeof x); // any bit pattern (NaN payloads read back as nan)
            }
        }
        ints[k] = {static_cast<int>(rng() % 2), static_cast<int>(rng() % 2), static_cast<int>(rng() % 2),
                   static_cast<int>(rng() % 2), static_cast<int>(rng() % 4), static_cast<int>(rng() % 4),
                   static_cast<int>(rng() % 8)};
        const auto& i = ints[k];
        const TraceRow r{v[0],  v[1],  v[2],  v[3],  v[4],  v[5],  v[6],  v[7],  v[8],  v[9],  v[10], v[11],
                         v[12], i[0],  i[1],  i[2],  v[13], i[3],  v[14], v[15], v[16], v[17], v[0],
                         v[18], v[19], i[4], i[5], i[6]};
        w.write(r);
    }
    ASSERT_TRUE(w.close(&err)) << err;

    std::ifstream f(path);
    std::string line;
    ASSERT_TRUE(std::getline(f, line));
    EXPECT_EQ(line, std::string(trace_header()) + ",psi_r_alpha_wb,psi_r_beta_wb,relay,relay_closed,desat");
    std::size_t k = 0;
    const int order[28] = {0,  1,  2,  3,  4,  5,  6,  7,  8,  9,  10, 11, 12, -1,
                           -2, -3, 13, -4, 14, 15, 16, 17, 0,  18, 19, -5, -6, -7};
    while (std::getline(f, line)) {
        ASSERT_LT(k, rows.size());
        const char* p = line.c_str();
        for (int c = 0; c < 28; ++c) {
            char* end = nullptr;
            const double got = std::strtod(p, &end);
            ASSERT_NE(end, p) << "row " << k << " column " << c << ": " << line;
            if (order[c] < 0) {
                EXPECT_EQ(got, ints[k][static_cast<std::size_t>(-order[c] - 1)]);
            } else {
                const double want = rows[k][static_cast<std::size_t>(order[c])];
                if (std::isnan(want)) {
                    EXPECT_TRUE(std::isnan(got)) << line;
                } else {
                    // Bit for bit (so -0.0 stays -0.0).
                    EXPECT_EQ(std::memcmp(&got, &want, sizeof got), 0)
                        << "row " << k << " column " << c << ": wrote " << want << " read " << got;
                }
            }
            p = end;
            ASSERT_EQ(*p, c < 27 ? ',' : '\0') << line;
            ++p;
        }
        ++k;
    }
    EXPECT_EQ(k, rows.size());
    std::filesystem::remove(path);
}

// put_shortest() writes exactly what std::to_chars writes (the shortest round-trip form, plain or
// scientific, whichever is shorter): every kind of double a trace holds and any bit pattern.
TEST(TraceWriter, ShortestTextIsTheToCharsText)
{
    std::mt19937_64 rng(1812);
    long checked = 0;
    auto check = [&checked](double x) {
        char want[64];
        char got[128];
        const char* want_end = std::to_chars(want, want + sizeof want, x).ptr;
        const char* got_end = put_shortest(got, x);
        ++checked;
        const std::string w(static_cast<const char*>(want), want_end);
        const std::string g(static_cast<const char*>(got), got_end);
        if (w != g) {
            ADD_FAILURE() << "to_chars " << w << ", put_shortest " << g;
            return false;
        }
        return true;
    };
    // Integers (plain form, the digit blocks of every 6-digit value; above 10^15 to_chars writes
    // the double's exact value), and every decade from 10^-330 to 10^310.
    for (int v = 0; v < 1000000; ++v) {
        ASSERT_TRUE(check(static_cast<double>(v)));
        ASSERT_TRUE(check(-static_cast<double>(v) * 1e-3));
    }
    for (int k = -330; k <= 310; ++k) {
        const double p10 = std::pow(10.0, k);
        for (double m : {1.0, 1.5, 9.999999999999999, 123456789012345.0, 3.0000000000000004}) {
            ASSERT_TRUE(check(m * p10));
            ASSERT_TRUE(check(std::nextafter(m * p10, 0.0)));
        }
    }
    for (std::uint64_t v = 1; v != 0 && v < (1ULL << 63); v = v * 3 + 1) { // 10^15 .. 10^22 and beyond
        ASSERT_TRUE(check(static_cast<double>(v)));
    }
    // The plant's accumulated time (k * 50 us), random decimals of 1..17 digits at any scale.
    double t = 0.0;
    for (int k = 0; k < 100000; ++k) {
        ASSERT_TRUE(check(t));
        t += 5e-05;
    }
    for (int k = 0; k < 500000; ++k) {
        const int digits = 1 + static_cast<int>(rng() % 17);
        const double sig = static_cast<double>(rng() % static_cast<std::uint64_t>(std::pow(10.0, digits)));
        const double x = sig * std::pow(10.0, static_cast<int>(rng() % 60) - 40);
        ASSERT_TRUE(check(x));
        ASSERT_TRUE(check(-x));
    }
    // Any bit pattern: subnormals, the extremes, NaN and infinities.
    for (int k = 0; k < 2000000; ++k) {
        const std::uint64_t bits = rng();
        double x;
        std::memcpy(&x, &bits, sizeof x);
        if (std::isnan(x)) {
            char got[64];
            const char* end = put_shortest(got, x);
            EXPECT_EQ(std::string(static_cast<const char*>(got), end), "nan");
            continue;
        }
        ASSERT_TRUE(check(x));
    }
    for (double x : {std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::min(),
                     std::numeric_limits<double>::max(), std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity(), -0.0, 0.0}) {
        ASSERT_TRUE(check(x));
    }
    EXPECT_GT(checked, 4000000);
}
