/*
 * im_dfoc.c - direct rotor-flux-oriented control of the induction machine, the baseline of
 * Casadei et al. 2006 section 13 ("DFOC": PI current regulators in the rotor-flux frame, SVM,
 * the same flux estimator): the law DTC_LAW_IM_DFOC of the IM module (im_dtc.h), one
 * im_dfoc_step() per control period = SVM carrier period (svm.h; the paper's drive: two-phase
 * modulation, 160 us cycle).
 *
 *   estimator, speed loop, start-up and references as the IM law (im_dtc_front, im_dtc_refs)
 *   -> rotor-flux frame from the estimator's direction e^{j theta} = (u_alpha, u_beta) (Casadei
 *      eq. 22): i_d = i . e^{j theta}, i_q = e^{j theta} x i (Park)
 *   -> references (T model in the rotor-flux frame, constant rotor flux, Casadei eqs. A7-A10):
 *        i_d* = phi_r* / m,   T = (m / l_r) phi_r i_q  ->  i_q* = (l_r / (m phi_r*)) T*
 *      with i_d* raised by the rotor-flux trim over m, (phi_r* / m)(trim / phi_r*) (im_psir_trim:
 *      the estimate's mean |phi_r| held at phi_r*, so that Casadei eq. 20's correction has no mean)
 *      and, while regenerating (T* w_s < 0), by the rotor-flux term K_f (phi_r* - |phi_r|) over m,
 *      K_f = (l_r/m)(tau_r/tau), once per speed period: i_d* acts in the estimate's frame, so an
 *      angle error eps moves the machine's i_d by -i_q eps, its rotor flux falls, and Casadei
 *      eq. 20's radial correction (phi_r* - |phi_r|)/tau, integrated at w_s, lags the estimate by
 *      (l_r/m)(phi_r* - |phi_r|)/(tau w_s |phi_r|): a loop of gain G = (l_r/m)(i_q/i_d)/(tau w_s),
 *      positive while i_q w_s < 0. With the term the rotor flux obeys
 *      tau_r^2 s^2 + tau_r (1 + K_f - G) s + 1 (the trim's integral included): stable wherever
 *      |w_s| > |w_slip| (K_f >= G there); measured, docs/sil.md
 *      (T* = 0 and i_d* the magnetising current during the start-up magnetisation)
 *   -> PI per axis, v_dq = K_p e + sum K_i Ts e (the integral clamped to +-1 pu, the nominal
 *      link; while the previous period's vector lay outside the SVM's hexagon, svm_o.overmod, an
 *      integral moves only towards zero: the conditional-integration anti-windup, so that a step
 *      of i_q* to the current's limit does not overshoot it after the voltage limit; measured,
 *      docs/sil.md), gains from the machine (tools/config: K_p = sigma l_s w_c, K_i = r_s
 *      w_c, w_c = 0.2 / Ts)
 *   -> stator frame, plus the back-EMF j w_s phi_s fed forward (Casadei eq. A6 in the steady
 *      state: v = R_s i + j w_s phi_s; with it the current loops see sigma l_s di/dt = v - R_s i),
 *      w_s = w + r_r T* / phi_r*^2 (Casadei eq. 16 solved for the slip), the whole vector advanced by the
 *      rotation 1.5 w_s Ts it makes until the middle of the period it acts in, (1 + j 1.5 w_s Ts)
 *   -> SVM and outputs (im_pwm_out, shared with the SFVC).
 *
 * Formats: IQ pu (dtc_base.h); gains IQ (K_i Ts per period).
 * Scaling and overflow: Park and the inverse rotation are two-term products rounded once
 * (iq_mac2, each |product| <= 2^62); PI products rounded IQ (iq_mpy), sums saturating, the
 * integrals clamped to +-1 pu (dqpi_integrate: formed and clamped in 64 bits); the feed-forward products rounded and saturating; the SVM clamps
 * the result onto its hexagon.
 */
#include "im_dtc_internal.h"

#include "dqpi.h"

void im_dfoc_init(im_dtc_t *c, const dtc_config_t *cfg)
{
    /* (l_r/m)(tau_r/Ts) = kr / (Ts/tau_r) in Q16 (init only): Ts/tau_r (magn_k_q31 >= 1, a Q31 below 1)
     * scaled by 2^n into [1/2, 1) and read as IQ (>> 7, exact to 2^-24), its reciprocal in (1, 2] by
     * the SVM's Newton (svm_recip: within a few LSB for x >= 2^-7), times kr = l_r/m (rounded IQ product,
     * saturating at 128 pu; kr is near 1), times 2^n back (below 2^62 in 64 bits for n <= 31) and
     * IQ -> Q16 by a rounded shift of 8, saturated */
    uint32_t x = (uint32_t)(cfg->u.im.ref.magn_k_q31 > 0 ? cfg->u.im.ref.magn_k_q31 : 1);
    uint16_t n = 0U;
    while (x < 0x40000000UL) {
        x <<= 1;
        ++n;
    }
    c->foc_kf_q16 = fix_rshift_rnd64_sat32(
        (int64_t)iq_mpy(cfg->u.im.machine.kr_iq, svm_recip(0, (iq_t)(x >> 7))) * (int64_t)((uint64_t)1 << n), 8U);
}

