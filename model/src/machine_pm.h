// machine_pm.h - PM BLAC machine for the plant (SI units, stationary frame), one machine behind
// the seam of machine.h: a surface PM (L_d = L_q = L_s) or a salient one (L_d != L_q).
//
// Hoang 2011 eqs. (6)-(10), written per phase so that the per-phase back-EMF gains and the
// 3rd/5th/7th harmonics (Hoang Table VII) enter naturally:
//   L_s di_x/dt = v_x0 - v_n0 - R_s i_x - e_x,   e_x = omega_e dpsi_pm,x/dtheta_e,
//   psi_pm,x = sum_n flux_amp[x][n] cos(n (theta_e - phi_x)), phi_x = 0, 2pi/3, 4pi/3.
// Torque T_e = p sum(i_x dpsi_pm,x/dtheta_e), which for sinusoidal balanced EMF is exactly Hoang
// eq. (10), 1.5 p (psi_alpha i_beta - psi_beta i_alpha). For the shared per-phase circuit the PM
// machine is the inductance L_s, the resistance R_s and the magnet's EMF; it has no states of its
// own. docs/plant.md, section 2, gives the error of the EMF expansion below.
//
// Salient PM (lq_h given and != ls_h): in the rotor frame psi_d = L_d i_d + psi_m, psi_q = L_q i_q
// (Hoang eqs. 8-9 with the inductance split by axis), T_e = 1.5 p (psi_m i_q + (L_d - L_q) i_d i_q).
// In the stationary frame the inductance turns with 2 theta_e:
//   L_ab(theta) = S0 I + S2 [cos 2th, sin 2th; sin 2th, -cos 2th],  S0 = (L_d + L_q)/2, S2 = (L_d - L_q)/2,
//   v_ab - R i_ab - e_pm,ab = L_ab di_ab/dt + omega_e (dL_ab/dtheta_e) i_ab.
// The circuit computes the currents' derivatives with the scalar L_c = L_d (circuit_inductance);
// salient_di() turns them into the salient machine's from the same terminal voltages (all three
// phases conducting: the 2x2 system above; one phase blocked: the system projected on the
// conducting pair's direction), and gives a blocked phase its floating terminal voltage with the
// mutually induced part. The surface machine never runs salient_di(): its arithmetic is unchanged.
#ifndef DTC_MODEL_MACHINE_PM_H
#define DTC_MODEL_MACHINE_PM_H

#include <cmath>

#include "plant.h"
#include "plant_state.h"

namespace plant_model {

class PmMachine {
public:
    static constexpr plant_machine_t kKind = PLANT_MACHINE_PM;
    // Parameters only this machine reads (nullptr: valid).
    static const char *check(const plant_params_t &p) {
        auto bad = [](double v) { return !std::isfinite(v); };
        if (bad(p.ls_h) || p.ls_h <= 0.0) return "ls_h must be finite and > 0";
        if (bad(p.psi_m_wb) || p.psi_m_wb < 0.0) return "psi_m_wb must be finite and >= 0";
        if (bad(p.lq_h) || p.lq_h < 0.0) return "lq_h must be finite and >= 0 (0: L_q = ls_h)";
        return nullptr;
    }

    PmMachine() = default;
    explicit PmMachine(const plant_params_t &p) noexcept : pole_pairs_(p.pole_pairs), pp_(p.pole_pairs), rs_(p.rs_ohm), ls_(p.ls_h) {
        has_harm_ = false;
        salient_ = p.lq_h > 0.0 && p.lq_h != p.ls_h;
        ld_ = p.ls_h;
        lq_ = salient_ ? p.lq_h : p.ls_h;
        sig0_ = 0.5 * (ld_ + lq_);
        sig2_ = 0.5 * (ld_ - lq_);
        for (int x = 0; x < 3; ++x) {
            const double g = p.psi_m_wb * p.emf_gain[x];
            const double h[4] = {1.0, p.emf_harm[x][0], p.emf_harm[x][1], p.emf_harm[x][2]};
            const int n[4] = {1, 3, 5, 7};
            for (int k = 0; k < 4; ++k) {
                flux_amp_[x][k] = g * h[k] / n[k];
                emf_amp_[x][k] = g * h[k];
                if (k > 0 && h[k] != 0.0) has_harm_ = true;
            }
        }
    }

