// cli.cpp - dtc-sil: acts on the command line cli_args.cpp parses.

#include <cmath>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <ostream>
#include <unistd.h>

#include "controller_adapter.hpp"
#include "identify.hpp"
#include "im_tau_check.h"
#include "run.hpp"
#include "sweep.hpp"

namespace sil {

namespace {
extern "C" void on_stop_signal(int sig) { g_stop_signal = sig; }
} // namespace

StopSignals::StopSignals()
{
    g_stop_signal = 0;
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
}

StopSignals::~StopSignals()
{
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
}

int dtc_sil_main(const std::vector<std::string>& args, std::ostream& out, std::ostream& err)
{
    SilArgs a;
    if (const int rc = parse_sil_args(args, &a, out, err); rc >= 0) {
        return rc;
    }
    if (a.cmd == SilArgs::Command::Sweep) {
        return sweep::sweep_main(args, out, err);
    }
    const std::string& scenario_path = a.scenario_path;
    const std::string& out_dir = a.out_dir;
    const std::vector<std::string>& sets = a.sets;
    const std::vector<std::string>& overlays = a.overlays;

    if (a.cmd == SilArgs::Command::Keys) {
        out << scenario_keys_markdown();
        return 0;
    }

    Scenario sc;
    Diagnostics diag;
    const bool ok = load_scenario(scenario_path, sets, &sc, &diag, overlays);
    err << diag.text();
    if (!ok) {
        err << "dtc-sil: " << scenario_path << ": scenario rejected, nothing run or written\n";
        return 1;
    }
    if (a.cmd == SilArgs::Command::Identify) {
        IdentifyReport rep;
        rep.max_time_s = a.ident_max_s;
        std::string e;
        if (!identify(sc, out_dir, &rep, &e)) {
            err << "dtc-sil: " << scenario_path << ": " << e << "\n";
            return 2;
        }
        out << "identify " << scenario_path << ": " << (rep.ok ? "ok" : "FAILED") << " after " << rep.duration_s
            << " s; wrote " << (std::filesystem::path(out_dir) / "identified.toml").string() << ", "
            << (std::filesystem::path(out_dir) / "identification.json").string() << "\n";
        if (!rep.warning.empty()) {
            err << "warning: " << rep.warning << "\n";
        }
        if (!rep.ok) {
            err << "dtc-sil: " << scenario_path << ": identification failed in step " << rep.failed_step << ": "
                << rep.reason << "\n";
            return 3;
        }
        return 0;
    }
    RunOptions opt;
    opt.out_dir = out_dir;
    opt.decimate = a.decimate;
    opt.write_trace = !a.no_trace;
    opt.force = a.force;
    opt.record_isr = a.record_isr;
    if (a.cmd == SilArgs::Command::Serve) {
        opt.serial_link = a.serial_link;
        opt.pace = a.pace;
        opt.serve_duration_s = a.serve_duration_s;
        opt.write_trace = !out_dir.empty();
    }
    RunResult res;
    std::string e;
    if (a.cmd == SilArgs::Command::Check) {
        // The same path as run up to the first period: plant, harness and firmware configuration.
        opt.check_only = true;
        opt.out_dir.clear();
        if (!run_scenario(sc, opt, &res, &e)) {
            err << "dtc-sil: " << scenario_path << ": " << e << "\n";
            err << "dtc-sil: " << scenario_path << ": scenario rejected\n";
            return 1;
        }
        // run's only extra refusal depends on its options: say when a traced run would meet it.
        const double rows = std::floor(sc.duration_s / sc.ts_s + 0.5);
        if (rows * kTraceBytesPerRow > opt.max_trace_bytes) {
            err << "warning: a traced run writes about " << rows * kTraceBytesPerRow / 1e9
                << " GB of trace.csv: `run` refuses it without --decimate, --no-trace or --force\n";
        }
        // Casadei eqs. 26-28: the configured improved-estimator tau against the operating range.
        const dtc_config_si_t tau_si = firmware_si_config(sc);
        im_tau_report_t tau_report;
        char tau_msg[600];
        if (im_tau_check(&tau_si, &tau_report, tau_msg, sizeof tau_msg) != 0) {
            err << "warning: control.observer_tau_s: " << tau_msg << "\n";
        }
        // The IM laws: the torque limit the current allows against the rated torque.
        char room_msg[600];
        if (dtc_im_torque_room_check(&tau_si, room_msg, sizeof room_msg) != 0) {
            err << "warning: motor.rated_torque_nm, protection.overcurrent_a, ts_s (control.carrier_hz): " << room_msg
                << "\n";
        }
        out << scenario_path << ": ok\n";
        return 0;
    }
    if (std::error_code ec; !out_dir.empty() && std::filesystem::exists(out_dir, ec) && !std::filesystem::is_directory(out_dir, ec)) {
        err << "dtc-sil: --out " << out_dir << ": exists and is not a directory; nothing run or written\n";
        return 1;
    }
    {
        opt.check_only = true; // refusals first (exit 1), before anything is created
        if (!run_scenario(sc, opt, &res, &e)) {
            err << "dtc-sil: " << scenario_path << ": " << e << "\n";
            err << "dtc-sil: " << scenario_path << ": scenario rejected, nothing run or written\n";
            return 1;
        }
        opt.check_only = false;
    }
    if (&err == &std::cerr && ::isatty(STDERR_FILENO) != 0) {
        opt.progress = &err;
    }
    StopSignals stop_signals;
    if (!run_scenario(sc, opt, &res, &e)) {
        err << "dtc-sil: " << scenario_path << ": " << e << "\n";
        if (!res.output_touched) {
            err << "dtc-sil: nothing written to " << out_dir
                << (a.record_isr.empty() ? std::string() : " or " + a.record_isr) << "\n";
        }
        return g_stop_signal != 0 ? 128 + static_cast<int>(g_stop_signal) : 2;
    }
    if (!a.quiet && out_dir.empty()) {
        out << "dtc-sil serve: " << res.info.sim_time_s << " s simulated, fault " << res.info.fault << "\n";
    } else if (!a.quiet) {
        out << summary_text(sc, res.metrics, res.info);
        out << "  wrote " << (std::filesystem::path(out_dir) / "metrics.json").string();
        if (opt.write_trace) {
            out << ", " << (std::filesystem::path(out_dir) / "trace.csv").string();
        }
        out << "\n";
    }
    if (run_failed_physically(res.info)) {
        err << "dtc-sil: " << scenario_path << ": " << res.info.fault << ": " << res.info.fault_detail << "\n";
        return 3;
    }
    return 0;
}

} // namespace sil
