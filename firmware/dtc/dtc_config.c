#include "dtc_config.h"

#include <stddef.h>

/* Largest encoder gain accepted: half an electrical turn per count (Q16). Anything coarser
 * aliases the electrical angle (fewer than two counts per electrical turn). */
#define DTC_ENC_GAIN_MAX ((uint32_t)1U << 31)

/* Each part's check returns DTC_OK or the code, and points *f at the field's name. */
#define DTC_REFUSE(cond, code, name) \
    do {                             \
        if (cond) {                  \
            *f = (name);             \
            return (code);           \
        }                            \
    } while (0)

static int16_t dtc_board_check(const dtc_board_cfg_t *b, const char **f)
{
    DTC_REFUSE(b->v_base_mv == 0U, DTC_ERR_BASE, "board.v_base_mv");
    DTC_REFUSE(b->i_base_ma == 0U, DTC_ERR_BASE, "board.i_base_ma");
    DTC_REFUSE(b->w_base_mrad_s == 0U, DTC_ERR_BASE, "board.w_base_mrad_s");
    DTC_REFUSE(b->topology > DTC_TOPO_FSTP, DTC_ERR_VARIANT, "board.topology");
    DTC_REFUSE(b->fstp_vmid_measured > 1U, DTC_ERR_VARIANT, "board.fstp_vmid_measured");
    DTC_REFUSE(b->ts_pu_iq <= 0, DTC_ERR_DELAY, "board.ts_pu_iq");
    DTC_REFUSE(b->td_ts_q15 < 0 || b->td_ts_q15 >= Q15(0.5), DTC_ERR_DEADTIME, "board.td_ts_q15");
    DTC_REFUSE(b->v_f_iq < 0, DTC_ERR_DROP, "board.v_f_iq");
    DTC_REFUSE(b->v_ce_iq < 0, DTC_ERR_DROP, "board.v_ce_iq");
    DTC_REFUSE(b->v_d_iq < 0, DTC_ERR_DROP, "board.v_d_iq");
    DTC_REFUSE(b->r_on_iq < 0, DTC_ERR_DROP, "board.r_on_iq");
    DTC_REFUSE(b->enc_counts < 4U, DTC_ERR_ENCODER, "board.enc_counts");
    DTC_REFUSE(b->enc_gain_q16 == 0U || b->enc_gain_q16 > DTC_ENC_GAIN_MAX, DTC_ERR_ENCODER,
               "board.enc_gain_q16");
    DTC_REFUSE(b->adc_i_gain_iq <= 0, DTC_ERR_ADC, "board.adc_i_gain_iq");
    DTC_REFUSE(b->adc_vdc_gain_iq <= 0, DTC_ERR_ADC, "board.adc_vdc_gain_iq");
    DTC_REFUSE(b->adc_vmid_gain_iq <= 0, DTC_ERR_ADC, "board.adc_vmid_gain_iq");
    DTC_REFUSE(b->adc_i_offset[0] > 4095U || b->adc_i_offset[1] > 4095U ||
                   b->adc_i_offset[2] > 4095U,
               DTC_ERR_ADC, "board.adc_i_offset");
    DTC_REFUSE(b->adc_vdc_offset > 4095U, DTC_ERR_ADC, "board.adc_vdc_offset");
    DTC_REFUSE(b->adc_vmid_offset > 4095U, DTC_ERR_ADC, "board.adc_vmid_offset");
    DTC_REFUSE(b->vmid_cal > 1U, DTC_ERR_POLARITY, "board.vmid_cal");
    DTC_REFUSE(b->i_sensors3 > 1U, DTC_ERR_FAULTDET, "board.i_sensors3");
    return DTC_OK;
}

/* Trip levels the ADC can see. The trips fire on a reading strictly above the level (app_core.c),
 * so a level at or above the largest reading never fires: the reading clamps first. Current:
 * the largest |i| a measured channel reads is its gain times the smaller side of its offset, in
 * counts, less the calibration's tolerance DTC_ADC_OFFSET_TOL_COUNTS (the calibrated offset may
 * sit that far off nominal); the channels are the measured ones (all three, or SSTP A and B,
 * FSTP B and C). DC link: the gain times the counts above its offset. Init only; 64-bit products
 * of a gain (IQ) and a count (< 2^12) cannot overflow. */
