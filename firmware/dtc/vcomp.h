/*
 * vcomp.h - inverter voltage-drop compensation terms added to the voltage-model flux equations
 * (Hoang section III, eqs. 20-38, Tables III-VI).
 *
 * Sign convention (Hoang eqs. 31-34): the returned (v_f_alpha, v_f_beta) is ADDED to the
 * reconstructed (v_alpha, v_beta), so that v + v_f is the voltage the machine really sees. Each
 * switched leg loses, in the direction of its current, a forward drop v_fx (Hoang Table III) plus
 * R_on*i_x (eq. 20); the compensation is minus the Clarke transform (Hoang eqs. 4-5) of those leg drops.
 *
 * Variants (enum dtc_compensation):
 *  NONE           (0, 0): Hoang eqs. 15-16.
 *  SSTP           Hoang ref. [29] as described in the text: device and diode drops equal (V_f), so a
 *                 leg drop is V_f*sign(i_x) whatever the state (Hoang Table III with V_CE = V_d = V_f), in
 *                 all three legs; plus the on-resistance terms -R_on*i_alpha, -R_on*i_beta (Hoang eqs. 24-25).
 *                 v_f_alpha = -V_f (2 sgn i_a - sgn i_b - sgn i_c)/3, v_f_beta = -V_f (sgn i_b - sgn i_c)/sqrt(3).
 *  FSTP_SIMPLE    Hoang Table V (eqs. 35-36): legs B and C only, V_f, indexed by sign(i_b), sign(i_c).
 *                 No R_on term (Hoang Table V is the forward drop alone).
 *  FSTP_PROPOSED  Hoang Table VI: per leg Table III (state 0: +V_d for i > 0, -V_CE for i < 0;
 *                 state 1: +V_CE for i > 0, -V_d for i < 0), combined by Hoang eqs. 33-34
 *                 v_f_alpha = (v_fb + v_fc)/3, v_f_beta = -(v_fb - v_fc)/sqrt(3);
 *                 plus the R_on terms of Hoang eqs. 37-38.
 *
 * R_on in the FSTP (Hoang eqs. 26-27, 37-38). The paper prints +R_on*i_alpha/3 in eqs. 26 and 37 and
 * -R_on*i_beta in Hoang eqs. 27 and 38. Deriving the terms the way the paper describes (eq. 20 applied
 * to legs B and C only, phase A on the mid-point has no device) gives minus the Clarke transform
 * of (0, R_on i_b, R_on i_c):
 *   alpha: -(0 - R_on i_b - R_on i_c)/3 = -R_on i_a/3 = -R_on i_alpha/3
 *   beta:  -(R_on i_b - R_on i_c)/sqrt(3) = -R_on i_beta
 * The beta term agrees with Hoang eq. 38; the alpha term has the opposite sign to the printed eq. 37.
 * The same derivation reproduces every row of Hoang Tables V and VI (for the forward drops) and eqs.
 * 24-25 (for the SSTP R_on terms), and puts the resistive and forward drops of a leg on the same
 * side, as they physically are; so this module uses -R_on*i_alpha/3, and the unit test
 * test_dtc_vcomp shows the derivation. (With the Hoang Table IV R_on = 0.075 Ohm at 2.2 A the term is
 * 0.055 V against a 14 V back-emf at 1500 rpm.)
 *
 * sign(0) is taken as positive (Hoang Tables III, V, VI only list + and -).
 *
 * Formats: currents and all outputs IQ pu; drops and R_on IQ pu from the configuration.
 * Scaling and overflow: the drop sums are at most 2*max(V_CE, V_d) and are formed with
 * saturating adds; 1/3 and 1/sqrt(3) are Q31 constants (rounded, <= 0.5 LSB); R_on*i is an IQ
 * product (rounded, saturating). No division.
 */
#ifndef VCOMP_H
#define VCOMP_H

#include <stdint.h>

