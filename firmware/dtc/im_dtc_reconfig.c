/*
 * im_dtc_reconfig.c - live reconfiguration of the IM switching-table DTC from the six-switch to the
 * four-switch inverter after a leg failure (im_dtc.h im_dtc_reconfigure), as the PM law does it
 * (dtc_reconfig.c). Runs once, in the ISR that found the failure: built into the init-only
 * archive dtc_init, which the F2812 image keeps in flash (firmware/CMakeLists.txt).
 */
#include "im_dtc_internal.h"

#include <stddef.h>

#include "clarke.h"
#include "svm.h"

/* What is frame-free carries over: the speed measurement and the sensorless speed's filters, the
 * speed PI and its integrator, the references, the torque trim, the start-up's progress, the
 * model supervision. The flux estimate's vectors (Casadei eqs. 1, 20-22: phi_s, phi_r, x, the unit
 * vector e^{j theta}, r_s i) are turned into the new frame (clarke_rot_phase), the rotor-flux
 * angle and the sensorless speed's previous angle by -x 120 deg (clarke_phase_angle), so the
 * estimator and Casadei eq. 22's speed go on from the same flux; the leg history is taken into the
 * new frame (b', c' = the legs x+1, x+2; leg x is off); the comparators restart with post's bands;
 * the drop and dead-time compensations and the current limit take the FSTP's parameters. The
 * flux the FSTP's voltage holds (post's references, Casadei eq. 19) takes effect through post:
 * a stator-flux reference in force above post's is brought down to it, and Casadei eq. 19 is
 * evaluated again on the next step; the estimator's rotor-flux reference (Casadei eq. 20) follows
 * the machine's rotor flux by the current model down to post's (im_dtc_fstp.c im_fstp_psir_fall:
 * the flux is not regulated while phase A' is open, and a reference away from the machine's flux
 * pulls the estimate off it). The estimate's alpha part is taken again (im_reseed_alpha). */
/* The estimate's alpha part (the failed phase's axis, after the turn into its frame) taken again
 * from the beta part and the rotor flux's magnitude. Between the leg's failure and its detection
 * the six-switch estimator integrated the voltage the law commanded on that leg, while the open
 * phase's terminal floated at the machine's EMF. That voltage enters alpha alone in the failed
 * phase's frame (Hoang eqs. 4-5: v_alpha = (2/3)(v_a0 - (v_b0 + v_c0)/2), v_beta = (v_b0 - v_c0)
 * / sqrt3); the current is measured, so beta is right and alpha carries the integral of the
 * error (SIL, 4 kW IM at 1000 rpm, leg C: the estimated |phi_s| 0.55 Wb against the machine's
 * 0.41 Wb at the detection, 5 ms after the failure, the estimated torque 34 N*m against 14). The
 * rotor flux's magnitude moves with tau_r (0.13 s on that machine), so the estimator's
 * rotor-flux reference from before the failure (psir_ref, Casadei eq. 20) stands for it:
 * x = (m/l_r) phi_r (Casadei eq. 21), x_alpha = +-sqrt(|x|^2 - x_beta^2) with the sign of the
 * estimate's x_alpha (0 where |x_beta| >= |x|), and the open phase carries no current, i_alpha =
 * 0, so phi_s,alpha = x_alpha and phi_r,alpha = (l_r/m) x_alpha; the unit vector is formed again
 * on the next step (inv_mag = 0). Formats: IQ pu; rounded products, iq_sqrt of a non-negative
 * difference of squares (|x| < 2 pu), the reciprocal of l_r/m by the SVM's Newton reciprocal. */
static void im_reseed_alpha(im_est_t *e, iq_t psir_ref_iq, const dtc_config_t *post)
{
    const iq_t xm = iq_mpy(psir_ref_iq, svm_recip(0, post->u.im.machine.kr_iq));
    iq_t xa = iq_sqrt(iq_sub(iq_mpy(xm, xm), iq_mpy(e->x_beta_iq, e->x_beta_iq)));
    if (e->x_alpha_iq < 0) {
        xa = fix_neg32(xa);
    }
    e->x_alpha_iq = xa;
    e->psi_alpha_iq = xa;
    e->psir_alpha_iq = iq_mpy(post->u.im.machine.kr_iq, xa);
    e->inv_mag_iq = 0;
}

