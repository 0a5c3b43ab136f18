/*
 * dtc_base.h - the per-unit system of the DTC firmware, defined in this one place.
 *
 * Every quantity inside firmware/ is per-unit (pu) against the bases below, held in the IQ
 * format of fixmath.h (iq_t, Q24, range +-128 pu) unless its name says otherwise. SI values exist
 * only on the host (tools/config converts them; model/, hal/host/ and the tests use them).
 *
 * Independent bases (chosen by the host converter, tools/config/dtc_config_si.h; the defaults in
 * brackets are those of Hoang et al. 2011 Table VIII and its 70 V DC link):
 *   V_base   voltage        [V]      = nominal DC-link voltage            [70 V]
 *   I_base   current        [A]      = rated peak phase current           [2.2 A]
 *   w_base   el. speed      [rad/s]  = rated electrical speed, p*w_mech   [2*pi*50 = 314.16 rad/s]
 * Derived bases (no other choice is consistent with the machine equations):
 *   psi_base flux linkage   [Wb]     = V_base / w_base                    [0.22282 Wb]
 *   Z_base   impedance      [Ohm]    = V_base / I_base                    [31.82 Ohm]
 *   L_base   inductance     [H]      = Z_base / w_base                    [0.10128 H]
 *   T_base   torque         [N.m]    = (3/2) * p * psi_base * I_base      [0.73530 N.m]
 *   t_base   time           [s]      = 1 / w_base                         [3.1831 ms]
 *
 * Space vectors use the amplitude-invariant Clarke transform (Hoang eqs. 4-5: x_alpha =
 * (2x_a - x_b - x_c)/3, x_beta = (x_b - x_c)/sqrt(3)), so a balanced set of peak amplitude X has a
 * space vector of length X, and with T_base as above Hoang eq. 10 becomes simply
 *   T_e[pu] = psi_alpha[pu] * i_beta[pu] - psi_beta[pu] * i_alpha[pu].
 * The machine equations keep their form in pu time (t_pu = t * w_base):
 *   d psi/dt_pu = v - r_s * i            (Hoang eqs. 6-7, 15-16)
 *   psi = l_s * i + psi_m * e^{j theta_e} (Hoang eqs. 8-9)
 * so the per-sample integration gain is Ts_pu = Ts * w_base (0.0157 at 50 us) and the speed in pu
 * is the electrical speed over w_base (mechanical speed in pu is the same number).
 *
 * Angles are angle_t (65536 = one electrical turn). Encoder counts stay raw counts
 * (0 .. 4*lines - 1) and are converted with gains the host precomputes, so that no division is
 * ever needed in firmware.
 *
 * Default figures (Hoang Table VIII machine): r_s = 0.466/31.82 = 0.01465 pu,
 * l_s = 3.19e-3/0.10128 = 0.03150 pu, psi_m = 0.0928/0.22282 = 0.41648 pu, rated torque
 * 0.3 N.m = 0.408 pu, a voltage vector of the SSTP has length 2/3 pu (Casadei eq. 2), those of the
 * FSTP 1/3 pu and 1/sqrt(3) pu (Hoang Table I).
 */
#ifndef DTC_BASE_H
#define DTC_BASE_H

#include "fixmath.h"

/* Number of control periods per speed-loop period (Hoang section IV: speed loop 10x slower). The
 * configuration carries the actual value; this is the paper's. */
#define DTC_SPEED_DIV_DEFAULT 10U

#endif /* DTC_BASE_H */
