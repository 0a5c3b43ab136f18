// The induction-machine control law (firmware/dtc/im_dtc.h) in closed loop with the plant's
// default induction machine (plant_params_im_default: 4 kW, 4 poles, 220 V; SSTP on 311 V with
// the plant's device drops and dead time, 40 us) through hal_host and the unchanged application
// (app_init / app_isr), the law configured directly in C from the converter's IM defaults (no
// scenario keys yet). From standstill the machine is magnetised at zero torque, then a rated
// torque step is commanded (Casadei Fig. 17b, at constant rotor flux, eq. 19); two cases below
// (rotor held with real parts; rotor free with ideal devices), and a flying start into a rotor
// the dynamometer turns (at the end of the file). Assertions are physics on the
// plant's true quantities:
//   - during the magnetisation the torque is zero and the phase currents are DC;
//   - when the torque is allowed the rotor flux is at least magn_frac of its reference, and
//     0.4 s (3 tau_r) later within 3 % of it;
//   - after the step the torque reaches 90 % of T* within 5 ms and its mean over the next 30 ms
//     is within 10 % of T*; in the ideal-device case the rotor-flux magnitude stays within 3 % of
//     phi_r* (Casadei eq. 19);
//   - no fault.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

extern "C" {
#include "app.h"
#include "dtc_config_si.h"
}

#include "firmware_si.hpp"
#include "hal_host.hpp"
#include "plant.h"
#include "scenario_outcome.hpp"

namespace {

struct ImRig {
    plant_params_t p{};
    dtc_config_si_t si{};
    dtc_config_t cfg{};
    std::unique_ptr<hal_host::Harness> h;

    // held_rpm: the rotor's speed at the start, at which the dynamometer holds it (free_rotor:
    // inertia only, no dynamometer); paper: Casadei eq. 20's reference at every speed (the
    // converter's default with the encoder pulls it towards the current model at low speed, im_sup.h)
    ImRig(bool ideal, bool free_rotor, double held_rpm = 0.0, int law = DTC_LAW_IM_DTC, bool paper = false)
    {
        plant_params_default(&p);
        plant_params_im_default(&p);
        p.vdc_v = 311.0;
        p.load = PLANT_LOAD_SPEED;
        p.load_speed_rpm = held_rpm;
        p.speed0_rpm = held_rpm;
        p.max_step_s = 40e-6;
        if (ideal) {
            p.drops_enabled = 0;
            p.dead_time_enabled = 0;
        }
        if (free_rotor) {
            p.load = PLANT_LOAD_INERTIA;
        }

        dtc_config_si_im_defaults(&si);
        if (paper) {
            si.cm_ref = 0;
        }
        si.mode = DTC_MODE_TORQUE;
        si.torque_ref_nm = 0.0;
        si.psir_ref_wb = 0.53;     // about the no-load rotor flux of 0.55 Wb stator flux
        si.law = law;
        si.v_ce_v = p.v_ce_v;      // the board's devices, as the firmware is told them
        si.v_d_v = p.v_d_v;
        si.v_f_v = 0.5 * (p.v_ce_v + p.v_d_v);
        si.r_on_ohm = p.r_on_ohm;
        si.dead_time_s = p.dead_time_s;
        if (ideal) {
            si.compensation = DTC_COMP_NONE;
            si.deadtime_comp = 0;
        }

        hal_host::HarnessConfig hc;
        hc.ts_s = si.ts_s;
        hc.sensors.current_range_a = 200.0;
        hc.sensors.voltage_range_v = 500.0;
        hc.sensors.encoder_lines = static_cast<std::uint32_t>(si.enc_lines);
        si.adc_i_a_per_count = hc.sensors.current_range_a / 2047.5; // hal_host's ADC model
        si.adc_vdc_v_per_count = hc.sensors.voltage_range_v / 4095.0;
        si.adc_vmid_v_per_count = hc.sensors.voltage_range_v / 4095.0;

        char msg[256] = {0};
        EXPECT_EQ(dtc_config_from_si(&si, &cfg, msg, sizeof msg), DTC_SI_OK) << msg;
        std::string err;
        h = hal_host::Harness::create(p, hc, &err);
        EXPECT_TRUE(h) << err;
        h->activate();
        hal_init();
        EXPECT_EQ(app_init(&cfg), 0);
    }
    ~ImRig() { h->deactivate(); }

