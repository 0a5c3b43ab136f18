/*
 * clarke.h - Clarke transform from two measured phase currents (Hoang eqs. 4-5, amplitude
 * invariant; the third current follows from i_a + i_b + i_c = 0, star connection, no neutral).
 *
 * Which two currents are measured:
 *   SSTP: i_a and i_b. All three legs switch and carry device drops symmetrically, so no phase
 *         is special; measuring A makes i_alpha = i_a exact (no arithmetic, no rounding) and B
 *         completes the pair (the conventional choice, as in the TI MotorControl SDK clarke).
 *         The SSTP compensation (Hoang ref. [29]) needs all three signs: sign(i_c) is taken from
 *         -(i_a + i_b).
 *   FSTP: i_b and i_c. These are the two SWITCHED phases: the compensation of Hoang Tables V
 *         and VI is indexed by sign(i_b) and sign(i_c) (Table III, per leg), so measuring them
 *         directly gives those signs from one sensor each; a sign of i_c reconstructed as
 *         -(i_a + i_b) would carry the noise and offset error of two sensors exactly where it
 *         matters, at the current zero crossing. Phase A (the capacitor mid-point) then follows
 *         as i_a = -(i_b + i_c); it is also the phase with the least switching ripple.
 *
 * Formats: currents in IQ (Q24) pu. Scaling and overflow: the sums are formed in 32 bits and
 * saturated (fix_add32); the 1/sqrt(3) and sqrt(3)/2 factors are Q31 constants below 1 applied
 * with a rounded 64-bit product (q31_mul_k: <= 0.5 LSB, cannot overflow). Inputs beyond +-64 pu
 * saturate rather than wrap.
 */
#ifndef CLARKE_H
#define CLARKE_H

#include "fixmath.h"

#define CLARKE_INV_SQRT3_Q31 FIX_Q31_INV_SQRT3

typedef struct {
    iq_t ia_iq, ib_iq, ic_iq;  /* all three phase currents (one of them reconstructed) */
    iq_t i_alpha_iq, i_beta_iq;
} clarke_out_t;

/* SSTP: measured i_a, i_b. i_alpha = i_a, i_beta = (i_a + 2 i_b)/sqrt(3) (Hoang eq. 5 with
 * i_c = -i_a - i_b). */
static inline void clarke_sstp(iq_t ia_iq, iq_t ib_iq, clarke_out_t *o)
{
    o->ia_iq = ia_iq;
    o->ib_iq = ib_iq;
    o->ic_iq = fix_neg32(fix_add32(ia_iq, ib_iq));
    o->i_alpha_iq = ia_iq;
    o->i_beta_iq = q31_mul_k(fix_add32(ia_iq, fix_add32(ib_iq, ib_iq)), CLARKE_INV_SQRT3_Q31);
}

/* FSTP: measured i_b, i_c. i_alpha = i_a = -(i_b + i_c) (Hoang eq. 4 with the zero sum),
 * i_beta = (i_b - i_c)/sqrt(3) (eq. 5). */
static inline void clarke_fstp(iq_t ib_iq, iq_t ic_iq, clarke_out_t *o)
{
    o->ib_iq = ib_iq;
    o->ic_iq = ic_iq;
    o->ia_iq = fix_neg32(fix_add32(ib_iq, ic_iq));
    o->i_alpha_iq = o->ia_iq;
    o->i_beta_iq = q31_mul_k(fix_sub32(ib_iq, ic_iq), CLARKE_INV_SQRT3_Q31);
}

/* The measured currents of either inverter (fstp != 0: i_b, i_c by clarke_fstp; else i_a, i_b by
 * clarke_sstp; the unmeasured one is not read). */
static inline void clarke_meas(uint16_t fstp, iq_t ia_iq, iq_t ib_iq, iq_t ic_iq, clarke_out_t *o)
{
    if (fstp != 0U) {
        clarke_fstp(ib_iq, ic_iq, o);
    } else {
        clarke_sstp(ia_iq, ib_iq, o);
    }
}

/* Inverse (Hoang eqs. 4-5 solved for the phases with i_a + i_b + i_c = 0): i_a = i_alpha,
 * i_b = -i_alpha/2 + (sqrt(3)/2) i_beta, i_c = -i_a - i_b (the zero sum holds exactly). IQ pu;
 * the products round, the sums saturate. */
#define CLARKE_SQRT3_2_Q31 FIX_Q31_SQRT3_2
static inline void clarke_inv(iq_t i_alpha_iq, iq_t i_beta_iq, clarke_out_t *o)
{
    o->i_alpha_iq = i_alpha_iq;
    o->i_beta_iq = i_beta_iq;
    o->ia_iq = i_alpha_iq;
    o->ib_iq = fix_sub32(q31_mul_k(i_beta_iq, CLARKE_SQRT3_2_Q31), fix_rshift_rnd32(i_alpha_iq, 1U));
    o->ic_iq = fix_neg32(fix_add32(o->ia_iq, o->ib_iq));
}

#endif /* CLARKE_H */
