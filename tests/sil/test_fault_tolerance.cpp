// test_fault_tolerance.cpp - fault tolerance on the SIL: a failed leg of the six-switch drive is found
// from its current signature and the drive goes on as the four-switch inverter with that phase on
// the capacitor mid-point (Hoang sec. I, ref. [9]); faults that cannot be ridden through trip to
// every gate off with their reason. Every run starts from standstill on the shipped scenarios
// (J = 5e-4 kg m^2, finite split link, generator load: full load at 1500 rpm) with the fault at
// t = 1 s, and is judged from its trace: when the relay command came (detection), the largest
// phase current after the fault, the gates, the speed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "run.hpp"
#include "scenario.hpp"
#include "trace_csv.hpp"

using namespace sil;
namespace fs = std::filesystem;

namespace {

const std::string kScenarios = std::string(DTC_SOURCE_DIR) + "/tools/scenarios/";
constexpr double kFaultT = 1.0;

struct Trace {
    std::vector<double> t, ia, ib, ic, speed, en, relay;
};

struct Outcome {
    RunInfo info;
    Trace tr;
    double trip_a = 0.0;
};

Trace to_trace(std::map<std::string, std::vector<double>>& c)
{
    for (const char* k : {"t_s", "i_a_a", "i_b_a", "i_c_a", "speed_rpm", "en", "relay"}) {
        EXPECT_EQ(c.count(k), 1u) << "trace column " << k;
    }
    return Trace{c["t_s"], c["i_a_a"], c["i_b_a"], c["i_c_a"], c["speed_rpm"], c["en"], c["relay"]};
}

// A scenario run as given (no fault time imposed): its scenario, result and trace columns.
struct Columns {
    Scenario sc;
    RunInfo info;
    Metrics metrics;
    std::map<std::string, std::vector<double>> c;
};

Columns run_columns(const std::string& file, const std::vector<std::string>& sets, const std::string& tag)
{
    Columns out;
    Diagnostics d;
    EXPECT_TRUE(load_scenario(kScenarios + file, sets, &out.sc, &d)) << d.text();
    const fs::path dir = fs::temp_directory_path() / ("dtc_fault_tolerance_" + tag);
    fs::remove_all(dir);
    RunOptions opt;
    opt.out_dir = dir.string();
    RunResult r;
    std::string err;
    EXPECT_TRUE(run_scenario(out.sc, opt, &r, &err)) << err;
    out.info = r.info;
    out.metrics = r.metrics;
    out.c = sil_test::read_trace(dir / "trace.csv");
    fs::remove_all(dir);
    return out;
}

Outcome run(const std::string& file, const std::vector<std::string>& sets, const std::string& tag)
{
    std::vector<std::string> all = {"duration_s=1.6", "faults.time_s=" + std::to_string(kFaultT)};
    all.insert(all.end(), sets.begin(), sets.end());
    Columns c = run_columns(file, all, tag);
    return Outcome{c.info, to_trace(c.c), c.sc.protection.overcurrent_a};
}

// First sample at or after t.
std::size_t at(const Trace& tr, double t)
{
    return static_cast<std::size_t>(std::lower_bound(tr.t.begin(), tr.t.end(), t - 1e-12) - tr.t.begin());
}

double peak_current(const Trace& tr, std::size_t from, std::size_t to)
{
    double m = 0.0;
    for (std::size_t k = from; k < to && k < tr.t.size(); ++k) {
        m = std::max({m, std::fabs(tr.ia[k]), std::fabs(tr.ib[k]), std::fabs(tr.ic[k])});
    }
    return m;
}

struct RideThrough {
    double detect_s = -1.0, dip_rpm = 0.0, late_dev_rpm = 0.0, peak_a = 0.0;
};

// A leg opened at kFaultT: the relay command names the phase, the drive runs on without a fault.
RideThrough expect_reconfigured(const Outcome& o, char phase, const std::string& what)
{
    RideThrough r;
    EXPECT_EQ(o.info.fault, "none") << what << ": " << o.info.fault_detail;
    EXPECT_EQ(o.info.reconfigured, std::string(1, phase)) << what;
    const std::size_t k0 = at(o.tr, kFaultT);
    for (std::size_t k = k0; k < o.tr.t.size(); ++k) {
        if (o.tr.relay[k] != 0.0) {
            r.detect_s = o.tr.t[k] - kFaultT;
            EXPECT_EQ(o.tr.relay[k], static_cast<double>(phase - 'a' + 1)) << what;
            break;
        }
    }
    for (std::size_t k = k0; k < o.tr.t.size(); ++k) {
        r.dip_rpm = std::max(r.dip_rpm, 1500.0 - o.tr.speed[k]);
    }
    for (std::size_t k = at(o.tr, kFaultT + 0.4); k < o.tr.t.size(); ++k) {
        r.late_dev_rpm = std::max(r.late_dev_rpm, std::fabs(o.tr.speed[k] - 1500.0));
    }
    r.peak_a = peak_current(o.tr, k0, o.tr.t.size());
    std::printf("MEASURE %s: detected %.1f ms, speed dip %.1f rpm (%.1f %%), recovery %.3f s, |i| peak %.2f A "
                "(trip %.1f A), last 0.2 s within %.1f rpm\n",
                what.c_str(), 1e3 * r.detect_s, r.dip_rpm, r.dip_rpm / 15.0, o.info.recovery_s, r.peak_a, o.trip_a,
                r.late_dev_rpm);
    EXPECT_GT(r.detect_s, 0.0) << what;
    EXPECT_LE(r.detect_s, 0.020) << what;          // required: detected within 20 ms
    EXPECT_LT(r.peak_a, 0.9 * o.trip_a) << what;    // current below the trip level
    EXPECT_LT(r.late_dev_rpm, 0.01 * 1500.0) << what; // back on speed: within 1 % after 0.4 s
    return r;
}

// Gates off from the first sample after the trip and for good.
void expect_tripped(const Outcome& o, const std::string& fault, double within_s, const std::string& what)
{
    EXPECT_EQ(o.info.fault, fault) << what << ": " << o.info.fault_detail;
    const std::size_t k0 = at(o.tr, kFaultT);
    std::size_t off = o.tr.t.size();
    for (std::size_t k = k0; k < o.tr.t.size(); ++k) {
        if (o.tr.en[k] == 0.0) {
            off = k;
            break;
        }
    }
    ASSERT_LT(off, o.tr.t.size()) << what << ": the gates never went off";
    for (std::size_t k = off; k < o.tr.t.size(); ++k) {
        ASSERT_EQ(o.tr.en[k], 0.0) << what << ": gates on again at t = " << o.tr.t[k];
    }
    const double dt = o.tr.t[off] - kFaultT;
    std::printf("MEASURE %s: %s, gates off %.2f ms after the fault, |i| peak before %.2f A (trip %.1f A)\n",
                what.c_str(), fault.c_str(), 1e3 * dt, peak_current(o.tr, k0, off), o.trip_a);
    EXPECT_LE(dt, within_s) << what;
}

const char* const kLegs[3] = {"a", "b", "c"};

} // namespace