static int16_t dtc_range_check(const dtc_config_t *c, const char **f)
{
    const dtc_board_cfg_t *b = &c->board;
    uint16_t k;
    int64_t head = 4095;
    for (k = 0U; k < 3U; k++) {
        const int64_t lo = (int64_t)b->adc_i_offset[k], hi = 4095 - (int64_t)b->adc_i_offset[k];
        const uint16_t measured =
            (uint16_t)(b->i_sensors3 != 0U || (b->topology == DTC_TOPO_FSTP ? k != 0U : k != 2U));
        if (measured != 0U) {
            head = lo < head ? lo : head;
            head = hi < head ? hi : head;
        }
    }
    head -= DTC_ADC_OFFSET_TOL_COUNTS;
    DTC_REFUSE((int64_t)c->prot.i_trip_iq >= (int64_t)b->adc_i_gain_iq * head, DTC_ERR_LIMIT, "prot.i_trip_iq");
    DTC_REFUSE((int64_t)c->prot.vdc_max_iq >= (int64_t)b->adc_vdc_gain_iq * (4095 - (int64_t)b->adc_vdc_offset),
               DTC_ERR_LIMIT, "prot.vdc_max_iq");
    return DTC_OK;
}

static int16_t dtc_protect_check(const dtc_protect_cfg_t *p, const char **f)
{
    DTC_REFUSE(p->i_trip_iq <= 0, DTC_ERR_LIMIT, "prot.i_trip_iq");
    DTC_REFUSE(p->vdc_max_iq <= 0, DTC_ERR_LIMIT, "prot.vdc_max_iq");
    DTC_REFUSE(p->vdc_min_iq < 0 || p->vdc_min_iq >= p->vdc_max_iq, DTC_ERR_LIMIT, "prot.vdc_min_iq");
    DTC_REFUSE(p->i_lim_iq < 0 || (p->i_lim_iq > 0 && p->i_lim_iq >= p->i_trip_iq), DTC_ERR_ILIM,
               "prot.i_lim_iq");
    DTC_REFUSE(p->stall_speed_periods == 0U, DTC_ERR_SPEED, "prot.stall_speed_periods");
    DTC_REFUSE(p->i_hold_iq < 0 || p->i_hold_iq >= p->i_trip_iq, DTC_ERR_ILIM, "prot.i_hold_iq");
    DTC_REFUSE(p->i_sum_max_iq < 0, DTC_ERR_FAULTDET, "prot.i_sum_max_iq");
    DTC_REFUSE(p->leg_i_min_iq < 0, DTC_ERR_FAULTDET, "prot.leg_i_min_iq");
    DTC_REFUSE(p->enc_freeze_speed_iq < 0, DTC_ERR_FAULTDET, "prot.enc_freeze_speed_iq");
    DTC_REFUSE(p->overspeed_iq < 0, DTC_ERR_LIMIT, "prot.overspeed_iq");
    DTC_REFUSE(p->i_plaus > 1U || (p->i_plaus != 0U && p->leg_i_min_iq <= 0), DTC_ERR_FAULTDET, "prot.i_plaus");
    return DTC_OK;
}

