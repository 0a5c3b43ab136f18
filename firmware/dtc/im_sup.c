/* im_sup.c - the IM model's supervision and the on-line r_r (im_sup.h), once per speed period. */
#include "im_dtc_internal.h"

#define IM_SUP_RHO_MIN IQ(0.5)
#define IM_SUP_RHO_MAX IQ(2.0)
#define IM_SUP_RHO_TOL IQ(0.2)     /* |rho - 1| beyond which r_r is reported off */
#define IM_SUP_D_MAX IQ(0.25)      /* |q - 1| within which rho adapts */

void im_sup_reset(im_dtc_t *c)
{
    im_sup_t *s = &c->sup;
    s->psir_cm_iq = 0;
    s->due = 0U;
    s->compared = 0U;
    s->adapting = 0U;
    s->n_bad = 0U;
    s->cause = 0U;
    s->warn = 0U;
    /* the machine is demagnetised: the current model starts at zero, at rest */
    s->cm_b_iq = s->cm_on != 0U ? IQ(1.0) : 0;
    s->cm_alpha_iq = 0;
    s->cm_beta_iq = 0;
    s->cm_mi_alpha_iq = 0;
    s->cm_mi_beta_iq = 0;
    s->cm_run = 1U;
}

/* The current model's rotation per step and its blend weight for this speed period (im_sup.h):
 * w Ts = w (IQ) ts_pu (Q31), a Q55 product rounded to Q31, saturated; (w Ts)^2 a Q62 product;
 * (w Ts)^2 / (3W) = ((w Ts)^2 2^cm_n, as IQ: Q62 >> (38 - cm_n), rounded, saturated) times
 * 1/(3W 2^cm_n), a rounded IQ product; b = 4/3 - that, clamped to [0, 1]. */
static void im_sup_cm_blend(im_dtc_t *c)
{
    im_sup_t *s = &c->sup;
    q31_t wt;
    int64_t w2;
    if (s->cm_on == 0U) {
        return;
    }
    wt = fix_rshift_rnd64_sat32((int64_t)c->speed_iq * (int64_t)c->est_p.ts_pu_q31, (uint16_t)FIX_IQ_Q);
    w2 = (int64_t)wt * (int64_t)wt;
    s->cm_b_iq = fix_clamp32(iq_sub(IQ_FRAC(4, 3), iq_mpy(fix_rshift_rnd64_sat32(w2, (uint16_t)(38U - s->cm_n)),
                                                          s->cm_inv_iq)),
                             0, IQ(1.0));
    if (s->cm_b_iq == 0) {
        s->cm_run = 0U; /* re-seeded from the estimate when b rises again */
    }
}

/* The tracked r_r in use (u.im.ref.rr_track): the slip of the sensorless speed and of the SFVC,
 * and the estimator's r_s by the same ratio (im_sup.h). Rounded IQ products. */
static void im_sup_apply(im_dtc_t *c)
{
    const im_sup_t *s = &c->sup;
    c->isp_p.rr_iq = iq_mpy(s->rho_iq, s->rr_cfg_iq);
    c->sfvc_kslip_iq = iq_mpy(s->rho_iq, s->kslip_cfg_iq);
    c->est_p.rs_iq = iq_mpy(s->rho_iq, s->rs_cfg_iq);
}

/* rho's adaptation on a speed period the encoder plausibility compared (im_dtc_enc_plaus: w_psi and
 * the encoder's speed through one filter, te_filt through it too; they hold until the next speed
 * period). q = |phi_r,cm|^2 / phi_r*^2
 * (IQ, inv_psir_sq the configuration's 1/phi_r*^2), 1/q ~ 1 - d + d^2. Returns nothing; sets
 * s->adapting. */
