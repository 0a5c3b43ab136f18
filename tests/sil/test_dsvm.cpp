// DTC with Discrete Space Vector Modulation against basic DTC (Casadei et al. 2006 sec. 11, Figs.
// 29-30): the default IM at 100 rpm and rated torque, from standstill (the drive magnetises the
// machine at zero torque, then the dynamometer ramps the rotor to 100 rpm: load.type = "speed",
// as tools/plot/casadei_table5.py), basic DTC (Casadei Table 1) at 80 us against DSVM
// (control.scheme = "dsvm", firmware/dtc/im_dsvm.c) at 160 us, at about the same mean switching
// frequency (metric switching_freq_hz: turn-on events per device per second, the PWM form's
// pulses inside the period counted). The paper's 2450 Hz is above what basic DTC reaches on this
// rig at 80 us (zero bands: about 1.9 kHz, printed), so DTC runs with zero bands and DSVM's torque
// band is tuned by bisection until its frequency is within 3 % of DTC's (flux band 1 % of the
// reference, Casadei Fig. 30's ratio to Fig. 29's 2 %). Then: DSVM's three-phase rms current ripple
// (current_ripple_rms_a) below basic DTC's by at least 10 %, both follow T* (mean within 3 %), no
// trip. The window: three electrical periods of the 100 rpm fundamental.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "run.hpp"
#include "scenario.hpp"

using namespace sil;

namespace {

const std::string kScenario = std::string(DTC_SOURCE_DIR) + "/tools/scenarios/im_dtc_speed.toml";
constexpr double kRatedNm = 26.5; // the default IM (plant_defaults.h)

struct Cell {
    double f_hz = 0.0, ripple_a = 0.0, torque_nm = 0.0;
    std::string fault;
};

// One run at 100 rpm, rated torque, from standstill (ramp after the 0.6 s magnetisation).
Cell run(const std::vector<std::string>& extra)
{
    const double f_e = 2.0 * 100.0 / 60.0; // pole pairs 2
    const double window = 3.0 / f_e;
    std::vector<std::string> sets = {"control.mode=torque", "control.torque_ref_nm=26.5", "load.type=speed",
                                     "load.speed_rpm=100", "load.speed_ramp_start_s=0.6", "load.speed_ramp_s=0.3",
                                     "load.step_time_s=0", "metrics_window_s=" + std::to_string(window),
                                     "duration_s=" + std::to_string(0.6 + 0.3 + 0.2 + window)};
    sets.insert(sets.end(), extra.begin(), extra.end());
    Scenario sc;
    Diagnostics d;
    Cell c;
    if (!load_scenario(kScenario, sets, &sc, &d)) {
        ADD_FAILURE() << d.text();
        return c;
    }
    RunResult r;
    std::string err;
    if (!run_scenario(sc, RunOptions{}, &r, &err)) {
        ADD_FAILURE() << err;
        return c;
    }
    c.fault = r.info.fault;
    c.f_hz = r.metrics.switching_freq_hz.value_or(0.0);
    c.ripple_a = r.metrics.current_ripple_rms_a.value_or(-1.0);
    c.torque_nm = r.metrics.torque_mean_nm;
    return c;
}

std::vector<std::string> dsvm_sets(double torque_band_nm)
{
    return {"control.scheme=dsvm", "ts_s=160e-6", "control.flux_band_wb=0.0055",
            "control.torque_band_nm=" + std::to_string(torque_band_nm)};
}

} // namespace

TEST(Dsvm, Figs29And30LessCurrentRippleThanBasicDtcAtEqualSwitchingFrequency)
{
    const Cell dtc = run({"ts_s=80e-6", "control.torque_band_nm=0", "control.flux_band_wb=0"});
    ASSERT_EQ(dtc.fault, "none");
    ASSERT_GT(dtc.f_hz, 1000.0);
    // DSVM's frequency falls as its torque band widens: bisection on [0, 0.5 T_rated].
    double lo = 0.0, hi = 0.5 * kRatedNm;
    Cell dsvm = run(dsvm_sets(lo));
    ASSERT_EQ(dsvm.fault, "none");
    ASSERT_GT(dsvm.f_hz, dtc.f_hz) << "DSVM with a zero band switches less than basic DTC";
    double band = lo;
    for (int k = 0; k < 12 && std::fabs(dsvm.f_hz / dtc.f_hz - 1.0) > 0.03; ++k) {
        band = 0.5 * (lo + hi);
        dsvm = run(dsvm_sets(band));
        ASSERT_EQ(dsvm.fault, "none") << "torque band " << band;
        (dsvm.f_hz > dtc.f_hz ? lo : hi) = band;
    }
    std::printf("basic DTC 80 us, zero bands: %.0f Hz, ripple %.3f A, torque %.2f N m\n", dtc.f_hz, dtc.ripple_a,
                dtc.torque_nm);
    std::printf("DSVM 160 us, torque band %.3f N m, flux band 0.0055 Wb: %.0f Hz, ripple %.3f A, torque %.2f N m\n",
                band, dsvm.f_hz, dsvm.ripple_a, dsvm.torque_nm);
    EXPECT_NEAR(dsvm.f_hz / dtc.f_hz, 1.0, 0.03);
    EXPECT_GT(dtc.ripple_a, 0.0);
    EXPECT_LT(dsvm.ripple_a, 0.9 * dtc.ripple_a);
    EXPECT_NEAR(dsvm.torque_nm / kRatedNm, 1.0, 0.03);
    EXPECT_NEAR(dtc.torque_nm / kRatedNm, 1.0, 0.03);
}
