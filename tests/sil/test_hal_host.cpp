// hal_host against a scripted plant: clock, one-period actuation delay, ADC/encoder emulation,
// noise statistics and seed reproducibility, hardware trip latching.
#include <gtest/gtest.h>

#include <cmath>

#include "hal_host.hpp"
#include "scripted_plant.hpp"
#include "sil_constants.hpp"

using hal_host::Harness;
using hal_host::HarnessConfig;
using sil::kPi;

namespace {

class HalHost : public ::testing::Test {
protected:
    void SetUp() override { scripted::reset(); }
    void TearDown() override { scripted::reset(); }
    std::unique_ptr<Harness> make(const HarnessConfig& cfg = HarnessConfig{}, plant_inverter_t inv = PLANT_INVERTER_SSTP)
    {
        plant_params_t p;
        plant_params_default(&p);
        p.inverter = inv;
        std::string err;
        auto h = Harness::create(p, cfg, &err);
        EXPECT_TRUE(h) << err;
        h->activate();
        return h;
    }
};

// Expected code for an ADC input voltage: round(4095 v / 3), ties to even (f2812-facts 3.2).
std::uint16_t code(double v) { return static_cast<std::uint16_t>(std::nearbyint(4095.0 * v / 3.0)); }
} // namespace

TEST_F(HalHost, CommandWrittenInPeriodKActsInPeriodKPlus1)
{
    auto h = make();
    hal_init();
    for (int k = 0; k < 6; ++k) {
        h->run_period([&] {
            hal_meas_t m;
            hal_read(&m);
            EXPECT_EQ(m.tick, static_cast<std::uint32_t>(k));
            const hal_cmd_t c{static_cast<std::uint16_t>(k % 2), static_cast<std::uint16_t>((k / 2) % 2), 1u, 1u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 0u};
            hal_write(&c);
        });
    }
    const auto& adv = scripted::log().advances;
    ASSERT_EQ(adv.size(), 6u);
    EXPECT_EQ(adv[0].enable, 0); // nothing written before period 0: gates off
    for (int k = 1; k < 6; ++k) {
        EXPECT_NEAR(adv[static_cast<std::size_t>(k)].t_start_s, k * 50e-6, 1e-15);
        EXPECT_DOUBLE_EQ(adv[static_cast<std::size_t>(k)].dt_s, 50e-6);
        EXPECT_EQ(adv[static_cast<std::size_t>(k)].sa, (k - 1) % 2) << "period " << k;
        EXPECT_EQ(adv[static_cast<std::size_t>(k)].sb, ((k - 1) / 2) % 2) << "period " << k;
        EXPECT_EQ(adv[static_cast<std::size_t>(k)].sc, 1);
        EXPECT_EQ(adv[static_cast<std::size_t>(k)].enable, 1);
    }
    EXPECT_EQ(h->period_count(), 6u);
    EXPECT_EQ(h->hal_writes(), 6u);
    EXPECT_EQ(h->invalid_writes(), 0u);
}

TEST_F(HalHost, ShadowRegisterKeepsTheLastCommandAndGatesOffActsNow)
{
    auto h = make();
    const hal_cmd_t on{1u, 0u, 1u, 1u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 0u};
    h->run_period([&] { hal_write(&on); });
    h->run_period([] {});                 // no write: the shadow register keeps the command
    h->run_period([] { hal_gates_off(); }); // fault path: off in this very period
    h->run_period([] {});
    const auto& adv = scripted::log().advances;
    EXPECT_EQ(adv[1].enable, 1);
    EXPECT_EQ(adv[1].sa, 1);
    EXPECT_EQ(adv[2].enable, 0);
    EXPECT_EQ(adv[3].enable, 0);
    const hal_cmd_t bad{2u, 0u, 0u, 1u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 0u};
    h->run_period([&] { hal_write(&bad); });
    EXPECT_EQ(h->invalid_writes(), 1u);
}

