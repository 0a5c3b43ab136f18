// test_im_fly.cpp - the induction-machine drive without an encoder (control.speed_sensor = "none")
// started into a rotor that already turns (firmware/dtc/im_dtc_internal.h im_magn_vector): the 4 kW IM of
// im_dtc_speed.toml and the second machine of im_second_machine.toml, at +-10, +-50 and +-100 %
// of the rated speed, the rotor held there by the dynamometer (load.type = "speed", torque mode,
// T* = 50 % rated in the rotor's direction: motoring, the dynamometer absorbs it) or coasting on
// its inertia (load.type = "inertia", speed mode, the reference 30 % of the rated speed in the
// rotor's direction: the drive accelerates the rotor from 10 % and brakes it from 50 and 100 %).
// Asserted on the plant, for every IM law:
//   - no fault over the run;
//   - the plant's torque has the right sign within 0.5 s of the start (its mean over 10 ms past a
//     quarter of the rated torque: held, the sign of T*; coasting, the sign of the reference less
//     the rotor's speed);
//   - once running (the last 0.1 s), the speed estimate within 5 % of the rotor's speed;
//   - held: the mean torque of the last 0.1 s within 25 % of T* (the flux built at the rotor's
//     speed: a flux the machine does not have gives the wrong torque with no fault).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "im_rig.hpp"

using namespace sil;
using sil_test::Rig;