    void period()
    {
        h->run_period([] {
            app_isr();
            app_background();
        });
    }
    app_status_t status() const
    {
        app_status_t s;
        app_get_status(&s);
        return s;
    }
    double psir_wb() const { return std::hypot(h->state().psi_r_alpha_wb, h->state().psi_r_beta_wb); }
};

// Torque mode at t_nm through the background's shadow set; returns app_set_refs' code.
int command_torque(const ImRig& r, double t_nm)
{
    dtc_refs_t refs{};
    refs.mode = DTC_MODE_TORQUE;
    refs.flux_ref_iq = r.cfg.speed.flux_ref_iq;
    refs.speed_ref_iq = 0;
    refs.kp_iq = r.cfg.speed.kp_iq;
    refs.ki_ts_iq = r.cfg.speed.ki_ts_iq;
    refs.torque_ref_iq = static_cast<iq_t>(std::lround(t_nm / (1.5 * r.si.pole_pairs *
        (r.si.v_base_v / r.si.w_base_rad_s) * r.si.i_base_a) * 16777216.0));
    return app_set_refs(&refs);
}

// Magnetisation at standstill, then a rated torque step; check_psir: assert the rotor flux's
// constancy (Casadei eq. 19) through the step.
void run_case(ImRig& r, bool check_psir)
{
    ASSERT_TRUE(r.h);
    const double ts = r.si.ts_s;
    const double t_rated = r.si.rated_torque_nm;
    const double psir_ref = r.si.psir_ref_wb;
    const long n_magn = static_cast<long>(r.cfg.u.im.ref.magn_periods);

    // Calibration (64 periods, app_core.h), then the magnetisation: T* = 0 whatever is commanded.
    app_status_t st{};
    long k = 0;
    for (; k < 200; ++k) {
        r.period();
    }
    st = r.status();
    ASSERT_EQ(st.state, APP_STATE_RUN) << app_fault_name(st.fault);
    dtc_refs_t refs{};
    ASSERT_EQ(app_set_refs(&refs), DTC_ERR_REFERENCE); // a zero flux reference is refused
    double worst_te = 0.0, ang0 = 0.0;
    const long k_end = n_magn + 64 - 5; // a few periods before the torque is allowed
    for (; k < k_end; ++k) {
        r.period();
        worst_te = std::fmax(worst_te, std::fabs(r.h->state().te_nm));
        if (k == k_end - static_cast<long>(5e-3 / ts)) {
            ang0 = std::atan2(r.h->state().i_beta_a, r.h->state().i_alpha_a);
        }
    }
    st = r.status();
    ASSERT_EQ(st.fault, APP_FAULT_NONE) << app_fault_name(st.fault);
    EXPECT_EQ(st.out.te_ref_iq, 0);
    EXPECT_LT(worst_te, 0.03 * t_rated); // zero torque while magnetising
    const double ang1 = std::atan2(r.h->state().i_beta_a, r.h->state().i_alpha_a);
    EXPECT_LT(std::fabs(ang1 - ang0), 0.02); // DC magnetising current: the vector stands still
    EXPECT_GE(r.psir_wb(), r.si.magn_frac * psir_ref);
    EXPECT_LE(r.psir_wb(), 1.03 * psir_ref);

    // Torque allowed (still commanded zero): the rotor flux completes its rise with tau_r
    // (0.128 s, im_dtc.h); 0.4 s later it is at its reference, as in Casadei Figs. 14-15 before the step.
    for (long j = 0; j < static_cast<long>(0.4 / ts); ++j, ++k) {
        r.period();
    }
    if (check_psir) {
        EXPECT_LT(std::fabs(r.psir_wb() / psir_ref - 1.0), 0.03);
    }
    // Rated torque commanded through the background's shadow set.
    ASSERT_EQ(command_torque(r, t_rated), DTC_OK);
    long reached = -1;
    double worst_psir = 0.0, te_sum = 0.0;
    long n_mean = 0;
    const long n_step = static_cast<long>(40e-3 / ts);
    for (long j = 0; j < n_step; ++j) {
        r.period();
        const double te = r.h->state().te_nm;
        if (reached < 0 && te >= 0.9 * t_rated) {
            reached = j;
        }
        worst_psir = std::fmax(worst_psir, std::fabs(r.psir_wb() / psir_ref - 1.0));
        if (j >= static_cast<long>(10e-3 / ts)) {
            te_sum += te;
            ++n_mean;
        }
    }
    st = r.status();
    EXPECT_EQ(st.fault, APP_FAULT_NONE) << app_fault_name(st.fault);
    ASSERT_GE(reached, 0);
    EXPECT_LE(reached * ts, 5e-3);
    EXPECT_LT(std::fabs(te_sum / n_mean / t_rated - 1.0), 0.10);
    if (check_psir) {
        EXPECT_LT(worst_psir, 0.03);
    }
    ::testing::Test::RecordProperty("torque_rise_ms", std::to_string(reached * ts * 1e3));
    ::testing::Test::RecordProperty("torque_mean_nm", std::to_string(te_sum / n_mean));
    ::testing::Test::RecordProperty("psir_worst_pct", std::to_string(100.0 * worst_psir));
    std::printf("MEASURE rise %.2f ms, mean torque %.2f N*m (T* %.2f), rotor flux worst %.1f %% of %.2f Wb\n",
                reached * ts * 1e3, te_sum / n_mean, t_rated, 100.0 * worst_psir, psir_ref);
}

} // namespace