TEST_F(HalHost, AdcScalesCurrentsAndVoltagesThroughTheSensingChain)
{
    HarnessConfig cfg;
    cfg.sensors.current_range_a = 10.0; // 0.15 V/A around 1.5 V
    cfg.sensors.voltage_range_v = 100.0; // 0.03 V/V
    cfg.sensors.current_gain_error = {0.02, 0.0, 0.0};
    cfg.sensors.current_offset_a = {0.0, 0.1, 0.0};
    cfg.sensors.vdc_offset_v = -1.0;
    scripted::set_script([](double, plant_state_t* s) {
        s->i_a = 2.5;
        s->i_b = -1.0;
        s->i_c = -1.5;
        s->vdc_v = 70.0;
        s->vc_lo_v = 34.0;
    });
    auto h = make(cfg, PLANT_INVERTER_FSTP);
    hal_meas_t m{};
    h->run_period([&] { hal_read(&m); });
    EXPECT_EQ(m.adc[HAL_ADC_IA], code(1.5 + 0.15 * 2.5 * 1.02));
    EXPECT_EQ(m.adc[HAL_ADC_IB], code(1.5 + 0.15 * (-1.0 + 0.1)));
    EXPECT_EQ(m.adc[HAL_ADC_IC], code(1.5 + 0.15 * -1.5));
    EXPECT_EQ(m.adc[HAL_ADC_VDC], code(0.03 * 69.0));
    EXPECT_EQ(m.adc[HAL_ADC_VMID], code(0.03 * 34.0));
    EXPECT_EQ(m.adc[HAL_ADC_IC], 1740u); // 1.5 V - 0.15 V/A * 1.5 A = 1.275 V; 4095 * 1.275 / 3 = 1740.4
}

TEST_F(HalHost, AdcQuantisesAndClampsAtTheRails)
{
    EXPECT_EQ(hal_host::adc_code(0.0), 0u);
    EXPECT_EQ(hal_host::adc_code(1.5), 2048u); // 2047.5: ties round to even
    EXPECT_EQ(hal_host::adc_code(3.0), 4095u);
    EXPECT_EQ(hal_host::adc_code(3.7), 4095u);
    EXPECT_EQ(hal_host::adc_code(-0.2), 0u);
    EXPECT_EQ(hal_host::adc_code(std::nan("")), 0u);
    EXPECT_EQ(hal_host::adc_code(3.0 / 4095.0 * 1000.4), 1000u);
    EXPECT_EQ(hal_host::adc_code(3.0 / 4095.0 * 1000.6), 1001u);
    // A 20 A current on a +-10 A sensor saturates the converter instead of wrapping.
    const auto ch = hal_host::current_channel(10.0, 0.0, 0.0, 0.0);
    EXPECT_EQ(ch.code(20.0, 0.0), 4095u);
    EXPECT_EQ(ch.code(-20.0, 0.0), 0u);
    // One LSB is 3 V / 4095 / 0.15 V/A = 4.88 mA.
    EXPECT_EQ(ch.code(0.00489 * 10, 0.0) - ch.code(0.0, 0.0), 10);
}

TEST_F(HalHost, VmidReadsZeroWithoutTheFstpSensor)
{
    scripted::set_script([](double, plant_state_t* s) { s->vc_lo_v = 35.0; s->vdc_v = 70.0; });
    auto h = make(HarnessConfig{}, PLANT_INVERTER_SSTP);
    hal_meas_t m{};
    h->run_period([&] { hal_read(&m); });
    EXPECT_EQ(m.adc[HAL_ADC_VMID], 0u);
    EXPECT_EQ(m.adc[HAL_ADC_VDC], code(2.1));
}

