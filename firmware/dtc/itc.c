/*
 * itc.c - indirect torque control of the PM machine (itc.h).
 */
#include "itc.h"

#include <stddef.h>

#include "lpfcorr.h"
#include "park.h"
#include "torque.h"
#include "vrec.h"

/* T* and its q-axis current i_q* = (i_q per T*) T* (itc.h), set together wherever T* changes (reset,
 * the speed loop, the torque mode's command), so that itc_cc_in need not form the product every
 * period: in speed mode T* changes at the speed-loop rate. One rounded IQ product, as before. */
static inline void itc_set_te_ref(itc_t *c, iq_t te_ref_iq)
{
    c->te_ref_iq = te_ref_iq;
    c->iq_ref_iq = iq_mpy(c->cfg->u.pm_itc.cc.iq_per_t_iq, te_ref_iq);
}

/* Adopts r (dtc_refs_adopt); in torque mode T* is the set's torque reference, which changes only
 * here, so T* and i_q* are formed here and not in every step. */
static void itc_adopt(itc_t *c, const dtc_refs_t *r)
{
    dtc_refs_adopt(&c->act, &c->pi_p, &c->pi, &c->te_trim_iq, c->te_ref_iq, r, c->cfg);
    if (c->act.mode == DTC_MODE_TORQUE) {
        itc_set_te_ref(c, c->act.torque_ref_iq);
    }
}

int16_t itc_init(itc_t *c, const dtc_config_t *cfg)
{
    dtc_refs_t r;
    const int16_t err = dtc_config_law_init_begin(c != NULL ? &c->cfg : NULL, cfg, itc_check);

    if (err != DTC_OK) {
        return err;
    }
    c->cfg = cfg;

    dtc_pm_est_params_from_config(&c->fe_p, &c->vc_p, cfg, &cfg->u.pm_itc.machine);
    {
        const uint16_t fstp = cfg->board.topology == (uint16_t)DTC_TOPO_FSTP ? 1U : 0U;
        c->var = (uint16_t)((fstp != 0U ? ITC_VAR_FSTP : 0U) |
                            (fstp != 0U && cfg->u.pm_itc.mid.g_iq > 0 ? ITC_VAR_MID_REG : 0U) |
                            (cfg->est.estimator == DTC_EST_VOLTAGE && c->vc_p.mode != (uint16_t)DTC_COMP_NONE
                                 ? ITC_VAR_VCOMP : 0U) |
                            (cfg->board.fstp_vmid_measured != 0U ? ITC_VAR_VMID_MEAS : 0U) |
                            (cfg->est.estimator != DTC_EST_VOLTAGE ? ITC_VAR_CM : 0U));
    }
    dtc_speed_params_from_config(&c->sm_p, &c->pi_p, cfg);
    {
        /* itc_vcomp's constants: F(e_B) - F(0), F(e_C) - F(0) (any current: they do not depend
         * on it) */
        static const clarke_out_t i0 = {0, 0, 0, 0, 0};
        iq_t a0, b0, a1, b1;
        uint16_t x;
        vcomp_step(&c->vc_p, 0U, 0U, 0U, &i0, &a0, &b0);
        for (x = 0U; x < 2U; x++) {
            vcomp_step(&c->vc_p, 0U, x == 0U ? 1U : 0U, x == 1U ? 1U : 0U, &i0, &a1, &b1);
            c->vcd_alpha_iq[x] = iq_sub(a1, a0);
            c->vcd_beta_iq[x] = iq_sub(b1, b0);
        }
    }
    vcomp_tab_init(&c->vc_t, &c->vc_p);
    c->cc_p.kp_iq = cfg->u.pm_itc.cc.kp_iq;
    c->cc_p.ki_ts_iq = cfg->u.pm_itc.cc.ki_ts_iq;
    c->cc_p.int_max_iq = iq_from_int(2); /* above any V_max: the link's 2/3 V_dc is < 2 pu */
    c->svm_p.mode = (uint16_t)SVM_SYMMETRIC;
    c->svm_p.dt_comp = cfg->est.deadtime_comp;
    c->svm_p.td_iq = iq_from_q15(cfg->board.td_ts_q15);
    {
        /* the mid-point current's bound: half the room the torque limit's current leaves below
         * the trip level (itc.h) */
        const iq_t room = iq_sub(cfg->prot.i_trip_iq, iq_mpy(cfg->speed.torque_limit_iq, cfg->u.pm_itc.cc.iq_per_t_iq));
        c->vmid_imax_iq = room > 0 ? fix_rshift_rnd32(room, 1U) : 0;
    }
    c->ts15_iq = iq_add(cfg->board.ts_pu_iq, fix_rshift_rnd32(cfg->board.ts_pu_iq, 1U)); /* 1.5 Ts, pu */
    c->svm4_p.dt_comp = c->svm_p.dt_comp;
    c->svm4_p.td_iq = c->svm_p.td_iq;

    dtc_refs_start(&c->act, &c->sh, &r, cfg);
    c->te_ref_iq = 0;
    itc_adopt(c, &r);

    flux_est_init(&c->fe, &c->fe_p);
    speed_meas_init(&c->sm, &c->sm_p, 0U);
    itc_reset(c);
    return DTC_OK;
}

