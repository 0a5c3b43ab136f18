#include "im_est.h"

#include "flux_est.h"

int16_t im_est_check(const im_est_params_t *p)
{
    if (p->estimator != IM_EST_VOLTAGE && p->estimator != IM_EST_IMPROVED) {
        return 1;
    }
    if (p->rs_iq < 0 || p->sigma_ls_iq < 0 || p->kr_iq <= 0 || p->ts_pu_q31 <= 0) {
        return 2;
    }
    if (p->k_in_q31 < 0 || p->k_leak_q31 < 0 || p->k_lo_q31 < 0 || p->k_hi_q31 < 0) {
        return 3;
    }
    if (p->w_lo_iq < 0 || p->w_hi_iq < p->w_lo_iq) {
        return 4;
    }
    return 0;
}

void im_est_init(im_est_t *s, const im_est_params_t *p)
{
    s->p = p;
    im_est_reset(s);
}

void im_est_reset(im_est_t *s)
{
    s->psi_alpha_iq = 0;
    s->psi_beta_iq = 0;
    s->psir_alpha_iq = 0;
    s->psir_beta_iq = 0;
    s->psir_mag_iq = 0;
    s->theta_r = 0U;
}

q31_t im_est_gain(const im_est_params_t *p, iq_t speed_iq)
{
    /* Section 10.2: tau may depend on speed. Piecewise linear in |w|; the slope is the host's. */
    const iq_t w = fix_abs32(speed_iq);
    if (w <= p->w_lo_iq) {
        return p->k_lo_q31;
    }
    if (w >= p->w_hi_iq) {
        return p->k_hi_q31;
    }
    /* (w - w_lo) < 2^31 (IQ) times the Q31 slope: a Q55 product in 64 bits, back to Q31. */
    return fix_add32(p->k_lo_q31,
                     fix_rshift_rnd64_sat32((int64_t)(w - p->w_lo_iq) * (int64_t)p->k_slope_q31,
                                            (uint16_t)FIX_IQ_Q));
}

void im_est_step(im_est_t *s, const im_est_in_t *in)
{
    const im_est_params_t *p = s->p;
    /* Casadei eq. 1: the stator EMF over the period. */
    const iq_t e_a = fix_sub32(in->v_alpha_iq, iq_mpy(p->rs_iq, in->i_alpha_iq));
    const iq_t e_b = fix_sub32(in->v_beta_iq, iq_mpy(p->rs_iq, in->i_beta_iq));
    iq_t x_a, x_b;

    if (p->estimator == IM_EST_IMPROVED) {
        /* Casadei eq. 20, with the correction phi_r* e^{j theta} - phi_r of the previous
         * instant (eqs. 21-22 evaluated at the end of the previous step). */
        const q31_t k = im_est_gain(p, in->speed_iq);
        const iq_t c_a = fix_sub32(iq_mpy_q15(in->psir_ref_iq, fix_cos(s->theta_r)), s->psir_alpha_iq);
        const iq_t c_b = fix_sub32(iq_mpy_q15(in->psir_ref_iq, fix_sin(s->theta_r)), s->psir_beta_iq);
        const int64_t d_a = (int64_t)p->ts_pu_q31 * (int64_t)e_a + (int64_t)k * (int64_t)c_a;
        const int64_t d_b = (int64_t)p->ts_pu_q31 * (int64_t)e_b + (int64_t)k * (int64_t)c_b;
        s->psi_alpha_iq = fix_add32(s->psi_alpha_iq, fix_rshift_rnd64_sat32(d_a, 31U));
        s->psi_beta_iq = fix_add32(s->psi_beta_iq, fix_rshift_rnd64_sat32(d_b, 31U));
    } else {
        s->psi_alpha_iq = flux_est_lpf(s->psi_alpha_iq, e_a, p->k_in_q31, p->k_leak_q31);
        s->psi_beta_iq = flux_est_lpf(s->psi_beta_iq, e_b, p->k_in_q31, p->k_leak_q31);
    }
    /* Casadei eqs. 21-22. */
    x_a = fix_sub32(s->psi_alpha_iq, iq_mpy(p->sigma_ls_iq, in->i_alpha_iq));
    x_b = fix_sub32(s->psi_beta_iq, iq_mpy(p->sigma_ls_iq, in->i_beta_iq));
    fix_polar(x_a, x_b, &s->theta_r, &s->psir_mag_iq);
    s->psir_mag_iq = iq_mpy(p->kr_iq, s->psir_mag_iq);
    s->psir_alpha_iq = iq_mpy(p->kr_iq, x_a);
    s->psir_beta_iq = iq_mpy(p->kr_iq, x_b);
}