    // The machine in the per-phase circuit: L di_x/dt = v_x - v_n - R i_x - e_x.
    double circuit_inductance() const { return ls_; }
    double circuit_resistance() const { return rs_; }
    double stator_resistance() const { return rs_; }  // copper loss R_s sum i_x^2

    // Before each integration step from (theta_m, omega_m) of length at most h: re-centre the EMF
    // expansion only when this step could leave n_max |delta| < kTcRecentre (truncation < 1.7e-9
    // of each harmonic's amplitude even at kTcRange); one expansion serves several periods.
    void begin_step(double theta_m, double omega_m, double h) {
        const double th = pole_pairs_ * theta_m;
        const double reach = (std::fabs(th - th0_) + std::fabs(pole_pairs_ * omega_m) * h * 1.2) * (has_harm_ ? 7.0 : 1.0);
        if (!tc_valid_ || reach >= kTcRecentre) {
            if (++sync_count_ >= 256 || std::fabs(th - th0_) >= 0.25) {
                sync_count_ = 0;
                c0_ = std::cos(th);
                s0_ = std::sin(th);
            } else {
                double c, s;
                fast_sincos(th, c, s);
                c0_ = c;
                s0_ = s;
            }
            th0_ = th;
            setup_emf_taylor();
        }
    }

    // Right-hand side, first half: phase back-EMF e_x at state y (omega_e = p omega_m), from the
    // expansion; w keeps dpsi_pm,x/dtheta_e for the torque.
    struct Work {
        double dpsi[3];
        double c, s;  // salient machine only: cos, sin theta_e
    };
    void emf(const Vec &y, double omega_e, double e[3], Work &w) const {
        dpsi_fast(pp_ * y[S_THETA], w.dpsi);
        for (int x = 0; x < 3; ++x) e[x] = omega_e * w.dpsi[x];
        if (salient_) fast_sincos(pp_ * y[S_THETA], w.c, w.s);
    }

    bool salient() const { return salient_; }
    // Work's angle for salient_di() outside the right-hand side (conduction-mode selection).
    void salient_work(const Vec &y, Work &w) const {
        const double th = pp_ * y[S_THETA];
        w.c = std::cos(th);
        w.s = std::sin(th);
    }

