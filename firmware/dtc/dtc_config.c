#include "dtc_config.h"

#include <stddef.h>

/* Largest encoder gain accepted: half an electrical turn per count (Q16). Anything coarser
 * aliases the electrical angle (fewer than two counts per electrical turn). */
#define DTC_ENC_GAIN_MAX ((uint32_t)1U << 31)

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

static int16_t dtc_machine_check(const dtc_machine_cfg_t *m, const char **f)
{
    DTC_REFUSE(m->pole_pairs == 0U, DTC_ERR_ENCODER, "machine.pole_pairs");
    DTC_REFUSE(m->rs_iq < 0, DTC_ERR_MACHINE, "machine.rs_iq");
    return DTC_OK;
}

static int16_t dtc_est_check(const dtc_est_cfg_t *e, uint16_t topology, const char **f)
{
    DTC_REFUSE(e->estimator > DTC_EST_IMPROVED, DTC_ERR_VARIANT, "est.estimator");
    DTC_REFUSE(e->compensation > DTC_COMP_FSTP_PROPOSED ||
                   (topology == DTC_TOPO_SSTP && e->compensation >= DTC_COMP_FSTP_SIMPLE) ||
                   (topology == DTC_TOPO_FSTP && e->compensation == DTC_COMP_SSTP),
               DTC_ERR_COMPENSATION, "est.compensation");
    DTC_REFUSE(e->k_in_q31 <= 0, DTC_ERR_FLUX_EST, "est.k_in_q31");
    DTC_REFUSE(e->k_leak_q31 <= 0, DTC_ERR_FLUX_EST, "est.k_leak_q31");
    DTC_REFUSE(e->deadtime_comp > 1U, DTC_ERR_DEADTIME, "est.deadtime_comp");
    return DTC_OK;
}

static int16_t dtc_speed_check(const dtc_speed_cfg_t *s, const char **f)
{
    DTC_REFUSE(s->mode > DTC_MODE_TORQUE, DTC_ERR_VARIANT, "speed.mode");
    DTC_REFUSE(s->sensor > DTC_SPEED_NONE, DTC_ERR_VARIANT, "speed.sensor");
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
    return DTC_OK;
}

int16_t dtc_config_check_common(const dtc_config_t *cfg, const char **field)
{
    const char *dummy = "";
    const char **f = field != NULL ? field : &dummy;
    int16_t err;

    *f = "";
    if (cfg == NULL) {
        return DTC_ERR_NULL;
    }
    DTC_REFUSE(cfg->version != DTC_CONFIG_VERSION, DTC_ERR_VERSION, "version");
    DTC_REFUSE(cfg->law >= DTC_LAW_COUNT, DTC_ERR_VARIANT, "law");
    err = dtc_board_check(&cfg->board, f);
    if (err == DTC_OK) {
        err = dtc_protect_check(&cfg->prot, f);
    }
    if (err == DTC_OK) {
        err = dtc_range_check(cfg, f);
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
        err = dtc_machine_check(&cfg->machine, f);
    }
    if (err == DTC_OK) {
        err = dtc_est_check(&cfg->est, cfg->board.topology, f);
    }
    if (err == DTC_OK) {
        err = dtc_speed_check(&cfg->speed, f);
    }
    return err;
}

int16_t dtc_config_check_law(const dtc_config_t *cfg, uint16_t first, uint16_t last,
                             int16_t (*part)(const dtc_config_t *cfg, const char **f), const char **field)
{
    const char *dummy = "";
    const char **f = field != NULL ? field : &dummy;
    const int16_t err = dtc_config_check_common(cfg, f);
    if (err != DTC_OK) {
        return err;
    }
    DTC_REFUSE(cfg->law < first || cfg->law > last, DTC_ERR_VARIANT, "law");
    return part(cfg, f);
}
