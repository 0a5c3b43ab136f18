/*
 * dtc_ref.h - double-precision references for the DTC firmware tests (host only).
 *
 * These are written straight from the papers (Hoang et al. 2011, Casadei et al. 2006), not from
 * the firmware: the paper's tables are typed in literally, the equations evaluated in double.
 */
#ifndef DTC_REF_H
#define DTC_REF_H

#define DTC_REF_PI 3.14159265358979323846

/* Hoang eqs. 4-5 from three phase values. */
void dtc_ref_clarke3(double a, double b, double c, double *alpha, double *beta);

/* Hoang Table I (FSTP): v_an, v_bn, v_cn, v_alpha, v_beta in units of V_dc for vector 1..4. */
void dtc_ref_table_i(int vec, double out[5]);

/* Hoang Table V, typed in: sign(i_b), sign(i_c) in {-1, +1}. */
void dtc_ref_table_v(int sgn_b, int sgn_c, double vf, double *va, double *vb);

/* Hoang Table VI, typed in row by row: S_B, S_C in {0, 1}, signs in {-1, +1}. */
void dtc_ref_table_vi(int sb, int sc, int sgn_b, int sgn_c, double vce, double vd, double *va,
                      double *vb);

/* FSTP inverter with device drops (Hoang Table III per leg, plus R_on*i of eq. 20): the
 * alpha-beta voltage applied to the machine for leg states S_B, S_C, DC link vdc with the
 * mid-point at vdc/2, phase currents i_b, i_c (positive out of the leg). All in pu. */
void dtc_ref_fstp_inverter(int sb, int sc, double vdc, double ib, double ic, double vce,
                           double vd, double ron, double *va, double *vb);

/* Surface PM machine (Hoang eqs. 6-10) in per-unit, alpha-beta frame, for closed-loop checks:
 * psi = ls i + psi_m e^{j theta}, d psi/dt = v - rs i, d theta/dt = w (constant speed). */
typedef struct {
    double rs, ls, psi_m, w;
    double psi_a, psi_b, theta;
} dtc_ref_pm_t;
void dtc_ref_pm_init(dtc_ref_pm_t *m, double rs, double ls, double psi_m, double w, double theta,
                     double ia, double ib);
void dtc_ref_pm_currents(const dtc_ref_pm_t *m, double *ia, double *ib);
double dtc_ref_pm_torque(const dtc_ref_pm_t *m);
/* Advance by dt (pu time) with constant (v_alpha, v_beta), n_sub RK4 sub-steps. */
void dtc_ref_pm_step(dtc_ref_pm_t *m, double va, double vb, double dt, int n_sub);

/* Squirrel-cage induction machine (Casadei eq. 9 and appendix, T model) in per-unit, stator
 * (alpha-beta) frame, at a constant electrical speed w:
 *   d psi_s/dt = v - rs i_s,   d psi_r/dt = -rr i_r + j w psi_r,
 *   i_s = (lr psi_s - m psi_r) / D,   i_r = (ls psi_r - m psi_s) / D,   D = ls lr - m^2,
 *   T = psi_s x i_s (Casadei eq. A10 in the bases of dtc_base.h). Demagnetised at init. */
typedef struct {
    double rs, rr, ls, lr, m, w;
    double psa, psb, pra, prb; /* stator and rotor flux */
} dtc_ref_im_t;
void dtc_ref_im_init(dtc_ref_im_t *x, double rs, double rr, double ls, double lr, double m, double w);
void dtc_ref_im_currents(const dtc_ref_im_t *x, double *ia, double *ib);
double dtc_ref_im_torque(const dtc_ref_im_t *x);
/* Advance by dt (pu time) with constant (v_alpha, v_beta), n_sub RK4 sub-steps. */
void dtc_ref_im_step(dtc_ref_im_t *x, double va, double vb, double dt, int n_sub);
/* Ideal six-switch inverter: the alpha-beta voltage of leg states sa, sb, sc on link vdc (Casadei
 * eq. 2 with the amplitude-invariant Clarke transform). */
void dtc_ref_sstp_ideal(int sa, int sb, int sc, double vdc, double *va, double *vb);

#endif /* DTC_REF_H */
