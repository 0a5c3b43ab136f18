// test_im_torque_bias.cpp - the IM drive's torque against its reference at low speed: the device-drop
// compensation (firmware/dtc/vcomp.c), the rotor-flux trim that keeps Casadei eq. 20's correction
// without a mean (firmware/dtc/im_dtc.c im_psir_trim), the dead-time error at the switching instant
// (im_dtc_estimate), and DSC's flux at low speed and light load. The whole grid (every law, 5 to 100 %
// of rated speed, 10 to 100 % of rated torque, both machines) is tools/sweep/im_torque_accuracy.py
// (ctest sil.im_torque_accuracy_grid).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

extern "C" {
#include "dtc_config_si.h"
}

#include "firmware_si.hpp"
#include "scenario_outcome.hpp"

namespace {

struct Point {
    double te_mean = 0.0, te_est = 0.0, psi = 0.0, psi_est = 0.0;
    std::string fault;
};

// The IM of `file` in torque mode, the dynamometer holding rpm from standstill, T* = t_nm, law
// `scheme`, compensation `comp`: 2 s, the plant's mean torque over the last 0.84 s (four electrical
// periods at 144 rpm) and the mean stator-flux magnitudes of the plant and of the estimate; below
// 100 rpm (72 rpm: 5 % of rated) 9.2 s and its last 8.33 s (20 electrical periods): there a 0.84 s
// mean scatters by about +-1.5 % of T* (DSVM, 4 kW, 10 % torque, the held speed moved by 0.02 rpm;
// docs/sil.md), as wide as the target, as in tools/sweep/im_torque_accuracy.py's WINDOWS.
// `sensor`: control.speed_sensor (the shipped scenarios' encoder, or "none"); `cm`:
// control.current_model_ref (Casadei eq. 20's reference from the rotor-flux current model at low speed,
// firmware/dtc/im_sup.h), on: the default, as in tools/sweep/im_torque_accuracy.py.
Point run_point(const std::string& file, const std::string& scheme, const std::string& comp, double rpm, double t_nm,
                const std::string& sensor = "encoder", bool cm = true)
{
    const bool low = rpm < 100.0;
    const sil_test::Outcome o = sil_test::run_shipped(
        file, {"control.mode=torque", "load.type=speed", "load.step_time_s=0",
               std::string("duration_s=") + (low ? "9.2" : "2.0"), std::string("metrics_window_s=") + (low ? "8.33" : "0.84"),
               "load.speed_rpm=" + std::to_string(rpm), "control.torque_ref_nm=" + std::to_string(t_nm),
               "control.scheme=" + scheme, "control.compensation=" + comp, "control.speed_sensor=" + sensor,
               "control.current_model_ref=" + std::string(cm ? "true" : "false")});
    Point p;
    p.fault = o.info.fault;
    p.te_mean = o.m.torque_mean_nm;
    p.te_est = o.m.torque_est_mean_nm.value_or(NAN);
    const sil::Series& s = o.series;
    double a = 0.0, b = 0.0;
    for (size_t k = 0; k < s.psi_a.size(); ++k) {
        a += std::hypot(s.psi_a[k], s.psi_b[k]);
        if (k < s.psi_a_est.size()) {
            b += std::hypot(s.psi_a_est[k], s.psi_b_est[k]);
        }
    }
    p.psi = s.psi_a.empty() ? NAN : a / static_cast<double>(s.psi_a.size());
    p.psi_est = s.psi_a_est.empty() ? NAN : b / static_cast<double>(s.psi_a_est.size());
    std::printf("MEASURE %s %s %s %s %.0f rpm T* %.3f: mean torque %.4f N*m (%+.2f %%), estimate %+.2f %%, |phi_s| %.3f Wb, "
                "estimate %.3f Wb, fault %s\n",
                file.c_str(), scheme.c_str(), comp.c_str(), sensor.c_str(), rpm, t_nm, p.te_mean, 100.0 * (p.te_mean / t_nm - 1.0),
                100.0 * (p.te_est / t_nm - 1.0), p.psi, p.psi_est, p.fault.c_str());
    return p;
}

} // namespace