// Ride-through: SSTP at 1500 rpm, full load, leg A (then B, then C) opens at t = 1 s;
// current model and voltage model ([29] compensation; the FSTP goes on with Hoang Table V). With a TRIAC
// (gate-triggered: 0.1 ms here) the dip stays within 5 % of the speed; with the default 15 ms
// relay the drive makes no useful torque from the failure until the relay closes (6.6-19 ms to
// detect plus 15 ms), so the dip is the load's deceleration over that time, 0.3 N*m / 5e-4 kg m^2
// = 600 rad/s^2: up to 8 % here, asserted below 10 %.
TEST(FaultTolerance, OpenLegIsFoundAndTheDriveGoesOnAsAnFstp)
{
    for (const char* scn : {"sstp_current_full.toml", "sstp_voltage_simple_full.toml"}) {
        for (int x = 0; x < 3; ++x) {
            for (const bool triac : {true, false}) {
                const std::string what = std::string(scn) + " leg " + kLegs[x] + (triac ? " triac" : " relay 15 ms");
                std::vector<std::string> sets = {"inverter.reconfig_relay=true",
                                                 std::string("faults.leg_open=\"") + kLegs[x] + "\""};
                if (triac) {
                    sets.push_back("inverter.relay_delay_s=1e-4");
                }
                const Outcome o = run(scn, sets, std::string("leg_") + kLegs[x]);
                const RideThrough r = expect_reconfigured(o, kLegs[x][0], what);
                EXPECT_LT(r.dip_rpm, (triac ? 0.05 : 0.10) * 1500.0) << what;
            }
        }
    }
}

// One device stuck open: its phase carries no current for the half-waves that device should
// carry, which the same check finds (the zero band, or the current's one direction while the
// other phases alternate), and the drive reconfigures. Found later than an open leg (39 and 10
// ms here; not asserted within the required 20 ms, which is for the open leg): the drive runs on
// with the half-waves it still has. Asserted: found, ridden through, within 0.5 s.
TEST(FaultTolerance, AnOpenDeviceIsFoundAsAnOpenPhase)
{
    for (const char* sw : {"a_upper", "c_lower"}) {
        const Outcome o = run("sstp_current_full.toml",
                              {"inverter.reconfig_relay=true", std::string("faults.switch_open=\"") + sw + "\""},
                              std::string("sw_") + sw);
        EXPECT_EQ(o.info.fault, "none") << sw << ": " << o.info.fault_detail;
        EXPECT_EQ(o.info.reconfigured, std::string(1, sw[0])) << sw;
        std::size_t k = at(o.tr, kFaultT);
        while (k < o.tr.t.size() && o.tr.relay[k] == 0.0) {
            ++k;
        }
        ASSERT_LT(k, o.tr.t.size()) << sw;
        const double dip = 1500.0 - *std::min_element(o.tr.speed.begin() + static_cast<long>(at(o.tr, kFaultT)),
                                                      o.tr.speed.end());
        std::printf("MEASURE switch open %s: detected %.1f ms, speed dip %.1f rpm, recovery %.3f s, |i| peak %.2f A\n",
                    sw, 1e3 * (o.tr.t[k] - kFaultT), dip, o.info.recovery_s,
                    peak_current(o.tr, at(o.tr, kFaultT), o.tr.t.size()));
        EXPECT_LE(o.tr.t[k] - kFaultT, 0.5) << sw;
        EXPECT_LT(peak_current(o.tr, at(o.tr, kFaultT), o.tr.t.size()), 0.9 * o.trip_a) << sw;
        EXPECT_LT(dip, 0.10 * 1500.0) << sw;
    }
}

