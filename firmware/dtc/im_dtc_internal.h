/*
 * im_dtc_internal.h - the IM laws' functions internal to their own files (im_dtc.c,
 * im_dtc_init.c, im_sfvc.c, im_dfoc.c, im_dsvm.c) and their white-box tests: the steps kept out of
 * line for the stack (as dtc_internal.h) and the inline pieces every IM scheme's step shares. Not
 * for the application, which reaches the law through app/law.h.
 */
#ifndef IM_DTC_INTERNAL_H
#define IM_DTC_INTERNAL_H

#include <stdint.h>

#include "im_dtc.h"

/* Internal: the rotor-flux reference for a stator-flux reference, and the adoption of a reference
 * set (shared by im_dtc_init and the shadow set). */
void im_dtc_psir_ref(im_dtc_t *c, iq_t psi_s_ref_iq);
void im_dtc_apply(im_dtc_t *c, const dtc_refs_t *r);
/* Internal to im_dtc_step, out of line for the stack (as dtc.c's helpers). */
void im_dtc_adopt(im_dtc_t *c, uint16_t seq);
void im_dtc_estimate(im_dtc_t *c, const dtc_meas_t *m);
/* The speed-loop period's speed and speed PI, and the torque mode's command (im_dtc.c), out of
 * line: im_dtc_speed's other periods pay for no call. */
void im_dtc_speed_tick(im_dtc_t *c, const dtc_meas_t *m, iq_t te);
void im_dtc_torque_cmd(im_dtc_t *c, iq_t te);
void im_dtc_enc_plaus(im_dtc_t *c);
void im_dtc_refs(im_dtc_t *c);
/* The rotor-flux trim (im_dtc.c), once per speed period: 1 when it moved. */
uint16_t im_psir_trim(im_dtc_t *c);
/* SFVC: c->sfvc_kpd_iq = K_p (l_s/m)(phi_r* + trim), Casadei eq. 18's d component times K_p. */
void im_sfvc_kpd(im_dtc_t *c);
/* DFOC: c->foc_id_ref_iq = i_d* with the rotor-flux trim and the flux term (im_dfoc.c); the
 * flux term's gain from the configuration (im_dfoc_init, init only). */
void im_dfoc_id_ref(im_dtc_t *c);
void im_dfoc_init(im_dtc_t *c, const dtc_config_t *cfg);
uint16_t im_dtc_select(im_dtc_t *c, iq_t te, dtc_out_t *o);
/* The model's supervision (im_sup.h): its parameters from cfg (im_sup_init.c, init only; after
 * sfvc_kslip_iq), its state back to the start with the tracked r_r kept (im_dtc_reset), and its
 * step once per speed period on that period's speed and encoder plausibility, in the step
 * sup.slot (im_dtc_speed). */
void im_sup_init(im_dtc_t *c, const dtc_config_t *cfg);
void im_sup_reset(im_dtc_t *c);
void im_sup_step(im_dtc_t *c);
/* While the blend weight sup.cm_b_iq > 0: the current model's step and Casadei eq. 20's reference
 * vector into c->ein (im_sup.c). */
void im_sup_cm_ref(im_dtc_t *c, uint16_t enc_count);

/* Internal to im_sfvc_step, out of line for the stack. */
void im_sfvc_regulate(im_dtc_t *c);
/* The modulated schemes' estimator input (SFVC, DFOC, DSVM), inline in im_dtc_front (defined
 * below, after the pieces it uses). */
static inline void im_sfvc_estimate(im_dtc_t *c, const dtc_meas_t *m);
/* Internal to im_dfoc_step, out of line for the stack. */
void im_dfoc_regulate(im_dtc_t *c);

