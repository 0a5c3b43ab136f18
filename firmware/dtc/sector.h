/*
 * sector.h - stator-flux sector without an arctangent (Hoang eq. 12 is never evaluated).
 *
 * SSTP: six sectors, sector k centred on the voltage vector V_k (Casadei Table 1 and Fig. 2):
 *   V_1 = (100) at 0 deg, V_2 = (110) 60, V_3 = (010) 120, V_4 = (011) 180, V_5 = (001) 240,
 *   V_6 = (101) 300 deg; sector k spans [(k-1)*60 - 30, (k-1)*60 + 30) deg (fix_sector6).
 * FSTP: four sectors (Hoang Table II, Fig. 3). Derivation from Tables I-II: V_1..V_4 point to
 *   0, 90, 180, 270 deg (Hoang Table I: V_1 = (V_dc/3, 0), V_2 = (0, V_dc/sqrt3), V_3 = (-V_dc/3, 0),
 *   V_4 = (0, -V_dc/sqrt3)). A vector at angle phi raises |psi| when cos(phi - theta) > 0 and
 *   raises the torque (turns psi counter-clockwise, theta increasing) when sin(phi - theta) > 0.
 *   In sector I Hoang Table II selects V_2 (90 deg) for (dpsi, dT) = (1, 1): needs theta in (0, 90);
 *   V_1 (0 deg) for (1, 0): cos(theta) > 0 and sin(-theta) < 0, theta in (0, 90); V_3 (180 deg)
 *   for (0, 1): theta in (0, 90); V_4 (270 deg) for (0, 0): theta in (0, 90). Every entry of the
 *   column holds exactly on (0, 90) deg, so sector I is the first quadrant, and by the 90-degree
 *   rotation of the columns sector II..IV are the next quadrants (fix_quadrant). The unit test
 *   test_dtc_sector repeats this derivation numerically from the two tables.
 *
 * Formats: flux components IQ pu; result 1..6 or 1..4. Cost: sign tests and (SSTP) two exact
 * 64-bit products; no overflow for any input.
 */
#ifndef SECTOR_H
#define SECTOR_H

#include <stdint.h>

#include "fixmath.h"

static inline uint16_t sector_sstp(iq_t psi_alpha_iq, iq_t psi_beta_iq)
{
    return fix_sector6(psi_alpha_iq, psi_beta_iq);
}

static inline uint16_t sector_fstp(iq_t psi_alpha_iq, iq_t psi_beta_iq)
{
    return fix_quadrant(psi_alpha_iq, psi_beta_iq);
}

#endif /* SECTOR_H */