// One device stuck open on the voltage model ([29] compensation, three sensors, the relay): the
// law's flux integrates the voltage the open device did not apply, and the DTC then keeps that
// phase's current small in the one direction it can still flow (-0.2 .. -0.4 A for A upper)
// instead of at zero, so the zero-band signature never lasts 60 deg. The phase's current has one
// direction only, which a synchronous machine's phase current never keeps for more than a turn
// while the other two alternate (app_fault.h APP_LEG_SIGN_ANGLE_IQ): found, reconfigured to the
// FSTP on the right phase, and back on the reference. Without that signature the speed fell to
// 146-330 rpm and the drive tripped "stall".
TEST(FaultTolerance, AnOpenDeviceOnTheVoltageModelIsReconfigured)
{
    for (const char* sw : {"a_upper", "b_upper", "c_lower"}) {
        const Outcome o = run("sstp_voltage_simple_full.toml",
                              {"inverter.reconfig_relay=true", "sensors.current_sensors=3",
                               std::string("faults.switch_open=\"") + sw + "\""},
                              std::string("vm_sw_") + sw);
        EXPECT_EQ(o.info.fault, "none") << sw << ": " << o.info.fault_detail;
        EXPECT_EQ(o.info.reconfigured, std::string(1, sw[0])) << sw;
        std::size_t k = at(o.tr, kFaultT);
        while (k < o.tr.t.size() && o.tr.relay[k] == 0.0) {
            ++k;
        }
        ASSERT_LT(k, o.tr.t.size()) << sw << ": never reconfigured";
        const std::size_t k0 = at(o.tr, kFaultT);
        const double n_min = *std::min_element(o.tr.speed.begin() + static_cast<long>(k0), o.tr.speed.end());
        double late = 0.0;
        for (std::size_t j = at(o.tr, kFaultT + 0.4); j < o.tr.t.size(); ++j) {
            late = std::max(late, std::fabs(o.tr.speed[j] - 1500.0));
        }
        const double peak = peak_current(o.tr, k0, o.tr.t.size());
        std::printf("MEASURE voltage model, switch open %s: detected %.1f ms, lowest speed %.0f rpm, recovery %.3f s, "
                    "|i| peak %.2f A, last 0.2 s within %.1f rpm\n",
                    sw, 1e3 * (o.tr.t[k] - kFaultT), n_min, o.info.recovery_s, peak, late);
        EXPECT_LE(o.tr.t[k] - kFaultT, 0.2) << sw;
        EXPECT_LT(peak, o.trip_a) << sw; // measured 5.4-5.7 A before the FSTP takes over: below the trip
        EXPECT_GT(n_min, 0.5 * 1500.0) << sw << ": the drive kept running";
        // back on speed after 0.4 s: within 3 %, not the open leg's 1 %. The split link's lower
        // capacitor comes out of the faulty period 5-9 V below V_dc / 2 and then wanders between 25
        // and 45 V for seconds (c_lower, seeds 1-3, 3.5 s runs), and the FSTP runs on with a speed
        // ripple of that size: 30.7-38.4 rpm at most over 1.4-3.5 s with the drops compensated at
        // the sign of the period's mean current, 33.4-36.0 rpm with them averaged over the period
        // (vcomp_leg_drop_lin); within this test's 0.2 s it is 1-31 rpm (docs/reliability.md)
        EXPECT_LT(late, 0.03 * 1500.0) << sw << ": back on speed within 3 % after 0.4 s";
    }
}

// Without the relay, an open leg trips (fault "leg"), it does not run on two legs.
TEST(FaultTolerance, WithoutTheRelayAnOpenLegTrips)
{
    // three sensors: their sum tells an open phase from a failed sensor
    const Outcome o = run("sstp_current_full.toml", {"faults.leg_open=\"b\"", "sensors.current_sensors=3"}, "norelay");
    expect_tripped(o, "leg", 0.020, "leg b open, no relay");
    EXPECT_EQ(o.info.reconfigured, "") << "no relay";
    // two sensors: phase B reads zero while the law drives current into it, which is what a sensor
    // stuck at zero does too; the plausibility check (app_plaus.h) trips on it at once and says so
    const Outcome o2 = run("sstp_current_full.toml", {"faults.leg_open=\"b\""}, "norelay2");
    expect_tripped(o2, "current_sensor", 0.002, "leg b open, no relay, two sensors");
    EXPECT_NE(o2.info.fault_detail.find("phase B reads zero"), std::string::npos) << o2.info.fault_detail;
}

// A shorted device: the shoot-through when its complement is gated on is caught by the gate
// driver's desaturation detection, which turns every gate off in hardware; the firmware names it
// (fault "desat", the leg) in the ISR that sees it and keeps every gate off: no reconfiguration
// (the phase stays tied to a rail), with or without the relay.
TEST(FaultTolerance, AShortedSwitchTripsWithinOneIsr)
{
    for (const char* sw : {"a_upper", "b_lower"}) {
        const Outcome o = run("sstp_current_full.toml",
                              {"inverter.reconfig_relay=true", std::string("faults.switch_short=\"") + sw + "\""},
                              std::string("short_") + sw);
        // the complement turns on within a few periods of the fault; the gates are off from the
        // period that follows the latch (the trace shows each period's start)
        expect_tripped(o, "desat", 0.005, std::string("switch short ") + sw);
        {
            // the firmware latched it in the ISR that sampled the desaturation: at most one period
            // after the gates went off in hardware (the trace's first period with en = 0)
            const std::size_t pos = o.info.fault_detail.find("latched at ISR ");
            ASSERT_NE(pos, std::string::npos) << o.info.fault_detail;
            const long isr = std::stol(o.info.fault_detail.substr(pos + 15));
            std::size_t off = at(o.tr, kFaultT);
            while (off < o.tr.t.size() && o.tr.en[off] != 0.0) {
                ++off;
            }
            const long off_isr = std::lround(o.tr.t[off] / 50e-6);
            EXPECT_GE(isr, off_isr - 1) << sw;
            EXPECT_LE(isr, off_isr + 1) << sw;
        }
        EXPECT_NE(o.info.fault_detail.find(std::string("leg ") + static_cast<char>(sw[0] - 'a' + 'A')),
                  std::string::npos)
            << o.info.fault_detail;
    }
}

