// Integrator accuracy of the default configuration against a fine reference.
//
// At the default 50 us step a switching period is a 2 us dead-time segment integrated with the
// midpoint rule (plant_advance uses it for a segment ending at a dead-time end and no longer than
// max_step/16) plus a 48 us RK4 step. At max_step 3.125 us every segment, including the dead-time
// one (2 us > 3.125/16 us), is RK4, and the RK4 error there is ~(3.125/50)^4 = 1.5e-5 of the default
// one, so that run is the reference. The test bounds the whole error of the default run: RK4 on the
// 48 us steps plus the midpoint dead-time segments (docs/plant.md, section 2).
#include <vector>

#include "model_test_util.h"

using namespace mt;

namespace {

struct Traj {
    std::vector<double> ia, ib, vlo, w;
};

// Same fixed pattern as Convergence.HalvingStepFstpSwitchingRun: FSTP vectors rotating at 25 Hz,
// every fourth period reversed, so a leg switches (and a dead-time segment occurs) in most periods.
Traj run(double h) {
    plant_params_t p;
    plant_params_default(&p);
    p.inverter = PLANT_INVERTER_FSTP;
    plant_params_emf_table_vii(&p);
    p.speed0_rpm = 1500.0;
    p.max_step_s = h;
    auto pl = make(p);
    Traj tr;
    for (int k = 0; k < 400; ++k) {  // 20 ms
        double a = 2 * kPi * 25.0 * k * 50e-6 + kPi / 2;
        if (k % 4 == 3) a += kPi;
        double x = std::fmod(a, 2 * kPi);
        if (x < 0) x += 2 * kPi;
        static const int tab[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};  // Hoang Table I: V1..V4
        const int q = static_cast<int>(std::floor((x + kPi / 4) / (kPi / 2))) % 4;
        plant_set_legs(pl.get(), 0, tab[q][0], tab[q][1], 1);
        plant_advance(pl.get(), 50e-6);
        const plant_state_t s = state(pl);
        tr.ia.push_back(s.i_a);
        tr.ib.push_back(s.i_b);
        tr.vlo.push_back(s.vc_lo_v);
        tr.w.push_back(s.omega_m_rad_s);
    }
    return tr;
}

double maxdiff(const std::vector<double> &a, const std::vector<double> &b) {
    double m = 0.0;
    for (size_t i = 0; i < a.size(); ++i) m = std::max(m, std::fabs(a[i] - b[i]));
    return m;
}

}  // namespace

// Default step vs the 3.125 us all-RK4 reference over a 20 ms full-fidelity FSTP switching run,
// sampled every 50 us: < 1e-5 A in the phase currents (1/500 of one LSB of a 12-bit +-10 A
// channel), < 1.2e-5 V on the lower capacitor, < 5e-5 rad/s in speed.
TEST(Integrator, DefaultStepAgainstFineReference) {
    plant_params_t def;
    plant_params_default(&def);
    ASSERT_EQ(def.max_step_s, 50e-6);
    ASSERT_EQ(def.dead_time_s, 2e-6);
    const Traj a = run(def.max_step_s);
    const Traj ref = run(3.125e-6);
    const double di = std::max(maxdiff(a.ia, ref.ia), maxdiff(a.ib, ref.ib));
    const double dv = maxdiff(a.vlo, ref.vlo);
    const double dw = maxdiff(a.w, ref.w);
    std::printf("default step vs 3.125 us reference: max |di| = %.3e A, |dv_lo| = %.3e V, |dw| = %.3e rad/s\n",
                di, dv, dw);
    EXPECT_LT(di, 1e-5);
    EXPECT_LT(dv, 1.2e-5);
    EXPECT_LT(dw, 5e-5);
}