#include "clarke.h"
#include "dtc_config_common.h"
#include "fixmath.h"
#include "vrec.h"

typedef struct {
    uint16_t mode;      /* enum dtc_compensation */
    iq_t ka_iq, kb_iq;  /* the R_on terms' coefficients on alpha and beta (Hoang eqs. 20, 24-25,
                         * 37-38): R_on, R_on (SSTP), R_on/3, R_on (FSTP proposed, eq. 37 as
                         * derived above), 0 where the variant has none (NONE, Hoang Table V) */
    iq_t mean_iq[2][5]; /* a leg's drop averaged over the four points of a period (vcomp_leg_drop_lin)
                         * by [leg state][points with i >= 0]: [s][4] is the drop for i >= 0, [s][0]
                         * for i < 0 (Hoang Table III with V_CE, V_d; V_f for both devices in [29]
                         * and Hoang Table V), [s][n] the rounded mean of 4 - n drops for i < 0 and n
                         * for i >= 0; filled at init so that the step only selects */
} vcomp_params_t;

/* Fills the parameters (mode checked by dtc_config_validate). */
void vcomp_init(vcomp_params_t *p, uint16_t mode, iq_t v_f_iq, iq_t v_ce_iq, iq_t v_d_iq,
                iq_t r_on_iq);

/* Forward drop of one leg (Hoang Table III). state 0/1, current sign from i_iq (>= 0 is +). */
static inline iq_t vcomp_leg_drop(uint16_t state, iq_t i_iq, iq_t v_ce_iq, iq_t v_d_iq)
{
    if (state == 0U) {
        return i_iq >= 0 ? v_d_iq : fix_neg32(v_ce_iq);
    }
    return i_iq >= 0 ? v_ce_iq : fix_neg32(v_d_iq);
}

/* Forward drop of one leg (Hoang Table III) averaged over a period in which its current moves
 * linearly from i0_iq to i1_iq (one vector applied, back-EMF nearly constant): the mean of the drop
 * at the four points i0 + (i1 - i0)(2j + 1)/8, j = 0..3. A current that crosses zero inside the
 * period has one polarity for part of it and the other for the rest, and the leg's drop changes
 * with it (V_CE to -V_d or V_d to -V_CE); one polarity for the whole period leaves up to
 * (V_CE + V_d)/2 of error on that period, on legs B and C only in the FSTP (phase A has no
 * device), a negative-sequence voltage error that the voltage model integrates into the flux. The
 * four points leave at most (V_CE + V_d)/8. mean is vcomp_params_t.mean_iq[state]. Currents of one
 * sign at both ends (i0 == i1 among them) give that sign's drop at once: only a period with a zero
 * crossing counts the points (vcomp_points_pos).
 * Formats: currents and drops IQ pu; the means are formed at init (vcomp_init). */
uint16_t vcomp_points_pos(iq_t i0_iq, iq_t i1_iq);
static inline iq_t vcomp_leg_drop_lin(const iq_t mean[5], iq_t i0_iq, iq_t i1_iq)
{
    if ((i0_iq >= 0) == (i1_iq >= 0)) {
        return mean[i0_iq >= 0 ? 4 : 0]; /* the mean of four equal drops is that drop, exactly */
    }
    return mean[vcomp_points_pos(i0_iq, i1_iq)];
}

/* vcomp_step_lin's two parts, for a law that forms the forward drops of one period once (dtc_step:
 * the prediction's drops of the legs at the sample i0 are the next step's estimator's drops of the
 * same legs over i0 -> i1 when no phase current changed sign, vcomp_leg_drop_lin).
 * vcomp_fwd_lin: the forward drops alone (Hoang Tables III, V, VI through eqs. 31-36), for a mode
 * other than DTC_COMP_NONE; vcomp_ron: the R_on terms (Hoang eqs. 24-25, 37-38) at the current i
 * subtracted from them, f - k i, by a rounded, saturating IQ product and a saturating difference.
 * vcomp_step_lin is the two in a row. Formats as vcomp_step_lin. */
