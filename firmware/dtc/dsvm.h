/*
 * dsvm.h - Discrete Space Vector Modulation for the induction-machine DTC (Casadei et al. 2006
 * section 11, Figs. 26-28; the selection criteria of section 8, Casadei eqs. 13-15). The derivation of
 * the tables is written out in docs/firmware-core.md ("DSVM"); tests/unit/test_dsvm.c recomputes
 * every entry from it in double precision.
 *
 * Vectors. The control period is split into three equal sub-intervals, each applying one basic
 * inverter vector V_0..V_7 (swtab.h numbering, V_k at (k-1) 60 deg, |V_k| = 2/3 V_dc, Casadei
 * eq. 2). The mean over the period is (a V_k + b V_k+1)/3 with a + b <= 3 (the rest of the
 * period null): the 37 points of the hexagonal lattice of step |V_k|/3, the union of the text's
 * outer ring (labels "333", "332", "223", "222" of the high-speed example, Casadei Fig. 28) and the
 * shorter vectors with null sub-intervals that the low speed range needs (docs/firmware-core.md,
 * "DSVM", on the paper's count of 19). Coded
 *     0                   the null (V_0 or V_7 in all three sub-intervals, swtab_null_choice)
 *     1 + 6 (k - 1) + i   k = 1..6, i = 0..5 for (a, b) = (1,0) (1,1) (1,2) (2,0) (2,1) (3,0)
 *   Sub-interval order (dsvm_vectors): the null sub-intervals first, then the active vector one
 *   commutation away from that null (the odd V_1, V_3, V_5 after V_0, the even after V_7), then
 *   the other; without a null, the majority vector first ("332" = V_3 V_3 V_2).
 * Tables. dsvm_table() holds the seven switching tables for a flux in sector 1 (about V_1,
 * sector.h): the dynamic EMF e = w phi_s* (rotor speed w, Casadei eq. 15's w_k, times the
 * stator-flux reference), in units of |V_k| = 2/3 V_dc, selects
 *     DSVM_LOW         |e| <  E1                       (one table, either sense of rotation)
 *     DSVM_MED_CCW/CW  E1 <= |e| < E2, e > 0 / e < 0
 *     DSVM_HIGH_*      E2 <= |e|, e > 0 / e < 0, each with the half sector 1- (flux behind V_k,
 *                      [-30, 0) deg) and 1+ ([0, 30) deg): twelve sectors at high speed (Casadei Fig. 28)
 *   with E1 = 0.2, E2 = 0.5 (the design ranges of the derivation; E3 = sqrt3/2, the largest EMF the
 *   hexagon sustains in steady state, bounds the high range), the flux comparator (up / down) and
 *   the five-level torque comparator (hyst5_step, hyst.h: +2, +1, 0, -1, -2). Other sectors: the
 *   entry rotated by (sector - 1) 60 deg (dsvm_rotate: code + 6 (sector - 1), modulo 36).
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
 * threshold E1 * 2/3 v_dc as a rounded IQ product, E2's as 2.5 times it by shifts and adds; dsvm_half forms a cross product of Q30
 * constants and IQ flux in 64 bits (< 2^62). Table look-ups otherwise.
 */
#ifndef DSVM_H
#define DSVM_H

#include <stdint.h>

#include "fixmath.h"

#define DSVM_NCODE 37U  /* the null and the 36 lattice vectors */

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

/* The speed-range boundaries of the derivation, in |V_k| = 2/3 V_dc, and E1 times 2/3 (so that the
 * firmware compares w phi_s* with E * 2/3 * v_dc). */
#define DSVM_E1 0.2
#define DSVM_E2 0.5
#define DSVM_E1_23_IQ IQ(0.2 * 2.0 / 3.0)

/* Entry of the switching tables for a flux in sector 1: range enum dsvm_range, flux_up 1/0,
 * level -2..+2. Returns the code 0..36 (out-of-range arguments: the null). */
extern const uint16_t dsvm_tab[DSVM_NRANGE][2][5];
static inline uint16_t dsvm_table(uint16_t range, uint16_t flux_up, int16_t level)
{
    if (range >= (uint16_t)DSVM_NRANGE || level < -2 || level > 2) {
        return 0U;
    }
    return dsvm_tab[range][flux_up != 0U ? 1U : 0U][(uint16_t)(level + 2)];
}

