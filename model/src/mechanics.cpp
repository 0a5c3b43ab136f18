// mechanics.cpp - load laws and parameter checks of the shaft (mechanics.h).
#include "mechanics.h"

namespace mech {

void set_load_law(const plant_params_t &p, double omega_ref, Shaft &s) {
    s.omega_load_ref = omega_ref;
    s.c0 = s.cw = s.cte = s.cq = 0.0;
    s.w_on = 1.0;
    s.fan_on = p.load == PLANT_LOAD_FAN;
    switch (p.load) {
        case PLANT_LOAD_SPEED:  // the dynamometer holds speed: T_load = T_e - b omega
            s.cte = 1.0;
            s.cw = -p.b_nm_s_per_rad;
            s.w_on = 0.0;
            break;
        case PLANT_LOAD_TORQUE: s.c0 = p.load_torque_nm; break;
        case PLANT_LOAD_GENERATOR: s.cw = p.load_torque_nm / omega_ref; break;
        case PLANT_LOAD_FAN: s.cq = p.load_torque_nm / (omega_ref * omega_ref); break;
        default: break;
    }
}

const char *check_shaft(const plant_params_t &p) {
    auto bad = [](double v) { return !std::isfinite(v); };
    if (bad(p.j_kgm2) || p.j_kgm2 <= 0.0) return "j_kgm2 must be finite and > 0";
    if (bad(p.b_nm_s_per_rad) || p.b_nm_s_per_rad < 0.0) return "b_nm_s_per_rad must be finite and >= 0";
    if (bad(p.coulomb_nm) || p.coulomb_nm < 0.0) return "coulomb_nm must be finite and >= 0";
    return nullptr;
}

const char *check_load(const plant_params_t &p) {
    auto bad = [](double v) { return !std::isfinite(v); };
    if (p.load < PLANT_LOAD_SPEED || p.load > PLANT_LOAD_FAN)
        return "load must be PLANT_LOAD_SPEED, _TORQUE, _GENERATOR, _INERTIA or _FAN";
    if (bad(p.load_speed_rpm) || bad(p.load_torque_nm)) return "load_speed_rpm/load_torque_nm must be finite";
    if (p.load == PLANT_LOAD_GENERATOR && p.load_speed_rpm == 0.0)
        return "load_speed_rpm must be non-zero for PLANT_LOAD_GENERATOR (torque = T * n / n_ref)";
    if (p.load == PLANT_LOAD_FAN && p.load_speed_rpm == 0.0)
        return "load_speed_rpm must be non-zero for PLANT_LOAD_FAN (torque = T * (n / n_ref)^2)";
    return nullptr;
}

}  // namespace mech
