// dtc_config_gen_cli.cpp - dtc_config_gen's command line (dtc_config_gen_cli.hpp).
#include "dtc_config_gen_cli.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdlib>
#include <cstring>

#include "dtc_config_si.h"

namespace {

/// The suffix the longest generated name adds to SYMBOL (SYMBOL_post_fstp).
constexpr const char* kLongestSuffix = "_post_fstp";
/// C99 5.2.4.1: 63 significant initial characters in an internal identifier.
constexpr std::size_t kMaxIdentifier = 63;

} // namespace

/// "" when s is a C identifier that can be SYMBOL, else why not.
std::string check_symbol(const std::string& s)
{
    static const char* const keywords[] = {
        "auto",     "break",    "case",     "char",   "const",    "continue", "default",  "do",
        "double",   "else",     "enum",     "extern", "float",    "for",      "goto",     "if",
        "inline",   "int",      "long",     "register", "restrict", "return", "short",    "signed",
        "sizeof",   "static",   "struct",   "switch", "typedef",  "union",    "unsigned", "void",
        "volatile", "while",    "_Bool",    "_Complex", "_Imaginary"};
    if (s.empty()) {
        return "is empty";
    }
    const auto ident = [](char c, bool first) {
        return c == '_' || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (!first && c >= '0' && c <= '9');
    };
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (!ident(s[i], i == 0)) {
            return "is not a C identifier (letters, digits and _, not starting with a digit)";
        }
    }
    for (const char* k : keywords) {
        if (s == k) {
            return "is a C keyword";
        }
    }
    if (s[0] == '_' && (s.size() == 1 || s[1] == '_' || (s[1] >= 'A' && s[1] <= 'Z'))) {
        return "is reserved for the implementation (C99 7.1.3: _ followed by _ or a capital)";
    }
    if (s.size() + std::strlen(kLongestSuffix) > kMaxIdentifier) {
        return "is " + std::to_string(s.size()) + " characters: with the " + kLongestSuffix + " suffix the file adds, " +
               "more than the " + std::to_string(kMaxIdentifier) + " a C compiler must tell apart (at most " +
               std::to_string(kMaxIdentifier - std::strlen(kLongestSuffix)) + ")";
    }
    return "";
}

int parse_gen_args(int argc, const char* const* argv, GenArgs* a, std::ostream& out, std::ostream& err)
{
    CLI::App app{"dtc_config_gen: writes the firmware's default configuration as a C source file"};
    app.set_version_flag("--version", std::string("dtc_config_gen ") + DTC_PROJECT_VERSION +
                                          " (configuration version " + std::to_string(DTC_CONFIG_VERSION) + ")");
    app.add_flag("--f2812-board", a->board, "dead time and control period as the F2812 board's registers produce them");
    app.add_flag("--im", a->im,
                 "the induction-machine defaults (dtc_config_si_im_defaults) instead of the PM drive's");
    app.add_flag("--params-md", a->params_md,
                 "write the table of every firmware parameter (docs/parameters.md) to OUTPUT instead");
    app.add_option("--reconfig-relay", a->relay_s,
                   "a six-switch board with reconfiguration relays closing in DELAY_S seconds (defines SYMBOL_post)")
        ->type_name("DELAY_S")
        ->check(CLI::Validator(
            [](std::string& v) {
                char* end = nullptr;
                const double x = std::strtod(v.c_str(), &end);
                return end != v.c_str() && *end == '\0' && std::isfinite(x) && x > 0.0 && x <= 10.0
                           ? std::string()
                           : "the relay's closing time in s: a number in (0, 10]";
            },
            "DELAY_S", "(0, 10] s"));
    app.add_option("output", a->output, "the C file to write")->required()->type_name("OUTPUT.c");
    app.add_option("symbol", a->sym, "the configuration's C name (default dtc_config_default)")->type_name("SYMBOL");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e, out, err) == 0 ? 0 : 2;
    }
    if (a->im && a->relay_s > 0.0) {
        err << "dtc_config_gen: --reconfig-relay with --im: the IM law has no post-fault configuration "
               "(a failed leg trips)\n";
        return 2;
    }
    if (a->output.empty() || a->output[0] == '-') {
        err << "dtc_config_gen: OUTPUT '" << a->output << "': a file name cannot start with '-' (write ./" << a->output
            << ")\n";
        return 2;
    }
    if (const std::string why = check_symbol(a->sym); !why.empty()) {
        err << "dtc_config_gen: SYMBOL '" << a->sym.substr(0, 80) << (a->sym.size() > 80 ? "..." : "") << "': " << why
            << "\n";
        return 2;
    }
    return -1;
}
