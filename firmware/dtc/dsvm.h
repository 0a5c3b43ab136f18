/*
 * dsvm.h - Discrete Space Vector Modulation for the induction-machine DTC (Casadei et al. 2006
 * section 11, Figs. 26-28; the selection criteria of section 8, eqs. 13-15). The derivation of
 * the tables is written out in docs/firmware-core.md ("DSVM"); tests/unit/test_dsvm.c recomputes
 * every entry from it in double precision.
 *
 * Vectors. The control period is split into three equal sub-intervals, each applying one basic
 * inverter vector V_0..V_7 (swtab.h numbering, V_k at (k-1) 60 deg, |V_k| = 2/3 V_dc, Casadei
 * eq. 2). The mean over the period is one of the 19 vectors of Fig. 26 as read here: the null
 * (label "000") and the outer ring (a V_k + b V_k+1)/3 with a + b = 3 (labels "333", "332",
 * "322", "222", ... as in the text's high-speed example), coded
 *     0                      the null (V_0 or V_7 in all three sub-intervals, swtab_null_choice)
 *     1 + 3 (k - 1) + j      k = 1..6, j = 0: V_k V_k V_k       (|v| = |V_k|, at (k-1) 60 deg)
 *                                      j = 1: V_k V_k V_k+1     (|v| = sqrt7/3 |V_k|, +19.1 deg)
 *                                      j = 2: V_k+1 V_k+1 V_k   (|v| = sqrt7/3 |V_k|, +40.9 deg)
 *   in sub-interval order (the majority vector first, as the labels), so codes 1..18 run round
 *   the ring counter-clockwise.
 * Tables. dsvm_table() holds the seven switching tables for a flux in sector 1 (about V_1,
 * sector.h): the dynamic EMF e = w phi_s* (rotor speed w, Casadei eq. 15's w_k, times the
 * stator-flux reference), in units of |V_k| = 2/3 V_dc, selects
 *     DSVM_LOW         |e| <  E1                       (one table, either sense of rotation)
 *     DSVM_MED_CCW/CW  E1 <= |e| < E2, e > 0 / e < 0
 *     DSVM_HIGH_*      E2 <= |e|, e > 0 / e < 0, each with the half sector 1- (flux behind V_k,
 *                      [-30, 0) deg) and 1+ ([0, 30) deg): twelve sectors at high speed (Fig. 28)
 *   with E1 = 0.2, E2 = 0.5 (the design ranges of the derivation; E3 = sqrt3/2, the largest EMF the
 *   hexagon sustains in steady state, bounds the high range), the flux comparator (up / down) and
 *   the five-level torque comparator (hyst5_step, hyst.h: +2, +1, 0, -1, -2). Other sectors: the
 *   entry rotated by (sector - 1) 60 deg (dsvm_rotate: code + 3 (sector - 1), modulo the ring).
 * PWM form (hal.h HAL_CMD_PWM): a leg's three sub-interval states s1 s2 s3 (pattern bit 2 = s1)
 *   are one active interval containing the period's middle: act = HIGH with the upper device's
 *   on-set when s2 = 1 or the leg stays low, else act = LOW with the lower device's on-set
 *   (100, 001, 101). The set's start is t = 0 (cmpr_up = 0) or Ts/3 (cmpr_up = 2/3 T1PR), its end
 *   2 Ts/3 (cmpr_dn = 2/3 T1PR) or Ts (cmpr_dn = 0); an empty set is T1PR + 1 on both halves.
 *   2/3 T1PR is rounded to the nearest count exactly: floor((2 T1PR + 1) / 3) by the
 *   multiply-shift (2 T1PR + 1) * 0xAAAAAAAB >> 33 (exact for every 32-bit numerator; no division).
 *
 * Formats: speed, flux, v_dc IQ pu; flux components IQ pu; results small integers.
 * Scaling and overflow: dsvm_range forms w phi_s* as a rounded IQ product (saturating) and the
 * thresholds E * 2/3 v_dc as rounded IQ products; dsvm_half forms a cross product of Q30
 * constants and IQ flux in 64 bits (< 2^62). Table look-ups otherwise.
 */
#ifndef DSVM_H
#define DSVM_H

#include <stdint.h>