static void im_sup_adapt(im_dtc_t *c, const dtc_config_t *cfg)
{
    im_sup_t *s = &c->sup;
    const iq_t te = c->isp.te_filt_iq;
    const iq_t q = iq_mpy(iq_mpy(s->psir_cm_iq, s->psir_cm_iq), cfg->u.im.ref.inv_psir_sq_iq);
    const iq_t d = iq_sub(q, IQ(1.0));
    iq_t inv_q, slip_hat, e, step;

    s->adapting = 0U;
    if (fix_abs32(d) > IM_SUP_D_MAX || fix_abs32(te) < s->te_min_iq || fix_abs32(c->speed_iq) < s->w_min_iq) {
        return;
    }
    inv_q = iq_add(iq_sub(IQ(1.0), d), iq_mpy(d, d));
    /* Casadei eq. 16 with r_r^ and the current model's flux */
    slip_hat = iq_mpy(im_ref_slip(iq_mpy(s->rho_iq, s->rr_cfg_iq), te, cfg->u.im.ref.inv_psir_sq_iq), inv_q);
    e = iq_sub(fix_sub32(c->isp.w_psi_iq, c->enc_filt_iq), slip_hat);
    step = iq_mpy(s->k_rho_iq, e);
    s->rho_iq = te >= 0 ? iq_add(s->rho_iq, step) : iq_sub(s->rho_iq, step);
    s->rho_iq = s->rho_iq < IM_SUP_RHO_MIN ? IM_SUP_RHO_MIN : (s->rho_iq > IM_SUP_RHO_MAX ? IM_SUP_RHO_MAX : s->rho_iq);
    s->adapting = 1U;
}

/* Casadei eq. 20's reference vector at low speed and the current model's step (im_sup.h), called
 * by im_dtc_ein_common while the blend weight b > 0: once magnetised, the reference phi_r* e^{j theta} + b (phi_r,cm -
 * phi_r* e^{j theta}) for the estimator (in->ref_vec), with the current model's flux and
 * e^{j theta} of the previous sampling instant, the instant of the estimate's phi_r that
 * im_est_flux corrects; then the current model one symplectic Euler step on to this instant,
 * turned by the rotor's angle step between the two instants (enc_count: this step's encoder
 * count, less the previous step's, times the angle of one count), with the previous instant's
 * current (forward Euler: taking this instant's current would put the model
 * one period ahead, w_s Ts in angle, and with a reference of this instant the estimate two:
 * measured 4.9 mrad, +3.6 % of torque on the second machine at 72 rpm, 10 % torque). When b has
 * risen from 0 the model starts from the estimate's rotor flux (and this instant's m i). Otherwise
 * the paper's reference (ref_vec 0; im_dtc_ein_common sets it while b = 0). Formats: IQ pu, Ts/tau_r and w Ts Q31; each component's change
 * Q31 x IQ products summed in 64 bits (each < 2^62) and rounded once, added with saturation; m i and
 * the blend rounded IQ products, saturating sums; the count step (at most counts/2 < 2^15) times
 * the count's angle (Q31) in 64 bits, saturated to Q31. */
