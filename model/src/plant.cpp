// plant.cpp - surface PM BLAC machine + SSTP/FSTP inverter + DC link + mechanics (SI units); the
// induction machine (machine_im.h) enters the same per-phase circuit as sigma*L_s, R_eff and a
// rotor-flux EMF, with its two rotor-flux states (S_PSIRA, S_PSIRB).
//
// Physics (docs/plant.md has the derivations and the error analysis):
//  * Machine: Hoang 2011 eqs. (6)-(10) in the stationary frame, written per phase so that the
//    per-phase back-EMF gains and 3rd/5th/7th harmonics (Hoang Table VII) enter naturally:
//      L_s di_x/dt = v_x0 - v_n0 - R_s i_x - e_x,   e_x = omega_e dpsi_pm,x/dtheta_e,
//    star connection, isolated neutral: sum(i_x) = 0 and v_n0 follows (Hoang eqs. 1-3).
//    Torque T_e = p sum(i_x dpsi_pm,x/dtheta_e), which for sinusoidal balanced EMF is exactly
//    Hoang eq. (10), 1.5 p (psi_alpha i_beta - psi_beta i_alpha).
//  * Inverter legs: every conducting path is (rail voltage) - v_f - R_on i with v_f from Hoang
//    Table III chosen by gate state and current sign (Hoang eq. 20). During dead time / gates
//    off the current sign picks the diode. At i = 0 a leg's voltage is the whole interval between
//    its two branches; a phase whose floating terminal voltage lies inside that interval stays at
//    exactly zero current (no chatter). This is a small complementarity problem solved by
//    enumeration whenever a current sits at zero.
//  * FSTP: phase A on the mid-point of two capacitors fed by a DC source with internal resistance.
//  * Integration: classical RK4 on sub-steps that land exactly on every switching and dead-time
//    edge and on every located current zero crossing / zero-current release (Illinois root
//    finding on the step's own solution); the explicit midpoint rule on a dead-time segment no
//    longer than max_step/16. Between events the right-hand side is smooth. docs/plant.md,
//    section 2, gives the error of each part; section 7 the cost.
#include "plant.h"
#include "plant_defaults.h"

#include <Eigen/Core>

#include "dc_link.h"
#include "machine_im.h"
#include "mechanics.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <new>

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSqrt3 = 1.73205080756887729353;
constexpr double kRpmToRadS = 2.0 * kPi / 60.0;

// State vector layout.
enum : int {
    S_IA = 0, S_IB, S_IC, S_THETA, S_OMEGA, S_VCLO, S_VCHI, S_PSIRA, S_PSIRB,
    S_EDC, S_ECU, S_EDEV, S_EFRIC, S_ELOAD, S_ERDC, S_IVA0, S_IVB0, S_IVC0, S_ELINK,
    NS
};
// The first ND states are dynamic (they enter the right-hand side); the rest are quadratures
// (energy accounts and terminal-voltage integrals) that RK4 integrates with the same weights, so
// the intermediate stage states only need their first ND entries.
constexpr int ND = S_PSIRB + 1;
using Vec = Eigen::Matrix<double, NS, 1>;

enum Rail : int { RAIL_ZERO = 0, RAIL_PLUS = 1, RAIL_MID = 2, RAIL_SRC = 3 };
enum Gate : int { GATE_LOWER = 0, GATE_UPPER = 1, GATE_OFF = 2 };

struct Path {
    int rail;   // which node the phase terminal is tied to through the conducting device
    double d;   // forward drop v_f (Hoang Table III sign convention): v_x0 = rail - d - r*i
    double r;   // on-state resistance in the path
};

// Right-hand-side coefficients of one phase in one PhaseMode (built with the legs, so a mode
// change only copies three of these).
struct PhaseCoef {
    double cond;          // 1 conducting, 0 blocked
    double a_lo, a_hi, c; // path voltage = a_lo vc_lo + a_hi vc_hi + c (c includes -v_f)
    double r;             // device resistance in the path
    double rtot;          // R_s + r
    double dev_d;         // v_f of the path, for the device loss term dev (d + r i) i
    double dev;           // 1 for a conducting device path
    double plus, mid, src;  // 1 if the conducting path is tied to that node
    double pd, pr;        // dev * dev_d, dev * r: device loss (pd + pr i) i
};

struct Mode {
    int ph[3];  // PhaseMode per phase
};

struct Leg {
    Path pos, neg;  // path for i > 0 (out of the leg into the machine) and for i < 0
    PhaseCoef coef[3];  // per PhaseMode
    bool sign_dep;  // the two paths differ: the voltage jumps at i = 0
    bool device;    // a semiconductor path (losses accounted); false for mid-point / ideal source
};

enum PhaseMode : int { PH_POS = 0, PH_NEG = 1, PH_BLOCKED = 2 };

// Per-step constants of the conduction mode, so the right-hand side is branch-light.
struct Prep {
    int nk;             // conducting phases
    double inv_nk;
    const PhaseCoef *ph[3];  // into the legs in force (valid until the next build_legs)
};

// Mode-independent linear forms (set in derive(), so the right-hand side has no branches on the
// inverter, DC link or load kind):
    //   T_load = ld_c0 + ld_cw omega + ld_cte T_e;  domega/dt = w_on (T_e - b omega - T_load) / J
    //   i_s = is_g (vdc - vc_lo - vc_hi)
    //   dvc_hi/dt = hi_s i_s - hi_p i_plus;  dvc_lo/dt = lo_s i_s - lo_p i_plus - lo_m i_mid
    //   p_dc = pdc_s i_s + pdc_st ((vc_lo + vc_hi) i_plus + vc_lo i_mid) + pdc_src p_src
struct Glob {
    double ld_c0, ld_cw, ld_cte, w_on;
    double ld_cq;  // fan load: T_load += ld_cq omega |omega| (used only when fan_on)
    double is_g, hi_s, hi_p, lo_s, lo_p, lo_m;
    double pdc_s, pdc_st, pdc_src, r_dc;
};


struct Aux {
    double te, tload, vn0;
    double vx0[3];
    double e[3];
};

inline double path_v(const Path &p, const double *rail_v) { return rail_v[p.rail] - p.d; }

}  // namespace

struct plant {
    plant_params_t p;
    // Derived constants.
    double omega_load_ref;  // rad/s for the generator law
    double pp;              // pole pairs as a double
    double inv_l_2_3, inv_l_1_3;  // (2/3) / L_s, (1/3) / L_s
    double c_lo, c_hi;      // capacitances (SSTP: one capacitor of 2*c_dc_f, split in the report)
    bool has_harm;
    double flux_amp[3][4];  // psi_m * gain * (1, h3/3, h5/5, h7/7)
    double emf_amp[3][4];   // psi_m * gain * (1, h3, h5, h7): -dpsi/dtheta amplitudes
    // Commands.
    int cmd[3];
    int enable;
    double v_set_alpha, v_set_beta;
    int override_mode[3];
    // Per-leg gate timeline.
    int gate[3];         // gate state in force now
    int gate_target[3];  // gate state after the dead time
    double dead_end[3];  // absolute time the dead time ends (<= t: none)
    // Switching instants of the next advance (plant_set_leg_edges): leg x's command toggles at
    // edge_t[x][k], k < edge_n[x], seconds from the advance's start; during the advance
    // edge_abs[x][k] are absolute times and edge_k[x] the next one due.
    int edge_n[3];
    int edge_k[3];
    double edge_t[3][PLANT_LEG_EDGES_MAX];
    double edge_abs[3][PLANT_LEG_EDGES_MAX];
    int edges_left;      // edges still to apply in this advance (0: plant_set_legs form)
    // Integrator.
    double t;
    Vec y;
    double last_dt;
    Mode mode;
    Leg leg_tab[3][3];     // [leg][Gate]: paths and coefficients, built at creation
    const Leg *legs[3];    // legs in force: &leg_tab[x][gate[x]]
    // sin/cos cache for the step being taken (advanced by a short rotation from step to step and
    // re-synchronised with the library sin/cos every 256 steps).
    double th0, c0, s0;
    unsigned sync_count;
    // Reciprocals used in the right-hand side.
    double inv_l, inv_j, inv_c_lo, inv_c_hi, inv_rdc;
    Prep prep;
    Glob g;
    dclink::LinkRC link;
    bool coulomb_on;  // coulomb_nm > 0
    bool fan_on;      // PLANT_LOAD_FAN
    // Machine seen by the per-phase circuit: L di/dt = v - r_ph i - e. PM: L_s, R_s and the
    // magnet's EMF; IM (machine_im.h): sigma L_s, R_eff and the rotor-flux EMF.
    bool im;
    im::Const imc;
    double r_ph, l_ph;
    bool prep_valid;  // prep matches prep_mode and the current legs / source voltages
    Mode prep_mode;
    // Taylor coefficients (in delta = theta_e - th0) of dpsi_pm,x/dtheta_e:
    // dpsi_x(th0 + d) = sum_k emf_tc[x][k] d^k, k = 0..7; used while n_max |d| < kTcRange.
    Eigen::Array4d emf_tc[8];  // [k], lane x = phase x (lane 3 zero): the three polynomials run as
                               // SIMD packets
    double tc_range;
    // The PM flux at the expansion centre as phasors, lane h = harmonic (1, 3, 5, 7): per phase x
    // flux_amp * (cos, sin)(n (th0 - phi_x)) and emf_amp * (cos, sin)(...); plant_get_state
    // rotates them by n (theta - th0) (exact, see pm_flux_centre()).
    Eigen::Array4d ph_fc[3], ph_fs[3], ph_ac[3], ph_as[3];
    bool tc_valid;
    bool short_seg;  // the step being taken is a short dead-time segment (midpoint rule)
    plant_stats_t stats;
};