void itc_reset(itc_t *c)
{
    const dtc_config_t *cfg = c->cfg;
    uint16_t x;

    flux_est_reset(&c->fe);
    speed_meas_reset(&c->sm, 0U);
    c->speed_primed = 0U;
    speed_pi_reset(&c->pi, 0, cfg->speed.torque_limit_iq);
    dqpi_reset(&c->cc, 0, 0);
    svm_reset(&c->svm);
    svm4_reset(&c->svm4);
    c->te_trim_iq = 0;
    c->div_cnt = 0U;
    itc_set_te_ref(c, c->act.mode == DTC_MODE_TORQUE ? c->act.torque_ref_iq : 0);
    c->speed_iq = 0;
    c->wls_iq = 0;
    c->wlq_iq = 0;
    c->wpsi_iq = 0;
    c->wpsi_ts_iq = 0;
    c->adv_iq = 0;
    c->v1_alpha_iq = 0;
    c->v1_beta_iq = 0;
    c->v2_alpha_iq = 0;
    c->v2_beta_iq = 0;
    for (x = 0U; x < 2U; x++) {
        c->d1_iq[x] = 0;
        c->d2_iq[x] = 0;
    }
    c->lpf_y_iq = 0;
    c->lpf_r_iq = 0;
    c->vmid_y_iq = 0;
    c->cc_in.meas_d_iq = 0;
    c->cc_in.meas_q_iq = 0;
    c->i_k.ia_iq = 0;
    c->i_k.ib_iq = 0;
    c->i_k.ic_iq = 0;
    c->i_k.i_alpha_iq = 0;
    c->i_k.i_beta_iq = 0;
    c->sc.cos_q15 = Q15(1.0);
    c->sc.sin_q15 = 0;
}

/* Copies the shadow set whose (even) sequence number is seq and adopts it (itc.h). */
void itc_shadow_adopt(itc_t *c, uint16_t seq)
{
    dtc_refs_t r;
    dtc_shadow_take(&c->sh, seq, &r);
    itc_adopt(c, &r);
}

/* Drop compensation of a PWM period (vcomp.h) with the effective duties d of the legs: each leg
 * spends d of the period in state 1 and 1 - d in state 0, and the compensation is a sum of
 * per-leg terms (minus the Clarke transform of the leg drops, Hoang eqs. 31-34), so its period
 * mean is F(0) + sum_x d_x (F(e_x) - F(0)), F(s) the value for the leg states s, e_x leg x alone
 * on. Hoang Table III's drop of a leg in state 1 less that in state 0 is V_CE - V_d for either current
 * sign, so F(e_x) - F(0) is a constant of the configuration (c->vcd_*, itc_init); SSTP [29] and
 * Hoang Table V do not depend on the states (their constants are 0). IQ pu; products rounded, sums
 * saturated. */
