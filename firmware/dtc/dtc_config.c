#include "dtc_config.h"

#include <stddef.h>

/* Largest encoder gain accepted: half an electrical turn per count (Q16). Anything coarser
 * aliases the electrical angle (fewer than two counts per electrical turn). */
#define DTC_ENC_GAIN_MAX ((uint32_t)1U << 31)

int16_t dtc_config_validate(const dtc_config_t *cfg)
{
    if (cfg == NULL) {
        return DTC_ERR_NULL;
    }
    if (cfg->version != DTC_CONFIG_VERSION) {
        return DTC_ERR_VERSION;
    }
    if (cfg->topology > DTC_TOPO_FSTP || cfg->estimator > DTC_EST_CURRENT ||
        cfg->sstp_table > DTC_ST_D || cfg->mode > DTC_MODE_TORQUE ||
        cfg->fstp_vmid_measured > 1U) {
        return DTC_ERR_VARIANT;
    }
    if (cfg->compensation > DTC_COMP_FSTP_PROPOSED ||
        (cfg->topology == DTC_TOPO_SSTP && cfg->compensation >= DTC_COMP_FSTP_SIMPLE) ||
        (cfg->topology == DTC_TOPO_FSTP && cfg->compensation == DTC_COMP_SSTP)) {
        return DTC_ERR_COMPENSATION;
    }
    if (cfg->rs_iq < 0 || cfg->ls_iq <= 0 || cfg->psi_m_iq <= 0) {
        return DTC_ERR_MACHINE;
    }
    if (cfg->k_in_q31 <= 0 || cfg->k_leak_q31 <= 0) {
        return DTC_ERR_FLUX_EST;
    }
    if (cfg->enc_counts < 4U || cfg->enc_gain_q16 == 0U || cfg->enc_gain_q16 > DTC_ENC_GAIN_MAX ||
        cfg->pole_pairs == 0U) {
        return DTC_ERR_ENCODER;
    }
    if (cfg->flux_band_iq < 0 || cfg->torque_band_iq < 0) {
        return DTC_ERR_BAND;
    }
    if (cfg->speed_div == 0U || cfg->speed_k_iq <= 0 || cfg->speed_min_counts == 0U ||
        cfg->stall_speed_periods == 0U) {
        return DTC_ERR_SPEED;
    }
    if (cfg->kp_iq < 0 || cfg->ki_ts_iq < 0 || cfg->torque_limit_iq <= 0 ||
        cfg->torque_trim_k_q15 < 0) {
        return DTC_ERR_PI;
    }
    if (cfg->flux_ref_iq <= 0 || cfg->speed_limit_iq <= 0 ||
        cfg->speed_ref_iq > cfg->speed_limit_iq || cfg->speed_ref_iq < -cfg->speed_limit_iq ||
        cfg->torque_ref_iq > cfg->torque_limit_iq || cfg->torque_ref_iq < -cfg->torque_limit_iq) {
        return DTC_ERR_REFERENCE;
    }
    if (cfg->v_f_iq < 0 || cfg->v_ce_iq < 0 || cfg->v_d_iq < 0 || cfg->r_on_iq < 0) {
        return DTC_ERR_DROP;
    }
    if (cfg->adc_i_gain_iq <= 0 || cfg->adc_vdc_gain_iq <= 0 || cfg->adc_vmid_gain_iq <= 0 ||
        cfg->adc_i_offset[0] > 4095U || cfg->adc_i_offset[1] > 4095U ||
        cfg->adc_i_offset[2] > 4095U || cfg->adc_vdc_offset > 4095U ||
        cfg->adc_vmid_offset > 4095U) {
        return DTC_ERR_ADC;
    }
    if (cfg->v_base_mv == 0U || cfg->i_base_ma == 0U || cfg->w_base_mrad_s == 0U) {
        return DTC_ERR_BASE;
    }
    if (cfg->i_trip_iq <= 0 || cfg->vdc_max_iq <= 0 || cfg->vdc_min_iq < 0 ||
        cfg->vdc_min_iq >= cfg->vdc_max_iq) {
        return DTC_ERR_LIMIT;
    }
    if (cfg->handover_speed_iq < 0 || cfg->handover_hyst_iq < 0 ||
        cfg->handover_hyst_iq > cfg->handover_speed_iq) {
        return DTC_ERR_HANDOVER;
    }
    if (cfg->delay_comp > 1U || cfg->ts_pu_iq <= 0 || cfg->inv_ls_iq <= 0) {
        return DTC_ERR_DELAY;
    }
    if (cfg->deadtime_comp > 1U || cfg->td_ts_q15 < 0 || cfg->td_ts_q15 >= Q15(0.5)) {
        return DTC_ERR_DEADTIME;
    }
    if (cfg->i_lim_iq < 0 || (cfg->i_lim_iq > 0 && cfg->i_lim_iq >= cfg->i_trip_iq)) {
        return DTC_ERR_ILIM;
    }
    if (cfg->polarity_mid > 1U || cfg->vmid_cal > 1U) {
        return DTC_ERR_POLARITY;
    }
    if (cfg->lpf_comp > 1U || (cfg->lpf_comp != 0U && (cfg->wc_pu_iq <= 0 || cfg->lpf_wmin_iq <= 0))) {
        return DTC_ERR_LPFCOMP;
    }
    if (cfg->dc_supp > 1U || (cfg->dc_supp != 0U && cfg->dcs_k_iq <= 0) || cfg->vmid_g_iq < 0) {
        return DTC_ERR_DCSUPP;
    }
    return DTC_OK;
}