namespace {

struct FlyCase {
    const char* machine; // scenario file under tools/scenarios
    double frac;         // initial speed / rated speed
    bool held;
};

struct FlyResult {
    std::string fault;
    double t_sign_s = -1.0;   // first time the 10 ms mean torque has the right sign past 25 % rated
    double speed_err = 0.0;   // worst |est - true| / |true| over the last 0.1 s
    double te_mean = 0.0;     // plant's mean torque over the last 0.1 s
    double speed_end = 0.0;
    double t_ref = 0.0;
};

FlyResult run_fly(const FlyCase& c, const char* law)
{
    const std::string scen = std::string(DTC_SOURCE_DIR) + "/tools/scenarios/" + c.machine;
    // rated speed and torque of the scenario's machine
    Rig probe({}, scen);
    FlyResult o;
    if (!probe.ok) {
        o.fault = "setup";
        return o;
    }
    const double rated_rpm = probe.sc.motor.rated_speed_rpm;
    const double rated_nm = probe.sc.motor.rated_torque_nm;
    const double rpm = c.frac * rated_rpm;
    char buf[64];
    std::vector<std::string> sets = {"control.speed_sensor=none", std::string("control.scheme=") + law,
                                     "load.step_time_s=0"};
    std::snprintf(buf, sizeof buf, "initial_speed_rpm=%.3f", rpm);
    sets.emplace_back(buf);
    if (c.held) {
        o.t_ref = std::copysign(0.5 * rated_nm, rpm); // motoring: the load absorbs it
        sets.emplace_back("load.type=speed");
        std::snprintf(buf, sizeof buf, "load.speed_rpm=%.3f", rpm);
        sets.emplace_back(buf);
        sets.emplace_back("control.mode=torque");
        std::snprintf(buf, sizeof buf, "control.torque_ref_nm=%.4f", o.t_ref);
        sets.emplace_back(buf);
    } else {
        // the speed loop towards 30 % of the rated speed in the rotor's direction: it accelerates
        // the rotor from 10 %, brakes it from 50 and 100 %; only the torque's sign is asserted
        const double ref = std::copysign(0.3 * rated_rpm, rpm);
        o.t_ref = std::copysign(rated_nm, ref - rpm);
        sets.emplace_back("load.type=inertia");
        // a coupled load of nine times the rotor's inertia (a fan or a conveyor that coasts): on
        // the bare rotor the magnetisation's own drag (the zero-torque band with the period's
        // delay, docs/sil.md) slows it to the reference before the speed loop runs
        std::snprintf(buf, sizeof buf, "motor.j_kgm2=%.6f", 10.0 * probe.sc.motor.j_kgm2);
        sets.emplace_back(buf);
        std::snprintf(buf, sizeof buf, "control.speed_ref_rpm=%.3f", ref);
        sets.emplace_back(buf);
    }
    Rig r(sets, scen);
    if (!r.ok) {
        o.fault = "setup";
        return o;
    }
    const double t_end = 1.0;
    const long n = r.periods(t_end), n_win = r.periods(0.01), n_last = r.periods(0.1);
    std::vector<double> te(static_cast<std::size_t>(n));
    double sum_last = 0.0;
    for (long k = 0; k < n; ++k) {
        r.period();
        te[static_cast<std::size_t>(k)] = r.st().te_nm;
        if (k >= n_win && o.t_sign_s < 0.0) {
            double s = 0.0;
            for (long j = k - n_win + 1; j <= k; ++j) {
                s += te[static_cast<std::size_t>(j)];
            }
            if (std::copysign(1.0, o.t_ref) * s / static_cast<double>(n_win) > 0.25 * rated_nm) {
                o.t_sign_s = static_cast<double>(k + 1) * r.ts();
            }
        }
        if (k >= n - n_last) {
            sum_last += r.st().te_nm;
            const double sp = r.st().speed_rpm;
            o.speed_err = std::fmax(o.speed_err, std::fabs(r.speed_est_rpm() - sp) / std::fmax(std::fabs(sp), 1.0));
        }
        if (r.fault() != "none") {
            break;
        }
    }
    o.fault = r.fault();
    o.te_mean = sum_last / static_cast<double>(n_last);
    o.speed_end = r.st().speed_rpm;
    return o;
}

struct FlyParam {
    const char* law;
    const char* machine;
};

class ImFly : public ::testing::TestWithParam<FlyParam> {};

TEST_P(ImFly, SensorlessStartIntoATurningRotorTorqueOfTheRightSignWithinHalfASecond)
{
    const FlyParam p = GetParam();
    for (bool held : {true, false}) {
        for (double frac : {0.1, -0.1, 0.5, -0.5, 1.0, -1.0}) {
            const FlyCase c{p.machine, frac, held};
            SCOPED_TRACE(std::string(held ? "held " : "coasting ") + std::to_string(frac));
            const FlyResult o = run_fly(c, p.law);
            std::printf("MEASURE im fly %s %s %s %+.0f %%: fault %s, torque's sign at %.3f s, speed estimate "
                        "error %.2f %% at %.0f rpm, mean torque %.2f N*m (T* %.2f)\n",
                        p.law, p.machine, held ? "held" : "coasting", 100.0 * frac, o.fault.c_str(), o.t_sign_s,
                        100.0 * o.speed_err, o.speed_end, o.te_mean, o.t_ref);
            EXPECT_EQ(o.fault, "none");
            EXPECT_GT(o.t_sign_s, 0.0);
            EXPECT_LE(o.t_sign_s, 0.5);
            EXPECT_LT(o.speed_err, 0.05);
            if (held) {
                EXPECT_NEAR(o.te_mean / o.t_ref, 1.0, 0.25);
            }
        }
    }
}

// Every IM law on the 4 kW IM; on the second machine every law but DSC, which fails there with
// the encoder as well (measured with dtc-sil run on im_second_machine.toml, docs/sil.md): at
// 144 rpm held, 0.99 N*m for T* = 5.875 N*m, and braking from 1440 to 432 rpm at the torque
// limit (J ten times the rotor's) it trips encoder_speed at 0.66 s, the estimate having lost the
// flux; DSC's low-speed and braking behaviour, not the flying start.
INSTANTIATE_TEST_SUITE_P(Laws, ImFly,
                         ::testing::Values(FlyParam{"dtc", "im_dtc_speed.toml"}, FlyParam{"dsc", "im_dtc_speed.toml"},
                                           FlyParam{"sfvc", "im_dtc_speed.toml"}, FlyParam{"dfoc", "im_dtc_speed.toml"},
                                           FlyParam{"dsvm", "im_dtc_speed.toml"}, FlyParam{"dtc", "im_second_machine.toml"},
                                           FlyParam{"sfvc", "im_second_machine.toml"},
                                           FlyParam{"dfoc", "im_second_machine.toml"},
                                           FlyParam{"dsvm", "im_second_machine.toml"}),
                         [](const ::testing::TestParamInfo<FlyParam>& i) {
                             return std::string(i.param.law) + "_" +
                                    (std::string(i.param.machine) == "im_dtc_speed.toml" ? "4kW" : "second");
                         });

} // namespace