namespace {

void set_err(char *err, size_t n, const char *msg) {
    if (err && n > 0) {
        std::snprintf(err, n, "%s", msg);
    }
}

void derive(plant_t *pl) {
    const plant_params_t &p = pl->p;
    pl->omega_load_ref = p.load_speed_rpm * kRpmToRadS;
    pl->pp = p.pole_pairs;
    pl->im = p.machine == PLANT_MACHINE_IM;
    if (pl->im) {
        pl->imc = im::derive(p);
        pl->r_ph = pl->imc.r_eff;
        pl->l_ph = pl->imc.l_eff;
    } else {
        pl->r_ph = p.rs_ohm;
        pl->l_ph = p.ls_h;
    }
    pl->inv_l_2_3 = (2.0 / 3.0) / pl->l_ph;
    pl->inv_l_1_3 = (1.0 / 3.0) / pl->l_ph;
    if (p.inverter == PLANT_INVERTER_SSTP) {
        pl->c_lo = pl->c_hi = 2.0 * p.c_dc_f;
    } else {
        pl->c_lo = pl->c_hi = p.c_dc_f;
    }
    pl->inv_l = 1.0 / pl->l_ph;
    pl->inv_j = 1.0 / p.j_kgm2;
    pl->inv_c_lo = (pl->c_lo > 0.0) ? 1.0 / pl->c_lo : 0.0;
    pl->inv_c_hi = (pl->c_hi > 0.0) ? 1.0 / pl->c_hi : 0.0;
    pl->inv_rdc = (p.r_dc_ohm > 0.0) ? 1.0 / p.r_dc_ohm : 0.0;
    pl->coulomb_on = p.coulomb_nm > 0.0;
    dclink::LinkRC &lk = pl->link;
    lk = dclink::LinkRC{};
    lk.on = p.finite_dc_link && p.inverter != PLANT_INVERTER_IDEAL && (p.r_bal_ohm > 0.0 || p.esr_ohm > 0.0);
    lk.fstp = p.inverter == PLANT_INVERTER_FSTP;
    lk.esr = p.esr_ohm > 0.0;
    lk.esr_ohm = p.esr_ohm;
    lk.vdc = p.vdc_v;
    lk.inv_c_lo = pl->inv_c_lo;
    lk.inv_c_hi = pl->inv_c_hi;
    lk.g_s = pl->inv_rdc;
    lk.g_e = lk.esr ? 1.0 / p.esr_ohm : 0.0;
    lk.g_b = (p.r_bal_ohm > 0.0) ? 1.0 / p.r_bal_ohm : 0.0;
    if (lk.on && lk.esr) {
        const double a = lk.g_s + lk.g_e + lk.g_b, c = lk.g_e + lk.g_b;
        const double det = c * (c - 2.0 * a);  // det [[a, -c], [c, -2c]] = -2ac + c^2
        lk.m11 = -2.0 * c / det;
        lk.m12 = c / det;
        lk.m21 = -c / det;
        lk.m22 = a / det;
        lk.inv_gsum = 1.0 / a;
    }
    pl->has_harm = false;
    for (int x = 0; x < 3; ++x) {
        const double g = pl->im ? 0.0 : p.psi_m_wb * p.emf_gain[x];
        const double h[4] = {1.0, p.emf_harm[x][0], p.emf_harm[x][1], p.emf_harm[x][2]};
        const int n[4] = {1, 3, 5, 7};
        for (int k = 0; k < 4; ++k) {
            pl->flux_amp[x][k] = g * h[k] / n[k];
            pl->emf_amp[x][k] = g * h[k];
            if (k > 0 && h[k] != 0.0) pl->has_harm = true;
        }
    }
}

// sin/cos of theta using the value cached at the step start and a short Taylor rotation for the
// small angle increment of an RK stage (|d| < 0.25 rad: truncation < 1e-16).
inline void fast_sincos(const plant_t *pl, double th, double &c, double &s) {
    const double d = th - pl->th0;
    if (std::fabs(d) < 0.25) {
        const double d2 = d * d;
        const double cd = 1.0 - d2 * (0.5 - d2 * (1.0 / 24.0 - d2 * (1.0 / 720.0 - d2 * (1.0 / 40320.0 - d2 / 3628800.0))));
        const double sd = d * (1.0 - d2 * (1.0 / 6.0 - d2 * (1.0 / 120.0 - d2 * (1.0 / 5040.0 - d2 * (1.0 / 362880.0 - d2 / 39916800.0)))));
        c = pl->c0 * cd - pl->s0 * sd;
        s = pl->s0 * cd + pl->c0 * sd;
    } else {
        c = std::cos(th);
        s = std::sin(th);
    }
}

// dpsi_pm,x/dtheta_e for the three phases (and, if wanted, psi_pm,x itself).
// psi_pm,x = sum_n flux_amp[x][n] cos(n (theta - phi_x)), phi_x = 0, 2pi/3, 4pi/3.
inline void pm_flux(const plant_t *pl, double theta_e, double dpsi[3], double *psi) {
    double c, s;
    fast_sincos(pl, theta_e, c, s);
    // Rotate by -2pi/3 and -4pi/3.
    const double ch = -0.5, sh = kSqrt3 / 2.0;
    const double cb = c * ch + s * sh, sb = s * ch - c * sh;  // theta - 2pi/3
    const double cc = c * ch - s * sh, sc = s * ch + c * sh;  // theta - 4pi/3 (= + 2pi/3)
    const double cx[3] = {c, cb, cc}, sx[3] = {s, sb, sc};
    for (int x = 0; x < 3; ++x) {
        const double *a = pl->emf_amp[x];
        double dp = -a[0] * sx[x];
        double ps = pl->flux_amp[x][0] * cx[x];
        if (pl->has_harm) {
            // z^n by complex multiplication: z2, z3, z5 = z3 z2, z7 = z5 z2.
            const double c1 = cx[x], s1 = sx[x];
            const double c2 = c1 * c1 - s1 * s1, s2 = 2.0 * c1 * s1;
            const double c3 = c2 * c1 - s2 * s1, s3 = s2 * c1 + c2 * s1;
            const double c5 = c3 * c2 - s3 * s2, s5 = s3 * c2 + c3 * s2;
            const double c7 = c5 * c2 - s5 * s2, s7 = s5 * c2 + c5 * s2;
            dp -= a[1] * s3 + a[2] * s5 + a[3] * s7;
            ps += pl->flux_amp[x][1] * c3 + pl->flux_amp[x][2] * c5 + pl->flux_amp[x][3] * c7;
        }
        dpsi[x] = dp;
        if (psi) psi[x] = ps;
    }
}

// Taylor expansion of dpsi_pm,x/dtheta_e around th0 (the cache angle), order kTcOrder = 7. For
// harmonic n, d^k/dtheta^k [-A sin(n u)] = -A n^k sin(n u + k pi/2); divided by k!. Remainder:
// (n_max |d|)^8 / 8! relative to the harmonic's amplitude, < 1.7e-9 within kTcRange (n_max |d| <
// 0.3). The step re-centres it when it could leave kTcRecentre (0.25), i.e. every few periods.
constexpr double kTcRange = 0.3;
constexpr double kTcRecentre = 0.25;
void setup_emf_taylor(plant_t *pl) {
    const double c = pl->c0, s = pl->s0;
    const double ch = -0.5, sh = kSqrt3 / 2.0;
    const double cx[3] = {c, c * ch + s * sh, c * ch - s * sh};
    const double sx[3] = {s, s * ch - c * sh, s * ch + c * sh};
    for (int x = 0; x < 3; ++x) {
        const double *a = pl->emf_amp[x];
        double cn[4], sn[4];
        cn[0] = cx[x];
        sn[0] = sx[x];
        const int nh = pl->has_harm ? 4 : 1;
        if (pl->has_harm) {
            const double c1 = cx[x], s1 = sx[x];
            const double c2 = c1 * c1 - s1 * s1, s2 = 2.0 * c1 * s1;
            cn[1] = c2 * c1 - s2 * s1; sn[1] = s2 * c1 + c2 * s1;
            cn[2] = cn[1] * c2 - sn[1] * s2; sn[2] = sn[1] * c2 + cn[1] * s2;
            cn[3] = cn[2] * c2 - sn[2] * s2; sn[3] = sn[2] * c2 + cn[2] * s2;
        }
        for (int h = 0; h < 4; ++h) {
            const bool on = h < nh;
            pl->ph_fc[x][h] = on ? pl->flux_amp[x][h] * cn[h] : 0.0;
            pl->ph_fs[x][h] = on ? pl->flux_amp[x][h] * sn[h] : 0.0;
            pl->ph_ac[x][h] = on ? a[h] * cn[h] : 0.0;
            pl->ph_as[x][h] = on ? a[h] * sn[h] : 0.0;
        }
        static const double nn[4] = {1.0, 3.0, 5.0, 7.0};
        double t0 = 0.0, t1 = 0.0, t2 = 0.0, t3 = 0.0, t4 = 0.0, t5 = 0.0, t6 = 0.0, t7 = 0.0;
        for (int h = 0; h < nh; ++h) {
            const double n = nn[h], n2 = n * n, n4 = n2 * n2;
            const double as = a[h] * sn[h], ac = a[h] * cn[h] * n;
            // -A n^k sin(nu + k pi/2) / k!, k = 0..7
            t0 -= as;
            t1 -= ac;
            t2 += as * n2 * 0.5;
            t3 += ac * n2 * (1.0 / 6.0);
            t4 -= as * n4 * (1.0 / 24.0);
            t5 -= ac * n4 * (1.0 / 120.0);
            t6 += as * n4 * n2 * (1.0 / 720.0);
            t7 += ac * n4 * n2 * (1.0 / 5040.0);
        }
        const double tc[8] = {t0, t1, t2, t3, t4, t5, t6, t7};
        for (int k = 0; k < 8; ++k) pl->emf_tc[k][x] = tc[k];
    }
    for (int k = 0; k < 8; ++k) pl->emf_tc[k][3] = 0.0;
    pl->tc_range = kTcRange / (pl->has_harm ? 7.0 : 1.0);
    pl->tc_valid = true;
}

inline void dpsi_fast(const plant_t *pl, double theta_e, double dpsi[3]) {
    const double d = theta_e - pl->th0;
    if (pl->tc_valid && std::fabs(d) < pl->tc_range) {
        const double d2 = d * d, d4 = d2 * d2;
        const Eigen::Array4d *t = pl->emf_tc;
        // Estrin's scheme: same polynomial, shorter dependency chain than Horner.
        const Eigen::Array4d r =
            ((t[0] + t[1] * d) + d2 * (t[2] + t[3] * d)) + d4 * ((t[4] + t[5] * d) + d2 * (t[6] + t[7] * d));
        dpsi[0] = r[0];
        dpsi[1] = r[1];
        dpsi[2] = r[2];
    } else {
        pm_flux(pl, theta_e, dpsi, nullptr);
    }
}

// psi_pm,x and dpsi_pm,x/dtheta_e at theta_e, exact (to rounding): the centre phasors rotated by
// n d, d = theta_e - th0, with cos/sin(n d) for n = 1, 3, 5, 7 from their Taylor series to d^12 /
// d^13 (remainder < 0.3^14/14! = 6e-19 for n_max |d| < 0.3), evaluated in SIMD lanes. Falls back
// to pm_flux() outside that range. Lower latency than pm_flux() (no chained rotations); used by
// plant_get_state once per period.
void pm_flux_centre(const plant_t *pl, double theta_e, double dpsi[3], double psi[3]) {
    const double d = theta_e - pl->th0;
    if (!(pl->tc_valid && std::fabs(d) * (pl->has_harm ? 7.0 : 1.0) < 0.3)) {
        pm_flux(pl, theta_e, dpsi, psi);
        return;
    }
    const Eigen::Array4d x = Eigen::Array4d(1.0, 3.0, 5.0, 7.0) * d;
    const Eigen::Array4d x2 = x * x, x4 = x2 * x2, x8 = x4 * x4;
    const Eigen::Array4d cv = ((1.0 - x2 * 0.5) + x4 * (1.0 / 24.0 - x2 * (1.0 / 720.0))) +
                              x8 * ((1.0 / 40320.0 - x2 * (1.0 / 3628800.0)) + x4 * (1.0 / 479001600.0));
    const Eigen::Array4d sv = x * (((1.0 - x2 * (1.0 / 6.0)) + x4 * (1.0 / 120.0 - x2 * (1.0 / 5040.0))) +
                                   x8 * ((1.0 / 362880.0 - x2 * (1.0 / 39916800.0)) + x4 * (1.0 / 6227020800.0)));
    for (int k = 0; k < 3; ++k) {
        psi[k] = (pl->ph_fc[k] * cv - pl->ph_fs[k] * sv).sum();
        dpsi[k] = -(pl->ph_as[k] * cv + pl->ph_ac[k] * sv).sum();
    }
}

// Phase back-EMF of the configured machine at state y (exact formulas; the step's right-hand side
// uses the same, with the PM's expansion).
inline void machine_emf(const plant_t *pl, const Vec &y, double e[3]) {
    const double omega_e = pl->pp * y[S_OMEGA];
    if (pl->im) {
        im::emf_phases(pl->imc, y[S_PSIRA], y[S_PSIRB], omega_e, e);
        return;
    }
    double dpsi[3];
    pm_flux(pl, pl->pp * y[S_THETA], dpsi, nullptr);
    for (int x = 0; x < 3; ++x) e[x] = omega_e * dpsi[x];
}



// Link terminal voltages at state y (the rail currents from the current signs; a zero current
// draws nothing whatever its path).
inline void dc_link_terminals(const plant_t *pl, const Vec &y, double &tv_lo, double &tv_hi) {
    double ip = 0.0, im = 0.0;
    for (int x = 0; x < 3; ++x) {
        const double i = y[S_IA + x];
        if (i == 0.0) continue;
        const Path &pa = (i > 0.0) ? pl->legs[x]->pos : pl->legs[x]->neg;
        if (pa.rail == RAIL_PLUS) ip += i;
        else if (pa.rail == RAIL_MID) im += i;
    }
    dclink::LinkNodes n;
    dclink::dc_link_nodes(pl->link, y[S_VCLO], y[S_VCHI], ip, im, n);
    tv_lo = n.tv_lo;
    tv_hi = n.tv_hi;
}

inline void rails(const plant_t *pl, const Vec &y, double rv[4], int x) {
    rv[RAIL_ZERO] = 0.0;
    if (pl->link.on) {
        double lo, hi;
        dc_link_terminals(pl, y, lo, hi);
        rv[RAIL_PLUS] = lo + hi;
        rv[RAIL_MID] = lo;
    } else {
        rv[RAIL_PLUS] = y[S_VCLO] + y[S_VCHI];
        rv[RAIL_MID] = y[S_VCLO];
    }
    rv[RAIL_SRC] = 0.0;
    if (pl->p.inverter == PLANT_INVERTER_IDEAL) {
        // Ideal source: phase voltages from the inverse amplitude-invariant Clarke transform.
        const double va = pl->v_set_alpha, vb = pl->v_set_beta;
        const double v[3] = {va, -0.5 * va + 0.5 * kSqrt3 * vb, -0.5 * va - 0.5 * kSqrt3 * vb};
        rv[RAIL_SRC] = v[x];
    }
}

void make_prep(plant_t *pl, const Mode &m, Prep &q) {
    q.nk = 0;
    for (int x = 0; x < 3; ++x) {
        q.ph[x] = &pl->legs[x]->coef[m.ph[x]];
        if (m.ph[x] != PH_BLOCKED) ++q.nk;
    }
    static const double inv_n[4] = {0.0, 1.0, 0.5, 1.0 / 3.0};
    q.inv_nk = inv_n[q.nk];
}

// Coefficients of a phase for one path (conducting) or blocked.
PhaseCoef phase_coef(const plant_t *pl, const Leg &L, const Path &pa, bool blk, double vsrc) {
    PhaseCoef k;
    k.cond = blk ? 0.0 : 1.0;
    k.a_lo = (pa.rail == RAIL_PLUS || pa.rail == RAIL_MID) ? 1.0 : 0.0;
    k.a_hi = (pa.rail == RAIL_PLUS) ? 1.0 : 0.0;
    k.c = ((pa.rail == RAIL_SRC) ? vsrc : 0.0) - pa.d;
    k.r = pa.r;
    k.rtot = pl->r_ph + pa.r;
    k.dev = (L.device && !blk) ? 1.0 : 0.0;
    k.dev_d = pa.d;
    k.plus = (!blk && pa.rail == RAIL_PLUS) ? 1.0 : 0.0;
    k.mid = (!blk && pa.rail == RAIL_MID) ? 1.0 : 0.0;
    k.src = (!blk && pa.rail == RAIL_SRC) ? 1.0 : 0.0;
    k.pd = k.dev * k.dev_d;
    k.pr = k.dev * k.r;
    return k;
}

// Load law and DC link as linear forms (see Glob).
void make_glob(plant_t *pl) {
    const plant_params_t &p = pl->p;
    Glob &q = pl->g;
    q.ld_c0 = q.ld_cw = q.ld_cte = q.ld_cq = 0.0;
    q.w_on = 1.0;
    pl->fan_on = p.load == PLANT_LOAD_FAN;
    switch (p.load) {
        case PLANT_LOAD_SPEED:  // the dynamometer holds speed: T_load = T_e - b omega
            q.ld_cte = 1.0;
            q.ld_cw = -p.b_nms;
            q.w_on = 0.0;
            break;
        case PLANT_LOAD_TORQUE: q.ld_c0 = p.load_torque_nm; break;
        case PLANT_LOAD_GENERATOR: q.ld_cw = p.load_torque_nm / pl->omega_load_ref; break;
        case PLANT_LOAD_FAN: q.ld_cq = p.load_torque_nm / (pl->omega_load_ref * pl->omega_load_ref); break;
        default: break;
    }
    q.is_g = q.hi_s = q.hi_p = q.lo_s = q.lo_p = q.lo_m = 0.0;
    q.pdc_s = q.pdc_st = q.pdc_src = q.r_dc = 0.0;
    if (p.inverter == PLANT_INVERTER_IDEAL) {
        q.pdc_src = 1.0;
    } else if (!p.finite_dc_link) {
        q.pdc_st = 1.0;
    } else {
        q.is_g = pl->inv_rdc;
        q.pdc_s = p.vdc_v;
        q.r_dc = p.r_dc_ohm;
        if (p.inverter == PLANT_INVERTER_FSTP) {
            q.hi_s = q.hi_p = pl->inv_c_hi;
            q.lo_s = q.lo_p = q.lo_m = pl->inv_c_lo;
        } else {
            // SSTP: one capacitor of 2*c_dc_f (c_lo holds that value, see derive()), reported as
            // two equal halves.
            q.hi_s = q.hi_p = q.lo_s = q.lo_p = 0.5 * pl->inv_c_lo;
        }
    }
}

// Neutral voltage when every phase is blocked: centre of the feasible range.
double vn0_all_blocked(const plant_t *pl, const Vec &y, const double e[3]) {
    double lo = -1e300, hi = 1e300;
    for (int x = 0; x < 3; ++x) {
        double rv[4];
        rails(pl, y, rv, x);
        const double a = path_v(pl->legs[x]->pos, rv), b = path_v(pl->legs[x]->neg, rv);
        lo = std::max(lo, std::min(a, b) - e[x]);
        hi = std::min(hi, std::max(a, b) - e[x]);
    }
    return 0.5 * (lo + hi);
}

// Right-hand side for a fixed conduction mode (pl->prep must match the mode). Only the first ND
// entries of y are read. Branch-free apart from the all-blocked neutral (Prep and Glob hold the
// linear forms of the paths, the DC link and the load). kAll: all three phases conduct (the
// common case; the blocked-phase terms drop out).
template <bool kAll>
inline void rhs_t(plant_t *pl, const Vec &y, Vec &dy, Aux *aux) {
    ++pl->stats.evals;
    const Prep &q = pl->prep;
    const PhaseCoef *const *k = q.ph;
    const double pp = pl->pp;
    const double omega = y[S_OMEGA];
    const double omega_e = pp * omega;
    double dpsi[3], e[3];
    if (!pl->im) {
        dpsi_fast(pl, pp * y[S_THETA], dpsi);
        for (int x = 0; x < 3; ++x) e[x] = omega_e * dpsi[x];
    } else {
        im::emf_phases(pl->imc, y[S_PSIRA], y[S_PSIRB], omega_e, e);
        dpsi[0] = dpsi[1] = dpsi[2] = 0.0;  // no PM torque term; the IM torque follows the loop
    }
    const double vlo = y[S_VCLO], vhi = y[S_VCHI];
    const double ix[3] = {y[S_IA], y[S_IB], y[S_IC]};
    // Rail voltages: the capacitor voltages, or with ESR / balancing resistors the link's node
    // voltages (dclink::LinkRC), which depend on the currents the inverter draws.
    double tvlo = vlo, tvhi = vhi;
    dclink::LinkNodes ln;
    if (pl->link.on) {
        double ip = 0.0, im = 0.0;
        for (int x = 0; x < 3; ++x) {
            ip += k[x]->plus * ix[x];
            im += k[x]->mid * ix[x];
        }
        dclink::dc_link_nodes(pl->link, vlo, vhi, ip, im, ln);
        tvlo = ln.tv_lo;
        tvhi = ln.tv_hi;
    }
    double vp[3], u[3];
#pragma GCC unroll 3
    for (int x = 0; x < 3; ++x) {
        vp[x] = k[x]->a_lo * tvlo + k[x]->a_hi * tvhi + k[x]->c;
        u[x] = vp[x] - k[x]->rtot * ix[x] - e[x];  // L di/dt + v_n0 of a conducting phase
    }
    double vn0;
    if (kAll) {
        vn0 = (u[0] + u[1] + u[2]) * (1.0 / 3.0);
    } else {
        const double sum = k[0]->cond * u[0] + k[1]->cond * u[1] + k[2]->cond * u[2];
        vn0 = (q.nk >= 2) ? sum * q.inv_nk : vn0_all_blocked(pl, y, e);
    }
    const double inv_l = pl->inv_l;
    double vx0[3];
    double te = 0.0, p_cu = 0.0, p_dev = 0.0, i_plus = 0.0, i_mid = 0.0, p_src = 0.0;
#pragma GCC unroll 3
    for (int x = 0; x < 3; ++x) {
        const double i = ix[x];
        const double vc = vp[x] - k[x]->r * i;
        if (kAll) {
            // (u_x - vn0) / L with vn0 = mean(u), written so that u_x does not wait for the sum.
            dy[S_IA + x] = pl->inv_l_2_3 * u[x] - pl->inv_l_1_3 * (u[(x + 1) % 3] + u[(x + 2) % 3]);
            vx0[x] = vc;
        } else {
            dy[S_IA + x] = k[x]->cond * (u[x] - vn0) * inv_l;
            vx0[x] = k[x]->cond * vc + (1.0 - k[x]->cond) * (vn0 + e[x]);  // blocked: floating terminal
        }
        p_dev += (k[x]->pd + k[x]->pr * i) * i;
        i_plus += k[x]->plus * i;
        i_mid += k[x]->mid * i;
        p_src += k[x]->src * vc * i;
        te += i * dpsi[x];
        p_cu += i * i;
    }
    te *= pp;
    double p_rotor_cu = 0.0;
    if (!pl->im) {
        dy[S_PSIRA] = dy[S_PSIRB] = 0.0;
    } else {
        const double i_al = (2.0 * ix[0] - ix[1] - ix[2]) * (1.0 / 3.0);
        const double i_be = (ix[1] - ix[2]) * (1.0 / kSqrt3);
        im::rotor(pl->imc, pl->p.pole_pairs, i_al, i_be, y[S_PSIRA], y[S_PSIRB], omega_e, dy[S_PSIRA],
                  dy[S_PSIRB], te, p_rotor_cu);
    }
    const Glob &g = pl->g;
    const double b = pl->p.b_nms;
    double tl = g.ld_c0 + g.ld_cw * omega + g.ld_cte * te;
    if (pl->fan_on) tl += g.ld_cq * omega * std::fabs(omega);
    dy[S_THETA] = omega;
    if (!pl->coulomb_on) {
        dy[S_OMEGA] = g.w_on * (te - b * omega - tl) * pl->inv_j;
        dy[S_EFRIC] = b * omega * omega;
    } else {
        // Coulomb friction tf on top of the viscous term; a held speed (speed load) makes the
        // dynamometer supply it (ld_cte = 1 there). Its direction is that of the speed at the
        // start of the step (pl->y: every evaluation within a step starts from it), so a step's
        // stages never see the jump; integrate() stops the rotor where the speed crosses zero.
        const double tf = mech::coulomb_torque(pl->p.coulomb_nm, pl->y[S_OMEGA], te - b * omega - tl);
        tl -= g.ld_cte * tf;
        dy[S_OMEGA] = g.w_on * (te - b * omega - tl - tf) * pl->inv_j;
        dy[S_EFRIC] = (b * omega + tf) * omega;
    }
    // DC link.
    double i_s;
    if (!pl->link.on) {
        i_s = g.is_g * (pl->p.vdc_v - (vlo + vhi));
        dy[S_VCHI] = g.hi_s * i_s - g.hi_p * i_plus;
        dy[S_VCLO] = g.lo_s * i_s - g.lo_p * i_plus - g.lo_m * i_mid;
        dy[S_ELINK] = 0.0;
    } else {
        i_s = ln.i_s;
        dy[S_VCHI] = ln.dv_hi;
        dy[S_VCLO] = ln.dv_lo;
        dy[S_ELINK] = ln.p_loss;
    }
    dy[S_EDC] = g.pdc_s * i_s + g.pdc_st * ((vlo + vhi) * i_plus + vlo * i_mid) + g.pdc_src * p_src;
    dy[S_ECU] = pl->p.rs_ohm * p_cu + p_rotor_cu;
    dy[S_EDEV] = p_dev;
    dy[S_ELOAD] = tl * omega;
    dy[S_ERDC] = g.r_dc * i_s * i_s;
    dy[S_IVA0] = vx0[0];
    dy[S_IVB0] = vx0[1];
    dy[S_IVC0] = vx0[2];
    if (aux) {
        aux->te = te;
        aux->tload = tl;
        aux->vn0 = vn0;
        for (int x = 0; x < 3; ++x) {
            aux->vx0[x] = vx0[x];
            aux->e[x] = e[x];
        }
    }
}

inline void rhs(plant_t *pl, const Vec &y, Vec &dy, Aux *aux) {
    if (pl->prep.nk == 3) rhs_t<true>(pl, y, dy, aux);
    else rhs_t<false>(pl, y, dy, aux);
}

// Leg paths and coefficients for every gate state (Hoang Table III, eq. 20); called at creation
// and when the ideal source's voltages change.
void build_leg_table(plant_t *pl) {
    const plant_params_t &p = pl->p;
    pl->prep_valid = false;
    const double vce = p.drops_enabled ? p.v_ce_v : 0.0;
    const double vd = p.drops_enabled ? p.v_d_v : 0.0;
    const double ron = p.drops_enabled ? p.r_on_ohm : 0.0;
    double vsrc[3] = {0.0, 0.0, 0.0};
    if (p.inverter == PLANT_INVERTER_IDEAL) {
        // Ideal source: phase voltages from the inverse amplitude-invariant Clarke transform.
        const double va = pl->v_set_alpha, vb = pl->v_set_beta;
        vsrc[0] = va;
        vsrc[1] = -0.5 * va + 0.5 * kSqrt3 * vb;
        vsrc[2] = -0.5 * va - 0.5 * kSqrt3 * vb;
    }
    for (int x = 0; x < 3; ++x)
    for (int gate = 0; gate < 3; ++gate) {
        Leg &L = pl->leg_tab[x][gate];
        if (p.inverter == PLANT_INVERTER_IDEAL) {
            L.pos = L.neg = Path{RAIL_SRC, 0.0, 0.0};
            L.sign_dep = false;
            L.device = false;
        } else if (p.inverter == PLANT_INVERTER_FSTP && x == 0) {
            L.pos = L.neg = Path{RAIL_MID, 0.0, 0.0};  // Hoang Fig. 1(b): no device in phase A
            L.sign_dep = false;
            L.device = false;
        } else {
            L.device = true;
            switch (gate) {
                case GATE_UPPER:  // Table III state 1: + -> V_CE, - -> -V_d
                    L.pos = Path{RAIL_PLUS, vce, ron};
                    L.neg = Path{RAIL_PLUS, -vd, ron};
                    break;
                case GATE_LOWER:  // Table III state 0: + -> V_d, - -> -V_CE
                    L.pos = Path{RAIL_ZERO, vd, ron};
                    L.neg = Path{RAIL_ZERO, -vce, ron};
                    break;
                default:  // both gates off: the current sign picks the diode
                    L.pos = Path{RAIL_ZERO, vd, ron};
                    L.neg = Path{RAIL_PLUS, -vd, ron};
                    break;
            }
            L.sign_dep = !(L.pos.rail == L.neg.rail && L.pos.d == L.neg.d && L.pos.r == L.neg.r);
        }
        L.coef[PH_POS] = phase_coef(pl, L, L.pos, false, vsrc[x]);
        L.coef[PH_NEG] = phase_coef(pl, L, L.neg, false, vsrc[x]);
        L.coef[PH_BLOCKED] = phase_coef(pl, L, L.pos, true, vsrc[x]);
    }
}

// Legs in force from the gate states.
void build_legs(plant_t *pl) {
    pl->prep_valid = false;
    for (int x = 0; x < 3; ++x) pl->legs[x] = &pl->leg_tab[x][pl->gate[x]];
}

// Conduction mode at state y. Currents that are exactly zero on a sign-dependent leg are resolved
// by enumerating {blocked, +, -} and keeping the consistent assignment (Filippov / linear
// complementarity; the leg characteristics are monotone so the consistent one is unique up to
// ties, which are broken towards "blocked" so a zero current never chatters).
Mode select_mode(plant_t *pl, const Vec &y) {
    Mode m;
    int zl[3], nz = 0;
    for (int x = 0; x < 3; ++x) {
        const double i = y[S_IA + x];
        if (i > 0.0) m.ph[x] = PH_POS;
        else if (i < 0.0) m.ph[x] = PH_NEG;
        else { m.ph[x] = PH_POS; zl[nz++] = x; }
    }
    if (nz == 0) return m;
    ++pl->stats.mode_selects;
    double e[3], rv[3][4];
    machine_emf(pl, y, e);
    for (int x = 0; x < 3; ++x) rails(pl, y, rv[x], x);
    int ncand = 1;
    for (int k = 0; k < nz; ++k) ncand *= 3;
    double best_v = 1e300;
    Mode best = m;
    for (int c = 0; c < ncand; ++c) {
        Mode t = m;
        int code = c;
        bool skip = false;
        for (int k = 0; k < nz; ++k) {
            const int digit = code % 3;
            code /= 3;
            const int x = zl[k];
            if (digit == 0) t.ph[x] = PH_BLOCKED;
            else if (digit == 1) t.ph[x] = PH_POS;
            else {
                if (!pl->legs[x]->sign_dep) { skip = true; }  // same as PH_POS
                t.ph[x] = PH_NEG;
            }
        }
        if (skip) continue;
        int nk = 0;
        double sum = 0.0, vp[3] = {0, 0, 0}, rr[3] = {0, 0, 0};
        for (int x = 0; x < 3; ++x) {
            if (t.ph[x] == PH_BLOCKED) continue;
            const Path &pa = (t.ph[x] == PH_POS) ? pl->legs[x]->pos : pl->legs[x]->neg;
            vp[x] = path_v(pa, rv[x]);
            rr[x] = pa.r;
            sum += vp[x] - (pl->r_ph + rr[x]) * y[S_IA + x] - e[x];
            ++nk;
        }
        if (nk == 1) continue;
        double viol = 0.0;
        if (nk == 0) {
            double lo = -1e300, hi = 1e300;
            for (int x = 0; x < 3; ++x) {
                const double a = path_v(pl->legs[x]->pos, rv[x]), b = path_v(pl->legs[x]->neg, rv[x]);
                lo = std::max(lo, std::min(a, b) - e[x]);
                hi = std::min(hi, std::max(a, b) - e[x]);
            }
            viol = std::max(0.0, lo - hi);
        } else {
            const double vn0 = sum / nk;
            for (int k = 0; k < nz; ++k) {
                const int x = zl[k];
                if (t.ph[x] == PH_BLOCKED) {
                    const double vf = vn0 + e[x];
                    const double a = path_v(pl->legs[x]->pos, rv[x]), b = path_v(pl->legs[x]->neg, rv[x]);
                    viol += std::max(0.0, std::min(a, b) - vf) + std::max(0.0, vf - std::max(a, b));
                } else if (pl->legs[x]->sign_dep) {
                    const double di = vp[x] - (pl->r_ph + rr[x]) * y[S_IA + x] - e[x] - vn0;  // L di/dt
                    if (t.ph[x] == PH_POS) viol += std::max(0.0, -di);
                    else viol += std::max(0.0, di);
                }
            }
        }
        if (viol < best_v) {
            best_v = viol;
            best = t;
            if (viol == 0.0) break;
        }
    }
    return best;
}

// After forcing the currents in snapped[] to zero, restore sum(i) = 0 on the others: with one other
// conducting phase left, it must be zero too; with two, they share the removed amount.
void snap_currents(Vec &y, bool snapped[3]) {
    double removed = 0.0;
    for (int x = 0; x < 3; ++x)
        if (snapped[x]) { removed += y[S_IA + x]; y[S_IA + x] = 0.0; }
    int nrest = 0;
    for (int x = 0; x < 3; ++x)
        if (!snapped[x] && y[S_IA + x] != 0.0) ++nrest;
    if (nrest <= 1) {
        for (int x = 0; x < 3; ++x) y[S_IA + x] = 0.0;
    } else {
        for (int x = 0; x < 3; ++x)
            if (!snapped[x] && y[S_IA + x] != 0.0) y[S_IA + x] += removed / nrest;
    }
}

// Classical RK4 over h from y0 with k1 = f(y0). The stage states carry only the ND dynamic
// entries (the quadratures do not enter f); the result is the full RK4 combination.
// Stage state y0 + c k on the ND dynamic entries, as a scalar loop on purpose: the right-hand
// side stores its outputs one double at a time, and a 16-byte SIMD load spanning two such fresh
// stores cannot be forwarded from the store buffer (a stall on the critical path of every stage;
// ~10 ns per period measured).
#if defined(__GNUC__) && !defined(__clang__)
#define DTC_NO_AUTOVEC __attribute__((optimize("no-tree-vectorize")))
#else
#define DTC_NO_AUTOVEC
#endif
DTC_NO_AUTOVEC inline void stage_state(const Vec &y0, double c, const Vec &k, Vec &yt) {
    for (int j = 0; j < ND; ++j) yt[j] = y0[j] + c * k[j];
}

inline void rk4(plant_t *pl, const Vec &y0, double h, const Vec &k1, Vec &out) {
    Vec k2, k3, k4, yt;
    stage_state(y0, 0.5 * h, k1, yt);
    rhs(pl, yt, k2, nullptr);
    stage_state(y0, 0.5 * h, k2, yt);
    rhs(pl, yt, k3, nullptr);
    stage_state(y0, h, k3, yt);
    rhs(pl, yt, k4, nullptr);
    out.noalias() = y0 + (h / 6.0) * (k1 + 2.0 * (k2 + k3) + k4);
}

// Explicit midpoint rule (second order, two evaluations) for short dead-time segments; same
// stage-state convention as rk4().
inline void midpoint(plant_t *pl, const Vec &y0, double h, const Vec &k1, Vec &out) {
    Vec k2, yt;
    stage_state(y0, 0.5 * h, k1, yt);
    rhs(pl, yt, k2, nullptr);
    out.noalias() = y0 + h * k2;
}

// The step's integrator: RK4, or the midpoint rule on a short dead-time segment (plant_advance
// sets pl->short_seg; docs/plant.md section 2 gives the rule and its error).
// With Coulomb friction (direction frozen over the step, see rhs_t) a speed that changes sign
// within the step is set to exactly zero at the step's end; the next step then either holds the
// rotor or breaks away (mech::coulomb_torque). The kinetic energy removed goes to the friction account, so the
// energy balance stays closed; the local error is one step's worth of the zero crossing
// (docs/plant.md, "Mechanics").
inline void integrate(plant_t *pl, const Vec &y0, double h, const Vec &k1, Vec &out) {
    if (pl->short_seg) midpoint(pl, y0, h, k1, out);
    else rk4(pl, y0, h, k1, out);
    if (pl->coulomb_on && pl->g.w_on != 0.0) {
        const double w0 = y0[S_OMEGA], w1 = out[S_OMEGA];
        if ((w0 > 0.0 && w1 < 0.0) || (w0 < 0.0 && w1 > 0.0)) {
            out[S_EFRIC] += 0.5 * pl->p.j_kgm2 * w1 * w1;
            out[S_OMEGA] = 0.0;
        }
    }
}

// Event function: the most negative of (a) dir * i for conducting sign-dependent phases (the
// current must not change sign inside a step with its path fixed) and (b) the margin of a
// blocked phase's floating voltage inside its zero-current interval (volts, scaled by 1e-3 A/V so
// the two kinds are of similar size; the root finder needs only sign and continuity).
double event_g(plant_t *pl, const Vec &y, const Mode &m, const bool active[3]) {
    double g = 1e300;
    bool any_blocked = false;
    for (int x = 0; x < 3; ++x) {
        if (!active[x]) continue;
        if (m.ph[x] == PH_BLOCKED) { any_blocked = true; continue; }
        const double v = (m.ph[x] == PH_POS) ? y[S_IA + x] : -y[S_IA + x];
        g = std::min(g, v);
    }
    if (any_blocked) {
        Vec dy;
        Aux aux;
        rhs(pl, y, dy, &aux);
        for (int x = 0; x < 3; ++x) {
            if (!active[x] || m.ph[x] != PH_BLOCKED) continue;
            double rv[4];
            rails(pl, y, rv, x);
            const double a = path_v(pl->legs[x]->pos, rv), b = path_v(pl->legs[x]->neg, rv);
            const double vf = aux.vx0[x];
            const double margin = std::min(vf - std::min(a, b), std::max(a, b) - vf);
            g = std::min(g, margin * 1e-3);
        }
    }
    return g;
}

// One step of at most h with mode selection and event location. Returns the time advanced.
double step(plant_t *pl, double h) {
    Vec &y = pl->y;
    const double th = pl->p.pole_pairs * y[S_THETA];
    // Re-centre the EMF expansion only when this step could leave n_max |delta| < kTcRecentre
    // (truncation < 1.7e-9 of each harmonic's amplitude even at kTcRange); one expansion serves
    // several periods.
    const double reach = (std::fabs(th - pl->th0) + std::fabs(pl->p.pole_pairs * y[S_OMEGA]) * h * 1.2) *
                         (pl->has_harm ? 7.0 : 1.0);
    if (!pl->tc_valid || reach >= kTcRecentre) {
        if (++pl->sync_count >= 256 || std::fabs(th - pl->th0) >= 0.25) {
            pl->sync_count = 0;
            pl->c0 = std::cos(th);
            pl->s0 = std::sin(th);
        } else {
            double c, s;
            fast_sincos(pl, th, c, s);
            pl->c0 = c;
            pl->s0 = s;
        }
        pl->th0 = th;
        setup_emf_taylor(pl);
    }
    // Fast path: no current exactly zero (the usual case), the mode follows the current signs.
    const bool nonzero = y[S_IA] != 0.0 && y[S_IB] != 0.0 && y[S_IC] != 0.0;
    // (Written in place, element by element: a struct copy of the freshly stored ints would stall
    // on store forwarding.)
    Mode &m = pl->mode;
    if (nonzero) {
        for (int x = 0; x < 3; ++x) m.ph[x] = (y[S_IA + x] > 0.0) ? PH_POS : PH_NEG;
    } else {
        const Mode ms = select_mode(pl, y);
        for (int x = 0; x < 3; ++x) m.ph[x] = ms.ph[x];
    }
    if (!pl->prep_valid || m.ph[0] != pl->prep_mode.ph[0] || m.ph[1] != pl->prep_mode.ph[1] ||
        m.ph[2] != pl->prep_mode.ph[2]) {
        make_prep(pl, m, pl->prep);
        for (int x = 0; x < 3; ++x) pl->prep_mode.ph[x] = m.ph[x];
        pl->prep_valid = true;
    }
    Vec k1, y1;
    rhs(pl, y, k1, nullptr);
    integrate(pl, y, h, k1, y1);
    ++pl->stats.steps;
    if (nonzero) {
        // No blocked phase and none starting at zero: the only events are sign changes of the
        // currents on sign-dependent legs (event_g's first kind).
        double g1 = 1e300;
        for (int x = 0; x < 3; ++x)
            if (pl->legs[x]->sign_dep) g1 = std::min(g1, (m.ph[x] == PH_POS) ? y1[S_IA + x] : -y1[S_IA + x]);
        if (g1 >= -1e-12) {
            y = y1;
            return h;
        }
    }
    // Which phases can produce an event?
    bool active[3] = {false, false, false};
    bool any = false;
    for (int x = 0; x < 3; ++x) {
        if (m.ph[x] == PH_BLOCKED) { active[x] = true; any = true; }
        else if (pl->legs[x]->sign_dep) {
            const double i0 = (m.ph[x] == PH_POS) ? y[S_IA + x] : -y[S_IA + x];
            if (i0 > 0.0) { active[x] = true; any = true; }
        }
    }
    if (!any) { y = y1; return h; }
    // Blocked phases: is the margin >= 0 at the end? (Cheap test first for currents.)
    double g1 = event_g(pl, y1, m, active);
    if (g1 >= -1e-12) {
        // Currents of phases that started exactly at zero and were released may have come back
        // through zero within the step; snap them (second-order small, see docs/plant.md).
        bool snapped[3] = {false, false, false};
        bool any_snap = false;
        for (int x = 0; x < 3; ++x) {
            if (m.ph[x] != PH_BLOCKED && pl->legs[x]->sign_dep && y[S_IA + x] == 0.0) {
                const double v = (m.ph[x] == PH_POS) ? y1[S_IA + x] : -y1[S_IA + x];
                if (v < 0.0) snapped[x] = any_snap = true;
            }
        }
        if (any_snap) snap_currents(y1, snapped);
        y = y1;
        return h;
    }
    // Locate the earliest sign change with the Illinois method on s in (0, 1].
    ++pl->stats.events;
    double a = 0.0, b = 1.0;
    double ga = event_g(pl, y, m, active), gb = g1;
    if (ga < 0.0) ga = 0.0;
    int side = 0;
    Vec ys = y1;
    double sb_keep = 1.0;
    Vec yb = y1;
    for (int it = 0; it < 40 && (b - a) * h > 1e-12; ++it) {
        double s = (a * gb - b * ga) / (gb - ga);
        if (!(s > a && s < b)) s = 0.5 * (a + b);
        integrate(pl, y, s * h, k1, ys);
        const double gs = event_g(pl, ys, m, active);
        if (gs < 0.0) {
            b = s; gb = gs; yb = ys; sb_keep = s;
            if (side == -1) ga *= 0.5;
            side = -1;
        } else {
            a = s; ga = gs;
            if (side == +1) gb *= 0.5;
            side = +1;
        }
    }
    y1 = yb;
    // Snap the currents that crossed zero to exactly zero, keeping sum(i) = 0.
    bool snapped[3] = {false, false, false};
    for (int x = 0; x < 3; ++x) {
        if (!active[x] || m.ph[x] == PH_BLOCKED) continue;
        const double v = (m.ph[x] == PH_POS) ? y1[S_IA + x] : -y1[S_IA + x];
        if (v <= 1e-9) snapped[x] = true;
    }
    snap_currents(y1, snapped);
    y = y1;
    return sb_keep * h;
}

// Gate timeline of leg x after its command (cmd, enable, override) changed at time t: the
// outgoing device turns off at once, the incoming one after the dead time; in between only the
// diodes conduct, the current sign picking which (Hoang/inverter practice). Used at the start of an
// advance and at every switching instant inside it (plant_set_leg_edges).
void command_leg(plant_t *pl, int x) {
    const plant_params_t &p = pl->p;
    int want;
    if (pl->override_mode[x] == PLANT_LEG_DIODE_ONLY) want = GATE_OFF;
    else if (pl->override_mode[x] == PLANT_LEG_UPPER_ON) want = GATE_UPPER;
    else if (pl->override_mode[x] == PLANT_LEG_LOWER_ON) want = GATE_LOWER;
    else if (!pl->enable) want = GATE_OFF;
    else want = pl->cmd[x] ? GATE_UPPER : GATE_LOWER;
    // Resolve a dead time still running from the previous command.
    if (pl->dead_end[x] > pl->t) {
        // Still off; the new target replaces the old one, dead time keeps running.
        pl->gate_target[x] = want;
        if (want == GATE_OFF) pl->dead_end[x] = pl->t;
        return;
    }
    const int cur = pl->gate[x];
    if (want == cur) return;
    const bool both_on = (cur != GATE_OFF) && (want != GATE_OFF);
    if (both_on && p.dead_time_enabled && p.dead_time_s > 0.0) {
        pl->gate[x] = GATE_OFF;
        pl->gate_target[x] = want;
        pl->dead_end[x] = pl->t + p.dead_time_s;
    } else {
        pl->gate[x] = want;
        pl->gate_target[x] = want;
    }
}

void update_gates_for_command(plant_t *pl) {
    for (int x = 0; x < 3; ++x) command_leg(pl, x);
}

const char *check_params(const plant_params_t *p) {
    if (!p) return "params: NULL";
    auto bad = [](double v) { return !std::isfinite(v); };
    if (bad(p->rs_ohm) || p->rs_ohm < 0.0) return "rs_ohm must be finite and >= 0";
    if (p->machine != PLANT_MACHINE_PM && p->machine != PLANT_MACHINE_IM)
        return "machine must be PLANT_MACHINE_PM or PLANT_MACHINE_IM";
    if (p->machine == PLANT_MACHINE_IM) {
        if (bad(p->rr_ohm) || p->rr_ohm <= 0.0) return "rr_ohm must be finite and > 0";
        if (bad(p->lm_h) || p->lm_h <= 0.0) return "lm_h must be finite and > 0";
        if (bad(p->lls_h) || p->lls_h < 0.0) return "lls_h must be finite and >= 0";
        if (bad(p->llr_h) || p->llr_h < 0.0) return "llr_h must be finite and >= 0";
        if (p->lls_h + p->llr_h <= 0.0) return "lls_h + llr_h must be > 0 (sigma L_s is the stator's inductance)";
    }
    if (p->machine == PLANT_MACHINE_PM) {
        if (bad(p->ls_h) || p->ls_h <= 0.0) return "ls_h must be finite and > 0";
        if (bad(p->psi_m_wb) || p->psi_m_wb < 0.0) return "psi_m_wb must be finite and >= 0";
    }
    if (p->pole_pairs < 1 || p->pole_pairs > 64) return "pole_pairs must be in 1..64";
    for (int x = 0; x < 3; ++x) {
        if (bad(p->emf_gain[x]) || p->emf_gain[x] < 0.0) return "emf_gain[] must be finite and >= 0";
        for (int k = 0; k < 3; ++k)
            if (bad(p->emf_harm[x][k]) || std::fabs(p->emf_harm[x][k]) > 1.0)
                return "emf_harm[][] must be finite with |h| <= 1";
    }
    if (bad(p->j_kgm2) || p->j_kgm2 <= 0.0) return "j_kgm2 must be finite and > 0";
    if (bad(p->b_nms) || p->b_nms < 0.0) return "b_nms must be finite and >= 0";
    if (bad(p->coulomb_nm) || p->coulomb_nm < 0.0) return "coulomb_nm must be finite and >= 0";
    if (bad(p->r_bal_ohm) || p->r_bal_ohm < 0.0) return "r_bal_ohm must be finite and >= 0 (0 = not fitted)";
    if (bad(p->esr_ohm) || p->esr_ohm < 0.0) return "esr_ohm must be finite and >= 0";
    if (p->inverter != PLANT_INVERTER_IDEAL && p->inverter != PLANT_INVERTER_SSTP &&
        p->inverter != PLANT_INVERTER_FSTP)
        return "inverter must be PLANT_INVERTER_IDEAL, _SSTP or _FSTP";
    if (bad(p->vdc_v) || p->vdc_v <= 0.0) return "vdc_v must be finite and > 0";
    if (bad(p->v_ce_v) || p->v_ce_v < 0.0) return "v_ce_v must be finite and >= 0";
    if (bad(p->v_d_v) || p->v_d_v < 0.0) return "v_d_v must be finite and >= 0";
    if (bad(p->r_on_ohm) || p->r_on_ohm < 0.0) return "r_on_ohm must be finite and >= 0";
    if (bad(p->dead_time_s) || p->dead_time_s < 0.0 || p->dead_time_s > 20e-6)
        return "dead_time_s must be in [0, 20e-6]";
    if (bad(p->max_step_s) || p->max_step_s <= 0.0 || p->max_step_s > 100e-6)
        return "max_step_s must be in (0, 100e-6]";
    if (p->finite_dc_link && p->inverter != PLANT_INVERTER_IDEAL) {
        if (bad(p->c_dc_f) || p->c_dc_f <= 0.0) return "c_dc_f must be > 0 with finite_dc_link";
        if (bad(p->r_dc_ohm) || p->r_dc_ohm <= 0.0) return "r_dc_ohm must be > 0 with finite_dc_link";
        // RK4 accuracy/stability on the source-capacitor mode: lambda * h <= 1.
        const double c_eff = (p->inverter == PLANT_INVERTER_FSTP) ? 0.5 * p->c_dc_f : 2.0 * p->c_dc_f;
        if (p->max_step_s > p->r_dc_ohm * c_eff)
            return "max_step_s exceeds r_dc_ohm * C_link (DC source/capacitor time constant): "
                   "reduce max_step_s or raise r_dc_ohm / c_dc_f";
    }
    if (p->load < PLANT_LOAD_SPEED || p->load > PLANT_LOAD_FAN)
        return "load must be PLANT_LOAD_SPEED, _TORQUE, _GENERATOR, _INERTIA or _FAN";
    if (bad(p->load_speed_rpm) || bad(p->load_torque_nm)) return "load_speed_rpm/load_torque_nm must be finite";
    if (p->load == PLANT_LOAD_GENERATOR && p->load_speed_rpm == 0.0)
        return "load_speed_rpm must be non-zero for PLANT_LOAD_GENERATOR (torque = T * n / n_ref)";
    if (p->load == PLANT_LOAD_FAN && p->load_speed_rpm == 0.0)
        return "load_speed_rpm must be non-zero for PLANT_LOAD_FAN (torque = T * (n / n_ref)^2)";
    if (bad(p->speed0_rpm) || bad(p->theta_m0_rad)) return "speed0_rpm/theta_m0_rad must be finite";
    return nullptr;
}

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
    p->b_nms = PLANT_DEF_PM_B_NM_S_PER_RAD;
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
    p->b_nms = PLANT_DEF_IM_B_NM_S_PER_RAD;
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
    derive(pl);
    make_glob(pl);
    pl->y.setZero();
    pl->y[S_THETA] = p->theta_m0_rad;
    pl->y[S_OMEGA] = (p->load == PLANT_LOAD_SPEED ? p->load_speed_rpm : p->speed0_rpm) * kRpmToRadS;
    pl->y[S_VCLO] = pl->y[S_VCHI] = 0.5 * p->vdc_v;
    pl->t = 0.0;
    pl->last_dt = 0.0;
    for (int x = 0; x < 3; ++x) {
        pl->cmd[x] = 0;
        pl->gate[x] = pl->gate_target[x] = GATE_OFF;
        pl->dead_end[x] = -1.0;
        pl->edge_n[x] = pl->edge_k[x] = 0;
        pl->override_mode[x] = PLANT_LEG_NORMAL;
        pl->mode.ph[x] = PH_BLOCKED;
    }
    pl->enable = 0;
    pl->edges_left = 0;
    pl->v_set_alpha = pl->v_set_beta = 0.0;
    pl->th0 = 0.0;
    pl->c0 = 1.0;
    pl->s0 = 0.0;
    pl->sync_count = 0;
    pl->tc_valid = false;
    std::memset(&pl->stats, 0, sizeof(pl->stats));
    build_leg_table(pl);
    build_legs(pl);
    return pl;
}

