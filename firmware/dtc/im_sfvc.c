/*
 * im_sfvc.c - stator-flux vector control of the induction machine (Casadei et al. 2006 sections
 * 10.3-10.5, Fig. 18): the law DTC_LAW_IM_SFVC of the IM module (im_dtc.h), one im_sfvc_step()
 * per control period, which is also the SVM carrier period (one centred pulse per leg, svm.h).
 *
 *   Clarke -> stator voltage of the period that ends now (the duties returned two steps ago as
 *      the SVM expects them to act, d_eff, on the V_dc measured when they were made) + the
 *      device-drop compensation
 *   -> stator and rotor flux (improved or voltage-model estimator, im_est.h), torque (Casadei eq. A10)
 *   -> speed and speed PI, start-up magnetisation, references (shared with im_dtc_step)
 *   -> stator-flux reference vector, Casadei eq. 18 in the rotor-flux frame at constant rotor
 *      flux (the s sigma tau_r phi_r term is zero):
 *        phi_s* = (l_s/m) (phi_r* + j sigma l_r T* / phi_r*)                     (Casadei eq. 18, pu)
 *      with the rotor-flux trim added to phi_r* in the d component (im_psir_trim: the estimate's
 *      mean |phi_r| held at phi_r*, so that Casadei eq. 20's correction has no mean)
 *      turned into the stator frame by the rotor-flux direction e^{j theta} of eq. 22 (im_est's
 *      unit vector); during the start-up magnetisation phi_s* = (ramp) e^{j theta} at T* = 0
 *   -> the flux regulator, Casadei eqs. 23-24:
 *        Delta phi_s = phi_s* - phi_s                                            (Casadei eq. 23)
 *        v_s* = R_s i_s + j w_s phi_s + K_p Delta phi_s                          (eq. 24)
 *      made to act in the period the command is applied in (the one-period delay of hal.h):
 *      phi_s is the estimate predicted for the start of that period, phi_s(k+1) = phi_s(k) +
 *      Ts (v(k) - R_s i(k)) with v(k) the voltage of the duties returned by the previous step
 *      (the stator-voltage equation, Casadei eq. A6 / eq. 1, forward Euler over one period), and
 *      phi_s* is advanced to k+1 by the rotation w_s Ts, (1 + j w_s Ts) phi_s*(k) (iq_cmul_1jx).
 *      With K_p Ts = 1 the flux error left after the period is zero (deadbeat): phi_s(k+2) =
 *      phi_s*(k+1) + j w_s Ts phi_s(k+1), the reference two periods on. The back-EMF term uses
 *      w_s, the stator-flux angular speed, = w + w_slip in the steady state, the slip from Casadei eq. 16
 *      with the references (w_slip = r_r T* / phi_r*^2, im_ref_slip).
 *   -> SVM (svm.h) of v_s* on the measured V_dc with dead-time compensation by the current
 *      sign (sec. 10.5), the PWM form in dtc_out_t.
 * The device drops (vcomp.h) are compensated in the estimator's voltage, not in v_s*: the flux
 * regulator's proportional term takes up the difference.
 *
 * Formats: IQ pu (dtc_base.h), the duties IQ in [0, 1]; K_p in pu voltage per pu flux (K_p /
 * w_base), Ts as ts_pu = Ts w_base.
 * Scaling and overflow: rounded IQ products (iq_mpy, and iq_mac2 for the two-term sums of
 * products, rounded once) and saturating sums; the reference's
 * magnitude is l_s/m |phi_r*| sqrt(1 + (sigma l_r T* / phi_r*^2)^2), a few pu at the torque limit;
 * v_s* is at most R_s |i| + |w_s||phi_s| + K_p |Delta phi_s| (K_p <= 1/ts_pu: 64 pu at 50 us and
 * 50 Hz base), saturating; the SVM clamps it onto its hexagon (svm.h).
 */
#include "im_dtc_internal.h"


/* Casadei Eqs. 18, 23, 24 (file comment) into c->vs_alpha_iq, c->vs_beta_iq. Eq. 24 is evaluated with K_p
 * distributed, v_s* = R_s i + (j w_s - K_p) phi_s + K_p phi_s*, so that K_p phi_s* comes from the
 * products K_p (l_s/m) phi_r* and K_p (l_s/m) sigma l_r / phi_r* made at init. */
void im_sfvc_regulate(im_dtc_t *c)
{
    const dtc_config_t *cfg = c->cfg;
    const iq_t ts = cfg->board.ts_pu_iq;
    const iq_t kp = cfg->u.im.sfvc.kp_iq;
    iq_t ws;

    /* w_s = w + w_slip (Casadei eq. 16), w_s Ts, and Casadei eq. 18's q component times K_p */
    im_svm_rate(c, c->sfvc_kpq_iq, 0U);
    ws = c->sr_ws_iq;
    /* K_p phi_s*: Casadei eq. 18 in the rotor-flux frame (d along phi_r), turned by e^{j theta}
     * (eq. 22), formed in c->vs_* (not on this frame, which the rotation's call would keep) */
    {
        iq_t d, q;
        if (c->magnetised == 0U) {
            d = iq_mpy(kp, c->psi_ref_iq); /* the start-up ramp, radial, T* = 0 */
            q = 0;
        } else {
            d = c->sfvc_kpd_iq;
            q = c->sr_gt_iq;
        }
        c->vs_alpha_iq = iq_mac2(d, c->est.u_alpha_iq, fix_neg32(q), c->est.u_beta_iq);
        c->vs_beta_iq = iq_mac2(d, c->est.u_beta_iq, q, c->est.u_alpha_iq);
    }
    /* the reference advanced by w_s Ts to k+1 (inline: a leaf, no call on its chain) */
    iq_cmul_1jx_inline(c->sr_adv_iq, &c->vs_alpha_iq, &c->vs_beta_iq);
    {
        /* R_s i: the estimator's product of this step (im_est_flux, the same r_s and i) */
        const iq_t ria = c->est.ri_alpha_iq, rib = c->est.ri_beta_iq;
        /* the flux predicted for k+1: the stator-voltage equation over the period under way */
        const iq_t pa = iq_add(c->est.psi_alpha_iq, iq_mpy(ts, iq_sub(iq_add(c->v1_alpha_iq, c->dva_iq), ria)));
        const iq_t pb = iq_add(c->est.psi_beta_iq, iq_mpy(ts, iq_sub(iq_add(c->v1_beta_iq, c->dvb_iq), rib)));
        /* Casadei eqs. 23-24: v_s* = R_s i + j w_s phi_s + K_p (phi_s* - phi_s) */
        c->vs_alpha_iq = iq_add(iq_sub(ria, iq_mac2(ws, pb, kp, pa)), c->vs_alpha_iq);
        c->vs_beta_iq = iq_add(iq_add(rib, iq_mac2(ws, pa, fix_neg32(kp), pb)), c->vs_beta_iq);
    }
}

void im_sfvc_step(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o)
{
    im_svm_scheme_step(c, m, o, 0U);
}