TEST(ImTorqueBias, DeviceDropsPerLegRemoveTheLowSpeedBias)
{
    // The IM rig's devices (plant_defaults.h) drop V_CE = 0.9 V through a transistor and
    // V_d = 1.25 V through a diode. The SSTP compensation of Hoang ref. [29] ("simple") assumes one
    // drop V_f = 0.9 V for both, so over the intervals in which a phase's current flows through the
    // diode of the switch that is off 0.35 V per leg goes uncompensated. At 72 rpm (5 % of rated)
    // and 10 % rated torque the stator voltage is a few volts and the estimated flux follows the
    // error: DTC gives -13.6 % (-11.8 % before the rotor-flux trim and the dead-time sign; +13.2 %
    // with V_f = 1.25 V: the sign follows the assumed drop). Hoang Table III per leg ("proposed" on
    // the SSTP) removes it. Shown without the encoder, where the voltage model alone sets the flux
    // angle (measured: "simple" -13.4 %, "proposed" +0.83 %); with the encoder, Casadei eq. 20's
    // correction pulls towards the rotor-flux current model at this speed (firmware/dtc/im_sup.h),
    // which the voltage's error does not reach: "simple" -0.76 %.
    const double t_ref = 0.1 * 26.5;
    EXPECT_LT(run_point("im_dtc_speed.toml", "dtc", "simple", 72.0, t_ref, "none").te_mean, 0.95 * t_ref); // the cause
    EXPECT_NEAR(run_point("im_dtc_speed.toml", "dtc", "proposed", 72.0, t_ref, "none").te_mean, t_ref, 0.015 * t_ref);
    EXPECT_NEAR(run_point("im_dtc_speed.toml", "dtc", "simple", 72.0, t_ref).te_mean, t_ref, 0.015 * t_ref);
    EXPECT_NEAR(run_point("im_dtc_speed.toml", "dtc", "proposed", 72.0, t_ref).te_mean, t_ref, 0.015 * t_ref);
    EXPECT_NEAR(run_point("im_dtc_speed.toml", "dtc", "proposed", 720.0, 0.5 * 26.5).te_mean, 0.5 * 26.5,
                0.005 * 0.5 * 26.5);
}

// Every IM law at 5 % of rated speed (72 rpm), the corner of the grid where the estimate's
// bias showed: 10 and 100 % of rated torque on the 4 kW IM and on the second machine, per-leg drop
// compensation. The causes, measured one at a time (docs/sil.md, the IM torque accuracy):
//   - Casadei eq. 20's correction (phi_r* e^{j theta} - phi_r)/tau is radial; while the law holds
//     |phi_r| off phi_r* (a table law's sampled flux comparator, DSC's hexagon, the DFOC's i_d) it
//     stays, and at the stator frequency w_s it becomes a flux-angle error (phi_r* - |phi_r|)/(tau w_s),
//     i_d/i_q times larger in the torque: ideal inverter, DTC, 0.31 mWb -> 2.7 mrad -> -1.9 %. The
//     rotor-flux trim (im_psir_trim) holds the mean |phi_r| at phi_r*;
//   - the dead-time error taken on the current's sign at the period's end instead of at the
//     switching instant: +3.1 % (DTC, ideal devices) once the trim is in;
//   - DSVM's resistive drop on the sampled current, while its fixed order of thirds (the nulls
//     first, dsvm.h) moves the period's mean current off the samples by (v_1 - v_3) Ts/(9 sigma L_s)
//     (im_dsvm.c): the second machine +4.68 % -> +0.82 %, 4 kW +1.89 % -> -1.36 %;
//   - the modulated laws' per-leg drops: a leg at duty d gives d (V_dc + V_d - V_CE) besides the
//     state-0 drops the estimator adds, 0.35 V per volt-second of duty that the estimate lacked
//     (im_dtc.h pwm_dv_iq): measured with the dead time off, second machine, SFVC +1.15 -> +0.60 %,
//     DFOC -0.17 % (the ideal inverter's -0.23 %). With the dead time on it leaves the dead time's
//     own error: SFVC +2.22 -> +1.76 %, DFOC -0.91 -> -1.79 % (the drop error had hidden part of
//     it), 4 kW SFVC +1.72 -> +0.91 %, DSVM -1.36 -> +1.37 %;
//   - the rotor-flux trim's ring through the improved estimator's slow pole w_s^2 tau / k_r (+-2-3 %
//     of T* per stator period for seconds): the current model's reference at low speed
//     (firmware/dtc/im_sup.h), second machine SFVC +1.76 -> +0.11 %, DFOC -1.79 -> +0.12 %.
// Before these: DTC -1.35 %, SFVC -3.28 %, DFOC +8.62 %, DSVM -4.62 % at 10 % torque (4 kW).
// Asserted: within the 1.5 % at every point, no law held below the torque asked for by the
// torque limit the current allows (dtc_im_hold_margin_a). The DFOC on the second machine at rated
// torque was (22.3 N*m of 23.5 while its excursion was a whole dI = 6.46 A); its zeta = 0 design
// now keeps its SVM ripple (1.31 A) as the SFVC does: 37.6 N*m, room enough (docs/sil.md).
TEST(ImTorqueBias, EveryLawWithinOnePointFivePercentAtFivePercentSpeed)
{
    struct M {
        const char* file;
        double t_rated;
    };
    const M machines[] = {{"im_dtc_speed.toml", 26.5}, {"im_second_machine.toml", 23.5}};
    for (const M& mc : machines) {
        for (const char* law : {"dtc", "sfvc", "dfoc", "dsvm"}) {
            for (double frac : {0.1, 1.0}) {
                SCOPED_TRACE(std::string(mc.file) + " " + law + " " + std::to_string(frac));
                const double t = frac * mc.t_rated;
                const Point p = run_point(mc.file, law, "proposed", 72.0, t);
                EXPECT_EQ(p.fault, "none");
                // the torque limit the current allows (the converter's, law_im_si.c)
                sil::Scenario sc;
                sil::Diagnostics d;
                ASSERT_TRUE(sil::load_scenario(sil_test::scenarios_dir() + mc.file,
                                               {std::string("control.scheme=") + law}, &sc, &d))
                    << d.text();
                const dtc_config_si_t si = sil::firmware_si_config(sc);
                const double t_lim =
                    dtc_im_torque_at_current_nm(&si, dtc_ilim_default_a(&si) - dtc_im_hold_margin_a(&si));
                const bool limited = t_lim < t;
                // no law is held below its rated torque (the second machine's DFOC was, at 22.3 N*m,
                // while its excursion was a whole dI: now its SVM ripple, as the SFVC's; docs/sil.md)
                EXPECT_FALSE(limited) << t_lim;
                const double t_held = limited ? t_lim : t;
                EXPECT_NEAR(p.te_mean, t_held, 0.015 * t_held);
                EXPECT_NEAR(p.te_est, t_held, 0.005 * t_held); // the comparators and regulators hold the estimate
            }
        }
    }
}

