// dtc_config_gen_cli.hpp - dtc_config_gen's command line (CLI11), apart from the writing so that
// the fuzz preset can drive it (tests/fuzz/fuzz_cli.cpp):
//
//   dtc_config_gen [--f2812-board] [--params-md] [--reconfig-relay DELAY_S] OUTPUT.c [SYMBOL]
#pragma once

#include <ostream>
#include <string>

struct GenArgs {
    bool board = false;     // --f2812-board
    bool im = false;        // --im
    bool params_md = false; // --params-md
    double relay_s = 0.0;   // --reconfig-relay: in (0, 10] s when given, else 0
    std::string output;     // OUTPUT.c: not empty, not starting with '-'
    std::string sym = "dtc_config_default"; // SYMBOL: check_symbol(sym) == ""
};

/// "" when s is a C identifier that can be SYMBOL (not a keyword, not reserved, short enough for
/// the suffixes the file adds), else why not.
std::string check_symbol(const std::string& s);

/// Reads argv (argv[0] the program's name) into *a. Returns -1 when the arguments are accepted,
/// else the exit status with its message written to out or err: 0 for --help and --version, 2 for
/// bad usage (an unknown option, a missing OUTPUT, a bad DELAY_S, OUTPUT or SYMBOL).
int parse_gen_args(int argc, const char* const* argv, GenArgs* a, std::ostream& out, std::ostream& err);
