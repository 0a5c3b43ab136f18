// bench_sil.cpp - prints where the SIL time goes (a benchmark, not a test: nothing is asserted).
//
//   build/host/bin/sil_bench [SCENARIO.toml] [--periods N]
//
// Default scenario: tools/scenarios/open_loop_rated_current.toml (no firmware needed). Prints
//   * hal_host sample() alone (ADC + encoder + trip emulation, plant state read), ns/period;
//   * plant advance alone (one 50 us period through hal_host::Harness::advance), ns/period;
//   * the whole run loop (controller + recording + metrics), trace off and trace on,
//     as simulated seconds per wall second.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "controller_adapter.hpp"
#include "run.hpp"

using clk = std::chrono::steady_clock;

int main(int argc, char** argv)
{
    std::string path = std::string(DTC_SOURCE_DIR) + "/tools/scenarios/open_loop_rated_current.toml";
    long periods = 20000;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--periods" && i + 1 < argc) {
            periods = std::atol(argv[++i]);
        } else {
            path = a;
        }
    }
    sil::Scenario sc;
    sil::Diagnostics d;
    if (!sil::load_scenario(path, {}, &sc, &d)) {
        std::fprintf(stderr, "%s", d.text().c_str());
        return 1;
    }
    std::string err;
    auto h = hal_host::Harness::create(sil::plant_params_from(sc), sil::harness_config_from(sc), &err);
    if (!h) {
        std::fprintf(stderr, "%s\n", err.c_str());
        return 1;
    }
    h->activate();
    // The plant's state read alone, then sample() (= state read + ADC, encoder, trip emulation).
    plant_state_t st;
    double sink = 0.0;
    auto t0 = clk::now();
    for (long k = 0; k < periods; ++k) {
        plant_get_state(h->plant(), &st);
        sink += st.i_a;
    }
    const double state_ns = std::chrono::duration<double, std::nano>(clk::now() - t0).count() / static_cast<double>(periods);
    t0 = clk::now();
    for (long k = 0; k < periods; ++k) {
        h->sample();
    }
    const double sample_ns = std::chrono::duration<double, std::nano>(clk::now() - t0).count() / static_cast<double>(periods);
    t0 = clk::now();
    for (long k = 0; k < periods; ++k) {
        h->advance(); // includes one sample() per call when none preceded it
    }
    const double advance_ns = std::chrono::duration<double, std::nano>(clk::now() - t0).count() / static_cast<double>(periods);
    h.reset();

    std::printf("sil_bench: %s, %ld periods of %.0f us\n", sc.name.c_str(), periods, sc.ts_s * 1e6);
    std::printf("  plant_get_state() alone:                              %8.1f ns/period\n", state_ns);
    std::printf("  hal_host sample() (state read + ADC, encoder, trip):  %8.1f ns/period\n", sample_ns);
    std::printf("  sample() + plant advance:                             %8.1f ns/period\n", advance_ns);

    sc.duration_s = static_cast<double>(periods) * sc.ts_s;
    sc.metrics_window_s = std::min(sc.metrics_window_s, sc.duration_s);
    for (int trace = 0; trace < 2; ++trace) {
        sil::RunOptions opt;
        if (trace != 0) {
            opt.out_dir = "/tmp/sil_bench_out";
        }
        sil::RunResult r;
        if (!sil::run_scenario(sc, opt, &r, &err)) {
            std::fprintf(stderr, "run: %s\n", err.c_str());
            return 1;
        }
        std::printf("  whole run loop, trace %-3s:                           %8.1f ns/period = %6.0fx real time\n",
                    trace != 0 ? "on" : "off", 1e9 * r.info.wall_time_s / static_cast<double>(r.info.isr_count),
                    r.info.sim_time_s / r.info.wall_time_s);
    }
    return sink == 12345.678 ? 2 : 0; // keeps the state reads from being optimised away
}