#include "fixmath.h"

#define DSVM_NVEC 19U   /* the null and the 18 outer-ring vectors */

enum dsvm_range {
    DSVM_LOW = 0,
    DSVM_MED_CCW = 1,
    DSVM_MED_CW = 2,
    DSVM_HIGH_CCW_M = 3, /* e > 0, half sector 1- */
    DSVM_HIGH_CCW_P = 4, /* e > 0, half sector 1+ */
    DSVM_HIGH_CW_M = 5,  /* e < 0, half sector 1- */
    DSVM_HIGH_CW_P = 6,  /* e < 0, half sector 1+ */
    DSVM_NRANGE = 7
};

/* The speed-range boundaries of the derivation, in |V_k| = 2/3 V_dc, and times 2/3 (so that the
 * firmware compares w phi_s* with E * 2/3 * v_dc). */
#define DSVM_E1 0.2
#define DSVM_E2 0.5
#define DSVM_E1_23_IQ IQ(0.2 * 2.0 / 3.0)
#define DSVM_E2_23_IQ IQ(0.5 * 2.0 / 3.0)

/* Entry of the switching tables for a flux in sector 1: range enum dsvm_range, flux_up 1/0,
 * level -2..+2. Returns the code 0..18 (out-of-range arguments: the null). */
uint16_t dsvm_table(uint16_t range, uint16_t flux_up, int16_t level);

/* Code of sector 1 turned to sector 1..6. */
static inline uint16_t dsvm_rotate(uint16_t code, uint16_t sector)
{
    uint16_t r;
    if (code == 0U || sector < 1U || sector > 6U) {
        return code;
    }
    r = (uint16_t)(code - 1U + 3U * (sector - 1U));
    if (r >= 18U) {
        r = (uint16_t)(r - 18U);
    }
    return (uint16_t)(r + 1U);
}

/* The three basic vectors (swtab.h numbers) of code 1..18 in sub-interval order; code 0 gives
 * null_vec (0 or 7) three times. */
void dsvm_vectors(uint16_t code, uint16_t null_vec, uint16_t v[3]);

/* 1 when the flux lies in the half sector 1+ of its sector (at or counter-clockwise of V_k):
 * the sign of V_k x phi (Q30 cos/sin of (k - 1) 60 deg). */
uint16_t dsvm_half(uint16_t sector, iq_t psi_alpha_iq, iq_t psi_beta_iq);

/* The table in force (enum dsvm_range) from w (pu), the stator-flux reference (pu), v_dc (pu)
 * and the half sector (dsvm_half). */
uint16_t dsvm_range(iq_t speed_iq, iq_t psi_ref_iq, iq_t vdc_iq, uint16_t half_plus);

/* Leg patterns (bit 2 = first sub-interval, 1 = upper device on) of three basic vectors. */
void dsvm_patterns(const uint16_t v[3], uint16_t pat[3]);

/* round(2 T1PR / 3) (file comment). */
static inline uint16_t dsvm_c23(uint16_t t1pr)
{
    const uint64_t n = 2U * (uint64_t)t1pr + 1U;
    return (uint16_t)((n * 0xAAAAAAABULL) >> 33);
}

/* The PWM form of a leg pattern (file comment): compare values and polarity (enum hal_pwm_act
 * values 0 = upper active high, 1 = upper active low). c23 = dsvm_c23(t1pr). */
static inline void dsvm_pwm(uint16_t pat, uint16_t t1pr, uint16_t c23, uint16_t *cmpr_up,
                            uint16_t *cmpr_dn, uint16_t *act)
{
    uint16_t set = (uint16_t)(pat & 7U);
    const uint16_t never = (uint16_t)(t1pr + 1U);
    *act = 0U;
    if ((set & 2U) == 0U && set != 0U) {
        set = (uint16_t)(~set & 7U); /* 100, 001, 101: the lower device's on-set, 011, 110, 010 */
        *act = 1U;
    }
    *cmpr_up = (set & 4U) != 0U ? 0U : ((set & 2U) != 0U ? c23 : never);
    *cmpr_dn = (set & 1U) != 0U ? 0U : ((set & 2U) != 0U ? c23 : never);
}

#endif /* DSVM_H */
