#include "flux_est.h"

#include "dtc_config.h"

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
    s->u_alpha_iq = 0;
    s->u_beta_iq = 0;
}

/* Hoang eqs. 8-9 into the state. */
static void flux_est_current_model(flux_est_t *s, const flux_est_in_t *in)
{
    const flux_est_params_t *p = s->p;
    s->psi_alpha_iq = fix_add32(iq_mpy(p->ls_iq, in->i_alpha_iq),
                                iq_mpy_q15(p->psi_m_iq, fix_cos(s->theta_e)));
    s->psi_beta_iq = fix_add32(iq_mpy(p->ls_iq, in->i_beta_iq),
                               iq_mpy_q15(p->psi_m_iq, fix_sin(s->theta_e)));
}

/* Voltage model guided by the current model (encoder fitted; docs/firmware-core.md):
 *   d psi/dt = e + 2 w_c (psi_cm - psi) + U,   dU/dt = w_c^2 (psi_cm - psi)
 * i.e. psi = [s^2/(s + w_c)^2] (e/s) + [(2 w_c s + w_c^2)/(s + w_c)^2] psi_cm: the integrator of
 * Hoang eqs. 15-16 above w_c, the current model (eqs. 8-9) below it, with no gain or phase error
 * at any speed when both models agree, and a DC voltage error b rejected (the integral state
 * settles at U = -b, so no DC flux offset and no DC phase current). Discretised with
 * a = k_leak = 1 - exp(-w_c Ts) ~ w_c Ts and the state U' = U Ts / a (so its increment a d
 * stays well above one LSB): psi += k_in e + 2 a d + a U',  U' += a d,  d = psi_cm - psi.
 * Scaling and overflow: each product is a rounded Q31 x IQ multiply (64-bit), sums saturate. */
static void flux_est_guided(flux_est_t *s, const flux_est_in_t *in, iq_t e_a, iq_t e_b)
{
    const flux_est_params_t *p = s->p;
    iq_t da = fix_sub32(fix_add32(iq_mpy(p->ls_iq, in->i_alpha_iq),
                                  iq_mpy_q15(p->psi_m_iq, fix_cos(s->theta_e))),
                        s->psi_alpha_iq);
    iq_t db = fix_sub32(fix_add32(iq_mpy(p->ls_iq, in->i_beta_iq),
                                  iq_mpy_q15(p->psi_m_iq, fix_sin(s->theta_e))),
                        s->psi_beta_iq);
    iq_t ada = q31_mul(da, p->k_leak_q31), adb = q31_mul(db, p->k_leak_q31);
    s->psi_alpha_iq = fix_add32(fix_add32(s->psi_alpha_iq, q31_mul(e_a, p->k_in_q31)),
                                fix_add32(fix_add32(ada, ada), q31_mul(s->u_alpha_iq, p->k_leak_q31)));
    s->psi_beta_iq = fix_add32(fix_add32(s->psi_beta_iq, q31_mul(e_b, p->k_in_q31)),
                               fix_add32(fix_add32(adb, adb), q31_mul(s->u_beta_iq, p->k_leak_q31)));
    s->u_alpha_iq = fix_add32(s->u_alpha_iq, ada);
    s->u_beta_iq = fix_add32(s->u_beta_iq, adb);
}

void flux_est_seed(flux_est_t *s, const flux_est_in_t *in)
{
    s->theta_e = flux_est_angle(in->enc_count, s->p->enc_gain_q16, s->p->enc_offset);
    flux_est_current_model(s, in);
}

void flux_est_step(flux_est_t *s, const flux_est_in_t *in)
{
    const flux_est_params_t *p = s->p;

    s->theta_e = flux_est_angle(in->enc_count, p->enc_gain_q16, p->enc_offset);
    if (p->estimator == DTC_EST_CURRENT) {
        flux_est_current_model(s, in);
    } else {
        /* Hoang eqs. 15-16 (31-32, 37-38 with the compensation already in v), low-pass. */
        iq_t e_a = fix_sub32(in->v_alpha_iq, iq_mpy(p->rs_iq, in->i_alpha_iq));
        iq_t e_b = fix_sub32(in->v_beta_iq, iq_mpy(p->rs_iq, in->i_beta_iq));
        if (p->cm_guide != 0U) {
            flux_est_guided(s, in, e_a, e_b);
        } else {
            s->psi_alpha_iq = flux_est_lpf(s->psi_alpha_iq, e_a, p->k_in_q31, p->k_leak_q31);
            s->psi_beta_iq = flux_est_lpf(s->psi_beta_iq, e_b, p->k_in_q31, p->k_leak_q31);
        }
    }
}