static void itc_vcomp(const itc_t *c, const clarke_out_t *i, const iq_t d[2], iq_t *va, iq_t *vb)
{
    iq_t a0, b0;
    vcomp_tab_step(&c->vc_t, i, &a0, &b0); /* F(0): vcomp_step with the legs off */
    *va = iq_add(a0, iq_add(iq_mpy(d[0], c->vcd_alpha_iq[0]), iq_mpy(d[1], c->vcd_alpha_iq[1])));
    *vb = iq_add(b0, iq_add(iq_mpy(d[0], c->vcd_beta_iq[0]), iq_mpy(d[1], c->vcd_beta_iq[1])));
}

/* The observer's input (itc.h): Clarke (Hoang eqs. 4-5) of the measured currents into c->i_k, and
 * the estimator's input c->fin on the voltage of the period just ended with its drop
 * compensation. */
void itc_observe_in(itc_t *c, const dtc_meas_t *m)
{
    const dtc_config_t *cfg = c->cfg;
    clarke_out_t *const i = &c->i_k;
    flux_est_in_t *const fin = &c->fin;
    clarke_meas(cfg->board.topology == (uint16_t)DTC_TOPO_FSTP ? 1U : 0U, m->ia_iq, m->ib_iq, m->ic_iq, i);
    flux_est_in_set(fin, c->v2_alpha_iq, c->v2_beta_iq, i->i_alpha_iq, i->i_beta_iq, m->enc_count, c->lpf_r_iq);
    if (cfg->est.estimator == DTC_EST_VOLTAGE && c->vc_p.mode != (uint16_t)DTC_COMP_NONE) {
        iq_t vfa, vfb;
        itc_vcomp(c, i, c->d2_iq, &vfa, &vfb);
        fin->v_alpha_iq = fix_add32(fin->v_alpha_iq, vfa);
        fin->v_beta_iq = fix_add32(fin->v_beta_iq, vfb);
    }
}

/* Observer (itc.h): the estimator on the voltage of the period just ended; returns the torque of
 * Hoang eq. 10 from its flux. */
iq_t itc_observe(itc_t *c, const dtc_meas_t *m)
{
    const dtc_config_t *cfg = c->cfg;
    const clarke_out_t *const i = &c->i_k;
    flux_est_in_t *const fin = &c->fin;
    itc_observe_in(c, m); /* its temporaries (Clarke, the drop compensation) are off this frame */
    if ((c->var & ITC_VAR_CM) != 0U || c->speed_primed == 0U) {
        /* the current model (Hoang eqs. 8-9): the estimator, or the voltage model's first step;
         * flux_est_seed's steps, with the encoder angle's sine and cosine taken once for it and
         * for the rotor frame of itc_cc_in and itc_i_pred (c->sc) */
        c->fe.theta_e = flux_est_angle(fin->enc_count, c->fe_p.enc_gain_q16, c->fe_p.enc_offset);
        park_sincos(c->fe.theta_e, &c->sc);
        flux_est_cm(&c->fe, fin, c->sc.sin_q15, c->sc.cos_q15);
    } else {
        /* the voltage model entered directly: through flux_est_step its frame would add to this chain */
        flux_est_vm_step(&c->fe, fin, iq_mpy(cfg->machine.rs_iq, i->i_alpha_iq),
                         iq_mpy(cfg->machine.rs_iq, i->i_beta_iq));
        park_sincos(c->fe.theta_e, &c->sc); /* the encoder's electrical angle (flux_est_angle) */
    }
    return torque_eq10(c->fe.psi_alpha_iq, c->fe.psi_beta_iq, i->i_alpha_iq, i->i_beta_iq);
}

/* Speed loop (itc.h): its step's work, out of line; itc_step calls it only where
 * speed_loop_due says the speed loop runs. */
