// Integrator accuracy of the default configuration against a fine reference.
//
// At the default 50 us step a switching period is a dead-time segment (1 us) integrated with the
// midpoint rule (plant_advance uses it for a segment ending at a dead-time end and no longer than
// max_step/16) plus an RK4 step for the rest. At max_step 3.125 us every segment, including the
// dead-time one (longer than 3.125/16 us), is RK4, and the RK4 error there is ~(3.125/50)^4 = 1.5e-5 of the default
// one, so that run is the reference. The test bounds the whole error of the default run: RK4 on the
// long steps plus the midpoint dead-time segments (docs/plant.md, section 2).
#include "model_test_util.h"

using namespace mt;

// Default step vs the 3.125 us all-RK4 reference over a 20 ms full-fidelity FSTP switching run,
// sampled every 50 us: < 1e-5 A in the phase currents (1/500 of one LSB of a 12-bit +-10 A
// channel), < 1.2e-5 V on the lower capacitor, < 5e-5 rad/s in speed.
TEST(Integrator, DefaultStepAgainstFineReference) {
    plant_params_t def;
    plant_params_default(&def);
    ASSERT_EQ(def.max_step_s, 50e-6);
    // The two integration rules the comment above describes: midpoint on the dead-time segment
    // at the default step, RK4 everywhere in the reference.
    ASSERT_LE(def.dead_time_s, def.max_step_s / 16.0);
    ASSERT_GT(def.dead_time_s, 3.125e-6 / 16.0);
    const Traj a = run_fixed_pattern(def.max_step_s);
    const Traj ref = run_fixed_pattern(3.125e-6);
    const double di = std::max(maxdiff(a.ia, ref.ia), maxdiff(a.ib, ref.ib));
    const double dv = maxdiff(a.vlo, ref.vlo);
    const double dw = maxdiff(a.w, ref.w);
    std::printf("default step vs 3.125 us reference: max |di| = %.3e A, |dv_lo| = %.3e V, |dw| = %.3e rad/s\n",
                di, dv, dw);
    EXPECT_LT(di, 1e-5);
    EXPECT_LT(dv, 1.2e-5);
    EXPECT_LT(dw, 5e-5);
}