/* Code of sector 1 turned to sector 1..6. */
static inline uint16_t dsvm_rotate(uint16_t code, uint16_t sector)
{
    uint16_t r;
    if (code == 0U || sector < 1U || sector > 6U) {
        return code;
    }
    r = (uint16_t)(code - 1U + 6U * (sector - 1U));
    if (r >= 36U) {
        r = (uint16_t)(r - 36U);
    }
    return (uint16_t)(r + 1U);
}

/* The three basic vectors (swtab.h numbers) of code 0..36 in sub-interval order (file comment);
 * null_vec (0 or 7) for the null sub-intervals. */
void dsvm_vectors(uint16_t code, uint16_t null_vec, uint16_t v[3]);

/* 1 when the flux lies in the half sector 1+ of its sector (at or counter-clockwise of V_k):
 * the sign of V_k x phi (Q30 cos/sin of (k - 1) 60 deg). */
extern const int32_t dsvm_cs_q30[6][2];
static inline uint16_t dsvm_half(uint16_t sector, iq_t psi_alpha_iq, iq_t psi_beta_iq)
{
    const uint16_t i = (uint16_t)((sector >= 1U && sector <= 6U) ? sector - 1U : 0U);
    const int64_t cross = (int64_t)dsvm_cs_q30[i][0] * (int64_t)psi_beta_iq -
                          (int64_t)dsvm_cs_q30[i][1] * (int64_t)psi_alpha_iq;
    return (uint16_t)(cross >= 0 ? 1U : 0U);
}

/* The table in force (enum dsvm_range) from w (pu), the stator-flux reference (pu), v_dc (pu)
 * and the half sector (dsvm_half). */
static inline uint16_t dsvm_range(iq_t speed_iq, iq_t psi_ref_iq, iq_t vdc_iq, uint16_t half_plus)
{
    const iq_t e = iq_mpy(speed_iq, psi_ref_iq);
    const iq_t ea = fix_abs32(e);
    const iq_t t1 = iq_mpy(DSVM_E1_23_IQ, vdc_iq);
    if (ea < t1) {
        return (uint16_t)DSVM_LOW;
    }
    /* E2 = 2.5 E1: t1 (2 + 1/2), t1 <= 2/15 * 128 pu (no overflow) */
    if (ea < t1 + t1 + fix_rshift_rnd32(t1, 1U)) {
        return (uint16_t)(e > 0 ? DSVM_MED_CCW : DSVM_MED_CW);
    }
    if (e > 0) {
        return (uint16_t)(half_plus != 0U ? DSVM_HIGH_CCW_P : DSVM_HIGH_CCW_M);
    }
    return (uint16_t)(half_plus != 0U ? DSVM_HIGH_CW_P : DSVM_HIGH_CW_M);
}

/* Leg patterns (bit 2 = first sub-interval, 1 = upper device on) of three basic vectors. */
void dsvm_patterns(const uint16_t v[3], uint16_t pat[3]);

extern const uint16_t dsvm_pat_tab[2][DSVM_NCODE];
extern const uint16_t dsvm_edge_tab[16];

/* The leg patterns of code 0..36 with the null null_vec (0 or 7): dsvm_vectors then
 * dsvm_patterns, by look-up (dsvm.c). */
static inline void dsvm_code_patterns(uint16_t code, uint16_t null_vec, uint16_t pat[3])
{
    const uint16_t p = dsvm_pat_tab[null_vec == 7U ? 1U : 0U][code < DSVM_NCODE ? code : 0U];
    pat[0] = (uint16_t)((p >> 6) & 7U);
    pat[1] = (uint16_t)((p >> 3) & 7U);
    pat[2] = (uint16_t)(p & 7U);
}

/* A leg's "on" thirds n (bits 0-1), rising edges (bits 2-3) and falling edges (bits 4-5) over its
 * previous state prev and pattern pat (the period's start counts), by look-up. */
static inline uint16_t dsvm_edges(uint16_t prev, uint16_t pat)
{
    return dsvm_edge_tab[((prev & 1U) << 3) | (pat & 7U)];
}

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
