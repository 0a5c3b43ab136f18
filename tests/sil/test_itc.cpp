// test_itc.cpp - the PM indirect torque control (control.scheme = "itc", firmware/dtc/itc.h) on
// the SIL: the current-controlled drive Hoang et al. set beside DTC (Figs. 5-8 (a)). Targets:
// from standstill (J = 5e-4 kg m^2, the shipped finite split link), with the generator load and a
// constant 0.3 N*m, 1500 rpm within 1 % on the FSTP and the SSTP with no trip; at full load the
// current imbalance and THD (harmonics 2..40) <= 5 %; the same on a machine other than Table
// VIII's with the gains derived by the converter; the voltage-model estimator running beside it
// as an observer (it does not touch the currents, and its compensations order as in Figs. 5-7 (a)).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

extern "C" {
#include "law.h" /* law_check: C linkage */
}
#include "dtc_config_si.h"
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

// No trip, mean speed within tol, every sample of the window within 2 tol; at full load the
// imbalance and THD40 at most 5 %.
void expect_target(const Outcome& o, const std::string& what)
{
    ASSERT_EQ(o.info.fault, "none") << what;
    const auto& v = o.series.speed_rpm;
    ASSERT_GT(v.size(), 100u) << what;
    EXPECT_NEAR(o.m.speed_mean_rpm, 1500.0, 0.01 * 1500.0) << what;
    const auto mm = std::minmax_element(v.begin(), v.end());
    EXPECT_GT(*mm.first, 1500.0 * 0.98) << what;
    EXPECT_LT(*mm.second, 1500.0 * 1.02) << what;
    ASSERT_TRUE(o.m.imbalance_pct.has_value()) << what;
    ASSERT_TRUE(o.m.thd40_total_pct.has_value()) << what;
    EXPECT_LE(*o.m.imbalance_pct, 5.0) << what;
    EXPECT_LE(*o.m.thd40_total_pct, 5.0) << what;
    std::printf("  %-34s speed %.1f rpm, imbalance %.2f %%, THD40 %.2f %%\n", what.c_str(), o.m.speed_mean_rpm,
                *o.m.imbalance_pct, *o.m.thd40_total_pct);
}

// A surface PM machine other than Table VIII's: two pole pairs, a third less magnet flux per pole
// pair, 0.8 ohm, 2 mH, balanced back-EMF; rated 0.3 N*m at 2.22 A (T = 3/2 p psi_m i). 1500 rpm
// is 14.1 V of back-EMF, within the FSTP's V_dc / (2 sqrt3) = 20.2 V.
const std::vector<std::string> kOtherMachine = {
    "motor.pole_pairs=2", "motor.psi_m_wb=0.045", "motor.ls_h=2.0e-3", "motor.rs_ohm=0.8",
    "motor.rated_current_a=2.25", "motor.emf_gain=[1.0,1.0,1.0]", "motor.emf_harm_a=[0.0,0.0,0.0]",
    "motor.emf_harm_b=[0.0,0.0,0.0]", "motor.emf_harm_c=[0.0,0.0,0.0]", "control.flux_ref_wb=0.045"};

std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string>& b)
{
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

// Amplitudes of the fundamental of two signals over the whole periods of the metrics window
// (projection onto cos/sin of the currents' fundamental angle).
void fundamentals(const Outcome& o, const std::vector<double>& x, const std::vector<double>& y, double* ax, double* ay)
{
    const std::size_t n = static_cast<std::size_t>(0.4 / o.series.ts_s);
    const Window w = whole_period_window(o.series.theta_fund_rad, n);
    double xc = 0, xs = 0, yc = 0, ys = 0;
    for (std::size_t k = w.begin; k < w.begin + w.n; ++k) {
        const double th = o.series.theta_fund_rad[k];
        xc += x[k] * std::cos(th);
        xs += x[k] * std::sin(th);
        yc += y[k] * std::cos(th);
        ys += y[k] * std::sin(th);
    }
    *ax = 2.0 * std::hypot(xc, xs) / static_cast<double>(w.n);
    *ay = 2.0 * std::hypot(yc, ys) / static_cast<double>(w.n);
}

} // namespace

TEST(Itc, TableViiiMachineReaches1500rpmOnBothInvertersWithBothLoads)
{
    // Measured: 1499.8-1499.9 rpm; FSTP imbalance 2.8 / 2.5 %, THD40 1.5 / 1.4 %; SSTP 0.3 / 0.3 %,
    // 1.7 / 1.4 % (generator / constant 0.3 N*m plus the rig's friction).
    for (const char* f : {"fstp_itc_full.toml", "sstp_itc_full.toml"}) {
        expect_target(run(f), std::string(f) + " generator");
        expect_target(run(f, {"load.type=torque", "load.torque_nm=0.3"}), std::string(f) + " 0.3 N*m");
    }
}

