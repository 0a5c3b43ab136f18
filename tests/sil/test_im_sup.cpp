// test_im_sup.cpp - the IM model's supervision (firmware/dtc/im_sup.h) on the SIL: a firmware
// R_r or L_m 30 % off the plant's raises im_model_mismatch within 1 s, healthy runs raise no
// warning, and the rotor resistance tracked on line keeps the torque at its reference while the
// windings warm (plant key motor.temp_rise_k); the plant's resistance change itself checked
// against Ohm's law at DC.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "plant.h"
#include "plant_defaults.h"
#include "run.hpp"
#include "scenario.hpp"
#include "scenario_outcome.hpp"

using sil_test::Outcome;

namespace {

const std::string kIm = "im_dtc_speed.toml";

bool warned(const Outcome& o)
{
    return o.info.warnings == std::vector<std::string>{"im_model_mismatch"};
}

// The default IM's firmware values 30 % off the plant's (plant_defaults.h).
std::string off(const char* key, double plant, double factor)
{
    return std::string("firmware.") + key + "=" + std::to_string(plant * factor);
}

} // namespace

TEST(ImSup, RrOrLmThirtyPercentOffWarnsWithinOneSecond)
{
    // Encoder fitted, from standstill: im_dtc_speed (magnetised at 0.44 s, then 1000 rpm on a fan
    // load) and the second machine (im_second_machine.toml, R_r 1.355 ohm, L_m 0.14375 H). The
    // warning must come within 1 s of the start; measured 0.53-0.66 s and 0.49-0.62 s: the
    // adaptation's time constant at half the rated torque is 4 T_filt T_lim / T = 0.12 s, the flux
    // check's tau_r. (The estimate converges to the plant's: r_r^/r_r -> 1.42 and 0.76 for the
    // 4 kW machine's R_r x0.7 and x1.3, 1/0.7 = 1.43 and 1/1.3 = 0.77.)
    struct Case {
        const char* file;
        double rr, lm;
    };
    for (const Case& c : {Case{"im_dtc_speed.toml", PLANT_DEF_IM_RR_OHM, PLANT_DEF_IM_LM_H},
                          Case{"im_second_machine.toml", 1.355, 0.14375}}) {
        for (const std::string& s : {off("rr_ohm", c.rr, 0.7), off("rr_ohm", c.rr, 1.3), off("lm_h", c.lm, 0.7),
                                     off("lm_h", c.lm, 1.3)}) {
            const Outcome o = sil_test::run_shipped(c.file, {s});
            EXPECT_EQ(o.info.fault, "none") << c.file << " " << s;
            EXPECT_TRUE(warned(o)) << c.file << " " << s;
            EXPECT_GT(o.info.warning_time_s, 0.3) << c.file << " " << s; // not before the flux is built
            EXPECT_LT(o.info.warning_time_s, 1.0) << c.file << " " << s;
        }
    }
}

TEST(ImSup, HealthyRunsRaiseNoWarning)
{
    // Exact parameters: every IM scheme on im_dtc_speed (start, 1000 rpm, rated-load step), the
    // second machine's scenario, and the same runs sensorless (the flux check alone).
    for (const char* scheme : {"dtc", "dsc", "sfvc", "dfoc", "dsvm"}) {
        const Outcome o = sil_test::run_shipped(kIm, {std::string("control.scheme=\"") + scheme + "\""});
        EXPECT_EQ(o.info.fault, "none") << scheme;
        EXPECT_TRUE(o.info.warnings.empty()) << scheme;
        EXPECT_LT(o.info.warning_time_s, 0.0) << scheme;
    }
    const Outcome m2 = sil_test::run_shipped("im_second_machine.toml");
    EXPECT_EQ(m2.info.fault, "none");
    EXPECT_TRUE(m2.info.warnings.empty());
    const Outcome sl = sil_test::run_shipped(kIm, {"control.speed_sensor=\"none\""});
    EXPECT_TRUE(sl.info.warnings.empty());
}

TEST(ImSup, SensorlessSeesLmButNotRr)
{
    // Without the encoder the slip is not measured: an R_r error is a speed error, nothing warns;
    // the flux check (m i_d against the improved estimator's |phi_r|) needs no encoder.
    const Outcome rr = sil_test::run_shipped(kIm, {"control.speed_sensor=\"none\"", off("rr_ohm", PLANT_DEF_IM_RR_OHM, 1.3)});
    EXPECT_TRUE(rr.info.warnings.empty());
    const Outcome lm = sil_test::run_shipped(kIm, {"control.speed_sensor=\"none\"", off("lm_h", PLANT_DEF_IM_LM_H, 1.3)});
    EXPECT_TRUE(warned(lm));
}

