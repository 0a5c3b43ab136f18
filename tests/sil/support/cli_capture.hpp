// cli_capture.hpp - dtc-sil's command line run inside the test: the helper the CLI-level SIL tests
// share (what the command prints is kept as text, nothing reaches the terminal).
#pragma once

#include <ostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "run.hpp"

namespace sil_test {

// A command-line entry point of dtc-sil: sil::dtc_sil_main, or one of its commands' own
// (sil::sweep::sweep_main).
using CliMain = int (*)(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

// Runs main on "dtc-sil" followed by args; *out and *err (where not null) get what it printed on
// stdout and stderr. Returns its exit status.
inline int run_cli(std::vector<std::string> args, std::string* out = nullptr, std::string* err = nullptr,
                   CliMain main = sil::dtc_sil_main)
{
    args.insert(args.begin(), "dtc-sil");
    std::ostringstream o, e;
    const int rc = main(args, o, e);
    if (out != nullptr) {
        *out = o.str();
    }
    if (err != nullptr) {
        *err = e.str();
    }
    return rc;
}

} // namespace sil_test