// Realistic parts (the plant's device drops and dead time, the firmware's SSTP drop [29] and
// dead-time compensation), rotor held at standstill by the dynamometer: zero torque and a DC
// current while magnetising, the rotor flux built, then the torque step tracked. The rotor flux
// through the step is measured, not asserted: at standstill under rated torque the stator
// frequency is the slip frequency (13 rad/s, below 1/tau = 100 rad/s) and the residual error of
// the drop compensation moves the machine's rotor flux by about 14 % (ideal devices: 3.6 %);
// a finding reported in docs/firmware-core.md.
TEST(ImLaw, StandstillRealPartsMagnetisesThenTracksATorqueStep)
{
    ImRig r(false, false);
    ASSERT_TRUE(r.h);
    run_case(r, false);
}

// The conditions of Casadei Figs. 14-15 (constant rotor flux through a torque step), the rotor
// free (inertia only) so that it accelerates from standstill under the step, ideal devices (no
// drops, no dead time; the firmware's compensation off) so that the law is judged without the
// inverter's voltage errors, which those figures do not show: the rotor flux stays within 3 % of
// phi_r* through the step (the paper: 2 %). Both estimators: the product's (with the encoder,
// Casadei eq. 20 pulled towards the rotor-flux current model at low speed, im_sup.h; measured
// 0.9 %) and the paper's (eq. 20's reference at every speed; 2.0 %). The rotor accelerates at
// about 19,000 rpm/s, through the current model's blend (136 to 272 rpm) within 7 ms: the model
// turns by the encoder's count step of each period; turned by the speed of the speed period (a
// mean over up to 16 of them) it lagged the rotor, and the machine's rotor flux moved 4.9 %.
TEST(ImLaw, FreeRotorIdealInverterKeepsRotorFluxThroughATorqueStep)
{
    for (const bool paper : {false, true}) {
        SCOPED_TRACE(paper ? "the paper's estimator" : "the product's estimator (current model at low speed)");
        ImRig r(true, true, 0.0, DTC_LAW_IM_DTC, paper);
        ASSERT_TRUE(r.h);
        run_case(r, true);
    }
}