/* The SFVC's and the DFOC's terms of T* and w: w_s = w + w_slip (Casadei eq. 16, the slip gain
 * r_r / phi_r*^2 that im_sup tracks), its advance w_s t_adv (t_adv: the SFVC's Ts, adv15 = 0, the
 * DFOC's 1.5 Ts, adv15 = 1, formed only here) and g T* (g_iq: the SFVC's K_p times
 * Casadei eq. 18's q component per pu T*, the DFOC's i_q per pu T*), into c->sr_*. Formed again only when T*, w or the slip gain differ from the ones
 * they were formed for (t_adv and g are constants of the configuration): in speed mode T* and w
 * change at the speed-loop rate. The same rounded IQ products and saturating sum as formed every
 * period. */
static inline void im_svm_rate(im_dtc_t *c, iq_t g_iq, uint16_t adv15)
{
    if (c->sr_valid == 0U || c->te_ref_iq != c->sr_te_iq || c->speed_iq != c->sr_w_iq ||
        c->sfvc_kslip_iq != c->sr_kslip_iq) {
        c->sr_te_iq = c->te_ref_iq;
        c->sr_w_iq = c->speed_iq;
        c->sr_kslip_iq = c->sfvc_kslip_iq;
        c->sr_valid = 1U;
        c->sr_ws_iq = iq_add(c->speed_iq, iq_mpy(c->sfvc_kslip_iq, c->te_ref_iq));
        const iq_t ts = c->cfg->board.ts_pu_iq;
        c->sr_adv_iq = iq_mpy(c->sr_ws_iq, adv15 != 0U ? iq_add(ts, fix_rshift_rnd32(ts, 1U)) : ts);
        c->sr_gt_iq = iq_mpy(g_iq, c->te_ref_iq);
    }
}

/* Internal to im_dsvm_step, out of line for the stack. */
/* lim_vec: im_ilim's vector of this step (used when c->i_limited). */
void im_dsvm_select(im_dtc_t *c, const dtc_meas_t *m, iq_t te, uint16_t lim_vec, dtc_out_t *o);

/* Internal to im_dtc_step_fstp (im_dtc_fstp.c), out of line for the stack. */
void im_dtc_estimate_fstp(im_dtc_t *c, const dtc_meas_t *m);
uint16_t im_dtc_select_fstp(im_dtc_t *c, iq_t te, dtc_out_t *o);
/* After a leg failure, the estimator's rotor-flux reference down the current model's rotor flux
 * (im_dtc_fstp.c), out of line for the stack. */
void im_fstp_psir_fall(im_dtc_t *c);
/* The vector while phase A' is open after a leg failure (im_dtc_fstp.c), out of line for the
 * stack. */
uint16_t im_open_vector(const im_dtc_t *c, iq_t psi_a, uint16_t up);
/* From the reconfiguration while the rotor flux falls: the torque-raising vector of the quadrant
 * that advances the flux more, or Hoang Table II's (im_dtc_fstp.c); out of line so that the
 * four-switch step of a drive that has not reconfigured carries none of it. */
uint16_t im_dtc_fstp_advance(const im_dtc_t *c, uint16_t sector, uint16_t flux_up, uint16_t up, iq_t te);

/* The steps of the speed period that carry its once-per-period work (div_cnt after its increment
 * in im_dtc_speed: 1 the speed loop's step, 0 the last step), so that no step carries two of the
 * pieces and each fits beside an ordinary period (docs/f2812.md, the IM image's worst ISR):
 *   speed_div >= 7: 9 and 0 the CORDIC's halves (im_polar_due), 1 the speed loop, 2 the encoder
 *   plausibility's comparison (im_plaus_slot), 4 the supervision (im_sup.h slot), 5 the rotor-flux
 *   trim (im_trim_slot), 6 Casadei eq. 19 (ref_slot); even steps where it can: the
 *   application's current-sensor plausibility judges its windows on the odd steps (app_core.h's
 *   slots);
 *   smaller speed_div: shared steps (im_dtc.h ref_slot, im_sup.h slot). */
