#include "svm.h"

#include <stddef.h>

#define SVM_ONE_IQ ((iq_t)1 << FIX_IQ_Q)
#define SVM_HALF_IQ ((iq_t)1 << (FIX_IQ_Q - 1))
#define SVM_SQRT3_2_Q31 Q31(0.86602540378443865)

void svm_reset(svm_t *s)
{
    s->inv_vdc_iq = 0;
}

/* Newton's reciprocal with a re-seed (svm.h). The seed 0.75 / 2^m for 2^m <= x < 2^(m+1) puts
 * x y0 in [0.75, 1.5), so |e0| = |1 - x y0| <= 1/2 and after the eight steps of four
 * iq_recip_newton calls |e| <= 2^-256: the result is the IQ rounding of 1/x. Otherwise one call
 * (two steps) refines the previous y: |e| <= 1/4 becomes <= 2^-8, then 2^-32 on the next call. */
iq_t svm_recip(iq_t y, iq_t x)
{
    if (x <= 0) {
        return y;
    }
    {
        /* |1 - x y| > 1/4 ? (x y in IQ, rounded, saturating) */
        const iq_t e = iq_sub(SVM_ONE_IQ, iq_mpy(x, y));
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
    }
    return iq_recip_newton(y, x);
}

static iq_t max3(iq_t a, iq_t b, iq_t c)
{
    const iq_t m = a > b ? a : b;
    return m > c ? m : c;
}

static iq_t min3(iq_t a, iq_t b, iq_t c)
{
    const iq_t m = a < b ? a : b;
    return m < c ? m : c;
}

/* Dead time of one leg (svm.h): the command and the expected effective duty. */
static void svm_leg_dt(const svm_params_t *p, iq_t d, iq_t i, iq_t td, iq_t *d_cmd, iq_t *d_eff)
{
    const iq_t sgn_td = i > 0 ? td : (i < 0 ? -td : 0);
    iq_t c = d;
    if (p->dt_comp != 0U && d > 0 && d < SVM_ONE_IQ) {
        c = fix_clamp32(iq_add(d, sgn_td), 0, SVM_ONE_IQ);
    }
    *d_cmd = c;
    *d_eff = (c > 0 && c < SVM_ONE_IQ) ? iq_sub(c, sgn_td) : c;
}

void svm_step(svm_t *s, const svm_params_t *p, iq_t v_alpha_iq, iq_t v_beta_iq, iq_t vdc_iq,
              const clarke_out_t *i, svm_out_t *o)
{
    iq_t n[3], mx, mn, off;
    uint16_t x;

    o->overmod = 0U;
    if (vdc_iq <= 0) {
        for (x = 0U; x < 3U; x++) {
            o->d_iq[x] = SVM_HALF_IQ;
            o->d_eff_iq[x] = SVM_HALF_IQ;
        }
        return;
    }
    s->inv_vdc_iq = svm_recip(s->inv_vdc_iq, vdc_iq);
    {
        /* phase references over V_dc (inverse amplitude-invariant Clarke, Hoang eqs. 4-5) */
        const iq_t a = iq_mpy(v_alpha_iq, s->inv_vdc_iq);
        const iq_t b = iq_mpy(v_beta_iq, s->inv_vdc_iq);
        const iq_t half_a = fix_rshift_rnd32(a, 1U);
        const iq_t sb = q31_mul(b, SVM_SQRT3_2_Q31);
        n[0] = a;
        n[1] = iq_sub(sb, half_a);
        n[2] = fix_neg32(iq_add(sb, half_a));
    }
    mx = max3(n[0], n[1], n[2]);
    mn = min3(n[0], n[1], n[2]);
    if (iq_sub(mx, mn) > SVM_ONE_IQ) {
        /* overmodulation: onto the hexagon boundary along the same angle (scale 1/span) */
        const iq_t k = svm_recip(0, iq_sub(mx, mn));
        const iq_t mid = iq_add(fix_rshift_rnd32(mx, 1U), fix_rshift_rnd32(mn, 1U));
        for (x = 0U; x < 3U; x++) {
            n[x] = iq_mpy(iq_sub(n[x], mid), k);
        }
        off = SVM_HALF_IQ;
        o->overmod = 1U;
    } else if (p->mode == (uint16_t)SVM_TWO_PHASE) {
        /* clamp the leg of the largest |n_x| to its rail */
        off = iq_add(mx, mn) >= 0 ? iq_sub(SVM_ONE_IQ, mx) : fix_neg32(mn);
    } else {
        /* min-max injection: 1/2 - (max + min)/2 */
        off = iq_sub(SVM_HALF_IQ, iq_add(fix_rshift_rnd32(mx, 1U), fix_rshift_rnd32(mn, 1U)));
    }
    {
        const iq_t td = iq_from_q15(p->td_ts_q15);
        for (x = 0U; x < 3U; x++) {
            const iq_t d = fix_clamp32(iq_add(n[x], off), 0, SVM_ONE_IQ);
            const iq_t ix = i == NULL ? 0 : (x == 0U ? i->ia_iq : (x == 1U ? i->ib_iq : i->ic_iq));
            svm_leg_dt(p, d, ix, td, &o->d_iq[x], &o->d_eff_iq[x]);
        }
    }
}
