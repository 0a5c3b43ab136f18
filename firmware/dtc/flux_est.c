#include "flux_est.h"

#include "dtc_config.h"
#include "dtc_refs.h"
#include "lpfcorr.h"

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

void flux_est_vm_step(flux_est_t *s, const flux_est_in_t *in, iq_t ri_alpha_iq, iq_t ri_beta_iq)
{
    const flux_est_params_t *p = s->p;
    /* Hoang eqs. 15-16 (31-32, 37-38 with the compensation already in v), low-pass; the
     * gain/phase correction on its input (lpfcorr.h). */
    iq_t e_a = fix_sub32(in->v_alpha_iq, ri_alpha_iq);
    iq_t e_b = fix_sub32(in->v_beta_iq, ri_beta_iq);

    s->theta_e = flux_est_angle(in->enc_count, p->enc_gain_q16, p->enc_offset);
    lpfcorr_rotate(in->r_iq, &e_a, &e_b); /* r = 0: unchanged */
    s->psi_alpha_iq = flux_est_lpf(s->psi_alpha_iq, e_a, p->k_in_q31, p->k_leak_q31);
    s->psi_beta_iq = flux_est_lpf(s->psi_beta_iq, e_b, p->k_in_q31, p->k_leak_q31);
}