static inline uint16_t im_plaus_slot(uint16_t speed_div)
{
    return (uint16_t)(speed_div > 6U ? 2U : (speed_div > 3U ? 3U : 0U));
}
static inline uint16_t im_trim_slot(const im_dtc_t *c)
{
    return c->ref_slot > 2U ? (uint16_t)(c->ref_slot - 1U) : c->ref_slot;
}
/* In im_dtc_front, before im_dtc_speed's increment: bit 0 im_est_polar_begin (the last step but
 * one of the speed period, or the last when speed_div is 1), bit 1 im_est_polar_end (the last
 * step: the speed loop's step follows). The angle and magnitude the speed loop, the
 * plausibility, the supervision, the trim and eq. 19 read are those of the x two steps before
 * the speed loop's (80 us at 40 us; with speed_div 1 the speed loop's own step).
 * The first half sits in the odd step 9, where the IM image's worst ISR was measured with it
 * (docs/f2812.md). The place of the trim's one |phi_r| sample per speed period does not move the
 * mean torque beyond the measurement's scatter: DSVM at 72 rpm, 10 % of rated torque (4 kW) gives
 * +0.06 .. +0.26 % of T* over an 8.33 s window with the sample zero to four steps before the
 * speed loop's. (On the sweep's 0.84 s window the same places read -0.63 .. +2.07 %; that spread
 * is the short window's scatter at this point, docs/sil.md, not an alias of the ripple.) */
static inline uint16_t im_polar_due(const im_dtc_t *c)
{
    /* r: the steps after this one in the speed period (0 in its last) */
    const uint16_t sd = c->cfg->speed.speed_div, r = (uint16_t)(sd - 1U - c->div_cnt);
    if (r > 1U) {
        return 0U;
    }
    return (uint16_t)(r == 1U ? 1U : (sd < 2U ? 3U : 2U));
}

/* Speed every speed_div-th period, as in the PM law (im_dtc_speed_tick: the encoder's or the
 * sensorless speed, the speed PI); the encoder plausibility's comparison (im_dtc_enc_plaus, with
 * the encoder and u.im.ref.enc_plaus_iq > 0) and then the model's supervision once per speed
 * period, each in a step of its own that carries neither the speed loop nor Casadei eq. 19
 * (im_dtc.h, im_sup.h slot), on the speed-loop step's values; in torque mode the command of the set in force (im_dtc_torque_cmd). Inline: the
 * periods without the speed loop pay for no call. */
static inline void im_dtc_speed(im_dtc_t *c, const dtc_meas_t *m, iq_t te, dtc_out_t *o)
{
    o->speed_tick = 0U;
    c->plaus_on = 0U;
    if (speed_loop_due(&c->sm, &c->speed_primed, &c->div_cnt, m->enc_count) != 0U) {
        o->speed_tick = 1U;
        im_dtc_speed_tick(c, m, te);
    }
    speed_loop_advance(&c->div_cnt, c->cfg->speed.speed_div);
    if ((c->sup.due & 2U) != 0U && c->div_cnt == im_plaus_slot(c->cfg->speed.speed_div)) {
        im_dtc_enc_plaus(c);
        c->sup.due = 1U;
        c->sup.compared = c->plaus_on;
    }
    if (c->sup.due != 0U && c->div_cnt == c->sup.slot) {
        c->sup.due = 0U;
        im_sup_step(c);
    }
    if (c->act.mode == DTC_MODE_TORQUE) {
        im_dtc_torque_cmd(c, te);
    }
}

/* The references of the period (im_dtc_refs). Most periods of the constant-rotor-flux law
 * (Casadei eq. 19, no flux weakening) after the start-up change nothing but T* = the speed loop's
 * or the torque mode's command: those take it here, without the call; the others, and eq. 19's
 * period (ref_due, in the step ref_slot: im_dtc_refs), call im_dtc_refs. */
static inline void im_dtc_refs_step(im_dtc_t *c)
{
    if (c->magnetised != 0U && (c->ref_due == 0U || (uint16_t)(c->ref_slot - c->div_cnt) > 1U) &&
        c->cfg->u.im.fw.on == 0U && c->cfg->u.im.ref.psir_ref_iq > 0) {
        c->te_ref_iq = c->te_cmd_iq;
    } else {
        im_dtc_refs(c);
    }
}

