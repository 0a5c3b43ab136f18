// ref_dtc.cpp - double-precision reference DTC (see ref_dtc.h and docs/plant.md).
#include "ref_dtc.h"

#include <cmath>

namespace dtc_ref {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kSqrt3 = 1.73205080756887729353;

inline double sgn(double i) { return (i >= 0.0) ? 1.0 : -1.0; }  // i >= 0 counts as "+"

int wrap6(int k) { return ((k - 1) % 6 + 6) % 6 + 1; }
int wrap4(int k) { return ((k - 1) % 4 + 4) % 4 + 1; }

int null_vector(const int prev[3]) {
    // Casadei Sec. 5: choose 0 or 7 to minimise the number of leg transitions.
    const int ones = (prev[0] != 0) + (prev[1] != 0) + (prev[2] != 0);
    return (ones >= 2) ? 7 : 0;
}
}  // namespace

void clarke(double a, double b, double c, double &alpha, double &beta) {
    alpha = (2.0 * a - b - c) / 3.0;  // Hoang eq. (4)
    beta = (b - c) / kSqrt3;          // Hoang eq. (5)
}

void phase_from_pole(const double v0[3], double vn[3]) {
    vn[0] = (2.0 * v0[0] - v0[1] - v0[2]) / 3.0;  // Hoang eq. (1)
    vn[1] = (2.0 * v0[1] - v0[0] - v0[2]) / 3.0;  // Hoang eq. (2)
    vn[2] = (2.0 * v0[2] - v0[0] - v0[1]) / 3.0;  // Hoang eq. (3)
}

void sstp_phase_voltages(int sa, int sb, int sc, double vdc, double vn[3]) {
    const double v0[3] = {sa * vdc, sb * vdc, sc * vdc};
    phase_from_pole(v0, vn);
}

void fstp_phase_voltages(int sb, int sc, double vdc, double vn[3]) {
    vn[0] = vdc * (1.0 - sb - sc) / 3.0;            // Hoang eq. (17)
    vn[1] = vdc * (4.0 * sb - 2.0 * sc - 1.0) / 6.0;  // Hoang eq. (18)
    vn[2] = vdc * (4.0 * sc - 2.0 * sb - 1.0) / 6.0;  // Hoang eq. (19)
}

void fstp_phase_voltages_mid(int sb, int sc, double vc_lo, double vc_hi, double vn[3]) {
    const double vdc = vc_lo + vc_hi;
    const double v0[3] = {vc_lo, sb * vdc, sc * vdc};
    phase_from_pole(v0, vn);
}

double leg_forward_drop(int s, double i, double v_ce, double v_d) {
    // Hoang Table III.
    if (s == 0) return (i >= 0.0) ? v_d : -v_ce;
    return (i >= 0.0) ? v_ce : -v_d;
}

void fstp_drop_simple(double i_b, double i_c, double v_f, double &vf_alpha, double &vf_beta) {
    vf_alpha = v_f * (sgn(i_b) + sgn(i_c)) / 3.0;       // Hoang eq. (35), Table V
    vf_beta = -v_f * (sgn(i_b) - sgn(i_c)) / kSqrt3;    // Hoang eq. (36), Table V
}

void fstp_drop_proposed(int sb, int sc, double i_b, double i_c, double v_ce, double v_d,
                        double &vf_alpha, double &vf_beta) {
    const double vfb = leg_forward_drop(sb, i_b, v_ce, v_d);
    const double vfc = leg_forward_drop(sc, i_c, v_ce, v_d);
    vf_alpha = (vfb + vfc) / 3.0;       // Hoang eq. (33) -> Table VI
    vf_beta = -(vfb - vfc) / kSqrt3;    // Hoang eq. (34) -> Table VI
}

void sstp_drop_equal(double i_a, double i_b, double i_c, double v_f, double &vf_alpha, double &vf_beta) {
    // Each leg drops v_f sign(i_x); the phase-to-zero voltages lose it, Hoang eqs. (1)-(5) carry it to
    // alpha-beta; the terms to ADD to the ideal voltage (same convention as Hoang eqs. 31-34).
    const double d[3] = {v_f * sgn(i_a), v_f * sgn(i_b), v_f * sgn(i_c)};
    vf_alpha = -(2.0 * d[0] - d[1] - d[2]) / 3.0;
    vf_beta = -(d[1] - d[2]) / kSqrt3;
}

int sector_sstp(double psi_alpha, double psi_beta) {
    const double ang = std::atan2(psi_beta, psi_alpha);  // (-pi, pi]
    const int k = static_cast<int>(std::floor((ang + kPi / 6.0) / (kPi / 3.0)));
    return ((k % 6) + 6) % 6 + 1;
}

