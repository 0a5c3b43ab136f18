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

/* svm.h. Proof, with Y = 2^48 / x (the exact 1/x in IQ LSB, 2^17 < Y <= 2^24), e_k = 1 - x y_k / 2^48:
 * - seed: m with 2^m <= x/2^24 < 2^(m+1) (m in [0, 6]), f = x/2^(24+m) - 1 in [0, 1) (t = f 2^24,
 *   from x >> m); 1/(1 + f) ~ s(f) = (98 - 80 f + 32 f^2)/99, the minimax quadratic of the relative
 *   error: |1 - (1 + f) s(f)| <= 1/99 on [0, 1] (the error equioscillates, four extrema of 1/99;
 *   checked on a 20,001-point grid). No table: the ATmega2560 proxy keeps constants in RAM. s in
 *   Q24 with the coefficients rounded and the two products truncated: within 2^-21 of s(f); y0 = s
 *   >> m: the shift truncates 2^m / s <= 2^-17 relative. |e0| < 1/99 + 2^-20 + 2^-17 < 0.0102 = eps0.
 * - step 1: r0 = 2^48 - x y0 = e0 2^48 exact (x y0 < 2^55), |r0| < 2^42; y1 = y0 + round(y0 floor(r0 /
 *   2^16) / 2^32) (y0 |r0| / 2^16 < 2^51: no overflow) = y0 (1 + e0) + d1, |d1| <= 1/2 + y0 / 2^32 <
 *   0.504, and y0 (1 + e0) = Y (1 - e0^2): e1 = e0^2 - d1 / Y, |e1| < eps0^2 + 0.504 / 2^17 < 1.08e-4.
 * - step 2: r1 = e1 2^48 exact, |r1| < 2^35, y1 < 2^24 + 1: y1 r1 < 2^60; y2 = y1 + round(y1 r1 /
 *   2^48) = Y (1 - e1^2) + d2, |d2| <= 1/2: |y2 - Y| <= Y e1^2 + 1/2 < 2^24 (1.08e-4)^2 + 0.5 < 0.7,
 *   so y2 is within one LSB of round(Y) (both integers, |y2 - round(Y)| < 1.2).
 * - rounding: r2 = 2^48 - x y2 = x (Y - y2), |r2| < x < 2^31: 2 r2 >= x means Y - y2 >= 1/2
 *   (round(Y) = y2 + 1), 2 r2 < -x means Y - y2 < -1/2 (y2 - 1), else round(Y) = y2 (half up). */
iq_t svm_recip_span(iq_t x)
{
    uint16_t m = 0U;
    int64_t y, r, t;
    while ((x >> m) >= (SVM_ONE_IQ << 1)) {
        m++;
    }
    t = (int64_t)((x >> m) - SVM_ONE_IQ); /* f in Q24, [0, 2^24) */
    y = 16607749 + (((-13557346 + ((5422939 * t) >> FIX_IQ_Q)) * t) >> FIX_IQ_Q); /* s(f), Q24 */
    y >>= m;
    r = ((int64_t)1 << 48) - (int64_t)x * y;
    y += (y * (r >> 16) + ((int64_t)1 << 31)) >> 32;
    r = ((int64_t)1 << 48) - (int64_t)x * y;
    y += (y * r + ((int64_t)1 << 47)) >> 48;
    r = ((int64_t)1 << 48) - (int64_t)x * y;
    if (2 * r >= (int64_t)x) {
        y++;
    } else if (2 * r < -(int64_t)x) {
        y--;
    }
    return (iq_t)y;
}

/* An overmodulated leg's duty x k, x = n_x - min n in [0, span], k = svm_recip_span(span): the
 * product is exact in 64 bits (x k < 2^31 2^24) and its rounding is >= 0; k is within 1/2 LSB of
 * 1/span, so x k <= 1 + span / 2 LSB: clamped to 1 at the top (the max leg's duty is 1 or 1 - 1
 * LSB before the clamp for span < 2). */
static inline iq_t svm_span_duty(iq_t x, iq_t k)
{
    const int64_t d = ((int64_t)x * (int64_t)k + ((int64_t)1 << (FIX_IQ_Q - 1))) >> FIX_IQ_Q;
    return d > (int64_t)SVM_ONE_IQ ? SVM_ONE_IQ : (iq_t)d;
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
        /* overmodulation: onto the hexagon boundary along the same angle (scale 1/span, < 1):
         * d_x = (n_x - min n) / span = 1/2 + (n_x - (max n + min n)/2) / span, the min leg at 0
         * and the max leg at 1 (svm_span_duty) */
        const iq_t k = svm_recip_span(mx - mn); /* mx - mn in (1, 120) pu */
        da = svm_span_duty(na - mn, k);
        db = svm_span_duty(nb - mn, k);
        dc = svm_span_duty(nc - mn, k);
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
