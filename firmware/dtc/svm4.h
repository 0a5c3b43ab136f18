/*
 * svm4.h - space-vector modulation of the four-switch three-phase (FSTP) inverter (Hoang Fig. 1b):
 * phase A on the capacitor mid-point, legs B and C switched. Its four switching states
 * (S_B, S_C) = 00, 10, 11, 01 are all active vectors (Hoang Table I; no null vector):
 *     V(S_B, S_C) = (2/3) (v_lo + a S_B V_dc + a^2 S_C V_dc),  a = e^{j 2 pi / 3}
 * (amplitude-invariant, Hoang eqs. 1-5, phase voltages to the negative rail, phase A at the
 * mid-point voltage v_lo), which span a parallelogram; V(00) and V(11) lie on the alpha axis.
 * Hoang Table I takes v_lo = V_dc/2; here v_lo is the MEASURED lower-capacitor voltage, so a
 * split link whose mid-point has moved is modulated with the vectors it really has.
 *
 * Carrier-based form. With the mean leg voltages d_B V_dc, d_C V_dc over a period and the phase-A
 * terminal at v_lo, the star machine sees the line-to-A voltages u_x = d_x V_dc - v_lo; from the
 * reference (v_alpha, v_beta) by the inverse Clarke transform (Hoang eqs. 4-5):
 *     u_B = v_b - v_a = -(3/2) v_alpha + (sqrt3/2) v_beta
 *     u_C = v_c - v_a = -(3/2) v_alpha - (sqrt3/2) v_beta
 *     d_x = m + n_x,  m = v_lo / V_dc,  n_x = u_x / V_dc         (x = B, C)
 * Two legs, two duties: the mean vector fixes them uniquely, so this equals the volt-second
 * balance over the three vectors of the half of the parallelogram (split by its V(00)-V(11)
 * diagonal) that holds the reference, which centred pulses produce (00-10-11-10-00 when
 * d_B > d_C, 00-01-11-01-00 otherwise): every vector of the four is used, three per period.
 * Linear range: 0 <= m + n_x <= 1 for both legs, the parallelogram; the largest circle about the
 * origin inside it has the radius min(v_lo, V_dc - v_lo) / sqrt3 (V_dc / (2 sqrt3) balanced).
 * Overmodulation: a reference outside is scaled by k < 1 onto the boundary along its own angle,
 * k = min over the violated legs of h_x / |n_x| (h_x = 1 - m for n_x > 0, m otherwise; the
 * smaller of the two ratios picked by cross-multiplication): the binding leg goes onto its rail
 * exactly and the other gets m + (n_o / |n_s|) h_s (one reciprocal); overmod says so.
 *
 * Output in the form of svm.h (svm_out_t): d_iq[1], d_iq[2] the duties of legs B and C;
 * d_iq[0] = m, the mean of phase A's terminal over V_dc (no device: the application ignores the
 * FSTP's leg A, hal.h), so that the mean vector of d_iq[0..2] by the six-switch formula
 * (v_alpha = V_dc (2 d_A - d_B - d_C)/3, v_beta = V_dc (d_B - d_C)/sqrt3) is the one applied.
 * Dead time (legs B and C; the rule of svm.h, svm_leg_dt): with compensation on, a switching leg
 * is commanded d + sgn(i) T_d/T_s; d_eff_iq is the duty the leg is expected to produce (the
 * command less the dead time's loss), d_eff_iq[0] = m. Phase A has no devices and no dead time,
 * so an uncompensated dead time is an error on two phases of three: an unbalanced disturbance
 * (SIL, Hoang Table VIII at 1500 rpm: 2 points of current imbalance).
 *
 * Formats: voltages IQ pu; duties IQ in [0, IQ(1)].
 * Scaling and overflow: 1/V_dc by Newton steps (svm_recip, relative 2^-24); v/V_dc rounded and
 * clamped to +-32, m clamped to [0, 1], so |n_x| <= 76 pu and every sum stays in int32 unsaturated;
 * the cross products h |n| are formed in 64 bits (< 2^62); 1/|n_s| by svm_recip from a fresh seed
 * (accurate for |n_s| >= 2^-7; a smaller one means m within 2^-7 of a rail and the final clamp
 * bounds the duty); duties clamped to [0, 1]. V_dc <= 0: every duty 1/2 (the application trips
 * on under-voltage first). No division.
 */
#ifndef SVM4_H
#define SVM4_H

#include <stdint.h>

#include "fixmath.h"
#include "svm.h"

typedef struct {
    uint16_t dt_comp; /* 1: dead-time compensation by the current sign */
    iq_t td_iq;       /* T_d / T_s, [0, 0.5) */
} svm4_params_t;

typedef struct {
    iq_t inv_vdc_iq; /* 1 / V_dc, Newton state (0: not known, re-seeded) */
} svm4_t;

void svm4_reset(svm4_t *s);

/* One PWM period: reference (v_alpha, v_beta), DC link vdc, lower-capacitor (mid-point to the
 * negative rail) voltage vlo, all measured at the period's sample; phase currents i (the dead
 * time's sign; null: no dead-time handling, d_eff = d, whatever p->dt_comp). */
void svm4_step(svm4_t *s, const svm4_params_t *p, iq_t v_alpha_iq, iq_t v_beta_iq, iq_t vdc_iq, iq_t vlo_iq,
               const clarke_out_t *i, svm_out_t *o);

#endif /* SVM4_H */
