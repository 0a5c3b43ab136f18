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
    s->u_alpha_iq = IQ(1.0);
    s->u_beta_iq = 0;
    s->inv_mag_iq = 0;
    s->k_valid = 0U;
    s->x_alpha_iq = 0;
    s->x_beta_iq = 0;
    s->ri_alpha_iq = 0;
    s->ri_beta_iq = 0;
    s->polar.xs = 0;
    s->polar.ys = 0;
    s->polar.turn = 0U;
    s->polar.shift = 0U;
}

/* |x| below which the direction is not resolved: 2^-6 pu, |x|^2 = 2^36 in Q48. */
#define IM_EST_MAG2_MIN ((uint64_t)1U << 36)

/* u = x r (Q24 x Q24 -> Q24, rounded, saturated); returns |u|^2 in Q30 (exact Q48 >> 18). */
static int64_t im_est_scale(iq_t x_a, iq_t x_b, iq_t r, iq_t *u_a, iq_t *u_b)
{
    *u_a = iq_mpy(x_a, r);
    *u_b = iq_mpy(x_b, r);
    return (int64_t)(iq_sumsq_q48(*u_a, *u_b) >> 18);
}

/* One Newton step for the inverse square root, r (3 - t) / 2, t in (1/4, 9/4) Q30, r IQ:
 * IQ x Q30 -> Q54, / 2 -> IQ by a rounded shift of 31 (the product < 2^31 * 2^32, saturated). */
static iq_t im_est_newton(iq_t r, int64_t t_q30)
{
    return fix_rshift_rnd64_sat32((int64_t)r * ((int64_t)3 * ((int64_t)1 << 30) - t_q30), 31U);
}

