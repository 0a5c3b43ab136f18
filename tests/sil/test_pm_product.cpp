// test_pm_product.cpp - the PM drive as a product: the targets this firmware meets, with a
// margin, on the SIL: start from standstill (J = 5e-4 kg m^2,
// set in the scenarios), hand-over, delay and dead-time compensation, bad configuration refused.
// Targets NOT met are not asserted here; docs/firmware-core.md lists them with figures.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "run.hpp"
#include "scenario.hpp"

using namespace sil;

namespace {

const std::string kScenarios = std::string(DTC_SOURCE_DIR) + "/tools/scenarios/";

struct Outcome {
    Metrics m;
    RunInfo info;
    Series series;
};

Outcome run(const std::string& file, const std::vector<std::string>& sets = {})
{
    Scenario sc;
    Diagnostics d;
    EXPECT_TRUE(load_scenario(kScenarios + file, sets, &sc, &d)) << d.text();
    RunOptions opt;
    RunResult r;
    std::string err;
    EXPECT_TRUE(run_scenario(sc, opt, &r, &err)) << err;
    return Outcome{r.metrics, r.info, r.series};
}

// Speed held within tol over the metrics window (instantaneous samples of the last 0.4 s).
void expect_speed_held(const Outcome& o, double ref_rpm, double tol, const std::string& what)
{
    ASSERT_EQ(o.info.fault, "none") << what;
    const auto& v = o.series.speed_rpm;
    ASSERT_GT(v.size(), 100u) << what;
    EXPECT_NEAR(o.m.speed_mean_rpm, ref_rpm, tol * ref_rpm) << what;
    const auto mm = std::minmax_element(v.begin(), v.end());
    EXPECT_GT(*mm.first, ref_rpm * (1.0 - 2.0 * tol)) << what;
    EXPECT_LT(*mm.second, ref_rpm * (1.0 + 2.0 * tol)) << what;
}

} // namespace

TEST(PmProduct, EveryCompensatedSchemeStartsFromStandstillAndHolds1500rpm)
{
    // Current model and the compensated voltage-model schemes, from standstill (the scenarios'
    // initial_speed_rpm = 0, J = 5e-4), with the generator load and with a constant 0.3 N*m:
    // no trip, mean speed within 1 %. Before the hand-over (main): every voltage-model scenario
    // here tripped on over-current. Measured: 1499.6-1499.9 rpm.
    for (const char* f : {"fstp_current_full.toml", "sstp_current_full.toml", "fstp_voltage_simple_full.toml",
                          "fstp_voltage_proposed_full.toml", "sstp_voltage_simple_full.toml"}) {
        const Outcome g = run(f);
        expect_speed_held(g, 1500.0, 0.01, std::string(f) + " generator");
        const Outcome t = run(f, {"load.type=torque", "load.torque_nm=0.3"});
        expect_speed_held(t, 1500.0, 0.01, std::string(f) + " 0.3 N*m");
    }
}

TEST(PmProduct, TableIxOrderingFromStandstillWithTheCompensations)
{
    // Hoang Table IX/X trends at 1500 rpm full load: imbalance none > simple > proposed, proposed
    // <= 8 % (measured 7.9 %), current model <= 5 % (1.4 %); estimated torque above the true one
    // without compensation (0.330 vs 0.300 N*m) and within 3 % of rated with the proposed scheme
    // (0.2996). The uncompensated scenario starts at 1500 rpm (it trips from standstill, see
    // its header).
    const Outcome none = run("fstp_voltage_none_full.toml");
    const Outcome simple = run("fstp_voltage_simple_full.toml");
    const Outcome prop = run("fstp_voltage_proposed_full.toml");
    const Outcome cur = run("fstp_current_full.toml");
    ASSERT_TRUE(none.m.imbalance_pct && simple.m.imbalance_pct && prop.m.imbalance_pct && cur.m.imbalance_pct);
    EXPECT_GT(*none.m.imbalance_pct, *simple.m.imbalance_pct);
    EXPECT_GT(*simple.m.imbalance_pct, *prop.m.imbalance_pct);
    EXPECT_LE(*prop.m.imbalance_pct, 8.5);
    EXPECT_LE(*cur.m.imbalance_pct, 5.0);
    ASSERT_TRUE(none.m.torque_est_mean_nm && prop.m.torque_est_mean_nm);
    EXPECT_GT(*none.m.torque_est_mean_nm, none.m.torque_mean_nm + 0.015);
    EXPECT_NEAR(*prop.m.torque_est_mean_nm, prop.m.torque_mean_nm, 0.03 * 0.3);
}

