// scripted_plant.cpp - see scripted_plant.hpp.
#include "scripted_plant.hpp"

#include <cstdio>
#include <cstring>

namespace scripted {
namespace {
std::function<void(double, plant_state_t*)> g_script;
std::string g_fail;
Log g_log;
} // namespace
void set_script(std::function<void(double, plant_state_t*)> state) { g_script = std::move(state); }
void fail_next_create(const std::string& msg) { g_fail = msg; }
Log& log() { return g_log; }
void reset()
{
    g_script = nullptr;
    g_fail.clear();
    g_log = Log{};
}
} // namespace scripted

struct plant {
    double t = 0.0;
    int sa = 0, sb = 0, sc = 0, en = 0;
    double va = 0.0, vb = 0.0;
};

extern "C" {

void plant_params_default(plant_params_t* p)
{
    std::memset(p, 0, sizeof *p);
    p->rs_ohm = 0.466;
    p->ls_h = 3.19e-3;
    p->psi_m_wb = 0.0928;
    p->pole_pairs = 1;
    p->emf_gain[0] = p->emf_gain[1] = p->emf_gain[2] = 1.0;
    p->j_kgm2 = 1e-4;
    p->inverter = PLANT_INVERTER_SSTP;
    p->vdc_v = 70.0;
    p->max_step_s = 5e-6;
}

plant_t* plant_create(const plant_params_t* p, char* err, size_t err_len)
{
    if (!scripted::g_fail.empty()) {
        std::snprintf(err, err_len, "%s", scripted::g_fail.c_str());
        scripted::g_fail.clear();
        return nullptr;
    }
    scripted::g_log.created.push_back(*p);
    return new plant();
}

void plant_destroy(plant_t* plant)
{
    ++scripted::g_log.destroyed;
    delete plant;
}

void plant_set_legs(plant_t* plant, int sa, int sb, int sc, int enable)
{
    plant->sa = sa;
    plant->sb = sb;
    plant->sc = sc;
    plant->en = enable;
}

// Records each leg's state at the start of the period (the scripted plant has no instants).
int plant_set_leg_edges(plant_t* plant, const plant_leg_edges_t legs[3], int enable)
{
    plant->sa = legs[0].state0;
    plant->sb = legs[1].state0;
    plant->sc = legs[2].state0;
    plant->en = enable;
    return 0;
}

void plant_set_voltage(plant_t* plant, double v_alpha_v, double v_beta_v)
{
    plant->va = v_alpha_v;
    plant->vb = v_beta_v;
}

void plant_set_load(plant_t* plant, plant_load_t load, double speed_rpm, double torque_nm)
{
    (void)plant;
    (void)load;
    (void)speed_rpm;
    ++scripted::g_log.load_changes;
    scripted::g_log.last_load_torque_nm = torque_nm;
}

void plant_advance(plant_t* plant, double dt_s)
{
    scripted::g_log.advances.push_back(
        scripted::Advance{plant->t, dt_s, plant->sa, plant->sb, plant->sc, plant->en, plant->va, plant->vb});
    plant->t += dt_s;
}

void plant_get_state(const plant_t* plant, plant_state_t* s)
{
    std::memset(s, 0, sizeof *s);
    s->t_s = plant->t;
    if (scripted::g_script) {
        scripted::g_script(plant->t, s);
        s->t_s = plant->t;
    }
}

// The core subset is, by contract (plant.h), plant_get_state's values of its fields.
void plant_get_state_core(const plant_t* plant, plant_state_t* s)
{
    plant_get_state(plant, s);
}

} // extern "C"

extern "C" {

// The sensed subset is, by contract (plant.h), the same values as plant_get_state's fields.
void plant_get_sensed(const plant_t* plant, plant_sensed_t* s)
{
    plant_state_t st;
    plant_get_state(plant, &st);
    s->t_s = st.t_s;
    s->i_a = st.i_a;
    s->i_b = st.i_b;
    s->i_c = st.i_c;
    s->theta_m_rad = st.theta_m_rad;
    s->omega_m_rad_s = st.omega_m_rad_s;
    s->vdc_v = st.vdc_v;
    s->vc_lo_v = st.vc_lo_v;
    s->vc_hi_v = st.vc_hi_v;
}

} // extern "C"

// Faults (plant.h): the scripted plant has no circuit; the commands are accepted and
// change nothing, and no desaturation ever latches.
extern "C" {

int plant_set_switch_fault(plant_t*, int, int, plant_switch_fault_t) { return 0; }
int plant_set_leg_open(plant_t*, int, int) { return 0; }
int plant_set_relay(plant_t*, int) { return 0; }
int plant_set_source_voltage(plant_t*, double) { return 0; }
int plant_set_resistances(plant_t*, double, double) { return 0; }
void plant_set_energy_accounts(plant_t*, int) {}
int plant_set_leg_override(plant_t*, int, plant_leg_override_t) { return 0; }
void plant_clear_desat(plant_t*) {}
void plant_get_fault_state(const plant_t*, plant_fault_state_t* f)
{
    f->desat_mask = 0;
    f->desat_t_s = -1.0;
    f->relay_cmd = 0;
    f->relay_closed = 0;
}

} // extern "C"
