#include "vcomp.h"

#include "dtc_config.h"
#include "vrec.h"

void vcomp_init(vcomp_params_t *p, uint16_t mode, iq_t v_f_iq, iq_t v_ce_iq, iq_t v_d_iq,
                iq_t r_on_iq)
{
    p->mode = mode;
    p->v_f_iq = v_f_iq;
    /* the SSTP schemes share one code path: [29] is Table III with V_CE = V_d = V_f */
    p->v_ce_iq = mode == DTC_COMP_SSTP ? v_f_iq : v_ce_iq;
    p->v_d_iq = mode == DTC_COMP_SSTP ? v_f_iq : v_d_iq;
    p->r_on_iq = r_on_iq;
    p->r_on_third_iq = q31_mul(r_on_iq, VREC_THIRD_Q31);
}

/* vcomp.h: the leg drop averaged over a period of linear current. */
iq_t vcomp_leg_drop_lin(uint16_t state, iq_t i0_iq, iq_t i1_iq, iq_t v_ce_iq, iq_t v_d_iq)
{
    iq_t dp, dm;
    int64_t d, step, pt;
    int32_t sum = 0;
    uint16_t j;
    if ((i0_iq >= 0) == (i1_iq >= 0)) {
        /* no zero crossing inside the period: the four points' polarities are i0's (the mean of
         * four equal drops is that drop, exactly) */
        return vcomp_leg_drop(state, i0_iq, v_ce_iq, v_d_iq);
    }
    dp = vcomp_leg_drop(state, 0, v_ce_iq, v_d_iq);  /* drop for i >= 0 */
    dm = vcomp_leg_drop(state, -1, v_ce_iq, v_d_iq); /* drop for i < 0 */
    d = (int64_t)i1_iq - (int64_t)i0_iq;
    step = d + d;                /* 8 x the change over a quarter period */
    pt = (int64_t)i0_iq * 8 + d; /* 8 x the current at 1/8 of the period */
    for (j = 0U; j < 4U; j++) {
        sum = fix_add32(sum, pt >= 0 ? dp : dm);
        pt += step;
    }
    return fix_rshift_rnd32(sum, 2U);
}

void vcomp_step(const vcomp_params_t *p, uint16_t sa, uint16_t sb, uint16_t sc,
                const clarke_out_t *i, iq_t *v_f_alpha_iq, iq_t *v_f_beta_iq)
{
    vcomp_step_lin(p, sa, sb, sc, i, i, i, v_f_alpha_iq, v_f_beta_iq);
}

void vcomp_step_lin(const vcomp_params_t *p, uint16_t sa, uint16_t sb, uint16_t sc, const clarke_out_t *i,
                    const clarke_out_t *i0, const clarke_out_t *i1, iq_t *v_f_alpha_iq, iq_t *v_f_beta_iq)
{
    iq_t da, db, dc, fa, fb;

    switch (p->mode) {
    case DTC_COMP_SSTP:
    case DTC_COMP_SSTP_PROPOSED:
        /* Leg drops (Hoang Table III: V_CE through the on transistor, V_d through the diode of
         * the other switch; [29]: V_CE = V_d = V_f, set so by vcomp_init); minus their Clarke
         * transform, then the on-resistance terms of Hoang eqs. 24-25. */
        da = vcomp_leg_drop_lin(sa, i0->ia_iq, i1->ia_iq, p->v_ce_iq, p->v_d_iq);
        db = vcomp_leg_drop_lin(sb, i0->ib_iq, i1->ib_iq, p->v_ce_iq, p->v_d_iq);
        dc = vcomp_leg_drop_lin(sc, i0->ic_iq, i1->ic_iq, p->v_ce_iq, p->v_d_iq);
        vrec_from_legs(da, db, dc, &fa, &fb);
        *v_f_alpha_iq = fix_sub32(fix_neg32(fa), iq_mpy(p->r_on_iq, i->i_alpha_iq));
        *v_f_beta_iq = fix_sub32(fix_neg32(fb), iq_mpy(p->r_on_iq, i->i_beta_iq));
        break;
    case DTC_COMP_FSTP_SIMPLE:
        /* Hoang Table V = eqs. 35-36: legs B and C, V_f, no leg-A device. */
        db = vcomp_leg_drop_lin(sb, i0->ib_iq, i1->ib_iq, p->v_f_iq, p->v_f_iq);
        dc = vcomp_leg_drop_lin(sc, i0->ic_iq, i1->ic_iq, p->v_f_iq, p->v_f_iq);
        *v_f_alpha_iq = q31_mul_k(fix_add32(db, dc), VREC_THIRD_Q31);          /* Hoang eq. 33 */
        *v_f_beta_iq = q31_mul_k(fix_sub32(dc, db), VREC_INV_SQRT3_Q31);       /* Hoang eq. 34 */
        break;
    case DTC_COMP_FSTP_PROPOSED:
        /* Hoang Table VI = Table III per leg + eqs. 33-34, plus the R_on terms (eqs. 37-38; see the
         * header for the sign of the alpha term). */
        db = vcomp_leg_drop_lin(sb, i0->ib_iq, i1->ib_iq, p->v_ce_iq, p->v_d_iq);
        dc = vcomp_leg_drop_lin(sc, i0->ic_iq, i1->ic_iq, p->v_ce_iq, p->v_d_iq);
        fa = q31_mul_k(fix_add32(db, dc), VREC_THIRD_Q31);                     /* Hoang eq. 33 */
        fb = q31_mul_k(fix_sub32(dc, db), VREC_INV_SQRT3_Q31);                 /* Hoang eq. 34 */
        *v_f_alpha_iq = fix_sub32(fa, iq_mpy(p->r_on_third_iq, i->i_alpha_iq));
        *v_f_beta_iq = fix_sub32(fb, iq_mpy(p->r_on_iq, i->i_beta_iq));
        break;
    default: /* DTC_COMP_NONE */
        *v_f_alpha_iq = 0;
        *v_f_beta_iq = 0;
        break;
    }
}

void vcomp_tab_init(vcomp_tab_t *t, const vcomp_params_t *p)
{
    vcomp_params_t p0 = *p;
    uint16_t k;
    p0.r_on_iq = 0;
    p0.r_on_third_iq = 0;
    for (k = 0U; k < 8U; k++) {
        clarke_out_t i0;
        i0.ia_iq = (k & 1U) != 0U ? -1 : 0;
        i0.ib_iq = (k & 2U) != 0U ? -1 : 0;
        i0.ic_iq = (k & 4U) != 0U ? -1 : 0;
        i0.i_alpha_iq = 0;
        i0.i_beta_iq = 0;
        vcomp_step(&p0, 0U, 0U, 0U, &i0, &t->va_iq[k], &t->vb_iq[k >> 1]); /* beta: the same for k and k ^ 1 */
    }
    switch (p->mode) {
    case DTC_COMP_SSTP:
    case DTC_COMP_SSTP_PROPOSED:
        t->ka_iq = p->r_on_iq;
        t->kb_iq = p->r_on_iq;
        break;
    case DTC_COMP_FSTP_PROPOSED:
        t->ka_iq = p->r_on_third_iq;
        t->kb_iq = p->r_on_iq;
        break;
    default: /* NONE, FSTP_SIMPLE: no R_on term */
        t->ka_iq = 0;
        t->kb_iq = 0;
        break;
    }
    t->legs_free = (uint16_t)(p->mode == DTC_COMP_SSTP_PROPOSED || p->mode == DTC_COMP_FSTP_PROPOSED ? 0U : 1U);
}