    // Salient machine: di (the circuit's dI/dt from L_c = L_d, phases), cond (1 conducting, 0
    // blocked), nk the number conducting, ix the currents, e the EMFs, vn0 (in: the circuit's
    // neutral voltage, out: the salient machine's) and vx0 (a blocked phase's floating terminal
    // voltage) are rewritten for L_ab(theta) (file comment). Amplitude-invariant Clarke (Hoang eqs.
    // 1-5 convention): x_alpha = x_a, x_beta = (x_b - x_c)/sqrt(3); a flux-like alpha-beta quantity X
    // is X_x = T^+ X per phase (x_a = X_alpha, x_b,c = -X_alpha/2 +- sqrt(3)/2 X_beta).
    void salient_di(int nk, const double cond[3], const double ix[3], double omega_e, const Work &w,
                    const double e[3], double di[3], double vx0[3], double &vn0) const {
        if (nk < 2) return;  // every phase blocked: no current, no change
        const double c2 = w.c * w.c - w.s * w.s, s2 = 2.0 * w.s * w.c;
        const double laa = sig0_ + sig2_ * c2, lab = sig2_ * s2, lbb = sig0_ - sig2_ * c2;  // L_ab(theta)
        const double gaa = -2.0 * sig2_ * s2, gab = 2.0 * sig2_ * c2, gbb = -gaa;    // dL_ab/dtheta_e
        const double ia = ix[0], ib = (ix[1] - ix[2]) * (1.0 / kSqrt3);
        const double ma = omega_e * (gaa * ia + gab * ib), mb = omega_e * (gab * ia + gbb * ib);  // omega dL i
        double da, db;
        if (nk == 3) {
            // L_c di_c (alpha-beta) = v - R i - e_pm; solve L_ab di = that - omega dL i (det L_d L_q).
            const double ra = ld_ * di[0] - ma, rb = ld_ * (di[1] - di[2]) * (1.0 / kSqrt3) - mb;
            const double inv_det = 1.0 / (ld_ * lq_);
            da = (lbb * ra - lab * rb) * inv_det;
            db = (laa * rb - lab * ra) * inv_det;
            di[0] = da;
            di[1] = -0.5 * da + 0.5 * kSqrt3 * db;
            di[2] = -0.5 * da - 0.5 * kSqrt3 * db;
            return;
        }
        // One phase blocked, the conducting pair y, z (i_y = -i_z): the circuit gave di_y =
        // (u_y - u_z) / (2 L_c). Along n = T (e_y - e_z): n^T T^+-weighted L n = 1.5 n^T L_ab n, so
        // di_y = (u_y - u_z - 1.5 n^T omega dL i) / (1.5 n^T L_ab n).
        int yz[2], k = 0, xb = 0;
        for (int x = 0; x < 3; ++x) {
            if (cond[x] != 0.0) yz[k++] = x;
            else xb = x;
        }
        static const double na_t[3] = {1.0, -0.5, -0.5}, nb_t[3] = {0.0, 0.5 * kSqrt3, -0.5 * kSqrt3};
        const int y0 = yz[0], z0 = yz[1];
        const double na = (2.0 / 3.0) * (na_t[y0] - na_t[z0]), nb = (2.0 / 3.0) * (nb_t[y0] - nb_t[z0]);
        const double nln = na * (laa * na + lab * nb) + nb * (lab * na + lbb * nb);
        const double sdi = (2.0 * ld_ * di[y0] - 1.5 * (na * ma + nb * mb)) / (1.5 * nln);
        const double dic[3] = {di[0], di[1], di[2]};
        di[y0] = sdi;
        di[z0] = -sdi;
        di[xb] = 0.0;
        da = di[0];
        db = (di[1] - di[2]) * (1.0 / kSqrt3);
        // X = L_ab di + omega dL i per phase: the machine's part of each phase voltage beside e_pm.
        const double xa = laa * da + lab * db + ma, xbt = lab * da + lbb * db + mb;
        double xp[3];
        for (int x = 0; x < 3; ++x) xp[x] = na_t[x] * xa + nb_t[x] * xbt;
        // u_x - vn0_c = L_c di_c,x for a conducting phase: the salient neutral is u_x - X_x.
        vn0 += 0.5 * ((ld_ * dic[y0] - xp[y0]) + (ld_ * dic[z0] - xp[z0]));
        vx0[xb] = vn0 + e[xb] + xp[xb];
    }
    // Right-hand side, second half, from the phase currents ix: torque, derivatives of the
    // machine's own states (none) and its loss beyond R_s sum i^2 (none).
    void torque_and_states(const Vec &, const double ix[3], double, const Work &w, Vec &dy, double &te,
                           double &p_internal) const {
        te = 0.0;
        for (int x = 0; x < 3; ++x) te += ix[x] * w.dpsi[x];
        te *= pp_;
        if (salient_) te += reluctance_torque(ix[0], (ix[1] - ix[2]) * (1.0 / kSqrt3), w.c, w.s);
        dy[S_MACH0] = dy[S_MACH1] = 0.0;
        p_internal = 0.0;
    }

    // Phase back-EMF by the exact formula (conduction-mode selection).
    void emf_exact(const Vec &y, double e[3]) const {
        const double omega_e = pp_ * y[S_OMEGA];
        double dpsi[3];
        pm_flux(pp_ * y[S_THETA], dpsi, nullptr);
        for (int x = 0; x < 3; ++x) e[x] = omega_e * dpsi[x];
    }

