#include "vcomp.h"

#include "dtc_config.h"
#include "vrec.h"

void vcomp_init(vcomp_params_t *p, uint16_t mode, iq_t v_f_iq, iq_t v_ce_iq, iq_t v_d_iq,
                iq_t r_on_iq)
{
    /* the SSTP schemes share one code path: [29] is Table III with V_CE = V_d = V_f; Hoang
     * Table V is the same with V_f on legs B and C */
    const uint16_t equal = (uint16_t)(mode == DTC_COMP_SSTP || mode == DTC_COMP_FSTP_SIMPLE ? 1U : 0U);
    const iq_t vce = equal != 0U ? v_f_iq : v_ce_iq, vd = equal != 0U ? v_f_iq : v_d_iq;
    uint16_t s, n, j;
    p->mode = mode;
    for (s = 0U; s < 2U; s++) {
        const iq_t dp = vcomp_leg_drop(s, 0, vce, vd), dm = vcomp_leg_drop(s, -1, vce, vd);
        p->mean_iq[s][0] = dm;
        p->mean_iq[s][4] = dp;
        for (n = 1U; n < 4U; n++) {
            /* 4 - n points with i < 0, then n with i >= 0: a saturating sum (no partial sum can
             * saturate for drops below 2^29, 32 pu) shifted right by 2 with rounding */
            int32_t sum = 0;
            for (j = 0U; j < 4U; j++) {
                sum = fix_add32(sum, j < 4U - n ? dm : dp);
            }
            p->mean_iq[s][n] = fix_rshift_rnd32(sum, 2U);
        }
    }
    switch (mode) {
    case DTC_COMP_SSTP:
    case DTC_COMP_SSTP_PROPOSED:
        p->ka_iq = r_on_iq; /* Hoang eqs. 24-25 */
        p->kb_iq = r_on_iq;
        break;
    case DTC_COMP_FSTP_PROPOSED:
        p->ka_iq = q31_mul(r_on_iq, VREC_THIRD_Q31); /* Hoang eqs. 37-38 (alpha: see vcomp.h) */
        p->kb_iq = r_on_iq;
        break;
    default: /* NONE, FSTP_SIMPLE (Hoang Table V is the forward drop alone) */
        p->ka_iq = 0;
        p->kb_iq = 0;
        break;
    }
}

/* vcomp.h vcomp_leg_drop_lin, a period whose current crosses zero: how many of the four points
 * have i >= 0. Point j is i0 + (i1 - i0)(2j + 1)/8; its sign is that of p_j = (7 - 2j) i0 +
 * (2j + 1) i1 (8 times the point), formed as p_0 = 7 i0 + i1 and p_(j+1) = p_j + 2 (i1 - i0).
 * Formats and overflow: IQ pu, 32 bits. i0 and i1 have opposite signs here, so for |i0|, |i1| <
 * 2^28 (16 pu) every p_j lies within 7 * 2^28 < 2^31 and 2 (i1 - i0) within 2^30: the points are
 * exact. A current at or beyond 16 pu (never measured: the over-current trip is far below) takes
 * both currents 4 bits shorter first (rounded shift; the ratio that places the crossing is kept,
 * a point within 2^4 x 8 LSB of zero may take the other polarity). No multiplication beyond the
 * constant 7, no division. */
uint16_t vcomp_points_pos(iq_t i0_iq, iq_t i1_iq)
{
    const int32_t lim = (int32_t)1 << 28;
    int32_t a = i0_iq, b = i1_iq, pt, step;
    uint16_t n = 0U, j;
    if (a <= -lim || a >= lim || b <= -lim || b >= lim) {
        a = fix_rshift_rnd32(a, 4U);
        b = fix_rshift_rnd32(b, 4U);
    }
    pt = (int32_t)7 * a + b;
    step = (b - a) * (int32_t)2;
    for (j = 0U; j < 4U; j++) {
        n = (uint16_t)(n + (pt >= 0 ? 1U : 0U));
        pt += step;
    }
    return n;
}

void vcomp_step_lin(const vcomp_params_t *p, uint16_t sa, uint16_t sb, uint16_t sc, const clarke_out_t *i,
                    const clarke_out_t *i0, const clarke_out_t *i1, iq_t *v_f_alpha_iq, iq_t *v_f_beta_iq)
{
    iq_t fa, fb;

    if (p->mode == DTC_COMP_NONE) {
        *v_f_alpha_iq = 0;
        *v_f_beta_iq = 0;
        return;
    }
    vcomp_fwd_lin(p, sa, sb, sc, i0, i1, &fa, &fb);
    vcomp_ron(p, i, fa, fb, v_f_alpha_iq, v_f_beta_iq);
}

void vcomp_tab_init(vcomp_tab_t *t, const vcomp_params_t *p)
{
    vcomp_params_t p0 = *p;
    uint16_t k;
    p0.ka_iq = 0;
    p0.kb_iq = 0;
    for (k = 0U; k < 8U; k++) {
        clarke_out_t i0;
        i0.ia_iq = (k & 1U) != 0U ? -1 : 0;
        i0.ib_iq = (k & 2U) != 0U ? -1 : 0;
        i0.ic_iq = (k & 4U) != 0U ? -1 : 0;
        i0.i_alpha_iq = 0;
        i0.i_beta_iq = 0;
        vcomp_step(&p0, 0U, 0U, 0U, &i0, &t->va_iq[k], &t->vb_iq[k >> 1]); /* beta: the same for k and k ^ 1 */
    }
    t->ka_iq = p->ka_iq;
    t->kb_iq = p->kb_iq;
    t->legs_free = (uint16_t)(p->mode == DTC_COMP_SSTP_PROPOSED || p->mode == DTC_COMP_FSTP_PROPOSED ? 0U : 1U);
}

void vcomp_pt_init(vcomp_pt_t *t, const vcomp_params_t *p)
{
    uint16_t k;
    t->ok = (uint16_t)(p->mode == DTC_COMP_FSTP_SIMPLE || p->mode == DTC_COMP_FSTP_PROPOSED ? 1U : 0U);
    for (k = 0U; k < 16U; k++) {
        clarke_out_t i0;
        i0.ia_iq = 0;
        i0.ib_iq = (k & 4U) != 0U ? -1 : 0;
        i0.ic_iq = (k & 1U) != 0U ? -1 : 0;
        i0.i_alpha_iq = 0;
        i0.i_beta_iq = 0;
        if (t->ok != 0U) {
            /* vcomp_fwd_lin: vcomp_step at i_alpha = i_beta = 0, whose R_on terms are 0 */
            vcomp_step(p, 0U, (uint16_t)((k >> 3) & 1U), (uint16_t)((k >> 1) & 1U), &i0, &t->fa_iq[k], &t->fb_iq[k]);
        } else {
            t->fa_iq[k] = 0;
            t->fb_iq[k] = 0;
        }
    }
}