// Encoder signal lost at 1500 rpm on the current model: the count stands still where that is
// impossible; the drive trips (fault "encoder") after 32 periods, 1.6 ms. A trip, not a hand-over
// to the voltage model: the PM law measures its speed with the encoder alone, so the speed loop
// would run blind.
TEST(FaultTolerance, LostEncoderTrips)
{
    for (const char* scn : {"sstp_current_full.toml", "sstp_voltage_simple_full.toml"}) {
        const Outcome o = run(scn, {"faults.encoder_lost=true"}, "enc");
        expect_tripped(o, "encoder", 0.002, std::string(scn) + " encoder lost");
    }
}

// A current sensor stuck (at mid-scale, or at a code that reads a current) at 1500 rpm full load,
// on every channel the firmware reads, with two or three sensors, with and without the hardware
// comparator: the drive trips "current_sensor" within 2 ms and the true current stays below 1.5x
// the trip level (the over-current trip reads the stuck value and cannot be relied on). With two
// sensors only the law's prediction (app_plaus.h) can see it; the fault comes 0.35 ms after the
// start of a plausibility window, the worst phase for a windowed check.
TEST(FaultTolerance, AStuckCurrentSensorTripsWithTwoOrThreeSensors)
{
    const double t_fault = kFaultT + 0.00035;
    for (const char* scn : {"sstp_current_full.toml", "sstp_voltage_simple_full.toml", "fstp_voltage_proposed_full.toml"}) {
        const bool fstp = std::string(scn).rfind("fstp", 0) == 0;
        for (int n : {2, 3}) {
            for (int x = 0; x < 3; ++x) {
                if (n == 2 && x == (fstp ? 0 : 2)) {
                    continue; // the derived phase: no sensor there (its fault is refused with a warning)
                }
                for (const char* hw : {"protection.hw_trip_current_a=0", "protection.hw_trip_current_a=8"}) {
                    for (const char* code : {"faults.current_sensor_code=2048", "faults.current_sensor_code=1800"}) {
                        const std::string what = std::string(scn) + " " + std::to_string(n) + " sensors, " + kLegs[x] +
                                                 " stuck, " + hw + ", " + code;
                        const Outcome o = run(scn,
                                              {"sensors.current_sensors=" + std::to_string(n),
                                               std::string("faults.current_sensor_stuck=\"") + kLegs[x] + "\"", hw, code,
                                               "faults.time_s=" + std::to_string(t_fault)},
                                              "stuck");
                        expect_tripped(o, "current_sensor", 0.002, what); // from kFaultT: conservative
                        EXPECT_LT(peak_current(o.tr, at(o.tr, t_fault), o.tr.t.size()), 1.5 * o.trip_a) << what;
                    }
                }
            }
        }
    }
}

TEST(FaultTolerance, ASpeedDipIsMeasuredFromTheSpeedTheDriveHadAtTheFault)
{
    // A DC sag to 85 % while the PM drive is still accelerating (0.1 s after the start, far below
    // 1500 rpm; 85 % still leaves the FSTP the voltage for 1500 rpm): the dip is what the speed
    // lost after the fault, not the distance to the reference it had not yet reached (measured
    // against the reference it read 616 rpm: the speed was 884 rpm at the fault). With the sag
    // the acceleration only slows, so nothing is lost beyond a few rpm.
    const Outcome o = run("fstp_current_full.toml", {"faults.dc_sag=0.85", "faults.time_s=0.1"}, "early_sag");
    ASSERT_EQ(o.info.fault, "none");
    const std::size_t k = at(o.tr, 0.1);
    ASSERT_LT(k, o.tr.speed.size());
    const double n_fault = o.tr.speed[k];
    EXPECT_LT(n_fault, 1000.0); // the start is under way, not finished
    ASSERT_GE(o.info.speed_dip_rpm, 0.0);
    EXPECT_LT(o.info.speed_dip_rpm, 10.0) << "speed at the fault " << n_fault;
}

// The induction machine's laws with two current sensors (A and B, C derived): a sensor stuck at
// code 2200 at 1.2 s (1000 rpm, the step to rated load of im_dtc_speed.toml) trips
// "current_sensor" naming the stuck phase, within the 2 ms of the target, with the true
// current below 1.5x the trip level: the law's current prediction (im_dtc.h im_dtc_i_pred) is
// what the plausibility (app_plaus.h) compares the readings with. Two fault instants, 1.5 and 3
// periods of the 160 us laws apart, put the sensor's jump at different places in the window.
// Without the prediction the same runs tripped "encoder_speed" after 8.2 ms (phase B: 14.6 ms).
class ImStuckSensor : public ::testing::TestWithParam<const char*> {};