static inline void vcomp_fwd_lin(const vcomp_params_t *p, uint16_t sa, uint16_t sb, uint16_t sc,
                                 const clarke_out_t *i0, const clarke_out_t *i1, iq_t *fa_iq, iq_t *fb_iq)
{
    const iq_t db = vcomp_leg_drop_lin(p->mean_iq[sb], i0->ib_iq, i1->ib_iq);
    const iq_t dc = vcomp_leg_drop_lin(p->mean_iq[sc], i0->ic_iq, i1->ic_iq);
    if (p->mode == DTC_COMP_SSTP || p->mode == DTC_COMP_SSTP_PROPOSED) {
        /* Leg drops (Hoang Table III: V_CE through the on transistor, V_d through the diode of
         * the other switch; [29]: V_CE = V_d = V_f, set so by vcomp_init); minus their Clarke
         * transform (the on-resistance terms of Hoang eqs. 24-25 follow in vcomp_ron). */
        vrec_from_legs(vcomp_leg_drop_lin(p->mean_iq[sa], i0->ia_iq, i1->ia_iq), db, dc, fa_iq, fb_iq);
        *fa_iq = fix_neg32(*fa_iq);
        *fb_iq = fix_neg32(*fb_iq);
    } else {
        /* FSTP, legs B and C, no leg-A device: Hoang Table V (V_f) or Table VI (Table III per leg),
         * combined by Hoang eqs. 33-34 (= eqs. 35-36 for Table V) */
        *fa_iq = q31_mul_k(fix_add32(db, dc), VREC_THIRD_Q31);    /* Hoang eq. 33 */
        *fb_iq = q31_mul_k(fix_sub32(dc, db), VREC_INV_SQRT3_Q31); /* Hoang eq. 34 */
    }
}
static inline void vcomp_ron(const vcomp_params_t *p, const clarke_out_t *i, iq_t fa_iq, iq_t fb_iq,
                             iq_t *v_f_alpha_iq, iq_t *v_f_beta_iq)
{
    /* see the header for the sign of Hoang eq. 37's term */
    *v_f_alpha_iq = fix_sub32(fa_iq, iq_mpy(p->ka_iq, i->i_alpha_iq));
    *v_f_beta_iq = fix_sub32(fb_iq, iq_mpy(p->kb_iq, i->i_beta_iq));
}

/* vcomp_fwd_lin at one sample (i0 = i1) on the four-switch inverter as a table. In the FSTP modes
 * (FSTP_SIMPLE, FSTP_PROPOSED) the forward drops of legs B and C at a sample are a function of the
 * two legs' states and their currents' signs alone (Hoang Tables V, VI: mean_iq[s][4] for i >= 0,
 * mean_iq[s][0] for i < 0), so the table holds vcomp_fwd_lin's value for each of the 16
 * combinations, formed at init by vcomp_fwd_lin itself (vcomp_step with no R_on current): bit for bit
 * the same. Index (vcomp_pt_index):
 * bit 3 s_b, bit 2 i_b < 0, bit 1 s_c, bit 0 i_c < 0. ok = 0 in the other modes (SSTP: three legs,
 * 64 combinations; NONE), where the caller forms the drops with vcomp_fwd_lin. Formats: IQ pu as
 * vcomp_fwd_lin. RAM per user: 32 IQ values and a flag (65 C28x words). */
typedef struct {
    iq_t fa_iq[16], fb_iq[16];
    uint16_t ok;
} vcomp_pt_t;

/* Fills t from p (init only). */
void vcomp_pt_init(vcomp_pt_t *t, const vcomp_params_t *p);

static inline uint16_t vcomp_pt_index(uint16_t sb, uint16_t sc, const clarke_out_t *i)
{
    return (uint16_t)((sb != 0U ? 8U : 0U) | (i->ib_iq < 0 ? 4U : 0U) | (sc != 0U ? 2U : 0U) |
                      (i->ic_iq < 0 ? 1U : 0U));
}