    // Reported flux (Hoang eqs. 8-9), torque and magnetic energy at state y, exact to rounding
    // (rotation from the expansion centre).
    void report(const Vec &y, double i_alpha, double i_beta, MachineReport &r) const {
        double dpsi[3], psi[3];
        pm_flux_centre(pp_ * y[S_THETA], dpsi, psi);
        const double psi_pm_alpha = (2.0 * psi[0] - psi[1] - psi[2]) * (1.0 / 3.0);
        const double psi_pm_beta = (psi[1] - psi[2]) * (1.0 / kSqrt3);
        r.psi_alpha = ls_ * i_alpha + psi_pm_alpha;  // Hoang eq. (8)
        r.psi_beta = ls_ * i_beta + psi_pm_beta;     // Hoang eq. (9)
        r.psi_r_alpha = r.psi_r_beta = 0.0;
        double te = 0.0;
        for (int x = 0; x < 3; ++x) te += y[S_IA + x] * dpsi[x];
        r.te = pp_ * te;
        const double ia2 = i_alpha * i_alpha + i_beta * i_beta;
        r.e_magnetic = 0.75 * ls_ * ia2;  // (3/2) * (1/2) L_s |i|^2, amplitude-invariant frame
        if (salient_) {
            // psi_ab = L_ab(theta) i_ab + psi_pm; energy (3/2)(1/2)(L_d i_d^2 + L_q i_q^2)
            const double th = pp_ * y[S_THETA];
            const double c = std::cos(th), s = std::sin(th);
            const double c2 = c * c - s * s, s2 = 2.0 * s * c;
            r.psi_alpha = (sig0_ + sig2_ * c2) * i_alpha + sig2_ * s2 * i_beta + psi_pm_alpha;
            r.psi_beta = sig2_ * s2 * i_alpha + (sig0_ - sig2_ * c2) * i_beta + psi_pm_beta;
            r.te += reluctance_torque(i_alpha, i_beta, c, s);
            const double id = c * i_alpha + s * i_beta, iq = c * i_beta - s * i_alpha;
            r.e_magnetic = 0.75 * (ld_ * id * id + lq_ * iq * iq);
        }
    }

    // The reluctance torque 1.5 p (L_d - L_q) i_d i_q at theta_e (c, s = cos, sin), from i_ab.
    double reluctance_torque(double i_alpha, double i_beta, double c, double s) const {
        const double id = c * i_alpha + s * i_beta, iq = c * i_beta - s * i_alpha;
        return 1.5 * pp_ * (ld_ - lq_) * id * iq;
    }

private:
    // Taylor expansion of dpsi_pm,x/dtheta_e around th0 (the cache angle), order 7. For harmonic
    // n, d^k/dtheta^k [-A sin(n u)] = -A n^k sin(n u + k pi/2); divided by k!. Remainder: (n_max
    // |d|)^8 / 8! relative to the harmonic's amplitude, < 1.7e-9 within kTcRange (n_max |d| <
    // 0.3). begin_step() re-centres it when it could leave kTcRecentre (0.25), i.e. every few
    // periods.
    static constexpr double kTcRange = 0.3;
    static constexpr double kTcRecentre = 0.25;

    // sin/cos of theta using the value cached at the step start and a short Taylor rotation for
    // the small angle increment of an RK stage (|d| < 0.25 rad: truncation < 1e-16).
    void fast_sincos(double th, double &c, double &s) const {
        const double d = th - th0_;
        if (std::fabs(d) < 0.25) {
            const double d2 = d * d;
            const double cd = 1.0 - d2 * (0.5 - d2 * (1.0 / 24.0 - d2 * (1.0 / 720.0 - d2 * (1.0 / 40320.0 - d2 / 3628800.0))));
            const double sd = d * (1.0 - d2 * (1.0 / 6.0 - d2 * (1.0 / 120.0 - d2 * (1.0 / 5040.0 - d2 * (1.0 / 362880.0 - d2 / 39916800.0)))));
            c = c0_ * cd - s0_ * sd;
            s = s0_ * cd + c0_ * sd;
        } else {
            c = std::cos(th);
            s = std::sin(th);
        }
    }

