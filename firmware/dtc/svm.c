#include "svm.h"

#include <stddef.h>

#define SVM_HALF_IQ ((iq_t)1 << (FIX_IQ_Q - 1))

void svm_reset(svm_t *s)
{
    s->inv_vdc_iq = 0;
}

/* The slow paths of svm_recip (svm.h), e = 1 - x y: |e| <= 1/4, two steps (iq_recip_newton) leave
 * e^4 (the next call refines); otherwise, or y <= 0, the seed 0.75 / 2^m for 2^m <= x < 2^(m+1)
 * puts x y0 in [0.75, 1.5), so |e0| <= 1/2, and the eight steps of four iq_recip_newton calls
 * leave |e| <= 2^-256: the result is the IQ rounding of 1/x. */
iq_t svm_recip_slow(iq_t y, iq_t x, iq_t e)
{
    if (x <= 0) {
        return y;
    }
    if (y <= 0 || e > (SVM_ONE_IQ >> 2) || e < -(SVM_ONE_IQ >> 2)) {
        iq_t p = SVM_ONE_IQ; /* 2^m with 2^m <= x < 2^(m+1), searched from 1 pu */
        int16_t m = 0;
        uint16_t n;
        while (p > x && m > -FIX_IQ_Q) {
            p >>= 1;
            m--;
        }
        while (m < 6 && (p << 1) <= x) {
            p <<= 1;
            m++;
        }
        /* y0 = 0.75 * 2^-m (m in [-24, 6]: y0 in [2^-7, 2^24] pu, saturated to IQ) */
        y = m >= 0 ? (iq_t)((SVM_ONE_IQ - (SVM_ONE_IQ >> 2)) >> (uint16_t)m)
                   : fix_sat32((int64_t)(SVM_ONE_IQ - (SVM_ONE_IQ >> 2)) << (uint16_t)(-m));
        for (n = 0U; n < 3U; n++) {
            y = iq_recip_newton(y, x);
        }
    }
    return iq_recip_newton(y, x);
}

/* The three legs' duties n_x + n_0 (in [0, 1]: svm_step) and their dead time (svm_leg_dt) into o.
 * Inline with a constant comp: svm_step takes one copy per case, decided once per call instead of
 * per leg. */
static inline void svm_legs(uint16_t comp, iq_t da, iq_t db, iq_t dc, iq_t ia, iq_t ib, iq_t ic, iq_t td,
                            svm_out_t *o)
{
    svm_leg_dt(comp, da, ia, td, &o->d_iq[0], &o->d_eff_iq[0]);
    svm_leg_dt(comp, db, ib, td, &o->d_iq[1], &o->d_eff_iq[1]);
    svm_leg_dt(comp, dc, ic, td, &o->d_iq[2], &o->d_eff_iq[2]);
}

void svm_step(svm_t *s, const svm_params_t *p, iq_t v_alpha_iq, iq_t v_beta_iq, iq_t vdc_iq,
              const clarke_out_t *i, svm_out_t *o)
{
    iq_t na, nb, nc, mx, mn, off, da, db, dc;

    o->overmod = 0U;
    if (vdc_iq <= 0) {
        o->d_iq[0] = o->d_iq[1] = o->d_iq[2] = SVM_HALF_IQ;
        o->d_eff_iq[0] = o->d_eff_iq[1] = o->d_eff_iq[2] = SVM_HALF_IQ;
        return;
    }
    s->inv_vdc_iq = svm_recip(s->inv_vdc_iq, vdc_iq);
    {
        /* phase references over V_dc (inverse amplitude-invariant Clarke, Hoang eqs. 4-5), the
         * normalised alpha/beta clamped to +-32 (the angle is kept below |v| = 32 V_dc): every
         * sum below is then under 2^31 without saturation (|n_x| < 60, |n_x + off| < 120 pu) */
        const iq_t a = svm_norm(v_alpha_iq, s->inv_vdc_iq, -SVM_ONE_IQ * 32, SVM_ONE_IQ * 32);
        const iq_t b = svm_norm(v_beta_iq, s->inv_vdc_iq, -SVM_ONE_IQ * 32, SVM_ONE_IQ * 32);
        const iq_t half_a = fix_rshift_rnd32(a, 1U);
        const iq_t sb = q31_mul_k(b, FIX_Q31_SQRT3_2); /* the constant > Q31_MIN: no saturation */
        na = a;
        nb = sb - half_a;
        nc = -(sb + half_a);
    }
    mx = na > nb ? na : nb;
    mx = mx > nc ? mx : nc;
    mn = na < nb ? na : nb;
    mn = mn < nc ? mn : nc;
    if (mx - mn > SVM_ONE_IQ) {
        /* overmodulation: onto the hexagon boundary along the same angle (scale 1/span, < 1);
         * the rounded products may leave [0, 1] by an LSB: clamped */
        const iq_t k = svm_recip(0, mx - mn);
        const iq_t mid = fix_rshift_rnd32(mx + mn, 1U);
        da = fix_clamp32(iq_mpy(na - mid, k) + SVM_HALF_IQ, 0, SVM_ONE_IQ);
        db = fix_clamp32(iq_mpy(nb - mid, k) + SVM_HALF_IQ, 0, SVM_ONE_IQ);
        dc = fix_clamp32(iq_mpy(nc - mid, k) + SVM_HALF_IQ, 0, SVM_ONE_IQ);
        o->overmod = 1U;
    } else {
        /* inside the hexagon, span = max n - min n <= 1: every n_x + off lies in [0, 1] without a
         * clamp. Two-phase: off = 1 - max n gives 1 - (max n - n_x) in [1 - span, 1], off = -min n
         * gives n_x - min n in [0, span]. Symmetric: off = 1/2 - r, r = (max n + min n)/2 rounded
         * half up, so (max n + min n)/2 <= r <= (max n + min n + 1 LSB)/2: max n + off <=
         * 1/2 + span/2 <= 1 and min n + off >= 1/2 - (span + 1 LSB)/2 >= -1/2 LSB, i.e. >= 0 in
         * whole LSB. */
        if (p->mode == (uint16_t)SVM_TWO_PHASE) {
            /* clamp the leg of the largest |n_x| to its rail */
            off = mx + mn >= 0 ? SVM_ONE_IQ - mx : -mn;
        } else {
            /* min-max injection: 1/2 - (max + min)/2 */
            off = SVM_HALF_IQ - fix_rshift_rnd32(mx + mn, 1U);
        }
        da = na + off;
        db = nb + off;
        dc = nc + off;
    }
    if (i == NULL) {
        svm_legs(0U, da, db, dc, 0, 0, 0, 0, o);
    } else if (p->dt_comp != 0U) {
        svm_legs(1U, da, db, dc, i->ia_iq, i->ib_iq, i->ic_iq, p->td_iq, o);
    } else {
        svm_legs(0U, da, db, dc, i->ia_iq, i->ib_iq, i->ic_iq, p->td_iq, o);
    }
}
