// plant_api.cpp - the C ABI of the plant (plant.h): creation and parameter checks, commands, the
// advance (integrator.cpp) and the reported state.
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <new>
#include <variant>

#include "plant.h"
#include "plant_impl.h"

using namespace plant_model;

namespace {

void set_err(char *err, size_t n, const char *msg) {
    if (err && n > 0) {
        std::snprintf(err, n, "%s", msg);
    }
}

const char *check_params(const plant_params_t *p) {
    if (!p) return "params: NULL";
    auto bad = [](double v) { return !std::isfinite(v); };
    if (bad(p->rs_ohm) || p->rs_ohm < 0.0) return "rs_ohm must be finite and >= 0";
    if (const char *m = Machines::check(*p)) return m;
    if (p->pole_pairs < 1 || p->pole_pairs > 64) return "pole_pairs must be in 1..64";
    for (int x = 0; x < 3; ++x) {
        if (bad(p->emf_gain[x]) || p->emf_gain[x] < 0.0) return "emf_gain[] must be finite and >= 0";
        for (int k = 0; k < 3; ++k)
            if (bad(p->emf_harm[x][k]) || std::fabs(p->emf_harm[x][k]) > 1.0)
                return "emf_harm[][] must be finite with |h| <= 1";
    }
    if (const char *m = mech::check_shaft(*p)) return m;
    if (const char *m = dclink::check_elements(*p)) return m;
    if (const char *m = check_inverter(*p)) return m;
    if (bad(p->max_step_s) || p->max_step_s <= 0.0 || p->max_step_s > 100e-6)
        return "max_step_s must be in (0, 100e-6]";
    if (const char *m = dclink::check_finite(*p)) return m;
    if (const char *m = mech::check_load(*p)) return m;
    if (p->reconfig_relay != 0 && p->reconfig_relay != 1) return "reconfig_relay must be 0 or 1";
    if (p->reconfig_relay && p->inverter != PLANT_INVERTER_SSTP)
        return "reconfig_relay: the relay reconfigures the six-switch inverter (PLANT_INVERTER_SSTP) only";
    if (bad(p->relay_delay_s) || p->relay_delay_s < 0.0 || p->relay_delay_s > 1.0)
        return "relay_delay_s must be in [0, 1]";
    if (bad(p->speed0_rpm) || bad(p->theta_m0_rad)) return "speed0_rpm/theta_m0_rad must be finite";
    return nullptr;
}

// The ideal inverter's voltages live in the leg coefficients: rebuild them.
void rebuild_legs(plant_t *pl) {
    build_leg_table(pl->p, pl->r_ph, pl->v_set_alpha, pl->v_set_beta, pl->any_fault ? &pl->faults : nullptr,
                    pl->leg_tab);
    set_legs_in_force(pl);
}

}  // namespace