    // dpsi_pm,x/dtheta_e for the three phases (and, if wanted, psi_pm,x itself).
    void pm_flux(double theta_e, double dpsi[3], double *psi) const {
        double c, s;
        fast_sincos(theta_e, c, s);
        // Rotate by -2pi/3 and -4pi/3.
        const double ch = -0.5, sh = kSqrt3 / 2.0;
        const double cb = c * ch + s * sh, sb = s * ch - c * sh;  // theta - 2pi/3
        const double cc = c * ch - s * sh, sc = s * ch + c * sh;  // theta - 4pi/3 (= + 2pi/3)
        const double cx[3] = {c, cb, cc}, sx[3] = {s, sb, sc};
        for (int x = 0; x < 3; ++x) {
            const double *a = emf_amp_[x];
            double dp = -a[0] * sx[x];
            double ps = flux_amp_[x][0] * cx[x];
            if (has_harm_) {
                // z^n by complex multiplication: z2, z3, z5 = z3 z2, z7 = z5 z2.
                const double c1 = cx[x], s1 = sx[x];
                const double c2 = c1 * c1 - s1 * s1, s2 = 2.0 * c1 * s1;
                const double c3 = c2 * c1 - s2 * s1, s3 = s2 * c1 + c2 * s1;
                const double c5 = c3 * c2 - s3 * s2, s5 = s3 * c2 + c3 * s2;
                const double c7 = c5 * c2 - s5 * s2, s7 = s5 * c2 + c5 * s2;
                dp -= a[1] * s3 + a[2] * s5 + a[3] * s7;
                ps += flux_amp_[x][1] * c3 + flux_amp_[x][2] * c5 + flux_amp_[x][3] * c7;
            }
            dpsi[x] = dp;
            if (psi) psi[x] = ps;
        }
    }