static int16_t dtc_machine_check(const dtc_machine_cfg_t *m, uint16_t law, const char **f)
{
    DTC_REFUSE(m->pole_pairs == 0U, DTC_ERR_ENCODER, "machine.pole_pairs");
    DTC_REFUSE(m->rs_iq < 0, DTC_ERR_MACHINE, "machine.rs_iq");
    if (law == DTC_LAW_PM_DTC) {
        DTC_REFUSE(m->pm.ls_iq <= 0, DTC_ERR_MACHINE, "machine.pm.ls_iq");
        DTC_REFUSE(m->pm.psi_m_iq <= 0, DTC_ERR_MACHINE, "machine.pm.psi_m_iq");
        DTC_REFUSE(m->pm.inv_ls_iq <= 0, DTC_ERR_MACHINE, "machine.pm.inv_ls_iq");
    } else {
        DTC_REFUSE(m->im.rr_iq <= 0, DTC_ERR_MACHINE, "machine.im.rr_iq");
        DTC_REFUSE(m->im.sigma_ls_iq <= 0, DTC_ERR_MACHINE, "machine.im.sigma_ls_iq");
        DTC_REFUSE(m->im.sigma_lr_iq <= 0, DTC_ERR_MACHINE, "machine.im.sigma_lr_iq");
        DTC_REFUSE(m->im.kr_iq <= 0, DTC_ERR_MACHINE, "machine.im.kr_iq");
        DTC_REFUSE(m->im.ks_iq <= 0, DTC_ERR_MACHINE, "machine.im.ks_iq");
        DTC_REFUSE(m->im.inv_ks_iq <= 0, DTC_ERR_MACHINE, "machine.im.inv_ks_iq");
        DTC_REFUSE(m->im.m_iq <= 0, DTC_ERR_MACHINE, "machine.im.m_iq");
    }
    return DTC_OK;
}

static int16_t dtc_est_check(const dtc_est_cfg_t *e, uint16_t law, uint16_t topology, const char **f)
{
    if (law == DTC_LAW_PM_DTC) {
        DTC_REFUSE(e->estimator > DTC_EST_CURRENT, DTC_ERR_VARIANT, "est.estimator");
    } else {
        DTC_REFUSE(e->estimator != DTC_EST_VOLTAGE && e->estimator != DTC_EST_IMPROVED,
                   DTC_ERR_VARIANT, "est.estimator");
    }
    DTC_REFUSE(e->compensation > DTC_COMP_FSTP_PROPOSED ||
                   (topology == DTC_TOPO_SSTP && e->compensation >= DTC_COMP_FSTP_SIMPLE) ||
                   (topology == DTC_TOPO_FSTP && e->compensation == DTC_COMP_SSTP),
               DTC_ERR_COMPENSATION, "est.compensation");
    DTC_REFUSE(e->k_in_q31 <= 0, DTC_ERR_FLUX_EST, "est.k_in_q31");
    DTC_REFUSE(e->k_leak_q31 <= 0, DTC_ERR_FLUX_EST, "est.k_leak_q31");
    DTC_REFUSE(e->handover_speed_iq < 0, DTC_ERR_HANDOVER, "est.handover_speed_iq");
    DTC_REFUSE(e->handover_hyst_iq < 0 || e->handover_hyst_iq > e->handover_speed_iq,
               DTC_ERR_HANDOVER, "est.handover_hyst_iq");
    DTC_REFUSE(e->delay_comp > 1U, DTC_ERR_DELAY, "est.delay_comp");
    DTC_REFUSE(e->deadtime_comp > 1U, DTC_ERR_DEADTIME, "est.deadtime_comp");
    DTC_REFUSE(e->polarity_mid > 1U, DTC_ERR_POLARITY, "est.polarity_mid");
    DTC_REFUSE(e->lpf_comp > 1U, DTC_ERR_LPFCOMP, "est.lpf_comp");
    DTC_REFUSE(e->lpf_comp != 0U && e->wc_pu_iq <= 0, DTC_ERR_LPFCOMP, "est.wc_pu_iq");
    DTC_REFUSE(e->lpf_comp != 0U && e->lpf_wmin_iq <= 0, DTC_ERR_LPFCOMP, "est.lpf_wmin_iq");
    DTC_REFUSE(e->dc_supp > 1U, DTC_ERR_DCSUPP, "est.dc_supp");
    DTC_REFUSE(e->dc_supp != 0U && e->dcs_k_iq <= 0, DTC_ERR_DCSUPP, "est.dcs_k_iq");
    DTC_REFUSE(e->vmid_g_iq < 0, DTC_ERR_DCSUPP, "est.vmid_g_iq");
    DTC_REFUSE(e->vmid_beta_s_iq < 0, DTC_ERR_DCSUPP, "est.vmid_beta_s_iq");
    if (law == DTC_LAW_IM_DTC && e->estimator == DTC_EST_IMPROVED) {
        DTC_REFUSE(e->im_k_lo_q31 <= 0, DTC_ERR_FLUX_EST, "est.im_k_lo_q31");
        DTC_REFUSE(e->im_k_hi_q31 <= 0, DTC_ERR_FLUX_EST, "est.im_k_hi_q31");
        DTC_REFUSE(e->im_w_lo_iq < 0, DTC_ERR_FLUX_EST, "est.im_w_lo_iq");
        DTC_REFUSE(e->im_w_hi_iq < e->im_w_lo_iq, DTC_ERR_FLUX_EST, "est.im_w_hi_iq");
    }
    return DTC_OK;
}