/* The estimator input of im_dtc_front: the legs on the six-switch inverter (im_dtc_estimate), the
 * modulated duties (im_sfvc_estimate), the legs on the four-switch inverter (im_dtc_estimate_fstp). */
enum im_front_kind { IM_FRONT_LEGS = 0, IM_FRONT_PWM = 1, IM_FRONT_FSTP = 2 };

/* Steps 1-5 of a control period, common to every scheme: the shadow set (dtc_refs.h), Clarke
 * (Hoang eqs. 4-5, the same transform as Casadei's space vectors; on the FSTP from i_b, i_c, the
 * switched phases), the stator and rotor flux (Casadei eqs. 1, 20-22) from the scheme's voltage
 * (kind, enum im_front_kind), the torque (Casadei eq. A10 = Hoang eq. 10 in these bases),
 * the speed and the speed loop. Returns the estimated torque. Inline with a constant kind: each
 * scheme's step gets its own copy (no call or branch added to the DTC path). */
static inline iq_t im_dtc_front(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o, uint16_t kind)
{
    iq_t te;
    {
        const uint16_t seq = dtc_shadow_pending(&c->sh);
        if (seq != 0U) {
            im_dtc_adopt(c, seq);
        }
    }
    if (kind == (uint16_t)IM_FRONT_FSTP) {
        clarke_fstp(m->ib_iq, m->ic_iq, &c->i);
        im_dtc_estimate_fstp(c, m);
    } else if (kind == (uint16_t)IM_FRONT_PWM) {
        clarke_sstp(m->ia_iq, m->ib_iq, &c->i);
        im_sfvc_estimate(c, m);
    } else {
        clarke_sstp(m->ia_iq, m->ib_iq, &c->i);
        im_dtc_estimate(c, m);
    }
    im_est_flux(&c->est, &c->ein);
    /* the rotor-flux angle and magnitude (CORDIC, Casadei eqs. 21-22) once per speed period, in
     * two halves (im_est_polar_begin, _end; after im_est_flux: the CORDIC's frame is not under
     * im_est_flux's): begun on the x of the speed period's last step but one, ended in the last
     * (im_polar_due); the speed loop's step that follows reads them */
    {
        const uint16_t due = im_polar_due(c);
        if (due != 0U) {
            if ((due & 1U) != 0U) {
                im_est_polar_begin(&c->est);
            }
            if ((due & 2U) != 0U) {
                im_est_polar_end(&c->est);
            }
        }
    }
    te = torque_eq10(c->est.psi_alpha_iq, c->est.psi_beta_iq, c->i.i_alpha_iq, c->i.i_beta_iq);
    im_dtc_speed(c, m, te, o);
    return te;
}

/* The start-up's vector (SSTP 1..6 or SWTAB_NULL) for the flux in sector 1..6, the flux
 * comparator's flux_up and the torque error err = T* - T, T* = 0 (im_dtc_refs).
 *   Rotor at rest (the encoder's speed 0): the radial vector V_k while the flux must rise, a null
 *     otherwise (Casadei Fig. 17b; file comment).
 *   Rotor turning (a flying start): a stationary flux would brake it (DC injection: the slip is
 *     the rotor's own speed, Casadei eq. 16), and the machine's rotor flux would not follow the
 *     magnetising ramp the estimator's reference assumes, so the estimate would settle on a
 *     flux the machine does not have. Instead ST-D's vectors under a two-level torque
 *     comparator held at T* = 0 (Casadei Table 3: V_k+1 / V_k-1 while the flux must rise,
 *     V_k+2 / V_k-2 while it must fall) turn the flux with the rotor in either sense, at a
 *     small mean torque against the motion (the zero band with the period's actuation delay;
 *     docs/sil.md gives the figures). At rest they would alternate about the radial direction
 *     with a torque ripple of about a quarter of the rated torque, hence the radial vector there.
 * Without an encoder (a sensorless flying start) the speed is not known before the flux is, so
 * ST-D's vectors at T* = 0 run from the first period, at rest too: the torque comparator is then
 * the zero-torque loop that finds the rotor. Zero torque means zero slip (Casadei eq. 16,
 * w_slip = r_r T / |phi_r|^2, valid in transients), so the flux it builds turns at the rotor's
 * own speed and sense from its first volt-seconds, the rotor-flux angle (Casadei eq. 22) moves
 * with the rotor and the sensorless speed (the angle's rate less that slip, im_ref.h) reads the
 * rotor's speed and direction by the end of the magnetisation; no search sweep, no added state
 * or step cost. At rest the torque ripples about zero (no mean torque) while the machine is
 * magnetised. DSVM (im_dsvm.c) takes the same vectors. The modulated laws (SFVC, DFOC) build
 * their flux along the estimated rotor flux turned at the sensorless speed, whose slip term
 * already moves that speed towards the rotor's (docs/sil.md gives the measured starts). */
