// machine_im.h - squirrel-cage induction machine for the plant (SI units, stationary frame).
//
// Casadei et al. 2006, appendix (Casadei eqs. A1-A10): space vectors by the amplitude-invariant
// transform (A1)-(A5), and with T-model parameters R_s, R_r, L_ls, L_lr, L_m (= Casadei's M), p:
//   (A6) v_s = R_s i_s + dpsi_s/dt,  (A7) 0 = R_r i_r + dpsi_r/dt - j omega_e psi_r,
//   (A8) psi_s = L_s i_s + L_m i_r,  (A9) psi_r = L_r i_r + L_m i_s,
//   L_s = L_ls + L_m, L_r = L_lr + L_m, sigma = 1 - L_m^2/(L_s L_r), tau_r = L_r/R_r,
//   (A10) T_e = 1.5 p i_s . j psi_s = 1.5 p Im(conj(psi_s) i_s).
// psi_r is the T-model rotor flux L_r i_r + L_m i_s (Casadei's phi_r; not the Gamma or inverse-Gamma
// rotor flux, see /work/shared/reference/im-facts.md). omega_e = p omega_m is electrical.
//
// States: stator current i_s (the plant's phase currents) and rotor flux psi_r. Eliminating i_r:
//   sigma L_s di_s/dt = v_s - R_eff i_s - e_s,   R_eff = R_s + R_r k_r^2,  k_r = L_m/L_r,
//   e_s = k_r (-psi_r/tau_r + j omega_e psi_r),
//   dpsi_r/dt = (L_m/tau_r) i_s - psi_r/tau_r + j omega_e psi_r,
// so for the plant's per-phase circuit the IM is an inductance sigma L_s, a resistance R_eff and
// a back-EMF e_s (taken to phase x by the inverse amplitude-invariant Clarke transform), plus two
// rotor-flux states. psi_s = sigma L_s i_s + k_r psi_r, and T_e = 1.5 p Im(conj(psi_s) i_s) =
// 1.5 p k_r (psi_r,alpha i_beta - psi_r,beta i_alpha). ImMachine puts this behind the seam of
// machine.h, the rotor flux in the machine's state slots S_MACH0 / S_MACH1.
#ifndef DTC_MODEL_MACHINE_IM_H
#define DTC_MODEL_MACHINE_IM_H

#include <cmath>

#include "plant.h"
#include "plant_state.h"

namespace im {

struct Const {
    double ls, lr, sigma, tau_r, inv_tau_r, kr;  // L_s, L_r, sigma, tau_r, 1/tau_r, L_m/L_r
    double lm, rr;
    double l_eff;                                // sigma L_s
    double r_eff;                                // R_s + R_r k_r^2
    double lm_inv_tau_r;                         // L_m / tau_r
    double kr_inv_tau_r;                         // k_r / tau_r
    double inv_lr;                               // 1 / L_r
};

inline Const derive(const plant_params_t &p) {
    Const c;
    c.lm = p.lm_h;
    c.rr = p.rr_ohm;
    c.ls = p.lls_h + p.lm_h;
    c.lr = p.llr_h + p.lm_h;
    c.sigma = 1.0 - p.lm_h * p.lm_h / (c.ls * c.lr);
    c.tau_r = c.lr / p.rr_ohm;
    c.inv_tau_r = p.rr_ohm / c.lr;
    c.kr = p.lm_h / c.lr;
    c.l_eff = c.sigma * c.ls;
    c.r_eff = p.rs_ohm + p.rr_ohm * c.kr * c.kr;
    c.lm_inv_tau_r = p.lm_h * c.inv_tau_r;
    c.kr_inv_tau_r = c.kr * c.inv_tau_r;
    c.inv_lr = 1.0 / c.lr;
    return c;
}

using plant_model::kSqrt3;

// Back-EMF e_s as phase values (inverse amplitude-invariant Clarke).
inline void emf_phases(const Const &c, double pra, double prb, double omega_e, double e[3]) {
    const double ea = -c.kr_inv_tau_r * pra - c.kr * omega_e * prb;
    const double eb = -c.kr_inv_tau_r * prb + c.kr * omega_e * pra;
    e[0] = ea;
    e[1] = -0.5 * ea + 0.5 * kSqrt3 * eb;
    e[2] = -0.5 * ea - 0.5 * kSqrt3 * eb;
}

// Rotor-flux derivative, torque (Casadei eq. A10), rotor copper loss 1.5 R_r |i_r|^2 for stator current
// (ia, ib in alpha/beta) and rotor flux (pra, prb).
inline void rotor(const Const &c, int pole_pairs, double i_al, double i_be, double pra, double prb,
                  double omega_e, double &dpra, double &dprb, double &te, double &p_rotor_cu) {
    dpra = c.lm_inv_tau_r * i_al - c.inv_tau_r * pra - omega_e * prb;
    dprb = c.lm_inv_tau_r * i_be - c.inv_tau_r * prb + omega_e * pra;
    te = 1.5 * pole_pairs * c.kr * (pra * i_be - prb * i_al);
    const double ira = (pra - c.lm * i_al) * c.inv_lr, irb = (prb - c.lm * i_be) * c.inv_lr;  // Casadei eq. A9
    p_rotor_cu = 1.5 * c.rr * (ira * ira + irb * irb);
}

// Stored magnetic energy 1.5 * 0.5 (psi_s . i_s + psi_r . i_r), amplitude-invariant frame.
inline double magnetic_energy(const Const &c, double i_al, double i_be, double pra, double prb) {
    const double psa = c.l_eff * i_al + c.kr * pra, psb = c.l_eff * i_be + c.kr * prb;
    const double ira = (pra - c.lm * i_al) / c.lr, irb = (prb - c.lm * i_be) / c.lr;
    return 0.75 * (psa * i_al + psb * i_be + pra * ira + prb * irb);
}

}  // namespace im