TEST_F(HalHost, NoiseHasTheConfiguredRmsAndIsReproducibleForASeed)
{
    // 0.05 A rms on a 10 A sensor = 10.2 LSB rms; 20000 samples: the sample rms is within 2 %
    // (standard error of an rms estimate = 1/sqrt(2N) = 0.5 %), the mean within 0.5 LSB.
    HarnessConfig cfg;
    cfg.sensors.current_noise_a_rms = 0.05;
    cfg.sensors.noise_seed = 1234;
    scripted::set_script([](double, plant_state_t* s) { s->i_a = 1.0; s->vdc_v = 70.0; });
    auto run = [&](std::uint64_t seed) {
        cfg.sensors.noise_seed = seed;
        auto h = make(cfg);
        std::vector<double> a;
        for (int k = 0; k < 20000; ++k) {
            h->run_period([&] {
                hal_meas_t m;
                hal_read(&m);
                a.push_back((hal_host::adc_code_to_volts(m.adc[HAL_ADC_IA]) - 1.5) / 0.15);
            });
        }
        return a;
    };
    const auto a = run(1234);
    double mean = 0.0, var = 0.0;
    for (double x : a) {
        mean += x;
    }
    mean /= static_cast<double>(a.size());
    for (double x : a) {
        var += (x - mean) * (x - mean);
    }
    const double rms = std::sqrt(var / static_cast<double>(a.size()));
    const double lsb_a = 3.0 / 4095.0 / 0.15;
    EXPECT_NEAR(mean, 1.0, 0.5 * lsb_a);
    // Quantisation adds LSB^2/12 of variance.
    EXPECT_NEAR(rms, std::sqrt(0.05 * 0.05 + lsb_a * lsb_a / 12.0), 0.02 * 0.05);
    EXPECT_EQ(run(1234), a);
    EXPECT_NE(run(1235), a);
}

TEST_F(HalHost, EncoderCountsUpForPositiveSpeedWithOneIndexPerTurn)
{
    // 1500 rpm = 25 rev/s: 0.00125 turn per 50 us period = 10 counts of 8000.
    const double w = 2.0 * kPi * 25.0;
    scripted::set_script([w](double t, plant_state_t* s) { s->theta_m_rad = w * t; });
    HarnessConfig cfg;
    cfg.sensors.encoder_offset_rad = 0.0;
    auto h = make(cfg);
    int index = 0;
    std::uint16_t prev = 0;
    for (int k = 0; k < 4000; ++k) { // 0.2 s = 5 turns
        h->run_period([&] {
            hal_meas_t m;
            hal_read(&m);
            EXPECT_LT(m.qep_count, 8000u);
            if (k > 0) {
                const int d = (static_cast<int>(m.qep_count) - static_cast<int>(prev) + 8000) % 8000;
                EXPECT_NEAR(d, 10, 1) << "period " << k;
            }
            prev = m.qep_count;
            index += m.qep_index_seen;
        });
    }
    EXPECT_EQ(index, 4); // the last sample is at 4.99875 turns: 4 index pulses after t = 0
    const hal_host::Encoder enc(2000, 0.0);
    EXPECT_EQ(enc.counts_per_turn(), 8000u);
    EXPECT_EQ(enc.count(2.0 * kPi * 0.3), 2400u);
    EXPECT_EQ(enc.count(-2.0 * kPi * 0.25), 6000u);
    EXPECT_EQ(enc.count(2.0 * kPi * 7.30001), 2400u);
    const hal_host::Encoder off(2000, kPi / 2.0); // index at theta = -90 deg mechanical
    EXPECT_EQ(off.count(0.0), 2000u);
    EXPECT_EQ(off.count(-kPi / 2.0), 0u);
}

TEST_F(HalHost, IndexFlagIsClearedByTheRead)
{
    scripted::set_script([](double t, plant_state_t* s) { s->theta_m_rad = t < 75e-6 ? -0.01 : 0.01; });
    auto h = make();
    std::vector<int> seen;
    for (int k = 0; k < 4; ++k) {
        h->run_period([&] {
            hal_meas_t m;
            hal_read(&m);
            seen.push_back(m.qep_index_seen);
            hal_read(&m);
            EXPECT_EQ(m.qep_index_seen, 0u);
        });
    }
    EXPECT_EQ(seen, (std::vector<int>{0, 0, 1, 0}));
}