static inline uint16_t im_magn_vector(im_dtc_t *c, uint16_t sector, uint16_t flux_up, iq_t err, int16_t *tdem)
{
    uint16_t up;
    if (c->cfg->speed.sensor == DTC_SPEED_ENCODER && c->speed_iq == 0) {
        *tdem = 0;
        return flux_up != 0U ? sector : SWTAB_NULL;
    }
    up = hyst2_step(&c->h_torque2, err);
    *tdem = up != 0U ? 1 : -1;
    return swtab_sstp_st(DTC_ST_D, sector, flux_up, up);
}

/* The current limit of the switching-table laws (DTC, DSC, DSVM): the table's vector vec, or,
 * when the sampled current exceeds prot.i_lim_iq, the vector that reduces |i| fastest
 * (ilim_select; the host leaves two periods' largest rise between the limit and the trip, the
 * vector chosen now acting from the next period on: tools/config dtc_ilim_default_a with the
 * transient inductance sigma L_s). Inside the square |i_alpha|, |i_beta| <= h = I_lim / sqrt2
 * (il_box_iq, from init) |i| <= I_lim, so there the exact squares are not needed: |x| <= h as
 * the unsigned x + h <= 2 h (modulo 2^32, exact for every int32 x, 0 <= h < 2^30). Limit off
 * (i_lim_iq = 0): h = 0, ilim_select returns vec. Sets c->i_limited. */
static inline uint16_t im_ilim(im_dtc_t *c, uint16_t vec)
{
    const uint32_t h = (uint32_t)c->il_box_iq;
    if ((uint32_t)c->i.i_alpha_iq + h <= h + h && (uint32_t)c->i.i_beta_iq + h <= h + h) {
        c->i_limited = 0U;
        return vec;
    }
    return ilim_select(&c->il_p, &c->i, vec, &c->i_limited);
}

/* What every IM scheme reports besides its command: the estimate (flux, torque at k), the
 * references, the speed and the rotor-flux angle and magnitude (updated once per speed
 * period), whether the current limit replaced the vector; the IM law has no current model. */
static inline void im_out_report(const im_dtc_t *c, dtc_out_t *o, iq_t te)
{
    o->psi_alpha_iq = c->est.psi_alpha_iq;
    o->psi_beta_iq = c->est.psi_beta_iq;
    o->te_iq = te;
    /* psi_ref: the start-up ramp, then (l_s/m) phi_r*: Casadei eq. 18's d part */
    law_out_state(o, c->te_ref_iq, c->speed_iq, c->est.theta_r, 0U, c->psi_ref_iq);
    o->psir_mag_iq = c->est.psir_mag_iq;
    o->i_limited = c->i_limited;
}

/* The end of a switching-table step (im_dtc_step, im_dtc_step_fstp) with the vector vec and its
 * legs: the legs into the history, the vector and the torque demand kept for the next step, the
 * command and the estimate out. */