void itc_speed(itc_t *c, const dtc_meas_t *m)
{
    const dtc_config_t *cfg = c->cfg;
    c->speed_iq = speed_meas_step(&c->sm, m->enc_count);
    /* the speed's products of the step (itc_step): w l_s, w psi_m, 1.5 w Ts */
    c->wls_iq = iq_mpy(c->speed_iq, cfg->u.pm_itc.machine.ls_iq);
    c->wlq_iq = iq_mpy(c->speed_iq, cfg->u.pm_itc.machine.lq_iq);
    c->wpsi_iq = iq_mpy(c->speed_iq, cfg->u.pm_itc.machine.psi_m_iq);
    c->wpsi_ts_iq = iq_mpy(c->wpsi_iq, cfg->board.ts_pu_iq); /* itc_i_pred's back-EMF step */
    c->adv_iq = iq_mpy(c->speed_iq, c->ts15_iq);
    if (cfg->u.pm_itc.est.lpf_comp != 0U) {
        const iq_t r = iq_mpy(cfg->u.pm_itc.est.wc_pu_iq,
                              c->lpf_y_iq = lpfcorr_recip(c->lpf_y_iq, c->speed_iq, cfg->u.pm_itc.est.lpf_wmin_iq));
        c->lpf_r_iq = c->speed_iq < 0 ? fix_neg32(r) : r;
    }
    if (c->act.mode == DTC_MODE_SPEED) {
        itc_set_te_ref(c, speed_pi_step(&c->pi, &c->pi_p, c->act.speed_ref_iq, c->speed_iq));
    }
}

void itc_cc_in(itc_t *c, const dtc_meas_t *m, iq_t vlo_iq)
{
    const dtc_config_t *cfg = c->cfg;
    dqpi_in_t *const in = &c->cc_in;
    const park_sc_t *const sc = &c->sc;

    /* c->sc: the sine and cosine of the encoder's electrical angle of this step (itc_observe) */
    park_fwd(sc, c->i_k.i_alpha_iq, c->i_k.i_beta_iq, &in->meas_d_iq, &in->meas_q_iq);
    /* the references: i_d* = 0, i_q* = c->iq_ref_iq (formed with T*: itc_set_te_ref) */
    if ((c->var & ITC_VAR_MID_REG) != 0U) {
        /* mid-point regulation: i_a* = g y, y += k_f (d - y) (itc.h), into the rotor frame */
        const iq_t d = iq_sub(vlo_iq, fix_rshift_rnd32(m->vdc_iq, 1U));
        c->vmid_y_iq = iq_add(c->vmid_y_iq, iq_mpy(cfg->u.pm_itc.mid.kf_iq, iq_sub(d, c->vmid_y_iq)));
        const iq_t ia0 = fix_clamp32(iq_mpy(cfg->u.pm_itc.mid.g_iq, c->vmid_y_iq), -c->vmid_imax_iq, c->vmid_imax_iq);
        in->ref_d_iq = iq_mpy_q15(ia0, sc->cos_q15); /* park.h of (i_a*, 0) */
        in->ref_q_iq = iq_sub(c->iq_ref_iq, iq_mpy_q15(ia0, sc->sin_q15));
    } else {
        in->ref_d_iq = 0;
        in->ref_q_iq = c->iq_ref_iq;
    }
    /* the rotor-frame EMF: v_d = -w l_q i_q, v_q = w l_d i_d + w psi_m (psi_d = l_d i_d + psi_m,
     * psi_q = l_q i_q: flux_est.h; l_q = l_d on a surface PM) */
    in->ff_d_iq = fix_neg32(iq_mpy(c->wlq_iq, in->meas_q_iq));
    in->ff_q_iq = iq_add(iq_mpy(c->wls_iq, in->meas_d_iq), c->wpsi_iq);
    if ((c->var & ITC_VAR_FSTP) != 0U) {
        const iq_t hi = iq_sub(m->vdc_iq, vlo_iq);
        in->vmax_iq = q31_mul_k(vlo_iq < hi ? vlo_iq : hi, FIX_Q31_INV_SQRT3); /* the constant > Q31_MIN */
    } else {
        in->vmax_iq = q31_mul_k(m->vdc_iq, FIX_Q31_INV_SQRT3);
    }
}

