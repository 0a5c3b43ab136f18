// bench_sil.cpp - prints where the SIL time goes (a benchmark, not a test: nothing is asserted).
//
//   build/host/bin/sil_bench [SCENARIO.toml] [--periods N] [--repeat R] [--no-trace] [--set key=value ...]
//
// Default scenario: tools/scenarios/open_loop_rated_current.toml (no firmware needed). Prints, in
// ns per 50 us control period (best of --repeat runs of each part, default 3: the machine may be
// shared, and the minimum is the least disturbed figure):
//   * plant_get_state() alone (the full true state) and plant_get_sensed() alone (what the
//     sensors see, the per-period read of hal_host);
//   * hal_host sample() alone (sensed read + ADC with noise, encoder, trip emulation);
//   * sample() + plant advance = the plant and HAL emulation side of one period, gates off (no
//     switching) and, for closed-loop scenarios, with the commands of a full run replayed;
//   * the ISR alone (controller step on measurements recorded from a full run and replayed
//     through Harness::replay_sample(), no plant): the firmware side of one period;
//   * the whole run loop (sample, controller, recording for the metrics, advance), trace off and
//     on, for --periods N periods (default: the scenario's own duration_s), as ns/period and as
//     simulated seconds per wall second.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "controller_adapter.hpp"
#include "run.hpp"

using clk = std::chrono::steady_clock;

namespace {

double ns_per(clk::time_point t0, long n)
{
    return std::chrono::duration<double, std::nano>(clk::now() - t0).count() / static_cast<double>(n);
}

std::unique_ptr<hal_host::Harness> harness(const sil::Scenario& sc)
{
    std::string err;
    auto h = hal_host::Harness::create(sil::plant_params_from(sc), sil::harness_config_from(sc), &err);
    if (!h) {
        std::fprintf(stderr, "%s\n", err.c_str());
        std::exit(1);
    }
    h->activate();
    return h;
}

} // namespace

