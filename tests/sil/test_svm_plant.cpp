// The fixed-point SVM (firmware/dtc/svm.h) through hal_host's PWM form into the plant: the
// volt-seconds the machine's terminals receive over a period equal the commanded ones.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "hal_host.hpp"
#include "ideal_plant.hpp"
#include "plant.h"

extern "C" {
#include "svm.h"
}

using hal_host::Harness;
using hal_host::HarnessConfig;

namespace {

constexpr double kPi = 3.14159265358979323846;

iq_t to_iq(double x) { return static_cast<iq_t>(std::lround(x * 16777216.0)); }
double from_iq(iq_t x) { return static_cast<double>(x) / 16777216.0; }

std::unique_ptr<Harness> make(const plant_params_t& p)
{
    std::string err;
    auto h = Harness::create(p, HarnessConfig{}, &err);
    EXPECT_TRUE(h) << err;
    h->activate();
    hal_init();
    return h;
}

hal_cmd_t cmd_of(const svm_out_t& o, std::uint16_t t1pr)
{
    hal_cmd_t c{};
    c.enable = 1u;
    c.form = HAL_CMD_PWM;
    for (int x = 0; x < 3; ++x) {
        c.cmpr_up[x] = c.cmpr_dn[x] = svm_cmpr(o.d_iq[x], t1pr);
        c.act[x] = HAL_PWM_UPPER_ACTIVE_HIGH;
    }
    return c;
}

struct VsErr {
    double rms_v = 0.0;
    double max_v = 0.0;
};

// Runs n periods of a rotating reference of magnitude frac * vdc/sqrt3 (per unit of the link),
// frequency f_hz, through the SVM into the plant; returns the error between the mean alpha/beta
// terminal voltage of each period (the plant's v_x0 averages, Casadei eq. 2) and the command.
VsErr run(plant_params_t p, std::uint16_t mode, std::uint16_t dt_comp, double frac, double f_hz, int n)
{
    auto h = make(p);
    const std::uint16_t t1pr = hal_pwm_period();
    EXPECT_GT(t1pr, 0u);
    const double ts = h->ts_s();
    svm_t s;
    svm_reset(&s);
    svm_params_t prm{};
    prm.mode = mode;
    prm.dt_comp = dt_comp;
    prm.td_iq = to_iq(p.dead_time_s / ts);
    std::vector<double> cmd_a, cmd_b;
    VsErr e;
    double sum = 0.0;
    int cnt = 0;
    for (int k = 0; k <= n; ++k) {
        const double ang = 2.0 * kPi * f_hz * k * ts;
        const double mag = frac / std::sqrt(3.0); // pu of the link (V_base = vdc_v)
        plant_state_t st;
        plant_get_state(h->plant(), &st);
        // the current at the start of the period the command governs is about the one now
        clarke_out_t i{};
        i.ia_iq = to_iq(st.i_a);
        i.ib_iq = to_iq(st.i_b);
        i.ic_iq = to_iq(st.i_c);
        svm_out_t o;
        svm_step(&s, &prm, to_iq(mag * std::cos(ang)), to_iq(mag * std::sin(ang)), to_iq(1.0), &i, &o);
        // the reference as quantised in IQ, volts
        cmd_a.push_back(from_iq(to_iq(mag * std::cos(ang))) * p.vdc_v);
        cmd_b.push_back(from_iq(to_iq(mag * std::sin(ang))) * p.vdc_v);
        h->run_period([&] {
            hal_meas_t m;
            hal_read(&m);
            const hal_cmd_t c = cmd_of(o, t1pr);
            hal_write(&c);
        });
        if (k == 0) {
            continue; // period 0 ran with the gates off
        }
        plant_get_state(h->plant(), &st);
        const double va = (2.0 * st.v_a0_v - st.v_b0_v - st.v_c0_v) / 3.0;
        const double vb = (st.v_b0_v - st.v_c0_v) / std::sqrt(3.0);
        const double err = std::hypot(va - cmd_a[static_cast<std::size_t>(k - 1)], vb - cmd_b[static_cast<std::size_t>(k - 1)]);
        sum += err * err;
        ++cnt;
        e.max_v = std::max(e.max_v, err);
    }
    EXPECT_EQ(h->invalid_writes(), 0u);
    e.rms_v = std::sqrt(sum / cnt);
    return e;
}

plant_params_t ideal_params() { return sil_test::ideal_plant_held_at(600.0); }

} // namespace