void itc_cc_out(itc_t *c)
{
    iq_t *const va = &c->vs_alpha_iq, *const vb = &c->vs_beta_iq;
    /* Stator frame, advanced by the 1.5 w Ts the rotor turns until the middle of the period the
     * command acts in: (1 + j 1.5 w Ts) (as im_dfoc.c; the magnitude error (1 + x^2)^(1/2) - 1
     * is 7e-5 at 1500 rpm, x = 0.012 rad). */
    park_inv(&c->sc, c->cc_out.v_d_iq, c->cc_out.v_q_iq, va, vb);
    iq_cmul_1jx_inline(c->adv_iq, va, vb);
}

void itc_keep(itc_t *c, const dtc_meas_t *m)
{
    iq_t va, vb;
    c->v2_alpha_iq = c->v1_alpha_iq;
    c->v2_beta_iq = c->v1_beta_iq;
    vrec_from_legs(c->svm_o.d_eff_iq[0], c->svm_o.d_eff_iq[1], c->svm_o.d_eff_iq[2], &va, &vb);
    c->v1_alpha_iq = iq_mpy(va, m->vdc_iq);
    c->v1_beta_iq = iq_mpy(vb, m->vdc_iq);
    c->d2_iq[0] = c->d1_iq[0]; /* legs B and C: what itc_vcomp weighs */
    c->d2_iq[1] = c->d1_iq[1];
    c->d1_iq[0] = c->svm_o.d_eff_iq[1];
    c->d1_iq[1] = c->svm_o.d_eff_iq[2];
}

void itc_step(itc_t *c, const dtc_meas_t *m, dtc_out_t *o)
{
    const dtc_config_t *cfg = c->cfg;
    const uint16_t var = c->var;
    clarke_out_t *const i = &c->i_k;
    iq_t vlo, te;

    /* 1. Shadow set: adopt a complete, not yet adopted set (dtc_refs.h). */
    {
        const uint16_t seq = dtc_shadow_pending(&c->sh);
        if (seq != 0U) {
            itc_shadow_adopt(c, seq);
        }
    }
    /* 2. Clarke (Hoang eqs. 4-5) and the observer (itc_observe), the speed loop. */
    te = itc_observe(c, m);
    o->speed_tick = 0U;
    if (speed_loop_due(&c->sm, &c->speed_primed, &c->div_cnt, m->enc_count) != 0U) {
        o->speed_tick = 1U;
        itc_speed(c, m);
    }
    speed_loop_advance(&c->div_cnt, cfg->speed.speed_div); /* T* in torque mode: itc_adopt */

    /* 3. Rotor frame (the encoder's electrical angle), references, current PI (dqpi.h) on the
     *    decoupling and back-EMF feed-forward, the voltage limit of the inverter, back to the
     *    stator frame (itc_cc_in, itc_cc_out). */
    vlo = (var & ITC_VAR_VMID_MEAS) != 0U ? m->vmid_iq : fix_rshift_rnd32(m->vdc_iq, 1U);
    itc_cc_in(c, m, vlo);
    dqpi_step(&c->cc, &c->cc_p, &c->cc_in, &c->cc_out);
    itc_cc_out(c);

    /* 4. SVM of the inverter (svm.h six switches, svm4.h four), the voltage it will apply kept
     *    for the observer (itc_keep). */
    if ((var & ITC_VAR_FSTP) != 0U) {
        svm4_step(&c->svm4, &c->svm4_p, c->vs_alpha_iq, c->vs_beta_iq, m->vdc_iq, vlo, i, &c->svm_o);
    } else {
        svm_step(&c->svm, &c->svm_p, c->vs_alpha_iq, c->vs_beta_iq, m->vdc_iq, i, &c->svm_o);
    }
    itc_keep(c, m);
    o->duty_iq[0] = c->svm_o.d_iq[0];
    o->duty_iq[1] = c->svm_o.d_iq[1];
    o->duty_iq[2] = c->svm_o.d_iq[2];

    /* 5. Outputs. */
    law_out_duty_only(o);
    o->psi_alpha_iq = c->fe.psi_alpha_iq;
    o->psi_beta_iq = c->fe.psi_beta_iq;
    o->te_iq = te;
    law_out_state(o, c->te_ref_iq, c->speed_iq, c->fe.theta_e, (var & ITC_VAR_CM) != 0U ? 1U : 0U,
                  c->act.flux_ref_iq);
    o->psir_mag_iq = 0;
    o->i_limited = 0U; /* the voltage limit is dqpi's (v.limited), not the current limit's */
}