void plant_destroy(plant_t *plant) { delete plant; }

// The 0/100 % case of plant_set_leg_edges: each leg's state at the start, no instant inside.
void plant_set_legs(plant_t *plant, int sa, int sb, int sc, int enable) {
    plant->cmd[0] = sa ? 1 : 0;
    plant->cmd[1] = sb ? 1 : 0;
    plant->cmd[2] = sc ? 1 : 0;
    plant->enable = enable ? 1 : 0;
    plant->edge_n[0] = plant->edge_n[1] = plant->edge_n[2] = 0;
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
    for (int x = 0; x < 3; ++x) {
        plant->cmd[x] = legs[x].state0 ? 1 : 0;
        plant->edge_n[x] = legs[x].n;
        for (int k = 0; k < legs[x].n; ++k) plant->edge_t[x][k] = legs[x].t_s[k];
    }
    plant->enable = enable ? 1 : 0;
    return 0;
}

void plant_set_voltage(plant_t *plant, double v_alpha_v, double v_beta_v) {
    plant->v_set_alpha = v_alpha_v;
    plant->v_set_beta = v_beta_v;
    build_leg_table(plant);  // the ideal source's phase voltages live in the leg coefficients
    build_legs(plant);
}

void plant_set_load(plant_t *plant, plant_load_t load, double speed_rpm, double torque_nm) {
    plant->p.load = load;
    plant->p.load_speed_rpm = speed_rpm;
    plant->p.load_torque_nm = torque_nm;
    derive(plant);
    if (load == PLANT_LOAD_SPEED) plant->y[S_OMEGA] = speed_rpm * kRpmToRadS;
    if ((load == PLANT_LOAD_GENERATOR || load == PLANT_LOAD_FAN) && speed_rpm == 0.0)
        plant->omega_load_ref = 1e300;  // no load
    make_glob(plant);
}