// Ideal devices, no dead time, stiff link: over one electrical turn in 400 periods (every sector
// and boundary region, the rotating reference at 0.3 and 0.95 of the linear limit, both modes)
// the mean vector of each period equals the command to the timer quantisation: a duty is
// rounded to half a count of T1PR = 1875, so a leg's mean voltage to q = vdc / 3750, and the
// space vector of three such errors, (2/3)|e_a + a e_b + a^2 e_c|, to at most (4/3) q.
TEST(SvmPlant, VoltSecondsEqualTheCommandEveryPeriod)
{
    const plant_params_t p = ideal_params();
    const double q = 4.0 / 3.0 * p.vdc_v / 3750.0;
    for (std::uint16_t mode : {std::uint16_t{SVM_SYMMETRIC}, std::uint16_t{SVM_TWO_PHASE}}) {
        for (double frac : {0.3, 0.95}) {
            const VsErr e = run(p, mode, 0u, frac, 50.0, 400);
            EXPECT_LT(e.max_v, q) << "mode " << mode << " frac " << frac;
        }
    }
}

// With the plant's dead time on (default 2 us of 50 us) and currents flowing (the PM machine
// held at 600 rpm against 0.95 of the linear limit), the uncompensated volt-seconds error is about
// of the dead time's T_d/T_s vdc per switching leg, and the current-sign compensation removes
// most of it (what stays: periods in which a current changes sign): the rms error falls below a quarter, in both modes.
TEST(SvmPlant, DeadTimeCompensationRestoresTheVoltSeconds)
{
    plant_params_t p = ideal_params();
    p.dead_time_enabled = 1;
    ASSERT_GT(p.dead_time_s, 0.0);
    for (std::uint16_t mode : {std::uint16_t{SVM_SYMMETRIC}, std::uint16_t{SVM_TWO_PHASE}}) {
        const VsErr off = run(p, mode, 0u, 0.6, 20.0, 1000);
        const VsErr on = run(p, mode, 1u, 0.6, 20.0, 1000);
        std::printf("mode %u: volt-seconds error rms %.4f V without, %.4f V with the compensation\n", mode, off.rms_v, on.rms_v);
        // uncompensated: a switching leg loses T_d/T_s vdc; the vector error is of that order
        EXPECT_GT(off.rms_v, 0.3 * p.dead_time_s / 50e-6 * p.vdc_v) << "mode " << mode;
        EXPECT_LT(on.rms_v, 0.25 * off.rms_v) << "mode " << mode << " off " << off.rms_v << " on " << on.rms_v;
    }
}

// Harness::set_substeps: the period integrated in parts, with the command's instants split among
// them, drives the plant as the period in one piece does (default plant: drops, dead time, finite
// link), to the integrator's accuracy; the observer is called once per part.
TEST(SvmPlant, SubstepsSeeTheSameCommand)
{
    plant_params_t p;
    plant_params_default(&p);
    p.load = PLANT_LOAD_SPEED;
    p.load_speed_rpm = 900.0;
    auto run = [&](int sub, long* calls) {
        auto h = make(p);
        if (sub > 1) {
            h->set_substeps(sub, [calls](const plant_t*) { ++*calls; });
        }
        const std::uint16_t t1pr = hal_pwm_period();
        svm_t s;
        svm_reset(&s);
        const svm_params_t prm{SVM_SYMMETRIC, 0u, 0};
        for (int k = 0; k < 400; ++k) {
            const double ang = 2.0 * kPi * 30.0 * k * h->ts_s();
            svm_out_t o;
            svm_step(&s, &prm, to_iq(0.4 * std::cos(ang)), to_iq(0.4 * std::sin(ang)), to_iq(1.0), nullptr, &o);
            h->run_period([&] {
                hal_meas_t m;
                hal_read(&m);
                const hal_cmd_t c = cmd_of(o, t1pr);
                hal_write(&c);
            });
        }
        plant_state_t st;
        plant_get_state(h->plant(), &st);
        return st;
    };
    long calls = 0;
    const plant_state_t a = run(1, &calls);
    const plant_state_t b = run(7, &calls);
    EXPECT_EQ(calls, 7L * 400L);
    const double imax = std::max({std::fabs(a.i_a), std::fabs(a.i_b), std::fabs(a.i_c)});
    ASSERT_GT(imax, 0.5);
    EXPECT_NEAR(b.i_a, a.i_a, 1e-6 * imax);
    EXPECT_NEAR(b.i_b, a.i_b, 1e-6 * imax);
    EXPECT_NEAR(b.vdc_v, a.vdc_v, 1e-6 * a.vdc_v);
    std::printf("substeps 7 vs 1 after 400 periods: i_a %.9f / %.9f A\n", b.i_a, a.i_a);
}
