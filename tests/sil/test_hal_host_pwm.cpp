// hal_host's PWM form (hal.h) on the real plant: compare values -> switching instants with the
// EV-A's up/down counter arithmetic, the one-period actuation delay, and the leg-state form as
// the PWM form's 0 / 100 % case, bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <string>
#include <vector>

#include "hal_host.hpp"
#include "ideal_plant.hpp"
#include "model_test_util.h"
#include "plant.h"

using hal_host::Harness;
using hal_host::HarnessConfig;

namespace {

constexpr std::uint16_t kT1pr = 1875; // 50 us at 75 MHz, up/down: 50e-6 * 75e6 / 2

hal_cmd_t pwm(const std::uint16_t up[3], const std::uint16_t dn[3], const std::uint16_t act[3])
{
    hal_cmd_t c{};
    c.enable = 1u;
    c.form = HAL_CMD_PWM;
    for (int x = 0; x < 3; ++x) {
        c.cmpr_up[x] = up[x];
        c.cmpr_dn[x] = dn[x];
        c.act[x] = act[x];
    }
    return c;
}

// Upper-device on-time over one period, counted in timer counts: the compare output is active
// for (T1PR - up) counts of the up-count half if up <= T1PR, and (T1PR - dn) counts of the
// down-count half if dn <= T1PR (f2812-facts 2.3-2.5; hal.h); active low inverts it.
double on_time_s(std::uint16_t up, std::uint16_t dn, std::uint16_t act, double ts)
{
    const long active = (up <= kT1pr ? kT1pr - up : 0) + (dn <= kT1pr ? kT1pr - dn : 0);
    const long on = act == HAL_PWM_UPPER_ACTIVE_LOW ? 2L * kT1pr - active : active;
    return static_cast<double>(on) * ts / (2.0 * kT1pr);
}

std::unique_ptr<Harness> make(const plant_params_t& p)
{
    std::string err;
    auto h = Harness::create(p, HarnessConfig{}, &err);
    EXPECT_TRUE(h) << err;
    h->activate();
    return h;
}

} // namespace

// Ideal devices, no dead time, stiff link, 1500 rpm held: every leg's terminal volt-seconds over
// period k+1 equal Vdc times the on-time the command of period k asks for, to 1e-12 V*s, for
// duties 0 and 1, mid, near-limit values, out-of-range values, asymmetric pulses, active-low
// legs and DSVM's thirds (1250 counts = ts / 3 from either end).
TEST(HalHostPwm, CompareValuesGiveTheCommandedVoltSecondsOnePeriodLater)
{
    plant_params_t p = sil_test::ideal_plant_held_at(1500.0);
    auto h = make(p);
    ASSERT_EQ(h->pwm_period(), kT1pr);
    hal_init();
    EXPECT_EQ(hal_pwm_period(), kT1pr);
    const double ts = h->ts_s();
    struct Row {
        std::uint16_t up[3], dn[3], act[3];
    };
    const std::uint16_t H = HAL_PWM_UPPER_ACTIVE_HIGH, L = HAL_PWM_UPPER_ACTIVE_LOW;
    const std::vector<Row> rows = {
        {{kT1pr + 1, 0, 937}, {kT1pr + 1, 0, 937}, {H, H, H}},       // duty 0, 1, ~0.5
        {{1, kT1pr, kT1pr - 1}, {1, kT1pr, kT1pr - 1}, {H, H, H}},   // near the limits
        {{60000, 0, 2000}, {0, 60000, 2000}, {H, H, H}},             // out of range halves
        {{500, 1800, 3}, {1200, 20, 1870}, {H, H, H}},               // asymmetric
        {{500, 937, 0}, {1200, 937, 0}, {L, L, L}},                  // active low
        {{1250, 1250, 1250}, {0, 1250, kT1pr + 1}, {L, H, H}},       // DSVM thirds
    };
    std::vector<hal_cmd_t> sent;
    for (std::size_t k = 0; k <= rows.size(); ++k) {
        h->run_period([&] {
            hal_meas_t m;
            hal_read(&m);
            if (k < rows.size()) {
                const hal_cmd_t c = pwm(rows[k].up, rows[k].dn, rows[k].act);
                hal_write(&c);
                sent.push_back(c);
            }
        });
        if (k == 0) {
            continue; // period 0 ran with the gates off (nothing written before it)
        }
        plant_state_t s;
        plant_get_state(h->plant(), &s);
        const hal_cmd_t& c = sent[k - 1];
        const double vx0[3] = {s.v_a0_v, s.v_b0_v, s.v_c0_v};
        for (int x = 0; x < 3; ++x) {
            EXPECT_NEAR(vx0[x] * ts, p.vdc_v * on_time_s(c.cmpr_up[x], c.cmpr_dn[x], c.act[x], ts), 1e-12)
                << "period " << k << " leg " << x;
        }
    }
    EXPECT_EQ(h->invalid_writes(), 0u);
}

