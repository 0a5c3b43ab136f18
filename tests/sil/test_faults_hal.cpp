// hal_host with the real plant under the faults of plant.h, and the runner's fault metrics: the desaturation latch reaches
// meas.desat and the trip, the relay command reaches the plant (coil at once, contacts after the
// delay, the named leg gated off), the encoder freezes, a current channel sticks at its code.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "hal_host.hpp"
#include "model_test_util.h"
#include "run.hpp"
#include "trace_csv.hpp"

using hal_host::Harness;
using hal_host::HarnessConfig;

namespace {

std::unique_ptr<Harness> make(plant_params_t p, const HarnessConfig& cfg = HarnessConfig{})
{
    std::string err;
    auto h = Harness::create(p, cfg, &err);
    EXPECT_TRUE(h) << err;
    h->activate();
    hal_init();
    return h;
}

hal_cmd_t legs(int sa, int sb, int sc, std::uint16_t relay = 0u)
{
    hal_cmd_t c{};
    c.sa = static_cast<std::uint16_t>(sa);
    c.sb = static_cast<std::uint16_t>(sb);
    c.sc = static_cast<std::uint16_t>(sc);
    c.enable = 1u;
    c.relay = relay;
    return c;
}

} // namespace

TEST(HalHostFaults, ShortedSwitchRaisesDesatAndTheTripAtTheNextSample)
{
    const plant_params_t p = mt::locked(mt::default_plant());
    auto h = make(p);
    ASSERT_EQ(plant_set_switch_fault(h->plant(), 1, 0, PLANT_SWITCH_SHORT), 0);  // leg B lower shorted
    hal_meas_t m{};
    int k_trip = -1;
    for (int k = 0; k < 6; ++k) {
        h->run_period([&] {
            hal_read(&m);
            if (m.desat != 0u && k_trip < 0) {
                k_trip = k;
            }
            // Period 0 writes B lower (the short changes nothing); period 2 writes B upper.
            const hal_cmd_t c = legs(1, k >= 2 ? 1 : 0, 0);
            hal_write(&c);
        });
    }
    // The B-upper command of period 2 is applied over period 3; the upper turns on after the dead
    // time inside it, so the sample at the start of period 4 is the first to see it.
    EXPECT_EQ(k_trip, 4);
    EXPECT_EQ(m.desat, 2u);
    EXPECT_EQ(m.trip, 1u);
    EXPECT_TRUE(h->trip_latched());
    EXPECT_EQ(h->trip_cause(), hal_host::TripCause::desat);
    EXPECT_FALSE(h->gates_enabled());
    EXPECT_NEAR(h->fault_state().desat_t_s, 3 * 50e-6 + p.dead_time_s, 1e-12);
    hal_trip_clear();  // the gate drivers' latch is reset with PDPINTA
    EXPECT_FALSE(h->trip_latched());
    EXPECT_EQ(h->fault_state().desat_mask, 0);
}

TEST(HalHostFaults, RelayCommandClosesThePlantRelayAfterItsDelayAndGatesTheLegOff)
{
    plant_params_t p;
    plant_params_default(&p);
    p.reconfig_relay = 1;
    p.relay_delay_s = 1e-3;
    auto h = make(p);
    const int n_delay = static_cast<int>(std::lround(p.relay_delay_s / 50e-6));
    for (int k = 0; k <= n_delay + 1; ++k) {
        h->run_period([&] {
            const hal_cmd_t c = legs(1, 0, 0, k >= 1 ? HAL_RELAY_C : HAL_RELAY_OPEN);
            hal_write(&c);
            if (k == 1) {
                EXPECT_EQ(h->relay_cmd(), HAL_RELAY_C);
                EXPECT_EQ(h->fault_state().relay_cmd, 3);  // the coil at once
                EXPECT_EQ(h->fault_state().relay_closed, 0);
            }
        });
        // Coil at t = 1 period; after run_period k the plant is at (k + 1) periods.
        if (k == n_delay - 1) {
            EXPECT_EQ(h->fault_state().relay_closed, 0) << "contacts before their delay";
        }
        if (k == n_delay) {
            EXPECT_EQ(h->fault_state().relay_closed, 3) << "contacts at their delay";
        }
    }
    EXPECT_EQ(h->fault_state().relay_closed, 3);
    EXPECT_EQ(h->fault_state().desat_mask, 0);  // leg C was gated off before the contacts closed
    EXPECT_EQ(h->invalid_writes(), 0u);
    hal_gates_off();  // leaves the relay as it is
    EXPECT_EQ(h->relay_cmd(), HAL_RELAY_C);
    const hal_cmd_t bad = legs(0, 0, 0, 4u);
    hal_write(&bad);
    EXPECT_EQ(h->invalid_writes(), 1u);
}

TEST(HalHostFaults, LostEncoderFreezesTheCountAndTheIndex)
{
    const plant_params_t p = mt::held_at(mt::default_plant(), 3000.0);  // 20 ms per turn: an index every 400 periods
    auto h = make(p);
    hal_meas_t m{};
    for (int k = 0; k < 100; ++k) {
        h->run_period([&] { hal_read(&m); });
    }
    const std::uint16_t frozen = m.qep_count;
    h->set_encoder_lost(true);
    int index_seen = 0;
    for (int k = 0; k < 1000; ++k) {
        h->run_period([&] {
            hal_read(&m);
            index_seen += m.qep_index_seen;
            // The count of the last sample before the loss, as the shaft turns on.
            EXPECT_EQ(m.qep_count, frozen) << "k = " << k;
        });
    }
    EXPECT_EQ(index_seen, 0);
    EXPECT_GT(h->sensed().theta_m_rad, 2.0 * 3.14159265358979);  // more than a turn since
}

