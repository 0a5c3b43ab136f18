// fuzz_sil_cli.cpp - libFuzzer harness of dtc-sil's own command line: parse_sil_args (run, check,
// identify, serve, keys; tools/sil/src/cli.cpp) and, for the sweep commands, parse_sweep_args
// (sweep, sweep-merge, sweep-exec; tools/sil/src/sweep.cpp). docs/fuzzing.md.
//
// Input: the arguments after the program's name, separated by '\n' (at most 24).
// Invariants (each a crash): no undefined behaviour, memory error or escaping exception; the status
// is -1 (accepted), 0 (help or version asked, text on stdout) or 1 (bad usage, with a message); an
// accepted line names a command, and every value it carries is one the command can act on:
//   run, identify: --out not empty (an empty DIR would write into the working directory);
//   run, serve: --decimate in [1, 10^6];
//   identify: --max-time finite in [0.01, 1000] s;
//   serve: --pace finite in [0, 1000], --duration-s finite in [0, 10^6] s, --serial not empty;
//   sweep: --out not empty, --jobs in [1, 4096], --timeout-s finite in [0.001, 1e7] s,
//          --chunk 0 (not given) or in [1, 10^5];
//   sweep-merge: --out not empty, at least one shard; sweep-exec: --jobs in [1, 4096].
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "fuzz_args.hpp"
#include "run.hpp"
#include "sweep.hpp"

namespace {

bool finite_in(double x, double lo, double hi) { return std::isfinite(x) && x >= lo && x <= hi; }

void require(bool cond)
{
    if (!cond) {
        std::abort();
    }
}

/// The status's own invariant: help on out, an error on err.
void check_status(int rc, bool help, const std::ostringstream& out, const std::ostringstream& err)
{
    require(rc == -1 || (rc == 0 && help && !out.str().empty()) || (rc == 1 && !err.str().empty()));
}

void check_sweep(const std::vector<std::string>& args, bool help)
{
    using C = sil::sweep::SweepArgs::Command;
    sil::sweep::SweepArgs a;
    std::ostringstream out, err;
    const int rc = sil::sweep::parse_sweep_args(args, &a, out, err);
    check_status(rc, help, out, err);
    if (rc != -1) {
        return;
    }
    require(a.cmd != C::None);
    if (a.cmd == C::Sweep) {
        require(!a.out_dir.empty() && a.jobs >= 1 && a.jobs <= 4096 && finite_in(a.timeout_s, 0.001, 1e7) &&
                a.chunk <= 100000);
    } else if (a.cmd == C::Merge) {
        require(!a.out_dir.empty() && !a.merge_dirs.empty());
    } else {
        require(a.exec_jobs >= 1 && a.exec_jobs <= 4096);
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t n)
{
    using C = sil::SilArgs::Command;
    const std::vector<std::string> args = fuzz_args(data, n, "dtc-sil", 24);
    bool help = false;
    for (const std::string& s : args) {
        help = help || fuzz_arg_is_help(s);
    }
    sil::SilArgs a;
    std::ostringstream out, err;
    const int rc = sil::parse_sil_args(args, &a, out, err);
    check_status(rc, help, out, err);
    if (rc != -1) {
        return 0;
    }
    require(a.cmd != C::None);
    switch (a.cmd) {
    case C::Sweep:
        check_sweep(args, help);
        break;
    case C::Run:
    case C::Identify:
        require(!a.out_dir.empty());
        require(a.decimate >= 1 && a.decimate <= 1000000);
        require(finite_in(a.ident_max_s, 0.01, 1000.0));
        break;
    case C::Serve:
        require(a.decimate >= 1 && a.decimate <= 1000000);
        require(finite_in(a.pace, 0.0, 1000.0) && finite_in(a.serve_duration_s, 0.0, 1.0e6));
        require(!a.serial_link.empty());
        break;
    default:
        break;
    }
    return 0;
}
