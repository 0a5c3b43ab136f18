// fuzz_args.hpp - a fuzz input as a command line: the arguments after the program's name,
// separated by '\n' (fuzz_cli.cpp, fuzz_sil_cli.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

/// args[0] is prog; then the input's '\n'-separated pieces, at most max_args of them.
inline std::vector<std::string> fuzz_args(const std::uint8_t* data, std::size_t n, const char* prog,
                                          std::size_t max_args)
{
    const std::string text(reinterpret_cast<const char*>(data), n);
    std::vector<std::string> args{prog};
    std::size_t b = 0;
    for (std::size_t i = 0; i <= text.size() && args.size() <= max_args; ++i) {
        if (i == text.size() || text[i] == '\n') {
            args.push_back(text.substr(b, i - b));
            b = i + 1;
        }
    }
    return args;
}

/// True when an argument asks for help or the version: --help, --version, or -h alone or in a
/// group of short flags (-hx).
inline bool fuzz_arg_is_help(const std::string& a)
{
    return a.rfind("--help", 0) == 0 || a.rfind("--version", 0) == 0 ||
           (a.size() > 1 && a[0] == '-' && a[1] != '-' && a.find('h') != std::string::npos);
}