int main(int argc, char** argv)
{
    std::string path = std::string(DTC_SOURCE_DIR) + "/tools/scenarios/open_loop_rated_current.toml";
    long periods = 20000;   // for the component figures
    long loop_periods = 0;  // whole loop: 0 = the scenario's duration
    int repeat = 3;
    bool trace_on = true;
    std::vector<std::string> overrides; // --set key=value, as dtc-sil run
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--periods" && i + 1 < argc) {
            periods = std::atol(argv[++i]);
            loop_periods = periods;
        } else if (a == "--repeat" && i + 1 < argc) {
            repeat = std::max(1, std::atoi(argv[++i]));
        } else if (a == "--set" && i + 1 < argc) {
            overrides.emplace_back(argv[++i]);
        } else if (a == "--no-trace") {
            trace_on = false;
        } else {
            path = a;
        }
    }
    if (periods <= 0) {
        std::fprintf(stderr, "--periods must be > 0\n");
        return 1;
    }
    sil::Scenario sc;
    sil::Diagnostics d;
    if (!sil::load_scenario(path, overrides, &sc, &d)) {
        std::fprintf(stderr, "%s", d.text().c_str());
        return 1;
    }
    double state_ns = 1e300, sensed_ns = 1e300, sample_ns = 1e300, advance_ns = 1e300;
    double sink = 0.0;
    for (int r = 0; r < repeat; ++r) {
        auto h = harness(sc);
        plant_state_t st;
        auto t0 = clk::now();
        for (long k = 0; k < periods; ++k) {
            plant_get_state(h->plant(), &st);
            sink += st.i_a;
        }
        state_ns = std::min(state_ns, ns_per(t0, periods));
        plant_sensed_t se;
        t0 = clk::now();
        for (long k = 0; k < periods; ++k) {
            plant_get_sensed(h->plant(), &se);
            sink += se.i_a;
        }
        sensed_ns = std::min(sensed_ns, ns_per(t0, periods));
        t0 = clk::now();
        for (long k = 0; k < periods; ++k) {
            h->sample();
        }
        sample_ns = std::min(sample_ns, ns_per(t0, periods));
        t0 = clk::now();
        for (long k = 0; k < periods; ++k) {
            h->sample();
            h->advance();
        }
        advance_ns = std::min(advance_ns, ns_per(t0, periods));
    }
    std::printf("sil_bench: %s, %ld periods of %.0f us, best of %d\n", sc.name.c_str(), periods, sc.ts_s * 1e6,
                repeat);
    std::printf("  plant_get_state() alone (full state):                 %8.1f ns/period\n", state_ns);
    std::printf("  plant_get_sensed() alone (sensor subset):             %8.1f ns/period\n", sensed_ns);
    std::printf("  hal_host sample() (sensed read + ADC, encoder, trip): %8.1f ns/period\n", sample_ns);
    std::printf("  plant + HAL: sample() + plant advance, gates off:     %8.1f ns/period\n", advance_ns);

    // The ISR alone: record the measurements of a full run, then replay them to a fresh
    // controller on a harness whose plant is never read or advanced.
    std::string err;
    double isr_ns = -1.0;
    if (sc.control.mode != sil::ControlMode::OpenLoop) {
        std::vector<hal_meas_t> rec(static_cast<std::size_t>(periods));
        std::vector<hal_cmd_t> cmds(static_cast<std::size_t>(periods));
        {
            auto h = harness(sc);
            auto ctrl = sil::make_controller(sc, &err);
            if (!ctrl || !ctrl->init(*h).empty()) {
                std::fprintf(stderr, "controller: %s\n", err.c_str());
                return 1;
            }
            for (long k = 0; k < periods; ++k) {
                h->sample();
                rec[static_cast<std::size_t>(k)] = h->meas();
                ctrl->step(*h);
                h->advance();
                cmds[static_cast<std::size_t>(k)] = h->applied_cmd(); // written in period k
            }
        }
        // Plant + HAL on the closed loop's own switching sequence (the gates-off figure above has
        // no switching events): sample(), the recorded command through hal_write(), advance().
        double replay_ns = 1e300;
        for (int r = 0; r < repeat; ++r) {
            auto h = harness(sc);
            const auto t0 = clk::now();
            for (long k = 0; k < periods; ++k) {
                h->sample();
                h->hal_write(&cmds[static_cast<std::size_t>(k)]);
                h->advance();
            }
            replay_ns = std::min(replay_ns, ns_per(t0, periods));
        }
        isr_ns = 1e300;
        for (int r = 0; r < repeat; ++r) {
            auto h = harness(sc);
            auto ctrl = sil::make_controller(sc, &err);
            if (!ctrl || !ctrl->init(*h).empty()) {
                return 1;
            }
            const auto t0 = clk::now();
            for (long k = 0; k < periods; ++k) {
                h->replay_sample(rec[static_cast<std::size_t>(k)]);
                ctrl->step(*h);
            }
            isr_ns = std::min(isr_ns, ns_per(t0, periods));
            sink += static_cast<double>(h->hal_writes());
        }
        std::printf("  plant + HAL, replayed closed-loop commands:           %8.1f ns/period\n", replay_ns);
        std::printf("  controller: ISR alone on replayed measurements:       %8.1f ns/period\n", isr_ns);
        std::printf("  (plant + HAL) / controller:                           %8.2f\n", replay_ns / isr_ns);
    }

    if (loop_periods > 0) {
        sc.duration_s = static_cast<double>(loop_periods) * sc.ts_s;
        sc.metrics_window_s = std::min(sc.metrics_window_s, sc.duration_s);
    }
    for (int trace = 0; trace < (trace_on ? 2 : 1); ++trace) {
        sil::RunOptions opt;
        if (trace != 0) {
            opt.out_dir = "/tmp/sil_bench_out";
        }
        double best = 1e300;
        sil::RunResult r;
        for (int k = 0; k < repeat; ++k) {
            if (!sil::run_scenario(sc, opt, &r, &err)) {
                std::fprintf(stderr, "run: %s\n", err.c_str());
                return 1;
            }
            best = std::min(best, r.info.wall_time_s);
        }
        const double ns = 1e9 * best / static_cast<double>(r.info.isr_count);
        std::printf("  whole run loop (%.2f s simulated), trace %-3s:         %8.1f ns/period = %6.0fx real time\n",
                    r.info.sim_time_s, trace != 0 ? "on" : "off", ns, r.info.sim_time_s / best);
    }
    return sink == 12345.678 ? 2 : 0; // keeps the reads from being optimised away
}