// DSC at low speed: at 72 rpm and 50 % rated torque the hexagon's flux sat below phi_s* (mean
// |phi_r| 17 mWb under phi_r*) and Casadei eq. 20's correction turned that into a flux-angle error
// of -150 mrad: -17 % of torque (-4.6 % at rated torque); the rotor-flux trim took that to 1.5 %.
// At 10 % torque DSC gave the wrong sign: DSC does not control the flux amplitude (Casadei sec. 9,
// "to the detriment of the control of the stator flux amplitude"); under the long null-vector
// intervals of low speed and light load the machine's flux decayed to 0.045 Wb while the improved
// estimator held the estimate at its reference (0.51 Wb). With ST-D's flux-raising vector for the
// null the flux held, but the hexagon's path still left eq. 20's correction a mean that the
// estimator turned into a 12-20 mrad angle error (-10.9 % of torque, +49 % on the second machine
// at 72 rpm, the same with an ideal inverter). Below the speed at which section 8 hands ST-D over
// to ST-A the law now runs ST-D's circular path (im_dsc_hexagon, Depenbrock's low-speed remedy).
// Asserted: the target (1.5 %) at 72 rpm, 50 % and 10 % torque, the machine's mean |phi_s| within
// 2 % of the estimate's, and the second machine at 10 % speed without the encoder-plausibility trip
// it had while its flux collapsed.
// The DFOC regenerating (the rotor held at 50 % of rated speed by the dynamometer, T* = -50 and
// -100 % of rated): the DFOC holds i_d* in the estimate's frame, so an angle error moves the
// machine's i_d by -i_q eps, and Casadei eq. 20's correction turns the rotor flux it loses into more
// lag, a loop of gain (l_r/m)(i_q/i_d)/(tau w_s) that is positive while i_q w_s < 0 (docs/sil.md).
// Without the DFOC's rotor-flux term (im_dfoc.c) the 4 kW tripped current_sensor at rated braking
// torque, with the encoder and without it (main cf91d9a; the second machine was then held at its
// 22.3 N*m limit). Asserted: no fault, the plant within the 1.5 %, with the encoder and
// without it.
TEST(ImTorqueBias, DfocRegeneratingHoldsTheRotorFluxAndTheTorque)
{
    const struct {
        const char* file;
        double t_rated;
    } machines[] = {{"im_dtc_speed.toml", 26.5}, {"im_second_machine.toml", 23.5}};
    for (const auto& mc : machines) {
        for (const char* sensor : {"encoder", "none"}) {
            for (double frac : {-0.5, -1.0}) {
                SCOPED_TRACE(std::string(mc.file) + " " + sensor + " " + std::to_string(frac));
                const double t = frac * mc.t_rated;
                const Point p = run_point(mc.file, "dfoc", "proposed", 720.0, t, sensor);
                EXPECT_EQ(p.fault, "none");
                EXPECT_NEAR(p.te_mean, t, 0.015 * std::fabs(t));
            }
        }
    }
}

TEST(ImTorqueBias, DscAtFivePercentSpeedHoldsTheTorqueLoadedAndTheFluxAtLightLoad)
{
    const Point loaded = run_point("im_dtc_speed.toml", "dsc", "proposed", 72.0, 13.25);
    EXPECT_EQ(loaded.fault, "none");
    EXPECT_NEAR(loaded.te_mean, 13.25, 0.015 * 13.25);
    const Point light = run_point("im_dtc_speed.toml", "dsc", "proposed", 72.0, 2.65);
    EXPECT_EQ(light.fault, "none");
    EXPECT_NEAR(light.psi, light.psi_est, 0.02 * light.psi_est);
    EXPECT_NEAR(light.te_mean, 2.65, 0.015 * 2.65);
    EXPECT_NEAR(light.te_est, 2.65, 0.02 * 2.65);
    const Point second = run_point("im_second_machine.toml", "dsc", "proposed", 144.0, 2.35);
    EXPECT_EQ(second.fault, "none");
    EXPECT_NEAR(second.psi, second.psi_est, 0.02 * second.psi_est);
    EXPECT_NEAR(second.te_mean, 2.35, 0.015 * 2.35);
}
