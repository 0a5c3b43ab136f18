// plant_params.cpp - parameter sets of the plant (plant.h): the default PM drive (Hoang 2011 Table
// VIII machine, Table IV devices), the default induction machine (Casadei's 4 kW test machine) and
// Hoang's Table VII back-EMF harmonics. docs/plant.md, section 3, gives every value's source.
#include "plant.h"

#include <cstring>

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kRpmToRadS = 2.0 * kPi / 60.0;
}  // namespace

extern "C" {

void plant_params_default(plant_params_t *p) {
    std::memset(p, 0, sizeof(*p));
    // Hoang 2011 Table VIII.
    p->rs_ohm = 0.466;
    p->ls_h = 3.19e-3;
    p->psi_m_wb = 0.0928;
    p->pole_pairs = 1;
    for (int x = 0; x < 3; ++x) p->emf_gain[x] = 1.0;
    // Mechanics: docs/plant.md ("Inertia and friction") gives the derivation.
    p->j_kgm2 = 1.0e-4;
    p->b_nms = 4.8e-4;
    p->inverter = PLANT_INVERTER_SSTP;
    p->vdc_v = 70.0;
    p->r_dc_ohm = 0.2;
    p->c_dc_f = 2200e-6;
    // Hoang Table IV.
    p->v_ce_v = 0.9;
    p->v_d_v = 1.25;
    p->r_on_ohm = 0.075;
    p->dead_time_s = 2e-6;
    p->drops_enabled = 1;
    p->dead_time_enabled = 1;
    p->finite_dc_link = 1;
    p->load = PLANT_LOAD_INERTIA;
    p->load_speed_rpm = 1500.0;
    p->load_torque_nm = 0.3;
    p->speed0_rpm = 0.0;
    p->theta_m0_rad = 0.0;
    p->max_step_s = 50e-6;
}

void plant_params_im_default(plant_params_t *p) {
    // Modelica Buildings IM_5HP_400V_50Hz (4 kW, 400 V, 50 Hz, 4 poles; R_s 1.405, R_r 1.395 ohm,
    // L_ls = L_lr 5.839 mH, L_m 172.2 mH, J 0.0131 kg*m^2), every R and L times (220/400)^2 =
    // 0.3025 for 220 V (per-unit values, power and torque unchanged). docs/plant.md, section 1.
    const double k = 0.3025;  // (220/400)^2
    p->machine = PLANT_MACHINE_IM;
    p->rs_ohm = 1.405 * k;
    p->rr_ohm = 1.395 * k;
    p->lls_h = 5.839e-3 * k;
    p->llr_h = 5.839e-3 * k;
    p->lm_h = 172.2e-3 * k;
    p->pole_pairs = 2;
    p->j_kgm2 = 0.0131;
    p->b_nms = 0.0;
    p->ls_h = 0.0;
    p->psi_m_wb = 0.0;
    for (int x = 0; x < 3; ++x) {
        p->emf_gain[x] = 1.0;
        for (int h = 0; h < 3; ++h) p->emf_harm[x][h] = 0.0;
    }
}

void plant_params_emf_table_vii(plant_params_t *p) {
    // Hoang 2011 Table VII: phase back-EMF harmonics (V) at 1500 rpm.
    static const double fund[3] = {14.0868, 14.2880, 14.4254};
    static const double harm[3][3] = {{0.0488, 0.2385, 0.2274},
                                      {0.0321, 0.2483, 0.2375},
                                      {0.0364, 0.2209, 0.2472}};
    const double we = 1500.0 * kRpmToRadS * p->pole_pairs;
    for (int x = 0; x < 3; ++x) {
        p->emf_gain[x] = (p->psi_m_wb > 0.0) ? fund[x] / (we * p->psi_m_wb) : 0.0;
        for (int k = 0; k < 3; ++k) p->emf_harm[x][k] = harm[x][k] / fund[x];
    }
}

}  // extern "C"