TEST(ImSup, TrackingHoldsTheTorqueAsTheWindingsWarm)
{
    // Torque mode, dynamometer at 720 rpm, T* = 13.25 N*m (50 % rated), the windings 102.6 K warmer
    // at the end of the 2 s run: R_s and R_r 40 % up (copper, 0.39 %/K). The torque over
    // 0.6..2.0 s in 0.1 s blocks, every IM scheme: within 3 % of T* with the tracking; without it
    // the voltage model's R_s error biases the estimate and the torque falls out of the 3 % late in
    // the run (DTC, SFVC, DSVM; DSC and DFOC lose 2.2-2.5 %). The warning is raised either way: the configured
    // resistances are off the warm machine's by more than a fifth.
    const std::vector<std::string> base = {"control.mode=\"torque\"", "load.type=\"speed\"", "load.speed_rpm=720",
                                           "control.torque_ref_nm=13.25", "load.step_time_s=0", "duration_s=2.0",
                                           "metrics_window_s=1.4", "motor.temp_rise_k=102.6"};
    auto worst_block = [](const Outcome& o) {
        const std::size_t n = static_cast<std::size_t>(std::lround(0.1 / o.series.ts_s));
        double worst = 0.0;
        for (std::size_t b = 0; b + n <= o.series.te.size(); b += n) {
            double s = 0.0;
            for (std::size_t k = b; k < b + n; ++k) {
                s += o.series.te[k];
            }
            worst = std::fmax(worst, std::fabs(s / static_cast<double>(n) / 13.25 - 1.0));
        }
        return worst;
    };
    auto tail_mean = [](const Outcome& o) { // the last 0.3 s: R +36..40 %
        const std::size_t n = static_cast<std::size_t>(std::lround(0.3 / o.series.ts_s));
        double s = 0.0;
        for (std::size_t k = o.series.te.size() - n; k < o.series.te.size(); ++k) {
            s += o.series.te[k];
        }
        return s / static_cast<double>(n) / 13.25 - 1.0;
    };
    // Measured, last 0.3 s, tracking on / off: DTC -0.67 / -3.77 %, DSC +1.25 / -2.23 %, SFVC
    // -0.70 / -3.96 %, DFOC -0.37 / -2.53 %, DSVM -1.09 / -3.90 %; worst 0.1 s block on / off:
    // 1.37 / 3.99, 1.58 / 2.73, 0.75 / 4.13, 0.64 / 2.74, 1.24 / 4.26 %.
    for (const char* scheme : {"dtc", "dsc", "sfvc", "dfoc", "dsvm"}) {
        std::vector<std::string> on = base, off_ = base;
        on.push_back(std::string("control.scheme=\"") + scheme + "\"");
        off_.push_back(on.back());
        on.push_back("control.rr_tracking=true");
        off_.push_back("control.rr_tracking=false");
        const Outcome t = sil_test::run_shipped(kIm, on);
        const Outcome u = sil_test::run_shipped(kIm, off_);
        ASSERT_EQ(t.info.fault, "none") << scheme;
        ASSERT_EQ(u.info.fault, "none") << scheme;
        ASSERT_GT(t.series.te.size(), 5000u) << scheme;
        EXPECT_LT(worst_block(t), 0.03) << scheme;
        EXPECT_LT(std::fabs(tail_mean(t)), 0.015) << scheme;
        EXPECT_GT(std::fabs(tail_mean(u)) - std::fabs(tail_mean(t)), 0.01) << scheme; // the tracking matters
        if (std::string(scheme) != "dsc" && std::string(scheme) != "dfoc") {
            EXPECT_LT(tail_mean(u), -0.03) << scheme;
            EXPECT_GT(worst_block(u), 0.03) << scheme;
        }
        EXPECT_TRUE(warned(t)) << scheme;
        EXPECT_TRUE(warned(u)) << scheme;
    }
}

TEST(ImSup, TempRiseKeyIsValidated)
{
    sil_test::expect_refused(kIm, {"motor.temp_rise_k=-101"}, "motor.temp_rise_k");
    sil_test::expect_refused(kIm, {"motor.temp_rise_k=301"}, "motor.temp_rise_k");
    sil_test::expect_refused(kIm, {"control.rr_tracking=1"}, "control.rr_tracking");
}

TEST(ImSup, PlantResistancesFollowOhmsLawAtDc)
{
    // The default IM on the ideal inverter with a DC voltage: at steady state the rotor flux
    // stands (Casadei eq. A7 at w = 0: dpsi_r/dt = 0 when psi_r = L_m i_s) and i = v / R_s.
    // plant_set_resistances(1.39 R_s, 1.39 R_r) (a 100 K rise of copper) gives v / (1.39 R_s).
    plant_params_t p;
    plant_params_default(&p);
    plant_params_im_default(&p);
    p.inverter = PLANT_INVERTER_IDEAL;
    p.load = PLANT_LOAD_SPEED;
    p.load_speed_rpm = 0.0;
    char err[256] = {0};
    std::unique_ptr<plant_t, void (*)(plant_t*)> pl(plant_create(&p, err, sizeof err), plant_destroy);
    ASSERT_NE(pl, nullptr) << err;
    const double v = 4.0;
    plant_set_voltage(pl.get(), v, 0.0);
    auto settle = [&]() {
        for (int k = 0; k < 40000; ++k) { // 2 s, 15 tau_r
            plant_advance(pl.get(), 50e-6);
        }
        plant_state_t s;
        plant_get_state(pl.get(), &s);
        return s.i_a;
    };
    // (within 0.1 %: the ideal source's own series resistance is below 1e-4 ohm, measured 8e-5)
    EXPECT_NEAR(settle(), v / p.rs_ohm, 1e-3 * v / p.rs_ohm);
    const double k = 1.0 + PLANT_DEF_CU_TEMPCO_PER_K * 100.0;
    ASSERT_EQ(plant_set_resistances(pl.get(), k * p.rs_ohm, k * p.rr_ohm), 0);
    EXPECT_NEAR(settle(), v / (k * p.rs_ohm), 1e-3 * v / (k * p.rs_ohm));
    EXPECT_EQ(plant_set_resistances(pl.get(), 0.0, p.rr_ohm), -1);
}