static inline void im_dtc_legs_out(im_dtc_t *c, dtc_out_t *o, uint16_t vec, const swtab_legs_t *legs, iq_t te)
{
    swtab_legs_shift(&c->legs_3, &c->legs_2, &c->legs_1, legs);
    c->vec_1 = vec;
    c->tdem_1 = o->torque_dem;
    o->sa = legs->sa;
    o->sb = legs->sb;
    o->sc = legs->sc;
    o->vector = vec;
    im_out_report(c, o, te);
}

/* A switching-table step on the six-switch (fstp = 0: Casadei's tables or DSC) or the four-switch
 * inverter (fstp = 1: Hoang Table II, im_dtc_fstp.c). Each caller passes a constant, so the
 * inlined copy of each step holds only its own branch. */
static inline void im_dtc_table_step(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o, uint16_t fstp)
{
    swtab_legs_t legs;
    uint16_t vec;
    /* 1-5. Shadow set, Clarke (SSTP i_a, i_b; FSTP i_b, i_c), stator and rotor flux, torque, speed
     * and speed loop. */
    const iq_t te = im_dtc_front(c, m, o, fstp != 0U ? IM_FRONT_FSTP : IM_FRONT_LEGS);
    /* 6. References: start-up, flux weakening, Casadei eq. 19. */
    im_dtc_refs_step(c);
    /* 7. Comparators, the table (or DSC), the null-vector choice, the current limit. */
    if (fstp != 0U) {
        vec = im_dtc_select_fstp(c, te, o);
        legs = swtab_fstp_legs(vec); /* S_A = 0: leg A is the mid-point */
    } else {
        vec = im_dtc_select(c, te, o);
        legs = swtab_sstp_legs(vec);
    }
    /* 8. Outputs. */
    im_dtc_legs_out(c, o, vec, &legs, te);
}

/* The end of an SVM scheme's period (SFVC, DFOC): the SVM of c->vs_* on the measured link with
 * dead-time compensation (svm.h), the voltage the new duties will apply kept for the estimator
 * and the prediction (d_eff on the link measured now plus pwm_dv_iq, Casadei eq. 2 / Hoang eqs.
 * 1-5: (2 d_a - d_b - d_c)/3 V, (d_b - d_c)/sqrt3 V with V = V_dc + V_d - V_CE under the per-leg
 * compensation, im_dtc.h; vrec_from_legs saturates, IQ products rounded),
 * and the outputs: the PWM form (duty_iq), the estimate, the references. */
static inline void im_pwm_out(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o, iq_t te)
{
    uint16_t x;
    svm_step(&c->svm, &c->svm_p, c->vs_alpha_iq, c->vs_beta_iq, m->vdc_iq, &c->i, &c->svm_o);
    c->v2_alpha_iq = c->v1_alpha_iq;
    c->v2_beta_iq = c->v1_beta_iq;
    {
        iq_t a, b;
        const iq_t vdc = fix_add32(m->vdc_iq, c->pwm_dv_iq); /* the duty's share of the drops (im_dtc.h) */
        vrec_from_legs(c->svm_o.d_eff_iq[0], c->svm_o.d_eff_iq[1], c->svm_o.d_eff_iq[2], &a, &b);
        c->v1_alpha_iq = iq_mpy(a, vdc);
        c->v1_beta_iq = iq_mpy(b, vdc);
    }
    for (x = 0U; x < 3U; x++) {
        o->duty_iq[x] = c->svm_o.d_iq[x];
    }
    law_out_duty_only(o); /* the PWM form carries the command (duty_iq) */
    im_out_report(c, o, te);
}

/* A step of an SVM scheme: the SFVC (dfoc = 0: Casadei eqs. 18, 23, 24) or the DFOC (dfoc = 1:
 * Casadei sec. 13). Each caller passes a constant, so the inlined copy of each step holds only
 * its own branch.
 * 1-5. Shadow set, Clarke, stator and rotor flux from the modulated voltage, torque, speed and
 * speed loop (im_dtc_front, as im_dtc_step). 6. References: start-up (the magnetising ramp), T*;
 * Casadei eq. 19's |phi_s*| is not used. Once per speed period, in the step im_trim_slot,
 * the rotor-flux trim on the |phi_r| of the speed period (im_polar_due) moves the SFVC's eq. 18 d component or the
 * DFOC's i_d*. 7. The SFVC's flux regulator or the DFOC's current regulators in the rotor-flux
 * frame; the SVM is called after it, so that its frame and the regulator's are not on one chain
 * (stack). 8. SVM and outputs. */