/* i_d* = (phi_r* / m)(1 + (trim + K_f (phi_r* - |phi_r|)) / phi_r*): the rotor-flux trim and the flux
 * term over m (rounded IQ products, saturating sums), at a reset and once per speed period. */
void im_dfoc_id_ref(im_dtc_t *c)
{
    const dtc_config_t *cfg = c->cfg;
    iq_t d = c->psir_trim_iq;
    if (c->magnetised != 0U && ((c->te_ref_iq > 0 && c->sr_ws_iq < 0) || (c->te_ref_iq < 0 && c->sr_ws_iq > 0))) {
        /* K_f (phi_r* - |phi_r|) = foc_kf (Ts/tau) (phi_r* - |phi_r|): (Ts/tau) e in Q31 (Q55 >> 24, below
         * 2^31 for |e| < 2^24), times the Q16 gain (< 2^62) back to IQ (>> 23), saturated */
        const int64_t ke = ((int64_t)c->est.k_q31 * (int64_t)iq_sub(c->psir_ref_iq, c->est.psir_mag_iq)) >> 24;
        d = iq_add(d, fix_rshift_rnd64_sat32(ke * (int64_t)c->foc_kf_q16, 23U));
    }
    c->foc_id_ref_iq = iq_add(cfg->u.im.dfoc.id_ref_iq, iq_mpy(cfg->u.im.dfoc.id_ref_iq, iq_mpy(d, cfg->u.im.ref.inv_psir_ref_iq)));
}

void im_dfoc_regulate(im_dtc_t *c)
{
    const dtc_config_t *cfg = c->cfg;
    const iq_t ua = c->est.u_alpha_iq, ub = c->est.u_beta_iq;
    const iq_t kp = cfg->u.im.dfoc.kp_iq, ki = cfg->u.im.dfoc.ki_ts_iq;
    const iq_t id = iq_mac2(c->i.i_alpha_iq, ua, c->i.i_beta_iq, ub);
    const iq_t iq = iq_mac2(c->i.i_beta_iq, ua, fix_neg32(c->i.i_alpha_iq), ub);
    iq_t iq_ref, ed, eq, vd, vq, va, vb, ws;

    /* w_s = w + w_slip (Casadei eq. 16), its advance by 1.5 w_s Ts, and i_q* */
    im_svm_rate(c, cfg->u.im.dfoc.iq_per_t_iq, 1U);
    ws = c->sr_ws_iq;
    iq_ref = c->magnetised != 0U ? c->sr_gt_iq : 0;
    ed = iq_sub(c->foc_id_ref_iq, id);
    eq = iq_sub(iq_ref, iq);

    /* anti-windup: while the previous period's vector lay outside the SVM's hexagon (svm_o.overmod:
     * scaled onto it, the voltage asked for not applied) an integral moves only towards zero */
    if (c->svm_o.overmod == 0U || (ed < 0) != (c->foc_id_int_iq < 0)) {
        c->foc_id_int_iq = dqpi_integrate(c->foc_id_int_iq, ki, ed, IQ(1.0));
    }
    if (c->svm_o.overmod == 0U || (eq < 0) != (c->foc_iq_int_iq < 0)) {
        c->foc_iq_int_iq = dqpi_integrate(c->foc_iq_int_iq, ki, eq, IQ(1.0));
    }
    vd = iq_add(iq_mpy(kp, ed), c->foc_id_int_iq);
    vq = iq_add(iq_mpy(kp, eq), c->foc_iq_int_iq);
    /* stator frame (inverse Park) plus j w_s phi_s */
    va = iq_sub(iq_mac2(vd, ua, fix_neg32(vq), ub), iq_mpy(ws, c->est.psi_beta_iq));
    vb = iq_add(iq_mac2(vd, ub, vq, ua), iq_mpy(ws, c->est.psi_alpha_iq));
    /* advanced by 1.5 w_s Ts: the flux turns that far until the middle of the next period */
    iq_cmul_1jx_inline(c->sr_adv_iq, &va, &vb);
    c->vs_alpha_iq = va;
    c->vs_beta_iq = vb;
}

void im_dfoc_step(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o)
{
    im_svm_scheme_step(c, m, o, 1U);
}
