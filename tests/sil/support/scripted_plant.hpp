// scripted_plant.hpp - a test double of the plant C ABI (model/include/plant.h).
//
// The plant's true state is whatever the test's script says at time t; every advance is logged
// with the leg states / voltages in force, so hal_host's clock, actuation delay, sensor emulation
// and the run loop can be checked against exact expectations without the real plant.
#ifndef SCRIPTED_PLANT_HPP
#define SCRIPTED_PLANT_HPP

#include <functional>
#include <string>
#include <vector>

#include "plant.h"

namespace scripted {

struct Advance {
    double t_start_s;
    double dt_s;
    int sa, sb, sc, enable;
    double v_alpha_v, v_beta_v;
};

struct Log {
    std::vector<Advance> advances;
    std::vector<plant_params_t> created;
    int destroyed = 0;
    int load_changes = 0;
    double last_load_torque_nm = 0.0;
};

/// state(t, s): fill s with the true state at time t (s->t_s is preset to t, the rest zeroed).
void set_script(std::function<void(double, plant_state_t*)> state);
/// Make the next plant_create() fail with this message (empty = succeed).
void fail_next_create(const std::string& msg);
Log& log();
void reset();

} // namespace scripted

#endif