static int16_t dtc_switch_check(const dtc_switch_cfg_t *s, uint16_t law, const char **f)
{
    DTC_REFUSE(s->sstp_table > (law == DTC_LAW_IM_DTC ? DTC_ST_SPEED : DTC_ST_D), DTC_ERR_VARIANT,
               "sw.sstp_table");
    DTC_REFUSE(s->scheme > (law == DTC_LAW_IM_DTC ? DTC_SCHEME_DSVM : DTC_SCHEME_DTC),
               DTC_ERR_VARIANT, "sw.scheme");
    DTC_REFUSE(s->flux_band_iq < 0, DTC_ERR_BAND, "sw.flux_band_iq");
    DTC_REFUSE(s->torque_band_iq < 0, DTC_ERR_BAND, "sw.torque_band_iq");
    if (law == DTC_LAW_IM_DTC) {
        DTC_REFUSE(s->im_table_speed_iq < 0, DTC_ERR_VARIANT, "sw.im_table_speed_iq");
        DTC_REFUSE(s->im_fw_on > 1U, DTC_ERR_WEAKENING, "sw.im_fw_on");
        if (s->im_fw_on != 0U) {
            DTC_REFUSE(s->im_fw_window < 20U, DTC_ERR_WEAKENING, "sw.im_fw_window");
            DTC_REFUSE(s->im_fw_step_down_iq <= 0, DTC_ERR_WEAKENING, "sw.im_fw_step_down_iq");
            DTC_REFUSE(s->im_fw_step_up_iq <= 0, DTC_ERR_WEAKENING, "sw.im_fw_step_up_iq");
            DTC_REFUSE(s->im_fw_psi_min_iq <= 0, DTC_ERR_WEAKENING, "sw.im_fw_psi_min_iq");
            DTC_REFUSE(s->im_fw_inv_psi_rated_iq <= 0, DTC_ERR_WEAKENING, "sw.im_fw_inv_psi_rated_iq");
            DTC_REFUSE(s->im_fw_kt_iq <= 0, DTC_ERR_WEAKENING, "sw.im_fw_kt_iq");
        }
        if (s->scheme == DTC_SCHEME_SFVC || s->scheme == DTC_SCHEME_DFOC) {
            /* section 12's flux weakening acts on the torque comparator, which SFVC and DFOC have
             * not */
            DTC_REFUSE(s->im_fw_on != 0U, DTC_ERR_VARIANT, "sw.im_fw_on");
            DTC_REFUSE(s->svm_mode > 1U, DTC_ERR_SVM, "sw.svm_mode");
        }
        if (s->scheme == DTC_SCHEME_SFVC) {
            DTC_REFUSE(s->sfvc_kp_iq <= 0, DTC_ERR_SVM, "sw.sfvc_kp_iq");
        }
        if (s->scheme == DTC_SCHEME_DSVM) {
            /* the torque comparator is five-level (hyst5_t), not the one section 12 watches */
            DTC_REFUSE(s->im_fw_on != 0U, DTC_ERR_VARIANT, "sw.im_fw_on");
            DTC_REFUSE(s->dsvm_torque_band2_iq < s->torque_band_iq, DTC_ERR_BAND, "sw.dsvm_torque_band2_iq");
        }
        if (s->scheme == DTC_SCHEME_DFOC) {
            DTC_REFUSE(s->dfoc_kp_iq <= 0, DTC_ERR_SVM, "sw.dfoc_kp_iq");
            DTC_REFUSE(s->dfoc_ki_ts_iq < 0, DTC_ERR_SVM, "sw.dfoc_ki_ts_iq");
            DTC_REFUSE(s->dfoc_id_ref_iq <= 0, DTC_ERR_SVM, "sw.dfoc_id_ref_iq");
            DTC_REFUSE(s->dfoc_iq_per_t_iq <= 0, DTC_ERR_SVM, "sw.dfoc_iq_per_t_iq");
        }
    }
    return DTC_OK;
}