TEST_P(ImStuckSensor, TripsCurrentSensorOnTheStuckPhaseWithin2ms)
{
    const std::string law = GetParam();
    for (const char* ph : {"a", "b"}) {
        for (const char* tf : {"1.2", "1.20024", "1.20048"}) {
            const std::string what = law + ", phase " + ph + " stuck at " + tf + " s";
            Columns c = run_columns("im_dtc_speed.toml",
                                    {"duration_s=1.25", "metrics_window_s=0.02", "sensors.current_sensors=2",
                                     "control.scheme=\"" + law + "\"", std::string("faults.current_sensor_stuck=\"") + ph + "\"",
                                     "faults.current_sensor_code=2200", std::string("faults.time_s=") + tf},
                                    "im_stuck_" + law);
            const Trace tr = to_trace(c.c);
            const double t_fault = std::stod(tf);
            const char phase = static_cast<char>(ph[0] - 'a' + 'A');
            EXPECT_EQ(c.info.fault, "current_sensor") << what << ": " << c.info.fault_detail;
            EXPECT_NE(c.info.fault_detail.find(std::string("phase ") + phase + "'s current sensor"), std::string::npos)
                << what << ": " << c.info.fault_detail;
            const std::size_t k0 = at(tr, t_fault);
            std::size_t off = k0;
            while (off < tr.t.size() && tr.en[off] != 0.0) {
                ++off;
            }
            ASSERT_LT(off, tr.t.size()) << what << ": the gates never went off";
            const double dt = tr.t[off] - t_fault, peak = peak_current(tr, k0, off);
            std::printf("MEASURE %s: gates off %.2f ms after the fault, |i| peak %.1f A (trip %.1f A)\n", what.c_str(),
                        1e3 * dt, peak, c.sc.protection.overcurrent_a);
            EXPECT_LE(dt, 0.002) << what;
            EXPECT_LT(peak, 1.5 * c.sc.protection.overcurrent_a) << what;
        }
    }
}

// The same laws, no fault, two and three sensors: the whole scenario (magnetisation, the
// acceleration to 1000 rpm, the step to rated load) runs without a trip.
TEST_P(ImStuckSensor, NoFalseTripWithoutAFault)
{
    const std::string law = GetParam();
    for (const char* n : {"2", "3"}) {
        const std::string what = law + ", " + n + " sensors";
        Columns c = run_columns("im_dtc_speed.toml", {std::string("sensors.current_sensors=") + n, "control.scheme=\"" + law + "\""},
                                "im_clean_" + law);
        EXPECT_EQ(c.info.fault, "none") << what << ": " << c.info.fault_detail;
    }
}

INSTANTIATE_TEST_SUITE_P(ImLaws, ImStuckSensor, ::testing::Values("dtc", "dsc", "sfvc", "dfoc", "dsvm"));

// The PM indirect torque control (itc.h itc_i_pred) on both inverters with two sensors and no
// hardware comparator: a sensor stuck at 2200 counts during full load at 1500 rpm trips
// current_sensor naming its phase within 2 ms, the current below 1.5x the trip; the same runs
// without the fault do not trip.
TEST(FaultTolerance, ItcStuckSensorTripsCurrentSensorWithin2ms)
{
    for (const auto& [scn, phases] : {std::pair<const char*, std::vector<const char*>>{"sstp_itc_full.toml", {"a", "b"}},
                                      std::pair<const char*, std::vector<const char*>>{"fstp_itc_full.toml", {"b", "c"}}}) {
        for (const char* ph : phases) {
            const std::string what = std::string(scn) + ", phase " + ph + " stuck";
            Columns c = run_columns(scn,
                                    {"duration_s=1.25", "metrics_window_s=0.02", "protection.hw_trip_current_a=0",
                                     std::string("faults.current_sensor_stuck=\"") + ph + "\"",
                                     "faults.current_sensor_code=2200", "faults.time_s=1.2"},
                                    "itc_stuck");
            const Trace tr = to_trace(c.c);
            const char phase = static_cast<char>(ph[0] - 'a' + 'A');
            EXPECT_EQ(c.info.fault, "current_sensor") << what << ": " << c.info.fault_detail;
            EXPECT_NE(c.info.fault_detail.find(std::string("phase ") + phase + "'s current sensor"), std::string::npos)
                << what << ": " << c.info.fault_detail;
            const std::size_t k0 = at(tr, 1.2);
            std::size_t off = k0;
            while (off < tr.t.size() && tr.en[off] != 0.0) {
                ++off;
            }
            ASSERT_LT(off, tr.t.size()) << what << ": the gates never went off";
            const double dt = tr.t[off] - 1.2, peak = peak_current(tr, k0, off);
            std::printf("MEASURE %s: gates off %.2f ms after the fault, |i| peak %.2f A (trip %.1f A)\n", what.c_str(),
                        1e3 * dt, peak, c.sc.protection.overcurrent_a);
            EXPECT_LE(dt, 0.002) << what;
            EXPECT_LT(peak, 1.5 * c.sc.protection.overcurrent_a) << what;
        }
        Columns clean = run_columns(scn, {"protection.hw_trip_current_a=0"}, "itc_clean");
        EXPECT_EQ(clean.info.fault, "none") << scn << ": " << clean.info.fault_detail;
    }
}