namespace plant_model {

class ImMachine {
public:
    static constexpr plant_machine_t kKind = PLANT_MACHINE_IM;
    // Parameters only this machine reads (nullptr: valid).
    static const char *check(const plant_params_t &p) {
        auto bad = [](double v) { return !std::isfinite(v); };
        if (bad(p.rr_ohm) || p.rr_ohm <= 0.0) return "rr_ohm must be finite and > 0";
        if (bad(p.lm_h) || p.lm_h <= 0.0) return "lm_h must be finite and > 0";
        if (bad(p.lls_h) || p.lls_h < 0.0) return "lls_h must be finite and >= 0";
        if (bad(p.llr_h) || p.llr_h < 0.0) return "llr_h must be finite and >= 0";
        if (p.lls_h + p.llr_h <= 0.0) return "lls_h + llr_h must be > 0 (sigma L_s is the stator's inductance)";
        return nullptr;
    }

    ImMachine() = default;
    // noexcept: std::variant::emplace then builds the machine in place (without it libstdc++ builds a
    // temporary variant and move-assigns it, which GCC 12 with the sanitizers reports as a
    // maybe-uninitialized read of the inactive alternative)
    explicit ImMachine(const plant_params_t &p) noexcept
        : c_(im::derive(p)), pole_pairs_(p.pole_pairs), pp_(p.pole_pairs), rs_(p.rs_ohm) {}

    // The machine in the per-phase circuit: sigma L_s di_x/dt = v_x - v_n - R_eff i_x - e_x.
    double circuit_inductance() const { return c_.l_eff; }
    double circuit_resistance() const { return c_.r_eff; }
    double stator_resistance() const { return rs_; }  // stator copper loss R_s sum i_x^2

    void begin_step(double, double, double) {}

    struct Work {};
    void emf(const Vec &y, double omega_e, double e[3], Work &) const {
        im::emf_phases(c_, y[S_MACH0], y[S_MACH1], omega_e, e);
    }
    // Torque (Casadei eq. A10), rotor-flux derivatives and the rotor copper loss from the phase currents.
    void torque_and_states(const Vec &y, const double ix[3], double omega_e, const Work &, Vec &dy, double &te,
                           double &p_internal) const {
        const double i_al = (2.0 * ix[0] - ix[1] - ix[2]) * (1.0 / 3.0);
        const double i_be = (ix[1] - ix[2]) * (1.0 / kSqrt3);
        im::rotor(c_, pole_pairs_, i_al, i_be, y[S_MACH0], y[S_MACH1], omega_e, dy[S_MACH0], dy[S_MACH1], te,
                  p_internal);
    }

    void emf_exact(const Vec &y, double e[3]) const {
        im::emf_phases(c_, y[S_MACH0], y[S_MACH1], pp_ * y[S_OMEGA], e);
    }

    void report(const Vec &y, double i_alpha, double i_beta, MachineReport &r) const {
        // psi_s = sigma L_s i_s + (L_m/L_r) psi_r (Casadei A8-A9 with i_r eliminated).
        r.psi_r_alpha = y[S_MACH0];
        r.psi_r_beta = y[S_MACH1];
        r.psi_alpha = c_.l_eff * i_alpha + c_.kr * y[S_MACH0];
        r.psi_beta = c_.l_eff * i_beta + c_.kr * y[S_MACH1];
        // Casadei eq. (A10): T_e = 1.5 p Im(conj(psi_s) i_s).
        r.te = 1.5 * pp_ * (r.psi_alpha * i_beta - r.psi_beta * i_alpha);
        r.e_magnetic = im::magnetic_energy(c_, i_alpha, i_beta, y[S_MACH0], y[S_MACH1]);
    }

private:
    im::Const c_{};
    int pole_pairs_ = 1;
    double pp_ = 1.0;
    double rs_ = 0.0;
};

}  // namespace plant_model

#endif  // DTC_MODEL_MACHINE_IM_H
