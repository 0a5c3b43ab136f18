// dtc_config_gen - writes the default configuration (dtc_config_si_defaults) as a C source file for
// a target build.
//
//   dtc_config_gen [--f2812-board] [--reconfig-relay DELAY_S] OUTPUT.c [SYMBOL]
//
// SYMBOL (default dtc_config_default) names the `const struct dtc_config`; the file also defines
// `const struct dtc_config *const SYMBOL_post`: the post-fault FSTP configuration for a six-switch
// board with reconfiguration relays (--reconfig-relay: their closing time; three current sensors;
// firmware app_core_set_reconfig), else NULL (the target passes it to app_set_reconfig).
// --f2812-board takes what the F2812 board's registers really produce from hal/f2812/f2812_board.h
// instead of the rig's defaults: the dead time the dead-band unit inserts (its DBT/prescaler
// rounding included) and the control period of timer 1, so the firmware's dead-time compensation
// and period scaling match the hardware it runs on.
//
// The file is written under OUTPUT.partial-PID and renamed to OUTPUT when complete: a refused
// configuration, a bad argument or a write error (a full disk included) leaves OUTPUT as it was.
// OUTPUT that exists and is not a regular file (/dev/stdout, a pipe) is written directly.
// Exit status: 0 written; 1 the configuration refused or a write error; 2 bad usage (CLI11).
#include <CLI/CLI.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

#include "dtc_config_si.h"
#include "im_tau_check.h"
#include "f2812_board.h"

namespace {

/// The suffix the longest generated name adds to SYMBOL (SYMBOL_post_fstp).
constexpr const char* kLongestSuffix = "_post_fstp";
/// C99 5.2.4.1: 63 significant initial characters in an internal identifier.
constexpr std::size_t kMaxIdentifier = 63;

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

/// Writes the configuration(s) to f; "" or why not.
std::string emit(std::FILE* f, const dtc_config_si_t& si, const std::string& sym, bool relay)
{
    dtc_config_t cfg;
    char msg[256];
    if (const int rc = dtc_config_from_si(&si, &cfg, msg, sizeof msg); rc != DTC_SI_OK) {
        return "configuration refused (" + std::to_string(rc) + "): " + msg;
    }
    im_tau_report_t tau_report;
    char tau_msg[600];
    if (im_tau_check(&si, &tau_report, tau_msg, sizeof tau_msg)) {
        std::fprintf(stderr, "dtc_config_gen: warning: %s\n", tau_msg);
    }
    const std::string post_sym = sym + "_post";
    if (dtc_config_emit_c(&cfg, sym.c_str(), f) != 0) {
        return std::string("write error: ") + std::strerror(errno != 0 ? errno : EIO);
    }
    if (relay) {
        dtc_config_si_t post_si;
        dtc_config_t post;
        if (dtc_config_post_fault_si(&si, &post_si) != DTC_SI_OK ||
            dtc_config_from_si(&post_si, &post, msg, sizeof msg) != DTC_SI_OK) {
            return std::string("post-fault configuration refused: ") + msg;
        }
        const std::string fstp_sym = post_sym + "_fstp";
        if (dtc_config_emit_c(&post, fstp_sym.c_str(), f) != 0 ||
            std::fprintf(f, "\n/* the post-fault configuration (app_set_reconfig) */\n"
                            "const struct dtc_config *const %s = &%s;\n",
                         post_sym.c_str(), fstp_sym.c_str()) < 0) {
            return std::string("write error: ") + std::strerror(errno != 0 ? errno : EIO);
        }
    } else if (std::fprintf(f, "\n/* no reconfiguration relays: a failed leg trips (app_set_reconfig) */\n"
                               "const struct dtc_config *const %s = 0;\n",
                            post_sym.c_str()) < 0) {
        return std::string("write error: ") + std::strerror(errno != 0 ? errno : EIO);
    }
    return "";
}

// The parameter table of docs/parameters.md, from the rows (firmware/dtc/dtc_param.h): one line per
// parameter of every part, the SI value of each row's range where its bases are the defaults'.
std::string emit_params_md(std::FILE* f)
{
    static const char* const fmt_name[] = {"u16", "u32", "Q15", "IQ24", "Q31", "angle"};
    static const char* const part_name[] = {"common", "PM DTC", "IM (all IM laws)", "PM ITC"};
    const dtc_param_list_t* lists[4] = {&dtc_params_common, &dtc_params_pm_dtc, &dtc_params_im, &dtc_params_pm_itc};
    std::string out =
        "<!-- Generated by build/host/bin/dtc_config_gen --params-md docs/parameters.md from the parameter rows of\n"
        "     firmware/dtc (dtc_param.h): do not edit; ctest unit.params_doc_current checks it. -->\n"
        "# Firmware parameters\n\n"
        "Every field of the firmware's configuration (`dtc_config_t`), described once next to its struct\n"
        "(`DTC_PARAMS_*` in `firmware/dtc/dtc_config_common.h`, `pm_dtc_cfg.h`, `im_cfg.h`, `pm_itc_cfg.h`).\n"
        "The id is the serial protocol's and never changes meaning. The range is of the stored raw value\n"
        "(the format's integer); the unit is what the per-unit value becomes with the board's bases\n"
        "(`firmware/dtc/dtc_base.h`). Flags: `RO` derived from other values or fixed by the board (written\n"
        "by the host converter only), `live` may be written while the drive runs; the others while it is\n"
        "disarmed. The firmware's checks refuse a value outside its range with the code given\n"
        "(`enum dtc_err`); relations between fields are checked in code.\n";
    for (int l = 0; l < 4; l++) {
        out += std::string("\n## ") + part_name[l] + "\n\n| id | name | format | unit | raw range | code | flags | meaning |\n"
               "|---:|---|---|---|---|---:|---|---|\n";
        for (uint16_t k = 0; k < lists[l]->n; k++) {
            const dtc_param_t& p = lists[l]->rows[k];
            const char* unit = dtc_param_unit(p.qty);
            char line[512];
            std::snprintf(line, sizeof line, "| %u | `%s` | %s | %s | %lld .. %lld | %d | %s | %s |\n",
                          static_cast<unsigned>(p.id), p.name, fmt_name[p.fmt],
                          unit[0] != '\0' ? unit : (p.qty == DTC_PQ_PU ? "pu" : "-"), static_cast<long long>(p.lo),
                          static_cast<long long>(p.hi), static_cast<int>(p.err),
                          (p.flags & DTC_PARAM_RO) != 0U ? "RO" : (p.flags & DTC_PARAM_LIVE) != 0U ? "live" : "",
                          p.text);
            out += line;
        }
    }
    if (std::fputs(out.c_str(), f) < 0) {
        return std::string("write error: ") + std::strerror(errno != 0 ? errno : EIO);
    }
    return "";
}

} // namespace

