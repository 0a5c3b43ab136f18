/*
 * vrec.h - phase-voltage reconstruction from the leg states and the measured DC link
 * (Hoang section III-A, eqs. 1-5 and 17-19).
 *
 * The leg (phase-to-negative-rail) voltages are v_x0 = S_x * V_dc for a switched leg. For the
 * FSTP, leg A is the capacitor mid-point: v_a0 = V_mid when the mid-point voltage is measured
 * (it drifts with the phase-A current through the capacitors), otherwise V_dc/2, which is
 * Hoang's "S_A = 1/2" and reproduces eqs. 17-19 exactly. Then (eqs. 1-5)
 *   v_alpha = (2 v_a0 - v_b0 - v_c0) / 3,   v_beta = (v_b0 - v_c0) / sqrt(3)
 * (the neutral-to-zero voltage v_n0 cancels in both). For the FSTP with v_a0 = V_dc/2:
 *   v_alpha = V_dc (1 - S_B - S_C)/3, v_beta = V_dc (S_B - S_C)/sqrt(3), i.e. Hoang Table I.
 *
 * Formats: V_dc, V_mid, outputs in IQ pu; leg states 0/1. Scaling and overflow: 2 v_a0 - v_b0 -
 * v_c0 is bounded by 2*|V_dc| + 2*|V_mid|, formed with saturating adds; the 1/3 and 1/sqrt(3)
 * factors are Q31 constants below 1 (q31_mul_k: rounded 64-bit product, <= 0.5 LSB each, cannot
 * overflow). No division.
 */
#ifndef VREC_H
#define VREC_H

#include <stdint.h>

#include "clarke.h"
#include "fixmath.h"
#include "swtab.h"

#define VREC_THIRD_Q31 FIX_Q31_THIRD
#define VREC_INV_SQRT3_Q31 FIX_Q31_INV_SQRT3

/* General form from the three leg voltages (IQ pu, referred to the negative rail). */
static inline void vrec_from_legs(iq_t va0_iq, iq_t vb0_iq, iq_t vc0_iq, iq_t *v_alpha_iq,
                                  iq_t *v_beta_iq)
{
    iq_t num = fix_sub32(fix_add32(va0_iq, va0_iq), fix_add32(vb0_iq, vc0_iq));
    *v_alpha_iq = q31_mul_k(num, VREC_THIRD_Q31);
    *v_beta_iq = q31_mul_k(fix_sub32(vb0_iq, vc0_iq), VREC_INV_SQRT3_Q31);
}

/* SSTP: v_x0 = S_x * V_dc (Casadei eq. 2: active vectors have length 2/3 V_dc). Inline, as
 * vrec_fstp. */
static inline void vrec_sstp(uint16_t sa, uint16_t sb, uint16_t sc, iq_t vdc_iq, iq_t *v_alpha_iq,
                             iq_t *v_beta_iq)
{
    vrec_from_legs(sa != 0U ? vdc_iq : 0, sb != 0U ? vdc_iq : 0, sc != 0U ? vdc_iq : 0,
                   v_alpha_iq, v_beta_iq);
}

/* FSTP: leg A at the mid-point. vmid_measured = 0 uses V_dc/2 (Hoang eqs. 17-19, S_A = 1/2);
 * 1 uses the measured mid-point (lower capacitor) voltage vmid_iq. Inline: the PM law's 50 us
 * path reconstructs up to two leg states per period, and a call with seven arguments costs as
 * much as the two products. */
static inline void vrec_fstp(uint16_t sb, uint16_t sc, iq_t vdc_iq, iq_t vmid_iq, uint16_t vmid_measured,
                             iq_t *v_alpha_iq, iq_t *v_beta_iq)
{
    /* V_dc/2 exactly: 2*v_a0 = V_dc, so pass half through the "2 v_a0" of vrec_from_legs by
     * rounding once: fix_rshift_rnd32 keeps the shift of a negative value inside fixmath. */
    iq_t va0_iq = vmid_measured != 0U ? vmid_iq : fix_rshift_rnd32(vdc_iq, 1U);
    vrec_from_legs(va0_iq, sb != 0U ? vdc_iq : 0, sc != 0U ? vdc_iq : 0, v_alpha_iq, v_beta_iq);
}

/* Dead-time compensation of the reconstructed voltage (Casadei sec. 10.5), shared by the laws that
 * reconstruct the voltage from leg states (the PM DTC law, dtc.c, and the IM laws' table schemes,
 * im_dtc.c): the error of the voltage reconstructed from the legs of a period whose legs went from
 * prev to cur, alpha/beta, IQ pu, with the link voltage and the phase currents at the switching
 * instant; 0 when no leg changed. Formats: e = V_dc * T_d/T_s (IQ x Q15, rounded), the leg errors
 * are 0 or +-e, vrec_from_legs saturates. Pure function, no state. */
typedef struct {
    q15_t td_ts_q15; /* dead time over the control period, T_d / T_s, [0, 0.5) (board.td_ts_q15) */
    uint16_t fstp;   /* 1: four-switch inverter, leg A on the mid-point never switches */
} deadtime_params_t;

