/*
 * pm_salient.c - the PM laws' salient-machine terms (l_q != l_d): the current model's q-axis term
 * (flux_est.h) and the PM DTC law's actuation-delay prediction in the rotor frame (dtc.c
 * dtc_predict). In a file of their own so that no compiler inlines them into the surface PM's path
 * (l_q = l_d), which keeps its instructions: each is entered from one test of dl_iq != 0.
 */
#include "dtc.h"
#include "dtc_internal.h"
#include "flux_est.h"

/* A salient PM's q-axis excess of the current model (flux_est.h):
 * psi += (l_q - l_d) i_q j e^{j theta_e} (formats and overflow there); sn, cs: the current model's
 * sine and cosine of theta_e. */
void flux_est_cm_salient(flux_est_t *s, const flux_est_in_t *in, q15_t sn, q15_t cs)
{
    const iq_t t = iq_mpy(s->p->dl_iq, flux_est_park_q(in->i_alpha_iq, in->i_beta_iq, sn, cs));
    s->psi_alpha_iq = fix_sub32(s->psi_alpha_iq, iq_mpy_q15(t, sn));
    s->psi_beta_iq = fix_add32(s->psi_beta_iq, iq_mpy_q15(t, cs));
}

/* dtc_predict on a salient PM (l_q != l_d). In the rotor frame (angle theta_e) psi_d = l_d i_d +
 * psi_m, psi_q = l_q i_q (flux_est.h; Hoang eqs. 8-9 are its l_d = l_q case). Over one period the
 * stator flux moves by dpsi (Hoang eqs. 6-7, as dtc_predict) and the frame turns by w Ts, so the
 * rotor-frame flux moves by y = e^{-j theta} x, x = dpsi - j w Ts psi, and y = (l_d di_d, l_q di_q)
 * (psi_m is fixed in that frame); the current turns with the frame:
 *   i(k+1) = i + e^{j theta} (y_d / l_d, y_q / l_q) + j w Ts i.
 * dtc_predict's surface step i + (x + j w Ts l_s i) / l_s is this with l_q = l_d = l_s. theta_e is
 * the estimator's angle of this step (the encoder's); 1/l_d is the configuration's, 1/l_q formed at
 * init (dtc_init.c; no division here). Formats: IQ pu, Q15 sine and cosine; y of rounded Q15 projections, its two
 * components times the IQ inverses and projected back (rounded products, saturating sums: no wrap
 * for any input; the sine table's error, a few Q15 LSB, on |x| / l_d). dtc_step calls it in place
 * of dtc_predict when dl_iq != 0. */
void dtc_predict_salient(dtc_t *c, const clarke_out_t *i, iq_t *psi_a, iq_t *psi_b, iq_t *te)
{
    const dtc_pm_machine_cfg_t *m = &c->cfg->u.pm_dtc.machine;
    const iq_t wts = c->wts_iq;
    const q15_t sn = fix_sin(c->fe.theta_e), cs = fix_cos(c->fe.theta_e);
    iq_t dpa, dpb, xa, xb, dd, dq, ia1, ib1;

    dtc_predict_dpsi(c, &dpa, &dpb);
    xa = fix_add32(dpa, iq_mpy(wts, *psi_b)); /* x = dpsi - j w Ts psi */
    xb = fix_sub32(dpb, iq_mpy(wts, *psi_a));
    dd = iq_mpy(m->inv_ls_iq, fix_add32(iq_mpy_q15(xa, cs), iq_mpy_q15(xb, sn))); /* y_d / l_d */
    dq = iq_mpy(c->fe_p.inv_lq_iq, flux_est_park_q(xa, xb, sn, cs));                   /* y_q / l_q */
    /* i + e^{j theta} (dd, dq) + j w Ts i */
    ia1 = fix_add32(i->i_alpha_iq, fix_sub32(iq_mpy_q15(dd, cs), iq_mpy_q15(dq, sn)));
    ib1 = fix_add32(i->i_beta_iq, fix_add32(iq_mpy_q15(dd, sn), iq_mpy_q15(dq, cs)));
    dtc_predict_end(c, psi_a, psi_b, te, dpa, dpb, fix_sub32(ia1, iq_mpy(wts, i->i_beta_iq)),
                    fix_add32(ib1, iq_mpy(wts, i->i_alpha_iq)));
}