// ---- The voltage-model estimator's start (firmware/dtc/im_est.h IM_EST_VOLTAGE) ---------------------
// The shipped IM scenarios with control.estimator = "voltage", as they run (speed mode from
// standstill to 1000 rpm on the fan, the rated-load step at 1.2 s): the start-up magnetises with
// Casadei eq. 20's correction towards the start-up's rotor-flux model, so the machine is not
// over-magnetised (the plant's |phi_s| below 115 % of phi_s* during the magnetisation: the flux
// band and the period's delay on top of the reference) and the drive carries the load (no fault,
// the last 0.3 s at the reference speed within 1 % and the rated torque within 3 %). Every law on
// the 4 kW IM and on the second machine (whose SFVC and DFOC once stalled after the load step, with
// the improved estimator as well: the torque limit the current allowed, docs/sil.md).
TEST(ImVoltageModel, StartsWithoutOverMagnetisingAndCarriesTheRatedLoad)
{
    const struct {
        const char* machine;
        const char* law;
    } cases[] = {{"im_dtc_speed.toml", "dtc"},       {"im_dtc_speed.toml", "dsc"},       {"im_dtc_speed.toml", "sfvc"},
                 {"im_dtc_speed.toml", "dfoc"},      {"im_dtc_speed.toml", "dsvm"},      {"im_second_machine.toml", "dtc"},
                 {"im_second_machine.toml", "dsc"}, {"im_second_machine.toml", "sfvc"},
                 {"im_second_machine.toml", "dfoc"}, {"im_second_machine.toml", "dsvm"}};
    for (const auto& c : cases) {
        SCOPED_TRACE(std::string(c.machine) + " " + c.law);
        Rig r({"control.estimator=voltage", std::string("control.scheme=") + c.law},
              std::string(DTC_SOURCE_DIR) + "/tools/scenarios/" + c.machine);
        ASSERT_TRUE(r.ok);
        const long n_magn = static_cast<long>(r.cfg.u.im.ref.magn_periods) + 64;
        const long n = r.periods(r.sc.duration_s), n_win = r.periods(0.3), n_step = r.periods(r.sc.load.step_time_s);
        double psis_peak = 0.0, te = 0.0, speed = 0.0;
        for (long k = 0; k < n && r.fault() == "none"; ++k) {
            if (k == n_step) { // the scenario's load step (dtc-sil run applies it; the rig steps the plant)
                plant_set_load(r.h->plant(), PLANT_LOAD_FAN, r.sc.load.speed_rpm, r.sc.load.step_torque_nm);
            }
            r.period();
            if (k < n_magn) {
                psis_peak = std::fmax(psis_peak, r.psis());
            }
            if (k >= n - n_win) {
                te += r.st().te_nm;
                speed += r.st().speed_rpm;
            }
        }
        te /= static_cast<double>(n_win);
        speed /= static_cast<double>(n_win);
        const double t_load = r.sc.load.step_torque_nm, n_ref = r.sc.control.speed_ref_rpm;
        std::printf("MEASURE voltage model %s %s: peak |phi_s| %.3f Wb in the start (phi_s* %.2f), fault %s, "
                    "last 0.3 s %.1f rpm (ref %.0f), %.2f N*m (load %.2f)\n",
                    c.machine, c.law, psis_peak, r.si.flux_ref_wb, r.fault().c_str(), speed, n_ref, te, t_load);
        EXPECT_EQ(r.fault(), "none");
        EXPECT_LT(psis_peak, 1.15 * r.si.flux_ref_wb);
        EXPECT_NEAR(speed, n_ref, 0.01 * n_ref);
        EXPECT_NEAR(te, t_load, 0.03 * t_load);
    }
}