int plant_set_leg_override(plant_t *plant, int leg, plant_leg_override_t mode) {
    if (!plant || leg < 0 || leg > 2 || mode < PLANT_LEG_NORMAL || mode > PLANT_LEG_LOWER_ON) return -1;
    plant->override_mode[leg] = mode;
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
    // Terminal-voltage integrals restart every advance (their mean over it is reported).
    pl->y[S_IVA0] = pl->y[S_IVB0] = pl->y[S_IVC0] = 0.0;
    pl->last_dt = dt_s;
    // Switching instants inside the advance: an instant at 0 acts at once, one at or beyond
    // dt_s at the end (the leg then holds its last command into the next advance).
    const bool has_edges = (pl->edge_n[0] | pl->edge_n[1] | pl->edge_n[2]) != 0;
    pl->edges_left = 0;
    for (int x = 0; has_edges && x < 3; ++x) {
        pl->edge_k[x] = 0;
        for (int k = 0; k < pl->edge_n[x]; ++k) pl->edge_abs[x][k] = pl->t + pl->edge_t[x][k];
        while (pl->edge_k[x] < pl->edge_n[x] && pl->edge_t[x][pl->edge_k[x]] <= 0.0) {
            pl->cmd[x] ^= 1;
            ++pl->edge_k[x];
        }
        pl->edges_left += pl->edge_n[x] - pl->edge_k[x];
    }
    update_gates_for_command(pl);
    const double t_end = pl->t + dt_s;
    const double eps = 1e-12 * (1.0 + std::fabs(t_end));
    int guard = 0;  // a runaway cap (never reached in the tests): 1e6 sub-steps per advance
    while (pl->t < t_end - eps && guard < 1000000) {
        ++guard;
        double next = t_end;
        bool changed = false;
        for (int x = 0; x < 3; ++x) {
            if (pl->gate[x] != pl->gate_target[x]) {
                if (pl->dead_end[x] <= pl->t + eps) {
                    pl->gate[x] = pl->gate_target[x];
                    changed = true;
                } else {
                    next = std::min(next, pl->dead_end[x]);
                }
            }
        }
        if (pl->edges_left > 0) {
            // Switching instants reached (the sub-steps land on them exactly, below); the dead
            // times they start join the candidates for the sub-step's end.
            for (int x = 0; x < 3; ++x) {
                while (pl->edge_k[x] < pl->edge_n[x] && pl->edge_abs[x][pl->edge_k[x]] <= pl->t) {
                    pl->cmd[x] ^= 1;
                    ++pl->edge_k[x];
                    --pl->edges_left;
                    command_leg(pl, x);
                    changed = true;
                }
                if (pl->gate[x] != pl->gate_target[x]) next = std::min(next, pl->dead_end[x]);
            }
        }
        // A sub-step ending at a dead-time end (not at a switching instant): the midpoint-rule case.
        const double next_dead = next;
        if (pl->edges_left > 0) {
            for (int x = 0; x < 3; ++x)
                if (pl->edge_k[x] < pl->edge_n[x]) next = std::min(next, pl->edge_abs[x][pl->edge_k[x]]);
        }
        if (changed || guard == 1) build_legs(pl);
        const double h = std::min(pl->p.max_step_s, next - pl->t);
        // A sub-step that ends at a dead-time end and is at most max_step/16 long (default: the
        // 2 us dead-time segment at the 50 us step) uses the midpoint rule: its local error is
        // O(h^3) on a tiny h, well below the RK4 error of the main step (docs/plant.md, section 2).
        pl->short_seg = next < t_end && next == next_dead && h == next - pl->t &&
                        h <= pl->p.max_step_s * (1.0 / 16.0);
        const double taken = step(pl, h);
        // Land exactly on breakpoints to avoid drift.
        if (taken == h) pl->t = (h == next - pl->t) ? next : pl->t + h;
        else pl->t += taken;
    }
    // Instants left (at or within eps of the end, or beyond it) set the command held from now.
    for (int x = 0; has_edges && x < 3; ++x) {
        for (; pl->edge_k[x] < pl->edge_n[x]; ++pl->edge_k[x]) pl->cmd[x] ^= 1;
        pl->edge_n[x] = 0;
    }
    pl->edges_left = 0;
    pl->t = t_end;
    if (pl->p.load == PLANT_LOAD_SPEED) pl->y[S_OMEGA] = pl->p.load_speed_rpm * kRpmToRadS;
}

