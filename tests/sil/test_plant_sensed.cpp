// plant_get_sensed() (the per-period read of hal_host) and plant_get_state_core() (the recorded
// periods' read of the metrics' series) against plant_get_state() on the real plant: the same
// values, bit for bit, on a switching FSTP run with a finite DC link (every field moves), and
// Harness::state() / state_core() (computed on demand) equal to a direct plant_get_state() read.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "hal_host.hpp"
#include "plant.h"

namespace {

void expect_same(const plant_sensed_t& se, const plant_state_t& st, int k)
{
    EXPECT_EQ(se.t_s, st.t_s) << k;
    EXPECT_EQ(se.i_a, st.i_a) << k;
    EXPECT_EQ(se.i_b, st.i_b) << k;
    EXPECT_EQ(se.i_c, st.i_c) << k;
    EXPECT_EQ(se.theta_m_rad, st.theta_m_rad) << k;
    EXPECT_EQ(se.omega_m_rad_s, st.omega_m_rad_s) << k;
    EXPECT_EQ(se.vdc_v, st.vdc_v) << k;
    EXPECT_EQ(se.vc_lo_v, st.vc_lo_v) << k;
    EXPECT_EQ(se.vc_hi_v, st.vc_hi_v) << k;
}

// plant_get_state_core()'s fields (plant.h) equal to the full state's, bit for bit.
void expect_same_core(const plant_state_t& c, const plant_state_t& st, int k)
{
    EXPECT_EQ(c.t_s, st.t_s) << k;
    EXPECT_EQ(c.i_a, st.i_a) << k;
    EXPECT_EQ(c.i_b, st.i_b) << k;
    EXPECT_EQ(c.i_c, st.i_c) << k;
    EXPECT_EQ(c.i_alpha_a, st.i_alpha_a) << k;
    EXPECT_EQ(c.i_beta_a, st.i_beta_a) << k;
    EXPECT_EQ(c.psi_alpha_wb, st.psi_alpha_wb) << k;
    EXPECT_EQ(c.psi_beta_wb, st.psi_beta_wb) << k;
    EXPECT_EQ(c.psi_r_alpha_wb, st.psi_r_alpha_wb) << k;
    EXPECT_EQ(c.psi_r_beta_wb, st.psi_r_beta_wb) << k;
    EXPECT_EQ(c.te_nm, st.te_nm) << k;
    EXPECT_EQ(c.theta_m_rad, st.theta_m_rad) << k;
    EXPECT_EQ(c.omega_m_rad_s, st.omega_m_rad_s) << k;
    EXPECT_EQ(c.speed_rpm, st.speed_rpm) << k;
    EXPECT_EQ(c.i2_int_a2s, st.i2_int_a2s) << k;
    EXPECT_EQ(c.q_a_as, st.q_a_as) << k;
    EXPECT_EQ(c.q_b_as, st.q_b_as) << k;
}

plant_params_t fstp_params()
{
    plant_params_t p;
    plant_params_default(&p);
    p.inverter = PLANT_INVERTER_FSTP;
    p.finite_dc_link = 1;
    p.speed0_rpm = 1500.0;
    p.load = PLANT_LOAD_INERTIA;
    return p;
}

// Legs (B, C) of the four FSTP vectors, stepped every 5 periods: currents, capacitor voltages and
// speed all change.
void legs_for(int k, int* sb, int* sc)
{
    static const int tab[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    *sb = tab[(k / 5) % 4][0];
    *sc = tab[(k / 5) % 4][1];
}

} // namespace

TEST(PlantSensed, SameValuesAsTheFullStateOnASwitchingFstpRun)
{
    const plant_params_t p = fstp_params();
    char err[256] = {0};
    plant_t* pl = plant_create(&p, err, sizeof err);
    ASSERT_NE(pl, nullptr) << err;
    double i_peak = 0.0, vc_min = 1e9, vc_max = -1e9;
    for (int k = 0; k < 400; ++k) {
        plant_sensed_t se;
        plant_state_t st;
        plant_get_sensed(pl, &se);
        plant_get_state(pl, &st);
        expect_same(se, st, k);
        plant_state_t core;
        std::memset(&core, 0xff, sizeof core); // NaN patterns: a field it fails to fill differs
        plant_get_state_core(pl, &core);
        expect_same_core(core, st, k);
        i_peak = std::max(i_peak, std::fabs(st.i_b));
        vc_min = std::min(vc_min, st.vc_lo_v);
        vc_max = std::max(vc_max, st.vc_lo_v);
        int sb = 0, sc = 0;
        legs_for(k, &sb, &sc);
        plant_set_legs(pl, 0, sb, sc, 1);
        plant_advance(pl, 50e-6);
    }
    plant_destroy(pl);
    // The run exercised what it claims to: real currents and a moving mid-point.
    EXPECT_GT(i_peak, 0.5);
    EXPECT_GT(vc_max - vc_min, 1e-3);
}

TEST(PlantSensed, HarnessStateOnDemandEqualsADirectRead)
{
    hal_host::HarnessConfig cfg;
    std::string err;
    auto h = hal_host::Harness::create(fstp_params(), cfg, &err);
    ASSERT_TRUE(h) << err;
    h->activate();
    for (int k = 0; k < 50; ++k) {
        h->sample();
        plant_state_t direct;
        plant_get_state(h->plant(), &direct);
        // The core first (what a recorded period without a trace row reads), then the whole
        // state, which must not be the core's partial fill.
        expect_same_core(h->state_core(), direct, k);
        const plant_state_t& lazy = h->state();
        EXPECT_EQ(lazy.t_s, direct.t_s) << k;
        EXPECT_EQ(lazy.i_a, direct.i_a) << k;
        EXPECT_EQ(lazy.te_nm, direct.te_nm) << k;
        EXPECT_EQ(lazy.psi_alpha_wb, direct.psi_alpha_wb) << k;
        EXPECT_EQ(lazy.psi_beta_wb, direct.psi_beta_wb) << k;
        EXPECT_EQ(lazy.vc_lo_v, direct.vc_lo_v) << k;
        EXPECT_EQ(lazy.vdc_v, direct.vdc_v) << k;
        EXPECT_EQ(lazy.e_kinetic_j, direct.e_kinetic_j) << k;
        EXPECT_EQ(lazy.v_alpha_v, direct.v_alpha_v) << k;
        EXPECT_EQ(lazy.speed_rpm, direct.speed_rpm) << k;
        expect_same(h->sensed(), direct, k);
        int sb = 0, sc = 0;
        legs_for(k, &sb, &sc);
        const hal_cmd_t cmd{0, static_cast<std::uint16_t>(sb), static_cast<std::uint16_t>(sc), 1, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 0u};
        h->hal_write(&cmd);
        h->advance();
        // After advance(), state() is the state at the new time_s(), not a stale copy.
        EXPECT_NEAR(h->state().t_s, h->time_s(), 1e-12) << k; // the plant sums its steps
    }
}