int sector_fstp(double psi_alpha, double psi_beta) {
    double ang = std::atan2(psi_beta, psi_alpha);
    if (ang < 0.0) ang += 2.0 * kPi;
    int k = static_cast<int>(std::floor(ang / (kPi / 2.0)));
    if (k > 3) k = 3;
    return k + 1;
}

int hysteresis2(double err, double band, int prev) {
    if (err > 0.5 * band) return 1;   // Hoang eqs. (13)-(14)
    if (err < -0.5 * band) return 0;
    return prev;
}

int hysteresis3(double err, double band, int prev) {
    const double h = 0.5 * band;
    if (err > h) return 1;
    if (err < -h) return -1;
    if (prev == 1 && err <= 0.0) return 0;
    if (prev == -1 && err >= 0.0) return 0;
    return prev;
}

int table_casadei1(int sector, int c_psi, int c_te, const int prev_legs[3]) {
    if (c_te == 0) return null_vector(prev_legs);
    if (c_psi) return wrap6(sector + (c_te > 0 ? 1 : -1));  // c_phi = +1: k+1 / k-1
    return wrap6(sector + (c_te > 0 ? 2 : -2));             // c_phi = -1: k+2 / k-2
}

int table_casadei3(SwitchingTable st, int sector, int d_psi, int d_te, const int prev_legs[3]) {
    if (d_te) return wrap6(sector + (d_psi ? 1 : 2));  // T up: V_{k+1} / V_{k+2} (all four STs)
    if (d_psi) {                                       // T down, psi up
        switch (st) {
            case SwitchingTable::ST_A: return null_vector(prev_legs);
            case SwitchingTable::ST_B:
            case SwitchingTable::ST_C: return sector;
            default: return wrap6(sector - 1);          // ST-D
        }
    }
    switch (st) {                                      // T down, psi down
        case SwitchingTable::ST_A:
        case SwitchingTable::ST_B: return null_vector(prev_legs);
        case SwitchingTable::ST_C: return wrap6(sector + 3);
        default: return wrap6(sector - 2);              // ST-D
    }
}

int table_hoang2(int sector, int d_psi, int d_te) {
    if (d_psi) return wrap4(sector + (d_te ? 1 : 0));
    return wrap4(sector + (d_te ? 2 : 3));
}

void sstp_vector_legs(int vector, int legs[3]) {
    static const int tab[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                  {0, 1, 1}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}};
    const int v = (vector >= 0 && vector <= 7) ? vector : 0;
    for (int i = 0; i < 3; ++i) legs[i] = tab[v][i];
}