void plant_get_state(const plant_t *plant, plant_state_t *s) {
    plant_t *pl = const_cast<plant_t *>(plant);  // rhs() counts evaluations; the state is unchanged
    // Every field is assigned below (no memset: this runs once per control period).
    static_assert(offsetof(plant_state_t, psi_r_beta_wb) == 34 * sizeof(double) &&
                      sizeof(plant_state_t) <= 35 * sizeof(double),
                  "plant_state_t changed: assign the new fields");
    const plant_params_t &p = pl->p;
    const Vec &y = pl->y;
    const double pp = p.pole_pairs;
    const double theta_e = pp * y[S_THETA];
    double dpsi[3], psi[3];
    // The reported flux and torque use the exact formula (rotation from the expansion centre).
    pm_flux_centre(pl, theta_e, dpsi, psi);
    s->t_s = pl->t;
    s->i_a = y[S_IA];
    s->i_b = y[S_IB];
    s->i_c = y[S_IC];
    // Amplitude-invariant Clarke (Hoang eqs. 4-5).
    s->i_alpha_a = (2.0 * s->i_a - s->i_b - s->i_c) * (1.0 / 3.0);
    s->i_beta_a = (s->i_b - s->i_c) * (1.0 / kSqrt3);
    const double psi_pm_alpha = (2.0 * psi[0] - psi[1] - psi[2]) * (1.0 / 3.0);
    const double psi_pm_beta = (psi[1] - psi[2]) * (1.0 / kSqrt3);
    if (!pl->im) {
        s->psi_alpha_wb = p.ls_h * s->i_alpha_a + psi_pm_alpha;  // Hoang eq. (8)
        s->psi_beta_wb = p.ls_h * s->i_beta_a + psi_pm_beta;     // Hoang eq. (9)
        s->psi_r_alpha_wb = s->psi_r_beta_wb = 0.0;
    } else {
        // psi_s = sigma L_s i_s + (L_m/L_r) psi_r (Casadei A8-A9 with i_r eliminated).
        s->psi_r_alpha_wb = y[S_PSIRA];
        s->psi_r_beta_wb = y[S_PSIRB];
        s->psi_alpha_wb = pl->imc.l_eff * s->i_alpha_a + pl->imc.kr * y[S_PSIRA];
        s->psi_beta_wb = pl->imc.l_eff * s->i_beta_a + pl->imc.kr * y[S_PSIRB];
    }
    // Wrap to [0, 2 pi): floor by truncation (|turns| < 2^53 for any finite run).
    const double turns = theta_e * (0.5 / kPi);
    double whole = static_cast<double>(static_cast<long long>(turns));
    if (whole > turns) whole -= 1.0;
    double th = theta_e - 2.0 * kPi * whole;
    if (th >= 2.0 * kPi) th -= 2.0 * kPi;
    if (th < 0.0) th = 0.0;
    s->theta_e_rad = th;
    s->theta_m_rad = y[S_THETA];
    s->omega_m_rad_s = y[S_OMEGA];
    s->speed_rpm = y[S_OMEGA] * (1.0 / kRpmToRadS);
    double te = 0.0;
    for (int x = 0; x < 3; ++x) te += y[S_IA + x] * dpsi[x];
    s->te_nm = pp * te;
    if (pl->im) {
        // Casadei eq. (A10): T_e = 1.5 p Im(conj(psi_s) i_s).
        s->te_nm = 1.5 * pp * (s->psi_alpha_wb * s->i_beta_a - s->psi_beta_wb * s->i_alpha_a);
    }
    s->tload_nm = pl->g.ld_c0 + pl->g.ld_cw * y[S_OMEGA] + pl->g.ld_cte * s->te_nm;  // as in rhs_t
    if (pl->fan_on) s->tload_nm += pl->g.ld_cq * y[S_OMEGA] * std::fabs(y[S_OMEGA]);
    if (pl->coulomb_on) {
        const double w = y[S_OMEGA];
        s->tload_nm -= pl->g.ld_cte * mech::coulomb_torque(p.coulomb_nm, w, s->te_nm - p.b_nms * w - s->tload_nm);
    }
    if (pl->link.on) {
        dc_link_terminals(pl, y, s->vc_lo_v, s->vc_hi_v);
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
    const double ia2 = s->i_alpha_a * s->i_alpha_a + s->i_beta_a * s->i_beta_a;
    s->e_magnetic_j = pl->im ? im::magnetic_energy(pl->imc, s->i_alpha_a, s->i_beta_a, y[S_PSIRA], y[S_PSIRB])
                             : 0.75 * p.ls_h * ia2;  // (3/2) * (1/2) L_s |i|^2, amplitude-invariant frame
    s->e_kinetic_j = 0.5 * p.j_kgm2 * y[S_OMEGA] * y[S_OMEGA];
    if (p.inverter == PLANT_INVERTER_SSTP) {
        const double v = y[S_VCLO] + y[S_VCHI];
        s->e_capacitor_j = 0.5 * pl->c_lo * v * v;
    } else if (p.inverter == PLANT_INVERTER_FSTP) {
        s->e_capacitor_j = 0.5 * pl->c_lo * y[S_VCLO] * y[S_VCLO] + 0.5 * pl->c_hi * y[S_VCHI] * y[S_VCHI];
    } else {
        s->e_capacitor_j = 0.0;
    }
    int mask = 0;
    if (y[S_IA] == 0.0 || y[S_IB] == 0.0 || y[S_IC] == 0.0) {
        const Mode m = select_mode(pl, y);
        for (int x = 0; x < 3; ++x)
            if (m.ph[x] == PH_BLOCKED) mask |= 1 << x;
    }
    s->blocked_mask = mask;
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
    if (plant->link.on) {
        dc_link_terminals(plant, y, s->vc_lo_v, s->vc_hi_v);
    } else {
        s->vc_lo_v = y[S_VCLO];
        s->vc_hi_v = y[S_VCHI];
    }
    s->vdc_v = s->vc_lo_v + s->vc_hi_v;
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