/* As vcomp_step for a period in which the currents move linearly from i0 to i1: the forward drops
 * of each leg averaged over the period (vcomp_leg_drop_lin), the R_on terms (linear in the current)
 * at the period's mean current i_mean. vcomp_step(p, .., i, ..) is vcomp_step_lin(p, .., i, i, i, ..). */
void vcomp_step_lin(const vcomp_params_t *p, uint16_t sa, uint16_t sb, uint16_t sc, const clarke_out_t *i_mean,
                    const clarke_out_t *i0, const clarke_out_t *i1, iq_t *v_f_alpha_iq, iq_t *v_f_beta_iq);
/* Compensation voltages for the leg states (0 or 1) applied during the integration interval and the
 * currents (all three phases and alpha-beta, from clarke_*). Outputs IQ pu, to be ADDED to v.
 * Inline, so that a caller's chain holds no frame of its own for it. */
static inline void vcomp_step(const vcomp_params_t *p, uint16_t sa, uint16_t sb, uint16_t sc,
                              const clarke_out_t *i, iq_t *v_f_alpha_iq, iq_t *v_f_beta_iq)
{
    vcomp_step_lin(p, sa, sb, sc, i, i, i, v_f_alpha_iq, v_f_beta_iq);
}

/* vcomp_step as a table of the phase currents' signs (the IM laws, the ITC's observer). With the legs
 * off (an SVM period's base term), or with drops that do not depend on the state (NONE, SSTP
 * [29] and Hoang Table V: V_CE = V_d = V_f), every variant above is a function of sgn i_a, sgn i_b,
 * sgn i_c alone plus the linear R_on terms: the table holds vcomp_step's value without the R_on
 * terms for each sign pattern (index bit 0: i_a < 0, bit 1: i_b < 0, bit 2: i_c < 0; vcomp_step
 * itself with R_on = 0, at init) and vcomp_tab_step subtracts the R_on terms by the same rounded
 * product and saturating difference as vcomp_step: the result is bit-identical to vcomp_step's.
 * ka, kb are the R_on coefficients of alpha and beta (R_on, R_on or R_on/3, R_on; 0 where the
 * variant has none: fix_sub32(x, 0) = x).
 * Formats: IQ pu as vcomp_step. Overflow: as vcomp_step (the table holds its saturated values, the
 * R_on product is rounded and saturated, the difference saturates). 12 words of RAM per user. */
typedef struct {
    iq_t va_iq[8];      /* alpha without the R_on term, legs off, per sign pattern */
    iq_t vb_iq[4];      /* beta, per the signs of i_b, i_c (pattern / 2: every variant's beta term
                         * depends on legs B and C only) */
    iq_t ka_iq, kb_iq;  /* the R_on terms' coefficients */
    uint16_t legs_free; /* 1: the table holds for any leg states */
} vcomp_tab_t;

/* Fills t from p (init only). */
void vcomp_tab_init(vcomp_tab_t *t, const vcomp_params_t *p);

/* vcomp_step(p, 0, 0, 0, i, ...) for the p of vcomp_tab_init (any legs when t->legs_free). */
static inline void vcomp_tab_step(const vcomp_tab_t *t, const clarke_out_t *i, iq_t *v_f_alpha_iq,
                                  iq_t *v_f_beta_iq)
{
    const uint16_t k = (uint16_t)((i->ia_iq < 0 ? 1U : 0U) | (i->ib_iq < 0 ? 2U : 0U) | (i->ic_iq < 0 ? 4U : 0U));
    *v_f_alpha_iq = fix_sub32(t->va_iq[k], iq_mpy(t->ka_iq, i->i_alpha_iq));
    *v_f_beta_iq = fix_sub32(t->vb_iq[k >> 1], iq_mpy(t->kb_iq, i->i_beta_iq));
}

#endif /* VCOMP_H */