static int16_t dtc_speed_check(const dtc_speed_cfg_t *s, uint16_t law, const char **f)
{
    DTC_REFUSE(s->mode > DTC_MODE_TORQUE, DTC_ERR_VARIANT, "speed.mode");
    DTC_REFUSE(s->sensor > (law == DTC_LAW_IM_DTC ? DTC_SPEED_NONE : DTC_SPEED_ENCODER),
               DTC_ERR_VARIANT, "speed.sensor");
    DTC_REFUSE(s->speed_div == 0U, DTC_ERR_SPEED, "speed.speed_div");
    DTC_REFUSE(s->speed_k_iq <= 0, DTC_ERR_SPEED, "speed.speed_k_iq");
    DTC_REFUSE(s->speed_min_counts == 0U, DTC_ERR_SPEED, "speed.speed_min_counts");
    DTC_REFUSE(s->kp_iq < 0, DTC_ERR_PI, "speed.kp_iq");
    DTC_REFUSE(s->ki_ts_iq < 0, DTC_ERR_PI, "speed.ki_ts_iq");
    DTC_REFUSE(s->torque_limit_iq <= 0, DTC_ERR_PI, "speed.torque_limit_iq");
    DTC_REFUSE(s->torque_trim_k_q15 < 0, DTC_ERR_PI, "speed.torque_trim_k_q15");
    DTC_REFUSE(s->flux_ref_iq <= 0, DTC_ERR_REFERENCE, "speed.flux_ref_iq");
    DTC_REFUSE(s->speed_limit_iq <= 0, DTC_ERR_REFERENCE, "speed.speed_limit_iq");
    DTC_REFUSE(s->speed_ref_iq > s->speed_limit_iq || s->speed_ref_iq < -s->speed_limit_iq,
               DTC_ERR_REFERENCE, "speed.speed_ref_iq");
    DTC_REFUSE(s->torque_ref_iq > s->torque_limit_iq || s->torque_ref_iq < -s->torque_limit_iq,
               DTC_ERR_REFERENCE, "speed.torque_ref_iq");
    if (law == DTC_LAW_IM_DTC) {
        DTC_REFUSE(s->psir_ref_iq < 0, DTC_ERR_REFERENCE, "speed.psir_ref_iq");
        DTC_REFUSE(s->psir_ref_iq > 0 && s->inv_psir_ref_iq <= 0, DTC_ERR_REFERENCE,
                   "speed.inv_psir_ref_iq");
        DTC_REFUSE(s->inv_psir_sq_iq <= 0, DTC_ERR_REFERENCE, "speed.inv_psir_sq_iq");
        DTC_REFUSE(s->im_gain_w_iq <= 0, DTC_ERR_SPEED, "speed.im_gain_w_iq");
        DTC_REFUSE(s->im_speed_filt_q31 <= 0, DTC_ERR_SPEED, "speed.im_speed_filt_q31");
        DTC_REFUSE(s->im_magn_periods == 0U, DTC_ERR_STARTUP, "speed.im_magn_periods");
        DTC_REFUSE(s->im_magn_ramp_iq <= 0, DTC_ERR_STARTUP, "speed.im_magn_ramp_iq");
        DTC_REFUSE(s->im_magn_k_q31 <= 0, DTC_ERR_STARTUP, "speed.im_magn_k_q31");
    }
    return DTC_OK;
}