/* itc_i_pred on a salient PM (l_q != l_d; l_s = l_d). With psi = l_d i + dl i_q j e^{j theta} +
 * psi_m e^{j theta} (flux_est.h) in dtc.c dtc_predict_salient's step, x = dpsi - j w Ts psi and
 * (da, db) = dpsi - j w Ts psi_m e^{j theta}:
 *   x + j w Ts l_d i = (da, db) + w Ts dl i_q e^{j theta},
 *   y_q = Im(e^{-j theta} x) = (da, db)_q - w Ts l_d i_d,
 *   i(k+1) = i + (x + j w Ts l_d i) / l_d + j e^{j theta} y_q (1/l_q - 1/l_d).
 * i_d, i_q and the angle's sine and cosine are the step's (itc_cc_in); w Ts from the speed-loop
 * rate's w. Formats: IQ pu, Q15 sine and cosine; rounded products, saturating sums (no wrap). */
static void itc_i_pred_salient(const itc_t *c, iq_t da, iq_t db, clarke_out_t *o)
{
    const dtc_pm_machine_cfg_t *m = &c->cfg->u.pm_itc.machine;
    const iq_t wts = iq_mpy(c->speed_iq, c->cfg->board.ts_pu_iq);
    const iq_t e = iq_mpy(wts, iq_mpy(c->fe_p.dl_iq, c->cc_in.meas_q_iq));
    const iq_t yq = fix_sub32(flux_est_park_q(da, db, c->sc.sin_q15, c->sc.cos_q15),
                              iq_mpy(wts, iq_mpy(m->ls_iq, c->cc_in.meas_d_iq)));
    const iq_t k = iq_mpy(fix_sub32(c->fe_p.inv_lq_iq, m->inv_ls_iq), yq);
    const iq_t xa = fix_add32(da, iq_mpy_q15(e, c->sc.cos_q15));
    const iq_t xb = fix_add32(db, iq_mpy_q15(e, c->sc.sin_q15));
    clarke_inv(fix_sub32(iq_add(c->i_k.i_alpha_iq, iq_mpy(m->inv_ls_iq, xa)), iq_mpy_q15(k, c->sc.sin_q15)),
               fix_add32(iq_add(c->i_k.i_beta_iq, iq_mpy(m->inv_ls_iq, xb)), iq_mpy_q15(k, c->sc.cos_q15)), o);
}

void itc_i_pred(const itc_t *c, iq_t i1[3])
{
    const dtc_config_t *cfg = c->cfg;
    const iq_t ts = cfg->board.ts_pu_iq;
    const iq_t inv_ls = cfg->u.pm_itc.machine.inv_ls_iq;
    const iq_t ets = c->wpsi_ts_iq; /* w psi_m Ts, at the speed-loop rate */
    /* Ts (v - r_s i) - w Ts j psi_r, psi_r = psi_m (cos, sin): j psi_r = (-sin, cos) psi_m */
    const iq_t da = fix_add32(iq_mpy(ts, iq_sub(c->v2_alpha_iq, iq_mpy(cfg->machine.rs_iq, c->i_k.i_alpha_iq))),
                              iq_mpy_q15(ets, c->sc.sin_q15));
    const iq_t db = fix_sub32(iq_mpy(ts, iq_sub(c->v2_beta_iq, iq_mpy(cfg->machine.rs_iq, c->i_k.i_beta_iq))),
                              iq_mpy_q15(ets, c->sc.cos_q15));
    clarke_out_t o;
    if (c->fe_p.dl_iq != 0) {
        itc_i_pred_salient(c, da, db, &o);
    } else {
        clarke_inv(iq_add(c->i_k.i_alpha_iq, iq_mpy(inv_ls, da)), iq_add(c->i_k.i_beta_iq, iq_mpy(inv_ls, db)), &o);
    }
    i1[0] = o.ia_iq;
    i1[1] = o.ib_iq;
    i1[2] = o.ic_iq;
}
