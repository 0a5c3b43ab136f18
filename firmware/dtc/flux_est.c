#include "flux_est.h"

#include "dtc_config.h"
#include "dtc_refs.h"

void flux_est_init(flux_est_t *s, const flux_est_params_t *p)
{
    s->p = p;
    flux_est_reset(s);
}

void flux_est_reset(flux_est_t *s)
{
    s->psi_alpha_iq = 0;
    s->psi_beta_iq = 0;
    s->theta_e = 0U;
}

/* Hoang eqs. 8-9 into the state (flux_est.h). psi_m cos and psi_m sin are iq_mpy_q15(psi_m, x)
 * written as iq_mpy(psi_m, iq_from_q15(x)), the same value bit for bit: iq_from_q15(x) = 512 x
 * exactly, and (512 y + 2^23) >> 24 = (512 (y + 2^14)) >> 24 = (y + 2^14) >> 15 for the product
 * y = psi_m x: the same shifted value, so the same rounding and the same saturation. On the Cortex-M0
 * (-Os) the inline 64-bit product, rounding and saturation held this function's frame at 48
 * bytes on dtc_step's deepest stack chain; four calls of the one product keep it small. */
void flux_est_cm_surface(flux_est_t *s, const flux_est_in_t *in, q15_t sn, q15_t cs)
{
    const flux_est_params_t *p = s->p;
    s->psi_alpha_iq = fix_add32(iq_mpy(p->ls_iq, in->i_alpha_iq), iq_mpy(p->psi_m_iq, iq_from_q15(cs)));
    s->psi_beta_iq = fix_add32(iq_mpy(p->ls_iq, in->i_beta_iq), iq_mpy(p->psi_m_iq, iq_from_q15(sn)));
}

void flux_est_seed(flux_est_t *s, const flux_est_in_t *in)
{
    q15_t sn, cs;
    s->theta_e = flux_est_angle(in->enc_count, s->p->enc_gain_q16, s->p->enc_offset);
    fix_sincos(s->theta_e, &sn, &cs);
    flux_est_cm(s, in, sn, cs);
}

void flux_est_step(flux_est_t *s, const flux_est_in_t *in)
{
    const flux_est_params_t *p = s->p;

    if (p->estimator == DTC_EST_CURRENT) {
        flux_est_seed(s, in);
    } else {
        flux_est_vm_step(s, in, iq_mpy(p->rs_iq, in->i_alpha_iq), iq_mpy(p->rs_iq, in->i_beta_iq));
    }
}
