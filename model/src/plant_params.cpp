// plant_params.cpp - parameter sets of the plant (plant.h): the default PM drive (Hoang 2011 Table
// VIII machine, Table IV devices), the default induction machine (Casadei's 4 kW test machine) and
// Hoang's Table VII back-EMF harmonics. docs/plant.md, section 3, gives every value's source.
#include "plant.h"
#include "plant_defaults.h"

#include <cstring>

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kRpmToRadS = 2.0 * kPi / 60.0;
}  // namespace

extern "C" {

void plant_params_default(plant_params_t *p) {
    // Values and sources: plant_defaults.h.
    std::memset(p, 0, sizeof(*p));
    p->rs_ohm = PLANT_DEF_PM_RS_OHM;
    p->ls_h = PLANT_DEF_PM_LS_H;
    p->psi_m_wb = PLANT_DEF_PM_PSI_M_WB;
    p->pole_pairs = PLANT_DEF_PM_POLE_PAIRS;
    for (int x = 0; x < 3; ++x) p->emf_gain[x] = 1.0;
    p->j_kgm2 = PLANT_DEF_PM_J_KGM2;
    p->b_nm_s_per_rad = PLANT_DEF_PM_B_NM_S_PER_RAD;
    p->inverter = PLANT_INVERTER_SSTP;
    p->vdc_v = PLANT_DEF_VDC_V;
    p->r_dc_ohm = PLANT_DEF_R_DC_OHM;
    p->c_dc_f = PLANT_DEF_C_DC_F;
    p->v_ce_v = PLANT_DEF_V_CE_V;
    p->v_d_v = PLANT_DEF_V_D_V;
    p->r_on_ohm = PLANT_DEF_R_ON_OHM;
    p->dead_time_s = PLANT_DEF_DEAD_TIME_S;
    p->drops_enabled = 1;
    p->dead_time_enabled = 1;
    p->finite_dc_link = 1;
    p->load = PLANT_LOAD_INERTIA;
    p->load_speed_rpm = PLANT_DEF_SPEED_REF_RPM;
    p->load_torque_nm = PLANT_DEF_PM_RATED_TORQUE_NM;
    p->speed0_rpm = 0.0;
    p->theta_m0_rad = 0.0;
    p->max_step_s = PLANT_DEF_MAX_STEP_S;
    p->reconfig_relay = 0;
    p->relay_delay_s = PLANT_DEF_RELAY_DELAY_S;
}

void plant_params_im_default(plant_params_t *p) {
    // Values and sources: plant_defaults.h (the 220 V rescaling of Modelica Buildings
    // IM_5HP_400V_50Hz, docs/plant.md section 1).
    p->machine = PLANT_MACHINE_IM;
    p->rs_ohm = PLANT_DEF_IM_RS_OHM;
    p->rr_ohm = PLANT_DEF_IM_RR_OHM;
    p->lls_h = PLANT_DEF_IM_LLS_H;
    p->llr_h = PLANT_DEF_IM_LLR_H;
    p->lm_h = PLANT_DEF_IM_LM_H;
    p->pole_pairs = PLANT_DEF_IM_POLE_PAIRS;
    p->j_kgm2 = PLANT_DEF_IM_J_KGM2;
    p->b_nm_s_per_rad = PLANT_DEF_IM_B_NM_S_PER_RAD;
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

void plant_params_fstp_generator(plant_params_t *p, double torque_nm) {
    plant_params_default(p);
    p->inverter = PLANT_INVERTER_FSTP;
    plant_params_emf_table_vii(p);
    p->load = PLANT_LOAD_GENERATOR;
    p->load_speed_rpm = 1500.0;
    p->load_torque_nm = torque_nm;
}

}  // extern "C"