// Overspeed: the six-switch drive in torque mode with no load but its inertia accelerates past
// its rated speed (the FSTP's half link holds it near 2260 rpm); the firmware trips "overspeed"
// at the derived level, 10 % above the rated speed (tools/config dtc_overspeed_default_rpm), and
// the speed never reaches 115 % of rated. Without the trip it ran to 4135 rpm.
TEST(FaultTolerance, OverspeedTripsBelow115PercentOfRated)
{
    Columns o = run_columns("sstp_current_full.toml",
                            {"control.mode=\"torque\"", "load.type=\"inertia\"", "duration_s=1.6"}, "overspeed");
    const Scenario& sc = o.sc;
    auto& c = o.c;
    EXPECT_EQ(o.info.fault, "overspeed") << o.info.fault_detail;
    double n_max = 0.0;
    for (double n : c["speed_rpm"]) {
        n_max = std::max(n_max, std::fabs(n));
    }
    std::printf("MEASURE overspeed: largest speed %.0f rpm, rated %.0f rpm (%.1f %%)\n", n_max,
                sc.motor.rated_speed_rpm, 100.0 * n_max / sc.motor.rated_speed_rpm);
    EXPECT_GT(n_max, sc.motor.rated_speed_rpm) << "the drive must have been above rated to trip";
    EXPECT_LT(n_max, 1.15 * sc.motor.rated_speed_rpm);
}

// protection.overspeed_rpm reaches the firmware: set to 3150 rpm (above the 3000 rpm speed limit,
// below the derived 3300 rpm), the same run trips on the way up within one speed period's
// acceleration beyond it. (A level at or below the speed limit is refused naming the key.)
TEST(FaultTolerance, OverspeedKeySetsTheTripLevel)
{
    Columns o = run_columns("sstp_current_full.toml",
                            {"control.mode=\"torque\"", "load.type=\"inertia\"", "duration_s=1.6",
                             "protection.overspeed_rpm=3150"},
                            "overspeed_key");
    EXPECT_EQ(o.info.fault, "overspeed") << o.info.fault_detail;
    double n_max = 0.0;
    for (double n : o.c["speed_rpm"]) {
        n_max = std::max(n_max, std::fabs(n));
    }
    std::printf("MEASURE overspeed at protection.overspeed_rpm = 3150: largest speed %.0f rpm\n", n_max);
    EXPECT_GT(n_max, 3150.0);
    EXPECT_LT(n_max, 3200.0);
}

// The induction machine's encoder lost during the magnetisation (im_dtc_speed: the count stands
// still at zero from 0.2 s, while the rotor is still at rest): when the magnetisation ends the
// speed loop sees 0 rpm and commands the torque limit. The lost-signal check cannot see a count
// that stands still at a measured speed of zero; the plausibility against the speed of the
// estimated rotor flux less its slip (Casadei eqs. 16, 22) does: the rotor accelerates at about
// p T_lim / J while the encoder reads nothing. Trips "encoder_speed" within 20 ms of the first
// torque (the sensorless speed's 5 ms filter, the derived tolerance of about 320 rpm at 58,000
// rpm/s, four speed periods), below the 1000 rpm reference; without it the drive ran to 1421 rpm
// at 54 A and tripped "stall" 0.1 s later.
TEST(FaultTolerance, ImEncoderLostDuringMagnetisationTripsOnTheFluxSpeed)
{
    Columns o = run_columns("im_dtc_speed.toml", {"duration_s=0.8", "faults.time_s=0.2", "faults.encoder_lost=true"},
                            "im_encoder");
    const Scenario& sc = o.sc;
    auto& c = o.c;
    EXPECT_EQ(o.info.fault, "encoder_speed") << o.info.fault_detail;
    ASSERT_GT(o.info.fault_time_s, 0.0) << "a firmware trip carries its time";
    const std::vector<double>& t = c["t_s"];
    const std::vector<double>& te = c["torque_nm"];
    const std::vector<double>& n = c["speed_rpm"];
    double t_torque = -1.0, n_max = 0.0;
    for (std::size_t k = 0; k < t.size(); ++k) {
        if (t_torque < 0.0 && t[k] > 0.2 && std::fabs(te[k]) > 0.1 * sc.motor.rated_torque_nm) {
            t_torque = t[k];
        }
        n_max = std::max(n_max, std::fabs(n[k]));
    }
    ASSERT_GT(t_torque, 0.2) << "the speed loop never applied torque";
    const double t_trip = o.info.fault_time_s;
    std::printf("MEASURE im encoder lost: first torque %.4f s, trip %.4f s (%.1f ms later), largest speed %.0f rpm\n",
                t_torque, t_trip, 1e3 * (t_trip - t_torque), n_max);
    EXPECT_GT(t_trip, t_torque) << "a trip before any torque is a false trip: the rotor was at rest";
    EXPECT_LT(t_trip - t_torque, 0.020);
    EXPECT_LT(n_max, sc.control.speed_ref_rpm);
}

// The most torque an induction machine gives at the electrical rotor speed w_r (rad/s) with a
// sinusoidal stator voltage of at most v_max: the T model in steady state in the rotor-flux frame
// (Casadei eqs. A7-A9, 16, 19 in SI): i_d = phi_r / M, T = (3/2) p phi_r^2 w_s / R_r,
// i_q = T L_r / ((3/2) p M phi_r), phi_s = (L_s i_d, sigma L_s i_q), v = R_s i + j (w_r + w_s) phi_s,
// searched over phi_r and the slip w_s. The FSTP's largest circle is v_max = V_dc / (2 sqrt3).
double im_torque_at_voltage(const MotorCfg& m, double w_r, double v_max)
{
    const double ls = m.lls_h + m.lm_h, lr = m.llr_h + m.lm_h, sig = 1.0 - m.lm_h * m.lm_h / (ls * lr);
    const double p = static_cast<double>(m.pole_pairs);
    double best = 0.0;
    for (int a = 1; a <= 300; ++a) {
        const double psir = 1.5 * a / 300.0;
        for (int b = 1; b <= 600; ++b) {
            const double ws = 0.5 * b;
            const double t = 1.5 * p * psir * psir * ws / m.rr_ohm;
            const double id = psir / m.lm_h, iq = t * lr / (1.5 * p * m.lm_h * psir), we = w_r + ws;
            const double vd = m.rs_ohm * id - we * sig * ls * iq, vq = m.rs_ohm * iq + we * ls * id;
            if (vd * vd + vq * vq > v_max * v_max) {
                break;
            }
            best = std::max(best, t);
        }
    }
    return best;
}

