// trace_csv.hpp - reads a run's trace.csv (tools/sil, docs/sil.md) into one vector per column,
// keyed by the column's name, for tests that judge a run from its trace.
#ifndef SIL_TEST_TRACE_CSV_HPP
#define SIL_TEST_TRACE_CSV_HPP

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace sil_test {

inline std::map<std::string, std::vector<double>> read_trace(const std::filesystem::path& p)
{
    std::ifstream f(p);
    std::string line;
    std::getline(f, line);
    std::vector<std::string> names;
    std::stringstream hs(line);
    for (std::string c; std::getline(hs, c, ',');) {
        names.push_back(c);
    }
    std::map<std::string, std::vector<double>> cols;
    while (std::getline(f, line)) {
        std::stringstream ls(line);
        std::size_t i = 0;
        for (std::string c; std::getline(ls, c, ','); ++i) {
            cols[names.at(i)].push_back(std::strtod(c.c_str(), nullptr));
        }
    }
    return cols;
}

} // namespace sil_test

#endif
