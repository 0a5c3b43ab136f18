// cli_parse.hpp - the command-line parse dtc-sil's commands share (cli.cpp, sweep.cpp).
#pragma once

#include <CLI/CLI.hpp>

#include <ostream>
#include <string>
#include <vector>

/// Parses args (args[0] is the program name) into app. On --help or a parse error CLI11's text goes
/// to out or err and the result is false with *rc the exit status (0 for --help, 1 for an error).
inline bool cli_parse(CLI::App& app, const std::vector<std::string>& args, std::ostream& out,
                      std::ostream& err, int* rc)
{
    std::vector<std::string> argv_rev(args.rbegin(), args.rend()); // CLI11 parses a reversed vector
    if (!argv_rev.empty()) {
        argv_rev.pop_back(); // program name
    }
    try {
        app.parse(argv_rev);
    } catch (const CLI::ParseError& e) {
        *rc = app.exit(e, out, err) == 0 ? 0 : 1;
        return false;
    }
    return true;
}