static inline void im_svm_scheme_step(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o, uint16_t dfoc)
{
    const iq_t te = im_dtc_front(c, m, o, IM_FRONT_PWM);
    if (c->ref_due != 0U && c->div_cnt == im_trim_slot(c)) {
        c->ref_due = 0U;
        if (c->magnetised != 0U) {
            const uint16_t moved = im_psir_trim(c);
            if (dfoc != 0U) {
                im_dfoc_id_ref(c); /* the flux term moves every speed period (im_dfoc.c) */
            } else if (moved != 0U) {
                im_sfvc_kpd(c);
            }
        }
    }
    im_dtc_refs_step(c);
    if (dfoc != 0U) {
        im_dfoc_regulate(c);
    } else {
        im_sfvc_regulate(c);
    }
    im_pwm_out(c, m, o, te);
}

/* The device-drop compensation of a period (vcomp.h) into c->dva_iq, c->dvb_iq for the leg states
 * sa, sb, sc (legs_any = 0: the caller's legs are all off, the SVM schemes): by the table of the
 * currents' signs where it holds (vcomp_tab_step, bit-identical), else vcomp_step (Hoang Table III
 * per leg with the legs switching). */
static inline void im_vcomp(im_dtc_t *c, uint16_t sa, uint16_t sb, uint16_t sc, uint16_t legs_any)
{
    if (legs_any == 0U || c->vc_t.legs_free != 0U) {
        vcomp_tab_step(&c->vc_t, &c->i, &c->dva_iq, &c->dvb_iq);
    } else {
        vcomp_step(&c->vc_p, sa, sb, sc, &c->i, &c->dva_iq, &c->dvb_iq);
    }
}

/* The estimator input's part common to both schemes (currents, rotor-flux reference, speed, and
 * the current model's reference at low speed). */
static inline void im_dtc_ein_common(im_dtc_t *c, const dtc_meas_t *m)
{
    im_est_in_t *in = &c->ein;
    in->i_alpha_iq = c->i.i_alpha_iq;
    in->i_beta_iq = c->i.i_beta_iq;
    in->psir_ref_iq = c->psir_ref_iq;
    /* at low speed with the encoder, eq. 20's reference vector (im_sup_cm_ref, out of line: the
     * other periods pay a compare) */
    if (c->sup.cm_b_iq != 0) {
        im_sup_cm_ref(c, m->enc_count);
    } else {
        in->ref_vec = 0U;
    }
    in->speed_iq = c->speed_iq;
    /* in->want_polar is not read: im_dtc_front runs the CORDIC in its own steps (im_polar_due) */
    /* in->start (the voltage model's start, im_est.h) follows c->magnetised where that changes:
     * set by im_dtc_reset, cleared when the magnetisation ends (im_dtc_refs) */
}

/* The estimator's input of the modulated schemes: the voltage of the period that ends now (kept
 * by the step two periods ago, d_eff: the dead time is in it, svm.h) plus the SSTP device-drop
 * terms (vcomp.h; with the SSTP's equal drops the leg state does not matter). */
static inline void im_sfvc_estimate(im_dtc_t *c, const dtc_meas_t *m)
{
    im_est_in_t *in = &c->ein;
    im_vcomp(c, 0U, 0U, 0U, 0U);
    in->v_alpha_iq = fix_add32(c->v2_alpha_iq, c->dva_iq);
    in->v_beta_iq = fix_add32(c->v2_beta_iq, c->dvb_iq);
    im_dtc_ein_common(c, m);
}

#endif /* IM_DTC_INTERNAL_H */