TEST_F(HalHost, HardwareTripLatchesGatesOffUntilClearedAfterTheFault)
{
    HarnessConfig cfg;
    cfg.sensors.trip_current_a = 8.0;
    // Over-current between t = 0.5 ms and 1.0 ms (periods 10..19).
    scripted::set_script([](double t, plant_state_t* s) { s->i_b = (t > 0.49e-3 && t < 0.99e-3) ? -9.0 : 1.0; });
    auto h = make(cfg);
    const hal_cmd_t on{0u, 1u, 0u, 1u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 0u};
    std::vector<int> trip_flag;
    for (int k = 0; k < 30; ++k) {
        h->run_period([&] {
            hal_meas_t m;
            hal_read(&m);
            trip_flag.push_back(m.trip);
            if (k == 15 || k == 25) {
                hal_trip_clear(); // at 15 the comparator still sees the fault: no effect
            }
            hal_write(&on); // the firmware keeps asking for the gates: the latch wins
        });
    }
    const auto& adv = scripted::log().advances;
    for (int k = 1; k < 10; ++k) {
        EXPECT_EQ(adv[static_cast<std::size_t>(k)].enable, 1) << k;
        EXPECT_EQ(trip_flag[static_cast<std::size_t>(k)], 0) << k;
    }
    for (int k = 10; k < 25; ++k) { // tripped in the period that saw the sample, latched past 20
        EXPECT_EQ(adv[static_cast<std::size_t>(k)].enable, 0) << k;
    }
    EXPECT_EQ(trip_flag[10], 1);
    EXPECT_EQ(trip_flag[25], 1);
    EXPECT_EQ(trip_flag[26], 0);
    EXPECT_EQ(adv[25].enable, 1); // cleared in the ISR of period 25: outputs back at once (FCOMPOE)
    EXPECT_FALSE(h->trip_latched());
}

TEST_F(HalHost, OneActiveHarnessAndCleanDestruction)
{
    {
        auto h = make();
        EXPECT_EQ(Harness::active(), h.get());
    }
    EXPECT_EQ(Harness::active(), nullptr);
    EXPECT_EQ(scripted::log().destroyed, 1);
    hal_meas_t m;
    EXPECT_DEATH(hal_read(&m), "no active Harness");
}

TEST_F(HalHost, InvalidPlantOrHarnessConfigurationIsRefused)
{
    plant_params_t p;
    plant_params_default(&p);
    std::string err;
    scripted::fail_next_create("rs_ohm must be > 0");
    EXPECT_FALSE(Harness::create(p, HarnessConfig{}, &err));
    EXPECT_EQ(err, "plant: rs_ohm must be > 0");
    HarnessConfig bad;
    bad.sensors.encoder_lines = 0;
    EXPECT_FALSE(Harness::create(p, bad, &err));
    EXPECT_NE(err.find("encoder"), std::string::npos);
    bad = HarnessConfig{};
    bad.ts_s = 0.0;
    EXPECT_FALSE(Harness::create(p, bad, &err));
}

// PWM form with asymmetric pulses (period-match reload in force, hal.h): an all-off command
// written in period k loads at the period match of k, so the period is run as two halves, the
// second with the gates off. A centred command followed by all-off keeps the one-period delay.
TEST_F(HalHost, AsymmetricPulseThenAllOffTurnsOffAtThePeriodMatch)
{
    auto h = make();
    hal_init();
    hal_cmd_t asym{};
    asym.enable = 1u;
    asym.form = HAL_CMD_PWM;
    asym.cmpr_up[0] = 500u;
    asym.cmpr_dn[0] = 1200u;
    hal_cmd_t centred = asym;
    centred.cmpr_dn[0] = 500u;
    hal_cmd_t off{};
    const hal_cmd_t seq[4] = {asym, off, centred, off};
    for (const hal_cmd_t& c : seq) {
        h->run_period([&] { hal_write(&c); });
    }
    const auto& adv = scripted::log().advances;
    // period 0: gates off (nothing written before); period 1: asym, whole period, then cut at
    // the match (two halves); period 2: off; period 3: centred, whole period.
    ASSERT_EQ(adv.size(), 5u);
    EXPECT_DOUBLE_EQ(adv[1].dt_s, 25e-6);
    EXPECT_EQ(adv[1].enable, 1);
    EXPECT_DOUBLE_EQ(adv[2].dt_s, 25e-6);
    EXPECT_EQ(adv[2].enable, 0);
    EXPECT_DOUBLE_EQ(adv[3].dt_s, 50e-6);
    EXPECT_EQ(adv[3].enable, 0);
    EXPECT_DOUBLE_EQ(adv[4].dt_s, 50e-6);
    EXPECT_EQ(adv[4].enable, 1);
    EXPECT_EQ(h->invalid_writes(), 0u);
}