void deadtime_error(const deadtime_params_t *p, iq_t vdc_iq, const clarke_out_t *i, const swtab_legs_t *prev,
                    const swtab_legs_t *cur, iq_t *dva, iq_t *dvb);

/* deadtime_error in its two parts, for a law that forms one leg change twice (dtc_step: the
 * prediction for k+1, then the estimator one step later, on the same legs and current sample but
 * the next link voltage): deadtime_error(p, vdc, i, prev, cur) is
 * deadtime_apply(p, vdc, deadtime_code(p, i, prev, cur)), bit for bit.
 * deadtime_code: the legs' errors k_x in {-1, 0, 1} (deadtime_leg) packed as
 * (k_a + 1) | (k_b + 1) << 2 | (k_c + 1) << 4; DEADTIME_CODE_ZERO (every k_x 0) also when no leg
 * changed. DEADTIME_CODE_NONE is no code (a caller's mark for "not formed"); deadtime_apply must
 * not be given it. */
#define DEADTIME_CODE_ZERO 21U
#define DEADTIME_CODE_NONE 0xFFFFU

/* Dead-time error of one leg over one period, in units of e = V_dc T_d/T_s: the leg changed state
 * at the period's start (prev -> cur) and for T_d both devices were off, so the phase current's
 * free-wheeling diode set the leg voltage: turning on the upper device with the current leaving the
 * leg (i > 0), the lower diode kept the leg at 0 for T_d: -e on the period's mean; turning it off
 * with the current entering (i < 0), the upper diode kept it at V_dc: +e. Otherwise the current
 * commutates at once and there is no error (0). The sign of the sampled current decides. */
static inline int32_t deadtime_leg(uint16_t prev, uint16_t cur, iq_t i)
{
    if (prev == 0U && cur != 0U && i > 0) {
        return -1;
    }
    if (prev != 0U && cur == 0U && i < 0) {
        return 1;
    }
    return 0;
}

/* Dead-time compensation (Casadei sec. 10.5; deadtime_code, then deadtime_apply): the leg errors of
 * deadtime_leg through the same leg-to-alpha/beta transform as the reconstruction (vrec_from_legs,
 * Hoang eqs. 1-5; FSTP: leg A is the mid-point and never switches). Phase currents at the switching
 * instant, all three (clarke_out_t: the two measured, the third by Kirchhoff). Inline: the PM law's
 * 50 us path forms one code per period.
 * Scaling and overflow: e = V_dc * T_d/T_s (IQ x Q15, rounded) with T_d/T_s < 1/2 (validated), so
 * |e| < 2^30 and the leg errors k_x e (k_x in {-1, 0, 1}) give 2 k_a e and (k_b + k_c) e exactly in
 * 32 bits: vrec_from_legs' sums 2 v_a and v_b + v_c cannot saturate, and its saturating
 * difference and rounded Q31 products are taken in deadtime_apply the same way on the integer
 * multiples of e (bit for bit vrec_from_legs of the three leg errors, with no 64-bit sum but the
 * last). */
static inline uint16_t deadtime_code(const deadtime_params_t *p, const clarke_out_t *i, const swtab_legs_t *prev,
                                     const swtab_legs_t *cur)
{
    int32_t ka, kb, kc;
    if (prev->sa == cur->sa && prev->sb == cur->sb && prev->sc == cur->sc) {
        return DEADTIME_CODE_ZERO; /* no leg changed: no dead-time error */
    }
    ka = p->fstp != 0U ? 0 : deadtime_leg(prev->sa, cur->sa, i->ia_iq);
    kb = deadtime_leg(prev->sb, cur->sb, i->ib_iq);
    kc = deadtime_leg(prev->sc, cur->sc, i->ic_iq);
    return (uint16_t)((uint32_t)(ka + 1) | ((uint32_t)(kb + 1) << 2) | ((uint32_t)(kc + 1) << 4));
}

/* The voltages of a deadtime_code for the link voltage vdc_iq: 0 for DEADTIME_CODE_ZERO, else
 * vrec_from_legs of the leg errors k_x e (formats and overflow: deadtime_code). */
static inline void deadtime_apply(const deadtime_params_t *p, iq_t vdc_iq, uint16_t code, iq_t *dva, iq_t *dvb)
{
    iq_t e;
    int32_t ka, kb, kc;
    if (code == DEADTIME_CODE_ZERO) {
        *dva = 0; /* no leg changed, or none with an error (the sums below are 0 then) */
        *dvb = 0;
        return;
    }
    e = iq_mpy_q15(vdc_iq, p->td_ts_q15);
    ka = (int32_t)(code & 3U) - 1;
    kb = (int32_t)((code >> 2) & 3U) - 1;
    kc = (int32_t)((code >> 4) & 3U) - 1;
    *dva = q31_mul_k(fix_sub32((ka + ka) * e, (kb + kc) * e), VREC_THIRD_Q31);
    *dvb = q31_mul_k((kb - kc) * e, VREC_INV_SQRT3_Q31);
}

#endif /* VREC_H */