// The induction machine's switching-table DTC on the six-switch inverter with the relays (Hoang
// sec. I and its refs. [12], [13]: the four-switch DTC of an induction machine is the
// fault-tolerant mode; firmware/dtc/im_dtc_reconfig.c, im_dtc_fstp.c): leg A, B or C opens at
// 1.5 s, at full load (im_dtc_speed.toml and im_second_machine.toml step to the rated torque at
// 1.2 s, fan load) at 1000 rpm, on a finite split link (2 x 4.7 mF, 22 kOhm balancing resistors,
// the mid-point measured) with the 15 ms relay. The drive finds the open phase, runs the
// single-phase machine on the two healthy legs until the relay has closed, then Hoang Table II
// with the flux the FSTP's voltage holds at 1000 rpm. Asserted on both machines: the failed phase
// named, found within 20 ms, the current below the trip level, no trip for 0.5 s after the fault,
// the speed dip. What a sinusoidal voltage within the FSTP's largest circle allows at 1000 rpm
// (im_torque_at_voltage) is 25.8 N*m for the 4 kW IM and 19.0 N*m for the second machine.
// On the 4 kW IM, whose rated 26.5 N*m is within reach, also: no trip to the end (1.5 s after
// the fault), the mean speed over the last 0.2 s within 1 % of 1000 rpm and the plant's mean
// torque there within 5 % of the load's. The second machine's rated 23.5 N*m is beyond its FSTP
// at 1000 rpm: it settles near 992 rpm at 23.1 N*m, short of the reference (printed;
// docs/reliability.md); asserted: the rated torque beyond that bound, and the drive's torque
// 0.2-0.3 s after the fault above it (the DTC goes into the corners of Hoang Table I's rhombus).
// The target for the dip is 10 %, asserted on both machines; measured (docs/reliability.md,
// "The induction machine after a leg failure") 8.6 / 9.4 / 7.1 % on the 4 kW IM and 4.5 / 6.7 /
// 5.0 % on the second machine. Leg B of the 4 kW IM has the least margin: the choice between the
// quadrant's two torque-raising vectors near the beta axis after the relay's closing decides it
// (im_dtc_fstp.c im_dtc_fstp_advance; 10.9 % with the measured mid-point's alpha lengths there).
TEST(FaultTolerance, ImOpenLegAtFullLoadIsFoundAndTheDriveGoesOnAsAnFstp)
{
    constexpr double kImFault = 1.5, kRef = 1000.0;
    for (const char* scn : {"im_dtc_speed.toml", "im_second_machine.toml"}) {
        const bool within = std::string(scn) == "im_dtc_speed.toml";
        for (int x = 0; x < 3; ++x) {
            const std::string what = std::string(scn) + " leg " + kLegs[x];
            Columns c = run_columns(scn,
                                    {"duration_s=3.0", "faults.time_s=1.5", "inverter.reconfig_relay=true",
                                     std::string("faults.leg_open=\"") + kLegs[x] + "\"", "control.fault_detect=true",
                                     "inverter.finite_dc_link=true", "inverter.c_dc_f=4.7e-3", "inverter.r_bal_ohm=22000",
                                     "inverter.esr_ohm=0.025", "sensors.vmid_fitted=true"},
                                    std::string("im_leg_") + kLegs[x]);
            ASSERT_EQ(c.c.count("torque_nm"), 1u);
            ASSERT_EQ(c.c.count("tload_nm"), 1u);
            const Trace tr = to_trace(c.c);
            const std::vector<double>& te = c.c["torque_nm"];
            const std::vector<double>& tl = c.c["tload_nm"];
            const double t_fstp = im_torque_at_voltage(c.sc.motor, kRef * M_PI / 30.0 * static_cast<double>(c.sc.motor.pole_pairs),
                                                       c.sc.inverter.vdc_v / (2.0 * std::sqrt(3.0)));
            EXPECT_EQ(c.info.reconfigured, std::string(1, kLegs[x][0])) << what;
            const std::size_t k0 = at(tr, kImFault), k1 = at(tr, kImFault + 0.5);
            double detect = -1.0, low = kRef, te_m = 0.0, tl_m = 0.0, n_m = 0.0, te_f = 0.0;
            std::size_t off = tr.t.size();
            for (std::size_t k = k0; k < tr.t.size(); ++k) {
                if (detect < 0.0 && tr.relay[k] != 0.0) {
                    detect = tr.t[k] - kImFault;
                }
                if (off == tr.t.size() && tr.en[k] == 0.0) {
                    off = k;
                }
                if (off == tr.t.size()) {
                    low = std::min(low, tr.speed[k]);
                }
            }
            // the torque after the fault: the mean over 0.1 s from 0.2 s after it
            for (std::size_t k = at(tr, kImFault + 0.2); k < at(tr, kImFault + 0.3); ++k) {
                te_f += te[k] / static_cast<double>(at(tr, kImFault + 0.3) - at(tr, kImFault + 0.2));
            }
            const std::size_t kw = at(tr, std::min(tr.t.back(), tr.t[std::min(off, tr.t.size() - 1)]) - 0.2);
            for (std::size_t k = kw; k < std::min(off, tr.t.size()); ++k) {
                te_m += te[k];
                tl_m += tl[k];
                n_m += tr.speed[k];
            }
            const double nw = static_cast<double>(std::min(off, tr.t.size()) - kw);
            te_m /= nw;
            tl_m /= nw;
            n_m /= nw;
            const double peak = peak_current(tr, k0, off);
            const double dip = (kRef - low) / kRef;
            std::printf("MEASURE %s: detected %.1f ms, speed dip %.1f rpm (%.1f %%), |i| peak %.1f A (trip %.1f A), "
                        "torque 0.2-0.3 s after the fault %.2f N*m (sinusoidal FSTP limit %.2f N*m), fault %s at %.3f s, "
                        "the 0.2 s before the end or the trip: mean %.1f rpm, torque %.2f N*m against the load's %.2f N*m\n",
                        what.c_str(), 1e3 * detect, kRef - low, 100.0 * dip, peak, c.sc.protection.overcurrent_a, te_f,
                        t_fstp, c.info.fault.c_str(), off < tr.t.size() ? tr.t[off] : tr.t.back(), n_m, te_m, tl_m);
            EXPECT_GT(detect, 0.0) << what;
            EXPECT_LE(detect, 0.020) << what;
            EXPECT_LT(peak, c.sc.protection.overcurrent_a) << what;
            EXPECT_GE(off, k1) << what << ": tripped within 0.5 s of the fault: " << c.info.fault_detail;
            EXPECT_LT(dip, 0.10) << what;
            if (within) {
                EXPECT_EQ(c.info.fault, "none") << what << ": " << c.info.fault_detail;
                EXPECT_NEAR(n_m, kRef, 0.01 * kRef) << what;
                EXPECT_NEAR(te_m, tl_m, 0.05 * tl_m) << what;
            } else {
                EXPECT_LT(t_fstp, c.sc.motor.rated_torque_nm) << what << ": the rated torque is within the FSTP's reach";
                EXPECT_GT(te_f, t_fstp) << what;
            }
        }
    }
}