// The leg-state form and the PWM form at 0 / 100 % (cmpr T1PR + 1 / 0, upper active high) drive
// the default plant (drops, dead time, finite link) identically, bit for bit.
TEST(HalHostPwm, LegStateFormEqualsPwmFormAtZeroAndFullDuty)
{
    const plant_params_t p = mt::torque_load(mt::default_plant(), 0.1);
    auto a = make(p);
    auto b = make(p);
    for (Harness* h : {a.get(), b.get()}) {
        h->activate();
        hal_init();
    }
    const std::uint16_t act[3] = {0, 0, 0};
    for (int k = 0; k < 3000; ++k) {
        const std::uint16_t s[3] = {static_cast<std::uint16_t>((k / 3) % 2), static_cast<std::uint16_t>((k / 5) % 2),
                                    static_cast<std::uint16_t>((k / 7) % 2)};
        a->activate();
        a->run_period([&] {
            hal_cmd_t c{};
            c.sa = s[0];
            c.sb = s[1];
            c.sc = s[2];
            c.enable = 1u;
            hal_write(&c);
        });
        b->activate();
        b->run_period([&] {
            std::uint16_t cm[3];
            for (int x = 0; x < 3; ++x) {
                cm[x] = s[x] ? 0u : static_cast<std::uint16_t>(kT1pr + 1u);
            }
            const hal_cmd_t c = pwm(cm, cm, act);
            hal_write(&c);
        });
    }
    plant_state_t sa, sb;
    plant_get_state(a->plant(), &sa);
    plant_get_state(b->plant(), &sb);
    const double* da = &sa.t_s;
    const double* db = &sb.t_s;
    const std::size_t nd = offsetof(plant_state_t, blocked_mask) / sizeof(double);
    for (std::size_t i = 0; i < nd; ++i) {
        EXPECT_EQ(std::memcmp(da + i, db + i, sizeof(double)), 0) << "field " << i;
    }
    EXPECT_GT(std::fabs(sa.omega_m_rad_s), 1.0);
}

// A period that is not a whole number of timer counts has no PWM form: hal_pwm_period() is 0, a
// PWM-form command is counted invalid and leaves the gates off; the leg-state form still works.
// Casadei's 40 us DTC period is 1500 counts.
TEST(HalHostPwm, PeriodThatIsNotAWholeNumberOfCountsHasNoPwmForm)
{
    plant_params_t p = sil_test::ideal_plant_held_at(0.0);
    HarnessConfig cfg;
    cfg.ts_s = 50.01e-6; // 1875.375 counts
    std::string err;
    auto h = Harness::create(p, cfg, &err);
    ASSERT_TRUE(h) << err;
    h->activate();
    hal_init();
    EXPECT_EQ(hal_pwm_period(), 0u);
    const std::uint16_t v1[3] = {0, 60000, 60000}, act[3] = {0, 0, 0}; // would be V1 (100)
    for (int k = 0; k < 3; ++k) {
        h->run_period([&] {
            const hal_cmd_t c = pwm(v1, v1, act);
            hal_write(&c);
        });
    }
    EXPECT_EQ(h->invalid_writes(), 3u);
    plant_state_t s;
    plant_get_state(h->plant(), &s);
    EXPECT_EQ(s.i_a, 0.0); // locked rotor, gates off: no current (V1 would drive ~1 A per period)
    cfg.ts_s = 40e-6;
    auto h40 = Harness::create(p, cfg, &err);
    ASSERT_TRUE(h40) << err;
    EXPECT_EQ(h40->pwm_period(), 1500u);
}