TEST(Itc, AnotherMachineReachesTheTargetsWithDerivedGains)
{
    // The same targets on the two-pole-pair machine above, nothing tuned: the converter derives
    // the current-loop gains (K_p = L_s w_c, K_i = R_s w_c, w_c = pi / (9 Ts)), i_q* per torque
    // (1 / psi_m) and the FSTP mid-point regulation (2 C w_m, w_m from the rated speed and the pole
    // pairs). Measured: FSTP imbalance 3.2 / 2.8 %, THD40 1.3 / 1.1 %; SSTP 0.06 / 0.06 %,
    // 1.3 / 1.1 %.
    for (const char* f : {"fstp_itc_full.toml", "sstp_itc_full.toml"}) {
        expect_target(run(f, kOtherMachine), std::string(f) + " other machine, generator");
        expect_target(run(f, with(kOtherMachine, {"load.type=torque", "load.torque_nm=0.3"})),
                      std::string(f) + " other machine, 0.3 N*m");
    }
}

TEST(Itc, GainsAreDerivedFromTheMachineAndTheControlPeriod)
{
    // K_p = L_s w_c and K_i Ts = R_s w_c Ts in pu (Z_base = V_base / I_base), w_c = pi / (9 Ts):
    // 60 deg of phase margin against the 1.5 Ts loop delay; i_q* per unit torque = 1 / psi_m.
    for (double ls : {3.19e-3, 2.0e-3}) {
        dtc_config_si_t si;
        dtc_config_si_defaults(&si);
        si.law = DTC_LAW_PM_ITC;
        si.ls_h = ls;
        si.fstp_vmid_measured = 1; /* the mid-point regulation's gains are derived with it */
        dtc_config_t cfg;
        char msg[256];
        ASSERT_EQ(dtc_config_from_si(&si, &cfg, msg, sizeof msg), DTC_SI_OK) << msg;
        dtc_bases_t b;
        dtc_bases_from_si(&si, &b);
        const double wc = M_PI / (9.0 * si.ts_s);
        EXPECT_DOUBLE_EQ(dtc_itc_wc_rad_s(&si), wc);
        EXPECT_EQ(cfg.u.pm_itc.part, DTC_PART_PM_ITC);
        EXPECT_NEAR(cfg.u.pm_itc.cc.kp_iq / 16777216.0, ls * wc / b.z_base_ohm, 1e-6);
        EXPECT_NEAR(cfg.u.pm_itc.cc.ki_ts_iq / 16777216.0, si.rs_ohm * wc * si.ts_s / b.z_base_ohm, 1e-6);
        EXPECT_NEAR(cfg.u.pm_itc.cc.iq_per_t_iq / 16777216.0, b.psi_base_wb / si.psi_m_wb, 1e-6);
        // FSTP with the mid-point measured: g = 2 C w_m, k_f = 4 w_m Ts, w_m the
        // electrical speed at half the rated speed over 20
        ASSERT_EQ(si.topology, DTC_TOPO_FSTP);
        const double wm = 0.5 * si.rated_speed_rpm * M_PI / 30.0 * si.pole_pairs / 20.0;
        EXPECT_DOUBLE_EQ(dtc_itc_vmid_wm_rad_s(&si), wm);
        EXPECT_NEAR(cfg.u.pm_itc.mid.g_iq / 16777216.0, 2.0 * si.c_dc_f * wm * b.z_base_ohm, 1e-6);
        EXPECT_NEAR(cfg.u.pm_itc.mid.kf_iq / 16777216.0, 4.0 * wm * si.ts_s, 1e-6);
    }
}

