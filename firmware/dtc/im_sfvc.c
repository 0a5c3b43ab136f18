/*
 * im_sfvc.c - stator-flux vector control of the induction machine (Casadei et al. 2006 sections
 * 10.3-10.5, Fig. 18): the scheme DTC_SCHEME_SFVC of the IM law (im_dtc.h), one im_sfvc_step()
 * per control period, which is also the SVM carrier period (one centred pulse per leg, svm.h).
 *
 *   Clarke -> stator voltage of the period that ends now (the duties returned two steps ago as
 *      the SVM expects them to act, d_eff, on the measured V_dc) + the device-drop compensation
 *   -> stator and rotor flux (improved or voltage-model estimator, im_est.h), torque (eq. A10)
 *   -> speed and speed PI, start-up magnetisation, references (shared with im_dtc_step)
 *   -> stator-flux reference vector, Casadei eq. 18 in the rotor-flux frame at constant rotor
 *      flux (the s sigma tau_r phi_r term is zero):
 *        phi_s* = (l_s/m) (phi_r* + j sigma l_r T* / phi_r*)                     (eq. 18, pu)
 *      turned into the stator frame by the rotor-flux direction e^{j theta} of eq. 22 (im_est's
 *      unit vector); during the start-up magnetisation phi_s* = (ramp) e^{j theta} at T* = 0
 *   -> the flux regulator, eqs. 23-24:
 *        Delta phi_s = phi_s* - phi_s                                            (eq. 23)
 *        v_s* = R_s i_s + j w_s phi_s + K_p Delta phi_s                          (eq. 24)
 *      made to act in the period the command is applied in (the one-period delay of hal.h):
 *      phi_s is the estimate predicted for the start of that period, phi_s(k+1) = phi_s(k) +
 *      Ts (v(k) - R_s i(k)) with v(k) the voltage of the duties returned by the previous step
 *      (the stator-voltage equation, Casadei eq. A6 / eq. 1, forward Euler over one period), and
 *      phi_s* is advanced to k+1 by the rotation w_s Ts, (1 + j w_s Ts) phi_s*(k) (iq_cmul_1jx).
 *      With K_p Ts = 1 the flux error left after the period is zero (deadbeat): phi_s(k+2) =
 *      phi_s*(k+1) + j w_s Ts phi_s(k+1), the reference two periods on. The back-EMF term uses
 *      w_s, the stator-flux angular speed, = w + w_slip in the steady state, the slip from eq. 16
 *      with the references (w_slip = r_r T* / phi_r*^2, im_ref_slip).
 *   -> SVM (svm.h) of v_s* on the measured V_dc with dead-time compensation by the current
 *      sign (sec. 10.5), the PWM form in dtc_out_t.
 * The device drops (vcomp.h) are compensated in the estimator's voltage, not in v_s*: the flux
 * regulator's proportional term takes up the difference.
 *
 * Formats: IQ pu (dtc_base.h), the duties IQ in [0, 1]; K_p in pu voltage per pu flux (K_p /
 * w_base), Ts as ts_pu = Ts w_base.
 * Scaling and overflow: rounded IQ products (iq_mpy) and saturating sums; the reference's
 * magnitude is l_s/m |phi_r*| sqrt(1 + (sigma l_r T* / phi_r*^2)^2), a few pu at the torque limit;
 * v_s* is at most R_s |i| + |w_s||phi_s| + K_p |Delta phi_s| (K_p <= 1/ts_pu: 64 pu at 50 us and
 * 50 Hz base), saturating; the SVM clamps it onto its hexagon (svm.h).
 */
#include "im_dtc.h"

#include "im_ref.h"
#include "torque.h"
#include "vrec.h"

/* Voltage of three expected duties on the link: leg voltages d_x V_dc through the reconstruction
 * of Hoang eqs. 1-5 (Casadei eq. 2). IQ x IQ rounded; vrec_from_legs saturates. */
static void sfvc_duty_voltage(const iq_t d[3], iq_t vdc_iq, iq_t *va, iq_t *vb)
{
    vrec_from_legs(iq_mpy(d[0], vdc_iq), iq_mpy(d[1], vdc_iq), iq_mpy(d[2], vdc_iq), va, vb);
}

/* The estimator's input (as im_dtc_estimate): the duties of the period that ends now plus the
 * SSTP device-drop terms (vcomp.h; with the SSTP's equal drops the leg state does not matter).
 * The dead time is in d_eff already (svm.h). */
void im_sfvc_estimate(im_dtc_t *c, const dtc_meas_t *m)
{
    im_est_in_t *in = &c->ein;
    sfvc_duty_voltage(c->d_eff_2, m->vdc_iq, &in->v_alpha_iq, &in->v_beta_iq);
    vcomp_step(&c->vc_p, 0U, 0U, 0U, &c->i, &c->dva_iq, &c->dvb_iq);
    in->v_alpha_iq = fix_add32(in->v_alpha_iq, c->dva_iq);
    in->v_beta_iq = fix_add32(in->v_beta_iq, c->dvb_iq);
    im_dtc_ein_common(c);
}