int main(int argc, char** argv)
{
    CLI::App app{"dtc_config_gen: writes the firmware's default configuration as a C source file"};
    app.set_version_flag("--version", std::string("dtc_config_gen ") + DTC_PROJECT_VERSION +
                                          " (configuration version " + std::to_string(DTC_CONFIG_VERSION) + ")");
    bool board = false, params_md = false;
    double relay_s = 0.0;
    std::string output, sym = "dtc_config_default";
    app.add_flag("--f2812-board", board, "dead time and control period as the F2812 board's registers produce them");
    app.add_flag("--params-md", params_md,
                 "write the table of every firmware parameter (docs/parameters.md) to OUTPUT instead");
    app.add_option("--reconfig-relay", relay_s,
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
    app.add_option("output", output, "the C file to write")->required()->type_name("OUTPUT.c");
    app.add_option("symbol", sym, "the configuration's C name (default dtc_config_default)")->type_name("SYMBOL");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    if (output.empty() || output[0] == '-') {
        std::fprintf(stderr, "dtc_config_gen: OUTPUT '%s': a file name cannot start with '-' (write ./%s)\n",
                     output.c_str(), output.c_str());
        return 2;
    }
    if (const std::string why = check_symbol(sym); !why.empty()) {
        std::fprintf(stderr, "dtc_config_gen: SYMBOL '%.80s%s': %s\n", sym.c_str(), sym.size() > 80 ? "..." : "",
                     why.c_str());
        return 2;
    }

    dtc_config_si_t si;
    dtc_config_si_defaults(&si);
    if (relay_s > 0.0) {
        si.topology = DTC_TOPO_SSTP;
        si.compensation = DTC_COMP_SSTP;
        si.i_sensors3 = 1;
        si.reconfig_relay = 1;
        si.relay_delay_s = relay_s;
    }
    if (board) {
        si.dead_time_s = static_cast<double>(F2812_DEADBAND_ACTUAL_NS) * 1e-9;
        si.ts_s = 1.0 / static_cast<double>(F2812_CONTROL_FREQ_HZ);
    }

    struct stat st {};
    const bool special = ::stat(output.c_str(), &st) == 0 && !S_ISREG(st.st_mode);
    const std::string path = special ? output : output + ".partial-" + std::to_string(static_cast<long>(::getpid()));
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (f == nullptr) {
        std::fprintf(stderr, "dtc_config_gen: %s: %s\n", path.c_str(), std::strerror(errno));
        return 1;
    }
    errno = 0;
    std::string why = params_md ? emit_params_md(f) : emit(f, si, sym, relay_s > 0.0);
    errno = 0;
    if (std::fflush(f) != 0 || std::ferror(f) != 0) {
        why = why.empty() ? std::string("write error: ") + std::strerror(errno != 0 ? errno : EIO) : why;
    }
    if (std::fclose(f) != 0 && why.empty()) {
        why = std::string("write error: ") + std::strerror(errno);
    }
    if (why.empty() && !special && std::rename(path.c_str(), output.c_str()) != 0) {
        why = std::string("cannot move the file in place: ") + std::strerror(errno);
    }
    if (!why.empty()) {
        if (!special) {
            std::remove(path.c_str());
        }
        std::fprintf(stderr, "dtc_config_gen: %s: %s%s\n", output.c_str(), why.c_str(),
                     special ? "" : " (nothing written)");
        return 1;
    }
    return 0;
}
