#include "svm4.h"

#include <stddef.h>

#define SVM4_HALF_IQ ((iq_t)1 << (FIX_IQ_Q - 1))

void svm4_reset(svm4_t *s)
{
    s->inv_vdc_iq = 0;
}

/* Headroom of a leg towards the rail its n points at (svm4.h): 1 - m up, m down. */
static iq_t svm4_room(iq_t n, iq_t m)
{
    return n > 0 ? SVM_ONE_IQ - m : m;
}

/* Legs B and C: their duties m + n_x (in [0, 1]: svm4_step) and dead time (svm_leg_dt) into o. Inline with a
 * constant comp: svm4_step takes one copy per case, decided once per call instead of per leg. */
static inline void svm4_legs(uint16_t comp, iq_t db, iq_t dc, iq_t ib, iq_t ic, iq_t td, svm_out_t *o)
{
    svm_leg_dt(comp, db, ib, td, &o->d_iq[1], &o->d_eff_iq[1]);
    svm_leg_dt(comp, dc, ic, td, &o->d_iq[2], &o->d_eff_iq[2]);
}

void svm4_step(svm4_t *s, const svm4_params_t *p, iq_t v_alpha_iq, iq_t v_beta_iq, iq_t vdc_iq, iq_t vlo_iq,
               const clarke_out_t *i, svm_out_t *o)
{
    iq_t m, nb, nc, db, dc;

    o->overmod = 0U;
    if (vdc_iq <= 0) {
        o->d_iq[0] = o->d_iq[1] = o->d_iq[2] = SVM4_HALF_IQ;
        o->d_eff_iq[0] = o->d_eff_iq[1] = o->d_eff_iq[2] = SVM4_HALF_IQ;
        return;
    }
    s->inv_vdc_iq = svm_recip(s->inv_vdc_iq, vdc_iq);
    m = svm_norm(vlo_iq, s->inv_vdc_iq, 0, SVM_ONE_IQ);
    {
        /* line-to-A references over V_dc (inverse Clarke, Hoang eqs. 4-5) */
        const iq_t a = svm_norm(v_alpha_iq, s->inv_vdc_iq, -SVM_ONE_IQ * 32, SVM_ONE_IQ * 32);
        const iq_t b = svm_norm(v_beta_iq, s->inv_vdc_iq, -SVM_ONE_IQ * 32, SVM_ONE_IQ * 32);
        const iq_t a15 = a + fix_rshift_rnd32(a, 1U);
        const iq_t sb = q31_mul_k(b, FIX_Q31_SQRT3_2); /* the constant > Q31_MIN: no saturation */
        nb = sb - a15;
        nc = -sb - a15;
    }
    {
        const iq_t hb = svm4_room(nb, m), hc = svm4_room(nc, m);
        const iq_t ab = nb < 0 ? -nb : nb, ac = nc < 0 ? -nc : nc;
        if (ab > hb || ac > hc) {
            /* onto the parallelogram along the same angle, k = min(h_B/|n_B|, h_C/|n_C|): the
             * binding leg lands on its rail exactly, the other is n_o k = (n_o / |n_s|) h_s */
            const int use_b = (int64_t)hb * ac <= (int64_t)hc * ab;
            const iq_t h = use_b ? hb : hc;
            const iq_t r = iq_mpy(use_b ? nc : nb, svm_recip(0, use_b ? ab : ac));
            const iq_t n_o = iq_mpy(r, h);
            const iq_t n_s = (use_b ? nb : nc) > 0 ? h : -h;
            /* the rounded n_o may leave [0, 1] by an LSB: clamped */
            db = fix_clamp32(m + (use_b ? n_s : n_o), 0, SVM_ONE_IQ);
            dc = fix_clamp32(m + (use_b ? n_o : n_s), 0, SVM_ONE_IQ);
            o->overmod = 1U;
        } else {
            /* inside: |n_x| <= h_x, the room towards the rail n_x points at (svm4_room), so
             * m + n_x lies in [0, 1] (m in [0, 1]) without a clamp */
            db = m + nb;
            dc = m + nc;
        }
    }
    o->d_iq[0] = m;
    o->d_eff_iq[0] = m;
    if (i == NULL) {
        svm4_legs(0U, db, dc, 0, 0, 0, o);
    } else if (p->dt_comp != 0U) {
        svm4_legs(1U, db, dc, i->ib_iq, i->ic_iq, p->td_iq, o);
    } else {
        svm4_legs(0U, db, dc, i->ib_iq, i->ic_iq, p->td_iq, o);
    }
}