void im_sup_cm_ref(im_dtc_t *c, uint16_t enc_count)
{
    im_sup_t *s = &c->sup;
    im_est_in_t *in = &c->ein;
    q31_t k, wt;
    iq_t m, mi_a, mi_b;
    int64_t d;
    int32_t dn = (int32_t)enc_count - (int32_t)s->cm_count;
    const int32_t half = (int32_t)(c->cfg->board.enc_counts >> 1);

    in->ref_vec = 0U;
    k = c->cfg->u.im.ref.magn_k_q31;
    m = c->cfg->u.im.machine.m_iq;
    mi_a = iq_mpy(m, in->i_alpha_iq);
    mi_b = iq_mpy(m, in->i_beta_iq);
    if (s->cm_run == 0U) {
        s->cm_alpha_iq = c->est.psir_alpha_iq;
        s->cm_beta_iq = c->est.psir_beta_iq;
        s->cm_mi_alpha_iq = mi_a;
        s->cm_mi_beta_iq = mi_b;
        s->cm_run = 1U;
        dn = 0;
    }
    /* the rotor's angle step since the previous step: the count difference folded across the
     * counter's wrap (as speed_meas_step); none in the law's first step after a reset, before
     * the count has a reference (speed_loop_due primes it in this step) */
    if (c->speed_primed == 0U) {
        dn = 0;
    } else if (dn > half) {
        dn -= (int32_t)c->cfg->board.enc_counts;
    } else if (dn <= -half) {
        dn += (int32_t)c->cfg->board.enc_counts;
    }
    s->cm_count = enc_count;
    wt = fix_sat32((int64_t)dn * (int64_t)s->cm_k_q31);
    if (c->magnetised != 0U) {
        if (s->cm_b_iq >= IQ(1.0)) {
            in->ref_alpha_iq = s->cm_alpha_iq;
            in->ref_beta_iq = s->cm_beta_iq;
        } else {
            const iq_t pa = iq_mpy(in->psir_ref_iq, c->est.u_alpha_iq);
            const iq_t pb = iq_mpy(in->psir_ref_iq, c->est.u_beta_iq);
            in->ref_alpha_iq = iq_add(pa, iq_mpy(s->cm_b_iq, iq_sub(s->cm_alpha_iq, pa)));
            in->ref_beta_iq = iq_add(pb, iq_mpy(s->cm_b_iq, iq_sub(s->cm_beta_iq, pb)));
        }
        in->ref_vec = 1U;
    }
    d = (int64_t)k * (int64_t)fix_sub32(s->cm_mi_alpha_iq, s->cm_alpha_iq) -
        (int64_t)wt * (int64_t)s->cm_beta_iq;
    s->cm_alpha_iq = fix_add32(s->cm_alpha_iq, fix_rshift_rnd64_sat32(d, 31U));
    d = (int64_t)k * (int64_t)fix_sub32(s->cm_mi_beta_iq, s->cm_beta_iq) +
        (int64_t)wt * (int64_t)s->cm_alpha_iq;
    s->cm_beta_iq = fix_add32(s->cm_beta_iq, fix_rshift_rnd64_sat32(d, 31U));
    s->cm_mi_alpha_iq = mi_a;
    s->cm_mi_beta_iq = mi_b;
}

void im_sup_step(im_dtc_t *c)
{
    const dtc_config_t *cfg = c->cfg;
    im_sup_t *s = &c->sup;
    uint16_t cause = 0U;
    im_sup_cm_blend(c);
    /* the current model, Casadei eqs. A7, A9 in the rotor-flux frame (im_sup.h) */
    const iq_t i_d = iq_add(iq_mpy(c->i.i_alpha_iq, c->est.u_alpha_iq), iq_mpy(c->i.i_beta_iq, c->est.u_beta_iq));
    s->psir_cm_iq = iq_add(s->psir_cm_iq,
                           q31_mul(s->k_cm_q31, iq_sub(iq_mpy(cfg->u.im.machine.m_iq, i_d), s->psir_cm_iq)));
    if (c->magnetised == 0U) {
        return;
    }
    if (s->compared != 0U) {
        im_sup_adapt(c, cfg);
        if (s->adapting != 0U && s->track != 0U) {
            im_sup_apply(c);
        }
    }
    if (fix_abs32(iq_sub(s->rho_iq, IQ(1.0))) > IM_SUP_RHO_TOL) {
        cause |= 1U;
    }
    /* the two rotor-flux magnitudes (improved estimator, Casadei eqs. 20-21; current model) differ
     * by more than 1/8 of the estimator's */
    if (fix_abs32(iq_sub(s->psir_cm_iq, c->est.psir_mag_iq)) > fix_rshift_rnd32(c->est.psir_mag_iq, 3U)) {
        cause |= 2U;
    }
    s->cause = cause;
    if (cause == 0U) {
        s->n_bad = 0U;
        s->warn = 0U;
    } else if (s->n_bad < s->n_confirm) {
        ++s->n_bad;
    } else {
        s->warn = 1U;
    }
}