int16_t im_dtc_reconfigure(im_dtc_t *c, const dtc_config_t *post, uint16_t phase)
{
    const angle_t d = clarke_phase_angle(phase);
    im_est_t *e = &c->est;

    if (phase > 2U || post == NULL || c->cfg == NULL || c->cfg->law != DTC_LAW_IM_DTC ||
        c->cfg->board.topology != DTC_TOPO_SSTP || post->law != DTC_LAW_IM_DTC ||
        post->board.topology != DTC_TOPO_FSTP || im_dtc_check(post, NULL) != DTC_OK) {
        return DTC_ERR_RECONFIG;
    }
    swtab_legs_permute(&c->legs_1, phase);
    swtab_legs_permute(&c->legs_2, phase);
    swtab_legs_permute(&c->legs_3, phase);
    clarke_rot_phase(&e->psi_alpha_iq, &e->psi_beta_iq, phase);
    clarke_rot_phase(&e->psir_alpha_iq, &e->psir_beta_iq, phase);
    clarke_rot_phase(&e->u_alpha_iq, &e->u_beta_iq, phase);
    clarke_rot_phase(&e->x_alpha_iq, &e->x_beta_iq, phase);
    clarke_rot_phase(&e->ri_alpha_iq, &e->ri_beta_iq, phase);
    e->theta_r = (angle_t)(e->theta_r - d);
    {
        /* the previous sample (the dead time's current signs) in the new phase order and frame */
        const iq_t ip[3] = {c->i_prev.ia_iq, c->i_prev.ib_iq, c->i_prev.ic_iq};
        c->i_prev.ia_iq = ip[phase];
        c->i_prev.ib_iq = ip[phase == 2U ? 0U : phase + 1U];
        c->i_prev.ic_iq = ip[phase == 0U ? 2U : phase - 1U];
        clarke_rot_phase(&c->i_prev.i_alpha_iq, &c->i_prev.i_beta_iq, phase);
    }
    c->isp.theta_prev = (angle_t)(c->isp.theta_prev - d);
    if (c->magnetised != 0U) {
        im_reseed_alpha(e, c->psir_ref_iq, post);
    }

    c->cfg = post;
    vcomp_init(&c->vc_p, post->est.compensation, post->board.v_f_iq, post->board.v_ce_iq, post->board.v_d_iq,
               post->board.r_on_iq);
    vcomp_tab_init(&c->vc_t, &c->vc_p);
    c->dt_p.td_ts_q15 = post->board.td_ts_q15;
    c->dt_p.fstp = 1U;
    c->il_p.i_lim_iq = post->prot.i_lim_iq;
    c->il_p.fstp = 1U;
    c->il_box_iq = iq_mpy(post->prot.i_lim_iq, (iq_t)11863283L); /* 1/sqrt2 rounded down, as im_dtc_init */
    hyst2_init(&c->h_flux, post->u.im.sw.flux_band_iq, 1U);
    hyst2_init(&c->h_torque2, post->u.im.sw.torque_band_iq, 1U);
    c->vec_1 = 1U;
    c->tdem_1 = 0;
    c->pi_p.limit_iq = post->speed.torque_limit_iq;
    if (c->act.flux_ref_iq > post->speed.flux_ref_iq) {
        c->act.flux_ref_iq = post->speed.flux_ref_iq;
    }
    if (c->act.torque_ref_iq > post->speed.torque_limit_iq) {
        c->act.torque_ref_iq = post->speed.torque_limit_iq;
    } else if (c->act.torque_ref_iq < fix_neg32(post->speed.torque_limit_iq)) {
        c->act.torque_ref_iq = fix_neg32(post->speed.torque_limit_iq);
    }
    c->ref_due = 1U;
    /* until the relay has closed phase A' is open (im_dtc_fstp.c): r_r / l_r = r_r / (k_r m) for
     * its alpha voltage, by the SVM's Newton reciprocal as im_dtc_init's constants */
    c->open_wait = post->prot.relay_periods;
    /* the estimator's rotor-flux reference follows the machine's rotor flux from the reference in
     * force down to post's (im_dtc_fstp.c im_fstp_psir_fall) */
    c->magn_psir_iq = c->psir_ref_iq;
    c->psir_fall = c->magnetised;
    c->rr_lr_iq = iq_mpy(post->u.im.machine.rr_iq,
                         svm_recip(0, iq_mpy(post->u.im.machine.kr_iq, post->u.im.machine.m_iq)));
    return DTC_OK;
}