extern "C" {

plant_t *plant_create(const plant_params_t *p, char *err, size_t err_len) {
    const char *msg = check_params(p);
    if (msg) {
        set_err(err, err_len, msg);
        return nullptr;
    }
    plant_t *pl = new (std::nothrow) plant_t();
    if (!pl) {
        set_err(err, err_len, "out of memory");
        return nullptr;
    }
    pl->p = *p;
    pl->pp = p->pole_pairs;
    Machines::make(*p, pl->machine);
    std::visit(
        [&](const auto &m) {
            pl->r_ph = m.circuit_resistance();
            const double l = m.circuit_inductance();
            pl->inv_l_2_3 = (2.0 / 3.0) / l;
            pl->inv_l_1_3 = (1.0 / 3.0) / l;
            pl->inv_l = 1.0 / l;
        },
        pl->machine);
    dclink::setup(*p, pl->link);
    mech::setup(*p, pl->shaft);
    mech::set_load_law(*p, p->load_speed_rpm * kRpmToRadS, pl->shaft);
    pl->y.setZero();
    pl->y[S_THETA] = p->theta_m0_rad;
    pl->y[S_OMEGA] = (p->load == PLANT_LOAD_SPEED ? p->load_speed_rpm : p->speed0_rpm) * kRpmToRadS;
    pl->y[S_VCLO] = pl->y[S_VCHI] = 0.5 * p->vdc_v;
    pl->t = 0.0;
    pl->last_dt = 0.0;
    pl->energy = true;
    LegSchedule &ls = pl->schedule;
    for (int x = 0; x < 3; ++x) {
        ls.cmd[x] = 0;
        ls.gate[x] = ls.gate_target[x] = GATE_OFF;
        ls.dead_end[x] = -1.0;
        ls.edge_n[x] = ls.edge_k[x] = 0;
        ls.override_mode[x] = PLANT_LEG_NORMAL;
        pl->mode.ph[x] = PH_BLOCKED;
    }
    ls.enable = 0;
    ls.hw_off = 0;
    std::memset(&pl->faults, 0, sizeof(pl->faults));
    pl->any_fault = false;
    pl->relay_cmd = 0;
    pl->relay_due = 0.0;
    pl->relay_pending = false;
    pl->desat_mask = 0;
    pl->desat_t = -1.0;
    pl->v_set_alpha = pl->v_set_beta = 0.0;
    std::memset(&pl->stats, 0, sizeof(pl->stats));
    rebuild_legs(pl);
    return pl;
}

void plant_destroy(plant_t *plant) { delete plant; }

// The 0/100 % case of plant_set_leg_edges: each leg's state at the start, no instant inside.
void plant_set_legs(plant_t *plant, int sa, int sb, int sc, int enable) {
    LegSchedule &ls = plant->schedule;
    ls.cmd[0] = sa ? 1 : 0;
    ls.cmd[1] = sb ? 1 : 0;
    ls.cmd[2] = sc ? 1 : 0;
    ls.enable = enable ? 1 : 0;
    ls.edge_n[0] = ls.edge_n[1] = ls.edge_n[2] = 0;
}

int plant_set_leg_edges(plant_t *plant, const plant_leg_edges_t legs[3], int enable) {
    if (!plant || !legs) return -1;
    for (int x = 0; x < 3; ++x) {
        const plant_leg_edges_t &L = legs[x];
        if (L.n < 0 || L.n > PLANT_LEG_EDGES_MAX) return -1;
        for (int k = 0; k < L.n; ++k) {
            if (!std::isfinite(L.t_s[k]) || L.t_s[k] < 0.0) return -1;
            if (k > 0 && !(L.t_s[k] >= L.t_s[k - 1])) return -1;
        }
    }
    LegSchedule &ls = plant->schedule;
    for (int x = 0; x < 3; ++x) {
        ls.cmd[x] = legs[x].state0 ? 1 : 0;
        ls.edge_n[x] = legs[x].n;
        for (int k = 0; k < legs[x].n; ++k) ls.edge_t[x][k] = legs[x].t_s[k];
    }
    ls.enable = enable ? 1 : 0;
    return 0;
}

void plant_set_voltage(plant_t *plant, double v_alpha_v, double v_beta_v) {
    plant->v_set_alpha = v_alpha_v;
    plant->v_set_beta = v_beta_v;
    rebuild_legs(plant);
}

void plant_set_load(plant_t *plant, plant_load_t load, double speed_rpm, double torque_nm) {
    plant->p.load = load;
    plant->p.load_speed_rpm = speed_rpm;
    plant->p.load_torque_nm = torque_nm;
    double omega_ref = speed_rpm * kRpmToRadS;
    if (load == PLANT_LOAD_SPEED) plant->y[S_OMEGA] = speed_rpm * kRpmToRadS;
    if ((load == PLANT_LOAD_GENERATOR || load == PLANT_LOAD_FAN) && speed_rpm == 0.0) omega_ref = 1e300;  // no load
    mech::set_load_law(plant->p, omega_ref, plant->shaft);
}

int plant_set_leg_override(plant_t *plant, int leg, plant_leg_override_t mode) {
    if (!plant || leg < 0 || leg > 2 || mode < PLANT_LEG_NORMAL || mode > PLANT_LEG_LOWER_ON) return -1;
    plant->schedule.override_mode[leg] = mode;
    return 0;
}

int plant_set_max_step(plant_t *plant, double max_step_s, char *err, size_t err_len) {
    plant_params_t q = plant->p;
    q.max_step_s = max_step_s;
    const char *msg = check_params(&q);
    if (msg) {
        set_err(err, err_len, msg);
        return -1;
    }
    plant->p.max_step_s = max_step_s;
    return 0;
}

void plant_advance(plant_t *pl, double dt_s) {
    if (!(dt_s > 0.0)) return;
    advance(pl, dt_s);
}

namespace {
// plant_get_state_core()'s fields (plant.h); returns the machine's report for the rest.
plant_model::MachineReport state_core(const plant_t *pl, plant_state_t *s) {
    const Vec &y = pl->y;
    s->t_s = pl->t;
    s->i_a = y[S_IA];
    s->i_b = y[S_IB];
    s->i_c = y[S_IC];
    // Amplitude-invariant Clarke (Hoang eqs. 4-5).
    s->i_alpha_a = (2.0 * s->i_a - s->i_b - s->i_c) * (1.0 / 3.0);
    s->i_beta_a = (s->i_b - s->i_c) * (1.0 / kSqrt3);
    MachineReport r;
    std::visit([&](const auto &m) { m.report(y, s->i_alpha_a, s->i_beta_a, r); }, pl->machine);
    s->psi_alpha_wb = r.psi_alpha;
    s->psi_beta_wb = r.psi_beta;
    s->psi_r_alpha_wb = r.psi_r_alpha;
    s->psi_r_beta_wb = r.psi_r_beta;
    s->theta_m_rad = y[S_THETA];
    s->omega_m_rad_s = y[S_OMEGA];
    s->speed_rpm = y[S_OMEGA] * (1.0 / kRpmToRadS);
    s->te_nm = r.te;
    s->i2_int_a2s = y[S_I2];
    s->q_a_as = y[S_QA];
    s->q_b_as = y[S_QB];
    return r;
}
}  // namespace

void plant_get_state_core(const plant_t *plant, plant_state_t *s) { (void)state_core(plant, s); }

void plant_get_state(const plant_t *plant, plant_state_t *s) {
    plant_t *pl = const_cast<plant_t *>(plant);  // mode selection counts; the state is unchanged
    // Every field is assigned below or by state_core() (no memset: this runs once per control period).
    static_assert(offsetof(plant_state_t, q_b_as) == 37 * sizeof(double) &&
                      sizeof(plant_state_t) <= 38 * sizeof(double),
                  "plant_state_t changed: assign the new fields");
    const plant_params_t &p = pl->p;
    const Vec &y = pl->y;
    const double theta_e = pl->pp * y[S_THETA];
    const MachineReport r = state_core(pl, s);
    // Wrap to [0, 2 pi): floor by truncation (|turns| < 2^53 for any finite run).
    const double turns = theta_e * (0.5 / kPi);
    double whole = static_cast<double>(static_cast<long long>(turns));
    if (whole > turns) whole -= 1.0;
    double th = theta_e - 2.0 * kPi * whole;
    if (th >= 2.0 * kPi) th -= 2.0 * kPi;
    if (th < 0.0) th = 0.0;
    s->theta_e_rad = th;
    s->tload_nm = mech::load_torque(pl->shaft, y[S_OMEGA], s->te_nm);  // as in the right-hand side
    if (pl->link.rc.on) {
        link_terminals(pl, s->vc_lo_v, s->vc_hi_v);
    } else {
        s->vc_lo_v = y[S_VCLO];
        s->vc_hi_v = y[S_VCHI];
    }
    s->vdc_v = s->vc_lo_v + s->vc_hi_v;
    if (pl->last_dt > 0.0) {
        const double inv_dt = 1.0 / pl->last_dt;
        s->v_a0_v = y[S_IVA0] * inv_dt;
        s->v_b0_v = y[S_IVB0] * inv_dt;
        s->v_c0_v = y[S_IVC0] * inv_dt;
        // Mean stator voltage: Hoang eqs. (1)-(5) applied to the mean terminal voltages (the
        // transform is linear, so this is the mean of the instantaneous alpha/beta voltage).
        s->v_alpha_v = (2.0 * s->v_a0_v - s->v_b0_v - s->v_c0_v) * (1.0 / 3.0);
        s->v_beta_v = (s->v_b0_v - s->v_c0_v) * (1.0 / kSqrt3);
    } else {
        s->v_a0_v = s->v_b0_v = s->v_c0_v = s->v_alpha_v = s->v_beta_v = 0.0;
    }
    s->e_dc_in_j = y[S_EDC];
    s->e_copper_j = y[S_ECU];
    s->e_device_j = y[S_EDEV];
    s->e_friction_j = y[S_EFRIC];
    s->e_load_j = y[S_ELOAD];
    s->e_rdc_j = y[S_ERDC];
    s->e_link_j = y[S_ELINK];
    s->e_magnetic_j = r.e_magnetic;
    s->e_kinetic_j = 0.5 * p.j_kgm2 * y[S_OMEGA] * y[S_OMEGA];
    s->e_capacitor_j = dclink::capacitor_energy(p, pl->link, y[S_VCLO], y[S_VCHI]);
    s->blocked_mask = blocked_mask(pl);
}

void plant_get_stats(const plant_t *plant, plant_stats_t *st) { *st = plant->stats; }

// Same expressions as the corresponding fields of plant_get_state(), so the values are identical.
void plant_get_sensed(const plant_t *plant, plant_sensed_t *s) {
    const Vec &y = plant->y;
    s->t_s = plant->t;
    s->i_a = y[S_IA];
    s->i_b = y[S_IB];
    s->i_c = y[S_IC];
    s->theta_m_rad = y[S_THETA];
    s->omega_m_rad_s = y[S_OMEGA];
    if (plant->link.rc.on) {
        link_terminals(plant, s->vc_lo_v, s->vc_hi_v);
    } else {
        s->vc_lo_v = y[S_VCLO];
        s->vc_hi_v = y[S_VCHI];
    }
    s->vdc_v = s->vc_lo_v + s->vc_hi_v;
}

int plant_set_switch_fault(plant_t *plant, int leg, int upper, plant_switch_fault_t mode) {
    if (!plant || leg < 0 || leg > 2 || (upper != 0 && upper != 1) || mode < PLANT_SWITCH_OK ||
        mode > PLANT_SWITCH_SHORT || plant->p.inverter == PLANT_INVERTER_IDEAL ||
        (plant->p.inverter == PLANT_INVERTER_FSTP && leg == 0))
        return -1;
    plant->faults.sw[leg][upper] = mode;
    plant->any_fault = true;
    rebuild_legs(plant);
    return 0;
}

int plant_set_leg_open(plant_t *plant, int leg, int open) {
    if (!plant || leg < 0 || leg > 2 || plant->p.inverter == PLANT_INVERTER_IDEAL ||
        (plant->p.inverter == PLANT_INVERTER_FSTP && leg == 0))
        return -1;
    plant->faults.open[leg] = open ? 1 : 0;
    plant->any_fault = true;
    if (open && plant->faults.relay_closed != leg + 1 && plant->y[S_IA + leg] != 0.0) {
        // The phase's current is cut; the other two keep sum(i) = 0.
        const double i = plant->y[S_IA + leg];
        plant->y[S_IA + leg] = 0.0;
        plant->y[S_IA + (leg + 1) % 3] += 0.5 * i;
        plant->y[S_IA + (leg + 2) % 3] += 0.5 * i;
    }
    rebuild_legs(plant);
    return 0;
}

int plant_set_relay(plant_t *plant, int phase) {
    if (!plant || !plant->p.reconfig_relay || phase < 0 || phase > 3) return -1;
    if (phase == plant->relay_cmd) return 0;
    plant->relay_cmd = phase;
    plant->any_fault = true;
    // The contacts move in the advance (integrator.cpp), at its start at the earliest: after the
    // gate commands of that advance, so a leg gated off together with the coil command is off
    // when a zero-delay relay closes.
    plant->relay_due = plant->t + plant->p.relay_delay_s;
    plant->relay_pending = true;
    return 0;
}

int plant_set_source_voltage(plant_t *plant, double vdc_v) {
    if (!plant || !std::isfinite(vdc_v) || vdc_v <= 0.0) return -1;
    plant->p.vdc_v = vdc_v;
    dclink::setup(plant->p, plant->link);
    if (!plant->p.finite_dc_link || plant->p.inverter == PLANT_INVERTER_IDEAL)
        plant->y[S_VCLO] = plant->y[S_VCHI] = 0.5 * vdc_v;
    return 0;
}

int plant_set_resistances(plant_t *plant, double rs_ohm, double rr_ohm) {
    if (!plant || !std::isfinite(rs_ohm) || rs_ohm <= 0.0 || !std::isfinite(rr_ohm) || rr_ohm <= 0.0) return -1;
    plant->p.rs_ohm = rs_ohm;
    if (plant->p.machine == PLANT_MACHINE_IM) plant->p.rr_ohm = rr_ohm;
    Machines::make(plant->p, plant->machine);  // the machine's constants only: its state lives in y
    std::visit([&](const auto &m) { plant->r_ph = m.circuit_resistance(); }, plant->machine);
    rebuild_legs(plant);
    return 0;
}

void plant_set_energy_accounts(plant_t *plant, int on) { plant->energy = on != 0; }

void plant_clear_desat(plant_t *plant) {
    plant->desat_mask = 0;
    plant->desat_t = -1.0;
    plant->schedule.hw_off = 0;
}

void plant_get_fault_state(const plant_t *plant, plant_fault_state_t *f) {
    f->desat_mask = plant->desat_mask;
    f->desat_t_s = plant->desat_t;
    f->relay_cmd = plant->relay_cmd;
    f->relay_closed = plant->faults.relay_closed;
}

int plant_set_phase_currents(plant_t *plant, double i_a, double i_b, double i_c) {
    const double sum = i_a + i_b + i_c;
    const double mag = std::fabs(i_a) + std::fabs(i_b) + std::fabs(i_c);
    if (!std::isfinite(mag) || std::fabs(sum) > 1e-12 * mag) return -1;
    plant->y[S_IA] = i_a;
    plant->y[S_IB] = i_b;
    plant->y[S_IC] = i_c;
    return 0;
}

}  // extern "C"
