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

/* Rotation of a space vector into the frame of a cyclic phase permutation (the live
 * reconfiguration after a leg failure: dtc_reconfig.c, im_dtc_reconfig.c): with (a', b', c') =
 * (x, x+1, x+2) the amplitude-invariant Clarke vector (Hoang eqs. 4-5), (2/3)(v_a' + a v_b' +
 * a^2 v_c') with a = e^{j 120 deg}, equals a^{-x} (2/3)(v_a + a v_b + a^2 v_c): the vector turned
 * by -x 120 deg. x = 1: (alpha, beta) -> (-alpha/2 + (sqrt3/2) beta, -(sqrt3/2) alpha - beta/2);
 * x = 2 the same with sqrt3/2 negated; x = 0 unchanged. Formats: IQ in and out, sqrt(3)/2 in
 * Q15 (28378, error 1.4e-5); products rounded, sums saturating. Init-time use. */
static inline void clarke_rot_phase(iq_t *a, iq_t *b, uint16_t x)
{
    const q15_t s = x == 1U ? (q15_t)-28378 : (q15_t)28378;
    const iq_t a0 = *a;
    const iq_t b0 = *b;
    if (x == 0U) {
        return;
    }
    *a = fix_sub32(fix_neg32(fix_rshift_rnd32(a0, 1U)), iq_mpy_q15(b0, s));
    *b = fix_sub32(iq_mpy_q15(a0, s), fix_rshift_rnd32(b0, 1U));
}

/* The angle of that rotation, x 120 deg in angle_t (65536 / 3 = 21845.33 LSB per 120 deg: the 1/3
 * LSB left is 0.002 deg), x = 0..2: an angle in the new frame is the old one less this. */
static inline angle_t clarke_phase_angle(uint16_t x)
{
    return (angle_t)(x * 21845U + (x == 2U ? 1U : 0U));
}

#endif /* CLARKE_H */