    void setup_emf_taylor() {
        const double c = c0_, s = s0_;
        const double ch = -0.5, sh = kSqrt3 / 2.0;
        const double cx[3] = {c, c * ch + s * sh, c * ch - s * sh};
        const double sx[3] = {s, s * ch - c * sh, s * ch + c * sh};
        for (int x = 0; x < 3; ++x) {
            const double *a = emf_amp_[x];
            double cn[4], sn[4];
            cn[0] = cx[x];
            sn[0] = sx[x];
            const int nh = has_harm_ ? 4 : 1;
            if (has_harm_) {
                const double c1 = cx[x], s1 = sx[x];
                const double c2 = c1 * c1 - s1 * s1, s2 = 2.0 * c1 * s1;
                cn[1] = c2 * c1 - s2 * s1; sn[1] = s2 * c1 + c2 * s1;
                cn[2] = cn[1] * c2 - sn[1] * s2; sn[2] = sn[1] * c2 + cn[1] * s2;
                cn[3] = cn[2] * c2 - sn[2] * s2; sn[3] = sn[2] * c2 + cn[2] * s2;
            }
            for (int h = 0; h < 4; ++h) {
                const bool on = h < nh;
                ph_fc_[x][h] = on ? flux_amp_[x][h] * cn[h] : 0.0;
                ph_fs_[x][h] = on ? flux_amp_[x][h] * sn[h] : 0.0;
                ph_ac_[x][h] = on ? a[h] * cn[h] : 0.0;
                ph_as_[x][h] = on ? a[h] * sn[h] : 0.0;
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
            for (int k = 0; k < 8; ++k) emf_tc_[k][x] = tc[k];
        }
        for (int k = 0; k < 8; ++k) emf_tc_[k][3] = 0.0;
        tc_range_ = kTcRange / (has_harm_ ? 7.0 : 1.0);
        tc_valid_ = true;
    }

    void dpsi_fast(double theta_e, double dpsi[3]) const {
        const double d = theta_e - th0_;
        if (tc_valid_ && std::fabs(d) < tc_range_) {
            const double d2 = d * d, d4 = d2 * d2;
            const Eigen::Array4d *t = emf_tc_;
            // Estrin's scheme: same polynomial, shorter dependency chain than Horner.
            const Eigen::Array4d r =
                ((t[0] + t[1] * d) + d2 * (t[2] + t[3] * d)) + d4 * ((t[4] + t[5] * d) + d2 * (t[6] + t[7] * d));
            dpsi[0] = r[0];
            dpsi[1] = r[1];
            dpsi[2] = r[2];
        } else {
            pm_flux(theta_e, dpsi, nullptr);
        }
    }

    // psi_pm,x and dpsi_pm,x/dtheta_e at theta_e, exact (to rounding): the centre phasors rotated
    // by n d, d = theta_e - th0, with cos/sin(n d) for n = 1, 3, 5, 7 from their Taylor series to
    // d^12 / d^13 (remainder < 0.3^14/14! = 6e-19 for n_max |d| < 0.3), evaluated in SIMD lanes.
    // Falls back to pm_flux() outside that range. Lower latency than pm_flux() (no chained
    // rotations); used by report() once per period.
    void pm_flux_centre(double theta_e, double dpsi[3], double psi[3]) const {
        const double d = theta_e - th0_;
        if (!(tc_valid_ && std::fabs(d) * (has_harm_ ? 7.0 : 1.0) < 0.3)) {
            pm_flux(theta_e, dpsi, psi);
            return;
        }
        const Eigen::Array4d x = Eigen::Array4d(1.0, 3.0, 5.0, 7.0) * d;
        const Eigen::Array4d x2 = x * x, x4 = x2 * x2, x8 = x4 * x4;
        const Eigen::Array4d cv = ((1.0 - x2 * 0.5) + x4 * (1.0 / 24.0 - x2 * (1.0 / 720.0))) +
                                  x8 * ((1.0 / 40320.0 - x2 * (1.0 / 3628800.0)) + x4 * (1.0 / 479001600.0));
        const Eigen::Array4d sv = x * (((1.0 - x2 * (1.0 / 6.0)) + x4 * (1.0 / 120.0 - x2 * (1.0 / 5040.0))) +
                                       x8 * ((1.0 / 362880.0 - x2 * (1.0 / 39916800.0)) + x4 * (1.0 / 6227020800.0)));
        for (int k = 0; k < 3; ++k) {
            psi[k] = (ph_fc_[k] * cv - ph_fs_[k] * sv).sum();
            dpsi[k] = -(ph_as_[k] * cv + ph_ac_[k] * sv).sum();
        }
    }

    int pole_pairs_ = 1;
    double pp_ = 1.0;        // pole pairs as a double
    double rs_ = 0.0, ls_ = 0.0;
    bool salient_ = false;                        // L_q != L_d
    double ld_ = 0.0, lq_ = 0.0, sig0_ = 0.0, sig2_ = 0.0;  // L_d, L_q, (L_d + L_q)/2, (L_d - L_q)/2
    bool has_harm_ = false;
    double flux_amp_[3][4] = {};  // psi_m * gain * (1, h3/3, h5/5, h7/7)
    double emf_amp_[3][4] = {};   // psi_m * gain * (1, h3, h5, h7): -dpsi/dtheta amplitudes
    // sin/cos cache at the expansion centre th0 (advanced by a short rotation from centre to
    // centre and re-synchronised with the library sin/cos every 256 re-centrings).
    double th0_ = 0.0, c0_ = 1.0, s0_ = 0.0;
    unsigned sync_count_ = 0;
    // Taylor coefficients (in delta = theta_e - th0) of dpsi_pm,x/dtheta_e: dpsi_x(th0 + d) =
    // sum_k emf_tc[k][x] d^k, k = 0..7; used while n_max |d| < kTcRange. Lane x = phase x (lane
    // 3 zero): the three polynomials run as SIMD packets.
    Eigen::Array4d emf_tc_[8];
    double tc_range_ = 0.0;
    // The PM flux at the expansion centre as phasors, lane h = harmonic (1, 3, 5, 7): per phase x
    // flux_amp * (cos, sin)(n (th0 - phi_x)) and emf_amp * (cos, sin)(...); report() rotates them
    // by n (theta - th0) (exact, see pm_flux_centre()).
    Eigen::Array4d ph_fc_[3], ph_fs_[3], ph_ac_[3], ph_as_[3];
    bool tc_valid_ = false;
};

}  // namespace plant_model

#endif  // DTC_MODEL_MACHINE_PM_H