namespace {

// A flying start: the dynamometer turns the rotor at held_rpm from before the drive is enabled
// (realistic parts, the encoder). Magnetising with a stationary flux would be DC injection into a
// turning rotor: the machine's rotor flux would stay far below the ramp the estimator's
// reference assumes, and the estimate would settle on a flux the machine does not have (with a
// stationary magnetising flux at 300 rpm the machine gives -7.3 N*m for T* = 26.5 while the
// estimate reads 26.5).
// Asserted on the plant's true quantities: no fault; the mean torque while magnetising is against
// the motion and below 20 % of rated (the zero band with the period's delay leaves the bang-bang
// torque below T* = 0 by part of its ripple, which grows with the speed: measured 2 % of rated at
// 300 rpm, 15 % at 1440 rpm); the rotor flux is built; then the rated torque step is tracked
// (mean within 10 % of T*).
void run_flying(double held_rpm, int scheme)
{
    ImRig r(false, false, held_rpm, scheme);
    ASSERT_TRUE(r.h);
    const double ts = r.si.ts_s;
    const double t_rated = r.si.rated_torque_nm;
    const double psir_ref = r.si.psir_ref_wb;
    const long n_on = static_cast<long>(r.cfg.u.im.ref.magn_periods) + 64; // calibration + magnetisation
    double te_sum = 0.0;
    long n = 0;
    for (long k = 0; k < n_on + static_cast<long>(0.4 / ts); ++k) {
        r.period();
        if (k >= 200 && k < n_on) {
            te_sum += r.h->state().te_nm;
            ++n;
        }
    }
    app_status_t st = r.status();
    ASSERT_EQ(st.fault, APP_FAULT_NONE) << app_fault_name(st.fault);
    const double te_magn = te_sum / static_cast<double>(n);
    EXPECT_LT(std::fabs(te_magn), 0.20 * t_rated);
    EXPECT_LE(te_magn * held_rpm, 0.0); // against the motion, if anything
    EXPECT_LT(std::fabs(r.psir_wb() / psir_ref - 1.0), 0.05);

    ASSERT_EQ(command_torque(r, t_rated), DTC_OK);
    double sum = 0.0;
    long m = 0;
    for (long j = 0; j < static_cast<long>(40e-3 / ts); ++j) {
        r.period();
        if (j >= static_cast<long>(10e-3 / ts)) {
            sum += r.h->state().te_nm;
            ++m;
        }
    }
    st = r.status();
    EXPECT_EQ(st.fault, APP_FAULT_NONE) << app_fault_name(st.fault);
    EXPECT_LT(std::fabs(sum / m / t_rated - 1.0), 0.10);
    std::printf("MEASURE flying start (scheme %d) at %.0f rpm: mean torque %.2f N*m while magnetising, rotor flux %.3f Wb (ref %.2f), "
                "then %.2f N*m for T* %.2f\n",
                scheme, held_rpm, te_magn, r.psir_wb(), psir_ref, sum / m, t_rated);
}

} // namespace

TEST(ImLaw, FlyingStartIntoATurningRotorBuildsTheFluxThenTracksTorque)
{
    // the switching-table DTC both ways, and DSVM (its own start-up code, im_dsvm.c)
    const struct { double rpm; int scheme; } cases[] = {
        {300.0, DTC_LAW_IM_DTC}, {-1440.0, DTC_LAW_IM_DTC}, {1440.0, DTC_LAW_IM_DSVM}};
    for (const auto& c : cases) {
        SCOPED_TRACE(c.rpm);
        SCOPED_TRACE(c.scheme);
        run_flying(c.rpm, c.scheme);
    }
}

// ---- The torque room (tools/config dtc_im_torque_room_check) ----
// The second machine (im_second_machine.toml: 30 A trip, 565 V) with DFOC at 160 us and its
// current PIs' poles placed (control.dfoc_zeta = 0.7: the PI's zero near w_c, the step overshoots,
// so its excursion above the held current is a whole dI, dtc_im_hold_margin_a) holds its steady
// current at I_trip - 3 dI = 10.6 A (dI = Ts (V_max + R_s I_trip)/(sigma L_s) = 6.46 A), below the
// 11.0 A its rated torque needs: the converter's check says so and gives the longest period and
// the lowest trip level that would carry the rated torque. The shipped DFOC (dfoc_zeta = 0, the
// first-order loops with the anti-windup: no overshoot) and the SFVC hold I_trip - 2 dI less
// their SVM ripple, V_max Ts / (4 sigma L_s) = 1.31 A: 15.8 A, room enough. Asserted: the warning
// for the placed-pole DFOC at 160 us, none for the shipped DFOC and SFVC at 160 us, DTC at 40 us
// nor the 4 kW IM's SFVC and DFOC; each suggestion, applied alone (0.1 % inside it), gives a
// torque limit at or above the rated torque and silences the check, and 1 % outside it does not
// (the suggestion is the bound, not a guess).
// The firmware's SI configuration of the shipped scenario `file` with the scheme `scheme`.
static dtc_config_si_t shipped_si(const char* file, const char* scheme, const char* extra = nullptr)
{
    sil::Scenario sc;
    sil::Diagnostics d;
    std::vector<std::string> sets = {std::string("control.scheme=") + scheme};
    if (extra != nullptr) {
        sets.emplace_back(extra);
    }
    EXPECT_TRUE(sil::load_scenario(sil_test::scenarios_dir() + file, sets, &sc, &d)) << d.text();
    return sil::firmware_si_config(sc);
}

