// im_rig.hpp - a SIL rig of an induction-machine scenario for the IM tests (test_im_casadei.cpp,
// test_im_fly.cpp): the scenario with --set overrides, the firmware as dtc-sil runs it
// (make_controller) on hal_host, stepped period by period, with the plant's true state, the
// application's status and the reference set through the shadow (app_set_refs).
#ifndef SIL_TEST_IM_RIG_HPP
#define SIL_TEST_IM_RIG_HPP

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <vector>

extern "C" {
#include "app.h"
#include "dtc_config_si.h"
}

#include "controller_adapter.hpp"
#include "hal_host.hpp"
#include "run.hpp"
#include "scenario.hpp"
#include "sil_constants.hpp"

namespace sil_test {

using namespace sil;

const std::string kScenario = std::string(DTC_SOURCE_DIR) + "/tools/scenarios/im_dtc_speed.toml";
constexpr double kIqOne = 16777216.0; // 2^24, iq_t

// One SIL rig from an induction-machine scenario (im_dtc_speed.toml unless another is named) plus
// --set overrides, stepped period by period.
struct Rig {
    Scenario sc;
    dtc_config_si_t si{};
    dtc_config_t cfg{};
    dtc_bases_t b{};
    std::unique_ptr<hal_host::Harness> h;
    std::unique_ptr<Controller> ctrl;
    bool ok = false;

    explicit Rig(const std::vector<std::string>& sets, const std::string& scenario = kScenario)
    {
        Diagnostics d;
        if (!load_scenario(scenario, sets, &sc, &d)) {
            ADD_FAILURE() << d.text();
            return;
        }
        si = firmware_si_config(sc);
        char msg[256] = {0};
        if (dtc_config_from_si(&si, &cfg, msg, sizeof msg) != DTC_SI_OK) {
            ADD_FAILURE() << msg;
            return;
        }
        dtc_bases_from_si(&si, &b);
        std::string err;
        h = hal_host::Harness::create(plant_params_from(sc), harness_config_from(sc), &err);
        if (!h) {
            ADD_FAILURE() << err;
            return;
        }
        h->activate();
        ctrl = make_controller(sc, &err);
        if (!ctrl) {
            ADD_FAILURE() << err;
            return;
        }
        const std::string e = ctrl->init(*h);
        if (!e.empty()) {
            ADD_FAILURE() << e;
            return;
        }
        ok = true;
    }
    ~Rig()
    {
        stop_record();
        if (h) {
            h->deactivate();
        }
    }
    double ts() const { return sc.ts_s; }
    long periods(double t_s) const { return static_cast<long>(std::llround(t_s / sc.ts_s)); }
    void period()
    {
        h->run_period([this] { ctrl->step(*h); });
        if (wave && ++wave_k % wave_every == 0) {
            write_wave_row();
        }
    }
    // Waveforms for tools/plot/casadei_report.py's figures: while recording, one row every `every`
    // periods to $DTC_FIGURE_DIR/NAME.csv (nothing without the variable).
    void record(const std::string& name, long every = 1)
    {
        stop_record();
        const char* dir = std::getenv("DTC_FIGURE_DIR");
        if (!dir || !*dir) {
            return;
        }
        wave = std::fopen((std::string(dir) + "/" + name + ".csv").c_str(), "w");
        if (!wave) {
            ADD_FAILURE() << "cannot write " << dir << "/" << name << ".csv";
            return;
        }
        wave_every = every;
        wave_k = 0;
        std::fprintf(wave, "t_s,speed_rpm,speed_est_rpm,te_nm,te_ref_nm,psi_alpha_wb,psi_beta_wb,psi_r_alpha_wb,"
                           "psi_r_beta_wb,psi_est_wb,psi_ref_wb,i_a_a,i_mag_a,vdc_v\n");
        write_wave_row();
    }
    void stop_record()
    {
        if (wave) {
            std::fclose(wave);
            wave = nullptr;
        }
    }
    void write_wave_row()
    {
        const app_status_t s = status();
        const double pb = b.psi_base_wb / kIqOne;
        std::fprintf(wave, "%.6f,%.3f,%.3f,%.4f,%.4f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.4f,%.4f,%.3f\n", h->time_s(),
                     st().speed_rpm, speed_est_rpm(), st().te_nm, s.out.te_ref_iq / kIqOne * b.t_base_nm, st().psi_alpha_wb,
                     st().psi_beta_wb, st().psi_r_alpha_wb, st().psi_r_beta_wb,
                     std::hypot(static_cast<double>(s.out.psi_alpha_iq), static_cast<double>(s.out.psi_beta_iq)) * pb,
                     s.out.psi_ref_iq * pb, st().i_alpha_a, imag(), st().vdc_v);
    }
    std::FILE* wave = nullptr;
    long wave_every = 1, wave_k = 0;
    // Runs t_s, calling f after every period.
    void run(double t_s, const std::function<void()>& f = {})
    {
        for (long k = 0, n = periods(t_s); k < n; ++k) {
            period();
            if (f) {
                f();
            }
        }
    }
    const plant_state_t& st() const { return h->state(); }
    double psir() const { return std::hypot(st().psi_r_alpha_wb, st().psi_r_beta_wb); }
    double psis() const { return std::hypot(st().psi_alpha_wb, st().psi_beta_wb); }
    double imag() const { return std::hypot(st().i_alpha_a, st().i_beta_a); }
    app_status_t status() const
    {
        app_status_t s;
        app_get_status(&s);
        return s;
    }
    std::string fault() const { return ctrl->fault(); }
    iq_t torque_iq(double nm) const { return static_cast<iq_t>(std::lround(nm / b.t_base_nm * kIqOne)); }
    iq_t speed_iq(double rpm) const
    {
        return static_cast<iq_t>(std::lround(rpm * kPi / 30.0 * static_cast<double>(si.pole_pairs) / b.w_base_rad_s * kIqOne));
    }
    double speed_est_rpm() const
    {
        return static_cast<double>(status().out.speed_iq) / kIqOne * b.w_base_rad_s * 30.0 / kPi /
               static_cast<double>(si.pole_pairs);
    }
    // Publishes a new reference set through the shadow (app_set_refs).
    void refs(int mode, double torque_nm, double speed_rpm)
    {
        dtc_refs_t r{};
        r.mode = static_cast<std::uint16_t>(mode);
        r.flux_ref_iq = cfg.speed.flux_ref_iq;
        r.kp_iq = cfg.speed.kp_iq;
        r.ki_ts_iq = cfg.speed.ki_ts_iq;
        r.torque_ref_iq = torque_iq(torque_nm);
        r.speed_ref_iq = speed_iq(speed_rpm);
        EXPECT_EQ(app_set_refs(&r), DTC_OK);
    }
    // Start-up: calibration and the magnetisation at zero torque, then settle_s more.
    void magnetise(double settle_s)
    {
        const double t_magn = static_cast<double>(cfg.u.im.ref.magn_periods) * ts();
        run(t_magn + 64.0 * ts() + settle_s);
    }
    // Moves the dynamometer's held speed linearly to rpm over t_s.
    void ramp_held_speed(double rpm, double t_s)
    {
        const double from = st().speed_rpm;
        const long n = periods(t_s);
        for (long k = 1; k <= n; ++k) {
            plant_set_load(h->plant(), PLANT_LOAD_SPEED, from + (rpm - from) * static_cast<double>(k) / static_cast<double>(n), 0.0);
            period();
        }
    }
};

} // namespace sil_test

#endif // SIL_TEST_IM_RIG_HPP