TEST(PmProduct, DelayAndDeadTimeCompensationsEachMeasurablyHelp)
{
    // Delay compensation on the current model: TRF 146.7 -> 75.7 %, THD 29.8 -> 16.1 % (FSTP).
    // Dead-time compensation on the proposed scheme: imbalance 17.3 -> 7.9 %.
    const Outcome off = run("fstp_current_full.toml", {"control.delay_comp=false"});
    const Outcome on = run("fstp_current_full.toml", {"control.deadtime_comp=false"});
    ASSERT_TRUE(off.m.thd_total_pct && on.m.thd_total_pct);
    EXPECT_LT(on.m.trf_pct, 0.7 * off.m.trf_pct);
    EXPECT_LT(*on.m.thd_total_pct, 0.7 * *off.m.thd_total_pct);
    const Outcome dt_off = run("fstp_voltage_proposed_full.toml", {"control.deadtime_comp=false"});
    const Outcome dt_on = run("fstp_voltage_proposed_full.toml");
    ASSERT_TRUE(dt_off.m.imbalance_pct && dt_on.m.imbalance_pct);
    EXPECT_LT(*dt_on.m.imbalance_pct, 0.5 * *dt_off.m.imbalance_pct);
}

TEST(PmProduct, NegativeHandOverSpeedIsRefusedNamingTheKey)
{
    Scenario sc;
    Diagnostics d;
    EXPECT_FALSE(load_scenario(kScenarios + "fstp_voltage_proposed_full.toml", {"control.handover_rpm=-1"}, &sc, &d));
    EXPECT_NE(d.text().find("control.handover_rpm"), std::string::npos) << d.text();
}

TEST(PmProduct, FirmwareParametersAreSetApartFromThePlantsByKeys)
{
    // firmware.* keys set the firmware's own values; not given, the firmware gets the plant's.
    // The same value given explicitly changes nothing, bit for bit.
    const Outcome base = run("fstp_voltage_proposed_full.toml");
    const Outcome same = run("fstp_voltage_proposed_full.toml", {"firmware.rs_ohm=0.466", "firmware.ls_h=3.19e-3",
                                                                 "firmware.psi_m_wb=0.0928", "firmware.v_ce_v=0.9"});
    ASSERT_TRUE(base.m.imbalance_pct && same.m.imbalance_pct);
    EXPECT_EQ(*base.m.imbalance_pct, *same.m.imbalance_pct);
    EXPECT_EQ(base.m.torque_mean_nm, same.m.torque_mean_nm);
    // Voltage model, the firmware's R_s 30 % low: the value reaches the firmware (the run differs)
    // and the drive still runs. (Measured with `dtc-sil sweep --grid firmware.rs_ohm=...`: the
    // proposed scheme trips on over-current from standstill outside about -30 % .. +5 % of R_s;
    // docs/firmware-core.md.)
    const Outcome rs_low = run("fstp_voltage_proposed_full.toml", {"firmware.rs_ohm=0.3262"});
    ASSERT_EQ(rs_low.info.fault, "none");
    ASSERT_TRUE(rs_low.m.imbalance_pct);
    EXPECT_NE(*rs_low.m.imbalance_pct, *base.m.imbalance_pct);
    // Current model (Hoang eqs. 8-9), the firmware's psi_m 10 % high: the estimated flux and hence
    // the estimated torque (eq. 10) are high against the true ones by about that much on the
    // torque-producing part.
    const Outcome cm = run("fstp_current_full.toml");
    const Outcome cm_psi = run("fstp_current_full.toml", {"firmware.psi_m_wb=0.10208"});
    ASSERT_EQ(cm_psi.info.fault, "none");
    ASSERT_TRUE(cm.m.flux_est_error_rms_pct && cm_psi.m.flux_est_error_rms_pct);
    EXPECT_GT(*cm_psi.m.flux_est_error_rms_pct, 5.0);
    EXPECT_LT(*cm.m.flux_est_error_rms_pct, 2.0);
    // A negative resistance is refused, naming the key.
    Scenario sc;
    Diagnostics d;
    EXPECT_FALSE(load_scenario(kScenarios + "fstp_voltage_proposed_full.toml", {"firmware.rs_ohm=-0.1"}, &sc, &d));
    EXPECT_NE(d.text().find("firmware.rs_ohm"), std::string::npos) << d.text();
}