static double room_torque(const dtc_config_si_t& si)
{
    return dtc_im_torque_at_current_nm(&si, dtc_ilim_default_a(&si) - dtc_im_hold_margin_a(&si));
}

TEST(ImLaw, TorqueRoomCheckNamesThePeriodAndTripThatCarryTheRatedTorque)
{
    char msg[600];
    for (const char* law : {"dfoc"}) {
        const dtc_config_si_t si = shipped_si("im_second_machine.toml", law, "control.dfoc_zeta=0.7");
        const double t_rated = si.rated_torque_nm;
        ASSERT_EQ(dtc_im_torque_room_check(&si, msg, sizeof msg), 1);
        std::printf("MEASURE second machine, %s, %.0f us: %s\n", law, 1e6 * si.ts_s, msg);
        EXPECT_LT(room_torque(si), t_rated);
        const char* at = std::strstr(msg, "ts_s <= ");
        ASSERT_NE(at, nullptr);
        double ts_max = 0.0, trip_min = 0.0;
        ASSERT_EQ(std::sscanf(at, "ts_s <= %lf s or i_trip_a >= %lf A", &ts_max, &trip_min), 2) << msg;
        // the suggestion applied alone: `inside` times it carries the rated torque and silences the
        // check, `outside` times it does not
        const auto bound = [&](double dtc_config_si_t::*key, double value, double inside, double outside) {
            dtc_config_si_t x = si;
            x.*key = inside * value;
            EXPECT_GE(room_torque(x), t_rated);
            EXPECT_EQ(dtc_im_torque_room_check(&x, msg, sizeof msg), 0);
            x.*key = outside * value;
            EXPECT_LT(room_torque(x), t_rated);
        };
        bound(&dtc_config_si_t::ts_s, ts_max, 0.999, 1.01);
        bound(&dtc_config_si_t::i_trip_a, trip_min, 1.001, 0.99);
    }
    const dtc_config_si_t sfvc = shipped_si("im_second_machine.toml", "sfvc");
    EXPECT_EQ(dtc_im_torque_room_check(&sfvc, msg, sizeof msg), 0);
    EXPECT_GE(room_torque(sfvc), sfvc.rated_torque_nm);
    std::printf("MEASURE second machine, sfvc, %.0f us: the torque the current allows %.1f N*m (rated %.1f)\n",
                1e6 * sfvc.ts_s, room_torque(sfvc), sfvc.rated_torque_nm);
    const dtc_config_si_t dfoc = shipped_si("im_second_machine.toml", "dfoc");
    EXPECT_EQ(dtc_im_torque_room_check(&dfoc, msg, sizeof msg), 0);
    EXPECT_GE(room_torque(dfoc), dfoc.rated_torque_nm);
    std::printf("MEASURE second machine, dfoc (dfoc_zeta 0), %.0f us: the torque the current allows %.1f N*m (rated %.1f)\n",
                1e6 * dfoc.ts_s, room_torque(dfoc), dfoc.rated_torque_nm);
    const dtc_config_si_t dtc40 = shipped_si("im_second_machine.toml", "dtc");
    EXPECT_EQ(dtc_im_torque_room_check(&dtc40, msg, sizeof msg), 0);
    for (const char* law : {"sfvc", "dfoc"}) {
        const dtc_config_si_t four = shipped_si("im_dtc_speed.toml", law);
        EXPECT_EQ(dtc_im_torque_room_check(&four, msg, sizeof msg), 0);
    }
}

// ---- The current limit (tools/config dtc_ilim_default_a, firmware im_ilim / the torque limit) ----
// Every IM law, realistic parts, the rotor held by the dynamometer at held_rpm; magnetised, then
// a 300 % rated torque request (Casadei Fig. 14's step size) through the shadow set. The firmware
// holds the torque at the limit the current allows (dtc_im_torque_at_current_nm at I_lim less
// dtc_im_hold_margin_a: dI, or the SFVC's SVM ripple) and
// the switching-table laws replace the vector when the sampled current passes I_lim. Asserted on
// the plant: no fault, the peak phase current below the trip level, the mean torque over the last
// 50 ms within 10 % of the derived limit (the estimate's bias, -4 % at 50 % rated torque on this
// machine and more at the limit, measured -8 % with DTC at 1000 rpm, is in that figure).
struct LimitRun {
    double i_peak = 0.0, te_mean = 0.0, t_lim = 0.0, i_trip = 0.0;
    uint16_t fault = APP_FAULT_NONE;
};

