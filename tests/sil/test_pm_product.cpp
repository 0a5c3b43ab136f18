// test_pm_product.cpp - the PM drive as a product: the targets this firmware meets, with a
// margin, on the SIL: start from standstill (J = 5e-4 kg m^2,
// set in the scenarios), hand-over, delay and dead-time compensation, bad configuration refused.
// Targets NOT met are not asserted here; docs/firmware-core.md lists them with figures.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "run.hpp"
#include "scenario.hpp"
#include "scenario_outcome.hpp"

using namespace sil;

namespace {

using sil_test::Outcome;

Outcome run(const std::string& file, const std::vector<std::string>& sets = {})
{
    return sil_test::run_shipped(file, sets);
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

TEST(PmProduct, EveryEstimatorAndCompensationStartsFromStandstillAndHolds1500rpm)
{
    // Every estimator x compensation (current; voltage with none / simple / proposed on the FSTP,
    // none / [29] on the SSTP), from standstill (the scenarios' initial_speed_rpm = 0, J = 5e-4)
    // on the shipped finite split link (2 x 4.7 mF, 3.3 kOhm, 25 mOhm), with the generator load
    // and with a constant (active) 0.3 N*m: no trip, mean speed within 1 %. What makes the
    // constant load pass: the rotor hold during the FSTP mid-point calibration (without it the load
    // turns the rotor back to -287 rpm and the reversal empties a capacitor: all three FSTP
    // voltage schemes stall) and, without compensation, the hand-over derived from the
    // current the uncompensated drop costs (941 rpm FSTP, 1441 rpm SSTP; at 477 rpm both stall).
    // Measured: 1499.5-1499.9 rpm.
    for (const char* f : {"fstp_current_full.toml", "sstp_current_full.toml", "fstp_voltage_none_full.toml",
                          "fstp_voltage_simple_full.toml", "fstp_voltage_proposed_full.toml",
                          "sstp_voltage_none_full.toml", "sstp_voltage_simple_full.toml"}) {
        const Outcome g = run(f);
        expect_speed_held(g, 1500.0, 0.01, std::string(f) + " generator");
        const Outcome t = run(f, {"load.type=torque", "load.torque_nm=0.3"});
        expect_speed_held(t, 1500.0, 0.01, std::string(f) + " 0.3 N*m");
    }
}

TEST(PmProduct, ActiveLoadIsHeldWhileTheMidPointIsCalibrated)
{
    // The first 50 ms of a start under a constant 0.3 N*m on the finite split link (FSTP, voltage
    // model, proposed): the mid-point calibration runs (3.2 ms gates off for the current offsets,
    // then the rotor hold until 51.2 ms). Without the hold the rotor rolls back freely:
    // omega = -(T/J) t = -0.3 / 5e-4 * 0.05 s = -30 rad/s = -286.5 rpm (closed form, friction of
    // the constant-torque load is zero). With it the rotor stays within a few encoder counts
    // (measured: speed within +-13 rpm, the damped hold's relay oscillation) and phase A, on the
    // mid-point, carries no current (measured: 3 mA at most, from the back-EMF of that motion).
    const std::vector<std::string> base = {"load.type=torque", "load.torque_nm=0.3", "duration_s=0.05",
                                           "metrics_window_s=0.05"};
    std::vector<std::string> off = base;
    off.push_back("control.cal_hold=false");
    const Outcome free = run("fstp_voltage_proposed_full.toml", off);
    ASSERT_FALSE(free.series.speed_rpm.empty());
    EXPECT_NEAR(free.series.speed_rpm.back(), -286.5, 0.03 * 286.5);
    const Outcome held = run("fstp_voltage_proposed_full.toml", base);
    ASSERT_EQ(held.info.fault, "none");
    const auto& v = held.series.speed_rpm;
    ASSERT_GT(v.size(), 500u);
    for (double w : v) {
        ASSERT_LT(std::fabs(w), 30.0);
    }
    double ia_max = 0.0;
    for (double i : held.series.ia) {
        ia_max = std::max(ia_max, std::fabs(i));
    }
    EXPECT_LT(ia_max, 0.05);
}

TEST(PmProduct, CurrentModelReversesABackwardsTurningRotorOnTheSplitLinkWhenPhaseAIsOffTheTorqueAxis)
{
    // A start from a rotor turning backwards (-287 rpm: what 51.2 ms of gates-off calibration
    // makes of standstill under an active 0.3 N*m with J = 5e-4) on the current model, constant
    // 0.3 N*m, shipped finite split link (2 x 4.7 mF); the rotor hold keeps the calibration
    // from causing it (ActiveLoadIsHeldWhileTheMidPointIsCalibrated), but a drive restarted on a
    // rotor the load is already turning backwards meets it. During the reversal the rotor barely turns,
    // so phase A (on the mid-point) carries i_a = -i_q sin(theta_e) almost constantly; the link
    // holds C V_dc = 0.33 C. With sin(theta_e) small at the reversal (theta = pi, 0.5 rad; 0.069 C
    // measured at 0.5 rad) the drive must reverse the rotor and hold 1500 rpm without a trip.
    // Near theta_e = +-90 deg the charge exceeds the link's and it stalls (a physical limit of the
    // FSTP on this link, not asserted here: docs/firmware-core.md "Active load on the finite split
    // link"). Measured: 1499.7-1499.8 rpm.
    for (const char* th : {"initial_theta_m_rad=3.142", "initial_theta_m_rad=0.5"}) {
        const Outcome o = run("fstp_current_full.toml",
                              {"load.type=torque", "load.torque_nm=0.3", "initial_speed_rpm=-287", th});
        expect_speed_held(o, 1500.0, 0.01, th);
    }
}

TEST(PmProduct, TableIxOrderingFromStandstillWithTheCompensations)
{
    // Hoang Table IX/X trends at 1500 rpm full load on the shipped finite split link: imbalance
    // none > simple > proposed, proposed <= 8 % (measured 7.1 %), current model <= 5 % (1.9 %);
    // estimated torque above the true one without compensation (0.327 vs 0.300 N*m) and within
    // 3 % of rated with the proposed scheme (0.3014). Every scenario from standstill (the
    // uncompensated one reaches 1500 rpm since the current limit, ilim.h; measured 59.3 / 19.6 /
    // 7.1 / 1.9 %).
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
    // Dead-time compensation on the proposed scheme: imbalance 17.3 -> 7.9 % (stiff link; on the
    // finite split link 4.9 -> 7.1 %, not an improvement there: docs/firmware-core.md).
    const Outcome off = run("fstp_current_full.toml", {"control.delay_comp=false"});
    const Outcome on = run("fstp_current_full.toml", {"control.deadtime_comp=false"});
    ASSERT_TRUE(off.m.thd_total_pct && on.m.thd_total_pct);
    EXPECT_LT(on.m.trf_pct, 0.7 * off.m.trf_pct);
    EXPECT_LT(*on.m.thd_total_pct, 0.7 * *off.m.thd_total_pct);
    const Outcome dt_off = run("fstp_voltage_proposed_full.toml", {"control.deadtime_comp=false", "inverter.finite_dc_link=false"});
    const Outcome dt_on = run("fstp_voltage_proposed_full.toml", {"inverter.finite_dc_link=false"});
    ASSERT_TRUE(dt_off.m.imbalance_pct && dt_on.m.imbalance_pct);
    EXPECT_LT(*dt_on.m.imbalance_pct, 0.5 * *dt_off.m.imbalance_pct);
}

TEST(PmProduct, NegativeHandOverSpeedIsRefusedNamingTheKey)
{
    sil_test::expect_refused("fstp_voltage_proposed_full.toml", {"control.handover_rpm=-1"}, "control.handover_rpm");
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
    // the estimated torque (Hoang eq. 10) are high against the true ones by about that much on the
    // torque-producing part.
    const Outcome cm = run("fstp_current_full.toml");
    const Outcome cm_psi = run("fstp_current_full.toml", {"firmware.psi_m_wb=0.10208"});
    ASSERT_EQ(cm_psi.info.fault, "none");
    ASSERT_TRUE(cm.m.flux_est_error_rms_pct && cm_psi.m.flux_est_error_rms_pct);
    EXPECT_GT(*cm_psi.m.flux_est_error_rms_pct, 5.0);
    EXPECT_LT(*cm.m.flux_est_error_rms_pct, 2.0);
    // A negative resistance is refused, naming the key.
    sil_test::expect_refused("fstp_voltage_proposed_full.toml", {"firmware.rs_ohm=-0.1"}, "firmware.rs_ohm");
}

TEST(PmProduct, UncompensatedVoltageModelStartsFromStandstillUnderTheCurrentLimit)
{
    // Without a current limit the four uncompensated voltage-model scenarios trip on over-current
    // during the acceleration (7.1-7.6 A against the 6 A trip). With the current limit below the trip
    // (firmware/dtc/ilim.h, I_lim derived from the trip level: 4.87 A) they reach 1500 rpm and
    // hold it within 1 %; with the limit off they still trip (the limit is what fixes it).
    for (const char* f : {"fstp_voltage_none_full.toml", "fstp_voltage_none_half.toml",
                          "fstp_voltage_none_inertial.toml", "sstp_voltage_none_full.toml"}) {
        const Outcome o = run(f);
        expect_speed_held(o, 1500.0, 0.01, f);
    }
    // constant 0.3 N*m: stiff link (on the finite link it stalls, as the compensated FSTP schemes)
    const Outcome t = run("fstp_voltage_none_full.toml", {"load.type=torque", "load.torque_nm=0.3", "inverter.finite_dc_link=false"});
    expect_speed_held(t, 1500.0, 0.01, "fstp none 0.3 N*m");
    const Outcome off = run("fstp_voltage_none_full.toml", {"control.current_limit_a=0"});
    EXPECT_EQ(off.info.fault, "overcurrent");
}

TEST(PmProduct, LowSpeedQuarterLoadHoldsSpeedProposedBestOfAll)
{
    // Hoang Figs. 18-20 operating points, 25 % load (0.075 N*m constant), the voltage model from
    // 100 rpm on (control.handover_rpm=100), on the shipped finite split link (2 x 4.7 mF, 3.3 kOhm,
    // 25 mOhm), from standstill: 700 rpm with every compensation, 300 rpm with simple and proposed,
    // 200 rpm with proposed hold the speed within 2 % with no trip, the proposed imbalance is below
    // the simple one (margin: 3/4 of it), and the proposed scheme's estimated torque is within 3 %
    // of the true one. Measured (seed 1; imbalance none / simple / proposed): 700 rpm 193.6 / 69.2 /
    // 25.0 %, 300 rpm 110.8 / 23.4 %, 200 rpm 116.1 / 32.0 %; estimated torque 0.0903 / 0.0854 N*m
    // against 0.0902 / 0.0852 at 300 / 200 rpm (at 200 rpm the proposed imbalance is 25.9-32.0 % over
    // seeds 1-3; its cause: LowSpeedImbalanceIsTheBackEmfOnceTheDropsAreAveragedOverThePeriod). What makes the finite link pass: the low-pass
    // correction on the estimator's input (lpfcorr.h; on its output it left a DC flux error after
    // every speed change) and the restoring mid-point term scaled down with the speed (dtc.c
    // dtc_vmid_dev; a fixed 1/16 made 200 rpm limit-cycle between 40 and 240 rpm). Before both,
    // none stalled at 700 rpm, simple at 700 and 300, proposed at 300 and 200.
    const std::vector<std::string> base = {"load.type=torque", "load.torque_nm=0.075", "control.handover_rpm=100",
                                           "duration_s=2.5", "metrics_window_s=0.6"};
    auto at = [&](const char* comp, double rpm, bool target = true) {
        std::vector<std::string> s = base;
        s.push_back("control.speed_ref_rpm=" + std::to_string(rpm));
        const Outcome o = run(std::string("fstp_voltage_") + comp + "_full.toml", s);
        if (target) {
            expect_speed_held(o, rpm, 0.02, std::string(comp) + " " + std::to_string(rpm));
        } else {
            EXPECT_EQ(o.info.fault, "none") << comp << " " << rpm;
        }
        return o;
    };
    {
        const Outcome none = at("none", 700.0);
        const Outcome simple = at("simple", 700.0);
        const Outcome prop = at("proposed", 700.0);
        ASSERT_TRUE(simple.m.imbalance_pct && prop.m.imbalance_pct && none.m.imbalance_pct);
        EXPECT_LT(*prop.m.imbalance_pct, 0.5 * *simple.m.imbalance_pct);
        EXPECT_LT(*simple.m.imbalance_pct, *none.m.imbalance_pct);
    }
    for (double rpm : {300.0, 200.0}) {
        const Outcome simple = at("simple", rpm, rpm > 250.0);
        const Outcome prop = at("proposed", rpm);
        ASSERT_TRUE(simple.m.imbalance_pct && prop.m.imbalance_pct && prop.m.torque_est_mean_nm);
        EXPECT_LT(*prop.m.imbalance_pct, 0.75 * *simple.m.imbalance_pct) << rpm;
        EXPECT_NEAR(*prop.m.torque_est_mean_nm, prop.m.torque_mean_nm, 0.03 * prop.m.torque_mean_nm) << rpm;
    }
}

TEST(PmProduct, EachLowSpeedEstimatorFixMeasurablyHelps)
{
    // Each option on/off, proposed FSTP, 25 % load, voltage model from 100 rpm, finite split link:
    //   control.polarity_mid (period-mean / switching-instant current): thd40_total summed over
    //     700 / 300 / 200 rpm (a single speed's figure moves with the noise seed; the sum much less),
    //     on a stiff link: the current's harmonics are then the estimator's and the drop
    //     compensation's alone. (On the finite link the mid-point's swing at the electrical
    //     frequency dominates them below 700 rpm: thd40 sum 177 with / 184 % without, seed 1, while
    //     the imbalance sum falls from 171 to 88 %.)
    //   control.lpf_comp (low-pass gain/phase correction), finite link: the 200 rpm estimated
    //     torque within 3 % of the true one with it, more than 20 % off without it.
    // (control.dc_supp: Thd40OfTheProposedFstpWithinTheTarget.)
    const std::vector<std::string> base = {"load.type=torque", "load.torque_nm=0.075", "control.handover_rpm=100",
                                           "duration_s=2.5", "metrics_window_s=0.6"};
    auto at = [&](double rpm, const char* extra, const char* extra2 = nullptr) {
        std::vector<std::string> s = base;
        s.push_back("control.speed_ref_rpm=" + std::to_string(rpm));
        if (extra != nullptr) {
            s.push_back(extra);
        }
        if (extra2 != nullptr) {
            s.push_back(extra2);
        }
        const Outcome o = run("fstp_voltage_proposed_full.toml", s);
        EXPECT_EQ(o.info.fault, "none") << rpm << " " << (extra ? extra : "");
        return o;
    };
    double thd_on = 0.0, thd_off = 0.0;
    for (double rpm : {700.0, 300.0, 200.0}) {
        const Outcome on = at(rpm, "inverter.finite_dc_link=false");
        const Outcome off = at(rpm, "inverter.finite_dc_link=false", "control.polarity_mid=false");
        ASSERT_TRUE(on.m.thd40_total_pct && off.m.thd40_total_pct);
        thd_on += *on.m.thd40_total_pct;
        thd_off += *off.m.thd40_total_pct;
    }
    EXPECT_LT(thd_on, 0.7 * thd_off);
    const Outcome on200 = at(200.0, nullptr);
    const Outcome lpf_off = at(200.0, "control.lpf_comp=false");
    ASSERT_TRUE(on200.m.torque_est_mean_nm && lpf_off.m.torque_est_mean_nm);
    EXPECT_LT(std::fabs(*on200.m.torque_est_mean_nm - on200.m.torque_mean_nm), 0.03 * on200.m.torque_mean_nm);
    EXPECT_GT(std::fabs(*lpf_off.m.torque_est_mean_nm - lpf_off.m.torque_mean_nm), 0.2 * lpf_off.m.torque_mean_nm);
}

TEST(PmProduct, LowSpeedImbalanceIsTheBackEmfOnceTheDropsAreAveragedOverThePeriod)
{
    // Hoang Figs. 18-20 (700 and 300 rpm, 25 % load, voltage model from 100 rpm), proposed FSTP, on
    // the stiff link the paper's analysis assumes: what makes the phase currents unbalanced here.
    //  - Balanced back-EMF: balanced (<= 7 %), as the paper's figures. Measured seeds 1-3: 2.4-3.1 %
    //    at 700 rpm, 3.1-4.7 % at 300 rpm.
    //  - Table VII's back-EMF: >= 15 % (20.8-22.0 / 24.7-26.1 %): the voltage model estimates the
    //    true flux, whose PM part is unbalanced, and the DTC holds it circular, so the current
    //    carries the PM flux's negative sequence, a fixed size that is a large part of 0.6-0.8 A.
    //  - The drop compensation's polarity within a period: the 50 us ripple (0.55 A pk-pk at zero
    //    bands) crosses zero inside about a third of the periods at these currents, and a leg's
    //    drop changes by V_CE + V_d there (on legs B and C only: a negative-sequence voltage error).
    //    With the polarity of one sample per period (control.polarity_mid=false) the imbalance at
    //    300 rpm is >= 2.5 times that of the drops averaged over the period (vcomp_leg_drop_lin):
    //    18.9-21.3 % against 3.1-4.7 %.
    //  - The finite split link (2 x 4.7 mF): its mid-point swings with phase A's current and the
    //    reconstruction's restoring part leaves an inductance error l_s / 8 on phase A (dtc.c
    //    dtc_vmid_beta): balanced back-EMF on it at 700 rpm >= 1.8 times the stiff link's (7.4-8.9 %).
    const std::vector<std::string> base = {"load.type=torque", "load.torque_nm=0.075", "control.handover_rpm=100",
                                           "duration_s=2.5", "metrics_window_s=0.6"};
    const std::vector<std::string> balanced = {"motor.emf_gain=[1, 1, 1]", "motor.emf_harm_a=[0, 0, 0]",
                                               "motor.emf_harm_b=[0, 0, 0]", "motor.emf_harm_c=[0, 0, 0]"};
    auto imb = [&](double rpm, bool bal, bool stiff, bool one_sample = false) {
        std::vector<std::string> s = base;
        s.push_back("control.speed_ref_rpm=" + std::to_string(rpm));
        if (bal) {
            s.insert(s.end(), balanced.begin(), balanced.end());
        }
        if (stiff) {
            s.push_back("inverter.finite_dc_link=false");
        }
        if (one_sample) {
            s.push_back("control.polarity_mid=false");
        }
        const Outcome o = run("fstp_voltage_proposed_full.toml", s);
        EXPECT_EQ(o.info.fault, "none") << rpm;
        EXPECT_NEAR(o.m.speed_mean_rpm, rpm, 0.01 * rpm);
        return o.m.imbalance_pct ? *o.m.imbalance_pct : 1e9;
    };
    for (double rpm : {700.0, 300.0}) {
        const double bal = imb(rpm, true, true);
        EXPECT_LE(bal, 7.0) << rpm;
        EXPECT_GE(imb(rpm, false, true), 15.0) << rpm;
        if (rpm < 500.0) {
            EXPECT_GE(imb(rpm, true, true, true), 2.5 * bal) << rpm;
        } else {
            EXPECT_GE(imb(rpm, true, false), 1.8 * bal) << rpm;
        }
    }
}

TEST(PmProduct, Thd40OfTheProposedFstpWithinTheTarget)
{
    // Target: thd40_total_pct <= 10 % for the proposed FSTP at 1500 rpm full load (paper 7.16 %),
    // from standstill, for three noise seeds. Measured 8.1 / 8.4 / 8.3 % (26.2 % without the
    // ripple-robust polarity and the DC-current suppression); with control.dc_supp=false 10.7 / 10.9 /
    // 14.9 %: the DC-current suppression is what brings it below the target with a margin.
    double on = 0.0, off = 0.0;
    for (const char* seed : {"sensors.seed=1", "sensors.seed=2", "sensors.seed=3"}) {
        const Outcome o = run("fstp_voltage_proposed_full.toml", {seed});
        expect_speed_held(o, 1500.0, 0.01, seed);
        ASSERT_TRUE(o.m.thd40_total_pct);
        EXPECT_LT(*o.m.thd40_total_pct, 9.5) << seed;
        const Outcome f = run("fstp_voltage_proposed_full.toml", {seed, "control.dc_supp=false"});
        ASSERT_TRUE(f.m.thd40_total_pct);
        on += *o.m.thd40_total_pct;
        off += *f.m.thd40_total_pct;
    }
    EXPECT_LT(on, 0.92 * off);
}

TEST(PmProduct, CurrentSensorGainCornersKeepEveryVoltageModelSchemeRunning)
{
    // Datasheet-grade current sensors (gain errors +-2 %, alternating signs) from standstill: no
    // trip, 1500 rpm held within 1 %, for every voltage-model scenario. (The DC-link and
    // mid-point voltage corners are NOT met on the FSTP: docs/firmware-core.md.)
    for (const char* f : {"fstp_voltage_none_full.toml", "fstp_voltage_simple_full.toml",
                          "fstp_voltage_proposed_full.toml", "sstp_voltage_none_full.toml",
                          "sstp_voltage_simple_full.toml"}) {
        for (const char* g : {"sensors.current_gain_error=[0.02,-0.02,0.02]",
                              "sensors.current_gain_error=[-0.02,0.02,-0.02]"}) {
            expect_speed_held(run(f, {g}), 1500.0, 0.01, std::string(f) + " " + g);
        }
    }
}

TEST(PmProduct, FstpVoltageSensorCornersKeepRunningOnTheStiffLink)
{
    // Realistic sensors on the FSTP (stiff split link; the shipped scenarios' finite link
    // below, FiniteSplitLinkKeepsTheTableIxOrdering): DC-link gain
    // +-2 %, DC-link offset +-1 V, mid-point offset +-0.5 V, from standstill: no trip, 1500 rpm
    // held within 1 %, for none / simple / proposed. Without the limit and the calibration: over-current in every
    // corner (a stall with the current limit alone); the mid-point calibration (control.vmid_cal) is what
    // makes them run: with it off the proposed scheme stalls at +2 % link gain.
    for (const char* f : {"fstp_voltage_none_full.toml", "fstp_voltage_simple_full.toml",
                          "fstp_voltage_proposed_full.toml"}) {
        for (const char* c : {"sensors.vdc_gain_error=0.02", "sensors.vdc_gain_error=-0.02", "sensors.vdc_offset_v=1",
                              "sensors.vdc_offset_v=-1", "sensors.vmid_offset_v=0.5", "sensors.vmid_offset_v=-0.5"}) {
            expect_speed_held(run(f, {c, "inverter.finite_dc_link=false"}), 1500.0, 0.01, std::string(f) + " " + c);
        }
    }
    const Outcome off = run("fstp_voltage_proposed_full.toml", {"sensors.vdc_gain_error=0.02", "control.vmid_cal=false",
                                                                "inverter.finite_dc_link=false"});
    EXPECT_NE(off.info.fault, "none");
}

TEST(PmProduct, FiniteSplitLinkKeepsTheTableIxOrdering)
{
    // The shipped FSTP scenarios run on finite split capacitors (4.7 mF each,
    // 3.3 kohm balancing resistors, 25 mohm ESR: docs/plant.md) from standstill, with the
    // DC-current suppression and the mid-point regulation (control.dc_supp): no trip, 1500 rpm
    // held, imbalance none > simple > proposed, proposed <= 8 % and thd40 <= 10 %. Measured
    // (seed 1) 59.6 / 19.2 / 6.8 %, thd40 8.4 %. And every realistic-sensor corner, for every
    // FSTP scheme: mid-point offset +-0.5 V, DC-link gain +-2 %, offset +-1 V. Before the
    // restoring mid-point reconstruction (firmware/dtc/dtc.c dtc_vmid_dev) the link read low
    // (-2 %, -1 V) stalled all three schemes at 30-40 rpm: the mid-point ran away (an unstable
    // mid-point / estimator loop).
    const std::vector<std::string> fin = {"inverter.finite_dc_link=true"};
    auto with = [&](std::vector<std::string> v, const char* extra) {
        if (extra != nullptr) {
            v.push_back(extra);
        }
        return v;
    };
    const Outcome none = run("fstp_voltage_none_full.toml", fin);
    const Outcome simple = run("fstp_voltage_simple_full.toml", fin);
    const Outcome prop = run("fstp_voltage_proposed_full.toml", fin);
    expect_speed_held(none, 1500.0, 0.01, "none finite");
    expect_speed_held(simple, 1500.0, 0.01, "simple finite");
    expect_speed_held(prop, 1500.0, 0.01, "proposed finite");
    ASSERT_TRUE(none.m.imbalance_pct && simple.m.imbalance_pct && prop.m.imbalance_pct && prop.m.thd40_total_pct);
    EXPECT_GT(*none.m.imbalance_pct, *simple.m.imbalance_pct);
    EXPECT_GT(*simple.m.imbalance_pct, *prop.m.imbalance_pct);
    EXPECT_LE(*prop.m.imbalance_pct, 8.0);
    EXPECT_LE(*prop.m.thd40_total_pct, 10.0);
    for (const char* f : {"fstp_voltage_none_full.toml", "fstp_voltage_simple_full.toml",
                          "fstp_voltage_proposed_full.toml"}) {
        for (const char* c : {"sensors.vmid_offset_v=0.5", "sensors.vmid_offset_v=-0.5",
                              "sensors.vdc_gain_error=0.02", "sensors.vdc_gain_error=-0.02",
                              "sensors.vdc_offset_v=1", "sensors.vdc_offset_v=-1"}) {
            expect_speed_held(run(f, with(fin, c)), 1500.0, 0.01, std::string(f) + " " + c);
        }
    }
}

TEST(PmProduct, SstpVoltageCornersKeepRunning)
{
    // SSTP (none, [29]): DC-link gain +-2 %, offset +-1 V from standstill: no trip, 1500 rpm held.
    for (const char* f : {"sstp_voltage_none_full.toml", "sstp_voltage_simple_full.toml"}) {
        for (const char* c : {"sensors.vdc_gain_error=0.02", "sensors.vdc_gain_error=-0.02",
                              "sensors.vdc_offset_v=1", "sensors.vdc_offset_v=-1"}) {
            expect_speed_held(run(f, {c}), 1500.0, 0.01, std::string(f) + " " + c);
        }
    }
}

TEST(PmProduct, BadCurrentLimitIsRefusedNamingTheKey)
{
    sil_test::expect_refused("fstp_voltage_proposed_full.toml", {"control.current_limit_a=-1"},
                             "control.current_limit_a");
    // at or above the trip: refused by the converter (the scenario check runs it), naming the key
    // and where it was set
    sil_test::expect_refused("fstp_voltage_proposed_full.toml", {"control.current_limit_a=6"},
                             "--set #1 'control.current_limit_a=6': control.current_limit_a: current_limit_a = 6");
}