// The induction machine on the four-switch inverter from standstill (tools/scenarios/
// im_fstp_speed.toml: the 4 kW IM, a finite split link of 2 x 4.7 mF with 22 kOhm balancing
// resistors, the mid-point measured; 600 rpm, half then full rated load). Phase A's current is
// the capacitors' only DC path (docs/plant.md "DC link"): the start-up builds the flux along beta
// (im_dtc_fstp.c), so the mid-point stays within 5 V of V_dc/2 over the first 0.2 s of the
// magnetisation (a flux built at DC with an alpha part took the lower capacitor from 155 V to 0 V
// within 0.1 s). Asserted besides: no trip, the mean speed in the metrics window within 1 % of 600
// rpm and the plant's mean torque within 2 % of the load's rated 26.5 N*m, the phase currents'
// imbalance below 10 %, and the mid-point within half of V_dc/2 over the whole run. Measured and
// not solved (docs/firmware-core.md): the unequal drops give phase A a small DC current that
// starts the rotor about 0.2 s into the magnetisation, after which the table's start moves the
// mid-point by 15 V, and the acceleration leaves it up to 54 V above V_dc/2 for a few hundred ms
// (the IM law has no mid-point regulation; the PM law's is dtc.c dtc_dcsupp).
TEST(FaultTolerance, ImOnTheFstpStartsFromStandstillOnTheSplitLink)
{
    Columns c = run_columns("im_fstp_speed.toml", {}, "im_fstp");
    ASSERT_EQ(c.c.count("vc_lo_v"), 1u);
    ASSERT_EQ(c.c.count("vdc_v"), 1u);
    EXPECT_EQ(c.info.fault, "none") << c.info.fault_detail;
    Trace tr;
    tr.t = c.c["t_s"];
    tr.speed = c.c["speed_rpm"];
    const std::vector<double>& lo = c.c["vc_lo_v"];
    const std::vector<double>& vdc = c.c["vdc_v"];
    const std::vector<double>& te = c.c["torque_nm"];
    double magn = 0.0, run = 0.0, n_m = 0.0, te_m = 0.0;
    const std::size_t k_magn = at(tr, 0.2), kw = at(tr, tr.t.back() - c.sc.metrics_window_s);
    for (std::size_t k = 0; k < tr.t.size(); ++k) {
        const double d = std::fabs(lo[k] - 0.5 * vdc[k]);
        (k < k_magn ? magn : run) = std::max(k < k_magn ? magn : run, d);
        if (k >= kw) {
            n_m += tr.speed[k];
            te_m += te[k];
        }
    }
    n_m /= static_cast<double>(tr.t.size() - kw);
    te_m /= static_cast<double>(tr.t.size() - kw);
    std::printf("MEASURE im_fstp_speed: mid-point within %.1f V of V_dc/2 during the magnetisation, %.1f V over the run; "
                "window: %.1f rpm, torque %.2f N*m, imbalance %.2f %%\n",
                magn, run, n_m, te_m, c.metrics.imbalance_pct.value_or(-1.0));
    EXPECT_LT(magn, 5.0);
    EXPECT_LT(run, 0.25 * 311.0); /* half of V_dc/2 */
    EXPECT_NEAR(n_m, 600.0, 6.0);
    EXPECT_NEAR(te_m, 26.5, 0.02 * 26.5);
    ASSERT_TRUE(c.metrics.imbalance_pct.has_value());
    EXPECT_LT(*c.metrics.imbalance_pct, 10.0);
}