static LimitRun run_limit(int scheme, double held_rpm, double t_req_nm)
{
    ImRig r(false, false, held_rpm, scheme);
    LimitRun o;
    if (!r.h) {
        return o;
    }
    const double ts = r.si.ts_s;
    const double ilim = dtc_ilim_default_a(&r.si);
    o.t_lim = std::fmin(r.si.torque_limit_nm, dtc_im_torque_at_current_nm(&r.si, ilim - dtc_im_hold_margin_a(&r.si)));
    o.i_trip = r.si.i_trip_a;
    const long n_on = static_cast<long>(r.cfg.u.im.ref.magn_periods) + 64;
    for (long k = 0; k < n_on + static_cast<long>(0.2 / ts); ++k) {
        r.period();
    }
    if (command_torque(r, t_req_nm) != DTC_OK) {
        o.fault = APP_FAULT_CONFIG;
        return o;
    }
    double sum = 0.0;
    long n = 0;
    const long n_run = static_cast<long>(0.15 / ts);
    for (long j = 0; j < n_run; ++j) {
        r.period();
        const auto& s = r.h->state();
        o.i_peak = std::fmax(o.i_peak, std::fmax(std::fabs(s.i_a), std::fmax(std::fabs(s.i_b), std::fabs(s.i_c))));
        if (j >= n_run - static_cast<long>(0.05 / ts)) {
            sum += s.te_nm;
            ++n;
        }
    }
    o.te_mean = sum / static_cast<double>(n);
    o.fault = r.status().fault;
    return o;
}

TEST(ImLaw, CurrentLimitHolds300PercentRequestAtTheTorqueTheCurrentAllows)
{
    const int laws[] = {DTC_LAW_IM_DTC, DTC_LAW_IM_DSC, DTC_LAW_IM_SFVC, DTC_LAW_IM_DFOC, DTC_LAW_IM_DSVM};
    for (int law : laws) {
        for (double rpm : {0.0, 1000.0}) {
            SCOPED_TRACE(law);
            SCOPED_TRACE(rpm);
            const LimitRun o = run_limit(law, rpm, 3.0 * 26.5);
            std::printf("MEASURE current limit, law %d at %.0f rpm, T* 300 %%: peak phase current %.1f A (trip %.0f A), "
                        "torque %.2f N*m, the current's limit %.2f N*m (%+.1f %%), fault %s\n",
                        law, rpm, o.i_peak, o.i_trip, o.te_mean, o.t_lim, 100.0 * (o.te_mean / o.t_lim - 1.0),
                        app_fault_name(o.fault));
            EXPECT_EQ(o.fault, APP_FAULT_NONE) << app_fault_name(o.fault);
            EXPECT_LT(o.i_peak, o.i_trip);
            EXPECT_LT(o.t_lim, 3.0 * 26.5); // the trip level does not allow 300 % on this machine
            EXPECT_NEAR(o.te_mean, o.t_lim, 0.10 * o.t_lim);
        }
    }
}

// A full-load (rated torque) step at 1000 rpm, every IM law: no trip, the peak below the trip.
TEST(ImLaw, CurrentLimitFullLoadStepAtSpeedStaysBelowTheTrip)
{
    const int laws[] = {DTC_LAW_IM_DTC, DTC_LAW_IM_DSC, DTC_LAW_IM_SFVC, DTC_LAW_IM_DFOC, DTC_LAW_IM_DSVM};
    for (int law : laws) {
        SCOPED_TRACE(law);
        const LimitRun o = run_limit(law, 1000.0, 26.5);
        std::printf("MEASURE full-load step, law %d at 1000 rpm: peak phase current %.1f A (trip %.0f A), torque %.2f N*m, fault %s\n",
                    law, o.i_peak, o.i_trip, o.te_mean, app_fault_name(o.fault));
        EXPECT_EQ(o.fault, APP_FAULT_NONE) << app_fault_name(o.fault);
        EXPECT_LT(o.i_peak, o.i_trip);
        EXPECT_NEAR(o.te_mean, 26.5, 0.06 * 26.5);
    }
}
