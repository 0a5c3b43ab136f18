/*
 * torque.h - electromagnetic torque (Hoang eq. 10) and stator-flux magnitude (Hoang eq. 11).
 *
 * With the bases of dtc_base.h (T_base = 3/2 p psi_base I_base) Hoang eq. 10 reads
 *     T_e = psi_alpha i_beta - psi_beta i_alpha        [pu]
 * and eq. 11 |psi_s| = sqrt(psi_alpha^2 + psi_beta^2) [pu].
 *
 * Formats: IQ pu in and out.
 * Scaling and overflow: torque: both products are exact Q48 values in 64 bits (each < 2^62), their
 * difference < 2^63; one rounding (<= 0.5 LSB) and saturation to +-128 pu. Magnitude: iq_mag
 * (fixmath), sum of squares exact in 64 bits, floor root, error <= 1 LSB, saturates at 128 pu.
 */
#ifndef TORQUE_H
#define TORQUE_H

#include "fixmath.h"

/* Hoang eq. 10 in pu. */
static inline iq_t torque_eq10(iq_t psi_alpha_iq, iq_t psi_beta_iq, iq_t i_alpha_iq,
                               iq_t i_beta_iq)
{
    int64_t acc = (int64_t)psi_alpha_iq * (int64_t)i_beta_iq -
                  (int64_t)psi_beta_iq * (int64_t)i_alpha_iq;
    return fix_rshift_rnd64_sat32(acc, (uint16_t)FIX_IQ_Q);
}

/* Hoang eq. 11 in pu. */
static inline iq_t torque_flux_mag(iq_t psi_alpha_iq, iq_t psi_beta_iq)
{
    return iq_mag(psi_alpha_iq, psi_beta_iq);
}

#endif /* TORQUE_H */