/* Eqs. 18, 23, 24 (file comment), then the SVM into c->svm_o. */
void im_sfvc_regulate(im_dtc_t *c, const dtc_meas_t *m)
{
    const dtc_config_t *cfg = c->cfg;
    const dtc_im_machine_cfg_t *im = &cfg->machine.im;
    const iq_t ts = cfg->board.ts_pu_iq;
    const iq_t rs = cfg->machine.rs_iq;
    iq_t pa, pb, ra, rb, ws, x;

    /* the flux predicted for k+1: the stator-voltage equation over the period under way */
    {
        iq_t v1a, v1b;
        sfvc_duty_voltage(c->d_eff_1, m->vdc_iq, &v1a, &v1b);
        pa = iq_add(c->est.psi_alpha_iq,
                    iq_mpy(ts, iq_sub(iq_add(v1a, c->dva_iq), iq_mpy(rs, c->i.i_alpha_iq))));
        pb = iq_add(c->est.psi_beta_iq,
                    iq_mpy(ts, iq_sub(iq_add(v1b, c->dvb_iq), iq_mpy(rs, c->i.i_beta_iq))));
    }
    /* eq. 18 in the rotor-flux frame (d along phi_r), then e^{j theta} (eq. 22) */
    {
        iq_t d, q;
        if (c->magnetised == 0U) {
            d = c->psi_ref_iq; /* the start-up ramp, radial, T* = 0 */
            q = 0;
        } else {
            d = iq_mpy(im->ks_iq, cfg->speed.psir_ref_iq);
            q = iq_mpy(im->ks_iq, iq_mpy(iq_mpy(im->sigma_lr_iq, c->te_ref_iq), cfg->speed.inv_psir_ref_iq));
        }
        ra = iq_sub(iq_mpy(d, c->est.u_alpha_iq), iq_mpy(q, c->est.u_beta_iq));
        rb = iq_add(iq_mpy(d, c->est.u_beta_iq), iq_mpy(q, c->est.u_alpha_iq));
    }
    /* w_s = w + w_slip (eq. 16), the reference advanced by w_s Ts to k+1 */
    ws = iq_add(c->speed_iq, im_ref_slip(im->rr_iq, c->te_ref_iq, cfg->speed.inv_psir_sq_iq));
    x = iq_mpy(ws, ts);
    iq_cmul_1jx(x, &ra, &rb);
    /* eq. 23 and eq. 24: v_s* = R_s i + j w_s phi_s + K_p (phi_s* - phi_s) */
    c->vs_alpha_iq = iq_add(iq_sub(iq_mpy(rs, c->i.i_alpha_iq), iq_mpy(ws, pb)),
                            iq_mpy(cfg->sw.sfvc_kp_iq, iq_sub(ra, pa)));
    c->vs_beta_iq = iq_add(iq_add(iq_mpy(rs, c->i.i_beta_iq), iq_mpy(ws, pa)),
                           iq_mpy(cfg->sw.sfvc_kp_iq, iq_sub(rb, pb)));
    svm_step(&c->svm, &c->svm_p, c->vs_alpha_iq, c->vs_beta_iq, m->vdc_iq, &c->i, &c->svm_o);
}

void im_sfvc_step(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o)
{
    iq_t te;
    uint16_t x;

    /* 1. Shadow set (dtc_refs.h). */
    {
        const uint16_t seq = dtc_shadow_pending(&c->sh);
        if (seq != 0U) {
            im_dtc_adopt(c, seq);
        }
    }
    /* 2. Clarke (Hoang eqs. 4-5). */
    clarke_sstp(m->ia_iq, m->ib_iq, &c->i);
    /* 3. Stator and rotor flux (Casadei eqs. 1, 20-22) from the modulated voltage. */
    im_sfvc_estimate(c, m);
    im_est_step(&c->est, &c->ein);
    /* 4. Torque (Casadei eq. A10). */
    te = torque_eq10(c->est.psi_alpha_iq, c->est.psi_beta_iq, c->i.i_alpha_iq, c->i.i_beta_iq);
    /* 5. Speed and speed loop; 6. references: start-up, eq. 19 (the stator-flux magnitude, for
     *    the telemetry and the magnetising ramp). */
    im_dtc_speed(c, m, te, o);
    im_dtc_refs(c);
    /* 7. Flux regulator (eqs. 18, 23, 24) and SVM. */
    im_sfvc_regulate(c, m);
    for (x = 0U; x < 3U; x++) {
        c->d_eff_2[x] = c->d_eff_1[x];
        c->d_eff_1[x] = c->svm_o.d_eff_iq[x];
        o->duty_iq[x] = c->svm_o.d_iq[x];
    }

    /* 8. Outputs. */
    o->pwm = 1U;
    o->sa = (uint16_t)(c->svm_o.d_iq[0] > IQ(0.5) ? 1U : 0U);
    o->sb = (uint16_t)(c->svm_o.d_iq[1] > IQ(0.5) ? 1U : 0U);
    o->sc = (uint16_t)(c->svm_o.d_iq[2] > IQ(0.5) ? 1U : 0U);
    o->vector = 0U;
    o->sector = 0U;
    o->flux_up = 0U;
    o->torque_dem = 0;
    o->psi_alpha_iq = c->est.psi_alpha_iq;
    o->psi_beta_iq = c->est.psi_beta_iq;
    o->te_iq = te;
    o->te_ref_iq = c->te_ref_iq;
    o->speed_iq = c->speed_iq;
    o->theta_e = c->est.theta_r;
    o->on_cm = 0U;
    o->psi_ref_iq = c->psi_ref_iq;
    o->psir_mag_iq = c->est.psir_mag_iq;
    o->i_limited = 0U;
}