int16_t dtc_config_check(const dtc_config_t *cfg, const char **field)
{
    const char *dummy = "";
    const char **f = field != NULL ? field : &dummy;
    int16_t err;

    *f = "";
    if (cfg == NULL) {
        return DTC_ERR_NULL;
    }
    DTC_REFUSE(cfg->version != DTC_CONFIG_VERSION, DTC_ERR_VERSION, "version");
    DTC_REFUSE(cfg->law > DTC_LAW_IM_DTC, DTC_ERR_VARIANT, "law");
    /* Casadei's tables, DSC and the IM estimators are written for the six-switch inverter. */
    DTC_REFUSE(cfg->law == DTC_LAW_IM_DTC && cfg->board.topology != DTC_TOPO_SSTP, DTC_ERR_VARIANT,
               "board.topology");
    err = dtc_board_check(&cfg->board, f);
    if (err == DTC_OK) {
        err = dtc_protect_check(&cfg->prot, f);
    }
    if (err == DTC_OK) {
        err = dtc_range_check(cfg, f);
    }
    if (err == DTC_OK) {
        /* the mid-point terms need a measured FSTP mid-point; the restoring term also the voltage
         * model and the mid-point calibration it corrects for (dtc.c dtc_vmid_beta) */
        const uint16_t mid = (uint16_t)(cfg->board.topology == DTC_TOPO_FSTP && cfg->board.fstp_vmid_measured != 0U);
        if (cfg->est.vmid_g_iq > 0 && mid == 0U) {
            *f = "est.vmid_g_iq";
            err = DTC_ERR_DCSUPP;
        } else if (cfg->est.vmid_beta_s_iq > 0 &&
                   (mid == 0U || cfg->est.estimator != DTC_EST_VOLTAGE || cfg->board.vmid_cal == 0U)) {
            *f = "est.vmid_beta_s_iq";
            err = DTC_ERR_DCSUPP;
        }
    }
    if (err == DTC_OK && cfg->prot.overspeed_iq > 0 && cfg->prot.overspeed_iq <= cfg->speed.speed_limit_iq) {
        *f = "prot.overspeed_iq"; /* at or below the speed limit a permitted reference would trip */
        err = DTC_ERR_LIMIT;
    }
    if (err == DTC_OK && cfg->prot.i_sum_max_iq > 0 && cfg->board.i_sensors3 == 0U) {
        *f = "prot.i_sum_max_iq"; /* the sum of two measured and one derived current is 0 */
        err = DTC_ERR_FAULTDET;
    }
    if (err == DTC_OK) {
        err = dtc_machine_check(&cfg->machine, cfg->law, f);
    }
    if (err == DTC_OK) {
        err = dtc_est_check(&cfg->est, cfg->law, cfg->board.topology, f);
    }
    if (err == DTC_OK) {
        err = dtc_switch_check(&cfg->sw, cfg->law, f);
    }
    if (err == DTC_OK) {
        err = dtc_speed_check(&cfg->speed, cfg->law, f);
    }
    if (err == DTC_OK && cfg->law == DTC_LAW_IM_DTC &&
        (cfg->sw.scheme == DTC_SCHEME_SFVC || cfg->sw.scheme == DTC_SCHEME_DFOC)) {
        /* SFVC (eq. 18) and DFOC take the rotor-flux command (and its reciprocal) */
        DTC_REFUSE(cfg->speed.psir_ref_iq <= 0, DTC_ERR_REFERENCE, "speed.psir_ref_iq");
    }
    if (err == DTC_OK && cfg->law == DTC_LAW_IM_DTC && cfg->sw.scheme == DTC_SCHEME_SFVC) {
        /* K_p Ts <= 1 (a larger gain overshoots the flux error every period) */
        DTC_REFUSE(iq_mpy(cfg->sw.sfvc_kp_iq, cfg->board.ts_pu_iq) > IQ(1.0), DTC_ERR_SVM, "sw.sfvc_kp_iq");
    }
    return err;
}

int16_t dtc_config_validate(const dtc_config_t *cfg)
{
    return dtc_config_check(cfg, NULL);
}

int16_t dtc_config_validate_for(const dtc_config_t *cfg, uint16_t law)
{
    const int16_t err = dtc_config_validate(cfg);
    if (err != DTC_OK) {
        return err;
    }
    return cfg->law == law ? DTC_OK : DTC_ERR_VARIANT;
}