TEST(Itc, TheEstimatorIsAnObserverAndItsCompensationsOrderAsInFigs5To8)
{
    // Under ITC the currents do not depend on the estimator's compensation (it is not in the
    // control path): the same imbalance to 0.01 % with none, simple (Table V) and proposed
    // (Table VI). The estimate does: its error against the plant's flux falls none > simple >
    // proposed, the estimated torque is above the true one without compensation (Hoang sec. IV:
    // the drops neglected make the flux and torque look larger) and within 1 % of it with the
    // proposed scheme, and the imbalance of the alpha/beta fundamentals of the estimated flux falls
    // from no compensation (Fig. 5 (a)) through the simple scheme (Fig. 6 (a)) to the proposed one
    // (Fig. 7 (a)), the current model balanced by construction (Fig. 8 (a)). Measured: flux error
    // 7.5 / 2.1 / 1.6 %, torque estimate 0.320 / 0.305 / 0.301 N*m against 0.300 N*m, alpha/beta
    // imbalance 7.6 / 2.9 / 1.3 / 0.07 %.
    const Outcome none = run("fstp_itc_full.toml", {"control.compensation=none"});
    const Outcome simple = run("fstp_itc_full.toml", {"control.compensation=simple"});
    const Outcome prop = run("fstp_itc_full.toml", {"control.compensation=proposed"});
    const Outcome cur = run("fstp_itc_full.toml", {"control.estimator=current", "control.compensation=none"});
    for (const Outcome* o : {&none, &simple, &prop, &cur}) {
        ASSERT_EQ(o->info.fault, "none");
        ASSERT_TRUE(o->m.imbalance_pct.has_value());
    }
    EXPECT_NEAR(*none.m.imbalance_pct, *prop.m.imbalance_pct, 0.01);
    EXPECT_NEAR(*simple.m.imbalance_pct, *prop.m.imbalance_pct, 0.01);
    ASSERT_TRUE(none.m.flux_est_error_rms_pct && simple.m.flux_est_error_rms_pct && prop.m.flux_est_error_rms_pct);
    EXPECT_GT(*none.m.flux_est_error_rms_pct, *simple.m.flux_est_error_rms_pct);
    EXPECT_GT(*simple.m.flux_est_error_rms_pct, *prop.m.flux_est_error_rms_pct);
    ASSERT_TRUE(none.m.torque_est_mean_nm && prop.m.torque_est_mean_nm);
    EXPECT_GT(*none.m.torque_est_mean_nm, none.m.torque_mean_nm * 1.03);
    EXPECT_NEAR(*prop.m.torque_est_mean_nm, prop.m.torque_mean_nm, 0.01 * prop.m.torque_mean_nm);
    double imb[4];
    int k = 0;
    for (const Outcome* o : {&none, &simple, &prop, &cur}) {
        double aa, ab;
        fundamentals(*o, o->series.psi_a_est, o->series.psi_b_est, &aa, &ab);
        imb[k] = 200.0 * std::fabs(aa - ab) / (aa + ab);
        std::printf("  estimated flux alpha %.4f Wb, beta %.4f Wb: alpha/beta imbalance %.2f %%\n", aa, ab, imb[k]);
        k++;
    }
    EXPECT_GT(imb[0], imb[1]);
    EXPECT_GT(imb[1], imb[2]);
    EXPECT_GT(imb[2], imb[3]);
    EXPECT_LT(imb[2], 2.0);
    EXPECT_LT(imb[3], 0.5);
}

TEST(Itc, BadInputIsRefusedByName)
{
    // control.scheme = "itc" is the PM machine's; the IM machine refuses it by its key, and the
    // PM machine refuses the IM schemes.
    sil_test::expect_refused("im_dtc_speed.toml", {"control.scheme=itc"}, "control.scheme");
    sil_test::expect_refused("fstp_itc_full.toml", {"control.scheme=dfoc"}, "control.scheme");
    // A configuration whose law is the ITC but whose part is the PM DTC law's (relabelled) is
    // refused by the law's check with the part named, and the reverse.
    dtc_config_si_t si;
    dtc_config_si_defaults(&si);
    dtc_config_t cfg;
    char msg[256];
    ASSERT_EQ(dtc_config_from_si(&si, &cfg, msg, sizeof msg), DTC_SI_OK) << msg;
    cfg.law = DTC_LAW_PM_ITC;
    const char* field = nullptr;
    EXPECT_EQ(law_check(&cfg, &field), DTC_ERR_PART);
    ASSERT_NE(field, nullptr);
    EXPECT_EQ(std::string(field), "u.pm_itc.part");
    si.law = DTC_LAW_PM_ITC;
    ASSERT_EQ(dtc_config_from_si(&si, &cfg, msg, sizeof msg), DTC_SI_OK) << msg;
    EXPECT_EQ(law_check(&cfg, &field), DTC_OK) << field;
    cfg.law = DTC_LAW_PM_DTC;
    EXPECT_EQ(law_check(&cfg, &field), DTC_ERR_PART);
    EXPECT_EQ(std::string(field), "u.pm_dtc.part");
    // An ITC part without a current-regulator gain: DTC_ERR_SVM, the gain named.
    cfg.law = DTC_LAW_PM_ITC;
    cfg.u.pm_itc.cc.kp_iq = 0;
    EXPECT_EQ(law_check(&cfg, &field), DTC_ERR_SVM);
    EXPECT_EQ(std::string(field), "u.pm_itc.cc.kp_iq");
    // The converter refuses the induction machine's fields with the ITC, naming the field.
    si.lm_h = 0.1;
    EXPECT_NE(dtc_config_from_si(&si, &cfg, msg, sizeof msg), DTC_SI_OK);
    EXPECT_NE(std::string(msg).find("lm_h"), std::string::npos) << msg;
}