void fstp_vector_legs(int vector, int &sb, int &sc) {
    static const int tab[5][2] = {{0, 0}, {0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const int v = (vector >= 1 && vector <= 4) ? vector : 1;
    sb = tab[v][0];
    sc = tab[v][1];
}

void fstp_vector_towards(double angle_rad, int &sb, int &sc) {
    double x = std::fmod(angle_rad, 2 * kPi);
    if (x < 0) x += 2 * kPi;
    const int k = static_cast<int>(std::floor((x + kPi / 4) / (kPi / 2))) % 4;
    fstp_vector_legs(k + 1, sb, sc);
}

int Controller::init(const Params &p) {
    msg_.clear();
    auto fail = [this](const char *m) {
        msg_ = m;
        return -1;
    };
    if (!(p.ts_s > 0.0)) return fail("ts_s must be > 0");
    if (p.speed_divider < 1) return fail("speed_divider must be >= 1");
    if (!(p.ls_h > 0.0)) return fail("ls_h must be > 0");
    if (!(p.rs_ohm >= 0.0)) return fail("rs_ohm must be >= 0");
    if (!(p.psi_m_wb >= 0.0)) return fail("psi_m_wb must be >= 0");
    if (p.pole_pairs < 1) return fail("pole_pairs must be >= 1");
    if (!(p.lpf_wc_rad_s >= 0.0)) return fail("lpf_wc_rad_s must be >= 0");
    if (p.voltage_delay_periods < 1 || p.voltage_delay_periods > 4)
        return fail("voltage_delay_periods must be in 1..4");
    if (!(p.band_psi_wb >= 0.0) || !(p.band_te_nm >= 0.0)) return fail("band_psi_wb/band_te_nm must be >= 0");
    if (!(p.te_max_nm > 0.0)) return fail("te_max_nm must be > 0");
    if (!(p.kp_nm_s_rad >= 0.0) || !(p.ki_nm_rad >= 0.0)) return fail("kp_nm_s_rad/ki_nm_rad must be >= 0");
    if (!(p.psi_ref_wb > 0.0)) return fail("psi_ref_wb must be > 0");
    const bool fstp = (p.topology == Topology::FSTP);
    if (fstp != (p.table == SwitchingTable::HOANG_FSTP))
        return fail("table: HOANG_FSTP goes with Topology::FSTP, the Casadei tables with SSTP");
    if (fstp && p.comp == DropComp::SSTP_EQUAL) return fail("comp: SSTP_EQUAL needs Topology::SSTP");
    if (!fstp && (p.comp == DropComp::FSTP_SIMPLE || p.comp == DropComp::FSTP_PROPOSED))
        return fail("comp: FSTP_SIMPLE/FSTP_PROPOSED need Topology::FSTP");
    p_ = p;
    reset(0.0);
    return 0;
}

void Controller::reset(double theta_e0_rad) {
    integ_ = 0.0;
    div_count_ = 0;
    te_ref_ = 0.0;
    psi_a_ = p_.psi_m_wb * std::cos(theta_e0_rad);
    psi_b_ = p_.psi_m_wb * std::sin(theta_e0_rad);
    first_ = true;
    for (auto &h : hist_) h[0] = h[1] = h[2] = 0;
    c_psi_ = 1;
    c_te_ = 1;
    last_ = Out{};
}

void Controller::keep_samples(const Meas &m, double i_alpha, double i_beta) {
    i_alpha_prev_ = i_alpha;
    i_beta_prev_ = i_beta;
    i_prev_[0] = m.i_a;
    i_prev_[1] = m.i_b;
    i_prev_[2] = m.i_c;
    vdc_prev_ = m.vdc_v;
    vc_lo_prev_ = m.vc_lo_v;
    vc_hi_prev_ = m.vc_hi_v;
}

Out Controller::step(const Meas &m) {
    const Params &p = p_;
    Out o;
    clarke(m.i_a, m.i_b, m.i_c, o.i_alpha, o.i_beta);
    const double ix[3] = {m.i_a, m.i_b, m.i_c};
    if (first_) keep_samples(m, o.i_alpha, o.i_beta);
    // ---- Stator flux ----
    if (p.estimator == FluxEstimator::CURRENT_MODEL) {
        psi_a_ = p.ls_h * o.i_alpha + p.psi_m_wb * std::cos(m.theta_e_rad);  // Hoang eq. (8)
        psi_b_ = p.ls_h * o.i_beta + p.psi_m_wb * std::sin(m.theta_e_rad);   // Hoang eq. (9)
    } else if (!first_) {
        // Voltage applied over the period just elapsed: legs output voltage_delay_periods ago,
        // DC-link voltages and currents averaged over the period (trapezoid).
        const int *lg = hist_[p.voltage_delay_periods - 1];
        const double vdc = 0.5 * (m.vdc_v + vdc_prev_);
        double vn[3];
        if (p.topology == Topology::SSTP) {
            sstp_phase_voltages(lg[0], lg[1], lg[2], vdc, vn);
        } else if (m.have_vc) {
            fstp_phase_voltages_mid(lg[1], lg[2], 0.5 * (m.vc_lo_v + vc_lo_prev_),
                                    0.5 * (m.vc_hi_v + vc_hi_prev_), vn);
        } else {
            fstp_phase_voltages(lg[1], lg[2], vdc, vn);
        }
        double va, vb;
        clarke(vn[0], vn[1], vn[2], va, vb);
        const double ia = 0.5 * (o.i_alpha + i_alpha_prev_), ib = 0.5 * (o.i_beta + i_beta_prev_);
        double im[3];
        for (int x = 0; x < 3; ++x) im[x] = 0.5 * (ix[x] + i_prev_[x]);
        double fa = 0.0, fb = 0.0;
        switch (p.comp) {
            case DropComp::NONE: break;
            case DropComp::SSTP_EQUAL:
                sstp_drop_equal(im[0], im[1], im[2], p.v_f_v, fa, fb);
                fa -= p.r_on_ohm * ia;  // Hoang eqs. (24)-(25)
                fb -= p.r_on_ohm * ib;
                break;
            case DropComp::FSTP_SIMPLE:
            case DropComp::FSTP_PROPOSED:
                if (p.comp == DropComp::FSTP_SIMPLE) fstp_drop_simple(im[1], im[2], p.v_f_v, fa, fb);
                else fstp_drop_proposed(lg[1], lg[2], im[1], im[2], p.v_ce_v, p.v_d_v, fa, fb);
                fa += (p.ron_alpha_as_printed ? 1.0 : -1.0) * p.r_on_ohm * ia / 3.0;  // Hoang eq. (37)
                fb -= p.r_on_ohm * ib;                                                // Hoang eq. (38)
                break;
        }
        o.v_alpha = va + fa;
        o.v_beta = vb + fb;
        // Hoang eqs. (15)-(16) through a first-order low-pass 1/(s + wc) instead of 1/s, discretised
        // exactly for an input held over the period.
        const double ua = o.v_alpha - p.rs_ohm * ia, ub = o.v_beta - p.rs_ohm * ib;
        if (p.lpf_wc_rad_s > 0.0) {
            const double a = std::exp(-p.lpf_wc_rad_s * p.ts_s);
            const double g = (1.0 - a) / p.lpf_wc_rad_s;
            psi_a_ = a * psi_a_ + g * ua;
            psi_b_ = a * psi_b_ + g * ub;
        } else {
            psi_a_ += p.ts_s * ua;
            psi_b_ += p.ts_s * ub;
        }
    }
    o.psi_alpha = psi_a_;
    o.psi_beta = psi_b_;
    o.psi_mag = std::sqrt(psi_a_ * psi_a_ + psi_b_ * psi_b_);                        // Hoang eq. (11)
    o.te_nm = 1.5 * p.pole_pairs * (psi_a_ * o.i_beta - psi_b_ * o.i_alpha);         // Hoang eq. (10)
    // ---- Speed loop at 1/speed_divider of the rate (Hoang Sec. IV), or torque mode ----
    if (p.mode == ControlMode::SPEED) {
        if (div_count_ == 0) {
            const double tss = p.ts_s * p.speed_divider;
            const double err = omega_ref_ - m.omega_m_rad_s;
            const double prop = p.kp_nm_s_rad * err;
            double integ = integ_ + p.ki_nm_rad * tss * err;
            if (integ > p.te_max_nm) integ = p.te_max_nm;
            if (integ < -p.te_max_nm) integ = -p.te_max_nm;
            double u = prop + integ;
            // Anti-windup by conditional integration: hold the integrator while the output is
            // saturated and the error would drive it further into saturation.
            if (u > p.te_max_nm) {
                u = p.te_max_nm;
                if (err > 0.0) integ = integ_;
            } else if (u < -p.te_max_nm) {
                u = -p.te_max_nm;
                if (err < 0.0) integ = integ_;
            }
            integ_ = integ;
            te_ref_ = u;
        }
        div_count_ = (div_count_ + 1) % p.speed_divider;
    } else {
        te_ref_ = std::fmax(-p.te_max_nm, std::fmin(p.te_max_nm, te_ref_cmd_));
    }
    o.te_ref_nm = te_ref_;
    // ---- Comparators, sector, switching table ----
    c_psi_ = hysteresis2(p.psi_ref_wb - o.psi_mag, p.band_psi_wb, c_psi_);  // Hoang eq. (13)
    const int *prev = hist_[0];
    int legs[3] = {0, 0, 0};
    if (p.topology == Topology::FSTP) {
        c_te_ = hysteresis2(te_ref_ - o.te_nm, p.band_te_nm, c_te_ > 0 ? 1 : 0);  // Hoang eq. (14)
        o.sector = sector_fstp(psi_a_, psi_b_);
        o.vector = table_hoang2(o.sector, c_psi_, c_te_);
        fstp_vector_legs(o.vector, legs[1], legs[2]);
    } else {
        o.sector = sector_sstp(psi_a_, psi_b_);
        if (p.table == SwitchingTable::CASADEI_T1) {
            c_te_ = hysteresis3(te_ref_ - o.te_nm, p.band_te_nm, c_te_);
            o.vector = table_casadei1(o.sector, c_psi_, c_te_, prev);
        } else {
            c_te_ = hysteresis2(te_ref_ - o.te_nm, p.band_te_nm, c_te_ > 0 ? 1 : 0);
            o.vector = table_casadei3(p.table, o.sector, c_psi_, c_te_, prev);
        }
        sstp_vector_legs(o.vector, legs);
    }
    o.c_psi = c_psi_;
    o.c_te = c_te_;
    o.sa = legs[0];
    o.sb = legs[1];
    o.sc = legs[2];
    for (int d = 3; d > 0; --d)
        for (int x = 0; x < 3; ++x) hist_[d][x] = hist_[d - 1][x];
    for (int x = 0; x < 3; ++x) hist_[0][x] = legs[x];
    keep_samples(m, o.i_alpha, o.i_beta);
    first_ = false;
    last_ = o;
    return o;
}

}  // namespace dtc_ref