TEST(HalHostFaults, StuckCurrentSensorReadsItsCodeWithoutNoiseAndTheOthersKeepTheirNoise)
{
    plant_params_t p;
    plant_params_default(&p);
    HarnessConfig cfg;
    cfg.sensors.current_noise_a_rms = 0.05;
    cfg.sensors.noise_seed = 11;
    auto a = make(p, cfg);
    std::vector<hal_meas_t> ref;
    for (int k = 0; k < 50; ++k) {
        a->run_period([&] {
            hal_meas_t m;
            hal_read(&m);
            ref.push_back(m);
        });
    }
    a.reset();
    auto b = make(p, cfg);
    b->set_current_sensor_stuck(0, 2048u);
    for (int k = 0; k < 50; ++k) {
        b->run_period([&] {
            hal_meas_t m;
            hal_read(&m);
            EXPECT_EQ(m.adc[HAL_ADC_IA], 2048u);
            EXPECT_EQ(m.adc[HAL_ADC_IB], ref[static_cast<std::size_t>(k)].adc[HAL_ADC_IB]);
            EXPECT_EQ(m.adc[HAL_ADC_IC], ref[static_cast<std::size_t>(k)].adc[HAL_ADC_IC]);
        });
    }
    // Not a constant by accident: the healthy channel A is noisy with this seed.
    int changes = 0;
    for (std::size_t k = 1; k < ref.size(); ++k) {
        changes += ref[k].adc[HAL_ADC_IA] != ref[k - 1].adc[HAL_ADC_IA] ? 1 : 0;
    }
    EXPECT_GT(changes, 10);
}

// ---- the runner's fault metrics against the trace they summarise ----------------------------
namespace {

using sil_test::read_trace;

sil::RunResult run_sstp(const std::vector<std::string>& sets, const std::string& out_dir)
{
    sil::Scenario sc;
    sil::Diagnostics d;
    EXPECT_TRUE(sil::load_scenario(std::string(DTC_SOURCE_DIR) + "/tools/scenarios/sstp_current_full.toml", sets, &sc,
                                   &d))
        << d.text();
    sil::RunOptions opt;
    opt.out_dir = out_dir;
    sil::RunResult r;
    std::string err;
    EXPECT_TRUE(sil::run_scenario(sc, opt, &r, &err)) << err;
    return r;
}

} // namespace

TEST(SilFaults, SpeedDipAndRecoveryAreTheTracesAfterTheFault)
{
    const auto dir = std::filesystem::temp_directory_path() / "dtc_sil_fault_metrics";
    std::filesystem::remove_all(dir);
    // A stuck-open upper switch at 0.4 s: the drive runs on with a speed dip (firmware without
    // reconfiguration: the dip and its recovery are what the plant and the firmware make of it).
    const sil::RunResult r = run_sstp({"duration_s=0.7", "metrics_window_s=0.1", "faults.time_s=0.4",
                                       "faults.switch_open=\"a_upper\""},
                                      dir.string());
    EXPECT_DOUBLE_EQ(r.info.injected_fault_time_s, 0.4);
    EXPECT_EQ(r.info.reconfigured, "");  // the firmware did not reconfigure
    const auto tr = read_trace(dir / "trace.csv");
    ASSERT_TRUE(tr.count("relay") && tr.count("desat"));
    const auto& t = tr.at("t_s");
    const auto& n = tr.at("speed_rpm");
    const double ref = 1500.0, band = 0.01 * ref;
    double dip = 0.0;
    std::ptrdiff_t last_out = -1, first = -1;
    for (std::size_t k = 0; k < t.size(); ++k) {
        if (t[k] < 0.4 - 1e-9) {
            continue;
        }
        if (first < 0) {
            first = static_cast<std::ptrdiff_t>(k);
        }
        // from the speed at the fault, capped at the reference
        dip = std::max(dip, std::min(n[static_cast<std::size_t>(first)], ref) - n[k]);
        if (std::fabs(n[k] - ref) > band) {
            last_out = static_cast<std::ptrdiff_t>(k);
        }
    }
    ASSERT_GE(first, 0);
    EXPECT_GT(dip, 5.0);  // the fault is visible
    EXPECT_NEAR(r.info.speed_dip_rpm, dip, 1e-9);
    const bool recovered = last_out + 1 < static_cast<std::ptrdiff_t>(t.size());
    if (!recovered) {
        EXPECT_LT(r.info.recovery_s, 0.0);
    } else if (last_out < 0) {
        EXPECT_DOUBLE_EQ(r.info.recovery_s, 0.0);
    } else {
        EXPECT_NEAR(r.info.recovery_s, t[static_cast<std::size_t>(last_out) + 1] - 0.4, 1e-9);
    }
    std::filesystem::remove_all(dir);

    // No fault: none of it.
    const sil::RunResult c = run_sstp({"duration_s=0.1", "metrics_window_s=0.05"}, "");
    EXPECT_LT(c.info.injected_fault_time_s, 0.0);
    EXPECT_LT(c.info.speed_dip_rpm, 0.0);
    EXPECT_LT(c.info.recovery_s, 0.0);
}
