// machine_im.h - squirrel-cage induction machine for the plant (SI units, stationary frame).
//
// Casadei et al. 2006, appendix: space vectors by the amplitude-invariant transform (A1)-(A5), and
// with T-model parameters R_s, R_r, L_ls, L_lr, L_m (= Casadei's M), p:
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
// 1.5 p k_r (psi_r,alpha i_beta - psi_r,beta i_alpha).
#ifndef DTC_MODEL_MACHINE_IM_H
#define DTC_MODEL_MACHINE_IM_H

#include "plant.h"

namespace im {

struct Const {
    double ls, lr, sigma, tau_r, inv_tau_r, kr;  // L_s, L_r, sigma, tau_r, 1/tau_r, L_m/L_r
    double lm, rr;
    double l_eff;                                // sigma L_s
    double r_eff;                                // R_s + R_r k_r^2
    double lm_inv_tau_r;                         // L_m / tau_r
    double kr_inv_tau_r;                         // k_r / tau_r
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
    return c;
}

constexpr double kSqrt3 = 1.73205080756887729353;

// Back-EMF e_s as phase values (inverse amplitude-invariant Clarke).
inline void emf_phases(const Const &c, double pra, double prb, double omega_e, double e[3]) {
    const double ea = -c.kr_inv_tau_r * pra - c.kr * omega_e * prb;
    const double eb = -c.kr_inv_tau_r * prb + c.kr * omega_e * pra;
    e[0] = ea;
    e[1] = -0.5 * ea + 0.5 * kSqrt3 * eb;
    e[2] = -0.5 * ea - 0.5 * kSqrt3 * eb;
}

// Rotor-flux derivative, torque (A10) and rotor copper loss 1.5 R_r |i_r|^2 for stator current
// (ia, ib in alpha/beta) and rotor flux (pra, prb).
inline void rotor(const Const &c, int pole_pairs, double i_al, double i_be, double pra, double prb,
                  double omega_e, double &dpra, double &dprb, double &te, double &p_rotor_cu) {
    dpra = c.lm_inv_tau_r * i_al - c.inv_tau_r * pra - omega_e * prb;
    dprb = c.lm_inv_tau_r * i_be - c.inv_tau_r * prb + omega_e * pra;
    te = 1.5 * pole_pairs * c.kr * (pra * i_be - prb * i_al);
    const double ira = (pra - c.lm * i_al) / c.lr, irb = (prb - c.lm * i_be) / c.lr;  // (A9)
    p_rotor_cu = 1.5 * c.rr * (ira * ira + irb * irb);
}

// Stored magnetic energy 1.5 * 0.5 (psi_s . i_s + psi_r . i_r), amplitude-invariant frame.
inline double magnetic_energy(const Const &c, double i_al, double i_be, double pra, double prb) {
    const double psa = c.l_eff * i_al + c.kr * pra, psb = c.l_eff * i_be + c.kr * prb;
    const double ira = (pra - c.lm * i_al) / c.lr, irb = (prb - c.lm * i_be) / c.lr;
    return 0.75 * (psa * i_al + psb * i_be + pra * ira + prb * irb);
}

}  // namespace im

#endif  // DTC_MODEL_MACHINE_IM_H
