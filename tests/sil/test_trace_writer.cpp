// trace.csv: every value reads back (strtod, as numpy.loadtxt) to the identical double.
#include <gtest/gtest.h>

#include <array>
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
    constexpr int n = 20000; // > one 1 MiB buffer: the flush path is exercised
    constexpr std::size_t nd = 20; // 18 columns of every trace + the IM's two rotor-flux columns
    std::vector<std::array<double, nd>> rows(n);
    std::vector<std::array<int, 4>> ints(n);
    TraceWriter w;
    w.set_rotor_flux_columns(true);
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
                   static_cast<int>(rng() % 2)};
        const auto& i = ints[k];
        const TraceRow r{v[0],  v[1],  v[2],  v[3],  v[4],  v[5],  v[6],  v[7],  v[8],  v[9],  v[10], v[11],
                         v[12], i[0],  i[1],  i[2],  v[13], i[3],  v[14], v[15], v[16], v[17], v[0],
                         v[18], v[19]};
        w.write(r);
    }
    ASSERT_TRUE(w.close(&err)) << err;

    std::ifstream f(path);
    std::string line;
    ASSERT_TRUE(std::getline(f, line));
    EXPECT_EQ(line, std::string(trace_header()) + ",psi_r_alpha_wb,psi_r_beta_wb");
    std::size_t k = 0;
    const int order[25] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, -1, -2, -3, 13, -4, 14, 15, 16, 17, 0, 18, 19};
    while (std::getline(f, line)) {
        ASSERT_LT(k, rows.size());
        const char* p = line.c_str();
        for (int c = 0; c < 25; ++c) {
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
            ASSERT_EQ(*p, c < 24 ? ',' : '\0') << line;
            ++p;
        }
        ++k;
    }
    EXPECT_EQ(k, rows.size());
    std::filesystem::remove(path);
}
