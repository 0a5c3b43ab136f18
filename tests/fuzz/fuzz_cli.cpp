// fuzz_cli.cpp - libFuzzer harness of dtc_config_gen's command line (parse_gen_args,
// tools/config/dtc_config_gen_cli.hpp), docs/fuzzing.md.
//
// Input: the arguments after the program's name, separated by '\n' (at most 16).
// Invariants (each a crash): no undefined behaviour, memory error or escaping exception; the
// status is -1 (accepted), 0 (--help, --version or -h, alone or in a group -hx) or 2 (bad usage, with a message); an
// accepted command line has an OUTPUT that is not empty and does not start with '-', a SYMBOL
// check_symbol accepts, and a relay closing time of 0 (not given) or in (0, 10] s.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "dtc_config_gen_cli.hpp"
#include "fuzz_args.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t n)
{
    const std::vector<std::string> args = fuzz_args(data, n, "dtc_config_gen", 16);
    std::vector<const char*> argv;
    bool help = false;
    for (const std::string& a : args) {
        argv.push_back(a.c_str());
        help = help || fuzz_arg_is_help(a);
    }
    GenArgs g;
    std::ostringstream out, err;
    const int rc = parse_gen_args(static_cast<int>(argv.size()), argv.data(), &g, out, err);
    if (rc == -1) {
        const bool relay_ok = g.relay_s == 0.0 || (std::isfinite(g.relay_s) && g.relay_s > 0.0 && g.relay_s <= 10.0);
        if (g.output.empty() || g.output[0] == '-' || !check_symbol(g.sym).empty() || !relay_ok) {
            std::abort();
        }
    } else if (!((rc == 0 && help && !out.str().empty()) || (rc == 2 && !err.str().empty()))) {
        std::abort();
    }
    return 0;
}
