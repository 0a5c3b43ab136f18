// ref_dtc.h - double-precision reference DTC controller (SI units), the golden model for the
// fixed-point firmware in SIL tests. Same equations, same ordering, no fixed-point effects.
//
// Papers: Hoang, Zhu, Foster 2011 (SSTP/FSTP DTC of a PM BLAC machine, drop compensation) and
// Casadei et al. 2006 (switching tables). Every function cites the equation / table it implements.
//
// Conventions
//  * Leg state 1 = upper device on. SSTP vectors V1..V6 = 100, 110, 010, 011, 001, 101 (V_k at
//    (k-1) * 60 deg, Casadei eq. 2 / Fig. A2), V0 = 000, V7 = 111.
//  * FSTP vectors V1..V4 = (S_B S_C) 00, 10, 11, 01 (Hoang Table I: 0, 90, 180, 270 deg).
//  * Amplitude-invariant Clarke transform (Hoang eqs. 4-5).
//  * Sign of a current for the compensation tables: i >= 0 counts as "+".
#ifndef DTC_MODEL_REF_DTC_H
#define DTC_MODEL_REF_DTC_H

#include <string>

#include "plant_defaults.h"

namespace dtc_ref {

enum class Topology { SSTP, FSTP };
enum class FluxEstimator { CURRENT_MODEL, VOLTAGE_MODEL };
enum class DropComp {
    NONE,          // Hoang eqs. (15)-(16) with the ideal reconstructed voltage
    SSTP_EQUAL,    // SSTP, equal device/diode drop v_f (Hoang ref. [29]) + R_on, every phase
    FSTP_SIMPLE,   // FSTP, Hoang Table V (eqs. 35-36) + the R_on terms of eqs. (37)-(38)
    FSTP_PROPOSED  // FSTP, Hoang Table VI (Table III + eqs. 33-34) + the R_on terms of (37)-(38)
};
enum class SwitchingTable {
    CASADEI_T1,  // SSTP, Casadei Table 1, three-level torque comparator, null 0/7 by transitions
    ST_A, ST_B, ST_C, ST_D,  // SSTP, Casadei Table 3, two-level comparators
    HOANG_FSTP   // FSTP, Hoang Table II
};
enum class ControlMode { TORQUE, SPEED };

struct Params {
    Topology topology = Topology::SSTP;
    FluxEstimator estimator = FluxEstimator::CURRENT_MODEL;
    DropComp comp = DropComp::NONE;
    SwitchingTable table = SwitchingTable::CASADEI_T1;
    ControlMode mode = ControlMode::SPEED;
    // Defaults: plant_defaults.h (values and sources).
    double ts_s = PLANT_DEF_TS_S;                       // torque/flux loop period
    int speed_divider = PLANT_DEF_SPEED_LOOP_DIVIDER;   // speed loop every N-th step
    // Machine.
    double rs_ohm = PLANT_DEF_PM_RS_OHM;
    double ls_h = PLANT_DEF_PM_LS_H;
    double psi_m_wb = PLANT_DEF_PM_PSI_M_WB;
    int pole_pairs = PLANT_DEF_PM_POLE_PAIRS;
    // Inverter model used by the compensation.
    double v_ce_v = PLANT_DEF_V_CE_V;
    double v_d_v = PLANT_DEF_V_D_V;
    double r_on_ohm = PLANT_DEF_R_ON_OHM;
    double v_f_v = PLANT_DEF_V_F_V;  // equal-drop value for SSTP_EQUAL / FSTP_SIMPLE
    // Sign of the FSTP alpha R_on term. Physics (a passive R_on in legs B and C of a star-connected
    // machine, verified against the plant) gives -R_on i_alpha / 3; Hoang eqs. (26)/(37) print
    // +R_on i_alpha / 3. false = physical sign (default), true = as printed.
    bool ron_alpha_as_printed = false;
    // Voltage-model estimator: first-order low-pass instead of a pure integrator (Hoang Sec. IV).
    double lpf_wc_rad_s = PLANT_DEF_LPF_CUTOFF_RAD_S;
    // The leg states that drove the period just elapsed were output this many steps ago. With a
    // HAL that applies a command at the next period boundary (hal.h), that is 2.
    int voltage_delay_periods = 2;
    // References and hysteresis bands (Hoang eqs. 13-14; Hoang uses zero bands).
    double psi_ref_wb = PLANT_DEF_FLUX_REF_WB;
    double band_psi_wb = 0.0;
    double band_te_nm = 0.0;
    // Speed PI (mechanical rad/s in, N*m out), limits. Default gains: the default rig's inertia
    // and speed bandwidth with the rule of the SIL and the SI converter (Kp = J wc, Ki = Kp wc / 4).
    double kp_nm_s_rad = PLANT_DEF_PM_J_KGM2 * 2.0 * PLANT_DEF_PI * PLANT_DEF_SPEED_BW_HZ;
    double ki_nm_rad = PLANT_DEF_PM_J_KGM2 * (2.0 * PLANT_DEF_PI * PLANT_DEF_SPEED_BW_HZ) *
                       (2.0 * PLANT_DEF_PI * PLANT_DEF_SPEED_BW_HZ) / 4.0;
    double te_max_nm = PLANT_DEF_TORQUE_LIMIT_NM;
};

struct Meas {
    double i_a = 0, i_b = 0, i_c = 0;  // phase currents, A (i_c may be -(i_a+i_b))
    double vdc_v = 0;                  // DC-link voltage, V
    bool have_vc = false;              // FSTP: capacitor voltages measured
    double vc_lo_v = 0, vc_hi_v = 0;   // lower / upper capacitor, V
    double theta_e_rad = 0;            // electrical rotor angle (current model)
    double omega_m_rad_s = 0;          // mechanical speed (speed loop)
};

struct Out {
    int sa = 0, sb = 0, sc = 0;  // leg states for the next period (FSTP: sa = 0, unused)
    int vector = 0;              // SSTP 0..7, FSTP 1..4
    int sector = 1;              // SSTP 1..6, FSTP 1..4
    int c_psi = 1;               // flux demand: 1 increase, 0 decrease (Hoang eq. 13)
    int c_te = 1;                // torque demand: 1 / 0 (Hoang eq. 14) or +1 / 0 / -1 (Casadei Table 1)
    double i_alpha = 0, i_beta = 0;
    double v_alpha = 0, v_beta = 0;  // compensated voltage used by the voltage model (last period)
    double psi_alpha = 0, psi_beta = 0, psi_mag = 0;
    double te_nm = 0, te_ref_nm = 0;
};

// ---- Building blocks (pure functions; each is tested against the papers' tables) ----

// Hoang eqs. (4)-(5), amplitude invariant, for a three-phase set (zero sequence removed).
void clarke(double a, double b, double c, double &alpha, double &beta);
// Phase voltages from phase-to-zero voltages, Hoang eqs. (1)-(3).
void phase_from_pole(const double v0[3], double vn[3]);
// SSTP ideal phase voltages from leg states (Casadei eq. 2 / Fig. A2 via Hoang eqs. 1-3).
void sstp_phase_voltages(int sa, int sb, int sc, double vdc, double vn[3]);
// FSTP ideal phase voltages from leg states, Hoang eqs. (17)-(19) (S_A = 1/2).
void fstp_phase_voltages(int sb, int sc, double vdc, double vn[3]);
// FSTP phase voltages with measured capacitor voltages: v_a0 = vc_lo, v_x0 = S_x (vc_lo + vc_hi),
// then Hoang eqs. (1)-(3). Equal to Hoang eqs. (17)-(19) when vc_lo = vc_hi.
void fstp_phase_voltages_mid(int sb, int sc, double vc_lo, double vc_hi, double vn[3]);
// Hoang Table III: forward drop v_f of one leg for switch state s and current i (i >= 0: "+").
double leg_forward_drop(int s, double i, double v_ce, double v_d);
// Hoang Table V / eqs. (35)-(36): FSTP simple compensation (equal drop v_f).
void fstp_drop_simple(double i_b, double i_c, double v_f, double &vf_alpha, double &vf_beta);
// Hoang Table VI: Table III per leg, then eqs. (33)-(34).
void fstp_drop_proposed(int sb, int sc, double i_b, double i_c, double v_ce, double v_d,
                        double &vf_alpha, double &vf_beta);
// SSTP equal-drop compensation: v_f sign(i_x) per leg, through Hoang eqs. (1)-(5) (Hoang ref. [29]).
void sstp_drop_equal(double i_a, double i_b, double i_c, double v_f, double &vf_alpha, double &vf_beta);
// Sector of the flux angle: SSTP 1..6 with sector k centred on V_k (Casadei Table 1); FSTP 1..4
// quadrants, sector I = [0, 90) deg (Hoang Fig. 3 / Table II).
int sector_sstp(double psi_alpha, double psi_beta);
int sector_fstp(double psi_alpha, double psi_beta);
// Two-level hysteresis (Hoang eqs. 13-14): 1 if err > band/2, 0 if err < -band/2, else prev.
int hysteresis2(double err, double band, int prev);
// Three-level torque comparator for Casadei Table 1 (+1 / 0 / -1), see docs/plant.md.
int hysteresis3(double err, double band, int prev);
// Casadei Table 1: c_psi in {+1, -1} (here 1 / 0 = increase / decrease), c_te in {+1, 0, -1};
// returns the SSTP vector 0..7; the null is 0 or 7, whichever needs fewer leg transitions from
// prev_legs (Casadei Sec. 5).
int table_casadei1(int sector, int c_psi, int c_te, const int prev_legs[3]);
// Casadei Table 3 (ST-A..ST-D), two-level demands d_psi, d_te in {1, 0}.
int table_casadei3(SwitchingTable st, int sector, int d_psi, int d_te, const int prev_legs[3]);
// Hoang Table II: FSTP vector 1..4.
int table_hoang2(int sector, int d_psi, int d_te);
void sstp_vector_legs(int vector, int legs[3]);
void fstp_vector_legs(int vector, int &sb, int &sc);
// FSTP legs (S_B, S_C) of the vector whose direction is nearest to angle_rad (Hoang Table I: V1
// 0, V2 90, V3 180, V4 270 deg): the open-loop drive patterns of the plant tests and benchmark.
void fstp_vector_towards(double angle_rad, int &sb, int &sc);

// ---- The controller ----
class Controller {
public:
    // Returns 0 or a negative code; message() says which parameter and why.
    int init(const Params &p);
    const std::string &message() const { return msg_; }
    // Clears estimator, comparators, PI; the voltage-model flux starts at psi_m e^{j theta_e0}.
    void reset(double theta_e0_rad = 0.0);
    void set_speed_ref(double omega_m_rad_s) { omega_ref_ = omega_m_rad_s; }
    void set_torque_ref(double te_nm) { te_ref_cmd_ = te_nm; }
    // One control period: measurement at this instant -> leg states for the next period.
    Out step(const Meas &m);
    const Params &params() const { return p_; }

private:
    Params p_{};
    std::string msg_;
    double omega_ref_ = 0.0, te_ref_cmd_ = 0.0, te_ref_ = 0.0;
    double integ_ = 0.0;
    int div_count_ = 0;
    double psi_a_ = 0.0, psi_b_ = 0.0;
    double i_alpha_prev_ = 0.0, i_beta_prev_ = 0.0, i_prev_[3] = {0, 0, 0};
    double vdc_prev_ = 0.0, vc_lo_prev_ = 0.0, vc_hi_prev_ = 0.0;
    // Keeps the samples of this period (currents, the alpha/beta ones, link and capacitor
    // voltages) for the next: the "previous" values of the voltage reconstruction.
    void keep_samples(const Meas &m, double i_alpha, double i_beta);
    bool first_ = true;
    int hist_[4][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}};  // hist_[d] = output d steps ago
    int c_psi_ = 1, c_te_ = 1;
    Out last_{};
};

}  // namespace dtc_ref

#endif  // DTC_MODEL_REF_DTC_H