/* e^{j theta} = x / |x| (Casadei eq. 22) by the tracked reciprocal (im_est.h). */
static void im_est_unit(im_est_t *s, iq_t x_a, iq_t x_b)
{
    const int64_t lo = (int64_t)1 << 28, hi = (int64_t)9 << 28; /* 1/4 and 9/4 in Q30 */
    const int64_t one = (int64_t)1 << 30, tol = (int64_t)1 << 10; /* 1 and 2^-20 in Q30 */
    const int64_t near = (int64_t)1 << 24;                        /* 2^-6 in Q30 */
    int64_t t = 0;
    uint16_t k;

    /* Tracking: the previous r, while it is known and at most 64 (then |x| > 2^-7 pu). */
    if (s->inv_mag_iq > 0 && s->inv_mag_iq <= IQ(64.0)) {
        t = im_est_scale(x_a, x_b, s->inv_mag_iq, &s->u_alpha_iq, &s->u_beta_iq);
    }
    if (!(t > lo && t < hi)) {
        const uint64_t m2 = iq_sumsq_q48(x_a, x_b);
        uint64_t v = m2;
        uint16_t n = 0U;
        if (m2 < IM_EST_MAG2_MIN) {
            s->u_alpha_iq = IQ(1.0);
            s->u_beta_iq = 0;
            s->inv_mag_iq = 0;
            return;
        }
        /* Re-seed: |x| in [2^n, 2^(n+1)) LSB (n >= 18 here), r = 2^(23-n) pu = 2^(47-n) in IQ,
         * so |x r| in [1/2, 1): t in [1/4, 1), from which Newton rises monotonically to 1
         * (within 2^-20 after six steps). */
        while (v >= 4U) {
            v >>= 2;
            ++n;
        }
        s->inv_mag_iq = (iq_t)((uint32_t)1U << (47U - n));
        t = im_est_scale(x_a, x_b, s->inv_mag_iq, &s->u_alpha_iq, &s->u_beta_iq);
    }
    for (k = 0U; k < 8U; ++k) {
        uint16_t small;
        if (t > one - tol && t < one + tol) {
            break; /* |x r|^2 within 2^-20 of 1 (u = x r in use) */
        }
        small = (uint16_t)(t > one - near && t < one + near ? 1U : 0U);
        s->inv_mag_iq = im_est_newton(s->inv_mag_iq, t);
        t = im_est_scale(x_a, x_b, s->inv_mag_iq, &s->u_alpha_iq, &s->u_beta_iq);
        if (small != 0U) {
            /* |x| had moved by less than 1/128 since r was last refined: this one step leaves
             * |t - 1| < 2^-12, and the next periods' steps refine it while |x| holds */
            break;
        }
    }
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

void im_est_flux(im_est_t *s, const im_est_in_t *in)
{
    const im_est_params_t *p = s->p;
    /* Casadei eq. 1: the stator EMF over the period. */
    const iq_t ri_a = iq_mpy(p->rs_iq, in->i_alpha_iq);
    const iq_t ri_b = iq_mpy(p->rs_iq, in->i_beta_iq);
    const iq_t e_a = fix_sub32(in->v_alpha_iq, ri_a);
    const iq_t e_b = fix_sub32(in->v_beta_iq, ri_b);
    iq_t x_a, x_b;

    s->ri_alpha_iq = ri_a;
    s->ri_beta_iq = ri_b;

    if (p->estimator == IM_EST_VOLTAGE && in->start == 0U) {
        s->psi_alpha_iq = flux_est_lpf(s->psi_alpha_iq, e_a, p->k_in_q31, p->k_leak_q31);
        s->psi_beta_iq = flux_est_lpf(s->psi_beta_iq, e_b, p->k_in_q31, p->k_leak_q31);
    } else {
        /* Casadei eq. 20, with the correction phi_r* e^{j theta} - phi_r of the previous
         * instant (eqs. 21-22 evaluated at the end of the previous step; e^{j theta} = x/|x|). */
        q31_t k;
        if (s->k_valid == 0U || (in->speed_iq != s->k_speed_iq && p->k_hi_q31 != p->k_lo_q31)) {
            /* the speed changes at the speed-loop rate; with k_hi = k_lo (one tau at every speed) the
             * gain is the reset's for good */
            s->k_q31 = im_est_gain(p, in->speed_iq);
            s->k_speed_iq = in->speed_iq;
            s->k_valid = 1U;
        }
        k = s->k_q31;
        const iq_t r_a = in->ref_vec != 0U ? in->ref_alpha_iq : iq_mpy(in->psir_ref_iq, s->u_alpha_iq);
        const iq_t r_b = in->ref_vec != 0U ? in->ref_beta_iq : iq_mpy(in->psir_ref_iq, s->u_beta_iq);
        const iq_t c_a = fix_sub32(r_a, s->psir_alpha_iq);
        const iq_t c_b = fix_sub32(r_b, s->psir_beta_iq);
        const int64_t d_a = (int64_t)p->ts_pu_q31 * (int64_t)e_a + (int64_t)k * (int64_t)c_a;
        const int64_t d_b = (int64_t)p->ts_pu_q31 * (int64_t)e_b + (int64_t)k * (int64_t)c_b;
        s->psi_alpha_iq = fix_add32(s->psi_alpha_iq, fix_rshift_rnd64_sat32(d_a, 31U));
        s->psi_beta_iq = fix_add32(s->psi_beta_iq, fix_rshift_rnd64_sat32(d_b, 31U));
    }
    /* Casadei eqs. 21-22. */
    x_a = fix_sub32(s->psi_alpha_iq, iq_mpy(p->sigma_ls_iq, in->i_alpha_iq));
    x_b = fix_sub32(s->psi_beta_iq, iq_mpy(p->sigma_ls_iq, in->i_beta_iq));
    im_est_unit(s, x_a, x_b);
    s->x_alpha_iq = x_a;
    s->x_beta_iq = x_b;
    s->psir_alpha_iq = iq_mpy(p->kr_iq, x_a);
    s->psir_beta_iq = iq_mpy(p->kr_iq, x_b);
}

void im_est_step(im_est_t *s, const im_est_in_t *in)
{
    im_est_flux(s, in);
    if (in->want_polar != 0U) {
        im_est_polar(s);
    }
}
