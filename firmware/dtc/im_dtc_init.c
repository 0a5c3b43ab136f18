/* im_dtc_init.c - initialisation of the IM law (im_dtc.h). Init-only code: its own file so that the
 * F2812 image keeps it in flash (archive dtc_init, firmware/CMakeLists.txt), out of the zero-wait
 * RAM the control path needs. */
#include "im_dtc_internal.h"

#include <stddef.h>

int16_t im_dtc_init(im_dtc_t *c, const dtc_config_t *cfg)
{
    dtc_refs_t r;
    const int16_t err = dtc_config_law_init_begin(c != NULL ? &c->cfg : NULL, cfg, im_dtc_check);

    if (err != DTC_OK) {
        return err;
    }

    c->est_p.estimator = cfg->est.estimator == DTC_EST_IMPROVED ? IM_EST_IMPROVED : IM_EST_VOLTAGE;
    c->est_p.rs_iq = cfg->machine.rs_iq;
    c->est_p.sigma_ls_iq = cfg->u.im.machine.sigma_ls_iq;
    c->est_p.kr_iq = cfg->u.im.machine.kr_iq;
    c->est_p.ts_pu_q31 = q31_from_iq(cfg->board.ts_pu_iq);
    c->est_p.k_in_q31 = cfg->est.k_in_q31;
    c->est_p.k_leak_q31 = cfg->est.k_leak_q31;
    c->est_p.k_lo_q31 = cfg->u.im.est.k_lo_q31;
    c->est_p.k_hi_q31 = cfg->u.im.est.k_hi_q31;
    c->est_p.w_lo_iq = cfg->u.im.est.w_lo_iq;
    c->est_p.w_hi_iq = cfg->u.im.est.w_hi_iq;
    c->est_p.k_slope_q31 = cfg->u.im.est.k_slope_q31;
    if (im_est_check(&c->est_p) != 0) {
        return DTC_ERR_FLUX_EST;
    }
    c->dt_p.td_ts_q15 = cfg->board.td_ts_q15;
    /* the six-switch inverter, or the FSTP with DTC_LAW_IM_DTC (im_dtc_check, im_dtc_fstp.c) */
    c->dt_p.fstp = cfg->board.topology == DTC_TOPO_FSTP ? 1U : 0U;
    c->il_p.i_lim_iq = cfg->prot.i_lim_iq;
    c->il_p.fstp = c->dt_p.fstp;
    c->il_box_iq = iq_mpy(cfg->prot.i_lim_iq, (iq_t)11863283L); /* 1/sqrt2 rounded down: floor(2^24 / sqrt(2)) */
    {
        /* the current prediction's constants (im_dtc_i_pred): 1/(sigma l_s) and 1/l_r = 1/(k_r m)
         * by the SVM's Newton reciprocal from a fresh seed (svm.h svm_recip; sigma l_s and l_r
         * > 0 by im_dtc_check, exact to a few LSB from 2^-7 pu), then rounded IQ products */
        const dtc_im_machine_cfg_t *im = &cfg->u.im.machine;
        const iq_t inv_sl = svm_recip(0, im->sigma_ls_iq);
        const iq_t inv_lr = svm_recip(0, iq_mpy(im->kr_iq, im->m_iq));
        c->ip_a_iq = iq_mpy(cfg->board.ts_pu_iq, inv_sl);
        c->ip_b_iq = iq_mpy(iq_mpy(cfg->board.ts_pu_iq, iq_mpy(im->rr_iq, inv_lr)), inv_sl);
        c->ip_g_iq = iq_add(iq_mpy(c->ip_a_iq, cfg->machine.rs_iq),
                            iq_mpy(c->ip_b_iq, iq_add(iq_mpy(im->m_iq, iq_mpy(im->m_iq, inv_lr)), im->sigma_ls_iq)));
        /* DSVM's mean ripple current's drop, k = r_s Ts / (9 sigma l_s), by pattern (im_dsvm.c) */
        const iq_t k = iq_mpy(iq_mpy(c->ip_a_iq, cfg->machine.rs_iq), IQ_FRAC(1, 9));
        uint16_t p;
        for (p = 0U; p < 8U; p++) {
            const uint16_t s1 = (uint16_t)((p >> 2) & 1U), s3 = (uint16_t)(p & 1U);
            c->dsvm_rip_iq[p] = s1 == s3 ? 0 : (s1 != 0U ? k : fix_neg32(k));
        }
    }
    vcomp_init(&c->vc_p, cfg->est.compensation, cfg->board.v_f_iq, cfg->board.v_ce_iq,
               cfg->board.v_d_iq, cfg->board.r_on_iq);
    vcomp_tab_init(&c->vc_t, &c->vc_p);
    /* the duty's share of the per-leg drops (im_dtc.h): Table III's state-0 minus state-1 drop
     * for i >= 0, V_d - V_CE */
    c->pwm_dv_iq = cfg->est.compensation == DTC_COMP_SSTP_PROPOSED
                       ? fix_sub32(c->vc_p.mean_iq[0][4], c->vc_p.mean_iq[1][4]) : 0;
    dtc_speed_params_from_config(&c->sm_p, &c->pi_p, cfg);
    c->isp_p.gain_w_iq = cfg->u.im.ref.gain_w_iq;
    c->isp_p.k_filt_q31 = cfg->u.im.ref.speed_filt_q31;
    c->isp_p.rr_iq = cfg->u.im.machine.rr_iq;
    c->fw_p.window = cfg->u.im.fw.window;
    c->fw_p.step_down_iq = cfg->u.im.fw.step_down_iq;
    c->fw_p.step_up_iq = cfg->u.im.fw.step_up_iq;
    c->fw_p.psi_min_iq = cfg->u.im.fw.psi_min_iq;
    c->fw_p.psi_rated_iq = cfg->speed.flux_ref_iq;
    c->fw_p.inv_psi_rated_iq = cfg->u.im.fw.inv_psi_rated_iq;
    c->fw_p.kt_iq = cfg->u.im.fw.kt_iq;
    if (cfg->u.im.fw.on != 0U && im_fw_check(&c->fw_p) != 0) {
        return DTC_ERR_WEAKENING;
    }
    c->svm_p.mode = cfg->u.im.svm_mode;
    c->svm_p.dt_comp = cfg->est.deadtime_comp;
    c->svm_p.td_iq = iq_from_q15(cfg->board.td_ts_q15);
    /* im_sfvc.c: Casadei eq. 18's components and eq. 16's slip per pu torque, times K_p where eq. 24 has
     * it (rounded IQ products, here once; the d component with the rotor-flux trim at im_dtc_reset) */
    c->sfvc_kpq_iq = iq_mpy(cfg->u.im.sfvc.kp_iq, iq_mpy(iq_mpy(cfg->u.im.machine.ks_iq, cfg->u.im.machine.sigma_lr_iq),
                                                       cfg->u.im.ref.inv_psir_ref_iq));
    c->sfvc_kslip_iq = iq_mpy(cfg->u.im.machine.rr_iq, cfg->u.im.ref.inv_psir_sq_iq);
    im_dfoc_init(c, cfg);
    /* the rotor flux from which the encoder plausibility trusts the flux angle: phi_r* / 16 (the
     * constant rotor flux of Casadei eq. 19, or the no-load one of the stator-flux reference) */
    c->plaus_psir_iq = fix_rshift_rnd32(cfg->u.im.ref.psir_ref_iq > 0
                                            ? cfg->u.im.ref.psir_ref_iq
                                            : iq_mpy(cfg->u.im.machine.inv_ks_iq, cfg->speed.flux_ref_iq),
                                        4U);
    /* Casadei eq. 19's step in the speed period (im_dtc.h ref_slot) */
    c->ref_slot = (uint16_t)(cfg->speed.speed_div > 6U ? 6U : (cfg->speed.speed_div > 2U ? 2U : 0U));
    c->cfg = cfg;
    im_sup_init(c, cfg);

    dtc_refs_start(&c->act, &c->sh, &r, cfg);
    c->te_cmd_iq = 0;
    c->te_trim_iq = 0;
    im_dtc_apply(c, &r);
    im_est_init(&c->est, &c->est_p);
    speed_meas_init(&c->sm, &c->sm_p, 0U);
    im_dtc_reset(c);
    return DTC_OK;
}

