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

/* Hoang eqs. 8-9 into the state; a salient PM's q-axis term after them. */
static void flux_est_current_model(flux_est_t *s, const flux_est_in_t *in)
{
    const flux_est_params_t *p = s->p;
    s->psi_alpha_iq = fix_add32(iq_mpy(p->ls_iq, in->i_alpha_iq),
                                iq_mpy_q15(p->psi_m_iq, fix_cos(s->theta_e)));
    s->psi_beta_iq = fix_add32(iq_mpy(p->ls_iq, in->i_beta_iq),
                               iq_mpy_q15(p->psi_m_iq, fix_sin(s->theta_e)));
    if (p->dl_iq != 0) {
        flux_est_cm_salient(s, in);
    }
}

void flux_est_seed(flux_est_t *s, const flux_est_in_t *in)
{
    s->theta_e = flux_est_angle(in->enc_count, s->p->enc_gain_q16, s->p->enc_offset);
    flux_est_current_model(s, in);
}

void flux_est_step(flux_est_t *s, const flux_est_in_t *in)
{
    const flux_est_params_t *p = s->p;

    if (p->estimator == DTC_EST_CURRENT) {
        s->theta_e = flux_est_angle(in->enc_count, p->enc_gain_q16, p->enc_offset);
        flux_est_current_model(s, in);
    } else {
        flux_est_vm_step(s, in, iq_mpy(p->rs_iq, in->i_alpha_iq), iq_mpy(p->rs_iq, in->i_beta_iq));
    }
}
