/*
 * swtab.h - DTC switching tables (Casadei Tables 1 and 3 for the SSTP, Hoang Table II for the
 * FSTP) and the voltage-vector -> leg-state maps (Casadei eq. 2 / Fig. 2a, Hoang Table I).
 *
 * SSTP vectors (index = DTC vector number, legs S_A S_B S_C):
 *   V_0 = 000, V_1 = 100, V_2 = 110, V_3 = 010, V_4 = 011, V_5 = 001, V_6 = 101, V_7 = 111.
 *   V_k (k = 1..6) points to (k-1)*60 deg. Indices k +- n are taken modulo 6 in 1..6.
 * FSTP vectors (Hoang Table I, legs S_B S_C; leg A is the mid-point, S_A reported as 0):
 *   V_1 = 00 (0 deg), V_2 = 10 (90 deg), V_3 = 11 (180 deg), V_4 = 01 (270 deg).
 *
 * Casadei Table 1 (three-level torque comparator c_T in {+1, 0, -1}, flux c_phi = +1 (increase)
 * or -1 (decrease), sector k):
 *              c_T = +1    c_T = 0     c_T = -1
 *   c_phi = +1  V_{k+1}    V_0 or V_7  V_{k-1}
 *   c_phi = -1  V_{k+2}    V_0 or V_7  V_{k-2}
 * Casadei Table 3 (two-level torque demand):
 *          T up, phi up   T up, phi down   T down, phi up   T down, phi down
 *   ST-A   V_{k+1}        V_{k+2}          V_0, V_7         V_0, V_7
 *   ST-B   V_{k+1}        V_{k+2}          V_k              V_0, V_7
 *   ST-C   V_{k+1}        V_{k+2}          V_k              V_{k+3}
 *   ST-D   V_{k+1}        V_{k+2}          V_{k-1}          V_{k-2}
 * The null vector (0 or 7) is chosen to minimise switch transitions (Casadei section 5): the one
 * reachable from the present leg states by the fewer leg changes (V_1, V_3, V_5 -> V_0 with one
 * change; V_2, V_4, V_6 -> V_7 with one change; a null vector stays as it is).
 * Hoang Table II (FSTP; dpsi, dT two-level, 1 = increase):
 *                 I         II        III       IV
 *   dpsi=1 dT=1   V_2(10)   V_3(11)   V_4(01)   V_1(00)
 *   dpsi=1 dT=0   V_1(00)   V_2(10)   V_3(11)   V_4(01)
 *   dpsi=0 dT=1   V_3(11)   V_4(01)   V_1(00)   V_2(10)
 *   dpsi=0 dT=0   V_4(01)   V_1(00)   V_2(10)   V_3(11)
 *
 * Pure table look-ups on small integers; no arithmetic that can overflow.
 */
#ifndef SWTAB_H
#define SWTAB_H

#include <stdint.h>

#define SWTAB_NULL 8U /* "a null vector" before the 0/7 choice */

typedef struct {
    uint16_t sa, sb, sc;
} swtab_legs_t;

/* The leg states of the last three periods, newest first (every law keeps them: the estimator
 * reconstructs the voltage of the period that just ended, the dead-time compensation needs the
 * change at its start): l3 <- l2 <- l1 <- now, field by field (no struct copy, i.e. no memcpy,
 * in the ISR). */
static inline void swtab_legs_shift(swtab_legs_t *l3, swtab_legs_t *l2, swtab_legs_t *l1,
                                    const swtab_legs_t *now)
{
    l3->sa = l2->sa;
    l3->sb = l2->sb;
    l3->sc = l2->sc;
    l2->sa = l1->sa;
    l2->sb = l1->sb;
    l2->sc = l1->sc;
    l1->sa = now->sa;
    l1->sb = now->sb;
    l1->sc = now->sc;
}

/* A leg state taken into the frame of the FSTP whose phase A' is the failed leg `phase` (0..2):
 * b', c' = the legs phase+1, phase+2 (mod 3), a' off (the live reconfigurations, dtc_reconfig.c
 * and im_dtc_reconfig.c; init-time use). */
static inline void swtab_legs_permute(swtab_legs_t *l, uint16_t phase)
{
    const uint16_t s[3] = {l->sa, l->sb, l->sc};
    l->sa = 0U;
    l->sb = s[phase == 2U ? 0U : phase + 1U];
    l->sc = s[phase == 0U ? 2U : phase - 1U];
}

/* Casadei Table 1. sector 1..6, flux_up 1/0 (c_phi = +1/-1), c_t in {+1, 0, -1}.
 * Returns 1..6 or SWTAB_NULL. */
uint16_t swtab_sstp_basic(uint16_t sector, uint16_t flux_up, int16_t c_t);

/* Casadei Table 3. strategy enum dtc_sstp_table (DTC_ST_A..DTC_ST_D), sector 1..6, flux_up and
 * torque_up 1/0. Returns 1..6 or SWTAB_NULL. */
uint16_t swtab_sstp_st(uint16_t strategy, uint16_t sector, uint16_t flux_up, uint16_t torque_up);

/* Hoang Table II. sector 1..4, flux_up and torque_up 1/0. Returns 1..4. Inline (the table in
 * swtab.c): the PM law's 50 us path, where a call costs as much as the look-up. */
extern const uint16_t swtab_fstp_table[4][4];
static inline uint16_t swtab_fstp(uint16_t sector, uint16_t flux_up, uint16_t torque_up)
{
    const uint16_t row = (uint16_t)((flux_up != 0U ? 0U : 2U) + (torque_up != 0U ? 0U : 1U));
    const uint16_t col = (uint16_t)((sector >= 1U && sector <= 4U) ? sector - 1U : 0U);
    return swtab_fstp_table[row][col];
}

/* Resolves SWTAB_NULL to 0 or 7 from the present SSTP vector (0..7); other vectors pass. */
uint16_t swtab_null_choice(uint16_t vec, uint16_t present_vec);

/* Leg states as a bit mask S_A S_B S_C (bit 2..0); built field by field so that no struct
 * copy (memcpy on some compilers) happens in the control path. */
static inline swtab_legs_t swtab_legs_of_mask(uint16_t m)
{
    swtab_legs_t l;
    l.sa = (uint16_t)((m >> 2) & 1U);
    l.sb = (uint16_t)((m >> 1) & 1U);
    l.sc = (uint16_t)(m & 1U);
    return l;
}

/* Leg states of SSTP vector 0..7 / FSTP vector 1..4 (sa = 0 for the FSTP). The FSTP's inline (the
 * mask table in swtab.c), as swtab_fstp. */
swtab_legs_t swtab_sstp_legs(uint16_t vec);
extern const uint16_t swtab_fstp_mask[5];
static inline swtab_legs_t swtab_fstp_legs(uint16_t vec)
{
    return swtab_legs_of_mask(swtab_fstp_mask[vec <= 4U ? vec : 0U]);
}

#endif /* SWTAB_H */
